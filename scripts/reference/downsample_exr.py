#!/usr/bin/env python3
"""Box-downsamples an RGB EXR by an integer factor (the mean of each
factor x factor block), written as a float RGB EXR: a reference for
`lqmc study equal-time --reference` at a lower resolution than the render
it comes from (e.g. Tungsten's 1024x1024 render of Bitterli's veach-bidir at
256x256). The box of the blocks is not the study's reconstruction filter,
so edges keep a small difference that no amount of samples removes.

Usage: python3 scripts/reference/downsample_exr.py IN.exr FACTOR OUT.exr
(needs `pip install mitsuba` for EXR input and output).
"""
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def main():
    source, factor, target = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    image = np.array(mi.Bitmap(source).convert(mi.Bitmap.PixelFormat.RGB,
                                               mi.Struct.Type.Float32, False))
    height, width, _ = image.shape
    if height % factor or width % factor:
        sys.exit(f"{width}x{height} is not divisible by {factor}")
    blocks = image.reshape(height // factor, factor, width // factor, factor, 3)
    mi.Bitmap(blocks.mean(axis=(1, 3)).astype(np.float32)).write(target)
    print(f"{source} {width}x{height} -> {target} {width // factor}x{height // factor}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The variance for `lqmc compare --variance` when both the lqmc render and
the reference are noisy: per pixel and channel, the render's own `variance`
layer (the variance of its pixel mean, RGB) plus the reference's variance of
its mean (an RGB EXR such as
`scenes/lqmc-equal-time/*/reference_variance.exr`), times the render's spp.

    python3 scripts/reference/sum_variances.py OURS.exr REFERENCE_VARIANCE.exr -o BOTH.exr
    lqmc compare OURS.exr reference.exr --variance BOTH.exr

`lqmc compare --variance` reads Mitsuba's convention, the variance of one
sample, and divides it by the tested image's spp (read from its metadata);
hence the factor. Passing a variance of a mean with `--spp 1` instead would
meet compare's floor of 1e-4 (Mitsuba's, meant for one sample's variance) and
test nothing in images whose standard error is below 0.01. Needs Mitsuba's
Python package (for EXR input and output) and numpy.
"""

import argparse

import numpy as np


def channels(mi, path):
    """The EXR file's channels by name, each an (height, width) float64 array,
    and its metadata."""
    bitmap = mi.Bitmap(path)
    array = np.array(bitmap, dtype=np.float64)
    layout = bitmap.struct_()
    names = [layout[index].name for index in range(len(layout))]
    return {name: array[:, :, index] for index, name in enumerate(names)}, bitmap.metadata()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("render", help="lqmc's EXR with a variance.R/G/B layer and spp metadata")
    parser.add_argument("reference_variance", help="RGB EXR: the reference's variance of its mean")
    parser.add_argument("-o", "--output", required=True)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant("scalar_rgb")
    ours, metadata = channels(mi, args.render)
    missing = [name for name in ("variance.R", "variance.G", "variance.B") if name not in ours]
    if missing:
        parser.error(f"{args.render} has no {', '.join(missing)} channel")
    if "spp" not in metadata:
        parser.error(f"{args.render} has no spp metadata")
    spp = float(metadata["spp"])
    reference, _ = channels(mi, args.reference_variance)
    total = np.stack(
        [(ours[f"variance.{c}"] + reference[c]) * spp for c in "RGB"], axis=2
    ).astype(np.float32)
    mi.Bitmap(total, pixel_format=mi.Bitmap.PixelFormat.RGB).write(args.output)
    print(f"wrote {args.output}: (variance of {args.render}'s mean + {args.reference_variance}) x {spp:g} spp")


if __name__ == "__main__":
    main()

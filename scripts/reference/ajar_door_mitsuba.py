#!/usr/bin/env python3
"""Mitsuba 3's render of the ajar door (`scenes/ajar-door/ajar-door.xml`,
lqmc's `builtin:ajar-door`): the file as it is, to check that lqmc and Mitsuba
read and render it alike.

Renders K independent images of SPP samples per pixel (seeds 0 .. K-1) with
the file's integrator (`path`, max_depth 16) and writes OUT.exr: RGB is the
per-pixel mean of the K images and `variance.R/G/B` the variance of that mean
(s^2 / K), the layer lqmc writes, so that
`lqmc compare OUT.exr LQMC.exr --image-variance` z-tests Mitsuba's mean, with
its variance, against a long lqmc render. Prints the image mean and the time.

Usage: pip install mitsuba==3.9.1
       python3 scripts/reference/ajar_door_mitsuba.py [--variant scalar_spectral]
           [--spp 256] [--images 8] [-o ajar-door-mitsuba.exr]
"""

import argparse
import time
from pathlib import Path

import numpy as np

SCENE = Path(__file__).resolve().parents[2] / "scenes/ajar-door/ajar-door.xml"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="scalar_spectral")
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--images", type=int, default=8)
    parser.add_argument("-o", "--output", default="ajar-door-mitsuba.exr")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    scene = mi.load_file(str(SCENE))
    images = []
    started = time.perf_counter()
    for seed in range(args.images):
        image = mi.render(scene, spp=args.spp, seed=seed)
        images.append(np.array(image, dtype=np.float64)[:, :, :3])
    seconds = time.perf_counter() - started
    stack = np.stack(images)
    mean = stack.mean(axis=0)
    variance = stack.var(axis=0, ddof=1) / len(images) if len(images) > 1 else np.zeros_like(mean)
    layers = np.concatenate([mean, variance], axis=2).astype(np.float32)
    bitmap = mi.Bitmap(layers, channel_names=["R", "G", "B", "variance.R", "variance.G", "variance.B"])
    bitmap.write(args.output)
    print(f"{SCENE.name}: Mitsuba {mi.__version__} {args.variant}, {args.images} x {args.spp} spp "
          f"in {seconds:.1f} s; image mean {mean.mean():.6f} +- {np.sqrt(variance.sum()) / mean.size:.6f}; "
          f"wrote {args.output}")


if __name__ == "__main__":
    main()

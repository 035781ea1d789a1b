#!/usr/bin/env python3
"""Reference image of Mitsuba 3's Cornell box for `crates/render/tests/cornell_reference.rs`.

Renders `scenes/cbox/cbox-rgb.xml` (which our `builtin:cornell-box` reproduces)
with Mitsuba 3.9.1, variant `scalar_spectral`, 256x256, max_depth 6, box
filter, independent sampler, as K independent images of `spp` samples per
pixel each (seeds 0 .. K-1 passed to `mi.render`). Each image is
box-downsampled by 4 to 64x64 (the mean of 4x4 pixels, which with a box
filter of one pixel equals rendering at 64x64). Writes, as little-endian PFM:

* `cbox_mitsuba_mean.pfm`: per pixel the mean of the K downsampled images;
* `cbox_mitsuba_variance.pfm`: per pixel the estimated variance of that mean,
  s^2 / K with s^2 the unbiased sample variance over the K images;
* `cbox_mitsuba_reference.txt`: the settings and Mitsuba version.

Usage: pip install mitsuba==3.9.1; python3 scripts/perf/mitsuba_cbox_reference.py
"""

import argparse
import time
from pathlib import Path

import numpy as np

# Vendored in the repository (scenes/external, see its README).
SCENE = Path(__file__).resolve().parents[2] / "scenes/external/mitsuba-data/scenes/cbox/cbox-rgb.xml"
OUTPUT = Path(__file__).resolve().parents[2] / "crates/render/tests/data"


def write_pfm(path, image):
    """Little-endian RGB PFM (scale -1), rows bottom to top."""
    height, width, _ = image.shape
    with open(path, "wb") as file:
        file.write(f"PF\n{width} {height}\n-1\n".encode())
        file.write(np.ascontiguousarray(image[::-1], dtype="<f4").tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--images", type=int, default=32, help="K independent images")
    parser.add_argument("--spp", type=int, default=64, help="samples per pixel per image")
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--factor", type=int, default=4, help="box downsampling factor")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--variant", default="scalar_spectral")
    parser.add_argument("--output", type=Path, default=OUTPUT)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    scene = mi.load_file(str(SCENE), spp=args.spp, res=args.res, max_depth=6)
    small = args.res // args.factor
    images = []
    start = time.perf_counter()
    for seed in range(args.images):
        image = np.array(mi.render(scene, spp=args.spp, seed=seed), dtype=np.float64)[..., :3]
        image = image.reshape(small, args.factor, small, args.factor, 3).mean(axis=(1, 3))
        images.append(image)
        print(f"image {seed + 1}/{args.images}, {time.perf_counter() - start:.1f} s", flush=True)
    seconds = time.perf_counter() - start
    stack = np.stack(images)
    mean = stack.mean(axis=0)
    variance_of_mean = stack.var(axis=0, ddof=1) / args.images

    args.output.mkdir(parents=True, exist_ok=True)
    write_pfm(args.output / "cbox_mitsuba_mean.pfm", mean)
    write_pfm(args.output / "cbox_mitsuba_variance.pfm", variance_of_mean)
    image_mean = mean.mean(axis=(0, 1))
    image_mean_sd = np.sqrt(variance_of_mean.sum(axis=(0, 1))) / (small * small)
    notes = [
        f"scene: mitsuba-data scenes/cbox/cbox-rgb.xml (max_depth 6, box filter, independent sampler)",
        f"mitsuba: {mi.__version__}, variant {args.variant}, {args.threads} threads",
        f"rendered: {args.images} images of {args.res}x{args.res} at {args.spp} spp, seeds 0..{args.images - 1}",
        f"total: {args.images * args.spp} spp at {args.res}x{args.res}, "
        f"{args.images * args.spp * args.factor ** 2} samples per {small}x{small} pixel",
        f"downsampled: box {args.factor}x{args.factor} to {small}x{small}",
        f"mean: per-pixel mean of the {args.images} images (cbox_mitsuba_mean.pfm)",
        f"variance: per-pixel sample variance over the images / {args.images} (cbox_mitsuba_variance.pfm)",
        f"image mean RGB: {image_mean[0]:.6f} {image_mean[1]:.6f} {image_mean[2]:.6f}",
        f"image mean standard deviation: {image_mean_sd[0]:.2e} {image_mean_sd[1]:.2e} {image_mean_sd[2]:.2e}",
        f"render time: {seconds:.1f} s",
    ]
    (args.output / "cbox_mitsuba_reference.txt").write_text("\n".join(notes) + "\n")
    print("\n".join(notes))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Mitsuba 3 references of the equal-time scenes (`scenes/lqmc-equal-time/`,
issue 34): each scene file as it is, rendered K times independently.

For each scene folder given, loads `scene.xml`, renders K images of SPP
samples per pixel with the file's integrator and sampler (seeds
SEED .. SEED + K - 1, so the images are independent) and writes into the
folder:

* `reference.exr`: RGB, per pixel and channel the mean of the K images;
* `reference_variance.exr`: RGB, per pixel and channel the variance of that
  mean, s^2 / K with s^2 the unbiased sample variance over the K images (in
  linear sRGB, the same quantity as the `variance` layer of lqmc's renders);
* `reference.png`: the mean, sRGB, for looking at;
* `reference.json`: Mitsuba's version, the variant, K, SPP, seeds, the render
  time and the image means with their standard errors.

A pixel whose value is not finite in some image (Mitsuba returns NaN for a
rare sample) leaves that image out of the pixel's statistics; the count is
reported. To z-test an lqmc render OURS against it with both images' noise:

    python3 scripts/reference/sum_variances.py OURS.exr reference_variance.exr -o both.exr
    lqmc compare OURS.exr reference.exr --variance both.exr

(`lqmc compare --variance` wants Mitsuba's convention, the variance of one
sample with the tested image's spp; `sum_variances.py` writes the sum of
the two variances of means in that form.)

Usage: pip install mitsuba==3.9.1
       python3 scripts/reference/lqmc_equal_time_references.py SCENE_DIR ...
           [--images K] [--spp SPP] [--variant llvm_ad_spectral] [--seed SEED]

The LLVM variants need libLLVM (Debian: `apt-get install libllvm19`,
`DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`; LLVM 15
crashes); `scalar_spectral` needs nothing.
"""

import argparse
import json
import time
from pathlib import Path

import numpy as np


def render_images(mi, scene_file, images, spp, seed):
    """The K renders of `scene_file` as a (K, height, width, 3) float64 array
    and the seconds they took (scene loading and JIT compilation included)."""
    started = time.perf_counter()
    scene = mi.load_file(str(scene_file))
    stack = []
    for index in range(images):
        image = mi.render(scene, spp=spp, seed=seed + index)
        stack.append(np.array(image, dtype=np.float64)[:, :, :3])
        print(f"  {scene_file.parent.name}: image {index + 1}/{images} "
              f"({time.perf_counter() - started:.0f} s)", flush=True)
    return np.stack(stack), time.perf_counter() - started


def statistics(stack):
    """Per-pixel mean and variance of the mean over the images that are finite
    there, and the number of (image, pixel) pairs left out."""
    finite = np.isfinite(stack).all(axis=3, keepdims=True)
    counts = finite.sum(axis=0)
    values = np.where(finite, stack, 0.0)
    mean = values.sum(axis=0) / np.maximum(counts, 1)
    squared = np.where(finite, (stack - mean) ** 2, 0.0).sum(axis=0)
    variance = squared / np.maximum(counts - 1, 1) / np.maximum(counts, 1)
    left_out = int((~finite).sum())
    return mean, variance, left_out


def write_rgb(mi, array, path):
    mi.Bitmap(array.astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(str(path))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+", type=Path, help="scene folders holding scene.xml")
    parser.add_argument("--images", type=int, default=8, help="independent renders K")
    parser.add_argument("--spp", type=int, default=512, help="samples per pixel of each render")
    parser.add_argument("--variant", default="llvm_ad_spectral")
    parser.add_argument("--seed", type=int, default=0, help="seed of the first render")
    args = parser.parse_args()
    if args.images < 2:
        parser.error("--images must be at least 2 for a variance")

    import mitsuba as mi

    mi.set_variant(args.variant)
    for folder in args.scenes:
        scene_file = folder / "scene.xml"
        stack, seconds = render_images(mi, scene_file, args.images, args.spp, args.seed)
        mean, variance, left_out = statistics(stack)
        write_rgb(mi, mean, folder / "reference.exr")
        write_rgb(mi, variance, folder / "reference_variance.exr")
        mi.Bitmap(mean.astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).convert(
            mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True
        ).write(str(folder / "reference.png"))
        pixels = mean.shape[0] * mean.shape[1]
        image_mean = mean.reshape(-1, 3).mean(axis=0)
        image_mean_error = np.sqrt(variance.reshape(-1, 3).sum(axis=0)) / pixels
        record = {
            "scene": str(scene_file),
            "mitsuba": mi.__version__,
            "variant": args.variant,
            "images": args.images,
            "spp_per_image": args.spp,
            "spp_total": args.images * args.spp,
            "seeds": [args.seed, args.seed + args.images - 1],
            "seconds": round(seconds, 1),
            "non_finite_left_out": left_out,
            "image_mean_rgb": [round(float(v), 6) for v in image_mean],
            "image_mean_standard_error_rgb": [round(float(v), 7) for v in image_mean_error],
            "mean_relative_standard_error_per_pixel": round(
                float(np.mean(np.sqrt(variance) / np.maximum(mean, 1e-3))), 5),
        }
        (folder / "reference.json").write_text(json.dumps(record, indent=2) + "\n")
        print(json.dumps(record), flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Reference image of two media-filled spheres for `crates/render/tests/volume_mitsuba_reference.rs`.

The scene (built here as a Mitsuba 3 dict; the Rust test builds the same one
as a `SceneDescription`):

* camera at (0, 1, -4) looking at (0, 0.6, 0), 40 degrees horizontal field of
  view, 32x32 pixels, box filter of one pixel;
* a one-sided diffuse ground rectangle (reflectance 0.5) of half-size 4 in
  y = 0, facing +y;
* a rectangular area light of half-size 1 at height 3 facing down, radiance
  rgb(4, 4, 4), and a constant environment of radiance rgb(0.3, 0.3, 0.3);
* left: a smooth dielectric sphere (centre (-0.75, 0.6, 0), radius 0.55,
  index 1.5 inside, 1 outside) filled with medium A: albedo rgb(0.9, 0.55,
  0.25), sigma_t 4, Henyey-Greenstein g = 0.5;
* right: an index-matched (`null`) sphere (centre (0.75, 0.6, 0), radius
  0.55) filled with medium B: albedo 0.85, a chromatic sigma_t given as the
  piecewise-linear spectrum 360:0.5, 500:1.5, 600:3, 830:5 (nm: 1/length),
  isotropic phase function.

Mitsuba 3.9.1 `scalar_spectral`, integrator `volpath` with max_depth 16,
independent sampler, rendered as K independent images of `spp` samples per
pixel (seeds 0 .. K-1). Writes `volume_spheres_mitsuba.exr` (32-bit float):
RGB is the per-pixel mean of the K images and `variance.R/G/B` the variance
of that mean (s^2 / K, s^2 the unbiased sample variance over the images;
a pixel whose value in one image is NaN, as Mitsuba returns for a rare
sample, leaves that image out of its statistics), plus `volume_spheres_mitsuba.txt` with the settings.

Usage: pip install mitsuba==3.9.1; python3 scripts/reference/mitsuba_volume_spheres.py
"""

import argparse
import time
from pathlib import Path

import numpy as np

OUTPUT = Path(__file__).resolve().parents[2] / "crates/render/tests/data"


def rotation_x(degrees):
    a = np.radians(degrees)
    return np.array([[1, 0, 0, 0],
                     [0, np.cos(a), -np.sin(a), 0],
                     [0, np.sin(a), np.cos(a), 0],
                     [0, 0, 0, 1]])


def translation(x, y, z):
    m = np.eye(4)
    m[:3, 3] = [x, y, z]
    return m


def scaling(x, y, z):
    return np.diag([x, y, z, 1.0])


def scene_dict(mi, resolution, max_depth):
    transform = lambda m: mi.ScalarTransform4f(m.tolist())
    medium_a = {
        "type": "homogeneous",
        "albedo": {"type": "rgb", "value": [0.9, 0.55, 0.25]},
        "sigma_t": 4.0,
        "scale": 1.0,
        "phase": {"type": "hg", "g": 0.5},
    }
    medium_b = {
        "type": "homogeneous",
        "albedo": 0.85,
        "sigma_t": {"type": "irregular", "wavelengths": "360, 500, 600, 830",
                    "values": "0.5, 1.5, 3.0, 5.0"},
        "scale": 1.0,
        "phase": {"type": "isotropic"},
    }
    return {
        "type": "scene",
        "integrator": {"type": "volpath", "max_depth": max_depth},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[0, 1, -4], target=[0, 0.6, 0], up=[0, 1, 0]),
            "sampler": {"type": "independent"},
            "film": {"type": "hdrfilm", "width": resolution, "height": resolution,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "environment": {"type": "constant", "radiance": {"type": "rgb", "value": [0.3, 0.3, 0.3]}},
        "ground": {
            "type": "rectangle",
            "to_world": transform(rotation_x(-90) @ scaling(4, 4, 4)),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.5, 0.5, 0.5]}},
        },
        "light": {
            "type": "rectangle",
            "to_world": transform(translation(0, 3, 0) @ rotation_x(90)),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}},
            "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [4.0, 4.0, 4.0]}},
        },
        "dielectric_sphere": {
            "type": "sphere", "center": [-0.75, 0.6, 0.0], "radius": 0.55,
            "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
            "interior": medium_a,
        },
        "null_sphere": {
            "type": "sphere", "center": [0.75, 0.6, 0.0], "radius": 0.55,
            "bsdf": {"type": "null"},
            "interior": medium_b,
        },
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--images", type=int, default=32, help="K independent images")
    parser.add_argument("--spp", type=int, default=256, help="samples per pixel per image")
    parser.add_argument("--res", type=int, default=32)
    parser.add_argument("--max-depth", type=int, default=16)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--variant", default="scalar_spectral")
    parser.add_argument("--output", type=Path, default=OUTPUT)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    scene = mi.load_dict(scene_dict(mi, args.res, args.max_depth))
    images = []
    start = time.perf_counter()
    for seed in range(args.images):
        image = np.array(mi.render(scene, spp=args.spp, seed=seed), dtype=np.float64)[..., :3]
        images.append(image)
        print(f"image {seed + 1}/{args.images}, {time.perf_counter() - start:.1f} s", flush=True)
    seconds = time.perf_counter() - start
    stack = np.stack(images)
    # Mitsuba's volpath returns NaN for a rare sample (about one pixel in a
    # few hundred at 512 spp); such a pixel's image is left out of that
    # pixel's statistics (the other images are independent of it).
    valid = np.isfinite(stack).all(axis=3, keepdims=True)
    dropped = int((~valid).sum())
    counts = valid.sum(axis=0)
    stack = np.where(valid, stack, np.nan)
    mean = np.nanmean(stack, axis=0)
    variance_of_mean = np.nanvar(stack, axis=0, ddof=1) / counts

    args.output.mkdir(parents=True, exist_ok=True)
    channels = np.concatenate([mean, variance_of_mean], axis=2).astype(np.float32)
    bitmap = mi.Bitmap(channels, pixel_format=mi.Bitmap.PixelFormat.MultiChannel,
                       channel_names=["R", "G", "B", "variance.R", "variance.G", "variance.B"])
    bitmap.write(str(args.output / "volume_spheres_mitsuba.exr"))
    image_mean = mean.mean(axis=(0, 1))
    image_mean_sd = np.sqrt(variance_of_mean.sum(axis=(0, 1))) / (args.res * args.res)
    notes = [
        "scene: scripts/reference/mitsuba_volume_spheres.py (dielectric sphere with medium A, null sphere with medium B)",
        f"mitsuba: {mi.__version__}, variant {args.variant}, integrator volpath, max_depth {args.max_depth}, {args.threads} threads",
        f"rendered: {args.images} images of {args.res}x{args.res} at {args.spp} spp, seeds 0..{args.images - 1}",
        f"time: {seconds:.1f} s",
        f"pixel images left out for NaN: {dropped} of {args.images * args.res * args.res}",
        f"image mean (R, G, B): {image_mean.tolist()} +- {image_mean_sd.tolist()}",
    ]
    (args.output / "volume_spheres_mitsuba.txt").write_text("\n".join(notes) + "\n")
    print("\n".join(notes))


if __name__ == "__main__":
    main()

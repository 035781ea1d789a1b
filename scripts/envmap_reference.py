#!/usr/bin/env python3
"""Mitsuba 3 references for the environment-map light (issue 4, lights).

1. Lookup conventions: evaluates Mitsuba's `envmap` on a 4x3 bitmap with
   R = column + 1, G = 10 (row + 1) at chosen (u, v) and prints the values
   (the facts `light/environment_map.rs` encodes: column centres at
   u = (i + 1/2)/W, periodic; rows at v = j/(H - 1); bilinear), and in the
   spectral variant between a white and a black row (spectra and scales
   interpolated separately: a quarter of white halfway).
2. A reference image for `crates/render/tests/light_envmap_reference.rs`: a
   diffuse sphere (reflectance 0.2, 0.5, 0.3) of radius 1 at the origin
   under `museum.exr` (rotated 60 degrees about +y, scale 1.5), seen from
   (0, 0, 4) towards the origin (up +y, 40 degree horizontal field of view),
   32x32, box filter, `path` with max_depth 3, variant `scalar_spectral`,
   K independent images of `spp` samples (seeds 0 .. K-1). Writes, as
   little-endian PFM, `envmap_mitsuba_mean.pfm` (per-pixel mean of the K
   images) and `envmap_mitsuba_variance.pfm` (the variance of that mean,
   s^2 / K), and `envmap_mitsuba_reference.txt`.

Usage: pip install mitsuba==3.9.1; python3 scripts/envmap_reference.py
(no numpy needed).
"""

import argparse
import math
import struct
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MUSEUM = ROOT / "scenes/external/mitsuba-data/common/textures/museum.exr"
OUTPUT = ROOT / "crates/render/tests/data"


def write_pfm(path, width, height, pixels):
    """Little-endian RGB PFM (scale -1), rows bottom to top; `pixels` row-major, top first."""
    with open(path, "wb") as file:
        file.write(f"PF\n{width} {height}\n-1\n".encode())
        for y in reversed(range(height)):
            for x in range(width):
                file.write(struct.pack("<3f", *pixels[y * width + x]))


def lookup_conventions(mi):
    mi.set_variant("scalar_rgb")
    width, height = 4, 3
    values = []
    for y in range(height):
        for x in range(width):
            values += [x + 1, 10 * (y + 1), 0.5]
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(mi.TensorXf(values, (height, width, 3)))})
    lines = ["lookup (scalar_rgb, 4x3 map, R = column + 1, G = 10 (row + 1)):"]
    for u, v in [(0.125, 0.5), (0.0, 0.5), (0.25, 0.5), (0.375, 0.5), (0.125, 0.25), (0.9, 0.75)]:
        phi, theta = 2 * math.pi * u, math.pi * v
        d = [math.sin(phi) * math.sin(theta), math.cos(theta), -math.cos(phi) * math.sin(theta)]
        si = mi.SurfaceInteraction3f()
        si.wi = -mi.Vector3f(d)
        value = emitter.eval(si)
        lines.append(f"  u={u} v={v}: {value[0]:.4f} {value[1]:.4f} {value[2]:.4f}")
    # Spectral: sigmoid spectra and scales are interpolated separately, so
    # halfway between a white and a black row gives a quarter of white.
    mi.set_variant("scalar_spectral")
    values = [1.0 if y == 0 else 0.0 for y in range(height) for _ in range(width) for _ in range(3)]
    emitter = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(mi.TensorXf(values, (height, width, 3)))})
    lines.append("lookup (scalar_spectral, row 0 white, rows 1-2 black, u = 0.125, 550 nm):")
    for v in [0.0001, 0.25, 0.5]:
        phi, theta = 2 * math.pi * 0.125, math.pi * v
        d = [math.sin(phi) * math.sin(theta), math.cos(theta), -math.cos(phi) * math.sin(theta)]
        si = mi.SurfaceInteraction3f()
        si.wi = -mi.Vector3f(d)
        si.wavelengths = [550.0] * 4
        lines.append(f"  v={v}: {emitter.eval(si)[0]:.5f}")
    return lines


def scene_dict(mi, spp, resolution):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": 40.0,
            "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[0, 0, 4], target=[0, 0, 0], up=[0, 1, 0]),
            "film": {"type": "hdrfilm", "width": resolution, "height": resolution,
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "sphere": {
            "type": "sphere", "center": [0, 0, 0], "radius": 1.0,
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.2, 0.5, 0.3]}},
        },
        "light": {
            "type": "envmap", "filename": str(MUSEUM), "scale": 1.5,
            "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=60),
        },
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--images", type=int, default=32)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--res", type=int, default=32)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--output", type=Path, default=OUTPUT)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    notes = lookup_conventions(mi)
    mi.set_variant("scalar_spectral")
    dr.set_thread_count(args.threads)
    scene = mi.load_dict(scene_dict(mi, args.spp, args.res))
    count = args.res * args.res * 3
    sums = [0.0] * count
    squares = [0.0] * count
    start = time.perf_counter()
    for seed in range(args.images):
        image = mi.render(scene, spp=args.spp, seed=seed)
        flat = list(image.array)
        channels = len(flat) // (args.res * args.res)
        for pixel in range(args.res * args.res):
            for c in range(3):
                value = flat[pixel * channels + c]
                sums[pixel * 3 + c] += value
                squares[pixel * 3 + c] += value * value
    seconds = time.perf_counter() - start
    k = args.images
    mean = [s / k for s in sums]
    variance = [max(q - k * m * m, 0.0) / (k - 1) / k for q, m in zip(squares, mean)]
    pixels = lambda data: [tuple(data[3 * i:3 * i + 3]) for i in range(args.res * args.res)]
    args.output.mkdir(parents=True, exist_ok=True)
    write_pfm(args.output / "envmap_mitsuba_mean.pfm", args.res, args.res, pixels(mean))
    write_pfm(args.output / "envmap_mitsuba_variance.pfm", args.res, args.res, pixels(variance))
    n = args.res * args.res
    image_mean = [sum(mean[c::3]) / n for c in range(3)]
    image_sd = [math.sqrt(sum(variance[c::3])) / n for c in range(3)]
    notes += [
        "scene: diffuse sphere (0.2, 0.5, 0.3), radius 1, under museum.exr (rotate y 60, scale 1.5);"
        " camera (0,0,4) -> origin, up +y, fov 40 (x), box filter, path max_depth 3",
        f"mitsuba: {mi.__version__}, variant scalar_spectral, {args.threads} threads",
        f"rendered: {k} images of {args.res}x{args.res} at {args.spp} spp, seeds 0..{k - 1}",
        f"image mean RGB: {image_mean[0]:.6f} {image_mean[1]:.6f} {image_mean[2]:.6f}",
        f"image mean standard deviation: {image_sd[0]:.2e} {image_sd[1]:.2e} {image_sd[2]:.2e}",
        f"render time: {seconds:.1f} s",
    ]
    (args.output / "envmap_mitsuba_reference.txt").write_text("\n".join(notes) + "\n")
    print("\n".join(notes))


if __name__ == "__main__":
    main()

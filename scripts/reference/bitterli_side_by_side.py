#!/usr/bin/env python3
"""Renders Bitterli's scenes with lqmc and writes ours | Tungsten side by side.

For each scene: `target/release/lqmc render` at a reduced resolution (the
image mean does not depend on it), Tungsten's `TungstenRender.exr`
box-downsampled to the same size, both tone-mapped the same way (linear,
exposure 0, clamped, sRGB transfer) and written next to each other as
`docs/images/bitterli-NAME.png` (each half at most 320 px wide). Prints the
table of image means (per channel and luminance, Rec. 709 weights) and their
ratios to Tungsten's.

Run from the project root after `cargo build --release -p lqmc-cli`:

    python3 scripts/reference/bitterli_side_by_side.py [--spp N] [--only NAME]

EXR files are read and PNGs written with Mitsuba 3's `Bitmap` (pip package
`mitsuba`, 3.9.1 was used), NumPy does the arithmetic.
"""

import argparse
import subprocess
import sys
from pathlib import Path

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / ".." / "shared" / "scenes" / "bitterli"

# name, scene file, render resolution (same aspect as Tungsten's image).
CASES = [
    ("cornell-box", "cornell-box/scene.xml", (256, 256)),
    ("veach-mis", "veach-mis/scene.xml", (320, 180)),
    ("veach-mis-pbrt", "veach-mis/scene-v4.pbrt", (320, 180)),
    ("veach-bidir", "veach-bidir/scene.xml", (256, 256)),
]


def read_rgb(path):
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)[..., :3]


def box_downsample(image, width, height):
    """Area average onto a width × height grid (the source size must be a
    multiple, as Tungsten's 1024² and 1280 × 720 are of the sizes above)."""
    h, w, _ = image.shape
    fy, fx = h // height, w // width
    if fy * height != h or fx * width != w:
        raise ValueError(f"{w}x{h} is not a multiple of {width}x{height}")
    return image.reshape(height, fy, width, fx, 3).mean(axis=(1, 3))


def srgb(linear):
    linear = np.clip(linear, 0.0, 1.0)
    encoded = np.where(
        linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(linear, 1 / 2.4) - 0.055
    )
    return (encoded * 255.0 + 0.5).astype(np.uint8)


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--only", default=None)
    parser.add_argument(
        "--reuse", action="store_true",
        help="use existing /tmp/lqmc-bitterli-NAME.exr renders instead of rendering",
    )
    parser.add_argument("--binary", default=str(ROOT / "target" / "release" / "lqmc"))
    args = parser.parse_args()
    out_dir = ROOT / "docs" / "images"
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    for name, scene, (width, height) in CASES:
        if args.only and args.only != name:
            continue
        scene_path = SCENES / scene
        ours_path = Path("/tmp") / f"lqmc-bitterli-{name}.exr"
        command = [
            args.binary, "render", str(scene_path),
            "--resolution", f"{width}x{height}",
            "--spp", str(args.spp), "--seed", "1", "--quiet",
            "-o", str(ours_path),
        ]
        print(" ".join(command), file=sys.stderr)
        if not (args.reuse and ours_path.exists()):
            subprocess.run(command, check=True)
        ours = read_rgb(ours_path)
        tungsten = box_downsample(read_rgb(scene_path.parent / "TungstenRender.exr"), width, height)
        side = np.concatenate([srgb(ours), srgb(tungsten)], axis=1)
        png = out_dir / f"bitterli-{name}.png"
        mi.Bitmap(np.ascontiguousarray(side)).write(str(png))
        ours_mean = ours.reshape(-1, 3).mean(axis=0)
        reference_mean = tungsten.reshape(-1, 3).mean(axis=0)
        rows.append((name, ours_mean, reference_mean))
        print(f"wrote {png}", file=sys.stderr)
    print("| scene | ours R, G, B | Tungsten R, G, B | ratio R, G, B | ratio luminance |")
    print("|---|---|---|---|---|")
    for name, ours_mean, reference_mean in rows:
        ratio = ours_mean / reference_mean
        print(
            f"| {name} | {ours_mean[0]:.4f}, {ours_mean[1]:.4f}, {ours_mean[2]:.4f} "
            f"| {reference_mean[0]:.4f}, {reference_mean[1]:.4f}, {reference_mean[2]:.4f} "
            f"| {ratio[0]:.3f}, {ratio[1]:.3f}, {ratio[2]:.3f} "
            f"| {luminance(ours_mean) / luminance(reference_mean):.3f} |"
        )


if __name__ == "__main__":
    main()

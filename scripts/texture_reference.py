#!/usr/bin/env python3
"""Reference values of Mitsuba 3 (3.9.1) textures for crates/render/tests/texture.rs.

Run: python3 scripts/texture_reference.py > scripts/texture_reference.txt
(needs `pip install mitsuba`; reads scenes/external/mitsuba-data/common/textures).

Output lines (whitespace separated):
  synthetic FILTER WRAP u v r g b        raw 3x2 float image (see SYNTHETIC), eval_3 in scalar_rgb
  wood_rgb u v r g b                     wood.jpg, sRGB-decoded, bilinear, scalar_rgb
  wood_spectral u v l0 l1 l2 l3 s0 s1 s2 s3   wood.jpg in scalar_spectral at wavelengths l (nm)
  checker u v value                      checkerboard color0=0.1 color1=0.7, to_uv = scale(3, 2)
  bump u v value du dv                   floor_tiles_bumpmap.png raw: eval_1 and eval_1_grad
"""
import os
from pathlib import Path
import numpy as np
import mitsuba as mi

HERE = os.path.dirname(os.path.abspath(__file__))
TEXTURES = os.path.join(HERE, "..", "..", "shared", "scenes", "mitsuba-data", "common", "textures")
if not os.path.isdir(TEXTURES):
    TEXTURES = str(Path(__file__).resolve().parents[1] / "scenes/external/mitsuba-data/common/textures")

# 3 columns x 2 rows, RGB; row 0 is the top row of the image.
SYNTHETIC = np.array(
    [
        [[0.0, 0.1, 0.2], [0.3, 0.4, 0.5], [0.6, 0.7, 0.8]],
        [[0.9, 1.0, 1.1], [1.2, 1.3, 1.4], [1.5, 1.6, 1.7]],
    ],
    dtype=np.float32,
)
SYNTHETIC_UVS = [
    (0.0, 0.0), (0.1, 0.2), (0.5, 0.5), (0.9, 0.8), (0.99, 0.99), (0.25, 0.75),
    (-0.3, 0.4), (1.2, -0.1), (1.7, 1.6), (-1.1, 2.3), (0.4, -0.7),
]
WOOD_UVS = [(0.1, 0.2), (0.5, 0.5), (0.73, 0.31), (0.05, 0.95), (0.999, 0.001), (0.3333, 0.6667)]
CHECKER_UVS = [(0.05, 0.05), (0.2, 0.05), (0.05, 0.3), (0.2, 0.3), (0.4, 0.7), (0.9, 0.1),
               (0.55, 0.8), (-0.1, 0.1), (0.1, -0.1)]
BUMP_UVS = [(0.1, 0.2), (0.5, 0.5), (0.73, 0.31), (0.25, 0.9), (0.6012, 0.1234)]


def interaction(u, v):
    si = mi.SurfaceInteraction3f()
    si.uv = mi.Point2f(u, v)
    return si


def main():
    mi.set_variant("scalar_rgb")
    for filter_type in ["nearest", "bilinear"]:
        for wrap in ["repeat", "mirror", "clamp"]:
            texture = mi.load_dict({
                "type": "bitmap",
                "bitmap": mi.Bitmap(SYNTHETIC),
                "raw": True,
                "filter_type": filter_type,
                "wrap_mode": wrap,
            })
            for u, v in SYNTHETIC_UVS:
                rgb = texture.eval(interaction(u, v))
                print("synthetic", filter_type, wrap, u, v, *(f"{float(c):.7g}" for c in rgb))
    wood = mi.load_dict({"type": "bitmap", "filename": os.path.join(TEXTURES, "wood.jpg")})
    for u, v in WOOD_UVS:
        rgb = wood.eval(interaction(u, v))
        print("wood_rgb", u, v, *(f"{float(c):.7g}" for c in rgb))
    checker = mi.load_dict({
        "type": "checkerboard",
        "color0": {"type": "rgb", "value": [0.1, 0.1, 0.1]},
        "color1": {"type": "rgb", "value": [0.7, 0.7, 0.7]},
        "to_uv": mi.ScalarTransform4f().scale([3.0, 2.0, 1.0]),
    })
    for u, v in CHECKER_UVS:
        value = checker.eval(interaction(u, v))
        print("checker", u, v, f"{float(value[0]):.7g}")
    bump = mi.load_dict({
        "type": "bitmap",
        "filename": os.path.join(TEXTURES, "floor_tiles_bumpmap.png"),
        "raw": True,
    })
    for u, v in BUMP_UVS:
        si = interaction(u, v)
        value = bump.eval_1(si)
        gradient = bump.eval_1_grad(si)
        print("bump", u, v, f"{float(value):.7g}", f"{float(gradient[0]):.7g}", f"{float(gradient[1]):.7g}")

    mi.set_variant("scalar_spectral")
    wood = mi.load_dict({"type": "bitmap", "filename": os.path.join(TEXTURES, "wood.jpg")})
    for wavelengths in [(400.0, 470.0, 550.0, 650.0), (430.0, 520.0, 600.0, 700.0)]:
        for u, v in WOOD_UVS:
            si = interaction(u, v)
            si.wavelengths = mi.Spectrum(wavelengths)
            values = wood.eval(si)
            print("wood_spectral", u, v, *wavelengths, *(f"{float(c):.7g}" for c in values))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""A Mitsuba 3.9.1 (`scalar_spectral`) reference for the scene that
Bitterli's `veach-mis/scene-v4.pbrt` describes, which is not the scene of
`veach-mis/scene.xml` and Tungsten's image. The Mitsuba XML equivalent is
derived from `scene.xml` with the differences the .pbrt file has (checked
against it by the asserts in `check_pbrt_file`):

- plates: pbrt-v4 `conductor`, Trowbridge–Reitz (GGX) with
  `remaproughness false`, so α = roughness = 0.01 / 0.05 / 0.1 / 0.25
  (scene.xml: Beckmann with the same α);
- no `specular_reflectance` factor (scene.xml: 0.3; pbrt-v4's conductor has
  no such parameter);
- η and κ: the file's RGB values (the same copper as scene.xml, two more
  digits), lifted to spectra as pbrt-v4's RGBUnboundedSpectrum does
  (scale s = 2 max(rgb), the reflectance upsampling of rgb / s, times s),
  here with Mitsuba's own upsampling table. (Mitsuba's parser would lift an
  `<rgb name="eta">` with its bounded reflectance fit, which saturates for
  κ > 1; see conductor_golden.py.) They are written as 5 nm spectra;
- `maxdepth 3` in pbrt counts scattering events: Mitsuba's max_depth 4
  (scene.xml: 3);
- geometry, lights (three spheres, `rgb L` 7.599088, 30.396353, 3039.635,
  radii 1, 0.5, 0.05), camera (vertical fov 20.114° = horizontal 35° at
  16:9) and the triangle filter of radius 1 (Mitsuba's tent) are the same.

The render is split into REPLICATIONS independent renders (seeds 0…), whose
spread gives the standard error of the image mean. Writes
crates/render/tests/data/veach_mis_pbrt_mitsuba.txt (the image mean per
channel and its standard error, and the same for the "dim" pixels: those
farther than DILATION pixels from any pixel whose luminance in Tungsten's
image box-filtered to WIDTH × HEIGHT exceeds BRIGHT, i.e. all but the
directly seen lights and their sharpest reflections, whose sub-pixel
footprints dominate the variance of the whole image's mean), which
tests/bitterli_scenes.rs compares with lqmc's render of scene-v4.pbrt.

Usage: python3 scripts/reference/veach_mis_pbrt_mitsuba.py [WIDTH HEIGHT SPP]
(default 160 90 1024, Tungsten's size / 8; about 5 minutes on 2 busy cores).
"""
import pathlib
import re
import sys
import time

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE_DIR = ROOT / "scenes/external/bitterli/veach-mis"
OUT = ROOT / "crates/render/tests/data/veach_mis_pbrt_mitsuba.txt"
REPLICATIONS = 8
BRIGHT = 20.0
DILATION = 2

PBRT_ETA = [0.200438, 0.924033, 1.102212]
PBRT_K = [3.912949, 2.452848, 2.142188]
ALPHAS = {"SmoothBSDF": 0.01, "GlossyBSDF": 0.05, "RoughBSDF": 0.1, "SuperRoughBSDF": 0.25}


def check_pbrt_file():
    text = (SCENE_DIR / "scene-v4.pbrt").read_text()
    assert '"integer maxdepth" [ 3 ]' in text
    assert text.count('"string type" [ "conductor" ]') == 4
    assert text.count('"bool remaproughness" [ false ]') == 4
    for alpha in ALPHAS.values():
        assert f'"float uroughness" [ {alpha} ]' in text and f'"float vroughness" [ {alpha} ]' in text
    assert text.count('"rgb eta" [ 0.200438 0.924033 1.102212 ]') == 4
    assert text.count('"rgb k" [ 3.912949 2.452848 2.142188 ]') == 4
    assert "reflectance" not in text.split("MakeNamedMaterial \"Null\"")[0].split("Smooth")[1]
    assert '"float fov" [ 20.114292 ]' in text
    assert 'PixelFilter "triangle"' in text
    assert len(re.findall(r'AreaLightSource "diffuse"', text)) == 3


def unbounded_spectrum(rgb):
    """pbrt-v4's RGBUnboundedSpectrum with Mitsuba's upsampling, at 5 nm."""
    scale = 2.0 * max(rgb)
    texture = mi.load_dict({"type": "rgb", "value": [c / scale for c in rgb]})
    si = mi.SurfaceInteraction3f()
    pairs = []
    for wavelength in range(360, 835, 5):
        si.wavelengths = mi.Spectrum([float(wavelength)] * 4)
        pairs.append(f"{wavelength}:{scale * float(texture.eval(si)[0]):.6f}")
    return ", ".join(pairs)


def equivalent_xml():
    xml = (SCENE_DIR / "scene.xml").read_text()
    eta, k = unbounded_spectrum(PBRT_ETA), unbounded_spectrum(PBRT_K)
    for name, alpha in ALPHAS.items():
        old = re.search(rf'<bsdf type="twosided" id="{name}">.*?</bsdf>\s*</bsdf>', xml, re.S).group(0)
        new = (f'<bsdf type="twosided" id="{name}"><bsdf type="roughconductor">'
               f'<float name="alpha" value="{alpha}"/><string name="distribution" value="ggx"/>'
               f'<spectrum name="eta" value="{eta}"/><spectrum name="k" value="{k}"/>'
               f'</bsdf></bsdf>')
        xml = xml.replace(old, new)
    assert "beckmann" not in xml and "specular_reflectance" not in xml
    return xml


def luminance(rgb):
    return 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]


def dim_pixels(width, height):
    """The mask of the module docs, from Tungsten's image."""
    tungsten = np.array(mi.Bitmap(str(SCENE_DIR / "TungstenRender.exr")), dtype=np.float64)[..., :3]
    fy, fx = tungsten.shape[0] // height, tungsten.shape[1] // width
    small = tungsten.reshape(height, fy, width, fx, 3).mean(axis=(1, 3))
    bright = luminance(small) > BRIGHT
    near = bright.copy()
    for dy in range(-DILATION, DILATION + 1):
        for dx in range(-DILATION, DILATION + 1):
            shifted = np.zeros_like(bright)
            shifted[max(dy, 0):height + min(dy, 0), max(dx, 0):width + min(dx, 0)] = \
                bright[max(-dy, 0):height + min(-dy, 0), max(-dx, 0):width + min(-dx, 0)]
            near |= shifted
    return ~near


def main():
    width, height, spp = (int(a) for a in sys.argv[1:4]) if len(sys.argv) > 3 else (160, 90, 1024)
    check_pbrt_file()
    xml = equivalent_xml()
    dim = dim_pixels(width, height)
    started = time.time()
    means, dim_means = [], []
    for seed in range(REPLICATIONS):
        scene = mi.load_string(xml, integrator="path", max_depth=4, resx=width, resy=height,
                               spp=spp // REPLICATIONS)
        image = np.array(mi.render(scene, seed=seed), dtype=np.float64)[..., :3]
        means.append(image.mean(axis=(0, 1)))
        dim_means.append(image[dim].mean(axis=0))
        print(f"replication {seed}: {means[-1]}, dim pixels {dim_means[-1]}", flush=True)

    def row(name, values):
        values = np.array(values)
        mean = values.mean(axis=0)
        standard_error = values.std(axis=0, ddof=1) / np.sqrt(REPLICATIONS)
        return [f"{name} " + " ".join(f"{v:.6f}" for v in mean),
                f"{name}_standard_error " + " ".join(f"{v:.6f}" for v in standard_error)]

    lines = [
        "# Mitsuba 3.9.1 scalar_spectral, path, max_depth 4: the scene of veach-mis/scene-v4.pbrt",
        f"# made by scripts/reference/veach_mis_pbrt_mitsuba.py at {width}x{height}, {spp} spp "
        f"({REPLICATIONS} replications), {time.time() - started:.0f} s",
        f"# dim pixels: {int(dim.sum())} of {dim.size} (luminance of Tungsten's image at this size "
        f"<= {BRIGHT} within {DILATION} pixels)",
        f"size {width} {height}",
        f"bright {BRIGHT} {DILATION}",
    ] + row("mean", means) + row("dim_mean", dim_means)
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

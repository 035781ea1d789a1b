"""Shows what Mitsuba 3.7.1's `flip_invalid_normals` and `use_shadowing_function`
(options of `bumpmap` and `normalmap`, on by default) do to Mitsuba's own test
scenes `test_bumpmap_path.xml` and `test_normalmap_path.xml`: renders each
with the options as the file has them (defaults: on) and with both off, and
prints the image means against the test reference
(`refs/test_*_ref_spectral.exr`) and, if given, against our render.

Usage: python3 scripts/reference/mitsuba_perturbation_options.py [OUR_DIR]
with OUR_DIR holding `bumpmap.exr` and `normalmap.exr` from
`lqmc render <scene> --integrator path --sampler independent --spp 8192`.
Needs `pip install mitsuba` (3.9.1 was used, 2026-12-04).

Result then (4096 spp, scalar_spectral, seed 3): against the references,
bump map with the options +0.08 %, without −0.46 %; normal map +0.09 % and
−0.51 %. Mitsuba without them rendered what we rendered before we
implemented them (within 0.12 % at 4096 spp); ours since: −0.05 % and
−0.04 % (8192 spp).
"""
import os
import re
import sys
import tempfile

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")
SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../scenes/external/mitsuba-data/tests/scenes/bsdf_spheres")


def mean_of(path):
    bitmap = mi.Bitmap(path)
    if bitmap.channel_count() != 3:
        bitmap = bitmap.split()[0][1]
    array = np.array(bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False))
    return float(array[:, :, :3].mean())


def render(text, spp=4096):
    # Write next to the original so that its relative paths resolve.
    handle, path = tempfile.mkstemp(suffix=".xml", dir=SCENES)
    try:
        with os.fdopen(handle, "w") as file:
            file.write(text)
        scene = mi.load_file(path, spp=spp)
        image = np.array(mi.render(scene, seed=3))[:, :, :3]
        return float(image.mean())
    finally:
        os.remove(path)


for name in ["bumpmap", "normalmap"]:
    with open(f"{SCENES}/test_{name}_path.xml") as file:
        text = file.read()
    off = re.sub(
        rf'(<bsdf type="{name}"[^>]*>)',
        r'\1<boolean name="flip_invalid_normals" value="false"/>'
        r'<boolean name="use_shadowing_function" value="false"/>',
        text,
    )
    reference = mean_of(f"{SCENES}/refs/test_{name}_ref_spectral.exr")
    on_mean, off_mean = render(text), render(off)
    print(f"{name}: reference {reference:.5f}, options on {on_mean:.5f} "
          f"({100 * (on_mean / reference - 1):+.2f} %), off {off_mean:.5f} "
          f"({100 * (off_mean / reference - 1):+.2f} %)")
    if len(sys.argv) > 1:
        ours = mean_of(os.path.join(sys.argv[1], f"{name}.exr"))
        print(f"  ours {ours:.5f} ({100 * (ours / reference - 1):+.2f} %)")

#!/usr/bin/env python3
"""Reference for `crates/render/tests/material_cornell_rough.rs`: Mitsuba 3's
Cornell box (`scenes/cbox/cbox-rgb.xml`) with the two boxes' diffuse BSDF
replaced by rough materials: the large box a rough conductor (GGX, alpha 0.2,
eta 0.2, k 3), the small box a rough plastic (Beckmann, alpha 0.3, int_ior
1.5, diffuse rgb 0.2 0.6 0.3, nonlinear), both inside `twosided`.

Rendered with Mitsuba 3.9.1 scalar_spectral as the Cornell reference is (see
scripts/perf/mitsuba_cbox_reference.py, whose helpers this reuses): K
independent 256x256 images, box-downsampled to 64x64, mean and variance of
the mean written as PFM to crates/render/tests/data/cbox_rough_mitsuba_*.pfm.

Usage (what made the committed reference, ~7 min on the shared 2 cores):
    python3 scripts/golden/mitsuba_cbox_rough_reference.py --images 12 --res 128 --factor 2
"""
import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts/perf"))
from mitsuba_cbox_reference import write_pfm  # noqa: E402

CBOX = ROOT / "scenes/external/mitsuba-data/scenes/cbox"
OUTPUT = ROOT / "crates/render/tests/data"

BSDFS = """
    <bsdf type="twosided" id="largebox_bsdf">
        <bsdf type="roughconductor">
            <string name="distribution" value="ggx"/>
            <float name="alpha" value="0.2"/>
            <float name="eta" value="0.2"/>
            <float name="k" value="3.0"/>
        </bsdf>
    </bsdf>
    <bsdf type="twosided" id="smallbox_bsdf">
        <bsdf type="roughplastic">
            <string name="distribution" value="beckmann"/>
            <float name="alpha" value="0.3"/>
            <float name="int_ior" value="1.5"/>
            <float name="ext_ior" value="1.0"/>
            <boolean name="nonlinear" value="true"/>
            <rgb name="diffuse_reflectance" value="0.2, 0.6, 0.3"/>
        </bsdf>
    </bsdf>
"""


def scene_xml():
    shapes = (CBOX / "fragments/shapes.xml").read_text()
    shapes = shapes.replace('value="meshes/', f'value="{CBOX}/meshes/')
    small, large = "cbox_smallbox.obj\"/>\n        <ref id=\"box\"/>", "cbox_largebox.obj\"/>\n        <ref id=\"box\"/>"
    assert small in shapes and large in shapes
    shapes = shapes.replace(small, "cbox_smallbox.obj\"/>\n        <ref id=\"smallbox_bsdf\"/>")
    shapes = shapes.replace(large, "cbox_largebox.obj\"/>\n        <ref id=\"largebox_bsdf\"/>")
    body = shapes.split("<scene version=\"3.0.0\">", 1)[1].rsplit("</scene>", 1)[0]
    return f"""<scene version="3.0.0">
    <include filename="{CBOX}/fragments/base.xml"/>
    <include filename="{CBOX}/fragments/bsdfs-rgb.xml"/>
    {BSDFS}
    {body}
    <emitter type="area" id="area-emitter">
        <rgb name="radiance" value="18.387, 10.9873, 2.75357"/>
    </emitter>
</scene>
"""


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--images", type=int, default=16)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--factor", type=int, default=4)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant("scalar_spectral")
    dr.set_thread_count(args.threads)
    with tempfile.NamedTemporaryFile("w", suffix=".xml", delete=False) as file:
        file.write(scene_xml())
    scene = mi.load_file(file.name, spp=args.spp, res=args.res, max_depth=6)
    small = args.res // args.factor
    images = []
    start = time.perf_counter()
    for seed in range(args.images):
        image = np.array(mi.render(scene, spp=args.spp, seed=seed), dtype=np.float64)[..., :3]
        images.append(image.reshape(small, args.factor, small, args.factor, 3).mean(axis=(1, 3)))
        print(f"image {seed + 1}/{args.images}, {time.perf_counter() - start:.1f} s", flush=True)
    stack = np.stack(images)
    write_pfm(OUTPUT / "cbox_rough_mitsuba_mean.pfm", stack.mean(axis=0))
    write_pfm(OUTPUT / "cbox_rough_mitsuba_variance.pfm", stack.var(axis=0, ddof=1) / args.images)
    print("image mean", stack.mean(axis=(0, 1, 2)))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Golden BSDF values from Mitsuba 3.9.1 (`pip install mitsuba==3.9.1`),
variant scalar_rgb, for crates/render/tests/material_mitsuba_golden.rs.

Writes crates/render/tests/data/mitsuba_bsdf_golden.txt, one line per
evaluation:

    CASE wo_x wo_y wo_z wi_x wi_y wi_z value

in lqmc's conventions: wo towards the camera (Mitsuba's si.wi), wi the light
direction (Mitsuba's wo), value = f(wo, wi) *without* the cosine factor
(Mitsuba's eval divided by |cos θ_wi|), first RGB channel (all parameters are
grey). CASE names the BSDF; the Rust test builds the same one. For the delta
BSDF `thin` the value is the probability of the reflection lobe R'
(Mitsuba's sampled pdf), and `ior:NAME` lines give Mitsuba's index for a
named `int_ior`.

Usage: python3 scripts/golden/mitsuba_bsdf_golden.py
"""
import math
import pathlib

import mitsuba as mi

mi.set_variant("scalar_rgb")

OUT = pathlib.Path(__file__).resolve().parents[2] / "crates/render/tests/data/mitsuba_bsdf_golden.txt"

CASES = {
    "conductor_ggx_03": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.3, "eta": 0.2, "k": 3.0},
    "conductor_ggx_aniso": {"type": "roughconductor", "distribution": "ggx", "alpha_u": 0.25, "alpha_v": 0.05, "eta": 1.1, "k": 2.6},
    "conductor_beckmann_02": {"type": "roughconductor", "distribution": "beckmann", "alpha": 0.2, "eta": 0.2, "k": 3.0},
    "conductor_beckmann_aniso": {"type": "roughconductor", "distribution": "beckmann", "alpha_u": 0.1, "alpha_v": 0.4, "eta": 0.2, "k": 3.0},
    "dielectric_ggx_02": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.2, "int_ior": 1.5, "ext_ior": 1.0},
    "dielectric_beckmann_03": {"type": "roughdielectric", "distribution": "beckmann", "alpha": 0.3, "int_ior": 1.33, "ext_ior": 1.0},
    "dielectric_ggx_aniso_ext": {"type": "roughdielectric", "distribution": "ggx", "alpha_u": 0.3, "alpha_v": 0.1, "int_ior": 1.5, "ext_ior": 1.2},
    "plastic_linear": {"type": "plastic", "diffuse_reflectance": {"type": "rgb", "value": 0.5}, "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": False},
    "plastic_nonlinear": {"type": "plastic", "diffuse_reflectance": {"type": "rgb", "value": 0.8}, "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": True},
    "roughplastic_ggx_01": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.1, "diffuse_reflectance": {"type": "rgb", "value": 0.5}, "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": False},
    "roughplastic_beckmann_03_nonlinear": {"type": "roughplastic", "distribution": "beckmann", "alpha": 0.3, "diffuse_reflectance": {"type": "rgb", "value": 0.8}, "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": True},
    "roughplastic_ggx_04_bk7": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.4, "diffuse_reflectance": {"type": "rgb", "value": 0.2}, "int_ior": "bk7", "ext_ior": "air", "nonlinear": True},
}

THIN = {"thin_water": {"type": "thindielectric", "int_ior": "water", "ext_ior": "air"}}

IOR_NAMES = ["vacuum", "helium", "hydrogen", "air", "carbon dioxide", "water", "acetone", "ethanol",
             "carbon tetrachloride", "glycerol", "benzene", "silicone oil", "bromine", "water ice",
             "fused quartz", "pyrex", "acrylic glass", "polypropylene", "bk7", "sodium chloride",
             "amber", "pet", "diamond"]


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def pairs(transmissive):
    wos = [direction(0, 0), direction(30, 10), direction(60, 200), direction(80, 45)]
    wis = [direction(0, 0), direction(20, 190), direction(45, 80), direction(70, 300), direction(35, 10)]
    out = [(wo, wi) for wo in wos for wi in wis]
    if transmissive:
        below = lambda w: [w[0], w[1], -w[2]]
        out += [(wo, below(wi)) for wo in wos for wi in wis]
        out += [(below(wo), wi) for wo in wos[:3] for wi in wis]
        out += [(below(wo), below(wi)) for wo in wos[:3] for wi in wis[:3]]
    return out


def main():
    lines = []
    ctx = mi.BSDFContext()
    for name, spec in CASES.items():
        bsdf = mi.load_dict(spec)
        for wo, wi in pairs(spec["type"] == "roughdielectric"):
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
            value = bsdf.eval(ctx, si, mi.Vector3f(wi))
            f = value[0] / abs(wi[2])
            lines.append(" ".join([name] + [f"{x:.9g}" for x in wo + wi] + [f"{f:.9g}"]))
    for name, spec in THIN.items():
        bsdf = mi.load_dict(spec)
        for theta in [0, 20, 45, 70, 85]:
            wo = direction(theta, 30)
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(wo)
            bs, _ = bsdf.sample(ctx, si, 0.0, mi.Point2f(0.5, 0.5))
            lines.append(" ".join([name] + [f"{x:.9g}" for x in wo + wo] + [f"{bs.pdf:.9g}"]))
    for name in IOR_NAMES:
        bsdf = mi.load_dict({"type": "dielectric", "int_ior": name, "ext_ior": 1.0})
        eta = mi.traverse(bsdf)["eta"]
        lines.append(f"ior:{name.replace(' ', '_')} 0 0 0 0 0 0 {eta:.9g}")
    OUT.write_text("\n".join(lines) + "\n")
    print(f"{len(lines)} lines -> {OUT}")


if __name__ == "__main__":
    main()

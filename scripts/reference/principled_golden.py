#!/usr/bin/env python3
"""Golden values of Mitsuba 3.9.1's `principled` and `principledthin` BSDFs
(`pip install mitsuba==3.9.1`), variant scalar_spectral, for
crates/render/tests/material_principled_golden.rs.

Writes crates/render/tests/data/mitsuba_principled_golden.txt, one line per
evaluation:

    CASE MODE wo_x wo_y wo_z wi_x wi_y wi_z f0 f1 f2 f3 pdf

in lqmc's conventions: wo towards the camera (Mitsuba's si.wi), wi the light
direction (Mitsuba's wo), f_k = f(wo, wi) at wavelength k of WAVELENGTHS
*without* the cosine factor (Mitsuba's eval divided by |cos θ_wi|), pdf =
Mitsuba's bsdf.pdf; MODE is R (radiance) or I (importance). The base colour
is BASE_COLOR, a spectrum linear in λ, so that the tints (which divide by
Mitsuba's spectral luminance) are exercised. Lines `# case NAME
TYPE key=value ...` at the top give each case's parameters (Mitsuba's
names; omitted ones take Mitsuba's defaults); the Rust test builds the same
BSDF from them.

Usage: python3 scripts/reference/principled_golden.py
"""
import math
import pathlib

import mitsuba as mi

mi.set_variant("scalar_spectral")

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "crates/render/tests/data/mitsuba_principled_golden.txt"

WAVELENGTHS = [450.0, 520.0, 580.0, 640.0]
# base(λ) = 0.2 + 0.6 (λ − 360)/(830 − 360): Mitsuba's `irregular` spectrum
# interpolates linearly between the two nodes.
BASE_COLOR = {"type": "irregular", "wavelengths": "360, 830", "values": "0.2, 0.8"}

CASES = {
    "default": {"type": "principled"},
    "metal_aniso": {"type": "principled", "metallic": 0.7, "roughness": 0.3, "anisotropic": 0.6, "specular": 0.7},
    "coat_sheen": {"type": "principled", "roughness": 0.4, "clearcoat": 0.8, "clearcoat_gloss": 0.3,
                   "sheen": 0.6, "sheen_tint": 0.5, "spec_tint": 0.4, "specular": 0.6},
    "flat": {"type": "principled", "roughness": 0.6, "flatness": 0.7, "metallic": 0.2},
    "glass": {"type": "principled", "roughness": 0.25, "spec_trans": 0.7, "anisotropic": 0.3,
              "clearcoat": 0.5, "sheen": 0.4, "eta": 1.4},
    "glass_full": {"type": "principled", "roughness": 0.15, "spec_trans": 1.0, "specular": 0.4},
    "scene1": {"type": "principled", "roughness": 0.15, "anisotropic": 0.8, "metallic": 0.1,
               "clearcoat": 0.9, "sheen": 0.2, "specular": 0.7},
    "rates": {"type": "principled", "roughness": 0.3, "spec_trans": 0.4, "clearcoat": 0.5,
              "main_specular_sampling_rate": 0.5, "clearcoat_sampling_rate": 2.0,
              "diffuse_reflectance_sampling_rate": 0.7},
    "thin_default": {"type": "principledthin"},
    "thin_scene": {"type": "principledthin", "anisotropic": 0.8, "spec_trans": 0.8, "diff_trans": 1.4,
                   "sheen": 0.8, "eta": 1.33},
    "thin_tint": {"type": "principledthin", "roughness": 0.3, "spec_trans": 0.5, "diff_trans": 0.6,
                  "spec_tint": 0.6, "sheen": 0.5, "sheen_tint": 0.7, "flatness": 0.4, "eta": 1.6},
    "thin_rates": {"type": "principledthin", "roughness": 0.4, "spec_trans": 0.3, "diff_trans": 0.5,
                   "specular_reflectance_sampling_rate": 0.5, "specular_transmittance_sampling_rate": 2.0,
                   "diffuse_reflectance_sampling_rate": 1.5, "diffuse_transmittance_sampling_rate": 0.3},
}


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def pairs():
    wos = [direction(0, 0), direction(30, 10), direction(60, 200), direction(80, 45),
           direction(150, 30), direction(120, 250)]
    wis = [direction(0, 0), direction(20, 190), direction(45, 80), direction(70, 300), direction(35, 10),
           direction(160, 20), direction(130, 200), direction(100, 100), direction(175, 300)]
    return [(wo, wi) for wo in wos for wi in wis]


def main():
    lines = [" ".join(["#", "wavelengths"] + [f"{l:g}" for l in WAVELENGTHS])]
    for name, params in CASES.items():
        keys = [f"{k}={v}" for k, v in params.items() if k != "type"]
        lines.append(" ".join(["#", "case", name, params["type"]] + keys))
    for name, params in CASES.items():
        bsdf = mi.load_dict({**params, "base_color": BASE_COLOR})
        for mode, mode_name in [(mi.TransportMode.Radiance, "R"), (mi.TransportMode.Importance, "I")]:
            if mode_name == "I" and "spec_trans" not in params:
                continue
            ctx = mi.BSDFContext(mode)
            for wo, wi in pairs():
                si = mi.SurfaceInteraction3f()
                si.wi = mi.Vector3f(wo)
                si.wavelengths = mi.Spectrum(WAVELENGTHS)
                value = bsdf.eval(ctx, si, mi.Vector3f(wi))
                pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
                f = [float(value[k]) / abs(wi[2]) for k in range(4)]
                fields = [name, mode_name] + [f"{x:.9g}" for x in wo + wi + f + [float(pdf)]]
                lines.append(" ".join(fields))
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {len(lines)} lines to {OUT}")
    # Mitsuba's spectral luminance of the base colour (for the tints).
    base = [0.2 + 0.6 * (l - 360.0) / 470.0 for l in WAVELENGTHS]
    print("luminance", mi.luminance(mi.Spectrum(base), mi.Spectrum(WAVELENGTHS)))


if __name__ == "__main__":
    main()

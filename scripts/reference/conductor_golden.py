#!/usr/bin/env python3
"""Golden values of Mitsuba 3.9.1's `conductor` and `roughconductor` BSDFs
(`pip install mitsuba==3.9.1`), variant scalar_spectral, for
crates/render/tests/material_conductor_golden.rs.

The cases are the conductors of the scenes the project compares with
Mitsuba and Tungsten: constant η and κ (the Mitsuba test scenes'
`bsdf_spheres`), Mitsuba's named materials (`<string name="material">`,
measured η and κ tables) and a `specular_reflectance` factor (Bitterli's
veach-mis has 0.3).

Not covered on purpose: RGB η and κ. Mitsuba 3.9.1's scalar_spectral lifts
`<rgb name="eta">` / `<rgb name="k">` of a conductor with its *reflectance*
upsampling, bounded to [0, 1] (a `SRGBReflectanceSpectrum` with saturated
coefficients: veach-mis's copper k = (3.91, 2.45, 2.14) becomes k = 1 at every
wavelength, and its normal-incidence reflectance 0.20 at 400–550 nm instead of
copper's 0.5–0.6). lqmc lifts them as unbounded spectra (pbrt-v4's
RGBUnboundedSpectrum), which is what the RGB renderers (Tungsten, Mitsuba's
RGB variants) mean by them.

Writes crates/render/tests/data/mitsuba_conductor_golden.txt:

    # case NAME TYPE key=value ...      (the BSDF's parameters, Mitsuba's names)
    S NAME l0 l1 l2 l3 cos f0 f1 f2 f3
        a smooth conductor: Mitsuba's sample weight (Fresnel reflectance
        times specular_reflectance) at incidence cosine `cos` and the four
        wavelengths l0..l3 (nm)
    R NAME l0 l1 l2 l3 wo_x wo_y wo_z wi_x wi_y wi_z f0 f1 f2 f3 pdf
        a rough conductor: f(wo, wi) without the cosine factor (Mitsuba's
        eval divided by cos θ_wi) and Mitsuba's pdf, in lqmc's conventions
        (wo towards the camera, Mitsuba's si.wi; wi the light direction)

Usage: python3 scripts/reference/conductor_golden.py
"""
import math
import pathlib

import mitsuba as mi

mi.set_variant("scalar_spectral")

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "crates/render/tests/data/mitsuba_conductor_golden.txt"

WAVELENGTH_SETS = [[400.0, 450.0, 500.0, 550.0], [600.0, 650.0, 700.0, 530.0]]

# name -> (plugin, parameters); `eta`/`k` given as a float (constant
# spectrum) or a list (rgb), `material` as a name.
CASES = {
    "spheres_smooth": ("conductor", {"eta": 0.789, "k": 6.15}),
    "Au": ("conductor", {"material": "Au"}),
    "Ag": ("conductor", {"material": "Ag"}),
    "Al": ("conductor", {"material": "Al"}),
    "Cu": ("conductor", {"material": "Cu"}),
    "Cr": ("conductor", {"material": "Cr"}),
    "Cu_palik": ("conductor", {"material": "Cu_palik"}),
    "none": ("conductor", {"material": "none"}),
    "Cu_03": ("conductor", {"material": "Cu", "specular_reflectance": 0.3}),
    "spheres_rough": ("roughconductor", {"distribution": "beckmann", "alpha": 0.05, "eta": 0.789, "k": 6.15}),
    "Au_ggx": ("roughconductor", {"distribution": "ggx", "alpha": 0.3, "material": "Au"}),
    "Cu_beckmann": ("roughconductor", {"distribution": "beckmann", "alpha": 0.2, "material": "Cu"}),
    "Cu_glossy_03": ("roughconductor", {"distribution": "beckmann", "alpha": 0.1, "material": "Cu",
                                        "specular_reflectance": 0.3}),
    "ggx_025": ("roughconductor", {"distribution": "ggx", "alpha": 0.25, "eta": 0.2, "k": 3.9}),
}

COSINES = [1.0, 0.9, 0.7, 0.5, 0.3, 0.1]


def spectrum(value):
    if isinstance(value, list):
        return {"type": "rgb", "value": value}
    return {"type": "spectrum", "value": value}


def mitsuba_dict(plugin, params):
    d = {"type": plugin}
    for key, value in params.items():
        if key in ("eta", "k", "specular_reflectance"):
            d[key] = spectrum(value)
        else:
            d[key] = value
    return d


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def rough_pairs():
    """Front-side pairs, with some near the mirror direction (the peak)."""
    wos = [direction(0, 0), direction(30, 10), direction(60, 200), direction(80, 45)]
    pairs = []
    for wo in wos:
        theta_o = math.degrees(math.acos(wo[2]))
        phi_o = math.degrees(math.atan2(wo[1], wo[0]))
        for d_theta, d_phi in [(0, 180), (3, 180), (8, 175), (15, 170)]:
            theta = min(89.0, theta_o + d_theta)
            pairs.append((wo, direction(theta, phi_o + d_phi)))
        for wi in [direction(20, 190), direction(45, 80), direction(70, 300)]:
            pairs.append((wo, wi))
    return pairs


def fmt(values):
    return [f"{x:.9g}" for x in values]


def main():
    lines = []
    for name, (plugin, params) in CASES.items():
        keys = [f"{k}={','.join(map(str, v)) if isinstance(v, list) else v}" for k, v in params.items()]
        lines.append(" ".join(["#", "case", name, plugin] + keys))
    for name, (plugin, params) in CASES.items():
        bsdf = mi.load_dict(mitsuba_dict(plugin, params))
        ctx = mi.BSDFContext()
        for lambdas in WAVELENGTH_SETS:
            if plugin == "conductor":
                for cos in COSINES:
                    si = mi.SurfaceInteraction3f()
                    si.wi = mi.Vector3f(math.sqrt(1.0 - cos * cos), 0.0, cos)
                    si.wavelengths = mi.Spectrum(lambdas)
                    _, weight = bsdf.sample(ctx, si, 0.5, mi.Point2f(0.5, 0.5))
                    f = [float(weight[k]) for k in range(4)]
                    lines.append(" ".join(["S", name] + fmt(lambdas + [cos] + f)))
            else:
                for wo, wi in rough_pairs():
                    si = mi.SurfaceInteraction3f()
                    si.wi = mi.Vector3f(wo)
                    si.wavelengths = mi.Spectrum(lambdas)
                    value = bsdf.eval(ctx, si, mi.Vector3f(wi))
                    pdf = bsdf.pdf(ctx, si, mi.Vector3f(wi))
                    f = [float(value[k]) / abs(wi[2]) for k in range(4)]
                    lines.append(" ".join(["R", name] + fmt(lambdas + wo + wi + f + [float(pdf)])))
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {len(lines)} lines to {OUT}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Reference values of the unpolarised Fresnel reflectance of a conductor with
complex relative index eta + i k, for the material tests
(crates/render/tests/material_bsdf.rs, CONDUCTOR_REFERENCE).

Uses the real-arithmetic form of the conductor Fresnel equations (Born and
Wolf, Principles of Optics, 14.2; the a^2 + b^2 form also used by pbrt-v3's
FrConductor), in double precision, independent of the complex-arithmetic form
the renderer implements. Output: one Rust tuple per line,
(cos_theta_i, eta, k, reflectance).
"""
import math

CASES = [
    (0.2, 3.0),   # gold-like metal in the red
    (0.27, 2.78),
    (1.1, 2.6),   # copper-like metal in the blue-green
    (2.0, 0.5),
    (1.5, 0.0),   # a dielectric: must equal the dielectric Fresnel formula
]
COSINES = [1.0, 0.8, 0.5, 0.2, 0.05]


def conductor_reflectance(cos_i, eta, k):
    cos2 = cos_i * cos_i
    sin2 = 1.0 - cos2
    t0 = eta * eta - k * k - sin2
    a2_plus_b2 = math.sqrt(t0 * t0 + 4.0 * eta * eta * k * k)
    a = math.sqrt(max(0.0, 0.5 * (a2_plus_b2 + t0)))
    t1 = a2_plus_b2 + cos2
    t2 = 2.0 * cos_i * a
    r_s = (t1 - t2) / (t1 + t2)
    t3 = cos2 * a2_plus_b2 + sin2 * sin2
    t4 = t2 * sin2
    r_p = r_s * (t3 - t4) / (t3 + t4)
    return 0.5 * (r_s + r_p)


for eta, k in CASES:
    for cos_i in COSINES:
        print(f"    ({cos_i:.2f}, {eta:.2f}, {k:.2f}, {conductor_reflectance(cos_i, eta, k):.9f}),")

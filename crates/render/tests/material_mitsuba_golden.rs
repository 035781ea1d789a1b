//! BSDF values against Mitsuba 3.9.1: `tests/data/mitsuba_bsdf_golden.txt`,
//! made by `scripts/golden/mitsuba_bsdf_golden.py` (`bsdf.eval` in
//! `scalar_rgb`, divided by the cosine), checked here without Python.
//!
//! Tolerances: GGX models agree to float rounding (relative 2·10⁻³ plus a
//! small absolute slack for values near 0). Beckmann models use the exact
//! Smith Λ here and Walter et al.'s rational fit in Mitsuba (< 0.4 % apart
//! per G1 term), so they get 1 %. Rough plastics get 1 % (their coating
//! tables come from different quadratures).

use glam::Vec3;
use render::material::{
    Bsdf, ConductorReflectance, MicrofacetDistribution, MicrofacetKind, PlasticBsdf,
    RoughConductorBsdf, RoughDielectricBsdf, RoughPlasticBsdf, RoughPlasticTables,
    ThinDielectricBsdf,
};
use render::scene::spectra::named_ior;
use render::spectrum::{SampledSpectrum, SampledWavelengths};

const GOLDEN: &str = include_str!("data/mitsuba_bsdf_golden.txt");

fn conductor(kind: MicrofacetKind, ax: f32, ay: f32, eta: f32, k: f32) -> Bsdf {
    RoughConductorBsdf::new(
        MicrofacetDistribution::new(kind, ax, ay),
        ConductorReflectance::Fresnel {
            eta: SampledSpectrum::splat(eta),
            k: SampledSpectrum::splat(k),
        },
        SampledSpectrum::splat(1.0),
        false,
    )
    .into()
}

fn rough_plastic(
    kind: MicrofacetKind,
    alpha: f32,
    diffuse: f32,
    eta: f32,
    nonlinear: bool,
) -> Bsdf {
    let distribution = MicrofacetDistribution::new(kind, alpha, alpha);
    RoughPlasticBsdf::new(
        distribution,
        RoughPlasticTables::shared(&distribution, eta),
        SampledSpectrum::splat(diffuse),
        eta,
        nonlinear,
        false,
    )
    .into()
}

/// The BSDF a case name stands for and the relative tolerance.
fn case(name: &str) -> (Bsdf, f32) {
    use MicrofacetKind::{Beckmann, Ggx};
    match name {
        "conductor_ggx_03" => (conductor(Ggx, 0.3, 0.3, 0.2, 3.0), 2e-3),
        "conductor_ggx_aniso" => (conductor(Ggx, 0.25, 0.05, 1.1, 2.6), 2e-3),
        "conductor_beckmann_02" => (conductor(Beckmann, 0.2, 0.2, 0.2, 3.0), 1e-2),
        "conductor_beckmann_aniso" => (conductor(Beckmann, 0.1, 0.4, 0.2, 3.0), 1e-2),
        "dielectric_ggx_02" => (
            RoughDielectricBsdf::new(MicrofacetDistribution::new(Ggx, 0.2, 0.2), 1.5, false).into(),
            2e-3,
        ),
        "dielectric_beckmann_03" => (
            RoughDielectricBsdf::new(MicrofacetDistribution::new(Beckmann, 0.3, 0.3), 1.33, false)
                .into(),
            1e-2,
        ),
        "dielectric_ggx_aniso_ext" => (
            RoughDielectricBsdf::new(MicrofacetDistribution::new(Ggx, 0.3, 0.1), 1.5 / 1.2, false)
                .into(),
            2e-3,
        ),
        "plastic_linear" => (
            PlasticBsdf::new(SampledSpectrum::splat(0.5), 1.5, false, false).into(),
            2e-3,
        ),
        "plastic_nonlinear" => (
            PlasticBsdf::new(SampledSpectrum::splat(0.8), 1.5, true, false).into(),
            2e-3,
        ),
        "roughplastic_ggx_01" => (rough_plastic(Ggx, 0.1, 0.5, 1.5, false), 1e-2),
        "roughplastic_beckmann_03_nonlinear" => {
            (rough_plastic(Beckmann, 0.3, 0.8, 1.5, true), 1e-2)
        }
        "roughplastic_ggx_04_bk7" => (rough_plastic(Ggx, 0.4, 0.2, 1.5046 / 1.000277, true), 1e-2),
        other => panic!("unknown golden case {other}"),
    }
}

struct Line<'a> {
    name: &'a str,
    wo: Vec3,
    wi: Vec3,
    value: f32,
}

fn lines() -> impl Iterator<Item = Line<'static>> {
    GOLDEN.lines().filter(|line| !line.is_empty()).map(|line| {
        let mut fields = line.split_whitespace();
        let name = fields.next().expect("case name");
        let numbers: Vec<f32> = fields
            .map(|field| field.parse().expect("a number"))
            .collect();
        assert_eq!(numbers.len(), 7, "{line}");
        Line {
            name,
            wo: Vec3::new(numbers[0], numbers[1], numbers[2]),
            wi: Vec3::new(numbers[3], numbers[4], numbers[5]),
            value: numbers[6],
        }
    })
}

#[test]
fn bsdf_values_match_mitsuba() {
    let wavelengths = SampledWavelengths::sample_visible(0.5);
    let mut checked = 0;
    let mut failures = Vec::new();
    for line in lines() {
        if line.name.starts_with("ior:") || line.name.starts_with("thin") {
            continue;
        }
        let (bsdf, tolerance) = case(line.name);
        let ours = bsdf.evaluate(line.wo, line.wi, &wavelengths)[0];
        let slack = tolerance * line.value.abs() + 1e-4;
        if (ours - line.value).abs() > slack {
            failures.push(format!(
                "{} wo {} wi {}: ours {ours}, Mitsuba {}",
                line.name, line.wo, line.wi, line.value
            ));
        }
        checked += 1;
    }
    assert!(checked > 300, "{checked} values");
    assert!(
        failures.is_empty(),
        "{} of {checked} differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn thin_dielectric_reflectance_matches_mitsuba() {
    let thin = ThinDielectricBsdf::new(1.3330 / 1.000277);
    for line in lines().filter(|line| line.name == "thin_water") {
        let ours = thin.reflectance(line.wo.z);
        assert!(
            (ours - line.value).abs() < 1e-5,
            "{}: {ours} vs {}",
            line.wo,
            line.value
        );
    }
}

#[test]
fn named_indices_match_mitsuba() {
    let mut count = 0;
    for line in lines() {
        let Some(name) = line.name.strip_prefix("ior:") else {
            continue;
        };
        let name = name.replace('_', " ");
        let ours = named_ior(&name).unwrap_or_else(|| panic!("{name} unknown"));
        assert!(
            (ours - line.value).abs() < 1e-6,
            "{name}: {ours} vs {}",
            line.value
        );
        count += 1;
    }
    assert_eq!(count, 23);
    assert!(named_ior("unobtainium").is_none());
}

//! Mitsuba 3.9.1's `conductor` and `roughconductor` against ours, in spectral
//! mode: `tests/data/mitsuba_conductor_golden.txt`, made by
//! `scripts/reference/conductor_golden.py` (`scalar_spectral`, two sets of
//! four wavelengths from 400 to 700 nm), checked here without Python.
//!
//! Covered: constant η and κ (the `bsdf_spheres` test scenes' conductor and
//! Beckmann α = 0.05 rough conductor), Mitsuba's named materials (`Au`, `Ag`,
//! `Al`, `Cu`, `Cr`, `Cu_palik`, `none`; our tables are Mitsuba's, looked up
//! by the names the Mitsuba loader uses, `metal-NAME-eta` / `metal-NAME-k`),
//! a `specular_reflectance` factor of 0.3, GGX and Beckmann.
//!
//! Smooth conductors are compared through the weight of a sample (Fresnel
//! reflectance times the factor), rough ones through f and the pdf.
//! Tolerances: relative 10⁻³ for the smooth Fresnel (the same formula, and
//! the tables interpolated linearly on both sides); for rough conductors
//! 2·10⁻³ with GGX and 1 % with Beckmann (exact Smith Λ here, Walter's
//! rational fit in Mitsuba), relative 10⁻² near the sharp peaks, where the
//! rounding of the half vector is amplified, plus an absolute 10⁻⁴.

use glam::Vec3;
use render::material::{
    Bsdf, ConductorBsdf, ConductorReflectance, MicrofacetDistribution, MicrofacetKind,
    RoughConductorBsdf,
};
use render::scene::spectra::named_spectrum;
use render::spectrum::{SampledSpectrum, SampledWavelengths};

const GOLDEN: &str = include_str!("data/mitsuba_conductor_golden.txt");

/// A case's parameters as the script wrote them (`key=value`).
struct Case {
    name: String,
    plugin: String,
    keys: Vec<(String, String)>,
}

impl Case {
    fn get(&self, key: &str) -> Option<&str> {
        self.keys
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    fn number(&self, key: &str) -> Option<f32> {
        self.get(key).map(|v| v.parse().unwrap())
    }
}

fn cases() -> Vec<Case> {
    GOLDEN
        .lines()
        .filter_map(|line| line.strip_prefix("# case "))
        .map(|line| {
            let mut fields = line.split_whitespace();
            let name = fields.next().unwrap().to_string();
            let plugin = fields.next().unwrap().to_string();
            let keys = fields
                .map(|field| {
                    let (k, v) = field.split_once('=').unwrap();
                    (k.to_string(), v.to_string())
                })
                .collect();
            Case { name, plugin, keys }
        })
        .collect()
}

/// η and κ at `wavelengths`, or `None` for Mitsuba's `none` (a perfect
/// mirror).
fn eta_and_k(case: &Case, wavelengths: &SampledWavelengths) -> Option<ConductorReflectance> {
    let (eta, k) = match case.get("material") {
        Some("none") => return None,
        Some(material) => (
            named_spectrum(&format!("metal-{material}-eta"))
                .unwrap_or_else(|| panic!("no metal-{material}-eta"))
                .sample(wavelengths),
            named_spectrum(&format!("metal-{material}-k"))
                .unwrap_or_else(|| panic!("no metal-{material}-k"))
                .sample(wavelengths),
        ),
        None => (
            SampledSpectrum::splat(case.number("eta").unwrap()),
            SampledSpectrum::splat(case.number("k").unwrap()),
        ),
    };
    Some(ConductorReflectance::Fresnel { eta, k })
}

/// Our BSDF for a case (one-sided, as Mitsuba's outside a `twosided`).
fn build(case: &Case, wavelengths: &SampledWavelengths) -> Bsdf {
    let factor = SampledSpectrum::splat(case.number("specular_reflectance").unwrap_or(1.0));
    let reflectance = eta_and_k(case, wavelengths);
    if case.plugin == "conductor" {
        let smooth = match reflectance {
            Some(ConductorReflectance::Fresnel { eta, k }) => ConductorBsdf::new(eta, k).unwrap(),
            _ => ConductorBsdf::perfect_mirror(),
        };
        return smooth
            .with_two_sided(false)
            .with_specular_factor(factor)
            .into();
    }
    let kind = match case.get("distribution").unwrap() {
        "ggx" => MicrofacetKind::Ggx,
        _ => MicrofacetKind::Beckmann,
    };
    let alpha = case.number("alpha").unwrap();
    RoughConductorBsdf::new(
        MicrofacetDistribution::new(kind, alpha, alpha),
        reflectance.unwrap_or(ConductorReflectance::Perfect),
        factor,
        false,
    )
    .into()
}

fn close(ours: f32, theirs: f32, relative: f32) -> bool {
    (ours - theirs).abs() <= relative * theirs.abs() + 1e-4
}

/// |ours − theirs| / theirs, for the report (0 where Mitsuba's value is 0).
fn relative_difference(ours: f32, theirs: f32) -> f32 {
    if theirs == 0.0 {
        0.0
    } else {
        (ours - theirs).abs() / theirs.abs()
    }
}

#[test]
fn conductors_match_mitsuba_spectral() {
    let cases = cases();
    assert_eq!(cases.len(), 14);
    let mut failures = Vec::new();
    let (mut smooth, mut rough) = (0, 0);
    let (mut largest_smooth, mut largest_rough) = (0.0f32, 0.0f32);
    for line in GOLDEN.lines().filter(|line| !line.starts_with('#')) {
        let mut fields = line.split_whitespace();
        let kind = fields.next().unwrap();
        let name = fields.next().unwrap();
        let numbers: Vec<f32> = fields.map(|field| field.parse().unwrap()).collect();
        let case = cases.iter().find(|case| case.name == name).unwrap();
        let lambdas: [f32; 4] = numbers[..4].try_into().unwrap();
        let mut wavelengths = SampledWavelengths::from_parts(lambdas, [1.0; 4]).unwrap();
        let bsdf = build(case, &wavelengths);
        if kind == "S" {
            assert_eq!(numbers.len(), 9, "{line}");
            let cos = numbers[4];
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            let sample = bsdf
                .sample(wo, 0.5, [0.5, 0.5], &mut wavelengths)
                .expect("a mirror sample");
            let weight = sample.value * (sample.wi.z.abs() / sample.pdf);
            for k in 0..4 {
                largest_smooth = largest_smooth.max(relative_difference(weight[k], numbers[5 + k]));
                if !close(weight[k], numbers[5 + k], 1e-3) {
                    failures.push(format!(
                        "{name} cos {cos} λ {}: F ours {}, Mitsuba {}",
                        lambdas[k],
                        weight[k],
                        numbers[5 + k]
                    ));
                }
            }
            smooth += 1;
        } else {
            assert_eq!(numbers.len(), 15, "{line}");
            let wo = Vec3::new(numbers[4], numbers[5], numbers[6]);
            let wi = Vec3::new(numbers[7], numbers[8], numbers[9]);
            let value = bsdf.evaluate(wo, wi, &wavelengths);
            let beckmann = case.get("distribution") == Some("beckmann");
            let relative = if value.max_component() > 5.0 || beckmann {
                1e-2
            } else {
                2e-3
            };
            for k in 0..4 {
                if numbers[10 + k] > 1e-3 {
                    largest_rough =
                        largest_rough.max(relative_difference(value[k], numbers[10 + k]));
                }
                if !close(value[k], numbers[10 + k], relative) {
                    failures.push(format!(
                        "{name} wo {wo} wi {wi} λ {}: f ours {}, Mitsuba {}",
                        lambdas[k],
                        value[k],
                        numbers[10 + k]
                    ));
                }
            }
            let pdf = bsdf.pdf(wo, wi);
            if !close(pdf, numbers[14], relative) {
                failures.push(format!(
                    "{name} wo {wo} wi {wi}: pdf ours {pdf}, Mitsuba {}",
                    numbers[14]
                ));
            }
            rough += 1;
        }
    }
    eprintln!(
        "{smooth} smooth lines, largest relative difference {largest_smooth:.2e}; \
         {rough} rough lines, largest relative difference of f {largest_rough:.2e}"
    );
    assert!(
        smooth >= 90 && rough >= 200,
        "{smooth} smooth, {rough} rough lines"
    );
    assert!(
        failures.is_empty(),
        "{} lines differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

//! Mitsuba 3.9.1's `principled` and `principledthin` against ours:
//! `tests/data/mitsuba_principled_golden.txt`, made by
//! `scripts/reference/principled_golden.py` (`bsdf.eval` divided by the
//! cosine and `bsdf.pdf`, in `scalar_spectral` at four fixed wavelengths, for
//! radiance and importance transport), checked here without Python.
//!
//! Both sides use GGX with the separable Smith G and the same closed forms,
//! so values agree to float rounding: relative 2·10⁻³ plus an absolute
//! 10⁻⁴ for values near 0 (and for the sharp GGX peaks, where rounding of
//! the half vector is amplified, relative 10⁻²).
//!
//! One deliberate difference: seen from behind with no transmission
//! (spec_trans = 0 or metallic = 1) the BSDF is black and samples nothing;
//! Mitsuba's `pdf` still reports a density there, which its `sample` never
//! produces. Those pdf values are skipped.

use glam::Vec3;
use render::material::{
    Bsdf, PrincipledBsdf, PrincipledParameters, PrincipledThinBsdf, PrincipledThinParameters,
    TransportMode, principled_eta_from_specular,
};
use render::spectrum::{SampledSpectrum, SampledWavelengths};

const GOLDEN: &str = include_str!("data/mitsuba_principled_golden.txt");

/// The script's base colour: linear from 0.2 at 360 nm to 0.8 at 830 nm.
fn base_color(wavelengths: &SampledWavelengths) -> SampledSpectrum {
    let lambdas = wavelengths.lambdas();
    SampledSpectrum::new(lambdas.map(|lambda| 0.2 + 0.6 * (lambda - 360.0) / 470.0))
}

fn golden_wavelengths() -> SampledWavelengths {
    let line = GOLDEN
        .lines()
        .find_map(|line| line.strip_prefix("# wavelengths "))
        .expect("a wavelengths line");
    let lambdas: Vec<f32> = line
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    SampledWavelengths::from_parts(lambdas.try_into().unwrap(), [1.0; 4]).unwrap()
}

/// A case: the BSDF and whether it transmits (for the back-side rule).
struct Case {
    name: String,
    thin: bool,
    keys: Vec<(String, f32)>,
}

fn cases() -> Vec<Case> {
    GOLDEN
        .lines()
        .filter_map(|line| line.strip_prefix("# case "))
        .map(|line| {
            let mut fields = line.split_whitespace();
            let name = fields.next().unwrap().to_string();
            let thin = fields.next().unwrap() == "principledthin";
            let keys = fields
                .map(|field| {
                    let (key, value) = field.split_once('=').unwrap();
                    (key.to_string(), value.parse().unwrap())
                })
                .collect();
            Case { name, thin, keys }
        })
        .collect()
}

fn build(case: &Case, wavelengths: &SampledWavelengths, mode: TransportMode) -> (Bsdf, bool) {
    let base = base_color(wavelengths);
    let bsdf: Bsdf;
    let transmits;
    if case.thin {
        let mut p = PrincipledThinParameters::new(base);
        for (key, value) in &case.keys {
            let v = *value;
            match key.as_str() {
                "roughness" => p.roughness = v,
                "anisotropic" => p.anisotropic = v,
                "spec_trans" => p.spec_trans = v,
                "eta" => p.eta = v,
                "spec_tint" => p.spec_tint = v,
                "sheen" => p.sheen = v,
                "sheen_tint" => p.sheen_tint = v,
                "flatness" => p.flatness = v,
                "diff_trans" => p.diff_trans = v,
                "specular_reflectance_sampling_rate" => p.specular_reflectance_sampling_rate = v,
                "specular_transmittance_sampling_rate" => {
                    p.specular_transmittance_sampling_rate = v
                }
                "diffuse_reflectance_sampling_rate" => p.diffuse_reflectance_sampling_rate = v,
                "diffuse_transmittance_sampling_rate" => p.diffuse_transmittance_sampling_rate = v,
                other => panic!("unknown thin parameter {other}"),
            }
        }
        transmits = true;
        bsdf = PrincipledThinBsdf::new(p, wavelengths).into();
    } else {
        let mut p = PrincipledParameters::new(base);
        p.eta = principled_eta_from_specular(0.5);
        for (key, value) in &case.keys {
            let v = *value;
            match key.as_str() {
                "roughness" => p.roughness = v,
                "anisotropic" => p.anisotropic = v,
                "metallic" => p.metallic = v,
                "spec_trans" => p.spec_trans = v,
                "eta" => p.eta = v,
                "specular" => p.eta = principled_eta_from_specular(v),
                "spec_tint" => p.spec_tint = v,
                "sheen" => p.sheen = v,
                "sheen_tint" => p.sheen_tint = v,
                "clearcoat" => p.clearcoat = v,
                "clearcoat_gloss" => p.clearcoat_gloss = v,
                "flatness" => p.flatness = v,
                "main_specular_sampling_rate" => p.main_specular_sampling_rate = v,
                "clearcoat_sampling_rate" => p.clearcoat_sampling_rate = v,
                "diffuse_reflectance_sampling_rate" => p.diffuse_reflectance_sampling_rate = v,
                other => panic!("unknown parameter {other}"),
            }
        }
        transmits = (1.0 - p.metallic) * p.spec_trans > 0.0;
        bsdf = PrincipledBsdf::new(p, wavelengths).into();
    }
    (bsdf.with_transport_mode(mode), transmits)
}

fn close(ours: f32, theirs: f32, relative: f32) -> bool {
    (ours - theirs).abs() <= relative * theirs.abs() + 1e-4
}

#[test]
fn principled_values_and_densities_match_mitsuba() {
    let wavelengths = golden_wavelengths();
    let cases = cases();
    assert_eq!(cases.len(), 12);
    let mut checked = 0;
    let mut failures = Vec::new();
    for line in GOLDEN.lines().filter(|line| !line.starts_with('#')) {
        let mut fields = line.split_whitespace();
        let name = fields.next().unwrap();
        let mode = match fields.next().unwrap() {
            "R" => TransportMode::Radiance,
            _ => TransportMode::Importance,
        };
        let numbers: Vec<f32> = fields.map(|field| field.parse().unwrap()).collect();
        assert_eq!(numbers.len(), 11, "{line}");
        let wo = Vec3::new(numbers[0], numbers[1], numbers[2]);
        let wi = Vec3::new(numbers[3], numbers[4], numbers[5]);
        let case = cases.iter().find(|case| case.name == name).unwrap();
        let (bsdf, transmits) = build(case, &wavelengths, mode);
        let value = bsdf.evaluate(wo, wi, &wavelengths);
        // Near-specular lobes amplify f32 rounding of the half vector.
        let relative = if value.max_component() > 5.0 {
            1e-2
        } else {
            2e-3
        };
        for k in 0..4 {
            if !close(value[k], numbers[6 + k], relative) {
                failures.push(format!(
                    "{name} {mode:?} wo {wo} wi {wi} λ{k}: f ours {}, Mitsuba {}",
                    value[k],
                    numbers[6 + k]
                ));
            }
        }
        if wo.z > 0.0 || transmits {
            let pdf = bsdf.pdf(wo, wi);
            if !close(pdf, numbers[10], relative) {
                failures.push(format!(
                    "{name} {mode:?} wo {wo} wi {wi}: pdf ours {pdf}, Mitsuba {}",
                    numbers[10]
                ));
            }
        }
        checked += 1;
    }
    assert!(checked > 900, "{checked} lines");
    assert!(
        failures.is_empty(),
        "{} of {checked} lines differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

//! Statistical and analytic tests of the BSDFs of `render::material`.
//!
//! - chi-square goodness of fit of `sample` against `pdf` (diffuse, two- and
//!   one-sided, several `wo`; the concentric disk mapping; the dielectric's
//!   reflect/refract choice against R and T), with a power check that the test
//!   rejects a wrong sampler;
//! - `sample` returns `evaluate` and `pdf` for non-delta lobes; `pdf`
//!   integrates to 1 over the sphere (uniform-sphere Monte Carlo, tolerance 5
//!   standard errors from the estimator's sample variance: false alarm < 10⁻⁶);
//! - white furnace: f |cos| / pdf is R (diffuse), 1 (mirror), F (conductor), 1
//!   (dielectric, importance) or 1/η² on refraction (dielectric, radiance);
//! - Fresnel: 0.04 at normal incidence on glass, total internal reflection,
//!   conductor values against an independent double-precision formula
//!   (`scripts/conductor_fresnel_reference.py`);
//! - reciprocity of the diffuse BSDF and the reverse-pdf pattern.
//!
//! Random numbers come from `qmc::random::SeekablePcg` with fixed seeds, so
//! every run sees the same samples.

use std::f64::consts::PI;

use glam::Vec3;
use qmc::random::SeekablePcg;
use render::material::{
    Bsdf, BsdfFlags, ConductorBsdf, DielectricBsdf, DiffuseBsdf, TransportMode, UNIFORM_SPHERE_PDF,
    fresnel_complex, fresnel_dielectric, sample_uniform_disk_concentric, sample_uniform_sphere,
};
use render::spectrum::{SampledSpectrum, SampledWavelengths};
use render::statistics::chi_square_test;

/// p-values below this fail a goodness-of-fit test.
const P_VALUE_THRESHOLD: f64 = 1e-4;

// ---------------------------------------------------------------------------
// Direction histograms over the sphere.

/// Cells over the sphere: `Z_BINS` equal slabs in cos θ (an even number, so a
/// slab never straddles z = 0 where hemispherical pdfs have a kink) times
/// `PHI_BINS` equal sectors in φ. Every cell has solid angle
/// (2/Z_BINS)·(2π/PHI_BINS) since dω = dz dφ.
const Z_BINS: usize = 16;
const PHI_BINS: usize = 32;

fn cell_of(direction: Vec3) -> usize {
    let z = f64::from(direction.z).clamp(-1.0, 1.0);
    let z_index = (((z + 1.0) / 2.0 * Z_BINS as f64) as usize).min(Z_BINS - 1);
    let mut phi = f64::from(direction.y).atan2(f64::from(direction.x));
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let phi_index = ((phi / (2.0 * PI) * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
    z_index * PHI_BINS + phi_index
}

fn direction(z: f64, phi: f64) -> Vec3 {
    let radius = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(
        (radius * phi.cos()) as f32,
        (radius * phi.sin()) as f32,
        z as f32,
    )
}

/// Expected counts per cell: `sample_count` × ∫_cell pdf dω by the composite
/// Simpson rule (4 × 4 intervals per cell, in z and φ).
fn expected_counts(pdf: impl Fn(Vec3) -> f32, sample_count: u64) -> Vec<f64> {
    const INTERVALS: usize = 4;
    let simpson_weight = |index: usize| match index {
        0 | INTERVALS => 1.0,
        index if index % 2 == 1 => 4.0,
        _ => 2.0,
    };
    let dz = 2.0 / Z_BINS as f64;
    let dphi = 2.0 * PI / PHI_BINS as f64;
    let mut expected = vec![0.0; Z_BINS * PHI_BINS];
    for z_index in 0..Z_BINS {
        for phi_index in 0..PHI_BINS {
            let z0 = -1.0 + z_index as f64 * dz;
            let phi0 = phi_index as f64 * dphi;
            let (hz, hphi) = (dz / INTERVALS as f64, dphi / INTERVALS as f64);
            let mut sum = 0.0;
            for i in 0..=INTERVALS {
                for j in 0..=INTERVALS {
                    let w = direction(z0 + i as f64 * hz, phi0 + j as f64 * hphi);
                    sum += simpson_weight(i) * simpson_weight(j) * f64::from(pdf(w));
                }
            }
            expected[z_index * PHI_BINS + phi_index] = sum * hz * hphi / 9.0 * sample_count as f64;
        }
    }
    expected
}

fn uniform_2d(random: &mut SeekablePcg) -> [f32; 2] {
    [random.next_f32(), random.next_f32()]
}

fn wavelengths() -> SampledWavelengths {
    SampledWavelengths::sample_visible(0.3)
}

/// A direction at polar angle with cos θ = `cos_theta` and azimuth `phi`.
fn at(cos_theta: f32, phi: f32) -> Vec3 {
    let sin = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos_theta)
}

/// The chi-square p-value of `sample_count` directions sampled by `bsdf` for
/// `wo` against `bsdf.pdf(wo, ·)`. Asserts that the pdf's integral over the
/// sphere (by the same quadrature) is 1.
fn bsdf_fit_p_value(bsdf: &Bsdf, wo: Vec3, sample_count: u64, seed: u64) -> f64 {
    let mut random = SeekablePcg::new(seed, 7);
    let mut observed = vec![0u64; Z_BINS * PHI_BINS];
    let mut taken = 0;
    for _ in 0..sample_count {
        let mut lambdas = wavelengths();
        let u_component = random.next_f32();
        if let Some(sample) = bsdf.sample(wo, u_component, uniform_2d(&mut random), &mut lambdas) {
            observed[cell_of(sample.wi)] += 1;
            taken += 1;
        }
    }
    assert_eq!(
        taken, sample_count,
        "every sample of a valid wo must succeed"
    );
    let expected = expected_counts(|wi| bsdf.pdf(wo, wi), sample_count);
    let total: f64 = expected.iter().sum::<f64>() / sample_count as f64;
    assert!(
        (total - 1.0).abs() < 1e-4,
        "pdf quadrature integrates to {total}"
    );
    chi_square_test(&observed, &expected).p_value
}

fn grey(value: f32) -> SampledSpectrum {
    SampledSpectrum::splat(value)
}

// ---------------------------------------------------------------------------
// Goodness of fit.

#[test]
fn diffuse_sampling_fits_its_pdf() {
    let two_sided: Bsdf = DiffuseBsdf::new(grey(0.7)).unwrap().into();
    let one_sided: Bsdf = DiffuseBsdf::one_sided(grey(0.7)).unwrap().into();
    let outgoing = [
        at(1.0, 0.0),
        at(0.5, 1.0),
        at(0.05, 4.0),
        at(-0.3, 2.0),
        at(-1.0, 0.0),
    ];
    for (index, &wo) in outgoing.iter().enumerate() {
        let p = bsdf_fit_p_value(&two_sided, wo, 100_000, index as u64);
        eprintln!("diffuse two-sided, wo.z = {:.2}: p = {p:.3}", wo.z);
        assert!(p > P_VALUE_THRESHOLD, "two-sided, wo {wo}: p = {p}");
        if wo.z > 0.0 {
            let p = bsdf_fit_p_value(&one_sided, wo, 100_000, 100 + index as u64);
            eprintln!("diffuse one-sided, wo.z = {:.2}: p = {p:.3}", wo.z);
            assert!(p > P_VALUE_THRESHOLD, "one-sided, wo {wo}: p = {p}");
        }
    }
}

#[test]
fn chi_square_rejects_a_wrong_sampler() {
    // Uniform hemisphere directions tested against the cosine pdf: the test
    // must notice (power check).
    let diffuse: Bsdf = DiffuseBsdf::new(grey(0.5)).unwrap().into();
    let wo = Vec3::Z;
    let sample_count = 100_000;
    let mut random = SeekablePcg::new(5, 5);
    let mut observed = vec![0u64; Z_BINS * PHI_BINS];
    for _ in 0..sample_count {
        let mut wi = sample_uniform_sphere(uniform_2d(&mut random));
        wi.z = wi.z.abs();
        observed[cell_of(wi)] += 1;
    }
    let expected = expected_counts(|wi| diffuse.pdf(wo, wi), sample_count);
    assert!(chi_square_test(&observed, &expected).p_value < 1e-12);
}

#[test]
fn concentric_disk_is_uniform() {
    // Cells of equal area: 8 rings equal in r² times 16 sectors.
    const RINGS: usize = 8;
    const SECTORS: usize = 16;
    let sample_count = 100_000u64;
    let mut random = SeekablePcg::new(11, 0);
    let mut observed = vec![0u64; RINGS * SECTORS];
    for _ in 0..sample_count {
        let point = sample_uniform_disk_concentric(uniform_2d(&mut random));
        let ring = ((point.length_squared() as f64 * RINGS as f64) as usize).min(RINGS - 1);
        let mut phi = f64::from(point.y).atan2(f64::from(point.x));
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let sector = ((phi / (2.0 * PI) * SECTORS as f64) as usize).min(SECTORS - 1);
        observed[ring * SECTORS + sector] += 1;
    }
    let expected = vec![sample_count as f64 / (RINGS * SECTORS) as f64; RINGS * SECTORS];
    let p = chi_square_test(&observed, &expected).p_value;
    eprintln!("concentric disk: p = {p:.3}");
    assert!(p > P_VALUE_THRESHOLD, "p = {p}");
}

#[test]
fn dielectric_chooses_reflection_with_probability_r() {
    let sample_count = 100_000u64;
    for (index, (eta, cos_theta)) in [(1.5_f32, 1.0_f32), (1.5, 0.3), (1.5, -0.9), (1.33, 0.05)]
        .into_iter()
        .enumerate()
    {
        let glass: Bsdf = DielectricBsdf::new(eta).unwrap().into();
        let wo = at(cos_theta, 0.4);
        let reflectance = f64::from(fresnel_dielectric(cos_theta, eta));
        let mut random = SeekablePcg::new(21, index as u64);
        let mut observed = [0u64; 2];
        for _ in 0..sample_count {
            let mut lambdas = wavelengths();
            let sample = glass
                .sample(wo, random.next_f32(), uniform_2d(&mut random), &mut lambdas)
                .unwrap();
            observed[usize::from(sample.is_transmission())] += 1;
        }
        let expected = [
            reflectance * sample_count as f64,
            (1.0 - reflectance) * sample_count as f64,
        ];
        let p = chi_square_test(&observed, &expected).p_value;
        assert!(
            p > P_VALUE_THRESHOLD,
            "η {eta}, cos {cos_theta}: {observed:?} vs {expected:?}"
        );
    }
}

// ---------------------------------------------------------------------------
// Consistency of sample, evaluate and pdf.

#[test]
fn diffuse_sample_agrees_with_evaluate_and_pdf() {
    let lambdas = wavelengths();
    let reflectance = SampledSpectrum::new([0.1, 0.4, 0.8, 1.0]);
    let bsdfs: [Bsdf; 2] = [
        DiffuseBsdf::new(reflectance).unwrap().into(),
        DiffuseBsdf::one_sided(reflectance).unwrap().into(),
    ];
    let mut random = SeekablePcg::new(3, 3);
    for bsdf in &bsdfs {
        for _ in 0..20_000 {
            let wo = sample_uniform_sphere(uniform_2d(&mut random));
            let mut sampled_lambdas = lambdas;
            let Some(sample) = bsdf.sample(
                wo,
                random.next_f32(),
                uniform_2d(&mut random),
                &mut sampled_lambdas,
            ) else {
                assert!(
                    wo.z <= 0.0,
                    "only a one-sided BSDF seen from behind may fail"
                );
                continue;
            };
            assert_eq!(sample.value, bsdf.evaluate(wo, sample.wi, &lambdas));
            let pdf = bsdf.pdf(wo, sample.wi);
            assert!(
                (sample.pdf - pdf).abs() <= 1e-6 * pdf,
                "{} vs {pdf}",
                sample.pdf
            );
            assert!((sample.wi.length() - 1.0).abs() < 1e-5);
            assert!(sample.wi.z * wo.z > 0.0);
            assert_eq!(sample.flags, BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE);
            assert_eq!(sample.eta, 1.0);
            assert!(!sample.pdf_is_proportional);
            assert_eq!(sampled_lambdas, lambdas);
        }
    }
}

/// Mean and standard error of `pdf(wo, wi) / p_uniform(wi)` over uniform
/// sphere directions: an unbiased estimate of ∫ pdf dω.
fn pdf_integral_estimate(bsdf: &Bsdf, wo: Vec3, sample_count: usize, seed: u64) -> (f64, f64) {
    let mut random = SeekablePcg::new(seed, 1);
    let (mut sum, mut sum_squares) = (0.0, 0.0);
    for _ in 0..sample_count {
        let wi = sample_uniform_sphere(uniform_2d(&mut random));
        let value = f64::from(bsdf.pdf(wo, wi)) / f64::from(UNIFORM_SPHERE_PDF);
        sum += value;
        sum_squares += value * value;
    }
    let n = sample_count as f64;
    let mean = sum / n;
    let variance = (sum_squares / n - mean * mean) * n / (n - 1.0);
    (mean, (variance / n).sqrt())
}

#[test]
fn diffuse_pdf_integrates_to_one() {
    let two_sided: Bsdf = DiffuseBsdf::new(grey(0.5)).unwrap().into();
    let one_sided: Bsdf = DiffuseBsdf::one_sided(grey(0.5)).unwrap().into();
    for (index, wo) in [at(1.0, 0.0), at(0.2, 1.0), at(-0.7, 2.0)]
        .into_iter()
        .enumerate()
    {
        let (mean, standard_error) = pdf_integral_estimate(&two_sided, wo, 200_000, index as u64);
        eprintln!(
            "∫ pdf dω, wo.z = {:.2}: {mean:.5} ± {standard_error:.5}",
            wo.z
        );
        assert!(
            (mean - 1.0).abs() < 5.0 * standard_error,
            "wo {wo}: {mean} ± {standard_error}"
        );
        let (mean, standard_error) = pdf_integral_estimate(&one_sided, wo, 200_000, index as u64);
        let expected = if wo.z > 0.0 { 1.0 } else { 0.0 };
        assert!(
            (mean - expected).abs() <= 5.0 * standard_error,
            "one-sided {wo}: {mean}"
        );
    }
}

#[test]
fn specular_bsdfs_have_no_density_or_value() {
    let lambdas = wavelengths();
    let bsdfs: [Bsdf; 3] = [
        ConductorBsdf::perfect_mirror().into(),
        ConductorBsdf::new(grey(0.2), grey(3.0)).unwrap().into(),
        DielectricBsdf::new(1.5).unwrap().into(),
    ];
    let wo = at(0.6, 0.3);
    for bsdf in &bsdfs {
        assert!(bsdf.flags().is_specular());
        assert!(!bsdf.flags().is_non_specular());
        let mut sampled = lambdas;
        let sample = bsdf.sample(wo, 0.0, [0.5, 0.5], &mut sampled).unwrap();
        assert!(sample.is_specular());
        assert_eq!(bsdf.pdf(wo, sample.wi), 0.0);
        assert!(bsdf.evaluate(wo, sample.wi, &lambdas).is_black());
    }
}

// ---------------------------------------------------------------------------
// White furnace: E[f |cos θi| / pdf] is the directional albedo.

#[test]
fn diffuse_furnace_returns_the_reflectance_exactly() {
    let reflectance = SampledSpectrum::new([0.0, 0.25, 0.5, 1.0]);
    let diffuse: Bsdf = DiffuseBsdf::new(reflectance).unwrap().into();
    let mut random = SeekablePcg::new(8, 8);
    for _ in 0..10_000 {
        let wo = sample_uniform_sphere(uniform_2d(&mut random));
        let mut lambdas = wavelengths();
        let Some(sample) =
            diffuse.sample(wo, random.next_f32(), uniform_2d(&mut random), &mut lambdas)
        else {
            continue; // wi in the tangent plane (probability ~0)
        };
        let weight = sample.weight();
        for index in 0..4 {
            assert!(
                (weight[index] - reflectance[index]).abs() <= 1e-6 * reflectance[index].max(1e-6),
                "zero-variance estimator: {weight:?}"
            );
        }
    }
}

#[test]
fn conductor_furnace_returns_the_fresnel_reflectance() {
    let mirror: Bsdf = ConductorBsdf::perfect_mirror().into();
    let eta = SampledSpectrum::new([0.2, 0.27, 1.1, 2.0]);
    let k = SampledSpectrum::new([3.0, 2.78, 2.6, 0.5]);
    let metal: Bsdf = ConductorBsdf::new(eta, k).unwrap().into();
    for cos_theta in [1.0_f32, 0.7, 0.2, 0.01, -0.5] {
        let wo = at(cos_theta, 1.2);
        let mut lambdas = wavelengths();
        let sample = mirror.sample(wo, 0.3, [0.1, 0.9], &mut lambdas).unwrap();
        assert!((sample.wi - Vec3::new(-wo.x, -wo.y, wo.z)).length() < 1e-7);
        assert!(sample.is_reflection() && sample.is_specular());
        for value in sample.weight().values() {
            assert!((value - 1.0).abs() < 1e-6, "mirror albedo {value}");
        }
        let sample = metal.sample(wo, 0.3, [0.1, 0.9], &mut lambdas).unwrap();
        for index in 0..4 {
            let expected = fresnel_complex(cos_theta.abs(), eta[index], k[index]);
            assert!((sample.weight()[index] - expected).abs() < 1e-5);
        }
    }
}

#[test]
fn dielectric_furnace_importance_is_one_and_radiance_scales_by_eta_squared() {
    let eta = 1.5_f32;
    let sample_count = 50_000;
    // cos −0.5 from inside is beyond the critical angle (total internal
    // reflection: every weight is 1, zero variance).
    for (index, cos_theta) in [0.9_f32, 0.4, -0.5, -0.8, -0.95].into_iter().enumerate() {
        let wo = at(cos_theta, 2.5);
        let importance: Bsdf = DielectricBsdf::new(eta).unwrap().into();
        let importance = importance.with_transport_mode(TransportMode::Importance);
        let radiance = importance.with_transport_mode(TransportMode::Radiance);
        let reflectance = f64::from(fresnel_dielectric(cos_theta, eta));
        // η along the path: entering the glass from above, leaving from below.
        let path_eta = if cos_theta > 0.0 { eta } else { 1.0 / eta };
        let mut random = SeekablePcg::new(31, index as u64);
        let (mut sum, mut sum_squares) = (0.0, 0.0);
        for _ in 0..sample_count {
            let u_component = random.next_f32();
            let u = uniform_2d(&mut random);
            let mut lambdas = wavelengths();
            let importance_sample = importance.sample(wo, u_component, u, &mut lambdas).unwrap();
            let radiance_sample = radiance.sample(wo, u_component, u, &mut lambdas).unwrap();
            assert_eq!(importance_sample.wi, radiance_sample.wi);
            let importance_weight = importance_sample.weight()[0];
            assert!(
                (importance_weight - 1.0).abs() < 1e-5,
                "{importance_weight}"
            );
            let radiance_weight = radiance_sample.weight()[0];
            if radiance_sample.is_transmission() {
                assert!((radiance_sample.eta - path_eta).abs() < 1e-6);
                let expected = 1.0 / (path_eta * path_eta);
                assert!((radiance_weight - expected).abs() < 1e-5 * expected);
                // Snell: η_i sin θi = η_t sin θt, and the sides differ.
                let sin_o = (1.0 - wo.z * wo.z).sqrt();
                let wi = radiance_sample.wi;
                let sin_i = (1.0 - wi.z * wi.z).max(0.0).sqrt();
                assert!((sin_o - path_eta * sin_i).abs() < 1e-5);
                assert!(wi.z * wo.z < 0.0);
            } else {
                assert!((radiance_weight - 1.0).abs() < 1e-5);
                assert_eq!(radiance_sample.eta, 1.0);
            }
            sum += f64::from(radiance_weight);
            sum_squares += f64::from(radiance_weight).powi(2);
        }
        // E[radiance weight] = R + T/η², checked within 5 standard errors
        // (plus 1e-6 for the f32 rounding of the weights, which matters when
        // the variance is 0).
        let n = sample_count as f64;
        let mean = sum / n;
        let standard_error = ((sum_squares / n - mean * mean) / (n - 1.0)).sqrt();
        let expected = reflectance + (1.0 - reflectance) / f64::from(path_eta * path_eta);
        eprintln!(
            "dielectric radiance furnace, cos {cos_theta}: {mean:.5} ± {standard_error:.5} (expected {expected:.5})"
        );
        assert!(
            (mean - expected).abs() <= 5.0 * standard_error + 1e-6,
            "cos {cos_theta}: {mean} vs {expected} ± {standard_error}"
        );
    }
}

#[test]
fn glass_reflects_four_percent_at_normal_incidence() {
    assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-7);
    let glass: Bsdf = DielectricBsdf::new(1.5).unwrap().into();
    let mut lambdas = wavelengths();
    // u_component below R = 0.04 reflects, above refracts straight through.
    let reflected = glass
        .sample(Vec3::Z, 0.039, [0.0, 0.0], &mut lambdas)
        .unwrap();
    assert!(reflected.is_reflection());
    assert!((reflected.pdf - 0.04).abs() < 1e-6);
    assert!((reflected.value[0] - 0.04).abs() < 1e-6);
    let refracted = glass
        .sample(Vec3::Z, 0.041, [0.0, 0.0], &mut lambdas)
        .unwrap();
    assert!(refracted.is_transmission());
    assert!((refracted.wi + Vec3::Z).length() < 1e-6);
    assert!((refracted.pdf - 0.96).abs() < 1e-6);
    assert!(
        (refracted.value[0] - 0.96 / 2.25).abs() < 1e-6,
        "radiance: T/η²"
    );
}

#[test]
fn total_internal_reflection_beyond_the_critical_angle() {
    let eta = 1.5_f32;
    let glass: Bsdf = DielectricBsdf::new(eta).unwrap().into();
    let critical_cos = (1.0 - 1.0 / (eta * eta)).sqrt();
    // Inside the glass (wo below), more grazing than the critical angle.
    for cos_theta in [critical_cos - 0.01, 0.5, 0.1] {
        let wo = at(-cos_theta, 0.7);
        assert_eq!(fresnel_dielectric(wo.z, eta), 1.0);
        for u_component in [0.0, 0.5, 0.999_999] {
            let mut lambdas = wavelengths();
            let sample = glass
                .sample(wo, u_component, [0.3, 0.3], &mut lambdas)
                .unwrap();
            assert!(sample.is_reflection(), "TIR at cos {cos_theta}");
            assert!((sample.weight()[0] - 1.0).abs() < 1e-6);
            assert!(sample.wi.z < 0.0);
        }
    }
    // Just inside the critical angle some light escapes.
    let wo = at(-(critical_cos + 0.01), 0.7);
    let mut lambdas = wavelengths();
    assert!(
        glass
            .sample(wo, 0.999, [0.3, 0.3], &mut lambdas)
            .unwrap()
            .is_transmission()
    );
}

#[test]
fn index_matched_interface_passes_light_straight_through() {
    let matched: Bsdf = DielectricBsdf::new(1.0).unwrap().into();
    assert_eq!(
        matched.flags(),
        BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR
    );
    for wo in [at(0.8, 0.2), at(-0.3, 2.0), at(0.01, 5.0)] {
        for u_component in [0.0, 0.5, 0.99] {
            let mut lambdas = wavelengths();
            let sample = matched
                .sample(wo, u_component, [0.2, 0.7], &mut lambdas)
                .unwrap();
            assert!(sample.is_transmission() && sample.is_specular());
            assert!((sample.wi + wo).length() < 1e-6);
            assert_eq!(sample.eta, 1.0);
            assert_eq!(sample.pdf, 1.0);
            assert!((sample.value[0] - 1.0 / wo.z.abs()).abs() < 1e-5 / wo.z.abs());
        }
    }
}

// ---------------------------------------------------------------------------
// Fresnel against reference values.

/// (cos θi, η, κ, reflectance) from `scripts/conductor_fresnel_reference.py`
/// (output committed as `scripts/conductor_fresnel_reference.txt`).
const CONDUCTOR_REFERENCE: [(f32, f32, f32, f64); 25] = [
    (1.00, 0.20, 3.00, 0.923371648),
    (0.80, 0.20, 3.00, 0.922402892),
    (0.50, 0.20, 3.00, 0.918411085),
    (0.20, 0.20, 3.00, 0.933369614),
    (0.05, 0.20, 3.00, 0.978070628),
    (1.00, 0.27, 2.78, 0.884384400),
    (0.80, 0.27, 2.78, 0.883245686),
    (0.50, 0.27, 2.78, 0.879891037),
    (0.20, 0.27, 2.78, 0.907257493),
    (0.05, 0.27, 2.78, 0.970040531),
    (1.00, 1.10, 2.60, 0.606087735),
    (0.80, 1.10, 2.60, 0.605258223),
    (0.50, 1.10, 2.60, 0.607654280),
    (0.20, 1.10, 2.60, 0.691541326),
    (0.05, 1.10, 2.60, 0.886364276),
    (1.00, 2.00, 0.50, 0.135135135),
    (0.80, 2.00, 0.50, 0.139938251),
    (0.50, 2.00, 0.50, 0.186053360),
    (0.20, 2.00, 0.50, 0.403910725),
    (0.05, 2.00, 0.50, 0.768072107),
    (1.00, 1.50, 0.00, 0.040000000),
    (0.80, 1.50, 0.00, 0.043894736),
    (0.50, 1.50, 0.00, 0.089186713),
    (0.20, 1.50, 0.00, 0.338894391),
    (0.05, 1.50, 0.00, 0.752130478),
];

#[test]
fn conductor_fresnel_matches_the_independent_formula() {
    for (cos_theta, eta, k, expected) in CONDUCTOR_REFERENCE {
        let value = f64::from(fresnel_complex(cos_theta, eta, k));
        assert!(
            (value - expected).abs() < 2e-6,
            "cos {cos_theta}, η {eta}, κ {k}: {value} vs {expected}"
        );
        if k == 0.0 {
            assert!((f64::from(fresnel_dielectric(cos_theta, eta)) - expected).abs() < 2e-6);
        }
    }
}

// ---------------------------------------------------------------------------
// Reciprocity and reverse densities.

#[test]
fn diffuse_is_reciprocal_and_reverse_pdf_is_the_swapped_call() {
    let lambdas = wavelengths();
    let reflectance = SampledSpectrum::new([0.9, 0.5, 0.3, 0.1]);
    let bsdfs: [Bsdf; 2] = [
        DiffuseBsdf::new(reflectance).unwrap().into(),
        DiffuseBsdf::one_sided(reflectance).unwrap().into(),
    ];
    let mut random = SeekablePcg::new(13, 13);
    for bsdf in &bsdfs {
        for _ in 0..5_000 {
            let wo = sample_uniform_sphere(uniform_2d(&mut random));
            let wi = sample_uniform_sphere(uniform_2d(&mut random));
            assert_eq!(
                bsdf.evaluate(wo, wi, &lambdas),
                bsdf.evaluate(wi, wo, &lambdas)
            );
            // The reverse density is that of sampling wo from wi: |cos θo|/π.
            let reverse = bsdf.pdf(wi, wo);
            if bsdf.evaluate(wo, wi, &lambdas).is_black() {
                assert_eq!(reverse, 0.0);
            } else {
                let expected = wo.z.abs() / std::f32::consts::PI;
                assert!((reverse - expected).abs() < 1e-6);
            }
        }
    }
}

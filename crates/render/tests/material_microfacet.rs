//! Statistical and analytic tests of the rough and layered BSDFs:
//! rough conductor and dielectric (GGX and Beckmann, isotropic and
//! anisotropic), plastic, rough plastic, thin dielectric, two-sided wrappers,
//! Mitsuba's principled and thin principled BSDFs.
//!
//! - chi-square goodness of fit of `sample` against `pdf` (the shared
//!   `render::statistics::chi_square_test`), delta lobes left out (their
//!   samples are not binned; the binned expectation is the pdf's, which
//!   excludes them too);
//! - `∫ pdf dω` over the sphere equals the fraction of samples that succeed
//!   (uniform-sphere Monte Carlo, 5 standard errors);
//! - sampled value and pdf equal `evaluate` and `pdf`;
//! - reciprocity (reflection; the importance-mode BSDF is the adjoint of the
//!   radiance one for transmission);
//! - white furnace: albedo ≤ 1; a perfect-mirror rough conductor (η → ∞)
//!   loses the energy that single-scattering microfacets lose, which equals
//!   1 − E[G1(wi)] over visible normals and grows with α;
//! - smooth limits: α → 0 gives the smooth BSDF's expected weight.
//!
//! Random numbers come from the tests' SplitMix64 with fixed seeds.

mod common;

use std::f64::consts::PI;

use common::TestRng;
use glam::Vec3;
use render::material::{
    Bsdf, BsdfModel, ConductorReflectance, DielectricBsdf, DiffuseBsdf, MicrofacetDistribution,
    MicrofacetKind, PlasticBsdf, PrincipledBsdf, PrincipledParameters, PrincipledThinBsdf,
    PrincipledThinParameters, RoughConductorBsdf, RoughDielectricBsdf, RoughPlasticBsdf,
    RoughPlasticTables, ThinDielectricBsdf, TransportMode, UNIFORM_SPHERE_PDF, fresnel_complex,
    fresnel_dielectric, sample_uniform_sphere,
};
use render::spectrum::{SampledSpectrum, SampledWavelengths};
use render::statistics::chi_square_test;

const P_VALUE_THRESHOLD: f64 = 1e-4;
const Z_BINS: usize = 32;
const PHI_BINS: usize = 64;

fn wavelengths() -> SampledWavelengths {
    SampledWavelengths::sample_visible(0.37)
}

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

/// `sample_count` × ∫_cell pdf dω by a 10 × 10 midpoint rule per cell
/// (dω = dz dφ).
fn expected_counts(pdf: impl Fn(Vec3) -> f32, sample_count: u64) -> Vec<f64> {
    const SUB: usize = 10;
    let dz = 2.0 / Z_BINS as f64;
    let dphi = 2.0 * PI / PHI_BINS as f64;
    let mut expected = vec![0.0; Z_BINS * PHI_BINS];
    for z_index in 0..Z_BINS {
        for phi_index in 0..PHI_BINS {
            let mut sum = 0.0;
            for i in 0..SUB {
                for j in 0..SUB {
                    let z = -1.0 + (z_index as f64 + (i as f64 + 0.5) / SUB as f64) * dz;
                    let phi = (phi_index as f64 + (j as f64 + 0.5) / SUB as f64) * dphi;
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    let w = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                    sum += f64::from(pdf(w));
                }
            }
            expected[z_index * PHI_BINS + phi_index] =
                sum / (SUB * SUB) as f64 * dz * dphi * sample_count as f64;
        }
    }
    expected
}

/// Chi-square test of the non-delta samples of `bsdf` for `wo`.
fn assert_sampling_matches_pdf(label: &str, bsdf: &Bsdf, wo: Vec3, seed: u64) {
    let sample_count = 100_000u64;
    let mut rng = TestRng(seed);
    let mut observed = vec![0u64; Z_BINS * PHI_BINS];
    let mut lambdas = wavelengths();
    for _ in 0..sample_count {
        let u_component = rng.uniform();
        let u = rng.uniform2();
        if let Some(sample) = bsdf.sample(wo, u_component, [u.x, u.y], &mut lambdas)
            && !sample.is_specular()
        {
            observed[cell_of(sample.wi)] += 1;
        }
    }
    let expected = expected_counts(|wi| bsdf.pdf(wo, wi), sample_count);
    let result = chi_square_test(&observed, &expected);
    assert!(
        result.p_value > P_VALUE_THRESHOLD,
        "{label} wo {wo}: chi² {} with {} dof, p = {}",
        result.statistic,
        result.degrees_of_freedom,
        result.p_value
    );
}

fn direction(theta_degrees: f32, phi_degrees: f32) -> Vec3 {
    let (theta, phi) = (theta_degrees.to_radians(), phi_degrees.to_radians());
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

fn distributions() -> Vec<MicrofacetDistribution> {
    let mut list = Vec::new();
    for kind in [MicrofacetKind::Ggx, MicrofacetKind::Beckmann] {
        list.push(MicrofacetDistribution::new(kind, 0.15, 0.15));
        list.push(MicrofacetDistribution::new(kind, 0.6, 0.6));
        list.push(MicrofacetDistribution::new(kind, 0.1, 0.4));
    }
    list
}

fn gold_like() -> ConductorReflectance {
    ConductorReflectance::Fresnel {
        eta: SampledSpectrum::splat(0.2),
        k: SampledSpectrum::splat(3.0),
    }
}

fn rough_conductor(distribution: MicrofacetDistribution, two_sided: bool) -> Bsdf {
    RoughConductorBsdf::new(
        distribution,
        gold_like(),
        SampledSpectrum::splat(1.0),
        two_sided,
    )
    .into()
}

fn rough_dielectric(distribution: MicrofacetDistribution, eta: f32, mode: TransportMode) -> Bsdf {
    Bsdf::from(RoughDielectricBsdf::new(distribution, eta, false)).with_transport_mode(mode)
}

fn rough_plastic(distribution: MicrofacetDistribution, diffuse: f32, two_sided: bool) -> Bsdf {
    RoughPlasticBsdf::new(
        distribution,
        RoughPlasticTables::shared(&distribution, 1.5),
        SampledSpectrum::splat(diffuse),
        1.5,
        true,
        two_sided,
    )
    .into()
}

#[test]
fn rough_conductor_sampling_matches_its_pdf() {
    for (index, distribution) in distributions().into_iter().enumerate() {
        for wo in [direction(20.0, 30.0), direction(70.0, 200.0)] {
            let bsdf = rough_conductor(distribution, false);
            assert_sampling_matches_pdf(&format!("{distribution:?}"), &bsdf, wo, index as u64);
        }
    }
    // Two-sided, seen from behind.
    let bsdf = rough_conductor(
        MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, 0.2),
        true,
    );
    assert_sampling_matches_pdf("two-sided conductor", &bsdf, -direction(40.0, 10.0), 99);
}

#[test]
fn rough_dielectric_sampling_matches_its_pdf() {
    for (index, distribution) in distributions().into_iter().enumerate() {
        for (wo, eta) in [
            (direction(25.0, 30.0), 1.5),
            (-direction(30.0, 120.0), 1.5),
            (direction(75.0, 300.0), 1.33),
            (-direction(60.0, 10.0), 1.33),
        ] {
            for mode in [TransportMode::Radiance, TransportMode::Importance] {
                let bsdf = rough_dielectric(distribution, eta, mode);
                let label = format!("{distribution:?} eta {eta} {mode:?}");
                assert_sampling_matches_pdf(&label, &bsdf, wo, 10 + index as u64);
            }
        }
    }
}

#[test]
fn plastics_sampling_matches_their_pdf() {
    let smooth: Bsdf = PlasticBsdf::new(SampledSpectrum::splat(0.6), 1.5, false, true).into();
    assert_sampling_matches_pdf("plastic", &smooth, direction(50.0, 0.0), 3);
    assert_sampling_matches_pdf("plastic back", &smooth, -direction(30.0, 0.0), 4);
    for (seed, distribution) in [
        MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.2, 0.2),
        MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.4, 0.4),
    ]
    .into_iter()
    .enumerate()
    {
        let bsdf = rough_plastic(distribution, 0.5, false);
        for wo in [direction(10.0, 0.0), direction(65.0, 90.0)] {
            assert_sampling_matches_pdf("rough plastic", &bsdf, wo, 20 + seed as u64);
        }
    }
    // A two-sided wrapper with a rough conductor front and a rough plastic back.
    let front = *rough_conductor(
        MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, 0.3),
        false,
    )
    .model();
    let back = *rough_plastic(
        MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, 0.3),
        0.4,
        false,
    )
    .model();
    let two_sided = Bsdf::two_sided(front, back);
    assert_sampling_matches_pdf("two-sided front", &two_sided, direction(35.0, 45.0), 30);
    assert_sampling_matches_pdf("two-sided back", &two_sided, -direction(35.0, 45.0), 31);
}

/// ∫ pdf dω by uniform-sphere Monte Carlo against the fraction of samples
/// that succeed; both with their standard errors.
fn assert_pdf_integrates_to_success_rate(label: &str, bsdf: &Bsdf, wo: Vec3, seed: u64) {
    let count = 200_000;
    let mut rng = TestRng(seed);
    let (mut sum, mut sum2) = (0.0_f64, 0.0_f64);
    for _ in 0..count {
        let u = rng.uniform2();
        let wi = sample_uniform_sphere([u.x, u.y]);
        let value = f64::from(bsdf.pdf(wo, wi) / UNIFORM_SPHERE_PDF);
        sum += value;
        sum2 += value * value;
    }
    let mean = sum / count as f64;
    let error = ((sum2 / count as f64 - mean * mean).max(0.0) / count as f64).sqrt();
    let mut lambdas = wavelengths();
    let mut successes = 0u64;
    for _ in 0..count {
        let u_component = rng.uniform();
        let u = rng.uniform2();
        if let Some(sample) = bsdf.sample(wo, u_component, [u.x, u.y], &mut lambdas)
            && !sample.is_specular()
        {
            successes += 1;
        }
    }
    let rate = successes as f64 / count as f64;
    let rate_error = (rate * (1.0 - rate) / count as f64).sqrt();
    let tolerance = 5.0 * (error * error + rate_error * rate_error).sqrt() + 1e-3;
    assert!(
        (mean - rate).abs() < tolerance && mean <= 1.0 + tolerance,
        "{label} wo {wo}: ∫pdf = {mean} ± {error}, success rate {rate}"
    );
}

#[test]
fn densities_integrate_to_the_success_rate() {
    for (index, distribution) in distributions().into_iter().enumerate() {
        // Peaked lobes are poorly resolved by uniform sampling; keep α ≥ 0.15.
        let seed = 100 + index as u64;
        assert_pdf_integrates_to_success_rate(
            "conductor",
            &rough_conductor(distribution, false),
            direction(45.0, 10.0),
            seed,
        );
        assert_pdf_integrates_to_success_rate(
            "dielectric",
            &rough_dielectric(distribution, 1.5, TransportMode::Radiance),
            -direction(35.0, 70.0),
            seed,
        );
    }
    assert_pdf_integrates_to_success_rate(
        "rough plastic",
        &rough_plastic(
            MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, 0.3),
            0.5,
            false,
        ),
        direction(60.0, 0.0),
        7,
    );
}

#[test]
fn samples_carry_evaluate_and_pdf() {
    let mut rng = TestRng(5);
    let mut lambdas = wavelengths();
    let mut bsdfs: Vec<Bsdf> = Vec::new();
    for distribution in distributions() {
        bsdfs.push(rough_conductor(distribution, true));
        bsdfs.push(rough_dielectric(distribution, 1.5, TransportMode::Radiance));
        bsdfs.push(rough_dielectric(
            distribution,
            1.5,
            TransportMode::Importance,
        ));
        bsdfs.push(rough_plastic(
            MicrofacetDistribution::new(
                distribution.kind(),
                distribution.alpha_x(),
                distribution.alpha_x(),
            ),
            0.5,
            true,
        ));
    }
    for bsdf in &bsdfs {
        for _ in 0..2000 {
            let u = rng.uniform2();
            let wo = sample_uniform_sphere([u.x, u.y]);
            let u = rng.uniform2();
            if let Some(sample) = bsdf.sample(wo, rng.uniform(), [u.x, u.y], &mut lambdas) {
                let value = bsdf.evaluate(wo, sample.wi, &lambdas);
                let pdf = bsdf.pdf(wo, sample.wi);
                assert!((sample.pdf - pdf).abs() <= 1e-4 * pdf, "{bsdf:?}");
                assert!(
                    (sample.value - value).max_component().abs() <= 1e-4 * value.max_component(),
                    "{bsdf:?}"
                );
                assert!(sample.pdf > 0.0 && sample.value.max_component().is_finite());
            }
        }
    }
}

#[test]
fn reciprocity() {
    let mut rng = TestRng(11);
    let lambdas = wavelengths();
    for distribution in distributions() {
        let conductor = rough_conductor(distribution, true);
        let radiance = rough_dielectric(distribution, 1.5, TransportMode::Radiance);
        let importance = rough_dielectric(distribution, 1.5, TransportMode::Importance);
        let plastic = rough_plastic(
            MicrofacetDistribution::new(
                distribution.kind(),
                distribution.alpha_x(),
                distribution.alpha_x(),
            ),
            0.7,
            true,
        );
        for _ in 0..2000 {
            let (u, v) = (rng.uniform2(), rng.uniform2());
            let (a, b) = (
                sample_uniform_sphere([u.x, u.y]),
                sample_uniform_sphere([v.x, v.y]),
            );
            let close = |x: f32, y: f32| (x - y).abs() <= 1e-3 * x.abs().max(y.abs()) + 1e-6;
            for bsdf in [&conductor, &plastic] {
                assert!(close(
                    bsdf.evaluate(a, b, &lambdas)[0],
                    bsdf.evaluate(b, a, &lambdas)[0]
                ));
            }
            // Reflection is symmetric; for transmission the importance BSDF
            // is the radiance BSDF's adjoint, f*(a, b) = f(b, a).
            let (forward, adjoint) = (
                importance.evaluate(a, b, &lambdas)[0],
                radiance.evaluate(b, a, &lambdas)[0],
            );
            // 1 − F loses digits in f32 where a direction grazes the
            // microfacet (F → 1), hence 1 % here.
            assert!(
                (forward - adjoint).abs() <= 1e-2 * forward.abs().max(adjoint.abs()) + 1e-4,
                "{distribution:?} {a} {b}: {forward} vs {adjoint}"
            );
            if a.z * b.z > 0.0 {
                assert!(close(
                    radiance.evaluate(a, b, &lambdas)[0],
                    radiance.evaluate(b, a, &lambdas)[0]
                ));
            }
        }
    }
}

/// The mean of f |cos θi| / pdf over `count` samples, its standard error,
/// and the same split by reflection / transmission.
fn albedo(bsdf: &Bsdf, wo: Vec3, count: u64, seed: u64) -> (f64, f64) {
    let mut rng = TestRng(seed);
    let mut lambdas = wavelengths();
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..count {
        let u = rng.uniform2();
        let weight = bsdf
            .sample(wo, rng.uniform(), [u.x, u.y], &mut lambdas)
            .map(|sample| f64::from(sample.weight()[0]))
            .unwrap_or(0.0);
        sum += weight;
        sum2 += weight * weight;
    }
    let mean = sum / count as f64;
    (
        mean,
        ((sum2 / count as f64 - mean * mean).max(0.0) / count as f64).sqrt(),
    )
}

/// Single-scattering energy of a perfect-mirror microfacet surface,
/// E[G1(wi, m)] over the visible normals m, by a midpoint rule over the
/// sampling square (an independent evaluation of the same integral).
fn mirror_energy(distribution: &MicrofacetDistribution, wo: Vec3) -> f64 {
    let steps = 400;
    let mut sum = 0.0;
    for i in 0..steps {
        for j in 0..steps {
            let u = [
                (i as f32 + 0.5) / steps as f32,
                (j as f32 + 0.5) / steps as f32,
            ];
            let m = distribution.sample_visible_normal(wo, u);
            let wi = 2.0 * wo.dot(m) * m - wo;
            if wi.z > 0.0 {
                sum += f64::from(distribution.g1(wi, m));
            }
        }
    }
    sum / (steps * steps) as f64
}

#[test]
fn white_furnace() {
    let count = 100_000;
    for kind in [MicrofacetKind::Ggx, MicrofacetKind::Beckmann] {
        let mut previous = 1.0;
        for alpha in [0.05, 0.3, 0.6, 1.0] {
            let distribution = MicrofacetDistribution::new(kind, alpha, alpha);
            let mirror: Bsdf = RoughConductorBsdf::new(
                distribution,
                ConductorReflectance::Perfect,
                SampledSpectrum::splat(1.0),
                false,
            )
            .into();
            let wo = direction(50.0, 0.0);
            let (mean, error) = albedo(&mirror, wo, count, 1);
            let expected = mirror_energy(&distribution, wo);
            assert!(mean <= 1.0 + 5.0 * error + 1e-4, "{kind:?} {alpha}: {mean}");
            assert!(
                (mean - expected).abs() < 5.0 * error + 2e-3,
                "{kind:?} {alpha}: {mean} vs {expected}"
            );
            assert!(expected <= previous + 1e-3, "energy loss grows with α");
            previous = expected;
            if alpha == 0.05 {
                assert!(expected > 0.99, "{kind:?}: {expected}");
            }
            if alpha == 1.0 {
                // Single scattering loses a large part of the energy at α = 1
                // (Heitz et al. 2016, Kulla and Conty 2017: up to ~60 % with
                // the separable Smith G); neither negligible nor everything.
                assert!(expected < 0.95 && expected > 0.3, "{kind:?}: {expected}");
            }
            // Importance-mode dielectric: reflection + transmission ≤ 1.
            let dielectric = rough_dielectric(distribution, 1.5, TransportMode::Importance);
            for wo in [
                direction(30.0, 0.0),
                -direction(30.0, 0.0),
                direction(80.0, 0.0),
            ] {
                let (mean, error) = albedo(&dielectric, wo, count, 2);
                assert!(
                    mean <= 1.0 + 5.0 * error + 1e-4 && mean > 0.3,
                    "{kind:?} {alpha} {wo}: {mean}"
                );
            }
            let plastic = rough_plastic(distribution, 1.0, false);
            let (mean, error) = albedo(&plastic, direction(30.0, 0.0), count, 3);
            // Mitsuba's rough plastic loses energy to single scattering in
            // the coating (twice), so a white base reflects well below 1.
            assert!(
                mean <= 1.0 + 5.0 * error + 1e-4 && mean > 0.3,
                "plastic {kind:?} {alpha}: {mean}"
            );
        }
    }
    let plastic: Bsdf = PlasticBsdf::new(SampledSpectrum::splat(1.0), 1.5, false, false).into();
    let (mean, error) = albedo(&plastic, direction(30.0, 0.0), count, 4);
    assert!(
        mean <= 1.0 + 5.0 * error + 1e-4 && mean > 0.8,
        "plastic: {mean}"
    );
    let thin: Bsdf = ThinDielectricBsdf::new(1.5).into();
    let (mean, error) = albedo(&thin, direction(60.0, 0.0), count, 5);
    assert!(
        (mean - 1.0).abs() < 5.0 * error + 1e-6,
        "thin dielectric: {mean}"
    );
}

#[test]
fn smooth_limits() {
    let count = 50_000;
    let wo = direction(40.0, 20.0);
    for kind in [MicrofacetKind::Ggx, MicrofacetKind::Beckmann] {
        let distribution = MicrofacetDistribution::new(kind, 2e-3, 2e-3);
        // Conductor: the expected weight is the Fresnel reflectance.
        let (mean, error) = albedo(&rough_conductor(distribution, false), wo, count, 1);
        let fresnel = f64::from(fresnel_complex(wo.z, 0.2, 3.0));
        assert!(
            (mean - fresnel).abs() < 5.0 * error + 2e-3,
            "{kind:?}: {mean} vs {fresnel}"
        );
        // Dielectric: reflection probability F and weights as the smooth one.
        let rough = rough_dielectric(distribution, 1.5, TransportMode::Radiance);
        let smooth = Bsdf::from(DielectricBsdf::new(1.5).unwrap());
        for wo in [wo, -wo] {
            let (rough_mean, rough_error) = albedo(&rough, wo, count, 2);
            let (smooth_mean, smooth_error) = albedo(&smooth, wo, count, 2);
            assert!(
                (rough_mean - smooth_mean).abs() < 5.0 * (rough_error + smooth_error) + 3e-3,
                "{kind:?} {wo}: rough {rough_mean} smooth {smooth_mean}"
            );
        }
        let mut rng = TestRng(9);
        let mut lambdas = wavelengths();
        let mut reflections = 0;
        for _ in 0..count {
            let u = rng.uniform2();
            if let Some(sample) = rough.sample(wo, rng.uniform(), [u.x, u.y], &mut lambdas) {
                reflections += usize::from(sample.is_reflection());
            }
        }
        let fraction = reflections as f64 / count as f64;
        let fresnel = f64::from(fresnel_dielectric(wo.z, 1.5));
        let error = (fresnel * (1.0 - fresnel) / count as f64).sqrt();
        assert!(
            (fraction - fresnel).abs() < 5.0 * error + 2e-3,
            "{fraction} vs {fresnel}"
        );
        // Rough plastic against smooth plastic.
        let rough = rough_plastic(MicrofacetDistribution::new(kind, 0.002, 0.002), 0.5, false);
        let smooth: Bsdf = PlasticBsdf::new(SampledSpectrum::splat(0.5), 1.5, true, false).into();
        let (rough_mean, rough_error) = albedo(&rough, wo, count, 3);
        let (smooth_mean, smooth_error) = albedo(&smooth, wo, count, 3);
        assert!(
            (rough_mean - smooth_mean).abs() < 5.0 * (rough_error + smooth_error) + 1e-2,
            "plastic {kind:?}: rough {rough_mean} smooth {smooth_mean}"
        );
    }
}

#[test]
fn one_sided_models_are_black_from_behind() {
    let lambdas = wavelengths();
    let (above, below) = (direction(30.0, 0.0), -direction(40.0, 180.0));
    let distribution = MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, 0.3);
    let mut lambdas_mut = wavelengths();
    for bsdf in [
        rough_conductor(distribution, false),
        rough_plastic(distribution, 0.5, false),
        PlasticBsdf::new(SampledSpectrum::splat(0.5), 1.5, false, false).into(),
    ] {
        assert!(bsdf.evaluate(below, -above, &lambdas).is_black());
        assert_eq!(bsdf.pdf(below, -above), 0.0);
        assert!(
            bsdf.sample(below, 0.5, [0.3, 0.6], &mut lambdas_mut)
                .is_none()
        );
        assert!(
            !bsdf
                .evaluate(above, direction(20.0, 170.0), &lambdas)
                .is_black()
        );
    }
    let two_sided = rough_conductor(distribution, true);
    assert!(!two_sided.evaluate(below, -above, &lambdas).is_black());
    // Mirroring: the back of a two-sided BSDF is the front seen upside down.
    let front = rough_conductor(distribution, false);
    let flip = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
    assert_eq!(
        two_sided.evaluate(below, -above, &lambdas),
        front.evaluate(flip(below), flip(-above), &lambdas)
    );
}

#[test]
fn roughness_for_lqmc() {
    let diffuse: Bsdf = DiffuseBsdf::new(SampledSpectrum::splat(0.5))
        .unwrap()
        .into();
    assert_eq!(diffuse.roughness(), 1.0);
    let glass: Bsdf = DielectricBsdf::new(1.5).unwrap().into();
    assert_eq!(glass.roughness(), 0.0);
    let anisotropic = MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.1, 0.4);
    assert_eq!(rough_conductor(anisotropic, false).roughness(), 0.4);
    let very_rough = MicrofacetDistribution::new(MicrofacetKind::Ggx, 1.7, 0.2);
    assert_eq!(
        rough_dielectric(very_rough, 1.5, TransportMode::Radiance).roughness(),
        1.0
    );
    let plastic: Bsdf = PlasticBsdf::new(SampledSpectrum::splat(0.5), 1.5, false, false).into();
    assert_eq!(plastic.roughness(), 0.0);
    let thin: Bsdf = ThinDielectricBsdf::new(1.5).into();
    assert_eq!(thin.roughness(), 0.0);
    let two = Bsdf::two_sided(
        *diffuse.model(),
        BsdfModel::ThinDielectric(ThinDielectricBsdf::new(1.5)),
    );
    assert_eq!(two.roughness(), 0.0);
}

/// Mitsuba's principled BSDF with `configure` applied to its defaults
/// (white base colour unless set).
fn principled(configure: impl Fn(&mut PrincipledParameters), mode: TransportMode) -> Bsdf {
    let mut parameters = PrincipledParameters::new(SampledSpectrum::splat(1.0));
    configure(&mut parameters);
    Bsdf::from(PrincipledBsdf::new(parameters, &wavelengths())).with_transport_mode(mode)
}

/// Mitsuba's thin principled BSDF with `configure` applied to its defaults.
fn principled_thin(configure: impl Fn(&mut PrincipledThinParameters)) -> Bsdf {
    let mut parameters = PrincipledThinParameters::new(SampledSpectrum::splat(1.0));
    configure(&mut parameters);
    PrincipledThinBsdf::new(parameters, &wavelengths()).into()
}

/// Principled configurations covering every lobe, with the `wo`s to test
/// (transmissive ones also from below).
fn principled_cases() -> Vec<(&'static str, Bsdf, Vec<Vec3>)> {
    let front = vec![direction(20.0, 30.0), direction(65.0, 200.0)];
    let both = vec![direction(40.0, 10.0), -direction(30.0, 250.0)];
    vec![
        (
            "metal anisotropic",
            principled(
                |p| {
                    p.base_color = SampledSpectrum::new([0.9, 0.6, 0.3, 0.8]);
                    p.metallic = 0.7;
                    p.roughness = 0.5;
                    p.anisotropic = 0.6;
                    p.spec_tint = 0.3;
                },
                TransportMode::Radiance,
            ),
            front.clone(),
        ),
        (
            "coated sheen",
            principled(
                |p| {
                    p.roughness = 0.45;
                    p.clearcoat = 0.8;
                    p.clearcoat_gloss = 0.2;
                    p.sheen = 0.5;
                    p.flatness = 0.4;
                },
                TransportMode::Radiance,
            ),
            front,
        ),
        (
            "glass",
            principled(
                |p| {
                    p.roughness = 0.5;
                    p.spec_trans = 0.7;
                    p.anisotropic = 0.3;
                    p.clearcoat = 0.5;
                    p.eta = 1.4;
                    p.main_specular_sampling_rate = 0.6;
                },
                TransportMode::Radiance,
            ),
            both.clone(),
        ),
        (
            "thin",
            principled_thin(|p| {
                p.roughness = 0.5;
                p.anisotropic = 0.5;
                p.spec_trans = 0.6;
                p.diff_trans = 0.8;
                p.sheen = 0.5;
                p.eta = 1.33;
            }),
            both,
        ),
    ]
}

#[test]
fn principled_sampling_matches_its_pdf() {
    for (index, (label, bsdf, wos)) in principled_cases().into_iter().enumerate() {
        for (j, wo) in wos.into_iter().enumerate() {
            assert_sampling_matches_pdf(label, &bsdf, wo, 300 + 10 * index as u64 + j as u64);
        }
    }
}

#[test]
fn principled_densities_integrate_to_the_success_rate() {
    for (index, (label, bsdf, wos)) in principled_cases().into_iter().enumerate() {
        for (j, wo) in wos.into_iter().enumerate() {
            assert_pdf_integrates_to_success_rate(
                label,
                &bsdf,
                wo,
                400 + 10 * index as u64 + j as u64,
            );
        }
    }
}

#[test]
fn principled_samples_carry_evaluate_and_pdf() {
    let mut rng = TestRng(6);
    let mut lambdas = wavelengths();
    for (label, bsdf, _) in principled_cases() {
        let mut successes = 0;
        for _ in 0..4000 {
            let u = rng.uniform2();
            let wo = sample_uniform_sphere([u.x, u.y]);
            let u = rng.uniform2();
            if let Some(sample) = bsdf.sample(wo, rng.uniform(), [u.x, u.y], &mut lambdas) {
                let value = bsdf.evaluate(wo, sample.wi, &lambdas);
                let pdf = bsdf.pdf(wo, sample.wi);
                assert!((sample.pdf - pdf).abs() <= 1e-4 * pdf, "{label}");
                assert!(
                    (sample.value - value).max_component().abs() <= 1e-4 * value.max_component(),
                    "{label}"
                );
                assert!(sample.pdf > 0.0 && sample.value.max_component().is_finite());
                assert_eq!(
                    sample.is_transmission(),
                    sample.wi.z * wo.z < 0.0,
                    "{label}"
                );
                successes += 1;
            }
        }
        assert!(successes > 1000, "{label}: {successes}");
    }
}

/// The configurations of the principled BSDFs whose lobes conserve energy
/// reflect at most what arrives (Burley's diffuse with retro-reflection and
/// the added sheen and clearcoat are not energy conserving in general, so
/// they are left out); the pure diffuse transmission of the thin sheet
/// transmits exactly everything.
#[test]
fn principled_white_furnace() {
    let count = 100_000;
    let metal = principled(
        |p| {
            p.metallic = 1.0;
            p.roughness = 0.4;
            p.anisotropic = 0.5;
        },
        TransportMode::Radiance,
    );
    let glass = principled(
        |p| {
            p.spec_trans = 1.0;
            p.roughness = 0.4;
            p.eta = 1.5;
        },
        TransportMode::Importance,
    );
    let dielectric_coat = principled(
        |p| {
            p.base_color = SampledSpectrum::splat(0.0);
            p.roughness = 0.3;
        },
        TransportMode::Radiance,
    );
    let thin_specular = principled_thin(|p| {
        p.spec_trans = 1.0;
        p.roughness = 0.4;
    });
    let thin_diffuse = principled_thin(|p| p.diff_trans = 2.0);
    for (label, bsdf, wos) in [
        (
            "metal",
            &metal,
            vec![direction(30.0, 0.0), direction(75.0, 0.0)],
        ),
        (
            "glass",
            &glass,
            vec![
                direction(30.0, 0.0),
                -direction(30.0, 0.0),
                direction(80.0, 0.0),
            ],
        ),
        (
            "dielectric coat",
            &dielectric_coat,
            vec![direction(60.0, 0.0)],
        ),
        (
            "thin specular",
            &thin_specular,
            vec![direction(30.0, 0.0), -direction(70.0, 0.0)],
        ),
    ] {
        for (seed, wo) in wos.into_iter().enumerate() {
            let (mean, error) = albedo(bsdf, wo, count, 500 + seed as u64);
            assert!(
                mean <= 1.0 + 5.0 * error + 1e-4 && mean > 0.02,
                "{label} {wo}: {mean} ± {error}"
            );
        }
    }
    let (mean, error) = albedo(&thin_diffuse, direction(50.0, 0.0), count, 9);
    assert!(
        (mean - 1.0).abs() < 5.0 * error + 1e-5,
        "thin diffuse: {mean}"
    );
}

#[test]
fn principled_roughness_for_lqmc() {
    let coated = principled(
        |p| {
            p.roughness = 0.5;
            p.clearcoat = 0.5;
            p.clearcoat_gloss = 1.0;
        },
        TransportMode::Radiance,
    );
    assert!((coated.roughness() - 0.001).abs() < 1e-6);
    let anisotropic = principled(
        |p| {
            p.roughness = 0.5;
            p.anisotropic = 0.5;
        },
        TransportMode::Radiance,
    );
    let expected = 0.25 / (1.0_f32 - 0.45).sqrt();
    assert!((anisotropic.roughness() - expected).abs() < 1e-6);
    assert_eq!(principled_thin(|p| p.roughness = 0.3).roughness(), 1.0);
}

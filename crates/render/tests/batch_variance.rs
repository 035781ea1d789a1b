//! The variance layer of one render of an integrator whose contributions
//! are splats — estimated by the driver from batches: the passes of BDPT,
//! light tracing and VCM (an iteration per pass), batches of chains for
//! PSSMLT — predicts the spread of independent renders. With the
//! `independent` sampler the passes are independent and identically
//! distributed (VCM's iterations up to the shrinking radius, whose bias is
//! far below the noise here); PSSMLT's chain batches are independent given
//! the bootstrap, whose own error the estimate leaves out (`lqmc render
//! --replications R` includes it).
//!
//! Statistic: the ratio of the mean estimated variance to the observed
//! variance over `RENDERS` renders, summed over pixel channels, with its
//! jackknife error over the renders (`support/variance_spread.rs`); it
//! must lie within four errors of 1. The same for the image's mean
//! luminance, whose estimate comes from the batches' image means (what
//! `lqmc render` prints), which must average to the image's.

use render::integrators::erpt::ErptSettings;
use render::integrators::markov_chain::ChainSettings;
use render::integrators::mmlt::MmltSettings;
use render::integrators::pssmlt::PssmltSettings;
use render::integrators::{IntegratorKind, IntegratorSettings};
use render::renderer::{RenderSettings, render};
use render::replication::luminance;
use render::sampler::SamplerKind;
use std::sync::atomic::AtomicBool;

mod path_comparison;
use path_comparison::{builtin, values};
#[path = "support/variance_spread.rs"]
mod variance_spread;
use variance_spread::ratio_with_error;

/// Independent renders per case.
const RENDERS: u64 = 96;

fn assert_predicts_spread(integrator: impl Into<IntegratorSettings>, samples_per_pixel: u64) {
    let integrator: IntegratorSettings = integrator.into();
    let scene = builtin("cornell-box");
    let renders: Vec<_> = (0..RENDERS)
        .map(|seed| {
            let settings = RenderSettings {
                integrator: integrator.clone(),
                sampler: SamplerKind::Independent,
                samples_per_pixel,
                seed: 300 + seed,
                ..RenderSettings::default()
            };
            let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
            let means = &output.batch_image_means;
            let count = means.len() as f64;
            let mean = means.iter().sum::<f64>() / count;
            let variance = means
                .iter()
                .map(|value| (value - mean).powi(2))
                .sum::<f64>()
                / (count - 1.0)
                / count;
            let image = output.image();
            let image_mean = image
                .pixels()
                .iter()
                .map(|pixel| luminance(pixel.map(f64::from)))
                .sum::<f64>()
                / image.pixels().len() as f64;
            assert!(
                (image_mean - mean).abs() <= 1e-5 * mean.abs(),
                "the batches' mean {mean} is the image's {image_mean}"
            );
            (
                (
                    values(&output.image()).collect::<Vec<_>>(),
                    values(&output.variance_image()).collect::<Vec<_>>(),
                ),
                (vec![mean], vec![variance]),
            )
        })
        .collect();
    let (renders, image_means): (Vec<_>, Vec<_>) = renders.into_iter().unzip();
    let (ratio, error) = ratio_with_error(&image_means);
    eprintln!(
        "{} ({samples_per_pixel} spp), image mean: estimated / observed variance {ratio:.3} ± {error:.3}",
        integrator.name()
    );
    assert!(
        (ratio - 1.0).abs() < 4.0 * error,
        "{}, image mean: estimated / observed = {ratio} ± {error}",
        integrator.name()
    );
    assert!(
        renders[0].1.iter().any(|variance| *variance > 0.0),
        "{}: no variance layer",
        integrator.name()
    );
    let (ratio, error) = ratio_with_error(&renders);
    eprintln!(
        "{} ({samples_per_pixel} spp): estimated / observed variance {ratio:.3} ± {error:.3}",
        integrator.name()
    );
    assert!(error < 0.15, "the test is too weak: error {error}");
    assert!(
        (ratio - 1.0).abs() < 4.0 * error,
        "{}: estimated / observed = {ratio} ± {error}",
        integrator.name()
    );
}

#[test]
fn bdpt_pass_variance_predicts_the_spread() {
    assert_predicts_spread(IntegratorKind::Bdpt, 16);
}

#[test]
fn light_tracing_pass_variance_predicts_the_spread() {
    assert_predicts_spread(IntegratorKind::Light, 16);
}

#[test]
fn vcm_iteration_variance_predicts_the_spread() {
    assert_predicts_spread(IntegratorKind::Vcm, 16);
}

/// A bootstrap of 10 000 samples (of 100 000 by default) keeps the 96
/// renders short; the chains are the defaults.
fn short_bootstrap() -> ChainSettings {
    ChainSettings {
        bootstrap_samples: 10_000,
        ..ChainSettings::default()
    }
}

#[test]
fn pssmlt_chain_batch_variance_predicts_the_spread() {
    let settings = PssmltSettings {
        chains: short_bootstrap(),
        ..PssmltSettings::default()
    };
    assert_predicts_spread(IntegratorSettings::Pssmlt(settings), 64);
}

#[test]
fn mmlt_chain_batch_variance_predicts_the_spread() {
    let settings = MmltSettings {
        chains: short_bootstrap(),
    };
    assert_predicts_spread(IntegratorSettings::Mmlt(settings), 64);
}

/// Chains of 20 mutations (100 by default) keep the renders short.
#[test]
fn erpt_pass_variance_predicts_the_spread() {
    let settings = ErptSettings {
        chain_length: 20,
        bootstrap_samples: 10_000,
        ..ErptSettings::default()
    };
    assert_predicts_spread(IntegratorSettings::Erpt(settings), 16);
}

//! The error estimate of a render of independent replications
//! (`render::replication`, `lqmc render --replications R`) predicts the
//! spread of independent renders, for the path tracer with seeded Halton,
//! BDPT with Owen-scrambled Sobol (randomized QMC) and LQMC with seeded
//! Halton (exploring the paper's classes on dof-spheres).
//!
//! `RENDERS` renders with independent base seeds, each the mean of
//! `REPLICATIONS` replications. Two estimates are checked, each by the
//! ratio of the mean estimated variance to the observed variance over the
//! renders, with its jackknife standard error (`support/variance_spread.rs`):
//! 1. per pixel: the variance layer `s²/r` against the spread of each
//!    pixel channel;
//! 2. the image: the squared standard error of the image's mean luminance
//!    (what `--target-error` stops on) against the spread of the renders'
//!    image means.
//!
//! The ratio must lie within four jackknife errors of 1, and the error must
//! be small enough for that to mean something. With `r = 4` the estimate
//! `s²/r` has 3 degrees of freedom per render; its mean over the renders is
//! still unbiased.

use render::integrators::IntegratorSettings;
use render::integrators::lqmc::LqmcSettings;
use render::renderer::RenderSettings;
use render::replication::{ReplicationPlan, render_replications};
use render::sampler::SamplerKind;
use render::scene::Scene;
use std::sync::atomic::AtomicBool;

mod path_comparison;
use path_comparison::{builtin, values};
#[path = "support/variance_spread.rs"]
mod variance_spread;
use variance_spread::{Render, ratio_with_error};

/// Independent renders per case.
const RENDERS: u64 = 96;
/// Replications per render.
const REPLICATIONS: u64 = 4;

/// Per render: (pixel channels, their variance layer) and (image mean
/// luminance, its squared standard error).
fn renders(scene: &Scene, settings: &RenderSettings) -> (Vec<Render>, Vec<Render>) {
    let plan = ReplicationPlan {
        first: 0,
        count: REPLICATIONS,
        region: None,
        target: None,
        time_budget: None,
    };
    (0..RENDERS)
        .map(|render| {
            let settings = RenderSettings {
                seed: 7000 + 1000 * render,
                ..settings.clone()
            };
            let rendered = render_replications(
                scene,
                &settings,
                &plan,
                &AtomicBool::new(false),
                &|_| {},
                None,
                &mut |_| {},
            )
            .unwrap();
            let accumulator = &rendered.accumulator;
            let estimate = accumulator.estimate();
            (
                (
                    values(&accumulator.mean_image()).collect(),
                    values(&accumulator.variance_image()).collect(),
                ),
                (
                    vec![estimate.region_mean],
                    vec![estimate.standard_error.powi(2)],
                ),
            )
        })
        .unzip()
}

fn assert_predicts_spread(name: &str, scene: &Scene, settings: RenderSettings) {
    let (pixels, means) = renders(scene, &settings);
    for (what, renders, largest_error) in [("pixels", pixels, 0.12), ("image mean", means, 0.3)] {
        let (ratio, error) = ratio_with_error(&renders);
        eprintln!(
            "{name}, {what}: estimated / observed variance {ratio:.3} ± {error:.3} ({RENDERS} renders of {REPLICATIONS} replications)"
        );
        assert!(
            error < largest_error,
            "{name}, {what}: the test is too weak: error {error}"
        );
        assert!(
            (ratio - 1.0).abs() < 4.0 * error,
            "{name}, {what}: estimated / observed = {ratio} ± {error}"
        );
    }
}

#[test]
fn path_halton_replications_predict_the_spread() {
    assert_predicts_spread(
        "path, halton",
        &builtin("cornell-box"),
        RenderSettings {
            samples_per_pixel: 4,
            ..RenderSettings::default()
        },
    );
}

#[test]
fn bdpt_owen_sobol_replications_predict_the_spread() {
    assert_predicts_spread(
        "bdpt, sobol",
        &builtin("cornell-box"),
        RenderSettings {
            integrator: render::integrators::IntegratorKind::Bdpt.into(),
            sampler: SamplerKind::Sobol,
            heuristic: render::integrators::MisHeuristic::Balance,
            samples_per_pixel: 4,
            ..RenderSettings::default()
        },
    );
}

#[test]
fn lqmc_halton_replications_predict_the_spread() {
    assert_predicts_spread(
        "lqmc, halton",
        &builtin("dof-spheres"),
        RenderSettings {
            integrator: IntegratorSettings::Lqmc(LqmcSettings::paper_classes()),
            samples_per_pixel: 4,
            ..RenderSettings::default()
        },
    );
}

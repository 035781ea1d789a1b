//! Integrators: estimators of the radiance arriving at the camera. Each
//! takes its numbers from a [`crate::sampler::SampleSource`] following the
//! dimension layout of [`crate::sampler::layout`].

pub mod lqmc;
pub mod path;
pub mod path_vertex;
pub mod volpath;

/// The integrators a user can choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IntegratorKind {
    /// Unidirectional path tracing with next-event estimation and MIS
    /// (surfaces only: participating media are ignored).
    Path,
    /// Volumetric path tracing: [`Path`](Self::Path) with homogeneous
    /// participating media, index-matched boundaries and spectral MIS
    /// (pbrt-v4's `VolPathIntegrator`; see [`volpath`]).
    VolPath,
    /// Local quasi-Monte Carlo exploration of Halton-seeded path tracing.
    Lqmc,
}

impl IntegratorKind {
    /// Every integrator with its command-line name.
    pub const ALL: [(IntegratorKind, &'static str); 3] = [
        (IntegratorKind::Path, "path"),
        (IntegratorKind::VolPath, "volpath"),
        (IntegratorKind::Lqmc, "lqmc"),
    ];

    /// The integrator called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(k, _)| *k)
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(k, _)| *k == self).unwrap().1
    }
}

/// How multiple importance sampling weighs next-event estimation against
/// BSDF sampling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MisHeuristic {
    /// Veach's power heuristic with exponent 2 (the default).
    #[default]
    Power,
    /// Veach's balance heuristic.
    Balance,
}

impl MisHeuristic {
    /// The weight of a technique with density `own` against one with `other`.
    #[inline]
    pub fn weight(self, own: f32, other: f32) -> f32 {
        match self {
            MisHeuristic::Power => {
                let (a, b) = (own * own, other * other);
                if a.is_infinite() {
                    1.0
                } else if a + b == 0.0 {
                    0.0
                } else {
                    a / (a + b)
                }
            }
            MisHeuristic::Balance => {
                if own + other == 0.0 {
                    0.0
                } else {
                    own / (own + other)
                }
            }
        }
    }

    /// `weight(own, other) / own`: what a sample drawn with density `own`
    /// is multiplied by. For the power heuristic that is `own / (own² +
    /// other²)`, one division where the weight and the estimator's division
    /// by the density made a chain of two (next-event estimation's hot
    /// path). Where that sum is zero or not finite, the two divisions are
    /// done as written, so the edge cases of [`MisHeuristic::weight`] stay.
    #[inline]
    pub fn weight_over_density(self, own: f32, other: f32) -> f32 {
        let sum = match self {
            MisHeuristic::Power => own * own + other * other,
            MisHeuristic::Balance => own + other,
        };
        if sum > 0.0 && sum < f32::INFINITY {
            match self {
                MisHeuristic::Power => own / sum,
                MisHeuristic::Balance => 1.0 / sum,
            }
        } else {
            self.weight(own, other) / own
        }
    }
}

/// Counters an integrator keeps while tracing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceCounters {
    /// Closest-hit rays.
    pub closest_hit_rays: u64,
    /// Shadow (any-hit) rays.
    pub shadow_rays: u64,
}

impl TraceCounters {
    /// All rays traced.
    pub fn rays(&self) -> u64 {
        self.closest_hit_rays + self.shadow_rays
    }

    /// Adds another set of counters.
    pub fn add(&mut self, other: &TraceCounters) {
        self.closest_hit_rays += other.closest_hit_rays;
        self.shadow_rays += other.shadow_rays;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heuristics_sum_to_one() {
        for heuristic in [MisHeuristic::Power, MisHeuristic::Balance] {
            let (a, b) = (0.3, 2.1);
            let total = heuristic.weight(a, b) + heuristic.weight(b, a);
            assert!((total - 1.0).abs() < 1e-6);
            assert_eq!(heuristic.weight(0.0, 0.0), 0.0);
        }
        assert_eq!(MisHeuristic::Power.weight(f32::INFINITY, 1.0), 1.0);
    }

    /// The one-division form equals the weight divided by the density, to
    /// rounding, and keeps the edge cases of the weight.
    #[test]
    fn weight_over_density_is_the_weight_divided_by_the_density() {
        for heuristic in [MisHeuristic::Power, MisHeuristic::Balance] {
            for (own, other) in [
                (0.3, 2.1),
                (5.0, 0.0),
                (1e-3, 3.0),
                (2e19, 1.0),
                (7.0, 1e30),
            ] {
                let expected = heuristic.weight(own, other) / own;
                let actual = heuristic.weight_over_density(own, other);
                assert!(
                    (actual - expected).abs() <= 1e-6 * expected.abs(),
                    "{heuristic:?} {own} {other}: {actual} vs {expected}"
                );
            }
        }
    }
}

//! Multiple importance sampling weights (Veach 1997, "Robust Monte Carlo
//! Methods for Light Transport Simulation", chapter 9): how a sample drawn
//! by one technique is weighted against another technique that could have
//! drawn it. Integrators weigh next-event estimation against BSDF sampling
//! with them, and layered BSDFs their internal strategies.

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

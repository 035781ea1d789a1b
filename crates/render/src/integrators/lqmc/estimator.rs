//! The estimator of one exploration: Eq. (9) of the paper, extended as
//! `docs/integrators/lqmc.md` ("Implementation notes") requires so that it stays
//! unbiased when the breakup vertex and the class are chosen per path.
//!
//! Member `j` carries its path tracer contribution `C_j = w_t f(X_j) /
//! p_t(X_j)` and `q_j = P(c | X_j) · p_t(X_j) / J_j`, the probability that
//! `X_j` would itself choose this exploration `c` (breakup vertex, class)
//! times the density of the seed's suffix given its prefix. Eq. (9),
//! `w_t f(X_j) / (J_j Σ_m p_t(X_m) / J_m)` times `P(c | X_j)`, is then
//! `C_j · q_j / Σ_m q_m`: a balance heuristic over the set. A failed member
//! has `q_j = 0`. With `s̄ = s` (no suffix) every valid member has the same
//! `q`, and each gets `C_j / M` with `M` the number of valid members: the
//! paper's Eq. (10).
//!
//! # Multi-lobe vertices (plastic, rough dielectric)
//!
//! The lobe of a vertex is chosen by its component number, which the set
//! shares with the seed. Write `c` for the shared numbers and `J_c(P)` for
//! the density of the prefix map `ū ↦ P` at fixed `c` (the chosen lobes' own
//! densities, without their selection probabilities). A member's path has
//! density `J_c(P_j) · p(S | P_seed)`, so Eq. (9) holds with any
//! contribution `C(c, X)` for which `∫ C(c, X) J_c(P) p(S | P) dc = f(X)`:
//! `J_c` cancels between the member density and the estimator and never has
//! to be computed. The walk uses the mixture (marginal) density `bsdf.pdf`
//! and the full `bsdf.evaluate` at non-specular vertices, whose integral of
//! `J_c` over `c` is exactly that mixture density, so the condition holds;
//! the suffix density is the mixture density as well (its component numbers
//! are integrated out, since its positions are kept). Delta lobes (smooth
//! plastic's coating, smooth dielectrics) are re-sampled with the seed's
//! numbers, the discrete probability staying in `C`. A member whose
//! rebuilt vertex samples another lobe than the seed's, or whose walked
//! directions make a different kind of scattering (reflection instead of
//! transmission), fails; the rule compares every member with the same
//! recorded lobes, so it is symmetric within the set and keeps the
//! estimator unbiased (it only costs members). Tested by
//! `tests/lqmc_convergence.rs` on a Cornell box with rough and smooth
//! plastic and on `translucent-spheres` (rough glass).

/// The weight of each member's own contribution, `q_j / Σ_m q_m`, written
/// into `weights` (all zero if every `q` is zero).
pub fn member_weights(suffix_densities: &[f64], weights: &mut Vec<f64>) {
    weights.clear();
    let total: f64 = suffix_densities.iter().filter(|q| q.is_finite()).sum();
    weights.extend(suffix_densities.iter().map(|q| {
        if total > 0.0 && q.is_finite() {
            q / total
        } else {
            0.0
        }
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_are_a_partition_of_unity() {
        let mut weights = Vec::new();
        member_weights(&[1.0, 3.0, 0.0, 4.0], &mut weights);
        assert_eq!(weights, vec![0.125, 0.375, 0.0, 0.5]);
        member_weights(&[0.0, 0.0], &mut weights);
        assert_eq!(weights, vec![0.0, 0.0]);
    }

    /// Eq. (10): exploring every dimension (no static suffix), each of the
    /// M valid members has the same q, so p(X_i) = p_t(X_i) · M and each
    /// contributes C_i / M.
    #[test]
    fn full_exploration_reduces_to_equation_ten() {
        let densities = [1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0];
        let valid = densities.iter().filter(|q| **q > 0.0).count() as f64;
        let mut weights = Vec::new();
        member_weights(&densities, &mut weights);
        for (q, weight) in densities.iter().zip(&weights) {
            let expected = if *q > 0.0 { 1.0 / valid } else { 0.0 };
            assert!((weight - expected).abs() < 1e-15);
        }
    }
}

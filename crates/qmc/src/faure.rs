//! Faure's digit permutations (Faure 1992), the scrambling of "scrambled
//! Halton" in Kollig & Keller (2002) and Grünschloß, Raab & Keller (2012).
//!
//! The permutations are defined recursively (facts from Faure 1992, as
//! summarised in `docs/qmc.md`, "Reference values"):
//! - σ₂ = (0, 1);
//! - for even b: σ_b = (2σ_{b/2}, 2σ_{b/2} + 1): first the doubled values of
//!   σ_{b/2}, then the doubled values plus one;
//! - for odd b: take σ_{b−1}, add one to every value ≥ (b−1)/2 and insert
//!   (b−1)/2 in the middle.
//!
//! Every σ_b fixes 0, so a Faure-permuted radical inverse of a finite index has
//! finitely many non-zero digits, and σ₂ and σ₃ are the identity, which keeps
//! the first two Halton dimensions (bases 2 and 3) unpermuted as per-pixel
//! enumeration requires.

/// Faure's permutation σ_b of the digits `0..base`, for `base >= 2`.
pub fn faure_permutation(base: u32) -> Vec<u16> {
    assert!(
        (2..=u16::MAX as u32 + 1).contains(&base),
        "Faure permutations need a base in 2..=65536"
    );
    if base == 2 {
        return vec![0, 1];
    }
    // σ_b needs only σ_{b/2} (even b) or σ_{b−1} (odd b): a chain of
    // about 2·log₂(b) smaller permutations.
    if base.is_multiple_of(2) {
        let half = faure_permutation(base / 2);
        half.iter()
            .map(|&v| 2 * v)
            .chain(half.iter().map(|&v| 2 * v + 1))
            .collect()
    } else {
        let middle = ((base - 1) / 2) as u16;
        let previous = faure_permutation(base - 1);
        let mut permutation: Vec<u16> = previous
            .iter()
            .map(|&v| if v >= middle { v + 1 } else { v })
            .collect();
        permutation.insert(previous.len() / 2, middle);
        permutation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_permutations_match_faure_1992() {
        assert_eq!(faure_permutation(2), vec![0, 1]);
        assert_eq!(faure_permutation(3), vec![0, 1, 2]);
        assert_eq!(faure_permutation(4), vec![0, 2, 1, 3]);
        assert_eq!(faure_permutation(5), vec![0, 3, 2, 1, 4]);
        // σ₇ from σ₆ = (0, 2, 4, 1, 3, 5): shift values ≥ 3, insert 3 in the middle.
        assert_eq!(faure_permutation(6), vec![0, 2, 4, 1, 3, 5]);
        assert_eq!(faure_permutation(7), vec![0, 2, 5, 3, 1, 4, 6]);
    }

    #[test]
    fn permutations_are_bijections_fixing_zero() {
        for base in [2u32, 3, 11, 97, 313, 8161] {
            let mut permutation = faure_permutation(base);
            assert_eq!(permutation.len(), base as usize);
            assert_eq!(permutation[0], 0);
            permutation.sort_unstable();
            assert!(
                permutation
                    .iter()
                    .enumerate()
                    .all(|(i, &v)| i == v as usize)
            );
        }
    }
}

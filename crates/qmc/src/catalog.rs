//! Point sets by name: the sequences and scrambles a user can choose on the
//! command line or in a renderer's sampler settings, built from one place.

use crate::cbc::{ProductWeights, cbc};
use crate::cranley_patterson::CranleyPatterson;
use crate::digital_scramble::{DigitalOrder, DigitalScramble, DigitalSequence, Scrambled};
use crate::halton::{Halton, HaltonScramble};
use crate::hammersley::Hammersley;
use crate::niederreiter::Niederreiter;
use crate::point_set::{PointSet, PointSetError};
use crate::random::RandomPoints;
use crate::sobol::Sobol;

/// A family of points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sequence {
    /// The Halton sequence (prime bases).
    Halton,
    /// The Hammersley point set (`i/N`, then Halton).
    Hammersley,
    /// The Sobol sequence with Joe–Kuo direction numbers.
    Sobol,
    /// The Niederreiter sequence in base 2.
    Niederreiter,
    /// A rank-1 lattice built by component-by-component construction.
    Lattice,
    /// Independent uniform random points (PCG).
    Random,
}

impl Sequence {
    /// Every sequence with its command-line name.
    pub const ALL: [(Sequence, &'static str); 6] = [
        (Sequence::Halton, "halton"),
        (Sequence::Hammersley, "hammersley"),
        (Sequence::Sobol, "sobol"),
        (Sequence::Niederreiter, "niederreiter"),
        (Sequence::Lattice, "lattice"),
        (Sequence::Random, "random"),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(s, _)| *s == self).unwrap().1
    }

    /// The sequence called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(s, _)| *s)
    }

    /// True for finite point sets, which need their size up front.
    pub fn is_finite(self) -> bool {
        matches!(self, Sequence::Hammersley | Sequence::Lattice)
    }

    /// How many points the sequence can produce (indices `0..max_points`).
    pub fn max_points(self) -> u64 {
        match self {
            Sequence::Sobol => crate::sobol::MAX_POINTS,
            Sequence::Niederreiter => crate::niederreiter::MAX_POINTS,
            _ => u64::MAX,
        }
    }

    /// How many dimensions the sequence supports.
    pub fn max_dimensions(self) -> usize {
        match self {
            Sequence::Halton => crate::primes::PRIME_COUNT,
            Sequence::Hammersley => crate::primes::PRIME_COUNT + 1,
            Sequence::Sobol => crate::sobol::MAX_DIMENSIONS,
            Sequence::Niederreiter => crate::niederreiter::MAX_DIMENSIONS,
            Sequence::Lattice | Sequence::Random => usize::MAX,
        }
    }
}

/// A randomization (or deterministic scramble) of a point set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scramble {
    /// The points as constructed.
    None,
    /// Faure's permutations (Halton, Hammersley).
    Faure,
    /// Random digit permutations per dimension and digit (Halton, Hammersley).
    Permute,
    /// Owen's nested uniform scrambling (hash-based for the base-2 sequences).
    Owen,
    /// Exact nested uniform scrambling with one random bit per tree node
    /// (base-2 sequences; slower reference for `Owen`).
    NestedUniform,
    /// Random digital shift: XOR with a random vector (base-2 sequences).
    Xor,
    /// Random linear matrix scrambling with a digital shift (base-2 sequences).
    LinearMatrix,
    /// Cranley–Patterson rotation: a random shift modulo one (any set).
    Shift,
}

impl Scramble {
    /// Every scramble with its command-line name.
    pub const ALL: [(Scramble, &'static str); 8] = [
        (Scramble::None, "none"),
        (Scramble::Faure, "faure"),
        (Scramble::Permute, "permute"),
        (Scramble::Owen, "owen"),
        (Scramble::NestedUniform, "nested"),
        (Scramble::Xor, "xor"),
        (Scramble::LinearMatrix, "lms"),
        (Scramble::Shift, "shift"),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(s, _)| *s == self).unwrap().1
    }

    /// The scramble called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(s, _)| *s)
    }
}

/// Builds `sequence` with `scramble` for points `0..point_count` in
/// `dimensions` dimensions. `point_count` sizes the finite sets (Hammersley,
/// lattice: by component-by-component construction with the product weights
/// `γ_j = 1/dimensions`); sequences ignore it. `order` enumerates the base-2 sequences
/// (Sobol, Niederreiter). Errors name what does not fit.
pub fn build(
    sequence: Sequence,
    scramble: Scramble,
    order: DigitalOrder,
    point_count: u64,
    dimensions: usize,
    seed: u64,
) -> Result<Box<dyn PointSet>, PointSetError> {
    if dimensions == 0 {
        return Err(PointSetError::InvalidParameter(
            "at least one dimension is needed".into(),
        ));
    }
    let unsupported = || {
        Err(PointSetError::InvalidParameter(format!(
            "the scramble '{}' does not apply to the sequence '{}'",
            scramble.name(),
            sequence.name()
        )))
    };
    let halton_scramble = match scramble {
        Scramble::None | Scramble::Shift => HaltonScramble::None,
        Scramble::Faure => HaltonScramble::Faure,
        Scramble::Permute => HaltonScramble::RandomPermutation,
        Scramble::Owen => HaltonScramble::Owen,
        Scramble::NestedUniform | Scramble::Xor | Scramble::LinearMatrix => HaltonScramble::None,
    };
    let digital_scramble = match scramble {
        Scramble::None | Scramble::Shift => Some(DigitalScramble::None),
        Scramble::Owen => Some(DigitalScramble::HashOwen),
        Scramble::NestedUniform => Some(DigitalScramble::NestedUniform),
        Scramble::Xor => Some(DigitalScramble::XorShift),
        Scramble::LinearMatrix => Some(DigitalScramble::LinearMatrix),
        Scramble::Faure | Scramble::Permute => None,
    };
    fn digital(
        sequence: impl DigitalSequence + 'static,
        scramble: DigitalScramble,
        seed: u64,
    ) -> Box<dyn PointSet> {
        match scramble {
            DigitalScramble::None => Box::new(PlainDigital(sequence)),
            _ => Box::new(Scrambled::new(sequence, scramble, seed)),
        }
    }
    let set: Box<dyn PointSet> = match sequence {
        Sequence::Halton | Sequence::Hammersley
            if matches!(
                scramble,
                Scramble::Xor | Scramble::LinearMatrix | Scramble::NestedUniform
            ) =>
        {
            return unsupported();
        }
        Sequence::Sobol | Sequence::Niederreiter if digital_scramble.is_none() => {
            return unsupported();
        }
        Sequence::Sobol => digital(
            Sobol::new(dimensions, order)?,
            digital_scramble.unwrap(),
            seed,
        ),
        Sequence::Niederreiter => digital(
            Niederreiter::new(dimensions, order)?,
            digital_scramble.unwrap(),
            seed,
        ),
        Sequence::Halton => Box::new(Halton::new(dimensions, halton_scramble, seed)?),
        Sequence::Hammersley => Box::new(Hammersley::new(
            point_count,
            dimensions,
            halton_scramble,
            seed,
        )?),
        Sequence::Random => match scramble {
            Scramble::None | Scramble::Shift => Box::new(RandomPoints::new(dimensions, seed)),
            _ => return unsupported(),
        },
        Sequence::Lattice => match scramble {
            Scramble::None | Scramble::Shift => Box::new(
                cbc(
                    point_count,
                    dimensions,
                    &ProductWeights::lqmc_default(dimensions),
                )?
                .lattice,
            ),
            _ => return unsupported(),
        },
    };
    if scramble == Scramble::Shift {
        // The rotation's shifts come from another stream than the set's own
        // randomness (none, for the sets that accept a shift here).
        return Ok(Box::new(CranleyPatterson::from_seed(set, seed)));
    }
    Ok(set)
}

/// A base-2 sequence as a [`PointSet`] without randomization.
struct PlainDigital<S: DigitalSequence>(S);

impl<S: DigitalSequence> PointSet for PlainDigital<S> {
    fn dimensions(&self) -> usize {
        self.0.dimensions()
    }
    fn len(&self) -> Option<u64> {
        self.0.len()
    }
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        crate::digital_scramble::bits_to_unit(self.0.sample_bits(index, dimension))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for (sequence, name) in Sequence::ALL {
            assert_eq!(Sequence::from_name(name), Some(sequence));
            assert_eq!(sequence.name(), name);
        }
        for (scramble, name) in Scramble::ALL {
            assert_eq!(Scramble::from_name(name), Some(scramble));
        }
        assert_eq!(Sequence::from_name("sobolev"), None);
    }

    #[test]
    fn every_sequence_builds_with_a_shift() {
        for (sequence, _) in Sequence::ALL {
            let set = build(sequence, Scramble::Shift, DigitalOrder::Natural, 16, 3, 5).unwrap();
            assert_eq!(set.dimensions(), 3);
            let value = set.sample(7, 2);
            assert!((0.0..1.0).contains(&value));
        }
    }

    #[test]
    fn lattice_is_built_by_cbc() {
        let set = build(
            Sequence::Lattice,
            Scramble::None,
            DigitalOrder::Natural,
            7,
            2,
            0,
        )
        .unwrap();
        assert_eq!(set.len(), Some(7));
        assert_eq!(set.sample(1, 0), 1.0 / 7.0);
    }

    #[test]
    fn mismatched_scramble_is_an_error() {
        assert!(
            build(
                Sequence::Halton,
                Scramble::Xor,
                DigitalOrder::Natural,
                0,
                2,
                0
            )
            .is_err()
        );
        assert!(
            build(
                Sequence::Random,
                Scramble::Faure,
                DigitalOrder::Natural,
                0,
                2,
                0
            )
            .is_err()
        );
        assert!(
            build(
                Sequence::Halton,
                Scramble::Faure,
                DigitalOrder::Natural,
                0,
                0,
                0
            )
            .is_err()
        );
    }
}

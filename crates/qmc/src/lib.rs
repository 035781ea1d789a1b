//! Quasi-Monte Carlo point sets and sequences for light transport.
//!
//! This crate knows nothing of rendering. It provides
//! - low-discrepancy sequences and point sets: Halton (plain, Faure-permuted,
//!   randomly permuted, Owen-scrambled) with per-pixel enumeration, Hammersley,
//!   Sobol (Joe–Kuo direction numbers), Niederreiter base 2;
//! - randomizations: Cranley–Patterson rotation, random digital shift, Owen
//!   scrambling (hash-based and exact nested uniform), linear matrix scrambling;
//! - rank-1 lattices built by fast component-by-component construction, and the
//!   closest lattice point on the unit torus (what local QMC exploration needs);
//! - randomized QMC: independent replications with unbiased mean and variance
//!   estimators, padded replications and Latin supercube sampling;
//! - pseudo-random generators (seekable PCG, MT19937) and discrepancy measures.
//!
//! Every point set implements [`PointSet`]: coordinates are asked for by index and
//! dimension, which is how the renderer's primary-sample-space samplers use them.

pub mod catalog;
pub mod cbc;
pub mod closest_point;
pub mod cranley_patterson;
pub mod digit_groups;
pub mod digital_scramble;
pub mod discrepancy;
pub mod faure;
pub mod halton;
pub mod hammersley;
pub mod hash;
pub mod lattice;
pub mod lattice_table;
pub mod niederreiter;
pub mod padded;
pub mod point_set;
pub mod primes;
pub mod radical_inverse;
pub mod random;
pub mod replication;
pub mod sobol;
pub mod summation;

pub use point_set::{PointSet, PointSetError};

//! Measured complex indices of refraction η + iκ of the metals (and a few
//! other absorbing materials) that Mitsuba 3 knows by name
//! (`<string name="material" value="Au"/>`), also used for pbrt-v4's named
//! spectra `metal-Ag-eta`, `metal-Ag-k`, … .
//!
//! Data: Mitsuba 3.9.1's `data/ior/*.spd` files, which cite the luxpop.com
//! database and, for the `*_palik` names, E. D. Palik, *Handbook of Optical
//! Constants of Solids* (1985); converted by
//! `scripts/golden/measured_conductors.py` into `measured_conductors_data.rs`.
//! Where a table stops inside the visible range (360–830 nm) its last value is
//! held constant to the end of the range (a table's spectrum would otherwise
//! drop to 0 there, which the Fresnel equations read as a perfect mirror).

use crate::spectrum::{
    CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, ConstantSpectrum, PiecewiseLinearSpectrum, Spectrum,
};

/// The generated tables (some measured values happen to be close to π).
#[allow(clippy::approx_constant, clippy::type_complexity)]
mod data {
    include!("measured_conductors_data.rs");
}
use data::MEASURED_CONDUCTORS;

/// The complex index of refraction of a named conductor.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredConductor {
    /// Real part η.
    pub eta: Spectrum,
    /// Extinction coefficient κ.
    pub k: Spectrum,
}

/// The conductor Mitsuba 3 calls `name` (`Au`, `Cu_palik`, `a-C`, …; see
/// Mitsuba's `conductor` plugin docs for the list), or `none`: η = κ = 0,
/// which the Fresnel equations here treat as a perfect mirror (Mitsuba's
/// "100 % reflecting mirror"). `None` for an unknown name.
pub fn measured_conductor(name: &str) -> Option<MeasuredConductor> {
    if name == "none" {
        let zero = Spectrum::Constant(ConstantSpectrum::new(0.0).ok()?);
        return Some(MeasuredConductor {
            eta: zero.clone(),
            k: zero,
        });
    }
    let (_, eta, k) = MEASURED_CONDUCTORS
        .iter()
        .find(|(known, _, _)| *known == name)?;
    Some(MeasuredConductor {
        eta: held_to_range(eta)?,
        k: held_to_range(k)?,
    })
}

/// The names [`measured_conductor`] knows (without `none`).
pub fn measured_conductor_names() -> impl Iterator<Item = &'static str> {
    MEASURED_CONDUCTORS.iter().map(|(name, _, _)| *name)
}

/// A piecewise-linear spectrum through `samples`, its end values held out to
/// the CIE range.
fn held_to_range(samples: &[(f32, f32)]) -> Option<Spectrum> {
    let mut points = samples.to_vec();
    let (first, last) = (*points.first()?, *points.last()?);
    if first.0 > CIE_LAMBDA_MIN as f32 {
        points.insert(0, (CIE_LAMBDA_MIN as f32, first.1));
    }
    if last.0 < CIE_LAMBDA_MAX as f32 {
        points.push((CIE_LAMBDA_MAX as f32, last.1));
    }
    PiecewiseLinearSpectrum::new(&points)
        .ok()
        .map(Spectrum::PiecewiseLinear)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_table_builds_and_gold_is_yellow() {
        for name in measured_conductor_names() {
            let conductor = measured_conductor(name).unwrap_or_else(|| panic!("{name}"));
            for lambda in [360.0, 550.0, 830.0] {
                assert!(conductor.eta.evaluate(lambda) > 0.0, "{name} {lambda}");
                assert!(conductor.k.evaluate(lambda) >= 0.0, "{name} {lambda}");
            }
        }
        assert!(measured_conductor("unobtainium").is_none());
        // Gold: κ grows with the wavelength and η drops below 0.5 in the red
        // (luxpop: η(652.5 nm) = 0.166, κ = 3.15).
        let gold = measured_conductor("Au").unwrap();
        assert!(gold.eta.evaluate(650.0) < 0.5 && gold.eta.evaluate(450.0) > 1.0);
        assert!((gold.k.evaluate(652.548) - 3.15).abs() < 1e-3);
        assert!((gold.eta.evaluate(652.548) - 0.166).abs() < 1e-4);
        let mirror = measured_conductor("none").unwrap();
        assert_eq!(mirror.eta.evaluate(500.0), 0.0);
    }
}

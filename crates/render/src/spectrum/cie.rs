//! The CIE tables the renderer's colour science rests on: the CIE 1931 2° standard
//! observer colour-matching functions x̄, ȳ, z̄ and the standard illuminant D65.
//!
//! Data: `crates/render/data/spectra/` (see its README), written by
//! `scripts/spectrum/make_cie_tables.py` from the colour-science package
//! (BSD-3-Clause), which tabulates CIE 15:2004 / CIE 018:2019 (CMFs, 360–830 nm,
//! 1 nm) and CIE 15:2004 / CIE S 014-2 (D65, 5 nm, linearly interpolated to 1 nm).
//!
//! Normalisation (pbrt-v4's convention): XYZ of a spectrum S is
//! X = Σ_λ S(λ) x̄(λ) / [`CIE_Y_INTEGRAL`] over 1 nm steps (and likewise Y, Z), so
//! the constant spectrum 1 has Y = 1. [`d65_illuminant`] is scaled so that its
//! Y is 1 too; a diffuse white lit by it then has linear sRGB ≈ (1, 1, 1).

use std::sync::OnceLock;

use super::densely_sampled::DenselySampledSpectrum;

/// Σ ȳ(λ) over λ = 360, 361, …, 830 nm: the normalisation of XYZ so that the
/// constant spectrum 1 has Y = 1. 106.856895 is pbrt-v4's value
/// (`CIE_Y_integral`); the sum over the CIE 018:2019 table shipped here is
/// 106.856917, 2·10⁻⁷ relative away.
pub const CIE_Y_INTEGRAL: f32 = 106.856_895;

/// First wavelength (nm) of the colour-matching function tables.
pub const CIE_LAMBDA_MIN: i32 = 360;

/// Last wavelength (nm) of the colour-matching function tables.
pub const CIE_LAMBDA_MAX: i32 = 830;

/// The CMF table: wavelength, x̄, ȳ, z̄ per line.
const CMF_TEXT: &str = include_str!("../../data/spectra/cie_1931_2deg_cmf_1nm.txt");

/// The D65 table: wavelength, relative power (100 at 560 nm) per line.
const D65_TEXT: &str = include_str!("../../data/spectra/cie_d65_1nm.txt");

/// Parses a whitespace-separated table (lines starting with `#` are comments)
/// with `columns` numbers per line and 1 nm steps; returns the first wavelength
/// and the value columns. The tables are part of the build, and the unit tests
/// read every one of them, so a malformed table fails the tests, never a render.
fn parse_table(text: &str, columns: usize) -> (i32, Vec<Vec<f32>>) {
    let mut lambda_min = None;
    let mut data = vec![Vec::new(); columns - 1];
    for line in text
        .lines()
        .filter(|line| !line.starts_with('#') && !line.trim().is_empty())
    {
        let numbers: Vec<f64> = line
            .split_whitespace()
            .map(|field| {
                field
                    .parse()
                    .expect("embedded CIE table holds a non-number")
            })
            .collect();
        assert_eq!(
            numbers.len(),
            columns,
            "embedded CIE table has a short line"
        );
        let lambda = numbers[0] as i32;
        let first = *lambda_min.get_or_insert(lambda);
        assert_eq!(
            lambda - first,
            data[0].len() as i32,
            "embedded CIE table is not in 1 nm steps"
        );
        for (column, value) in data.iter_mut().zip(&numbers[1..]) {
            column.push(*value as f32);
        }
    }
    (lambda_min.expect("embedded CIE table is empty"), data)
}

/// The three colour-matching functions, parsed once.
pub(super) fn cmf_tables() -> &'static [DenselySampledSpectrum; 3] {
    static TABLES: OnceLock<[DenselySampledSpectrum; 3]> = OnceLock::new();
    TABLES.get_or_init(|| {
        let (lambda_min, columns) = parse_table(CMF_TEXT, 4);
        columns
            .into_iter()
            .map(|values| {
                DenselySampledSpectrum::from_values(lambda_min, values).expect("CIE CMF table")
            })
            .collect::<Vec<_>>()
            .try_into()
            .expect("three CMF columns")
    })
}

/// CIE 1931 2° colour-matching function x̄ (360–830 nm, 1 nm).
pub fn cie_x() -> &'static DenselySampledSpectrum {
    &cmf_tables()[0]
}

/// CIE 1931 2° colour-matching function ȳ, the photopic luminous efficiency
/// V(λ) (360–830 nm, 1 nm).
pub fn cie_y() -> &'static DenselySampledSpectrum {
    &cmf_tables()[1]
}

/// CIE 1931 2° colour-matching function z̄ (360–830 nm, 1 nm).
pub fn cie_z() -> &'static DenselySampledSpectrum {
    &cmf_tables()[2]
}

/// CIE standard illuminant D65 as tabulated: relative spectral power with
/// value 100 at 560 nm, 300–830 nm at 1 nm.
pub fn d65_relative() -> &'static DenselySampledSpectrum {
    static TABLE: OnceLock<DenselySampledSpectrum> = OnceLock::new();
    TABLE.get_or_init(|| {
        let (lambda_min, mut columns) = parse_table(D65_TEXT, 2);
        DenselySampledSpectrum::from_values(lambda_min, columns.remove(0)).expect("CIE D65 table")
    })
}

/// CIE standard illuminant D65 scaled to luminance Y = 1:
/// Σ_λ D65(λ) ȳ(λ) / [`CIE_Y_INTEGRAL`] = 1 over 1 nm steps (pbrt-v4 normalises
/// its named illuminants the same way). Its linear sRGB is ≈ (1, 1, 1).
pub fn d65_illuminant() -> &'static DenselySampledSpectrum {
    static TABLE: OnceLock<DenselySampledSpectrum> = OnceLock::new();
    TABLE.get_or_init(|| {
        let relative = d65_relative();
        let luminance: f64 = (CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX)
            .map(|lambda| {
                f64::from(relative.evaluate(lambda as f32))
                    * f64::from(cie_y().evaluate(lambda as f32))
            })
            .sum();
        relative.scaled((f64::from(CIE_Y_INTEGRAL) / luminance) as f32)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_cover_their_ranges() {
        for table in [cie_x(), cie_y(), cie_z()] {
            assert_eq!(table.lambda_min(), CIE_LAMBDA_MIN);
            assert_eq!(table.lambda_max(), CIE_LAMBDA_MAX);
        }
        assert_eq!(d65_relative().lambda_min(), 300);
        assert_eq!(d65_relative().lambda_max(), 830);
        assert_eq!(d65_relative().evaluate(560.0), 100.0);
    }

    #[test]
    fn y_integral_matches_the_table() {
        let sum: f64 = cie_y().values().iter().map(|&value| f64::from(value)).sum();
        assert!(
            (sum / f64::from(CIE_Y_INTEGRAL) - 1.0).abs() < 1e-6,
            "sum {sum}"
        );
        // ȳ peaks at 1 at 555 nm by definition of the photometric scale.
        assert!((cie_y().evaluate(555.0) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn known_table_values() {
        // CIE 018:2019 values at 600 nm: 1.0622, 0.631, 0.0008.
        assert!((cie_x().evaluate(600.0) - 1.0622).abs() < 1e-4);
        assert!((cie_y().evaluate(600.0) - 0.631).abs() < 1e-4);
        assert!((cie_z().evaluate(600.0) - 0.0008).abs() < 1e-4);
        // CIE D65 at 500 nm: 109.354; at 302 nm (interpolated): 0.0341 + 0.4 (1.6643 − 0.0341).
        assert!((d65_relative().evaluate(500.0) - 109.354).abs() < 1e-3);
        assert!((d65_relative().evaluate(302.0) - (0.0341 + 0.4 * (1.6643 - 0.0341))).abs() < 1e-4);
    }

    #[test]
    fn normalised_d65_has_unit_luminance() {
        let luminance: f64 = (CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX)
            .map(|lambda| {
                f64::from(
                    d65_illuminant().evaluate(lambda as f32) * cie_y().evaluate(lambda as f32),
                )
            })
            .sum::<f64>()
            / f64::from(CIE_Y_INTEGRAL);
        assert!((luminance - 1.0).abs() < 1e-5);
    }
}

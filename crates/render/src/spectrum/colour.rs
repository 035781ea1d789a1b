//! From spectra to colours: the Monte Carlo estimate of CIE XYZ from a sampled
//! spectrum, XYZ ↔ linear sRGB, luminance, and the sRGB transfer function.

use super::cie::{CIE_Y_INTEGRAL, cie_y, cmf_tables};
use super::padded_table::PaddedTableIndexer;
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::{SPECTRUM_SAMPLE_COUNT, SampledWavelengths};

/// CIE XYZ → linear sRGB (D65 white), IEC 61966-2-1:1999 §5.2 (4 decimals).
pub const XYZ_TO_LINEAR_SRGB: [[f32; 3]; 3] = [
    [3.2406, -1.5372, -0.4986],
    [-0.9689, 1.8758, 0.0415],
    [0.0557, -0.2040, 1.0570],
];

/// Linear sRGB → CIE XYZ (D65 white), IEC 61966-2-1:1999 §5.2 (4 decimals).
/// Not the exact inverse of [`XYZ_TO_LINEAR_SRGB`] (both are rounded); the two
/// agree to about 10⁻⁴.
pub const LINEAR_SRGB_TO_XYZ: [[f32; 3]; 3] = [
    [0.4124, 0.3576, 0.1805],
    [0.2126, 0.7152, 0.0722],
    [0.0193, 0.1192, 0.9505],
];

/// Multiplies a 3-vector by a row-major 3×3 matrix.
pub fn apply_matrix(matrix: &[[f32; 3]; 3], vector: [f32; 3]) -> [f32; 3] {
    matrix.map(|row| row[0] * vector[0] + row[1] * vector[1] + row[2] * vector[2])
}

/// CIE XYZ → linear sRGB.
pub fn xyz_to_linear_srgb(xyz: [f32; 3]) -> [f32; 3] {
    apply_matrix(&XYZ_TO_LINEAR_SRGB, xyz)
}

/// Linear sRGB → CIE XYZ.
pub fn linear_srgb_to_xyz(rgb: [f32; 3]) -> [f32; 3] {
    apply_matrix(&LINEAR_SRGB_TO_XYZ, rgb)
}

/// Luminance Y of a linear sRGB colour (the middle row of
/// [`LINEAR_SRGB_TO_XYZ`]).
pub fn linear_srgb_luminance(rgb: [f32; 3]) -> f32 {
    let row = LINEAR_SRGB_TO_XYZ[1];
    row[0] * rgb[0] + row[1] * rgb[1] + row[2] * rgb[2]
}

/// [`linear_srgb_luminance`] in `f64` (Rec. 709 Y, pbrt-v4's and
/// Mitsuba's), for sums over images and the Metropolis target.
#[inline]
pub fn linear_srgb_luminance_f64(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// sRGB transfer function (IEC 61966-2-1): linear value → encoded value, for
/// writing 8-bit images. Negative inputs give 0; values above 1 follow the
/// curve (clamp afterwards if needed).
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.0 {
        0.0
    } else if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// Inverse sRGB transfer function (IEC 61966-2-1): encoded value → linear value,
/// for reading 8-bit textures. Negative inputs give 0.
pub fn srgb_decode(encoded: f32) -> f32 {
    if encoded <= 0.0 {
        0.0
    } else if encoded <= 0.040_45 {
        encoded / 12.92
    } else {
        ((encoded + 0.055) / 1.055).powf(2.4)
    }
}

/// Monte Carlo estimate of the CIE XYZ of the spectrum whose values at
/// `wavelengths` are `spectrum`:
/// X ≈ (1/N) Σᵢ S(λᵢ) x̄(λᵢ) / p(λᵢ) / [`CIE_Y_INTEGRAL`] (and likewise Y, Z).
///
/// Wavelengths with pdf 0 (terminated secondary wavelengths) contribute 0, but
/// the average is still over all N slots; see
/// [`SampledWavelengths::terminate_secondary`] for why this stays unbiased. The
/// expectation is the exact XYZ Σ_λ S(λ) x̄(λ) / CIE_Y_INTEGRAL in pbrt-v4's
/// normalisation, where the constant spectrum 1 has Y = 1.
pub fn to_xyz(spectrum: &SampledSpectrum, wavelengths: &SampledWavelengths) -> [f32; 3] {
    // One pass over the wavelengths reading one interleaved table (this runs
    // once per camera path): one index per wavelength instead of three, the
    // same sums in the same order as with the three tables.
    let weighted = spectrum.safe_div(&wavelengths.pdf());
    let table = interleaved_cmf();
    let mut sums = [0.0f32; 3];
    let entries = table
        .indexer
        .look_up_four(&table.values, wavelengths.lambdas());
    for ([x, y, z, _], &weight) in entries.into_iter().zip(weighted.values()) {
        sums[0] += x * weight;
        sums[1] += y * weight;
        sums[2] += z * weight;
    }
    // One multiplication per channel instead of two divisions.
    let scale = 1.0 / (SPECTRUM_SAMPLE_COUNT as f32 * CIE_Y_INTEGRAL);
    sums.map(|sum| sum * scale)
}

/// x̄, ȳ, z̄ (and a zero pad to 16 bytes) at every integer wavelength of the
/// CIE tables, evaluated as [`super::DenselySampledSpectrum::evaluate`] does
/// (nearest nm, 0 outside, through a [`PaddedTableIndexer`] with a zero entry
/// at each end), so [`to_xyz`] reads one entry per wavelength.
struct InterleavedCmf {
    indexer: PaddedTableIndexer,
    values: Vec<[f32; 4]>,
}

#[cfg(test)]
impl InterleavedCmf {
    /// The entry for one wavelength (the tests compare it with the three tables).
    fn evaluate(&self, lambda: f32) -> [f32; 4] {
        self.indexer.look_up(&self.values, lambda)
    }
}

fn interleaved_cmf() -> &'static InterleavedCmf {
    static TABLE: std::sync::OnceLock<InterleavedCmf> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let [x_bar, y_bar, z_bar] = cmf_tables();
        debug_assert!(
            x_bar.lambda_min() == y_bar.lambda_min() && y_bar.lambda_min() == z_bar.lambda_min()
        );
        let values: Vec<[f32; 4]> = x_bar
            .values()
            .iter()
            .zip(y_bar.values())
            .zip(z_bar.values())
            .map(|((&x, &y), &z)| [x, y, z, 0.0])
            .collect();
        // The CIE tables (360–830 nm) are part of the build and always in range.
        let indexer = PaddedTableIndexer::new(x_bar.lambda_min(), values.len())
            .expect("the CIE tables fit a padded table");
        InterleavedCmf {
            values: indexer.pad(&values),
            indexer,
        }
    })
}

/// Monte Carlo estimate of the luminance Y alone (see [`to_xyz`]).
pub fn to_luminance(spectrum: &SampledSpectrum, wavelengths: &SampledWavelengths) -> f32 {
    (cie_y().sample(wavelengths) * spectrum.safe_div(&wavelengths.pdf())).average() / CIE_Y_INTEGRAL
}

/// Monte Carlo estimate of the linear sRGB of a sampled spectrum:
/// [`xyz_to_linear_srgb`] of [`to_xyz`] (the matrix is linear, so the estimate
/// stays unbiased).
pub fn to_linear_srgb(spectrum: &SampledSpectrum, wavelengths: &SampledWavelengths) -> [f32; 3] {
    xyz_to_linear_srgb(to_xyz(spectrum, wavelengths))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrices_are_near_inverses() {
        for column in 0..3 {
            let mut unit = [0.0; 3];
            unit[column] = 1.0;
            let back = xyz_to_linear_srgb(linear_srgb_to_xyz(unit));
            for (value, expected) in back.iter().zip(unit) {
                assert!((value - expected).abs() < 5e-4, "{back:?}");
            }
        }
    }

    #[test]
    fn d65_white_maps_to_white() {
        // XYZ of D65 with Y = 1 (CIE 15:2004): (0.95047, 1, 1.08883).
        let rgb = xyz_to_linear_srgb([0.950_47, 1.0, 1.088_83]);
        for value in rgb {
            assert!((value - 1.0).abs() < 1e-3, "{rgb:?}");
        }
        assert!((linear_srgb_luminance([1.0, 1.0, 1.0]) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn transfer_function_round_trips_and_is_continuous() {
        for step in 0..=1000 {
            let linear = step as f32 / 1000.0;
            assert!((srgb_decode(srgb_encode(linear)) - linear).abs() < 1e-6);
        }
        // The two pieces meet at the break points (to the 4-decimal constants).
        let below = 12.92 * 0.003_130_8_f32;
        let above = 1.055 * 0.003_130_8_f32.powf(1.0 / 2.4) - 0.055;
        assert!((below - above).abs() < 1e-6);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.5) - 0.735_357).abs() < 1e-6);
        assert!((srgb_decode(0.5) - 0.214_041_14).abs() < 1e-6);
        assert_eq!(srgb_encode(-1.0), 0.0);
    }

    #[test]
    fn interleaved_table_matches_the_three_tables() {
        let [x_bar, y_bar, z_bar] = cmf_tables();
        let table = interleaved_cmf();
        for step in 0..2000 {
            let lambda = 300.0 + step as f32 * 0.3;
            assert_eq!(
                table.evaluate(lambda)[..3],
                [
                    x_bar.evaluate(lambda),
                    y_bar.evaluate(lambda),
                    z_bar.evaluate(lambda)
                ],
                "{lambda}"
            );
        }
        assert_eq!(table.evaluate(f32::NAN), [0.0; 4]);
    }

    #[test]
    fn terminated_wavelengths_do_not_contribute() {
        let mut wavelengths = SampledWavelengths::sample_visible(0.5);
        wavelengths.terminate_secondary();
        let only_secondaries = SampledSpectrum::new([0.0, 1.0, 1.0, 1.0]);
        assert_eq!(to_xyz(&only_secondaries, &wavelengths), [0.0; 3]);
    }
}

//! RGB → spectrum → XYZ → RGB round trip of the Jakob–Hanika sigmoid table, and
//! the time it takes to fit the table.
//!
//! The spectrum's colour is computed exactly (no Monte Carlo): the reflectance
//! times D65 summed against the CMFs over 1 nm steps, normalised by the Y of D65,
//! then the IEC 61966-2-1 XYZ → linear sRGB matrix.

use std::time::Instant;

use render::spectrum::{
    CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, DEFAULT_RGB_TABLE_RESOLUTION, RgbAlbedoSpectrum,
    RgbToSpectrumTable, cie_x, cie_y, cie_z, d65_illuminant, linear_srgb_to_xyz,
    xyz_to_linear_srgb,
};

/// Linear sRGB of a reflectance lit by D65 (Y of the white reflectance = 1).
fn reflectance_to_srgb(reflectance: impl Fn(f32) -> f32) -> [f64; 3] {
    let mut xyz = [0.0_f64; 3];
    let mut white_luminance = 0.0_f64;
    for lambda in CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX {
        let lambda = lambda as f32;
        let power = f64::from(d65_illuminant().evaluate(lambda));
        let value = f64::from(reflectance(lambda)) * power;
        xyz[0] += value * f64::from(cie_x().evaluate(lambda));
        xyz[1] += value * f64::from(cie_y().evaluate(lambda));
        xyz[2] += value * f64::from(cie_z().evaluate(lambda));
        white_luminance += power * f64::from(cie_y().evaluate(lambda));
    }
    let xyz = xyz.map(|value| (value / white_luminance) as f32);
    xyz_to_linear_srgb(xyz).map(f64::from)
}

/// Max and mean absolute component error of the round trip over a grid of
/// `steps`³ colours in [0, 1]³, and the colour with the largest error.
fn round_trip_errors(table: &RgbToSpectrumTable, steps: usize) -> (f64, f64, [f32; 3]) {
    let mut max_error = 0.0_f64;
    let mut sum_error = 0.0_f64;
    let mut worst = [0.0; 3];
    let mut count = 0;
    for r in 0..steps {
        for g in 0..steps {
            for b in 0..steps {
                let rgb = [r, g, b].map(|i| i as f32 / (steps - 1) as f32);
                let spectrum = RgbAlbedoSpectrum::with_table(table, rgb).unwrap();
                let back = reflectance_to_srgb(|lambda| spectrum.evaluate(lambda));
                let error = back
                    .iter()
                    .zip(rgb)
                    .map(|(a, b)| (a - f64::from(b)).abs())
                    .fold(0.0, f64::max);
                if error > max_error {
                    max_error = error;
                    worst = rgb;
                }
                sum_error += error;
                count += 1;
            }
        }
    }
    (max_error, sum_error / count as f64, worst)
}

/// The embedded table is exactly the fitter's output (the whole table; the
/// unit tests refit only a sample of columns), and its round trip is accurate.
#[test]
fn srgb_table_round_trip_is_accurate() {
    let start = Instant::now();
    let fitted = RgbToSpectrumTable::generate(DEFAULT_RGB_TABLE_RESOLUTION).unwrap();
    let elapsed = start.elapsed();
    println!("fitting the R = {DEFAULT_RGB_TABLE_RESOLUTION} sRGB table took {elapsed:?}");
    let table = RgbToSpectrumTable::srgb();
    assert!(
        fitted == *table,
        "the stored table differs from the fitter's output: regenerate it with \
         `cargo run --release -p render --example rgb_to_spectrum_table`"
    );
    let (max_error, mean_error, worst) = round_trip_errors(table, 17);
    println!(
        "round trip over 17³ colours: max {max_error:.2e} at {worst:?}, mean {mean_error:.2e}"
    );
    assert!(mean_error < 5e-4, "mean error {mean_error}");
    assert!(max_error < 5e-3, "max error {max_error} at {worst:?}");
}

/// Resolution 32, the renderer's table before issue 15, for comparison (run
/// with --ignored): its round trip is within 3.3·10⁻³ (mean 8.7·10⁻⁴) and
/// it fails [`illuminant_colours_keep_their_xyz`] (X, Y, Z of the
/// illuminant-normalised colours −0.12, −0.13, −0.12 %; at 64: −0.03 %).
#[test]
#[ignore]
fn resolution_32_round_trip() {
    let start = Instant::now();
    let table = RgbToSpectrumTable::generate(32).unwrap();
    println!("fitting the R = 32 sRGB table took {:?}", start.elapsed());
    let (max_error, mean_error, worst) = round_trip_errors(&table, 17);
    println!(
        "round trip over 17³ colours: max {max_error:.2e} at {worst:?}, mean {mean_error:.2e}"
    );
    let bias = illuminant_xyz_bias(&table);
    println!("illuminant-normalised colours: XYZ bias {bias:?} %");
    assert!(mean_error < 2e-3 && max_error < 2e-2);
}

/// The signed mean relative error, in per cent, of X, Y and Z of colours
/// normalised as illuminants and unbounded spectra are (rgb / (2 max rgb), so
/// the largest component is ½), upsampled and integrated again: a grid of
/// 33² chromaticities on each face max = ½ of the cube.
fn illuminant_xyz_bias(table: &RgbToSpectrumTable) -> [f64; 3] {
    let steps = 33;
    let (mut upsampled, mut exact) = ([0.0_f64; 3], [0.0_f64; 3]);
    for face in 0..3 {
        for a in 0..steps {
            for b in 0..steps {
                let mut rgb = [0.0_f32; 3];
                rgb[face] = 0.5;
                rgb[(face + 1) % 3] = 0.5 * a as f32 / (steps - 1) as f32;
                rgb[(face + 2) % 3] = 0.5 * b as f32 / (steps - 1) as f32;
                let polynomial = table.lookup(rgb);
                let back = reflectance_to_srgb(|lambda| polynomial.evaluate(lambda));
                let back = linear_srgb_to_xyz(back.map(|v| v as f32));
                let target = linear_srgb_to_xyz(rgb);
                for channel in 0..3 {
                    upsampled[channel] += f64::from(back[channel]);
                    exact[channel] += f64::from(target[channel]);
                }
            }
        }
    }
    std::array::from_fn(|channel| 100.0 * (upsampled[channel] / exact[channel] - 1.0))
}

/// Issue 15: RGB illuminants (environment maps, area lights) upsampled with
/// the table keep their X, Y and Z on average. Mitsuba 3's references use its
/// resolution-64 table; our resolution-32 one darkened `museum.exr` by
/// 0.13–0.16 %, which the z-test sees in directly visible environment pixels
/// (variance 10⁻⁴ of the value) as a one-sided error. The bound is a third
/// of that darkening.
#[test]
fn illuminant_colours_keep_their_xyz() {
    let bias = illuminant_xyz_bias(RgbToSpectrumTable::srgb());
    println!("illuminant-normalised colours: XYZ bias {bias:?} %");
    for (channel, value) in bias.iter().enumerate() {
        assert!(value.abs() < 0.05, "channel {channel}: {value} %");
    }
}

#[test]
fn grey_albedos_are_constant() {
    for value in [0.0_f32, 0.18, 0.5, 1.0] {
        let spectrum = RgbAlbedoSpectrum::new([value; 3]).unwrap();
        for lambda in (360..=830).step_by(10) {
            assert!((spectrum.evaluate(lambda as f32) - value).abs() < 1e-6);
        }
        let back = reflectance_to_srgb(|lambda| spectrum.evaluate(lambda));
        for component in back {
            assert!(
                (component - f64::from(value)).abs() < 1e-3,
                "{value}: {back:?}"
            );
        }
    }
}

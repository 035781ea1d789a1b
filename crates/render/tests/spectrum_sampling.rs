//! Statistical tests of hero-wavelength sampling and of the spectral Monte Carlo
//! colour estimate.
//!
//! - chi-square goodness of fit of `sample_visible` (each of the four
//!   wavelengths) and `sample_uniform` against their densities;
//! - the expectation of `to_xyz` for spectra with known XYZ (constant 1, D65,
//!   RGB illuminant (1, 1, 1), a blackbody) with and without terminated
//!   secondary wavelengths. Tolerances are 5 standard errors estimated from the
//!   sample variance (a false alarm probability below 10⁻⁶ per check).

use qmc::random::SeekablePcg;
use render::spectrum::{
    BlackbodyNormalisation, BlackbodySpectrum, CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, CIE_Y_INTEGRAL,
    ConstantSpectrum, RgbAlbedoSpectrum, RgbIlluminantSpectrum, SPECTRUM_SAMPLE_COUNT,
    SampledWavelengths, Spectrum, VISIBLE_LAMBDA_MAX, VISIBLE_LAMBDA_MIN, cie_x, cie_y, cie_z,
    d65_illuminant, to_xyz, visible_wavelength_pdf, xyz_to_linear_srgb,
};
use render::statistics::chi_square_test;

// ---------------------------------------------------------------------------
// Chi-square goodness of fit.

/// Pearson's chi-square test of `samples` in [`min`, `max`] against the density
/// `pdf`, with `bins` equal bins whose expected counts come from Simpson
/// integration of the pdf (see [`chi_square_test`] for the merging of bins that
/// expect few samples). Returns the p-value.
fn wavelength_fit_p_value(
    samples: &[f32],
    min: f64,
    max: f64,
    bins: usize,
    pdf: impl Fn(f64) -> f64,
) -> f64 {
    let width = (max - min) / bins as f64;
    let mut observed = vec![0u64; bins];
    for &sample in samples {
        let bin = (((f64::from(sample) - min) / width) as usize).min(bins - 1);
        observed[bin] += 1;
    }
    let expected: Vec<f64> = (0..bins)
        .map(|bin| {
            let a = min + bin as f64 * width;
            let steps = 64;
            let h = width / steps as f64;
            let mut sum = 0.0;
            for i in 0..=steps {
                let weight = if i == 0 || i == steps {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                sum += weight * pdf(a + i as f64 * h);
            }
            sum * h / 3.0 * samples.len() as f64
        })
        .collect();
    chi_square_test(&observed, &expected).p_value
}

const P_VALUE_THRESHOLD: f64 = 1e-4;

#[test]
fn chi_square_rejects_a_wrong_density() {
    // Uniform wavelengths are not distributed like the visible density.
    let mut random = SeekablePcg::new(5, 9);
    let samples: Vec<f32> = (0..20_000)
        .map(|_| VISIBLE_LAMBDA_MIN + random.next_f32() * (VISIBLE_LAMBDA_MAX - VISIBLE_LAMBDA_MIN))
        .collect();
    let p_value = wavelength_fit_p_value(&samples, 360.0, 830.0, 94, |lambda| {
        f64::from(visible_wavelength_pdf(lambda as f32))
    });
    assert!(p_value < P_VALUE_THRESHOLD, "p = {p_value}");
}

#[test]
fn visible_wavelengths_follow_their_pdf() {
    let count = 200_000;
    let mut random = SeekablePcg::new(7, 1);
    let mut per_index: Vec<Vec<f32>> = (0..SPECTRUM_SAMPLE_COUNT)
        .map(|_| Vec::with_capacity(count))
        .collect();
    for _ in 0..count {
        let wavelengths = SampledWavelengths::sample_visible(random.next_f32());
        for (index, samples) in per_index.iter_mut().enumerate() {
            samples.push(wavelengths.lambda(index));
        }
    }
    for (index, samples) in per_index.iter().enumerate() {
        let p_value = wavelength_fit_p_value(
            samples,
            f64::from(VISIBLE_LAMBDA_MIN),
            f64::from(VISIBLE_LAMBDA_MAX),
            94,
            |lambda| f64::from(visible_wavelength_pdf(lambda as f32)),
        );
        assert!(
            p_value > P_VALUE_THRESHOLD,
            "wavelength {index}: p = {p_value}"
        );
    }
}

#[test]
fn uniform_wavelengths_follow_their_pdf() {
    let count = 100_000;
    let mut random = SeekablePcg::new(11, 3);
    let mut samples = Vec::with_capacity(count);
    for _ in 0..count {
        let wavelengths =
            SampledWavelengths::sample_uniform(random.next_f32(), 400.0, 700.0).unwrap();
        samples.push(wavelengths.hero());
    }
    let p_value = wavelength_fit_p_value(&samples, 400.0, 700.0, 60, |_| 1.0 / 300.0);
    assert!(p_value > P_VALUE_THRESHOLD, "p = {p_value}");
}

// ---------------------------------------------------------------------------
// Monte Carlo colour estimates.

/// Exact XYZ of a spectrum in the renderer's normalisation: the 1 nm sum.
fn exact_xyz(spectrum: &Spectrum) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for lambda in CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX {
        let lambda = lambda as f32;
        let value = f64::from(spectrum.evaluate(lambda));
        xyz[0] += value * f64::from(cie_x().evaluate(lambda));
        xyz[1] += value * f64::from(cie_y().evaluate(lambda));
        xyz[2] += value * f64::from(cie_z().evaluate(lambda));
    }
    xyz.map(|value| value / f64::from(CIE_Y_INTEGRAL))
}

/// Mean and standard error of `to_xyz` over `count` independent wavelength
/// samples (optionally with secondary wavelengths terminated).
fn estimate_xyz(
    spectrum: &Spectrum,
    count: usize,
    terminate: bool,
    seed: u64,
) -> ([f64; 3], [f64; 3]) {
    let mut random = SeekablePcg::new(seed, 5);
    let mut sum = [0.0_f64; 3];
    let mut sum_squares = [0.0_f64; 3];
    for _ in 0..count {
        let mut wavelengths = SampledWavelengths::sample_visible(random.next_f32());
        if terminate {
            wavelengths.terminate_secondary();
        }
        let xyz = to_xyz(&spectrum.sample(&wavelengths), &wavelengths);
        for channel in 0..3 {
            let value = f64::from(xyz[channel]);
            sum[channel] += value;
            sum_squares[channel] += value * value;
        }
    }
    let n = count as f64;
    let mean = sum.map(|value| value / n);
    let standard_error: [f64; 3] = std::array::from_fn(|channel| {
        ((sum_squares[channel] / n - mean[channel].powi(2)).max(0.0) / (n - 1.0)).sqrt()
    });
    (mean, standard_error)
}

/// Asserts that the Monte Carlo mean is within 5 standard errors (plus the f32
/// accumulation slack 1e-5) of the exact XYZ.
fn assert_estimate_matches(spectrum: &Spectrum, terminate: bool, label: &str) -> [f64; 3] {
    let exact = exact_xyz(spectrum);
    let (mean, standard_error) = estimate_xyz(spectrum, 200_000, terminate, 17);
    for channel in 0..3 {
        let tolerance = 5.0 * standard_error[channel] + 1e-5 * exact[channel].abs();
        assert!(
            (mean[channel] - exact[channel]).abs() <= tolerance,
            "{label} channel {channel}: mean {} vs exact {} (5σ = {})",
            mean[channel],
            exact[channel],
            5.0 * standard_error[channel]
        );
    }
    exact
}

#[test]
fn constant_one_has_unit_luminance() {
    let one: Spectrum = ConstantSpectrum::new(1.0).unwrap().into();
    let exact = assert_estimate_matches(&one, false, "constant 1");
    // Σ ȳ / CIE_Y_INTEGRAL = 1 (the data and the constant agree).
    assert!((exact[1] - 1.0).abs() < 1e-6, "exact Y {}", exact[1]);
    println!("constant 1: exact XYZ {exact:?}");
}

#[test]
fn d65_is_srgb_white() {
    let d65: Spectrum = Spectrum::DenselySampled(d65_illuminant().clone());
    let exact = assert_estimate_matches(&d65, false, "D65");
    let rgb = xyz_to_linear_srgb(exact.map(|value| value as f32));
    println!("D65 (Y = 1): XYZ {exact:?}, linear sRGB {rgb:?}");
    // Y = 1 by construction; the residual is the 4-decimal rounding of the
    // IEC 61966-2-1 matrix and the white point of CIE 1931 tables.
    assert!((exact[1] - 1.0).abs() < 1e-5);
    for component in rgb {
        assert!((component - 1.0).abs() < 2e-3, "{rgb:?}");
    }
}

#[test]
fn rgb_illuminant_white_is_srgb_white() {
    let white: Spectrum = RgbIlluminantSpectrum::new([1.0; 3]).unwrap().into();
    let exact = assert_estimate_matches(&white, false, "RGB illuminant (1, 1, 1)");
    let rgb = xyz_to_linear_srgb(exact.map(|value| value as f32));
    for component in rgb {
        assert!((component - 1.0).abs() < 2e-3, "{rgb:?}");
    }
    // A coloured illuminant reproduces its RGB too (the sigmoid fit is made
    // for reflectances under D65, which is what RGB × D65 is).
    let orange: Spectrum = RgbIlluminantSpectrum::new([4.0, 2.0, 0.5]).unwrap().into();
    let rgb = xyz_to_linear_srgb(exact_xyz(&orange).map(|value| value as f32));
    for (component, expected) in rgb.iter().zip([4.0, 2.0, 0.5]) {
        assert!((component - expected).abs() < 0.02 * 4.0, "{rgb:?}");
    }
}

#[test]
fn terminated_secondary_wavelengths_keep_the_expectation() {
    let spectra: Vec<(Spectrum, &str)> = vec![
        (
            BlackbodySpectrum::new(3000.0, BlackbodyNormalisation::PeakOne)
                .unwrap()
                .into(),
            "blackbody 3000 K",
        ),
        (
            RgbAlbedoSpectrum::new([0.1, 0.8, 0.3]).unwrap().into(),
            "green albedo",
        ),
    ];
    for (spectrum, label) in &spectra {
        assert_estimate_matches(spectrum, false, label);
        assert_estimate_matches(spectrum, true, label);
        // Termination trades stratification for a single wavelength: the
        // variance can only grow.
        let (_, full) = estimate_xyz(spectrum, 50_000, false, 23);
        let (_, terminated) = estimate_xyz(spectrum, 50_000, true, 23);
        assert!(
            terminated[1] > full[1],
            "{label}: {terminated:?} vs {full:?}"
        );
    }
}

#[test]
fn blackbody_colour_is_warm() {
    // A 3000 K blackbody is orange: red > green > blue in linear sRGB.
    let spectrum: Spectrum = BlackbodySpectrum::new(3000.0, BlackbodyNormalisation::PeakOne)
        .unwrap()
        .into();
    let rgb = xyz_to_linear_srgb(exact_xyz(&spectrum).map(|value| value as f32));
    assert!(rgb[0] > rgb[1] && rgb[1] > rgb[2], "{rgb:?}");
}

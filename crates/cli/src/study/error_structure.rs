//! How much structure an error image has, beyond white noise: the measures
//! of `lqmc study lattice-structure`, computed from a render and a
//! reference.
//!
//! - The **error image** e is the luminance difference render − reference
//!   (Y = 0.2126 R + 0.7152 G + 0.0722 B, linear Rec. 709), its mean
//!   subtracted; pixels where either image is not finite count as 0.
//! - Its **power spectrum** is the periodogram P(k) = |Σ_x e(x)
//!   exp(−2πi k·x/size)|² / (W·H), by a two-dimensional FFT: white noise
//!   of variance σ² has E[P(k)] = σ² at every frequency.
//! - The **radial average** is the mean of P over rings of width 1/min(W, H)
//!   cycles per pixel around the origin (ring r holds the frequencies whose
//!   length, in cycles per pixel, rounds to r/min(W, H)), up to 0.5 cycles
//!   per pixel.
//! - The **peak ratio** is the largest P(k) among the off-axis frequencies
//!   (neither component zero; the axes carry the leakage of the image's
//!   non-periodic borders and of the tile grid) divided by the median of P
//!   over its ring, over the rings of at least [`MIN_RING_FREQUENCIES`]
//!   frequencies. A regular pattern that repeats across the image (the same
//!   lattice projection splatted again and again) makes a peak; white noise
//!   gives the largest of many exponential variables over their median
//!   (about 16 for a 320×240 image; [`white_noise_structure`] measures it).
//!   Averaging the spectra of several renders ([`mean_spectrum`]) before
//!   taking the ratio lowers white noise's peaks and keeps a pattern that
//!   every render repeats at the same frequencies.
//! - The **autocorrelation sum** is Σ_d ρ(d) over the lags d = (dx, dy)
//!   with 0 < max(|dx|, |dy|) ≤ L, ρ(d) = Σ_x e(x) e(x + d) / Σ_x e(x)²
//!   over the pixel pairs inside the image: about 0 for white noise,
//!   positive where the error comes in blobs wider than a pixel (a splat
//!   filter, an exploration's members landing near each other).

use render::image::Image;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

/// Rings with fewer frequencies than this have no reliable median and are
/// left out of the peak ratio.
pub const MIN_RING_FREQUENCIES: usize = 32;

/// The luminance weights of linear Rec. 709 / sRGB primaries.
const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// What a power spectrum shows: its radial average and its largest
/// off-axis peak.
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumStructure {
    /// The mean of P over each ring r = 0, 1, …: ring r is at r / min(W, H)
    /// cycles per pixel (ring 0 is the mean, removed: 0).
    pub radial_power: Vec<f64>,
    /// The largest off-axis P(k) over the median of its ring.
    pub peak_ratio: f64,
    /// The peak's frequency (x, y) in cycles per pixel, each in [−½, ½).
    pub peak_frequency: [f64; 2],
}

/// The structure measures of one error image.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorStructure {
    /// The power spectrum P, row-major by frequency index (k_x, k_y).
    pub spectrum: Vec<f64>,
    /// Its radial average and peak.
    pub structure: SpectrumStructure,
    /// Σ ρ(d) over 0 < max(|dx|, |dy|) ≤ the largest lag.
    pub autocorrelation_sum: f64,
}

/// The luminance error render − reference, mean subtracted, row-major.
/// Panics if the sizes differ.
pub fn luminance_error(render: &Image, reference: &Image) -> Vec<f64> {
    assert_eq!(
        (render.width(), render.height()),
        (reference.width(), reference.height()),
        "a render and its reference have one size"
    );
    let luminance = |pixel: &[f32; 3]| {
        pixel
            .iter()
            .zip(LUMINANCE)
            .map(|(value, weight)| f64::from(*value) * weight)
            .sum::<f64>()
    };
    let mut error: Vec<f64> = render
        .pixels()
        .iter()
        .zip(reference.pixels())
        .map(|(a, b)| {
            let difference = luminance(a) - luminance(b);
            if difference.is_finite() {
                difference
            } else {
                0.0
            }
        })
        .collect();
    let mean = error.iter().sum::<f64>() / error.len().max(1) as f64;
    for value in &mut error {
        *value -= mean;
    }
    error
}

/// The periodogram |DFT(values)|² / (width·height) of a `width`×`height`
/// row-major image, row-major by frequency index (k_x, k_y) in
/// 0..width × 0..height.
pub fn power_spectrum(values: &[f64], width: usize, height: usize) -> Vec<f64> {
    assert_eq!(values.len(), width * height);
    let mut planner = FftPlanner::<f64>::new();
    let mut data: Vec<Complex<f64>> = values.iter().map(|&v| Complex::new(v, 0.0)).collect();
    // Rows, then columns (gathered into a buffer of their own).
    let rows = planner.plan_fft_forward(width);
    for row in data.chunks_exact_mut(width) {
        rows.process(row);
    }
    let columns = planner.plan_fft_forward(height);
    let mut column = vec![Complex::new(0.0, 0.0); height];
    for x in 0..width {
        for (y, value) in column.iter_mut().enumerate() {
            *value = data[y * width + x];
        }
        columns.process(&mut column);
        for (y, value) in column.iter().enumerate() {
            data[y * width + x] = *value;
        }
    }
    let scale = 1.0 / (width * height) as f64;
    data.iter().map(|value| value.norm_sqr() * scale).collect()
}

/// Frequency index `k` of a DFT of length `n` as a signed index in
/// [−n/2, n/2).
fn signed_frequency(k: usize, n: usize) -> i64 {
    if 2 * k >= n {
        k as i64 - n as i64
    } else {
        k as i64
    }
}

/// The ring of frequency (k_x, k_y) (signed indices) of a `width`×`height`
/// spectrum: its length in cycles per pixel times min(W, H), rounded.
fn ring_of(kx: i64, ky: i64, width: usize, height: usize) -> usize {
    let fx = kx as f64 / width as f64;
    let fy = ky as f64 / height as f64;
    ((fx * fx + fy * fy).sqrt() * width.min(height) as f64).round() as usize
}

/// The number of rings up to 0.5 cycles per pixel.
pub fn ring_count(width: usize, height: usize) -> usize {
    width.min(height) / 2 + 1
}

/// The frequency of ring `ring` in cycles per pixel.
pub fn ring_frequency(ring: usize, width: usize, height: usize) -> f64 {
    ring as f64 / width.min(height) as f64
}

/// The median of `values` (which it sorts), NaN for none.
fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    if values.len() % 2 == 1 {
        values[middle]
    } else {
        0.5 * (values[middle - 1] + values[middle])
    }
}

/// The measures of the error image `error` (`width`×`height`, row-major,
/// mean already removed), the autocorrelation summed up to `max_lag`.
pub fn error_structure(
    error: &[f64],
    width: usize,
    height: usize,
    max_lag: usize,
) -> ErrorStructure {
    let spectrum = power_spectrum(error, width, height);
    ErrorStructure {
        structure: spectrum_structure(&spectrum, width, height),
        spectrum,
        autocorrelation_sum: autocorrelation_sum(error, width, height, max_lag),
    }
}

/// The radial average and the largest off-axis peak of the `width`×`height`
/// power spectrum `spectrum` (see the module's documentation).
pub fn spectrum_structure(spectrum: &[f64], width: usize, height: usize) -> SpectrumStructure {
    let rings = ring_count(width, height);
    let mut ring_values: Vec<Vec<f64>> = vec![Vec::new(); rings];
    // (power, ring, kx, ky) of the off-axis frequencies.
    let mut off_axis = Vec::new();
    for ky in 0..height {
        let signed_y = signed_frequency(ky, height);
        for kx in 0..width {
            let signed_x = signed_frequency(kx, width);
            let ring = ring_of(signed_x, signed_y, width, height);
            if ring >= rings {
                continue;
            }
            let power = spectrum[ky * width + kx];
            ring_values[ring].push(power);
            if signed_x != 0 && signed_y != 0 {
                off_axis.push((power, ring, signed_x, signed_y));
            }
        }
    }
    let radial_power: Vec<f64> = ring_values
        .iter()
        .map(|values| values.iter().sum::<f64>() / values.len().max(1) as f64)
        .collect();
    let counts: Vec<usize> = ring_values.iter().map(Vec::len).collect();
    let medians: Vec<f64> = ring_values
        .iter_mut()
        .map(|values| median(values))
        .collect();
    let mut peak_ratio = 0.0;
    let mut peak_frequency = [0.0, 0.0];
    for (power, ring, kx, ky) in off_axis {
        let median = medians[ring];
        if ring == 0 || counts[ring] < MIN_RING_FREQUENCIES || median.is_nan() || median <= 0.0 {
            continue;
        }
        let ratio = power / median;
        if ratio > peak_ratio {
            peak_ratio = ratio;
            peak_frequency = [kx as f64 / width as f64, ky as f64 / height as f64];
        }
    }
    SpectrumStructure {
        radial_power,
        peak_ratio,
        peak_frequency,
    }
}

/// The element-wise mean of equally long `spectra`.
pub fn mean_spectrum<'a>(spectra: impl IntoIterator<Item = &'a [f64]>) -> Vec<f64> {
    let mut sum: Vec<f64> = Vec::new();
    let mut count = 0usize;
    for spectrum in spectra {
        if sum.is_empty() {
            sum = vec![0.0; spectrum.len()];
        }
        for (total, value) in sum.iter_mut().zip(spectrum) {
            *total += value;
        }
        count += 1;
    }
    for total in &mut sum {
        *total /= count.max(1) as f64;
    }
    sum
}

/// Σ ρ(d) over the lags 0 < max(|dx|, |dy|) ≤ `max_lag` (see the module's
/// documentation); 0 for an image of zeros.
pub fn autocorrelation_sum(error: &[f64], width: usize, height: usize, max_lag: usize) -> f64 {
    let energy: f64 = error.iter().map(|value| value * value).sum();
    if energy <= 0.0 {
        return 0.0;
    }
    let lag = max_lag as i64;
    let (w, h) = (width as i64, height as i64);
    let mut sum = 0.0;
    for dy in -lag..=lag {
        for dx in -lag..=lag {
            if dx == 0 && dy == 0 {
                continue;
            }
            let mut products = 0.0;
            for y in 0.max(-dy)..h.min(h - dy) {
                for x in 0.max(-dx)..w.min(w - dx) {
                    products +=
                        error[(y * w + x) as usize] * error[((y + dy) * w + x + dx) as usize];
                }
            }
            sum += products / energy;
        }
    }
    sum
}

/// The measures of Gaussian white noise of the given size, one image per
/// stream `stream` (a fixed pseudo-random stream each): what an error image
/// without any structure gives.
pub fn white_noise_structure(
    width: usize,
    height: usize,
    max_lag: usize,
    stream: u64,
) -> ErrorStructure {
    let mut random = qmc::random::SeekablePcg::new(0x0057_6869_7465, stream);
    let mut noise: Vec<f64> = (0..width * height)
        .map(|_| {
            // Box–Muller.
            let u = 1.0 - random.next_f64();
            let v = random.next_f64();
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        })
        .collect();
    let mean = noise.iter().sum::<f64>() / noise.len().max(1) as f64;
    for value in &mut noise {
        *value -= mean;
    }
    error_structure(&noise, width, height, max_lag)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The FFT's periodogram is the direct DFT's.
    #[test]
    fn the_power_spectrum_is_the_direct_dfts() {
        let (width, height) = (6, 5);
        let values: Vec<f64> = (0..width * height)
            .map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.3)
            .collect();
        let spectrum = power_spectrum(&values, width, height);
        for ky in 0..height {
            for kx in 0..width {
                let mut sum = Complex::new(0.0, 0.0);
                for y in 0..height {
                    for x in 0..width {
                        let phase = -std::f64::consts::TAU
                            * (kx as f64 * x as f64 / width as f64
                                + ky as f64 * y as f64 / height as f64);
                        sum += Complex::from_polar(values[y * width + x], phase);
                    }
                }
                let expected = sum.norm_sqr() / (width * height) as f64;
                let found = spectrum[ky * width + kx];
                assert!((found - expected).abs() < 1e-9, "({kx}, {ky})");
            }
        }
    }

    /// Parseval: the spectrum's mean is the values' mean square.
    #[test]
    fn the_spectrum_keeps_the_energy() {
        let (width, height) = (16, 12);
        let values: Vec<f64> = (0..width * height)
            .map(|i| ((i * 7919 % 101) as f64).sin())
            .collect();
        let spectrum = power_spectrum(&values, width, height);
        let mean_square = values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64;
        let mean_power = spectrum.iter().sum::<f64>() / spectrum.len() as f64;
        assert!((mean_square - mean_power).abs() < 1e-12);
    }

    /// White noise: a flat spectrum at its variance, a peak ratio of a few
    /// medians' worth, an autocorrelation sum near 0. A diagonal cosine:
    /// one off-axis peak at its frequency, far above the ring's median.
    #[test]
    fn white_noise_is_flat_and_a_diagonal_wave_peaks() {
        let (width, height) = (64, 48);
        let white = white_noise_structure(width, height, 2, 0);
        let rings = ring_count(width, height);
        assert_eq!(white.structure.radial_power.len(), rings);
        let mean_power = white.structure.radial_power[4..].iter().sum::<f64>() / (rings - 4) as f64;
        assert!((mean_power - 1.0).abs() < 0.1, "{mean_power}");
        let peak = white.structure.peak_ratio;
        assert!((5.0..30.0).contains(&peak), "{peak}");
        assert!(white.autocorrelation_sum.abs() < 0.2, "{white:?}");
        // Averaging spectra lowers white noise's peaks.
        let streams: Vec<ErrorStructure> = (1..5)
            .map(|stream| white_noise_structure(width, height, 2, stream))
            .collect();
        let mean = mean_spectrum(streams.iter().map(|white| white.spectrum.as_slice()));
        let averaged = spectrum_structure(&mean, width, height).peak_ratio;
        assert!(
            averaged < peak && averaged > 1.0,
            "{averaged} against {peak}"
        );

        let (fx, fy) = (8.0 / width as f64, 6.0 / height as f64);
        let mut wave: Vec<f64> = (0..width * height)
            .map(|i| {
                let (x, y) = ((i % width) as f64, (i / width) as f64);
                (std::f64::consts::TAU * (fx * x + fy * y)).cos()
            })
            .collect();
        // A little noise, so that the ring's median is not zero.
        let mut random = qmc::random::SeekablePcg::new(1, 0);
        for value in &mut wave {
            *value += 0.1 * (random.next_f64() - 0.5);
        }
        let structure = error_structure(&wave, width, height, 1);
        assert!(structure.structure.peak_ratio > 1000.0, "{structure:?}");
        let [px, py] = structure.structure.peak_frequency;
        assert!(
            ((px - fx).abs() < 1e-12 && (py - fy).abs() < 1e-12)
                || ((px + fx).abs() < 1e-12 && (py + fy).abs() < 1e-12),
            "{structure:?}"
        );
        // Neighbours along the wave's crests are alike.
        assert!(structure.autocorrelation_sum > 0.5, "{structure:?}");
    }

    /// The autocorrelation of a constant-per-2×2-block image at lag 1 and
    /// the luminance error's mean removal.
    #[test]
    fn blocks_correlate_and_errors_lose_their_mean() {
        let (width, height) = (8, 8);
        let blocks: Vec<f64> = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width / 2, i / width / 2);
                if (x * 3 + y * 5) % 2 == 0 { 1.0 } else { -1.0 }
            })
            .collect();
        assert!(autocorrelation_sum(&blocks, width, height, 1) > 0.5);
        assert_eq!(autocorrelation_sum(&[0.0; 4], 2, 2, 1), 0.0);

        let render = Image::from_pixels(2, 1, vec![[1.0, 1.0, 1.0], [3.0, 3.0, f32::NAN]]).unwrap();
        let reference = Image::from_pixels(2, 1, vec![[0.0; 3], [0.0; 3]]).unwrap();
        let error = luminance_error(&render, &reference);
        // 1 and 0 (not finite), mean 0.5 removed.
        assert!((error[0] - 0.5).abs() < 1e-12 && (error[1] + 0.5).abs() < 1e-12);
    }
}

//! What the film accumulates per pixel, in `f64`: the filter-weighted RGB
//! sum and weight sum (the pixel value is their ratio), the sample count,
//! and Welford's running mean and sum of squared deviations of each
//! channel's per-sample value (for the variance of the pixel mean).

/// The accumulated camera samples of one pixel.
///
/// The variance statistics are those of the *unweighted* per-sample RGB
/// values `L_i`: with `n` samples, `sample_variance = M2 / (n − 1)` (the
/// unbiased sample variance, Welford 1962) and
/// `variance_of_mean = sample_variance / n`, the estimated variance of the
/// mean `Σ L_i / n`. With the film's exactly sampled filters every weight
/// is 1, so that mean *is* the pixel value and this is the estimated
/// variance of the pixel value; with unequal weights it would only
/// approximate it. Splats are not included.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PixelStatistics {
    weighted_sum: [f64; 3],
    weight_sum: f64,
    sample_count: u64,
    mean: [f64; 3],
    squared_deviation_sum: [f64; 3],
}

impl PixelStatistics {
    /// Adds one sample of value `rgb` and filter weight `weight` (the
    /// caller has checked that both are finite and the weight not negative).
    pub(crate) fn add(&mut self, rgb: [f64; 3], weight: f64) {
        self.sample_count += 1;
        self.weight_sum += weight;
        // One division per sample rather than one per channel.
        let inverse_count = 1.0 / self.sample_count as f64;
        for (channel, value) in rgb.into_iter().enumerate() {
            self.weighted_sum[channel] += weight * value;
            // Welford: update the mean, then M2 with old and new deviations.
            let deviation = value - self.mean[channel];
            self.mean[channel] += deviation * inverse_count;
            self.squared_deviation_sum[channel] += deviation * (value - self.mean[channel]);
        }
    }

    /// Adds the samples summarised by `other`, combining the means and
    /// squared-deviation sums by the pairwise formula of Chan, Golub and
    /// LeVeque (1979): `M2 = M2a + M2b + δ² na nb / n`. Deterministic: the
    /// result depends only on the two operands and their order.
    pub(crate) fn merge(&mut self, other: &Self) {
        if other.sample_count == 0 && other.weight_sum == 0.0 {
            return;
        }
        if self.sample_count == 0 && self.weight_sum == 0.0 {
            *self = *other;
            return;
        }
        let (count_a, count_b) = (self.sample_count as f64, other.sample_count as f64);
        let total = count_a + count_b;
        for channel in 0..3 {
            self.weighted_sum[channel] += other.weighted_sum[channel];
            let delta = other.mean[channel] - self.mean[channel];
            if total > 0.0 {
                self.mean[channel] += delta * count_b / total;
                self.squared_deviation_sum[channel] += other.squared_deviation_sum[channel]
                    + delta * delta * count_a * count_b / total;
            }
        }
        self.weight_sum += other.weight_sum;
        self.sample_count += other.sample_count;
    }

    /// `Σ wᵢ Lᵢ` per channel.
    pub fn weighted_sum(&self) -> [f64; 3] {
        self.weighted_sum
    }

    /// `Σ wᵢ`.
    pub fn weight_sum(&self) -> f64 {
        self.weight_sum
    }

    /// Number of accepted samples.
    pub fn sample_count(&self) -> u64 {
        self.sample_count
    }

    /// The pixel value `Σ wᵢ Lᵢ / Σ wᵢ`, or black when no weight was added.
    pub fn weighted_mean(&self) -> [f64; 3] {
        if self.weight_sum > 0.0 {
            self.weighted_sum.map(|sum| sum / self.weight_sum)
        } else {
            [0.0; 3]
        }
    }

    /// The unweighted mean `Σ Lᵢ / n` (black without samples).
    pub fn sample_mean(&self) -> [f64; 3] {
        self.mean
    }

    /// The unbiased sample variance `M2 / (n − 1)` per channel; zero with
    /// fewer than two samples.
    pub fn sample_variance(&self) -> [f64; 3] {
        if self.sample_count < 2 {
            return [0.0; 3];
        }
        let denominator = (self.sample_count - 1) as f64;
        self.squared_deviation_sum.map(|sum| sum / denominator)
    }

    /// The estimated variance of the pixel mean, `sample_variance / n`;
    /// zero with fewer than two samples.
    pub fn variance_of_mean(&self) -> [f64; 3] {
        let count = self.sample_count.max(1) as f64;
        self.sample_variance().map(|variance| variance / count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welford_matches_two_pass_and_merge_matches_sequential() {
        let values: Vec<[f64; 3]> = (0..101)
            .map(|index| {
                let t = index as f64;
                [t.sin() * 3.0 + 1e6, (t * 0.37).cos(), t * t * 1e-3]
            })
            .collect();
        let mut sequential = PixelStatistics::default();
        for value in &values {
            sequential.add(*value, 1.0);
        }
        let n = values.len() as f64;
        for channel in 0..3 {
            let mean = values.iter().map(|value| value[channel]).sum::<f64>() / n;
            let variance = values
                .iter()
                .map(|value| (value[channel] - mean).powi(2))
                .sum::<f64>()
                / (n - 1.0);
            let got = sequential.sample_variance()[channel];
            assert!(
                (got - variance).abs() <= 1e-9 * variance,
                "{got} vs {variance}"
            );
            assert!(
                (sequential.sample_mean()[channel] - mean).abs() <= 1e-12 * mean.abs().max(1.0)
            );
        }

        let mut merged = PixelStatistics::default();
        for chunk in values.chunks(17) {
            let mut part = PixelStatistics::default();
            for value in chunk {
                part.add(*value, 1.0);
            }
            merged.merge(&part);
        }
        assert_eq!(merged.sample_count(), sequential.sample_count());
        for channel in 0..3 {
            let (a, b) = (
                merged.sample_variance()[channel],
                sequential.sample_variance()[channel],
            );
            assert!((a - b).abs() <= 1e-9 * b, "{a} vs {b}");
        }
    }

    #[test]
    fn fewer_than_two_samples_have_zero_variance() {
        let mut pixel = PixelStatistics::default();
        assert_eq!(pixel.variance_of_mean(), [0.0; 3]);
        assert_eq!(pixel.weighted_mean(), [0.0; 3]);
        pixel.add([1.0, 2.0, 3.0], 0.5);
        assert_eq!(pixel.variance_of_mean(), [0.0; 3]);
        assert_eq!(pixel.weighted_mean(), [1.0, 2.0, 3.0]);
    }
}

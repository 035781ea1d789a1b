//! Choosing a light for next-event estimation in proportion to its power
//! (pbrt-v4's default `PowerLightSampler`).

/// A discrete distribution over the scene's lights.
#[derive(Debug, Clone)]
pub struct LightSampler {
    /// Cumulative probabilities; `cdf[i + 1] - cdf[i]` is light i's.
    cdf: Vec<f32>,
}

impl LightSampler {
    /// The distribution proportional to `powers` (uniform if they are all 0).
    pub fn new(powers: &[f32]) -> Self {
        let total: f64 = powers.iter().map(|&p| p.max(0.0) as f64).sum();
        let mut cdf = Vec::with_capacity(powers.len() + 1);
        cdf.push(0.0);
        let mut running = 0.0f64;
        for &power in powers {
            running += if total > 0.0 {
                power.max(0.0) as f64 / total
            } else {
                1.0 / powers.len() as f64
            };
            cdf.push(running as f32);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Self { cdf }
    }

    /// The number of lights.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// True when there are no lights.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Chooses a light with `u`; returns its index, its probability and `u`
    /// remapped to a fresh uniform number in `[0, 1)` (so one dimension can
    /// also choose, e.g., a triangle of the light).
    pub fn sample(&self, u: f32) -> Option<(usize, f32, f32)> {
        if self.is_empty() {
            return None;
        }
        let index = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(self.len() - 1);
        let (low, high) = (self.cdf[index], self.cdf[index + 1]);
        let probability = high - low;
        if probability <= 0.0 {
            return None;
        }
        let remapped = ((u - low) / probability).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
        Some((index, probability, remapped))
    }

    /// The probability of choosing light `index`.
    pub fn probability(&self, index: usize) -> f32 {
        self.cdf[index + 1] - self.cdf[index]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chooses_in_proportion_to_power() {
        let sampler = LightSampler::new(&[1.0, 3.0, 0.0]);
        assert_eq!(sampler.len(), 3);
        assert!((sampler.probability(0) - 0.25).abs() < 1e-6);
        assert!((sampler.probability(1) - 0.75).abs() < 1e-6);
        assert_eq!(sampler.probability(2), 0.0);
        let mut counts = [0usize; 3];
        let n = 10_000;
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            let (index, probability, remapped) = sampler.sample(u).unwrap();
            assert!((0.0..1.0).contains(&remapped));
            assert_eq!(probability, sampler.probability(index));
            counts[index] += 1;
        }
        assert_eq!(counts, [2500, 7500, 0]);
    }

    #[test]
    fn no_lights_no_sample() {
        assert!(LightSampler::new(&[]).sample(0.3).is_none());
        let uniform = LightSampler::new(&[0.0, 0.0]);
        assert!((uniform.probability(1) - 0.5).abs() < 1e-6);
    }
}

//! Choosing a light for next-event estimation in proportion to its power
//! (pbrt-v4's `PowerLightSampler`), with infinite lights given a fixed share
//! as pbrt-v4's default `BVHLightSampler` gives them (see
//! [`LightSampler::with_infinite_share`]).

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

    /// Infinite lights (flagged in `is_infinite`) get probability
    /// 1 / (n + 1) each for n infinite lights, and the finite lights share the
    /// remaining 1 / (n + 1) in proportion to `powers` (all of it goes to the
    /// infinite lights when there are no finite ones with power, and the
    /// finite lights share everything when there are no infinite ones).
    ///
    /// pbrt-v4's `BVHLightSampler` (its default) samples infinite lights
    /// with this probability, because an infinite light's "power" (what
    /// crosses the scene's bounding sphere) grows with the scene's size and
    /// says little about its contribution at a point: in Mitsuba's
    /// `spot_light/test_spot_direct` a constant environment of radiance 0.1
    /// had 92 % of the power and the spot, which lights the visible plane
    /// six times more, was chosen 8 % of the time.
    pub fn with_infinite_share(powers: &[f32], is_infinite: &[bool]) -> Self {
        assert_eq!(powers.len(), is_infinite.len());
        // Lights without power (a black environment) are never chosen.
        let shared = |index: usize| is_infinite[index] && powers[index] > 0.0;
        let infinite_count = (0..powers.len()).filter(|&index| shared(index)).count();
        let finite_power: f64 = (0..powers.len())
            .filter(|&index| !is_infinite[index])
            .map(|index| powers[index].max(0.0) as f64)
            .sum();
        if infinite_count == 0 {
            return Self::new(powers);
        }
        let share = 1.0 / (infinite_count as f64 + f64::from(u8::from(finite_power > 0.0)));
        let weights: Vec<f32> = (0..powers.len())
            .map(|index| {
                if shared(index) {
                    share as f32
                } else if is_infinite[index] || finite_power <= 0.0 {
                    0.0
                } else {
                    (share * powers[index].max(0.0) as f64 / finite_power) as f32
                }
            })
            .collect();
        Self::new(&weights)
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
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32, f32)> {
        if self.is_empty() {
            return None;
        }
        // One light (the common case): skip the search and the division,
        // with the same result as below.
        if self.cdf.len() == 2 {
            return Some((0, 1.0, u.clamp(0.0, 1.0 - f32::EPSILON / 2.0)));
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
    #[inline]
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
        let single = LightSampler::new(&[2.0]);
        for u in [0.0, 0.3, 0.999_999_9] {
            assert_eq!(single.sample(u), Some((0, 1.0, u)));
        }
    }

    #[test]
    fn infinite_lights_get_a_fixed_share() {
        // Two finite lights (powers 1 and 3) and two infinite ones.
        let sampler =
            LightSampler::with_infinite_share(&[1.0, 50.0, 3.0, 0.1], &[false, true, false, true]);
        let expected = [1.0 / 12.0, 1.0 / 3.0, 3.0 / 12.0, 1.0 / 3.0];
        for (index, expected) in expected.into_iter().enumerate() {
            assert!((sampler.probability(index) - expected).abs() < 1e-6);
        }
        // Without infinite lights: in proportion to power.
        let finite = LightSampler::with_infinite_share(&[1.0, 3.0], &[false, false]);
        assert!((finite.probability(1) - 0.75).abs() < 1e-6);
        // Only infinite lights (or finite ones without power): uniform over
        // the infinite ones with power.
        let infinite =
            LightSampler::with_infinite_share(&[0.0, 2.0, 5.0, 0.0], &[false, true, true, true]);
        assert_eq!(infinite.probability(0), 0.0);
        assert!((infinite.probability(2) - 0.5).abs() < 1e-6);
        assert_eq!(infinite.probability(3), 0.0);
    }

    #[test]
    fn no_lights_no_sample() {
        assert!(LightSampler::new(&[]).sample(0.3).is_none());
        let uniform = LightSampler::new(&[0.0, 0.0]);
        assert!((uniform.probability(1) - 0.5).abs() < 1e-6);
    }
}

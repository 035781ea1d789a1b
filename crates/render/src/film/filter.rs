//! Pixel reconstruction filters, normalised and exactly importance-sampled.
//!
//! The film uses filter importance sampling (pbrt-v4, section 8.8): a
//! camera sample for pixel `p` is placed at `p + (0.5, 0.5) + offset` with
//! the offset drawn from the filter, weighted by `f(offset) / pdf(offset)`,
//! and counts for pixel `p` only. Every filter here is *normalised* to unit
//! integral over its support and sampled exactly (the pdf is `f` itself),
//! so the weight is exactly 1 for all of them. pbrt-v4's filters are not
//! normalised (its box and triangle return weight 1 anyway, its Gaussian a
//! tabulated `f/p`), but a constant factor cancels in the film's
//! `Σ w·L / Σ w`, so images do not change.
//!
//! Offsets are in pixels; a filter with radius `r` is zero outside
//! `[−r, r]` on each axis. The 2-D filters are separable products of 1-D
//! ones, sampled one axis per random number.
//!
//! The Gaussian is the *truncated* Gaussian `exp(−x²/2σ²)` on `[−r, r]`
//! per axis, sampled by inverting its CDF with [`erf`] and [`inverse_erf`].
//! pbrt-v4 subtracts the value at the radius, `exp(−r²/2σ²)`, to make the
//! filter continuous at its edge; with the defaults (σ = 0.5, r = 1.5) that
//! value is 1.1% of the peak, and dropping the subtraction is what lets the
//! sampling be exact with a constant weight.

use super::FilmError;
use crate::math::{erf, inverse_erf};

/// An offset drawn from a filter and its importance weight `f / pdf`
/// (exactly 1 for the filters of this module).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSample {
    /// Offset from the pixel centre, in pixels.
    pub offset: [f32; 2],
    /// The filter value divided by the density of `offset`.
    pub weight: f32,
}

fn check_positive(name: &'static str, value: f32) -> Result<f32, FilmError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(FilmError::InvalidFilterParameter { name, value })
    }
}

/// The box filter: constant `1 / (4 rx ry)` on `[−rx, rx] × [−ry, ry]`.
/// With the default radius 0.5 (pbrt-v4's) it is the pixel's own square.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxFilter {
    radius: [f32; 2],
}

impl BoxFilter {
    /// pbrt-v4's default radius.
    pub const DEFAULT_RADIUS: f32 = 0.5;

    /// A box of half-widths `radius` (positive and finite).
    pub fn new(radius: [f32; 2]) -> Result<Self, FilmError> {
        check_positive("box radius", radius[0])?;
        check_positive("box radius", radius[1])?;
        Ok(Self { radius })
    }

    /// Half-widths of the support.
    pub fn radius(&self) -> [f32; 2] {
        self.radius
    }

    /// The normalised filter value at `offset`.
    pub fn evaluate(&self, offset: [f32; 2]) -> f32 {
        if offset[0].abs() <= self.radius[0] && offset[1].abs() <= self.radius[1] {
            1.0 / (4.0 * self.radius[0] * self.radius[1])
        } else {
            0.0
        }
    }

    /// A uniform offset in the box from `u` in `[0, 1)²`; weight 1.
    pub fn sample(&self, u: [f32; 2]) -> FilterSample {
        let offset = [0, 1].map(|axis| (2.0 * u[axis] - 1.0) * self.radius[axis]);
        FilterSample {
            offset,
            weight: 1.0,
        }
    }
}

impl Default for BoxFilter {
    fn default() -> Self {
        Self {
            radius: [Self::DEFAULT_RADIUS; 2],
        }
    }
}

/// The triangle (tent) filter `(rx − |x|)(ry − |y|) / (rx² ry²)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleFilter {
    radius: [f32; 2],
}

impl TriangleFilter {
    /// pbrt-v4's default radius.
    pub const DEFAULT_RADIUS: f32 = 2.0;

    /// A tent of half-widths `radius` (positive and finite).
    pub fn new(radius: [f32; 2]) -> Result<Self, FilmError> {
        check_positive("triangle radius", radius[0])?;
        check_positive("triangle radius", radius[1])?;
        Ok(Self { radius })
    }

    /// Half-widths of the support.
    pub fn radius(&self) -> [f32; 2] {
        self.radius
    }

    /// The normalised filter value at `offset`.
    pub fn evaluate(&self, offset: [f32; 2]) -> f32 {
        let mut value = 1.0;
        for (position, radius) in offset.into_iter().zip(self.radius) {
            value *= (radius - position.abs()).max(0.0) / (radius * radius);
        }
        value
    }

    /// An offset with density equal to the filter, by inverting the tent's
    /// CDF on each axis; weight 1.
    pub fn sample(&self, u: [f32; 2]) -> FilterSample {
        let offset = [0, 1].map(|axis| {
            let u = u[axis];
            let unit_tent = if u < 0.5 {
                -1.0 + (2.0 * u).sqrt()
            } else {
                1.0 - (2.0 - 2.0 * u).sqrt()
            };
            unit_tent * self.radius[axis]
        });
        FilterSample {
            offset,
            weight: 1.0,
        }
    }
}

impl Default for TriangleFilter {
    fn default() -> Self {
        Self {
            radius: [Self::DEFAULT_RADIUS; 2],
        }
    }
}

/// The truncated Gaussian filter: per axis `exp(−x²/2σ²)` on `[−r, r]`,
/// normalised by `σ √(2π) erf(r / (σ√2))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussianFilter {
    radius: [f32; 2],
    sigma: f32,
    /// `erf(r / (σ√2))` per axis: the Gaussian mass inside the radius.
    mass_inside: [f64; 2],
}

impl GaussianFilter {
    /// pbrt-v4's default radius.
    pub const DEFAULT_RADIUS: f32 = 1.5;
    /// pbrt-v4's default standard deviation.
    pub const DEFAULT_SIGMA: f32 = 0.5;

    /// A Gaussian of standard deviation `sigma` truncated to `radius`
    /// (all positive and finite).
    pub fn new(radius: [f32; 2], sigma: f32) -> Result<Self, FilmError> {
        check_positive("gaussian radius", radius[0])?;
        check_positive("gaussian radius", radius[1])?;
        check_positive("gaussian sigma", sigma)?;
        let mass_inside =
            radius.map(|radius| erf(radius as f64 / (sigma as f64 * std::f64::consts::SQRT_2)));
        Ok(Self {
            radius,
            sigma,
            mass_inside,
        })
    }

    /// Half-widths of the support.
    pub fn radius(&self) -> [f32; 2] {
        self.radius
    }

    /// Standard deviation in pixels.
    pub fn sigma(&self) -> f32 {
        self.sigma
    }

    /// The normalised filter value at `offset`.
    pub fn evaluate(&self, offset: [f32; 2]) -> f32 {
        match (self.axis_value(0, offset[0]), self.axis_value(1, offset[1])) {
            (Some(x), Some(y)) => (x * y) as f32,
            _ => 0.0,
        }
    }

    /// The normalised 1-D factor of axis `axis` at `position` (`None`
    /// outside the radius): [`GaussianFilter::evaluate`] is the product of
    /// the two axes' factors, so a film splatting over a block of pixels
    /// evaluates one factor per row and per column instead of two
    /// exponentials per pixel, with the same result.
    pub fn axis_value(&self, axis: usize, position: f32) -> Option<f64> {
        let sigma = self.sigma as f64;
        let x = position as f64;
        (x.abs() <= self.radius[axis] as f64).then(|| {
            (-x * x / (2.0 * sigma * sigma)).exp()
                / (sigma * (2.0 * std::f64::consts::PI).sqrt() * self.mass_inside[axis])
        })
    }

    /// An offset with density equal to the filter: per axis
    /// `x = σ√2 · erf⁻¹((2u − 1) · erf(r / (σ√2)))`, the inverse of the
    /// truncated Gaussian's CDF; weight 1.
    pub fn sample(&self, u: [f32; 2]) -> FilterSample {
        let offset = [0, 1].map(|axis| {
            let target = (2.0 * u[axis] as f64 - 1.0) * self.mass_inside[axis];
            let x = self.sigma as f64 * std::f64::consts::SQRT_2 * inverse_erf(target);
            (x as f32).clamp(-self.radius[axis], self.radius[axis])
        });
        FilterSample {
            offset,
            weight: 1.0,
        }
    }
}

impl Default for GaussianFilter {
    fn default() -> Self {
        Self::new([Self::DEFAULT_RADIUS; 2], Self::DEFAULT_SIGMA)
            .unwrap_or_else(|_| unreachable!("the default parameters are valid"))
    }
}

/// One of the reconstruction filters, as the film stores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Filter {
    /// See [`BoxFilter`].
    Box(BoxFilter),
    /// See [`TriangleFilter`].
    Triangle(TriangleFilter),
    /// See [`GaussianFilter`].
    Gaussian(GaussianFilter),
}

impl Filter {
    /// Half-widths of the support, in pixels.
    pub fn radius(&self) -> [f32; 2] {
        match self {
            Self::Box(filter) => filter.radius(),
            Self::Triangle(filter) => filter.radius(),
            Self::Gaussian(filter) => filter.radius(),
        }
    }

    /// The normalised filter value at `offset` (it integrates to 1).
    pub fn evaluate(&self, offset: [f32; 2]) -> f32 {
        match self {
            Self::Box(filter) => filter.evaluate(offset),
            Self::Triangle(filter) => filter.evaluate(offset),
            Self::Gaussian(filter) => filter.evaluate(offset),
        }
    }

    /// The normalised 1-D factor of axis `axis` at `offset` (zero outside
    /// the radius): every filter here is separable, and
    /// [`Filter::evaluate`] is the product of the two axes' factors.
    pub fn axis_value(&self, axis: usize, offset: f32) -> f64 {
        let radius = self.radius()[axis] as f64;
        let offset = offset as f64;
        if offset.abs() > radius {
            return 0.0;
        }
        match self {
            Self::Box(_) => 0.5 / radius,
            Self::Triangle(_) => (radius - offset.abs()) / (radius * radius),
            Self::Gaussian(filter) => filter.axis_value(axis, offset as f32).unwrap_or(0.0),
        }
    }

    /// The density of camera-sample positions at raster `position` when
    /// every pixel of an image of `resolution` places equally many by
    /// filter importance sampling ([`Filter::sample`] around its centre),
    /// per pixel: `Σ_p f(position − centre_p)`, the sum of the weights a
    /// splat at `position` gives the image's pixels. One inside the image
    /// for the default box; near one inside it, falling off across its
    /// border, for wider filters.
    pub fn sample_density(&self, resolution: [u32; 2], position: [f32; 2]) -> f64 {
        let radius = self.radius();
        let mut density = 1.0;
        for axis in 0..2 {
            let x = position[axis] as f64;
            let reach = radius[axis] as f64;
            // Pixel centres c = i + ½ with |x − c| ≤ reach.
            let first = (x - reach - 0.5).ceil().max(0.0) as i64;
            let last = ((x + reach - 0.5).floor() as i64).min(resolution[axis] as i64 - 1);
            let mut sum = 0.0;
            for pixel in first..=last {
                sum += self.axis_value(axis, (pixel as f64 + 0.5 - x) as f32);
            }
            density *= sum;
        }
        density
    }

    /// An offset distributed exactly as [`Filter::evaluate`], from `u` in
    /// `[0, 1)²`, with weight `f / pdf = 1`.
    pub fn sample(&self, u: [f32; 2]) -> FilterSample {
        match self {
            Self::Box(filter) => filter.sample(u),
            Self::Triangle(filter) => filter.sample(u),
            Self::Gaussian(filter) => filter.sample(u),
        }
    }
}

impl Default for Filter {
    /// pbrt-v4's default: the Gaussian with radius 1.5 and σ = 0.5.
    fn default() -> Self {
        Self::Gaussian(GaussianFilter::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The separable factors multiply to the filter, and the sample density
    /// is the sum of the pixels' filter values (one inside the image for
    /// the box, a partition of unity for the tent; zero beyond the reach).
    #[test]
    fn sample_density_sums_the_pixels_filter_values() {
        for (name, filter) in filters_under_test() {
            for offset in [[0.1, -0.3], [0.7, 0.2], [-1.2, 1.4], [2.5, 0.0]] {
                let product = filter.axis_value(0, offset[0]) * filter.axis_value(1, offset[1]);
                let value = filter.evaluate(offset) as f64;
                assert!(
                    (product - value).abs() <= 1e-6 * value.max(1e-6),
                    "{name}: {offset:?}"
                );
            }
            let resolution = [7, 5];
            for position in [[3.3, 2.1], [0.2, 4.9], [-0.7, 1.5], [7.6, -0.4], [1.0, 1.0]] {
                let mut sum = 0.0;
                for y in 0..resolution[1] {
                    for x in 0..resolution[0] {
                        let offset = [
                            position[0] - (x as f32 + 0.5),
                            position[1] - (y as f32 + 0.5),
                        ];
                        sum += filter.evaluate(offset) as f64;
                    }
                }
                let density = filter.sample_density(resolution, position);
                assert!(
                    (density - sum).abs() < 1e-5,
                    "{name} at {position:?}: {density} vs {sum}"
                );
            }
        }
        let tent = Filter::Triangle(TriangleFilter::default());
        assert!((tent.sample_density([9, 9], [4.3, 4.8]) - 1.0).abs() < 1e-6);
        let unit_box = Filter::Box(BoxFilter::default());
        assert_eq!(unit_box.sample_density([4, 4], [2.3, 0.1]), 1.0);
        assert_eq!(unit_box.sample_density([4, 4], [-0.2, 0.1]), 0.0);
    }
    use crate::statistics::chi_square_test;
    use qmc::random::SeekablePcg;

    fn filters_under_test() -> Vec<(&'static str, Filter)> {
        vec![
            ("box default", Filter::Box(BoxFilter::default())),
            (
                "box 1.5x0.75",
                Filter::Box(BoxFilter::new([1.5, 0.75]).unwrap()),
            ),
            (
                "triangle default",
                Filter::Triangle(TriangleFilter::default()),
            ),
            (
                "triangle 1x0.5",
                Filter::Triangle(TriangleFilter::new([1.0, 0.5]).unwrap()),
            ),
            (
                "gaussian default",
                Filter::Gaussian(GaussianFilter::default()),
            ),
            (
                "gaussian wide sigma",
                Filter::Gaussian(GaussianFilter::new([1.0, 2.0], 1.5).unwrap()),
            ),
            (
                "gaussian narrow",
                Filter::Gaussian(GaussianFilter::new([2.5, 2.5], 0.3).unwrap()),
            ),
        ]
    }

    /// ∫∫ of the filter over `[x0, x1] × [y0, y1]` by a composite Simpson
    /// rule on a 16×16 grid (exact for the box and, with bin edges on the
    /// tent's kink, for the triangle).
    fn integrate(filter: &Filter, x: [f64; 2], y: [f64; 2]) -> f64 {
        const STEPS: usize = 16;
        let weight = |index: usize| match index {
            0 | STEPS => 1.0,
            odd if odd % 2 == 1 => 4.0,
            _ => 2.0,
        };
        let (hx, hy) = ((x[1] - x[0]) / STEPS as f64, (y[1] - y[0]) / STEPS as f64);
        let mut sum = 0.0;
        for i in 0..=STEPS {
            for j in 0..=STEPS {
                // Evaluate just inside the bin so that the box's edges are
                // counted from the inside.
                let px = (x[0] + hx * i as f64).clamp(x[0] + 1e-9, x[1] - 1e-9);
                let py = (y[0] + hy * j as f64).clamp(y[0] + 1e-9, y[1] - 1e-9);
                sum += weight(i) * weight(j) * filter.evaluate([px as f32, py as f32]) as f64;
            }
        }
        sum * hx * hy / 9.0
    }

    #[test]
    fn filters_integrate_to_one_and_vanish_outside() {
        for (name, filter) in filters_under_test() {
            let [rx, ry] = filter.radius().map(|radius| radius as f64);
            // Four quadrants so that the triangle's kink is on an edge.
            let mut total = 0.0;
            for x in [[-rx, 0.0], [0.0, rx]] {
                for y in [[-ry, 0.0], [0.0, ry]] {
                    total += integrate(&filter, x, y);
                }
            }
            assert!((total - 1.0).abs() < 1e-5, "{name}: integral {total}");
            let outside = [rx as f32 * 1.001 + 1e-3, 0.0];
            assert_eq!(filter.evaluate(outside), 0.0, "{name}");
            assert_eq!(
                filter.evaluate([0.0, -(ry as f32) * 1.001 - 1e-3]),
                0.0,
                "{name}"
            );
        }
    }

    #[test]
    fn filter_sampling_matches_evaluate_chi_square() {
        const BINS: usize = 20; // even: bin edges on the axes
        const SAMPLES: usize = 200_000;
        for (index, (name, filter)) in filters_under_test().into_iter().enumerate() {
            let radius = filter.radius();
            let mut random = SeekablePcg::new(0x5eed_f117, index as u64);
            let mut observed = vec![0u64; BINS * BINS];
            let mut weight_sum = 0.0f64;
            for _ in 0..SAMPLES {
                let sample = filter.sample([random.next_f32(), random.next_f32()]);
                weight_sum += sample.weight as f64;
                let bin = [0, 1].map(|axis| {
                    let offset = sample.offset[axis];
                    assert!(
                        offset.abs() <= radius[axis],
                        "{name}: offset {offset} outside"
                    );
                    let unit = (offset / radius[axis] + 1.0) * 0.5;
                    ((unit * BINS as f32) as usize).min(BINS - 1)
                });
                observed[bin[1] * BINS + bin[0]] += 1;
            }
            let edges = |axis: usize, bin: usize| {
                let width = 2.0 * radius[axis] as f64 / BINS as f64;
                let start = -(radius[axis] as f64) + width * bin as f64;
                [start, start + width]
            };
            let mut expected = Vec::with_capacity(BINS * BINS);
            for row in 0..BINS {
                for column in 0..BINS {
                    let mass = integrate(&filter, edges(0, column), edges(1, row));
                    expected.push(mass * SAMPLES as f64);
                }
            }
            let p_value = chi_square_test(&observed, &expected).p_value;
            println!("{name}: chi-square p-value {p_value:.4}");
            assert!(p_value > 1e-4, "{name}: chi-square p-value {p_value}");

            // E[f/p] = ∫ f = 1; every weight is exactly 1 here.
            let mean_weight = weight_sum / SAMPLES as f64;
            assert_eq!(mean_weight, 1.0, "{name}: mean weight {mean_weight}");
        }
    }

    #[test]
    fn chi_square_detects_a_slightly_wrong_sigma() {
        // Negative control: samples of σ = 0.5 against the density of
        // σ = 0.53 must fail the test used above.
        const BINS: usize = 20;
        const SAMPLES: usize = 200_000;
        let sampled = GaussianFilter::default();
        let claimed = Filter::Gaussian(GaussianFilter::new([1.5; 2], 0.53).unwrap());
        let mut random = SeekablePcg::new(3, 3);
        let mut observed = vec![0u64; BINS * BINS];
        for _ in 0..SAMPLES {
            let offset = sampled
                .sample([random.next_f32(), random.next_f32()])
                .offset;
            let bin =
                offset.map(|x| (((x / 1.5 + 1.0) * 0.5 * BINS as f32) as usize).min(BINS - 1));
            observed[bin[1] * BINS + bin[0]] += 1;
        }
        let width = 3.0 / BINS as f64;
        let edges = |bin: usize| [-1.5 + width * bin as f64, -1.5 + width * (bin + 1) as f64];
        let expected: Vec<f64> = (0..BINS * BINS)
            .map(|index| {
                integrate(&claimed, edges(index % BINS), edges(index / BINS)) * SAMPLES as f64
            })
            .collect();
        let p_value = chi_square_test(&observed, &expected).p_value;
        assert!(p_value < 1e-4, "p-value {p_value}");
    }

    #[test]
    fn gaussian_sampling_is_the_inverse_cdf() {
        // The median maps to the centre, and u = 0, 1 to the radius.
        let filter = GaussianFilter::default();
        assert_eq!(filter.sample([0.5, 0.5]).offset, [0.0, 0.0]);
        let edge = filter.sample([0.0, 1.0 - f32::EPSILON]).offset;
        assert!(
            (edge[0] + 1.5).abs() < 1e-6 && (edge[1] - 1.5).abs() < 2e-2,
            "{edge:?}"
        );
        // Monotone in u.
        let mut previous = f32::NEG_INFINITY;
        for step in 0..1000 {
            let offset = filter.sample([step as f32 / 1000.0, 0.5]).offset[0];
            assert!(offset >= previous);
            previous = offset;
        }
    }

    #[test]
    fn invalid_parameters_are_errors() {
        assert!(BoxFilter::new([0.0, 1.0]).is_err());
        assert!(TriangleFilter::new([1.0, f32::NAN]).is_err());
        assert!(GaussianFilter::new([1.0, 1.0], -0.5).is_err());
        let message = GaussianFilter::new([1.0, 1.0], 0.0)
            .unwrap_err()
            .to_string();
        assert!(message.contains("sigma"), "{message}");
    }
}

//! Piecewise-constant distributions on [0, 1) and [0, 1)², sampled by
//! inverting their cumulative distribution (pbrt-v4's `PiecewiseConstant1D`
//! and `PiecewiseConstant2D`, Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., sections A.4.2 and A.5.2).
//!
//! A function given by `n` non-negative values is a step function over `n`
//! equal cells of [0, 1); its normalised version is the density sampled.
//! The 2-D form samples a row from the marginal distribution of the rows'
//! sums and then a column from that row's conditional distribution, so
//! both coordinates are monotonic in the two uniform numbers (what QMC
//! points need to keep their structure). Environment maps use it; any other
//! tabulated density (textured area lights, projection lights) can.

/// A step function over `n` equal cells of [0, 1), normalised to a density.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseConstant1D {
    /// The (clamped) function values, one per cell.
    function: Vec<f32>,
    /// `cdf[i]` = ∫₀^{i/n} density; `cdf[0] = 0`, `cdf[n] = 1`.
    cdf: Vec<f32>,
    /// ∫₀¹ function = the mean of the values.
    integral: f32,
}

/// A value drawn from a [`PiecewiseConstant1D`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample1D {
    /// The point in [0, 1).
    pub value: f32,
    /// Its density.
    pub pdf: f32,
    /// The cell it fell in.
    pub cell: usize,
}

impl PiecewiseConstant1D {
    /// The distribution proportional to `values` (negative and non-finite
    /// values count as 0; if all are 0 the distribution is uniform).
    ///
    /// # Panics
    ///
    /// If `values` is empty.
    pub fn new(values: &[f32]) -> Self {
        assert!(
            !values.is_empty(),
            "a piecewise-constant distribution needs at least one value"
        );
        let function: Vec<f32> = values
            .iter()
            .map(|&value| {
                if value.is_finite() && value > 0.0 {
                    value
                } else {
                    0.0
                }
            })
            .collect();
        let count = function.len();
        let total: f64 = function.iter().map(|&value| value as f64).sum();
        let mut cdf = Vec::with_capacity(count + 1);
        cdf.push(0.0f32);
        let mut running = 0.0f64;
        for (index, &value) in function.iter().enumerate() {
            running += if total > 0.0 {
                value as f64 / total
            } else {
                1.0 / count as f64
            };
            cdf.push(if index + 1 == count {
                1.0
            } else {
                running as f32
            });
        }
        Self {
            function,
            cdf,
            integral: (total / count as f64) as f32,
        }
    }

    /// The number of cells.
    pub fn len(&self) -> usize {
        self.function.len()
    }

    /// Never true (a distribution has at least one cell).
    pub fn is_empty(&self) -> bool {
        self.function.is_empty()
    }

    /// ∫₀¹ of the (unnormalised) function: the mean of its values.
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// The unnormalised value of cell `cell`.
    pub fn function(&self, cell: usize) -> f32 {
        self.function[cell]
    }

    /// The probability of cell `cell`.
    pub fn cell_probability(&self, cell: usize) -> f32 {
        self.cdf[cell + 1] - self.cdf[cell]
    }

    /// The density at cell `cell` (its probability times the cell count).
    pub fn cell_pdf(&self, cell: usize) -> f32 {
        if self.integral > 0.0 {
            self.function[cell] / self.integral
        } else {
            1.0
        }
    }

    /// The cell that contains `x` (clamped into [0, 1)).
    pub fn cell_of(&self, x: f32) -> usize {
        let scaled = x * self.len() as f32;
        if scaled.is_nan() {
            0
        } else {
            (scaled.max(0.0) as usize).min(self.len() - 1)
        }
    }

    /// The density at `x` ∈ [0, 1).
    pub fn pdf(&self, x: f32) -> f32 {
        self.cell_pdf(self.cell_of(x))
    }

    /// Draws a point by inverting the CDF at `u` ∈ [0, 1): the cell whose CDF
    /// interval contains `u`, then linearly inside it.
    pub fn sample(&self, u: f32) -> Sample1D {
        let count = self.len();
        // The last cell whose left CDF value is ≤ u, skipping empty cells.
        let cell = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(count - 1);
        let (low, high) = (self.cdf[cell], self.cdf[cell + 1]);
        let fraction = if high > low {
            ((u - low) / (high - low)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let value = ((cell as f32 + fraction) / count as f32).min(1.0 - f32::EPSILON / 2.0);
        Sample1D {
            value,
            pdf: self.cell_pdf(cell),
            cell,
        }
    }
}

/// A step function over a `width × height` grid of equal cells of [0, 1)²,
/// normalised to a density (row `y` covers v ∈ [y/height, (y+1)/height)).
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseConstant2D {
    /// One conditional distribution over u per row.
    conditional: Vec<PiecewiseConstant1D>,
    /// The distribution of rows, proportional to their integrals.
    marginal: PiecewiseConstant1D,
}

/// A point drawn from a [`PiecewiseConstant2D`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample2D {
    /// The point (u, v) in [0, 1)².
    pub point: [f32; 2],
    /// Its density with respect to area in [0, 1)².
    pub pdf: f32,
    /// The cell (column, row) it fell in.
    pub cell: [usize; 2],
}

impl PiecewiseConstant2D {
    /// The distribution proportional to `values`, row-major (`values[y *
    /// width + x]`), with the conventions of [`PiecewiseConstant1D::new`].
    ///
    /// # Panics
    ///
    /// If `width` or `height` is 0 or `values.len() != width * height`.
    pub fn new(values: &[f32], width: usize, height: usize) -> Self {
        assert!(
            width > 0 && height > 0 && values.len() == width * height,
            "a {width}×{height} distribution needs {} values, got {}",
            width * height,
            values.len()
        );
        let conditional: Vec<PiecewiseConstant1D> = values
            .chunks_exact(width)
            .map(PiecewiseConstant1D::new)
            .collect();
        let row_integrals: Vec<f32> = conditional.iter().map(|row| row.integral()).collect();
        Self {
            marginal: PiecewiseConstant1D::new(&row_integrals),
            conditional,
        }
    }

    /// Columns and rows.
    pub fn resolution(&self) -> [usize; 2] {
        [self.conditional[0].len(), self.conditional.len()]
    }

    /// ∫ over [0, 1)² of the (unnormalised) function.
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// The density of cell (column, row).
    pub fn cell_pdf(&self, cell: [usize; 2]) -> f32 {
        let [x, y] = cell;
        if self.marginal.integral() > 0.0 {
            self.conditional[y].function(x) / self.marginal.integral()
        } else {
            // All zero: both 1-D distributions are uniform.
            1.0
        }
    }

    /// The probability of cell (column, row).
    pub fn cell_probability(&self, cell: [usize; 2]) -> f32 {
        let [width, height] = self.resolution();
        self.cell_pdf(cell) / (width * height) as f32
    }

    /// The cell containing `point` (clamped into [0, 1)²).
    pub fn cell_of(&self, point: [f32; 2]) -> [usize; 2] {
        let y = self.marginal.cell_of(point[1]);
        [self.conditional[y].cell_of(point[0]), y]
    }

    /// The density at `point` ∈ [0, 1)².
    pub fn pdf(&self, point: [f32; 2]) -> f32 {
        self.cell_pdf(self.cell_of(point))
    }

    /// Draws a point: v from the marginal with `u[1]`, then u from that
    /// row's conditional with `u[0]`.
    pub fn sample(&self, u: [f32; 2]) -> Sample2D {
        let row = self.marginal.sample(u[1]);
        let column = self.conditional[row.cell].sample(u[0]);
        Sample2D {
            point: [column.value, row.value],
            pdf: row.pdf * column.pdf,
            cell: [column.cell, row.cell],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statistics::chi_square_test;
    use qmc::random::SeekablePcg;

    #[test]
    fn one_dimensional_density_is_the_normalised_function() {
        let distribution = PiecewiseConstant1D::new(&[1.0, 0.0, 3.0, -2.0, f32::NAN]);
        assert_eq!(distribution.len(), 5);
        assert!((distribution.integral() - 4.0 / 5.0).abs() < 1e-6);
        // Densities 1/0.8, 0, 3/0.8, 0, 0 integrate to 1 over cells of 1/5.
        assert!((distribution.pdf(0.1) - 1.25).abs() < 1e-6);
        assert_eq!(distribution.pdf(0.3), 0.0);
        assert!((distribution.pdf(0.5) - 3.75).abs() < 1e-6);
        let total: f32 = (0..5).map(|cell| distribution.cell_probability(cell)).sum();
        assert!((total - 1.0).abs() < 1e-6);
    }

    #[test]
    fn sampling_inverts_the_cdf() {
        let distribution = PiecewiseConstant1D::new(&[1.0, 0.0, 3.0]);
        // u = 0.25 is the end of the first cell's CDF interval [0, 1/4).
        let first = distribution.sample(0.125);
        assert_eq!(first.cell, 0);
        assert!((first.value - 1.0 / 6.0).abs() < 1e-6);
        let last = distribution.sample(0.625);
        assert_eq!(last.cell, 2);
        assert!((last.value - (2.0 + 0.5) / 3.0).abs() < 1e-6);
        assert_eq!(last.pdf, distribution.pdf(last.value));
        // The empty middle cell is never chosen, not even at its CDF value.
        assert_eq!(distribution.sample(0.25).cell, 2);
        assert!(distribution.sample(1.0 - f32::EPSILON).value < 1.0);
        assert!(distribution.sample(0.0).value >= 0.0);
    }

    #[test]
    fn all_zero_is_uniform() {
        let distribution = PiecewiseConstant1D::new(&[0.0, 0.0]);
        assert_eq!(distribution.pdf(0.7), 1.0);
        let sample = distribution.sample(0.7);
        assert!((sample.value - 0.7).abs() < 1e-6);
        let grid = PiecewiseConstant2D::new(&[0.0; 6], 3, 2);
        assert_eq!(grid.pdf([0.2, 0.9]), 1.0);
        assert!((grid.cell_probability([1, 1]) - 1.0 / 6.0).abs() < 1e-7);
    }

    #[test]
    fn one_dimensional_chi_square() {
        let values: Vec<f32> = (0..37)
            .map(|i| ((i as f32 * 0.37).sin() + 1.1).powi(3))
            .collect();
        let distribution = PiecewiseConstant1D::new(&values);
        let mut random = SeekablePcg::new(7, 0);
        let samples = 200_000;
        let bins = 74; // two bins per cell: checks the uniform part too
        let mut observed = vec![0u64; bins];
        for _ in 0..samples {
            let sample = distribution.sample(random.next_f32());
            assert!((0.0..1.0).contains(&sample.value));
            assert_eq!(sample.pdf, distribution.pdf(sample.value));
            observed[((sample.value * bins as f32) as usize).min(bins - 1)] += 1;
        }
        let expected: Vec<f64> = (0..bins)
            .map(|bin| distribution.cell_probability(bin / 2) as f64 / 2.0 * samples as f64)
            .collect();
        let result = chi_square_test(&observed, &expected);
        assert!(result.p_value > 1e-3, "{result:?}");
    }

    #[test]
    fn two_dimensional_chi_square_and_pdf() {
        let (width, height) = (9, 5);
        let values: Vec<f32> = (0..width * height)
            .map(|i| {
                let (x, y) = ((i % width) as f32, (i / width) as f32);
                if x == 4.0 {
                    0.0
                } else {
                    1.0 + x * y + (x - y).abs()
                }
            })
            .collect();
        let distribution = PiecewiseConstant2D::new(&values, width, height);
        assert_eq!(distribution.resolution(), [width, height]);
        let total: f32 = values.iter().sum();
        assert!((distribution.integral() - total / (width * height) as f32).abs() < 1e-5);
        let mut random = SeekablePcg::new(11, 3);
        let samples = 300_000;
        let mut observed = vec![0u64; width * height];
        for _ in 0..samples {
            let sample = distribution.sample([random.next_f32(), random.next_f32()]);
            let [u, v] = sample.point;
            assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
            assert_eq!(distribution.cell_of(sample.point), sample.cell);
            assert!((sample.pdf - distribution.pdf(sample.point)).abs() <= 1e-5 * sample.pdf);
            observed[sample.cell[1] * width + sample.cell[0]] += 1;
        }
        let expected: Vec<f64> = values
            .iter()
            .map(|&value| value as f64 / total as f64 * samples as f64)
            .collect();
        let result = chi_square_test(&observed, &expected);
        assert!(result.p_value > 1e-3, "{result:?}");
        // The density integrates to 1 (midpoint rule is exact for steps).
        let integral: f64 = (0..width * height)
            .map(|i| {
                let point = [
                    ((i % width) as f32 + 0.5) / width as f32,
                    ((i / width) as f32 + 0.5) / height as f32,
                ];
                distribution.pdf(point) as f64 / (width * height) as f64
            })
            .sum();
        assert!((integral - 1.0).abs() < 1e-5);
    }
}

//! Compensated summation for sums whose terms nearly cancel.
//!
//! The figures of merit of CBC lattice construction and the L2 discrepancies
//! are sums of many terms that cancel to a result orders of magnitude below
//! the terms themselves; plain `f64` addition would lose the result in the
//! rounding of the partial sums.

/// Neumaier's compensated running sum (an improved Kahan summation): the
/// rounding error of every addition is accumulated separately and added back
/// at the end, so small terms are not lost next to a large total.
#[derive(Debug, Default, Clone, Copy)]
pub struct NeumaierSum {
    sum: f64,
    compensation: f64,
}

impl NeumaierSum {
    /// Adds `value` to the sum.
    #[inline]
    pub fn add(&mut self, value: f64) {
        let total = self.sum + value;
        if self.sum.abs() >= value.abs() {
            self.compensation += (self.sum - total) + value;
        } else {
            self.compensation += (value - total) + self.sum;
        }
        self.sum = total;
    }

    /// The sum of every value added so far.
    #[inline]
    pub fn total(&self) -> f64 {
        self.sum + self.compensation
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compensated_sum_keeps_small_terms() {
        let mut sum = NeumaierSum::default();
        sum.add(1.0);
        for _ in 0..1000 {
            sum.add(1e-17);
        }
        sum.add(-1.0);
        assert!((sum.total() - 1e-14).abs() < 1e-20);
    }
}

//! Whether estimated variances predict the spread of independent renders:
//! the ratio of the mean estimate to the observed variance, with its
//! jackknife standard error over the renders (`replication_variance.rs`,
//! `replication_error_estimate.rs`).
//!
//! For every value `i` (a pixel channel, or an image mean), the estimate
//! `v_{i,k}` of render `k` is unbiased for the variance of the render's
//! value `I_{i,k}`, so `E[mean_k v_{i,k}] = E[V_i]` with `V_i` the sample
//! variance of `I_{i,1} … I_{i,R}`. The statistic is the ratio of the sums
//! over values, `Σ_i mean_k v_{i,k} / Σ_i V_i`; its error is the jackknife
//! over the renders (values of one render are correlated, renders are
//! independent).
#![allow(dead_code)] // each test uses part of it

/// Per render: its values and their estimated variances.
pub type Render = (Vec<f64>, Vec<f64>);

/// `Σ_i mean_k v_{i,k} / Σ_i V_i` over `renders`.
pub fn variance_ratio(renders: &[&Render]) -> f64 {
    let count = renders.len() as f64;
    let values = renders[0].0.len();
    let (mut estimated, mut observed) = (0.0, 0.0);
    for value in 0..values {
        let mean = renders.iter().map(|(image, _)| image[value]).sum::<f64>() / count;
        observed += renders
            .iter()
            .map(|(image, _)| (image[value] - mean).powi(2))
            .sum::<f64>()
            / (count - 1.0);
        estimated += renders
            .iter()
            .map(|(_, variance)| variance[value])
            .sum::<f64>()
            / count;
    }
    estimated / observed
}

/// The ratio and its jackknife standard error.
pub fn ratio_with_error(renders: &[Render]) -> (f64, f64) {
    jackknife(renders, variance_ratio)
}

/// `statistic` of all `items` and its jackknife standard error: the
/// spread of the statistic with each item left out in turn.
pub fn jackknife<T>(items: &[T], statistic: impl Fn(&[&T]) -> f64) -> (f64, f64) {
    let all: Vec<&T> = items.iter().collect();
    let value = statistic(&all);
    let count = items.len();
    let leave_one_out: Vec<f64> = (0..count)
        .map(|left_out| {
            let kept: Vec<&T> = items
                .iter()
                .enumerate()
                .filter(|(index, _)| *index != left_out)
                .map(|(_, item)| item)
                .collect();
            statistic(&kept)
        })
        .collect();
    let mean = leave_one_out.iter().sum::<f64>() / count as f64;
    let variance = leave_one_out
        .iter()
        .map(|value| (value - mean).powi(2))
        .sum::<f64>()
        * (count as f64 - 1.0)
        / count as f64;
    (value, variance.sqrt())
}

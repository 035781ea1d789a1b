//! The multiple-importance weights of bidirectional path tracing, in O(k)
//! per strategy: Veach's ratio walk (Veach 1997 §10.2; pbrt-v4's
//! `MISWeight` computes the same quantities).
//!
//! A path of k + 1 vertices made by strategy (s, t) — s vertices of the
//! light subpath `y₀ … y_{s−1}`, t of the camera subpath `z₀ … z_{t−1}` —
//! could have been made by every other split (s', t') with s' + t' = s + t.
//! With `p_{s'}` the area-measure density of the path under split s', the
//! balance heuristic's weight is `p_s / Σ p_{s'}` and the power heuristic's
//! `p_s² / Σ p_{s'}²`. Walking out from the connection, the density ratio
//! of neighbouring splits is the ratio of one vertex's two densities:
//! moving the split one vertex towards the camera trades `z_i`'s forward
//! density (sampled from `z_{i−1}`) for its reverse density (sampled from
//! `z_{i+1}`, the light side), and likewise on the light subpath. So
//!
//! `1 / w = 1 + Σ_{i=t−1}^{1} Π_{j=i}^{t−1} (p←(z_j) / p→(z_j))^β
//!            + Σ_{i=s−1}^{0} Π_{j=i}^{s−1} (p←(y_j) / p→(y_j))^β`,
//!
//! β = 1 (balance) or 2 (power). A split is impossible where its connection
//! would join a vertex that scattered by a delta lobe, or where it would
//! have to hit a light of delta position: those terms are left out. Zero
//! densities (a delta scattering's) count as 1 in the ratios, so that the
//! product carries on past them (pbrt-v4's `remap0`).
//!
//! The caller fills the densities of the path as the strategy sees it: the
//! reverse densities of the two connection vertices and of their
//! predecessors depend on the connection and are set per strategy.
//!
//! # Media: densities per wavelength
//!
//! In participating media a vertex's density has a free flight's factor —
//! the transmittance of the segment that reached it, times the extinction
//! σt where it is a medium point — which differs between wavelengths, while
//! the walks sample distances at the hero wavelength only. The throughputs
//! then carry `f / p_hero`, and the estimator combines the strategies and
//! the four choices of hero (the one-sample spectral MIS of pbrt-v4's
//! `volpath`, its `r_u`) in one balance (or power) heuristic over the
//! spectrally averaged densities `p̄_s = mean_j p_{s,j}` (strategy s
//! marginalised over the choice of hero): the strategy s that made the
//! path contributes `f_i p̄_s^{β−1} / Σ_{s'} p̄_{s'}^β`, which is its
//! throughput `f_i / p_{s,0}` times `m_s^{β−1} / Σ_{s'} m_{s'}^β` with
//! `m_{s'} = p̄_{s'} / p_{s,0} = mean_j r_j R_j(s')`: `r_j = p_{s,j} /
//! p_{s,0}` is the walks' spectral density ratio
//! ([`crate::integrators::path_space::WalkState::spectral_density_ratio`]),
//! and `R_j(s') = p_{s',j} / p_{s,j}` is the ratio walk above run per
//! wavelength on the densities with their free flights. Without media all
//! four wavelengths have the same densities and this is the scalar weight.
//! Without this combination the throughput's `T_j σ_j / (T_0 σ_0)` has
//! infinite variance wherever the hero's extinction exceeds twice another
//! wavelength's.

use crate::integrators::MisHeuristic;
use crate::spectrum::{SPECTRUM_SAMPLE_COUNT, SampledSpectrum};

/// The densities of one vertex of a bidirectional path, per unit area (per
/// unit volume in a medium): a geometric part (direction density, cosine
/// and distance) and, per wavelength, the free flight's factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexDensities {
    /// Of sampling the vertex from its predecessor on its own subpath,
    /// without the free flight.
    pub forward: f32,
    /// Of sampling it from the other side (its successor on its subpath),
    /// without the free flight.
    pub reverse: f32,
    /// The free flight's factor of `forward` per wavelength (transmittance
    /// of the segment from the predecessor, times σt at a medium vertex; 1
    /// without media).
    pub forward_free_flight: SampledSpectrum,
    /// The free flight's factor of `reverse` per wavelength.
    pub reverse_free_flight: SampledSpectrum,
    /// The vertex scattered by a delta lobe (no connection can join it).
    pub delta: bool,
}

impl Default for VertexDensities {
    fn default() -> Self {
        Self::geometric(0.0, 0.0, false)
    }
}

impl VertexDensities {
    /// Densities without free flights (no media on either side).
    pub fn geometric(forward: f32, reverse: f32, delta: bool) -> Self {
        Self {
            forward,
            reverse,
            forward_free_flight: SampledSpectrum::splat(1.0),
            reverse_free_flight: SampledSpectrum::splat(1.0),
            delta,
        }
    }

    /// Sets the reverse density: `geometric` times `free_flight`.
    #[inline]
    pub fn set_reverse(&mut self, geometric: f32, free_flight: SampledSpectrum) {
        self.reverse = geometric;
        self.reverse_free_flight = free_flight;
    }
}

/// Which strategies a render uses besides the always-present ones, and the
/// heuristic that weighs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Strategies {
    /// The heuristic.
    pub heuristic: MisHeuristic,
    /// Whether the strategies with t = 1 (light tracing: the light
    /// subpath's vertices connected to the camera) are used; Kollig & Keller
    /// leave them out for OFFICE.
    pub camera_connections: bool,
}

/// The weight of the strategy that made a path from the camera subpath's
/// `camera` vertices (`z₀` first) and the light subpath's `light` vertices
/// (`y₀` first), their densities as this strategy sees them;
/// `delta_light` says whether `y₀`'s light has a delta position (no camera
/// path can reach it). A path of two vertices has one strategy: weight 1.
///
/// In scenes with media, `spectral_density_ratio` is the path's `r_j` (the
/// two subpaths' spectral density ratios multiplied) and the weight is the
/// spectral one of the module docs; `None` without media.
pub fn strategy_weight(
    camera: &[VertexDensities],
    light: &[VertexDensities],
    delta_light: bool,
    strategies: Strategies,
    spectral_density_ratio: Option<&SampledSpectrum>,
) -> f32 {
    if let Some(ratio) = spectral_density_ratio {
        return spectral_strategy_weight(camera, light, delta_light, strategies, ratio);
    }
    let heuristic = strategies.heuristic;
    if camera.len() + light.len() == 2 {
        return 1.0;
    }
    let remap = |density: f32| if density != 0.0 { density } else { 1.0 };
    let power = |ratio: f64| match heuristic {
        MisHeuristic::Balance => ratio,
        MisHeuristic::Power => ratio * ratio,
    };
    let mut sum = 0.0f64;
    let mut ratio = 1.0f64;
    for i in (1..camera.len()).rev() {
        ratio *= remap(camera[i].reverse) as f64 / remap(camera[i].forward) as f64;
        // i = 1 is the split with one camera vertex: light tracing.
        if !camera[i].delta && !camera[i - 1].delta && (i > 1 || strategies.camera_connections) {
            sum += power(ratio);
        }
    }
    ratio = 1.0;
    for i in (0..light.len()).rev() {
        ratio *= remap(light[i].reverse) as f64 / remap(light[i].forward) as f64;
        let before_delta = if i > 0 {
            light[i - 1].delta
        } else {
            delta_light
        };
        if !light[i].delta && !before_delta {
            sum += power(ratio);
        }
    }
    (1.0 / (1.0 + sum)) as f32
}

/// The weight of the module docs' spectral combination:
/// `m_s^{β−1} / Σ_{s'} m_{s'}^β`, with `m_{s'} = mean_j r_j R_j(s')`. Kept
/// out of line: scenes without media keep the scalar weight's code.
#[inline(never)]
fn spectral_strategy_weight(
    camera: &[VertexDensities],
    light: &[VertexDensities],
    delta_light: bool,
    strategies: Strategies,
    spectral_density_ratio: &SampledSpectrum,
) -> f32 {
    let heuristic = strategies.heuristic;
    let lanes = SPECTRUM_SAMPLE_COUNT;
    let remap = |density: f32| if density != 0.0 { density } else { 1.0 } as f64;
    let power = |value: f64| match heuristic {
        MisHeuristic::Balance => value,
        MisHeuristic::Power => value * value,
    };
    // r_j, with wavelengths the strategy cannot sample as hero left out.
    let path_ratio: [f64; SPECTRUM_SAMPLE_COUNT] = std::array::from_fn(|j| {
        let r = spectral_density_ratio[j] as f64;
        if r.is_finite() && r > 0.0 { r } else { 0.0 }
    });
    let own = path_ratio.iter().sum::<f64>() / lanes as f64;
    if own <= 0.0 {
        return 0.0;
    }
    if camera.len() + light.len() == 2 {
        // One strategy: the spectral MIS alone.
        return (1.0 / own) as f32;
    }
    // m_{s'} from the per-wavelength ratios R_j(s').
    let mean_of = |ratio: &[f64; SPECTRUM_SAMPLE_COUNT]| -> f64 {
        let mut total = 0.0;
        for j in 0..lanes {
            if path_ratio[j] > 0.0 {
                total += path_ratio[j] * ratio[j];
            }
        }
        total / lanes as f64
    };
    let step = |ratio: &mut [f64; SPECTRUM_SAMPLE_COUNT], vertex: &VertexDensities| {
        let geometric = remap(vertex.reverse) / remap(vertex.forward);
        for (j, value) in ratio.iter_mut().enumerate() {
            let forward = vertex.forward_free_flight[j] as f64;
            let reverse = vertex.reverse_free_flight[j] as f64;
            *value *= if forward > 0.0 {
                geometric * reverse / forward
            } else {
                0.0
            };
        }
    };
    let mut sum = power(own);
    let mut ratio = [1.0f64; SPECTRUM_SAMPLE_COUNT];
    for i in (1..camera.len()).rev() {
        step(&mut ratio, &camera[i]);
        if !camera[i].delta && !camera[i - 1].delta && (i > 1 || strategies.camera_connections) {
            sum += power(mean_of(&ratio));
        }
    }
    ratio = [1.0; SPECTRUM_SAMPLE_COUNT];
    for i in (0..light.len()).rev() {
        step(&mut ratio, &light[i]);
        let before_delta = if i > 0 {
            light[i - 1].delta
        } else {
            delta_light
        };
        if !light[i].delta && !before_delta {
            sum += power(mean_of(&ratio));
        }
    }
    let weight = match heuristic {
        MisHeuristic::Balance => 1.0 / sum,
        MisHeuristic::Power => own / sum,
    };
    if weight.is_finite() {
        weight as f32
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(heuristic: MisHeuristic) -> Strategies {
        Strategies {
            heuristic,
            camera_connections: true,
        }
    }

    fn vertex(forward: f32, reverse: f32) -> VertexDensities {
        VertexDensities::geometric(forward, reverse, false)
    }

    /// Densities of a path of four vertices under every split, from the
    /// per-vertex densities: p_s = Π light-side forward of the first s
    /// vertices (from the light end) × Π camera-side forward of the rest.
    /// The weights computed by the ratio walk for each split equal
    /// p_s^β / Σ p^β computed directly, and they sum to one.
    #[test]
    fn ratio_walk_equals_the_direct_heuristic() {
        // Vertices x₀ (light end) … x₃ (camera end). from_light[i]: density
        // of x_i sampled from the light side (x₀: the light's origin
        // density); from_camera[i]: from the camera side (x₃: the lens's).
        let from_light = [0.7f32, 1.3, 0.4, 2.0];
        let from_camera = [0.9f32, 0.25, 1.7, 1.0];
        let path_density = |s: usize| -> f64 {
            let light: f64 = from_light[..s].iter().map(|&d| d as f64).product();
            let camera: f64 = from_camera[s..].iter().map(|&d| d as f64).product();
            light * camera
        };
        for heuristic in [MisHeuristic::Balance, MisHeuristic::Power] {
            let exponent = if heuristic == MisHeuristic::Balance {
                1
            } else {
                2
            };
            // Splits s = 0 … 3 (t = 4 − s ≥ 1).
            let total: f64 = (0..4).map(|s| path_density(s).powi(exponent)).sum();
            let mut sum_of_weights = 0.0;
            for s in 0..4usize {
                let t = 4 - s;
                // Camera vertices z_j = x_{3−j}; light vertices y_i = x_i.
                let camera: Vec<VertexDensities> = (0..t)
                    .map(|j| vertex(from_camera[3 - j], from_light[3 - j]))
                    .collect();
                let light: Vec<VertexDensities> = (0..s)
                    .map(|i| vertex(from_light[i], from_camera[i]))
                    .collect();
                let weight = strategy_weight(&camera, &light, false, all(heuristic), None) as f64;
                let expected = path_density(s).powi(exponent) / total;
                assert!(
                    (weight - expected).abs() < 1e-6,
                    "{heuristic:?} s={s}: {weight} vs {expected}"
                );
                sum_of_weights += weight;
            }
            assert!((sum_of_weights - 1.0).abs() < 1e-6);
        }
    }

    /// In media, a path of four vertices whose densities differ per
    /// wavelength (a geometric part times a free flight's factor per
    /// wavelength): for every split s the spectral weight equals
    /// `p_{s,0} p̄_s^{β−1} / Σ_{s'} p̄_{s'}^β` computed directly, so that the
    /// throughput `f / p_{s,0}` times it is `f p̄_s^{β−1} / Σ p̄^β`; and
    /// `Σ_s p̄_s` times the contributions' density-weighted sum is `f`.
    #[test]
    fn spectral_weights_equal_the_direct_heuristic_over_averaged_densities() {
        let geometric_light = [0.7f32, 1.3, 0.4, 2.0];
        let geometric_camera = [0.9f32, 0.25, 1.7, 1.0];
        // Free flights per vertex and wavelength (x₀ on the light: none).
        let free_light = [
            [1.0f32, 1.0, 1.0, 1.0],
            [0.5, 0.9, 0.2, 1.4],
            [1.1, 0.3, 0.8, 0.6],
            [0.7, 0.7, 1.5, 0.25],
        ];
        let free_camera = [
            [0.4f32, 1.2, 0.9, 0.3],
            [0.8, 0.6, 1.3, 0.5],
            [0.9, 1.6, 0.35, 1.0],
            [1.0, 1.0, 1.0, 1.0],
        ];
        let density = |s: usize, j: usize| -> f64 {
            let light: f64 = (0..s)
                .map(|i| geometric_light[i] as f64 * free_light[i][j] as f64)
                .product();
            let camera: f64 = (s..4)
                .map(|i| geometric_camera[i] as f64 * free_camera[i][j] as f64)
                .product();
            light * camera
        };
        let averaged = |s: usize| (0..4).map(|j| density(s, j)).sum::<f64>() / 4.0;
        let spectrum = |values: [f32; 4]| SampledSpectrum::new(values);
        for heuristic in [MisHeuristic::Balance, MisHeuristic::Power] {
            let exponent = if heuristic == MisHeuristic::Balance {
                1
            } else {
                2
            };
            let total: f64 = (0..4).map(|s| averaged(s).powi(exponent)).sum();
            let mut unbiased = 0.0;
            for s in 0..4usize {
                let t = 4 - s;
                let camera: Vec<VertexDensities> = (0..t)
                    .map(|j| {
                        let x = 3 - j;
                        VertexDensities {
                            forward: geometric_camera[x],
                            reverse: geometric_light[x],
                            forward_free_flight: spectrum(free_camera[x]),
                            reverse_free_flight: spectrum(free_light[x]),
                            delta: false,
                        }
                    })
                    .collect();
                let light: Vec<VertexDensities> = (0..s)
                    .map(|i| VertexDensities {
                        forward: geometric_light[i],
                        reverse: geometric_camera[i],
                        forward_free_flight: spectrum(free_light[i]),
                        reverse_free_flight: spectrum(free_camera[i]),
                        delta: false,
                    })
                    .collect();
                let ratio = spectrum(std::array::from_fn(|j| {
                    (density(s, j) / density(s, 0)) as f32
                }));
                let weight =
                    strategy_weight(&camera, &light, false, all(heuristic), Some(&ratio)) as f64;
                let expected = density(s, 0) * averaged(s).powi(exponent - 1) / total;
                assert!(
                    (weight / expected - 1.0).abs() < 1e-5,
                    "{heuristic:?} s={s}: {weight} vs {expected}"
                );
                // The expectation over the hero choice of f · weight / p_{s,0}
                // with f = 1, summed over the strategies: Σ_s p̄_s w_s / p_{s,0}.
                unbiased += averaged(s) * weight / density(s, 0);
            }
            assert!((unbiased - 1.0).abs() < 1e-5, "{heuristic:?}: {unbiased}");
        }
    }

    /// A delta vertex removes the splits that would connect at it, and a
    /// delta light the split that would hit it.
    #[test]
    fn delta_vertices_remove_their_connections() {
        let camera = [vertex(1.0, 1.0), vertex(1.0, 1.0)];
        let light = [vertex(1.0, 1.0)];
        // Three splits of equal density: 1/3 each.
        let weight = strategy_weight(&camera, &light, false, all(MisHeuristic::Balance), None);
        assert!((weight - 1.0 / 3.0).abs() < 1e-6);
        // The light cannot be hit: two splits left.
        let weight = strategy_weight(&camera, &light, true, all(MisHeuristic::Balance), None);
        assert!((weight - 0.5).abs() < 1e-6);
        let mut specular = camera;
        specular[1].delta = true;
        // z₁ is a delta vertex: the split connecting z₁ to the light's
        // vertex is gone (the strategy itself is the caller's to rule out).
        let weight = strategy_weight(&specular, &light, false, all(MisHeuristic::Balance), None);
        assert!((weight - 1.0 / 2.0).abs() < 1e-6);
        assert_eq!(
            strategy_weight(&camera[..1], &light, false, all(MisHeuristic::Power), None),
            1.0
        );
        // Without light tracing the split with one camera vertex is gone.
        let without = Strategies {
            heuristic: MisHeuristic::Balance,
            camera_connections: false,
        };
        let weight = strategy_weight(&camera, &light, false, without, None);
        assert!((weight - 0.5).abs() < 1e-6);
    }
}

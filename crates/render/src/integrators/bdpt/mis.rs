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

use crate::integrators::MisHeuristic;

/// The densities of one vertex of a bidirectional path, per unit area (per
/// unit volume in a medium).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VertexDensities {
    /// Of sampling the vertex from its predecessor on its own subpath.
    pub forward: f32,
    /// Of sampling it from the other side (its successor on its subpath).
    pub reverse: f32,
    /// The vertex scattered by a delta lobe (no connection can join it).
    pub delta: bool,
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
pub fn strategy_weight(
    camera: &[VertexDensities],
    light: &[VertexDensities],
    delta_light: bool,
    strategies: Strategies,
) -> f32 {
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
        VertexDensities {
            forward,
            reverse,
            delta: false,
        }
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
                let weight = strategy_weight(&camera, &light, false, all(heuristic)) as f64;
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

    /// A delta vertex removes the splits that would connect at it, and a
    /// delta light the split that would hit it.
    #[test]
    fn delta_vertices_remove_their_connections() {
        let camera = [vertex(1.0, 1.0), vertex(1.0, 1.0)];
        let light = [vertex(1.0, 1.0)];
        // Three splits of equal density: 1/3 each.
        let weight = strategy_weight(&camera, &light, false, all(MisHeuristic::Balance));
        assert!((weight - 1.0 / 3.0).abs() < 1e-6);
        // The light cannot be hit: two splits left.
        let weight = strategy_weight(&camera, &light, true, all(MisHeuristic::Balance));
        assert!((weight - 0.5).abs() < 1e-6);
        let mut specular = camera;
        specular[1].delta = true;
        // z₁ is a delta vertex: the split connecting z₁ to the light's
        // vertex is gone (the strategy itself is the caller's to rule out).
        let weight = strategy_weight(&specular, &light, false, all(MisHeuristic::Balance));
        assert!((weight - 1.0 / 2.0).abs() < 1e-6);
        assert_eq!(
            strategy_weight(&camera[..1], &light, false, all(MisHeuristic::Power)),
            1.0
        );
        // Without light tracing the split with one camera vertex is gone.
        let without = Strategies {
            heuristic: MisHeuristic::Balance,
            camera_connections: false,
        };
        let weight = strategy_weight(&camera, &light, false, without);
        assert!((weight - 0.5).abs() < 1e-6);
    }
}

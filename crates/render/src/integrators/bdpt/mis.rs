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
    /// The vertex is on a surface (not in a medium): vertex merging
    /// ([`technique_weight`]) happens on surfaces only.
    pub on_surface: bool,
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
            on_surface: true,
        }
    }

    /// Sets the reverse density: `geometric` times `free_flight`.
    #[inline]
    pub fn set_reverse(&mut self, geometric: f32, free_flight: SampledSpectrum) {
        self.reverse = geometric;
        self.reverse_free_flight = free_flight;
    }
}

/// Which strategies a render uses besides the always-present one (the
/// camera subpath reaching a light), and the heuristic that weighs them:
/// BDPT's connections, and vertex connection and merging's merges
/// (Georgiev et al. 2012; every mode of `--vcm-mode` is such a set).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Strategies {
    /// The heuristic.
    pub heuristic: MisHeuristic,
    /// Connections with s ≥ 1 (next-event estimation, subpath connections,
    /// light tracing): BDPT's; off for bidirectional photon mapping.
    pub connections: bool,
    /// Whether the strategies with t = 1 (light tracing: the light
    /// subpath's vertices connected to the camera) are among the
    /// connections; Kollig & Keller leave them out for OFFICE.
    pub camera_connections: bool,
    /// Vertex merging, with η = π r² N_VM / N_VC: the merging disc's area
    /// times the light subpaths each camera subpath merges with, over those
    /// it connects to (one). A merge at a vertex has the density of the
    /// connection there times η times the density of the vertex sampled
    /// from the light side (Georgiev et al. 2012, §4).
    pub merging: Option<f32>,
}

impl Strategies {
    /// BDPT's strategies: every connection, light tracing if
    /// `camera_connections`, no merging.
    pub fn bidirectional(heuristic: MisHeuristic, camera_connections: bool) -> Self {
        Self {
            heuristic,
            connections: true,
            camera_connections,
            merging: None,
        }
    }
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
    if strategies.merging.is_some() || !strategies.connections {
        return technique_weight(
            camera,
            light,
            delta_light,
            strategies,
            OwnTechnique::Connection,
            spectral_density_ratio,
        );
    }
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

/// Which technique made the path whose weight is asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OwnTechnique {
    /// The connection of the split the densities describe (s, t).
    Connection,
    /// A merge at the camera subpath's last vertex `z_{t−1}`: the light
    /// subpath reached a point near it after `y_{s−1}`; the densities are
    /// those of the split (s, t), `z_{t−1}`'s reverse density its density
    /// as sampled from `y_{s−1}`.
    MergeAtCameraEnd,
}

/// Whether a vertex can be merged at: a surface point whose scattering is
/// not a delta lobe (VCM here merges on surfaces only).
#[inline]
fn mergeable(vertex: &VertexDensities) -> bool {
    vertex.on_surface && !vertex.delta
}

/// The multiple-importance weight of technique `own` over the strategies
/// `techniques` (vertex connection and merging), for the path of the
/// split (s, t) described by `camera` (`z₀` first) and `light` (`y₀`
/// first) as in [`strategy_weight`]. The ratio walk of the module docs,
/// with a merge at each vertex `x` besides the connections: its density
/// relative to the split whose connection joins `x` to its light-side
/// neighbour is η times `x`'s density sampled from the light side
/// (Georgiev et al. 2012, Eq. 11; SmallVCM's dVCM, dVC and dVM are the
/// same sums, accumulated along the subpaths). A merge needs a mergeable
/// vertex that is neither the lens `z₀` nor the light's own point `y₀`.
///
/// In media, `spectral_density_ratio` is as in [`strategy_weight`] (the
/// path's `r_j` for the split (s, t)) and the combination with the choice
/// of hero wavelength is the same: `m_X = mean_j r_j R_j(X)` per
/// technique X, weight `(p_{own,0} / p_{s,0}) m_own^{β−1} / Σ_X m_X^β`.
pub fn technique_weight(
    camera: &[VertexDensities],
    light: &[VertexDensities],
    delta_light: bool,
    techniques: Strategies,
    own: OwnTechnique,
    spectral_density_ratio: Option<&SampledSpectrum>,
) -> f32 {
    match spectral_density_ratio {
        // r_j, with wavelengths the strategy cannot sample as hero left out.
        Some(ratio) => technique_weight_in_lanes(
            camera,
            light,
            delta_light,
            techniques,
            own,
            std::array::from_fn::<f64, SPECTRUM_SAMPLE_COUNT, _>(|j| {
                let r = ratio[j] as f64;
                if r.is_finite() && r > 0.0 { r } else { 0.0 }
            }),
        ),
        // Without media every wavelength has the same densities: one lane.
        None => technique_weight_in_lanes(camera, light, delta_light, techniques, own, [1.0]),
    }
}

/// [`technique_weight`] over `LANES` wavelengths whose `r_j` are
/// `path_ratio` (one lane of ratio 1 without media).
fn technique_weight_in_lanes<const LANES: usize>(
    camera: &[VertexDensities],
    light: &[VertexDensities],
    delta_light: bool,
    techniques: Strategies,
    own: OwnTechnique,
    path_ratio: [f64; LANES],
) -> f32 {
    let (s, t) = (light.len(), camera.len());
    let heuristic = techniques.heuristic;
    let power = |value: f64| match heuristic {
        MisHeuristic::Balance => value,
        MisHeuristic::Power => value * value,
    };
    let remap = |density: f32| if density != 0.0 { density } else { 1.0 } as f64;
    let mean_of = |ratio: &[f64; LANES]| -> f64 {
        (0..LANES).map(|j| path_ratio[j] * ratio[j]).sum::<f64>() / LANES as f64
    };
    let step = |ratio: &mut [f64; LANES], vertex: &VertexDensities| {
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
    // A merge at `vertex`, from the split with ratios `ratio`: times η and
    // the vertex's light-side density (with its free flight).
    let merge = |ratio: &[f64; LANES], vertex: &VertexDensities, eta: f32| -> [f64; LANES] {
        std::array::from_fn(|j| {
            ratio[j] * vertex.reverse as f64 * vertex.reverse_free_flight[j] as f64 * eta as f64
        })
    };
    // Whether the connection joining the last `i` camera vertices' side to
    // the rest is a technique of the set: between z_{i−1} and z_i.
    let connection = |before: &VertexDensities, after: &VertexDensities, light_count: usize| {
        if light_count == 0 {
            // The camera subpath reaching the light.
            !delta_light
        } else {
            techniques.connections && !before.delta && !after.delta
        }
    };

    let ones = [1.0f64; LANES];
    let mut sum = 0.0f64;
    // The split (s, t) itself.
    let own_split = match (s, t) {
        (_, 0) => false,
        (0, _) => !delta_light,
        (_, 1) => techniques.connections && techniques.camera_connections && !light[s - 1].delta,
        _ => techniques.connections && !light[s - 1].delta && !camera[t - 1].delta,
    };
    let own_split = own == OwnTechnique::Connection || own_split;
    if own_split {
        sum += power(mean_of(&ones));
    }
    let mut own_relative = match own {
        OwnTechnique::Connection => Some(ones),
        OwnTechnique::MergeAtCameraEnd => None,
    };
    // A path of two vertices (the lens and the light's point) has one
    // technique, the camera subpath reaching the light (BDPT leaves (1, 1)
    // to it): only the split's own term.
    let others = if s + t > 2 { t } else { 0 };
    // The camera side: merges at z_i and connections between z_{i−1}, z_i.
    let mut ratio = ones;
    for i in (1..others).rev() {
        if let Some(eta) = techniques.merging
            && mergeable(&camera[i])
            && s + t - i >= 2
        {
            let merged = merge(&ratio, &camera[i], eta);
            if i == t - 1 && own == OwnTechnique::MergeAtCameraEnd {
                own_relative = Some(merged);
            }
            sum += power(mean_of(&merged));
        }
        step(&mut ratio, &camera[i]);
        let light_count = s + t - i;
        let allowed = if i == 1 {
            techniques.camera_connections
        } else {
            true
        };
        if allowed && connection(&camera[i - 1], &camera[i], light_count) {
            sum += power(mean_of(&ratio));
        }
    }
    // The light side: merges at y_i (i ≥ 1) and connections between y_{i−1}
    // and y_i (i = 0: the camera subpath reaching the light).
    ratio = ones;
    let others = if s + t > 2 { s } else { 0 };
    for i in (0..others).rev() {
        if i >= 1
            && let Some(eta) = techniques.merging
            && mergeable(&light[i])
        {
            sum += power(mean_of(&merge(&ratio, &light[i], eta)));
        }
        step(&mut ratio, &light[i]);
        let counted = if i == 0 {
            !light[0].delta && !delta_light
        } else {
            connection(&light[i - 1], &light[i], i)
        };
        if counted {
            sum += power(mean_of(&ratio));
        }
    }
    let Some(own_relative) = own_relative else {
        // The merge is not a technique of the set here.
        return 0.0;
    };
    let own_mean = mean_of(&own_relative);
    let weight = match heuristic {
        MisHeuristic::Balance => own_relative[0] / sum,
        MisHeuristic::Power => own_relative[0] * own_mean / sum,
    };
    if weight.is_finite() && sum > 0.0 {
        weight as f32
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(heuristic: MisHeuristic) -> Strategies {
        Strategies::bidirectional(heuristic, true)
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
                            on_surface: true,
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
                        on_surface: true,
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
        let without = Strategies::bidirectional(MisHeuristic::Balance, false);
        let weight = strategy_weight(&camera, &light, false, without, None);
        assert!((weight - 0.5).abs() < 1e-6);
    }

    /// The path of `ratio_walk_equals_the_direct_heuristic` as split (s, t)
    /// sees it: camera vertices z_j = x_{3−j}, light vertices y_i = x_i.
    fn split(
        from_light: &[f32; 4],
        from_camera: &[f32; 4],
        s: usize,
    ) -> (Vec<VertexDensities>, Vec<VertexDensities>) {
        let t = 4 - s;
        let camera = (0..t)
            .map(|j| vertex(from_camera[3 - j], from_light[3 - j]))
            .collect();
        let light = (0..s)
            .map(|i| vertex(from_light[i], from_camera[i]))
            .collect();
        (camera, light)
    }

    /// Without merging, the technique weight of a connection is BDPT's.
    #[test]
    fn technique_weight_without_merging_is_the_strategy_weight() {
        let from_light = [0.7f32, 1.3, 0.4, 2.0];
        let from_camera = [0.9f32, 0.25, 1.7, 1.0];
        let ratio = SampledSpectrum::new([1.0, 0.6, 1.7, 0.3]);
        for heuristic in [MisHeuristic::Balance, MisHeuristic::Power] {
            for camera_connections in [true, false] {
                let techniques = Strategies::bidirectional(heuristic, camera_connections);
                let strategies = techniques;
                for s in 0..3usize {
                    let (camera, light) = split(&from_light, &from_camera, s);
                    for spectral in [None, Some(&ratio)] {
                        let expected =
                            strategy_weight(&camera, &light, false, strategies, spectral);
                        let actual = technique_weight(
                            &camera,
                            &light,
                            false,
                            techniques,
                            OwnTechnique::Connection,
                            spectral,
                        );
                        assert!(
                            (actual - expected).abs() < 1e-6,
                            "{heuristic:?} s={s}: {actual} vs {expected}"
                        );
                    }
                }
            }
        }
    }

    /// A path of four vertices x₀ (light) … x₃ (lens) made by every
    /// connection (s = 0 … 3) and every merge (at x₁ and x₂, η = 0.37):
    /// each technique's weight equals p^β / Σ p^β computed directly from
    /// the per-vertex densities (a merge at x_k: the connection density of
    /// split k times η times x_k's light-side density), and they sum to
    /// one; with connections off (`bpm`), the same over the light hit and
    /// the merges.
    #[test]
    fn merging_weights_equal_the_direct_heuristic() {
        let from_light = [0.7f32, 1.3, 0.4, 2.0];
        let from_camera = [0.9f32, 0.25, 1.7, 1.0];
        let eta = 0.37f64;
        let path_density = |s: usize| -> f64 {
            let light: f64 = from_light[..s].iter().map(|&d| d as f64).product();
            let camera: f64 = from_camera[s..].iter().map(|&d| d as f64).product();
            light * camera
        };
        let merge_density = |k: usize| path_density(k) * from_light[k] as f64 * eta;
        for heuristic in [MisHeuristic::Balance, MisHeuristic::Power] {
            for connections in [true, false] {
                let exponent = if heuristic == MisHeuristic::Balance {
                    1
                } else {
                    2
                };
                let techniques = Strategies {
                    heuristic,
                    connections,
                    camera_connections: true,
                    merging: Some(eta as f32),
                };
                let connection_splits: Vec<usize> = if connections {
                    vec![0, 1, 2, 3]
                } else {
                    vec![0]
                };
                let total: f64 = connection_splits
                    .iter()
                    .map(|&s| path_density(s).powi(exponent))
                    .sum::<f64>()
                    + [1, 2]
                        .iter()
                        .map(|&k| merge_density(k).powi(exponent))
                        .sum::<f64>();
                let mut sum_of_weights = 0.0;
                for &s in &connection_splits {
                    let (camera, light) = split(&from_light, &from_camera, s);
                    let weight = technique_weight(
                        &camera,
                        &light,
                        false,
                        techniques,
                        OwnTechnique::Connection,
                        None,
                    ) as f64;
                    let expected = path_density(s).powi(exponent) / total;
                    assert!(
                        (weight - expected).abs() < 1e-6,
                        "{heuristic:?} {connections} s={s}: {weight} vs {expected}"
                    );
                    sum_of_weights += weight;
                }
                for k in [1usize, 2] {
                    // The merge at x_k as split (k, 4 − k) sees it: z_{t−1} = x_k.
                    let (camera, light) = split(&from_light, &from_camera, k);
                    let weight = technique_weight(
                        &camera,
                        &light,
                        false,
                        techniques,
                        OwnTechnique::MergeAtCameraEnd,
                        None,
                    ) as f64;
                    let expected = merge_density(k).powi(exponent) / total;
                    assert!(
                        (weight - expected).abs() < 1e-6,
                        "{heuristic:?} {connections} merge at x{k}: {weight} vs {expected}"
                    );
                    sum_of_weights += weight;
                }
                assert!((sum_of_weights - 1.0).abs() < 1e-6, "{sum_of_weights}");
            }
        }
    }

    /// No merge at a delta vertex or in a medium, at the lens or at the
    /// light's own point.
    #[test]
    fn merges_need_a_surface_vertex_that_is_not_delta() {
        let techniques = Strategies {
            heuristic: MisHeuristic::Balance,
            connections: true,
            camera_connections: true,
            merging: Some(1.0),
        };
        let camera = [vertex(1.0, 1.0), vertex(1.0, 1.0)];
        let light = [vertex(1.0, 1.0)];
        // Splits s = 0, 1, 2 and the merge at the middle vertex: 1/4 each.
        let own = OwnTechnique::MergeAtCameraEnd;
        let weight = technique_weight(&camera, &light, false, techniques, own, None);
        assert!((weight - 0.25).abs() < 1e-6, "{weight}");
        let mut in_medium = camera;
        in_medium[1].on_surface = false;
        assert_eq!(
            technique_weight(&in_medium, &light, false, techniques, own, None),
            0.0
        );
        let weight = technique_weight(
            &in_medium,
            &light,
            false,
            techniques,
            OwnTechnique::Connection,
            None,
        );
        assert!((weight - 1.0 / 3.0).abs() < 1e-6, "{weight}");
        // Two vertices (the lens and the light's point): one technique, as
        // in BDPT, and nothing to merge.
        let weight = technique_weight(
            &camera[..1],
            &light,
            false,
            techniques,
            OwnTechnique::Connection,
            None,
        );
        assert_eq!(weight, 1.0);
    }
}

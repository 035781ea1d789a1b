//! Vertex merging (Georgiev, Křivánek, Davidovič & Slusallek 2012): the
//! camera subpath of a pixel sample of an iteration, traced by BDPT
//! ([`crate::integrators::bdpt`]), merges each of its vertices with the
//! iteration's light vertices near it. [`MergingPass`] is what BDPT's
//! sample asks of the iteration ([`LightSubpathPass`]): the shared
//! wavelengths, time and strategies, the light subpath traced for the
//! pixel, and the merges with their weights.

use super::{LightStore, LightVertexRecord, NearbySearch};
use crate::integrators::bdpt::mis::{OwnTechnique, Strategies, VertexDensities, technique_weight};
use crate::integrators::bdpt::{
    Bidirectional, LightOrigin, LightSubpathPass, light_vertex_reverse,
    set_camera_predecessor_reverse,
};
use crate::integrators::path_space::{Scatterer, Vertex};
use crate::material::TransportMode;
use crate::spectrum::{SampledWavelengths, to_linear_srgb};
use glam::Vec3;

/// A work unit's merging scratch space, kept from sample to sample.
#[derive(Debug, Default)]
pub(super) struct MergeScratch {
    /// The merges done, counted.
    pub count: u64,
    /// The t of each camera vertex that merges (a query of `nearby`).
    ends: Vec<usize>,
    /// Their points.
    points: Vec<Vec3>,
    /// The light vertices near them.
    nearby: NearbySearch,
}

/// What a camera subpath of an iteration needs of it.
pub(super) struct MergingPass<'a> {
    /// The iteration's wavelengths.
    pub wavelengths: SampledWavelengths,
    /// The iteration's time sample (0.5 without motion blur).
    pub time_sample: f32,
    /// The techniques and η.
    pub strategies: Strategies,
    /// Photon mapping: merge at the first non-specular vertex, no MIS.
    pub first_merge_only: bool,
    /// 1 / (π r² N).
    pub normalisation: f32,
    /// The light subpaths.
    pub lights: &'a LightStore,
    /// The pixel whose camera subpath merges: it connects to the light
    /// subpath traced for it.
    pub pixel: (u32, u32),
    /// The work unit's scratch space.
    pub scratch: &'a mut MergeScratch,
}

impl<'a> LightSubpathPass<'a> for MergingPass<'a> {
    fn wavelengths(&self) -> SampledWavelengths {
        self.wavelengths
    }

    fn time_sample(&self) -> f32 {
        self.time_sample
    }

    fn strategies(&self) -> Strategies {
        self.strategies
    }

    fn prefetch_light_subpath(&self) {
        self.lights.prefetch_pixel_path(self.pixel);
    }

    fn light_subpath(&self) -> (Option<LightOrigin>, &'a [Vertex], bool) {
        let lights: &'a LightStore = self.lights;
        let (path, vertices) = lights.pixel_path(self.pixel);
        (path.origin, vertices, path.secondary_terminated)
    }

    /// Photon mapping: only light seen through delta lobes (the rest is
    /// merged).
    fn reached_light_weight(&self, camera: &[Vertex], vertices_before: usize) -> Option<f32> {
        self.first_merge_only
            .then(|| only_delta_before(camera, vertices_before))
    }

    /// The camera vertices of `camera` that merge with the pass's light
    /// vertices (their t and their points) and the light vertices near
    /// each, asked of the cache: found before the connections, merged after
    /// them, so that the misses are waited for while the connections are
    /// traced.
    fn find_merge_partners(&mut self, camera: &[Vertex], max_depth: usize) {
        let MergeScratch {
            ends,
            points,
            nearby,
            ..
        } = &mut *self.scratch;
        ends.clear();
        points.clear();
        // A merge at z_{t−1} makes a path of at least t segments.
        for t in 2..=(camera.len() + 1).min(max_depth) {
            let end = &camera[t - 2];
            if matches!(end.scatterer, Scatterer::Surface { .. }) && end.is_connectible() {
                ends.push(t);
                points.push(end.point);
                if self.first_merge_only {
                    break;
                }
            }
        }
        self.lights.find_near(points, nearby);
        self.lights.prefetch(&nearby.found);
    }

    /// Vertex merging: every surface vertex of the camera subpath `camera`
    /// that is not purely specular merges with each light vertex of the
    /// pass within its radius, weighted against every technique of the
    /// pass's strategies (with photon mapping's `first_merge_only`, at the
    /// first such vertex only, weight 1). A merge of `z_{t−1}` with the
    /// light vertex `y_s` reached from `y_{s−1}` is the path `y₀ … y_{s−1}
    /// z_{t−1} … z₀`: its value is `β(z_{t−1}) f(z_{t−1}; wo, wi) β(y_s) /
    /// (π r² N)`, the BSDF without a cosine (the light subpath's density at
    /// `y_s` holds it) but with the shading normal's `|wi·ns| / |wi·ng|`,
    /// `wi` the direction the light arrived from. Returns the sum in linear
    /// sRGB, each merge converted with the wavelengths of its two subpaths.
    fn merges(
        &mut self,
        bidirectional: &Bidirectional<'_>,
        camera: &[Vertex],
        camera_wavelengths: &SampledWavelengths,
        camera_densities: &mut Vec<VertexDensities>,
        light_densities: &mut Vec<VertexDensities>,
    ) -> [f32; 3] {
        let max_depth = bidirectional.max_depth();
        let MergeScratch {
            count,
            ends,
            nearby,
            ..
        } = &mut *self.scratch;
        let mut rgb = [0.0f32; 3];
        let mut densities_of = usize::MAX;
        for (query, point) in &nearby.found {
            let t = ends[*query as usize];
            let end = &camera[t - 2];
            let Scatterer::Surface { hit, bsdf, .. } = &end.scatterer else {
                continue;
            };
            let (light_path, light, k) = self.lights.vertex(point);
            // The light vertex y_s = light[k], s = k + 1 vertices before it.
            let s = k + 1;
            if s + t - 1 > max_depth {
                continue;
            }
            let Some(origin) = &light_path.origin else {
                continue;
            };
            let photon = &light[k];
            let wi = photon.wo;
            let cosine_geometric = wi.dot(hit.geometric_normal).abs();
            if cosine_geometric == 0.0 {
                continue;
            }
            let mut wavelengths = *camera_wavelengths;
            if light_path.secondary_terminated {
                wavelengths.terminate_secondary();
            }
            let shading = bsdf.shading_normal_for(end.wo, wi, TransportMode::Radiance);
            let value = end.beta
                * bsdf.evaluate(end.wo, wi, &wavelengths)
                * photon.beta
                * (origin.beta_scale * wi.dot(shading).abs() / cosine_geometric
                    * self.normalisation);
            *count += 1;
            if value.is_black() {
                continue;
            }
            let weight = if self.first_merge_only {
                1.0
            } else {
                // The camera subpath's densities up to z_{t−1}, once per
                // camera vertex (a merge sets only the last two's reverse
                // densities).
                if densities_of != t {
                    bidirectional.subpath_densities(
                        VertexDensities::default(),
                        camera,
                        t,
                        camera_densities,
                    );
                    densities_of = t;
                }
                merge_weight(
                    bidirectional,
                    camera,
                    t,
                    origin,
                    light,
                    k,
                    self.strategies,
                    camera_densities,
                    light_densities,
                )
            };
            let merged = to_linear_srgb(&(value * weight), &wavelengths);
            for channel in 0..3 {
                rgb[channel] += merged[channel];
            }
        }
        rgb
    }
}

/// 1 if the camera subpath's first `count` vertices all scattered by delta
/// lobes, else 0: photon mapping's weight for light the camera subpath
/// reached (only through specular chains, the rest being merged).
fn only_delta_before(camera: &[Vertex], count: usize) -> f32 {
    if camera[..count].iter().all(|vertex| vertex.delta) {
        1.0
    } else {
        0.0
    }
}

/// The weight of the merge of `z_{t−1}` (`camera[t − 2]`) with the light
/// vertex `light[k]` (`y_s`, s = k + 1) against the strategies: the
/// densities of the split (s, t) with `z_{t−1}` sampled from `y_{s−1}` as
/// the light subpath sampled `y_s`. `camera_densities` holds the camera
/// subpath's t densities ([`Bidirectional::subpath_densities`]); the last
/// two's reverse densities are set here.
#[allow(clippy::too_many_arguments)]
fn merge_weight(
    bidirectional: &Bidirectional<'_>,
    camera: &[Vertex],
    t: usize,
    origin: &LightOrigin,
    light: &[LightVertexRecord],
    k: usize,
    strategies: Strategies,
    camera_densities: &mut [VertexDensities],
    light_densities: &mut Vec<VertexDensities>,
) -> f32 {
    let s = k + 1;
    let end = &camera[t - 2];
    let photon = &light[k];
    let wi = photon.wo;
    camera_densities[t - 1].set_reverse(photon.pdf_forward, photon.arrival_transmittance);
    camera_densities[t - 1].delta = false;
    set_camera_predecessor_reverse(camera, t, wi, camera_densities);
    light_densities.clear();
    light_densities.push(origin.densities);
    light_densities.extend(light[..k].iter().map(|record| record.densities));
    let before = (s >= 2).then(|| {
        let before = &light[k - 1];
        (before.point, before.geometric_normal, before.extinction)
    });
    let (density, free_flight) =
        light_vertex_reverse(end, end.wo, before, origin, photon.arrival_transmittance);
    light_densities[s - 1].set_reverse(density, free_flight);
    let spectral_density_ratio = if s >= 2 {
        end.spectral_density_ratio * light[k - 1].spectral_density_ratio
    } else {
        end.spectral_density_ratio
    };
    technique_weight(
        camera_densities,
        light_densities,
        origin.delta_light,
        strategies,
        OwnTechnique::MergeAtCameraEnd,
        bidirectional.has_media().then_some(&spectral_density_ratio),
    )
}

//! Heinrich & Keller's particle simulation of the radiance equation (1994,
//! §4): the radiance arriving at every triangle of a scene after exactly
//! m = 0 … M reflections, `⟨T^m L₀, Ψ⟩` with `Ψ = G · χ_A` (their Eqs.
//! 10–14), estimated by particles whose numbers come from one point of a
//! point set in `[0, 1)^{2M+4}` each.
//!
//! A particle starts uniformly on the light surfaces: the first coordinate
//! chooses a light patch in proportion to its area (and is rescaled to
//! [0, 1) within it), the first two coordinates then place the point on it
//! (a rectangle's two edge parameters, as in the paper; a triangle's by
//! the square-root map). It leaves in local spherical coordinates
//! `(φ, ϑ)` with the paper's substitution `τ = (1 − cos 2ϑ) / 2 = sin²ϑ`
//! (cosine-weighted): coordinates 2, 3 are `(φ / 2π, τ)`; reflection j
//! takes coordinates `2j + 4, 2j + 5` the same way. Point i thus uses its
//! first `2m + 4` coordinates for the terms up to m.
//!
//! The particles are walks of the path-space core ([`super::path_space`],
//! importance transport, no Russian roulette, M + 1 vertices): the walk
//! asks for its numbers by the light-subpath layout, and [`ParticleNumbers`]
//! answers from the point (for a reflection's direction, the pair that the
//! diffuse BSDF's concentric mapping takes to the paper's `(φ, τ)`
//! direction, so that the point set integrates the paper's integrand).
//! Transport is RGB, as the paper's tables: each triangle has the RGB
//! reflectance of its diffuse material, each light its RGB radiance; a
//! particle carries the lights' total power over N and is multiplied by
//! the reflectance of every triangle it reflects at. Each segment's end
//! receives the particle's flux: the sum over the particles is the flux
//! arriving at each triangle after m reflections, and over the triangle's
//! area its irradiance ("radiance arriving at A" in the paper's words).

use super::TraceCounters;
use super::path_space::{
    SubpathLayout, VertexAt, WalkObserver, WalkSettings, WalkStart, WalkState, walk,
};
use crate::geometry::{OffsetPoint, Ray};
use crate::material::TransportMode;
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::scene::description::{
    MaterialDescription, SceneDescription, ShapeGeometry, SpectrumDescription, TextureDescription,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
use std::ops::ControlFlow;

/// Why a scene cannot be simulated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParticleSceneError {
    /// A shape is not a triangle mesh.
    #[error("shape {0} is not a triangle mesh (the particle study needs triangles)")]
    NotAMesh(usize),
    /// A shape's material is not diffuse with a constant RGB reflectance.
    #[error(
        "shape {0}: the particle study needs diffuse materials with a constant RGB reflectance (or black emitters)"
    )]
    UnsupportedMaterial(usize),
    /// An emitter whose radiance is not a constant RGB value.
    #[error("shape {0}: the particle study needs constant RGB emission")]
    UnsupportedEmission(usize),
    /// Nothing emits.
    #[error("no shape emits light")]
    NoLights,
    /// The scene does not build.
    #[error("the scene does not build: {0}")]
    Build(String),
}

/// A light patch particles start on.
#[derive(Debug, Clone, Copy)]
struct LightPatch {
    /// A corner.
    corner: Vec3,
    /// The two edges from the corner.
    edges: [Vec3; 2],
    /// A rectangle (parallelogram) or the triangle of the two edges.
    parallelogram: bool,
    /// The unit normal particles leave along (the side the light faces).
    normal: Vec3,
    /// The area.
    area: f64,
}

/// A scene prepared for the particle simulation.
pub struct ParticleScene {
    scene: Scene,
    /// Per shape, the index of its first triangle in the scene-wide numbering.
    first_triangle: Vec<u32>,
    /// Per triangle, its area.
    areas: Vec<f64>,
    /// Per triangle, its RGB reflectance (zero for emitters).
    reflectances: Vec<[f64; 3]>,
    lights: Vec<LightPatch>,
    /// Cumulative areas of the light patches over the total.
    light_cdf: Vec<f64>,
    /// The power the lights emit (RGB): π L A summed.
    power: [f64; 3],
}

impl ParticleScene {
    /// Prepares `description`: every shape a triangle mesh with a diffuse
    /// material of constant RGB reflectance or a black one, emitters with
    /// a constant RGB radiance (a two-triangle parallelogram is one
    /// rectangular light, other emitting meshes a light per triangle).
    pub fn new(description: &SceneDescription) -> Result<Self, ParticleSceneError> {
        let mut first_triangle = Vec::new();
        let mut areas = Vec::new();
        let mut reflectances = Vec::new();
        let mut lights = Vec::new();
        let mut power = [0.0f64; 3];
        for (index, shape) in description.shapes.iter().enumerate() {
            let ShapeGeometry::Mesh {
                positions,
                triangles,
                ..
            } = &shape.geometry
            else {
                return Err(ParticleSceneError::NotAMesh(index));
            };
            first_triangle.push(areas.len() as u32);
            let reflectance = match &shape.material {
                MaterialDescription::Diffuse {
                    reflectance: TextureDescription::Constant(SpectrumDescription::Rgb(rgb)),
                    ..
                } => rgb.map(f64::from),
                MaterialDescription::Black => [0.0; 3],
                _ => return Err(ParticleSceneError::UnsupportedMaterial(index)),
            };
            let corners = |triangle: &[u32; 3]| triangle.map(|vertex| positions[vertex as usize]);
            for triangle in triangles {
                let [a, b, c] = corners(triangle);
                areas.push(0.5 * (b - a).cross(c - a).length() as f64);
                reflectances.push(reflectance);
            }
            let Some(emission) = &shape.emission else {
                continue;
            };
            let SpectrumDescription::Rgb(radiance) = emission else {
                return Err(ParticleSceneError::UnsupportedEmission(index));
            };
            let patches = light_patches(triangles, positions, |triangle| corners(triangle));
            for patch in patches {
                for (total, value) in power.iter_mut().zip(radiance) {
                    *total += std::f64::consts::PI * *value as f64 * patch.area;
                }
                lights.push(patch);
            }
        }
        if lights.is_empty() {
            return Err(ParticleSceneError::NoLights);
        }
        let total_area: f64 = lights.iter().map(|light| light.area).sum();
        let mut cumulative = 0.0;
        let light_cdf = lights
            .iter()
            .map(|light| {
                cumulative += light.area / total_area;
                cumulative
            })
            .collect();
        let scene = Scene::build(description)
            .map_err(|error| ParticleSceneError::Build(error.to_string()))?;
        Ok(Self {
            scene,
            first_triangle,
            areas,
            reflectances,
            lights,
            light_cdf,
            power,
        })
    }

    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.areas.len()
    }

    /// The triangles' areas, in the scene-wide numbering (shapes in order,
    /// each mesh's triangles in order).
    pub fn areas(&self) -> &[f64] {
        &self.areas
    }

    /// The lights' total power, RGB.
    pub fn power(&self) -> [f64; 3] {
        self.power
    }

    /// Traces the particle of `point` (at least `2 · bounces + 4`
    /// coordinates) and adds `weight` times its flux to `flux`, laid out
    /// as `(bounces + 1)` rows of one RGB triple per triangle: row m is
    /// the flux arriving after m reflections. Returns the rays traced.
    pub fn trace(&self, point: &[f64], bounces: usize, weight: f64, flux: &mut [[f64; 3]]) -> u64 {
        debug_assert!(point.len() >= 2 * bounces + 4);
        debug_assert!(flux.len() >= (bounces + 1) * self.triangle_count());
        // The light patch, with the first coordinate rescaled within it.
        let u0 = point[0];
        let chosen = self
            .light_cdf
            .partition_point(|&cumulative| cumulative <= u0)
            .min(self.lights.len() - 1);
        let below = if chosen == 0 {
            0.0
        } else {
            self.light_cdf[chosen - 1]
        };
        let width = self.light_cdf[chosen] - below;
        let u = if width > 0.0 {
            ((u0 - below) / width).clamp(0.0, 1.0 - f64::EPSILON)
        } else {
            0.5
        };
        let light = &self.lights[chosen];
        let (s, t) = (u as f32, point[1] as f32);
        let origin = if light.parallelogram {
            light.corner + light.edges[0] * s + light.edges[1] * t
        } else {
            // The square-root map (Turk 1990): uniform on the triangle.
            let root = s.sqrt();
            light.corner + light.edges[0] * (root * (1.0 - t)) + light.edges[1] * (root * t)
        };
        let local = paper_direction(point[2] as f32, point[3] as f32);
        let (tangent, bitangent) = crate::geometry::coordinate_frame(light.normal);
        let direction =
            (tangent * local.x + bitangent * local.y + light.normal * local.z).normalize();
        let ray_origin = OffsetPoint::new(origin, light.normal, direction).towards(direction);
        let start_flux = self.power.map(|channel| channel * weight);
        let mut observer = FluxDeposit {
            scene: self,
            flux,
            carried: start_flux,
            triangle: 0,
        };
        let mut numbers = ParticleNumbers { point };
        let mut wavelengths = SampledWavelengths::sample_visible(0.5);
        let mut counters = TraceCounters::default();
        walk(
            &self.scene,
            WalkStart {
                ray: Ray::with_time(ray_origin, direction, 0.0),
                beta: SampledSpectrum::splat(1.0),
                pdf_direction: 0.0,
                medium: None,
            },
            &WalkSettings {
                mode: TransportMode::Importance,
                max_vertices: bounces + 1,
                russian_roulette_depth: u32::MAX,
                layout: SubpathLayout::LIGHT,
                media: false,
                null_crossings: false,
            },
            &mut wavelengths,
            &mut numbers,
            &mut counters,
            &mut observer,
        );
        counters.closest_hit_rays
    }
}

/// The result of a simulation: the flux arriving at every triangle after m
/// = 0 … M reflections (RGB), and the rays traced.
#[derive(Debug, Clone, PartialEq)]
pub struct FluxTable {
    /// M.
    pub bounces: usize,
    /// The number of triangles.
    pub triangles: usize,
    /// Row m, triangle t at `m · triangles + t`.
    pub flux: Vec<[f64; 3]>,
    /// The particles simulated.
    pub particles: u64,
    /// Closest-hit rays traced.
    pub rays: u64,
}

impl FluxTable {
    /// Triangle `triangle`'s flux summed over m = 0 … M (the truncated
    /// Neumann series of Eq. 4): the paper's Eq. (14) with Ψ = G χ_A, "the
    /// total radiance that reaches A", integrated over the triangle (RGB).
    pub fn total_flux(&self, triangle: usize) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for m in 0..=self.bounces {
            let cell = self.flux[m * self.triangles + triangle];
            for channel in 0..3 {
                sum[channel] += cell[channel];
            }
        }
        sum
    }

    /// Every triangle's [`Self::total_flux`].
    pub fn total_fluxes(&self) -> Vec<[f64; 3]> {
        (0..self.triangles)
            .map(|triangle| self.total_flux(triangle))
            .collect()
    }

    /// [`Self::total_flux`] over the triangle's area: the radiance arriving
    /// at it, averaged over the triangle (RGB).
    pub fn radiance(&self, triangle: usize, areas: &[f64]) -> [f64; 3] {
        let area = areas[triangle];
        self.total_flux(triangle)
            .map(|value| if area > 0.0 { value / area } else { 0.0 })
    }

    /// Every triangle's [`Self::radiance`].
    pub fn radiances(&self, areas: &[f64]) -> Vec<[f64; 3]> {
        (0..self.triangles)
            .map(|triangle| self.radiance(triangle, areas))
            .collect()
    }
}

/// The paper's mean square deviation of two measurements (§5):
/// `√(Σ_i |A_i| d²(L_i, L'_i) / Σ_i |A_i|)`, d the RGB distance.
pub fn deviation(first: &[[f64; 3]], second: &[[f64; 3]], areas: &[f64]) -> f64 {
    let mut weighted = 0.0;
    let mut total_area = 0.0;
    for ((a, b), &area) in first.iter().zip(second).zip(areas) {
        let distance_squared: f64 = (0..3)
            .map(|channel| (a[channel] - b[channel]).powi(2))
            .sum();
        weighted += area * distance_squared;
        total_area += area;
    }
    if total_area > 0.0 {
        (weighted / total_area).sqrt()
    } else {
        0.0
    }
}

/// Particles per work unit of [`simulate`]: its sums are added in unit
/// order, so the table is the same for any number of threads.
const PARTICLES_PER_UNIT: u64 = 4096;

/// Simulates particles `0 … count − 1` of `points` (at least `2M + 4`
/// dimensions; a finite set needs `count` points) with `bounces` = M
/// reflections on all of rayon's threads, each carrying 1/count of the
/// lights' power. Deterministic: work units of [`PARTICLES_PER_UNIT`]
/// particles are summed separately and added in order.
pub fn simulate(
    scene: &ParticleScene,
    points: &(dyn qmc::point_set::PointSet + Sync),
    count: u64,
    bounces: usize,
) -> FluxTable {
    use rayon::prelude::*;
    let triangles = scene.triangle_count();
    let cells = (bounces + 1) * triangles;
    let units = count.div_ceil(PARTICLES_PER_UNIT);
    let weight = 1.0 / count.max(1) as f64;
    let partial: Vec<(Vec<[f64; 3]>, u64)> = (0..units)
        .into_par_iter()
        .map(|unit| {
            let mut flux = vec![[0.0f64; 3]; cells];
            let mut point = vec![0.0; 2 * bounces + 4];
            let mut rays = 0;
            let end = ((unit + 1) * PARTICLES_PER_UNIT).min(count);
            for index in unit * PARTICLES_PER_UNIT..end {
                points.point(index, &mut point);
                rays += scene.trace(&point, bounces, weight, &mut flux);
            }
            (flux, rays)
        })
        .collect();
    let mut flux = vec![[0.0f64; 3]; cells];
    let mut rays = 0;
    for (unit_flux, unit_rays) in partial {
        for (total, cell) in flux.iter_mut().zip(unit_flux) {
            for channel in 0..3 {
                total[channel] += cell[channel];
            }
        }
        rays += unit_rays;
    }
    FluxTable {
        bounces,
        triangles,
        flux,
        particles: count,
        rays,
    }
}

/// The light patches of an emitting mesh: one rectangle if it is two
/// triangles forming a parallelogram, else one patch per triangle. The
/// normal is the triangles' geometric normal (the side area lights emit to).
fn light_patches(
    triangles: &[[u32; 3]],
    positions: &[Vec3],
    corners: impl Fn(&[u32; 3]) -> [Vec3; 3],
) -> Vec<LightPatch> {
    let triangle_patch = |triangle: &[u32; 3]| {
        let [a, b, c] = corners(triangle);
        let cross = (b - a).cross(c - a);
        LightPatch {
            corner: a,
            edges: [b - a, c - a],
            parallelogram: false,
            normal: cross.normalize_or_zero(),
            area: 0.5 * cross.length() as f64,
        }
    };
    if let [first, second] = triangles {
        // A fan (0, 1, 2), (0, 2, 3) of the quad 0 1 2 3, as polygon meshes
        // and OBJ quads are split: a parallelogram if 1 + 3 = 0 + 2.
        if first[0] == second[0] && first[2] == second[1] {
            let [p0, p1, p2] = corners(first);
            let p3 = positions[second[2] as usize];
            let scale = (p2 - p0).length().max(1e-12);
            if ((p1 + p3) - (p0 + p2)).length() <= 1e-5 * scale {
                let cross = (p1 - p0).cross(p3 - p0);
                // The fan's winding gives the normal (p1 − p0) × (p2 − p0).
                let normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                return vec![LightPatch {
                    corner: p0,
                    edges: [p1 - p0, p3 - p0],
                    parallelogram: true,
                    normal,
                    area: cross.length() as f64,
                }];
            }
        }
    }
    triangles.iter().map(triangle_patch).collect()
}

/// The paper's local direction for coordinates `(u_φ, τ)`: φ = 2π u_φ,
/// sin²ϑ = τ (z along the normal).
#[inline]
fn paper_direction(u_phi: f32, tau: f32) -> Vec3 {
    let phi = 2.0 * PI * u_phi;
    let sin_theta = tau.clamp(0.0, 1.0).sqrt();
    let cos_theta = (1.0 - tau).clamp(0.0, 1.0).sqrt();
    Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// The square `[0, 1)²` point that the concentric disk mapping
/// ([`crate::material::sample_uniform_disk_concentric`], the
/// diffuse BSDF's cosine-weighted sampling) takes to the disk point of the
/// paper's direction for `(u_φ, τ)`: radius √τ at angle 2π u_φ. Its
/// inverse, region by region.
fn concentric_preimage(u_phi: f32, tau: f32) -> [f32; 2] {
    let radius = tau.clamp(0.0, 1.0).sqrt();
    // The angle in (−π, π].
    let mut angle = 2.0 * PI * u_phi;
    if angle > PI {
        angle -= 2.0 * PI;
    }
    let (x, y) = if angle.abs() <= FRAC_PI_4 {
        (radius, radius * angle / FRAC_PI_4)
    } else if angle >= 3.0 * FRAC_PI_4 {
        (-radius, -radius * (angle - PI) / FRAC_PI_4)
    } else if angle <= -3.0 * FRAC_PI_4 {
        (-radius, -radius * (angle + PI) / FRAC_PI_4)
    } else if angle > 0.0 {
        (radius * (FRAC_PI_2 - angle) / FRAC_PI_4, radius)
    } else {
        (-radius * (-FRAC_PI_2 - angle) / FRAC_PI_4, -radius)
    };
    let to_unit = |value: f32| ((value + 1.0) * 0.5).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
    [to_unit(x), to_unit(y)]
}

/// The numbers a particle's walk asks for, from its point: reflection k's
/// direction pair from coordinates `2k + 4, 2k + 5` (warped for the
/// concentric mapping), 0.5 for everything else (a diffuse reflection reads
/// nothing else; there is no Russian roulette).
struct ParticleNumbers<'a> {
    point: &'a [f64],
}

impl ParticleNumbers<'_> {
    /// The direction pair of reflection `block`.
    fn direction_pair(&self, block: usize) -> [f32; 2] {
        let first = 2 * block + 4;
        match (self.point.get(first), self.point.get(first + 1)) {
            (Some(&u_phi), Some(&tau)) => concentric_preimage(u_phi as f32, tau as f32),
            _ => [0.5; 2],
        }
    }
}

impl SampleSource for ParticleNumbers<'_> {
    fn get(&mut self, dimension: usize) -> f32 {
        let first = SubpathLayout::LIGHT.first;
        if dimension < first {
            return 0.5;
        }
        let (block, offset) = (
            (dimension - first) / layout::VERTEX_BLOCK,
            (dimension - first) % layout::VERTEX_BLOCK,
        );
        match offset {
            layout::SCATTER_DIRECTION => self.direction_pair(block)[0],
            offset if offset == layout::SCATTER_DIRECTION + 1 => self.direction_pair(block)[1],
            _ => 0.5,
        }
    }

    fn get_2d(&mut self, dimension: usize) -> [f32; 2] {
        let first = SubpathLayout::LIGHT.first;
        if dimension >= first && (dimension - first).is_multiple_of(layout::VERTEX_BLOCK) {
            return self.direction_pair((dimension - first) / layout::VERTEX_BLOCK);
        }
        [self.get(dimension), self.get(dimension + 1)]
    }
}

/// The walk's observer: adds the particle's flux to the triangle each
/// segment ends on (row = reflections so far), then takes the
/// triangle's reflectance.
struct FluxDeposit<'a, 'b> {
    scene: &'a ParticleScene,
    flux: &'b mut [[f64; 3]],
    /// The flux the particle carries (RGB).
    carried: [f64; 3],
    /// The triangle the last segment ended on.
    triangle: usize,
}

impl WalkObserver for FluxDeposit<'_, '_> {
    const FINDS_EMISSION: bool = false;

    /// Every surface a segment ends on receives the flux (also black ones,
    /// where the walk ends without a vertex).
    #[inline]
    fn surface(
        &mut self,
        walk: &WalkState,
        hit: &crate::geometry::SurfaceHit,
        _wavelengths: &SampledWavelengths,
    ) -> ControlFlow<()> {
        let triangle = self.scene.first_triangle[hit.shape_index as usize] as usize
            + hit.primitive_index as usize;
        let row = walk.vertex_index as usize * self.scene.triangle_count();
        let cell = &mut self.flux[row + triangle];
        for (total, carried) in cell.iter_mut().zip(self.carried) {
            *total += carried;
        }
        self.triangle = triangle;
        ControlFlow::Continue(())
    }

    /// The reflection at the vertex the last segment reached.
    #[inline]
    fn vertex<S: SampleSource + ?Sized>(
        &mut self,
        _walk: &WalkState,
        _vertex: &VertexAt<'_>,
        _wavelengths: &SampledWavelengths,
        _sampler: &mut S,
        _counters: &mut TraceCounters,
    ) -> ControlFlow<()> {
        let reflectance = self.scene.reflectances[self.triangle];
        for (carried, factor) in self.carried.iter_mut().zip(reflectance) {
            *carried *= factor;
        }
        if self.carried.iter().all(|&value| value == 0.0) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::description::{FilterDescription, ShapeDescription, polygon_mesh};
    use qmc::halton::{Halton, HaltonScramble};
    use qmc::hammersley::Hammersley;
    use qmc::point_set::PointSet;

    /// A closed box 2 × 1 × 1.5 and a light quad below its ceiling, every
    /// surface diffuse with reflectance `albedo` (the light too).
    fn closed_room(albedo: [f32; 3]) -> SceneDescription {
        let (x, y, z) = (2.0f32, 1.0f32, 1.5f32);
        let room = polygon_mesh(&[
            &[[0.0, 0.0, 0.0], [x, 0.0, 0.0], [x, 0.0, z], [0.0, 0.0, z]],
            &[[0.0, y, 0.0], [0.0, y, z], [x, y, z], [x, y, 0.0]],
            &[[0.0, 0.0, 0.0], [0.0, y, 0.0], [x, y, 0.0], [x, 0.0, 0.0]],
            &[[0.0, 0.0, z], [x, 0.0, z], [x, y, z], [0.0, y, z]],
            &[[0.0, 0.0, 0.0], [0.0, 0.0, z], [0.0, y, z], [0.0, y, 0.0]],
            &[[x, 0.0, 0.0], [x, y, 0.0], [x, y, z], [x, 0.0, z]],
        ]);
        let light = polygon_mesh(&[&[
            [0.8, 0.95, 0.6],
            [1.2, 0.95, 0.6],
            [1.2, 0.95, 0.9],
            [0.8, 0.95, 0.9],
        ]]);
        let material = MaterialDescription::diffuse_rgb(albedo);
        let mut description = crate::scene::builtin::builtin_scene("cornell-box").unwrap();
        description.shapes = vec![
            ShapeDescription::new(room, material.clone()),
            ShapeDescription::new(light, material).emitting([1.0, 2.0, 3.0]),
        ];
        description.lights.clear();
        description.filter = FilterDescription::Box { radius: 0.5 };
        description
    }

    fn point_sets(count: u64, dimensions: usize) -> Vec<(&'static str, Box<dyn PointSet>)> {
        vec![
            (
                "random",
                Box::new(qmc::random::RandomPoints::new(dimensions, 7)),
            ),
            (
                "halton",
                Box::new(Halton::new(dimensions, HaltonScramble::None, 0).unwrap()),
            ),
            (
                "scrambled halton",
                Box::new(Halton::new(dimensions, HaltonScramble::Faure, 0).unwrap()),
            ),
            (
                "hammersley",
                Box::new(Hammersley::new(count, dimensions, HaltonScramble::None, 0).unwrap()),
            ),
        ]
    }

    /// In a closed room with one reflectance ρ everywhere (the light too),
    /// every particle reaches a surface at the end of each of its M + 1
    /// segments, so the flux arriving after m reflections, summed over the
    /// triangles, is Φ ρ^m for every particle: exactly, for every pattern.
    #[test]
    fn closed_room_receives_the_power_times_albedo_to_the_m() {
        let albedo = [0.6f32, 0.5, 0.8];
        let scene = ParticleScene::new(&closed_room(albedo)).unwrap();
        // The light quad is one rectangle 0.4 × 0.3 of radiance (1, 2, 3).
        let power = scene.power();
        for (channel, radiance) in [1.0, 2.0, 3.0].iter().enumerate() {
            let expected = std::f64::consts::PI * radiance * 0.12;
            assert!((power[channel] - expected).abs() < 1e-6 * expected);
        }
        let bounces = 4;
        let count = 2000u64;
        let triangles = scene.triangle_count();
        for (name, points) in point_sets(count, 2 * bounces + 4) {
            let mut flux = vec![[0.0f64; 3]; (bounces + 1) * triangles];
            let mut point = vec![0.0; 2 * bounces + 4];
            for index in 0..count {
                points.point(index, &mut point);
                scene.trace(&point, bounces, 1.0 / count as f64, &mut flux);
            }
            for m in 0..=bounces {
                let row = &flux[m * triangles..(m + 1) * triangles];
                for channel in 0..3 {
                    let total: f64 = row.iter().map(|cell| cell[channel]).sum();
                    let expected = power[channel] * (albedo[channel] as f64).powi(m as i32);
                    assert!(
                        (total - expected).abs() < 1e-9 * expected,
                        "{name}: m = {m}, channel {channel}: {total} vs {expected}"
                    );
                }
            }
        }
    }

    /// The concentric mapping of the preimage gives back the paper's disk
    /// point.
    #[test]
    fn concentric_preimage_inverts_the_concentric_mapping() {
        for i in 0..64 {
            for j in 0..32 {
                let (u_phi, tau) = ((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 32.0);
                let disk = crate::material::sample_uniform_disk_concentric(concentric_preimage(
                    u_phi, tau,
                ));
                let expected = paper_direction(u_phi, tau);
                assert!(
                    (disk.x - expected.x).abs() < 1e-5 && (disk.y - expected.y).abs() < 1e-5,
                    "({u_phi}, {tau}): {disk} vs {expected}"
                );
            }
        }
    }

    /// Per-triangle radiance from random particles agrees with a master
    /// computation (scrambled Halton, 2^18 particles) within the standard
    /// errors estimated from 16 independent random batches: the fraction of
    /// triangle channels beyond 4 standard errors is below 1 %, and the
    /// deviation of the batches' mean from the master is of the size the
    /// standard errors predict. The simulation is the same for 1 and 2
    /// threads.
    #[test]
    fn random_particles_agree_with_the_master_within_their_errors() {
        let description = crate::scene::builtin::builtin_scene("heinrich-keller").unwrap();
        let scene = ParticleScene::new(&description).unwrap();
        let bounces = 4;
        let dimensions = 2 * bounces + 4;
        let areas = scene.areas().to_vec();
        let master_points = Halton::new(dimensions, HaltonScramble::Faure, 0).unwrap();
        let master = simulate(&scene, &master_points, 1 << 18, bounces).radiances(&areas);
        let batches = 16;
        let per_batch = 1u64 << 14;
        let mut sum = vec![[0.0f64; 3]; scene.triangle_count()];
        let mut sum_squares = vec![[0.0f64; 3]; scene.triangle_count()];
        for batch in 0..batches {
            let points = qmc::random::RandomPoints::new(dimensions, 1000 + batch);
            let radiances = simulate(&scene, &points, per_batch, bounces).radiances(&areas);
            for (triangle, value) in radiances.iter().enumerate() {
                for channel in 0..3 {
                    sum[triangle][channel] += value[channel];
                    sum_squares[triangle][channel] += value[channel] * value[channel];
                }
            }
        }
        let r = batches as f64;
        let (mut tested, mut beyond) = (0, 0);
        for triangle in 0..scene.triangle_count() {
            for channel in 0..3 {
                let mean = sum[triangle][channel] / r;
                let variance =
                    (sum_squares[triangle][channel] / r - mean * mean).max(0.0) * r / (r - 1.0);
                let error = (variance / r).sqrt();
                if error == 0.0 {
                    continue;
                }
                tested += 1;
                if (mean - master[triangle][channel]).abs() > 4.0 * error {
                    beyond += 1;
                }
            }
        }
        assert!(tested > 600, "{tested} triangle channels tested");
        assert!(
            (beyond as f64) < 0.01 * tested as f64,
            "{beyond} of {tested} beyond 4 standard errors"
        );
        // Threads do not change the table.
        let points = Halton::new(dimensions, HaltonScramble::Faure, 0).unwrap();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| simulate(&scene, &points, 10_000, bounces));
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
            .install(|| simulate(&scene, &points, 10_000, bounces));
        assert_eq!(one, two);
    }

    /// The m = 0 term of a triangle is the flux it receives directly, the
    /// light's power times the form factor: on a small scene, a unit square
    /// light facing a parallel unit square at distance 1 (everything else
    /// black), the receiver's two triangles get Φ F with F = 0.19982
    /// (the closed form for parallel, directly opposed unit squares at unit
    /// distance), within 4 standard errors of the random estimate and the
    /// Hammersley estimate within 0.5 %.
    #[test]
    fn the_direct_term_matches_the_form_factor_of_two_squares() {
        // Parallel directly opposed rectangles a × b at distance c (Howell's
        // catalogue, C-11), a = b = c = 1.
        let (x, y) = (1.0f64, 1.0f64);
        let form_factor = 2.0 / (std::f64::consts::PI * x * y)
            * (((1.0 + x * x) * (1.0 + y * y) / (1.0 + x * x + y * y))
                .sqrt()
                .ln()
                + x * (1.0 + y * y).sqrt() * (x / (1.0 + y * y).sqrt()).atan()
                + y * (1.0 + x * x).sqrt() * (y / (1.0 + x * x).sqrt()).atan()
                - x * x.atan()
                - y * y.atan());
        assert!((form_factor - 0.19982).abs() < 1e-4);
        let light = polygon_mesh(&[&[
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ]]);
        let receiver = polygon_mesh(&[&[
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
        ]]);
        let mut description = closed_room([0.5; 3]);
        description.shapes = vec![
            ShapeDescription::new(receiver, MaterialDescription::Black),
            ShapeDescription::new(light, MaterialDescription::Black).emitting([1.0, 1.0, 1.0]),
        ];
        let scene = ParticleScene::new(&description).unwrap();
        let power = scene.power()[0];
        assert!((power - std::f64::consts::PI).abs() < 1e-6);
        let expected = power * form_factor;
        let received = |table: &FluxTable| table.flux[0][0] + table.flux[1][0];
        let count = 1u64 << 16;
        let hammersley = Hammersley::new(count, 4, HaltonScramble::None, 0).unwrap();
        let quasi = received(&simulate(&scene, &hammersley, count, 0));
        assert!(
            (quasi / expected - 1.0).abs() < 0.005,
            "Hammersley {quasi} vs {expected}"
        );
        let random = qmc::random::RandomPoints::new(4, 3);
        let estimate = received(&simulate(&scene, &random, count, 0));
        // Each particle hits with probability F: a binomial count.
        let error = power * (form_factor * (1.0 - form_factor) / count as f64).sqrt();
        assert!(
            (estimate - expected).abs() < 4.0 * error,
            "random {estimate} vs {expected} ± {error}"
        );
    }
}

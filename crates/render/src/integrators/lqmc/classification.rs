//! Path classes (normal, caustic, depth of field, next-event estimation)
//! and the breakup vertex distribution `P(b | X)` (the paper's Sec. 3.3 and
//! 3.4). Both are functions of a path alone, so that every member of an
//! exploration can evaluate them for itself: the estimator needs `P(b | X_j)`
//! and class membership of each member to stay unbiased.

use super::path_record::{CameraVertex, SplatEvent, SurfaceVertex, Terminal};
use super::settings::{BreakupChoice, LqmcSettings};
use crate::material::{BsdfFlags, SurfaceBsdf};
use crate::scene::Scene;
use glam::Vec3;

/// The classes that choose the lattice size and the tiles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PathClass {
    /// Everything else.
    Normal,
    /// A (near-)diffuse vertex followed by a (near-)specular chain to the
    /// light.
    Caustic,
    /// The first hit is out of focus.
    DepthOfField,
    /// Made by next-event estimation.
    NextEvent,
}

impl PathClass {
    /// Every class, in the order statistics list them.
    pub const ALL: [PathClass; 4] = [
        PathClass::Normal,
        PathClass::Caustic,
        PathClass::DepthOfField,
        PathClass::NextEvent,
    ];

    /// Index in [`PathClass::ALL`].
    pub fn index(self) -> usize {
        match self {
            PathClass::Normal => 0,
            PathClass::Caustic => 1,
            PathClass::DepthOfField => 2,
            PathClass::NextEvent => 3,
        }
    }

    /// The name used by options and statistics.
    pub fn name(self) -> &'static str {
        match self {
            PathClass::Normal => "normal",
            PathClass::Caustic => "caustic",
            PathClass::DepthOfField => "dof",
            PathClass::NextEvent => "nee",
        }
    }
}

/// The roughness of a vertex for the breakup CDF and the caustic class: 0
/// for a specular scattering, otherwise the roughness recorded with the
/// vertex (see [`lobe_roughness`]; √(1 − g²) in media).
pub fn vertex_roughness(vertex: &SurfaceVertex) -> f32 {
    scattered_roughness(vertex.sampled, vertex.roughness)
}

/// The roughness of a vertex that sampled the lobes `sampled` and recorded
/// `roughness` ([`vertex_roughness`]'s rule).
pub fn scattered_roughness(sampled: BsdfFlags, roughness: f32) -> f32 {
    if sampled.is_specular() {
        0.0
    } else {
        roughness
    }
}

/// Whether a path whose last vertex is `x_k`, `k = last_vertex`, is long
/// enough to be explored: paths of fewer than three vertices are not.
pub fn long_enough_to_explore(last_vertex: usize) -> bool {
    last_vertex >= 2
}

/// The effective roughness of the lobes `lobes` of `bsdf` (the sampled
/// lobe's flags, or all of the BSDF's flags where nothing was sampled, as
/// at a next-event vertex): 1 if they include a diffuse lobe (plastic's
/// substrate as well), the BSDF's own roughness ([`SurfaceBsdf::roughness`],
/// the microfacet α) for glossy lobes, 0 for specular ones.
pub fn lobe_roughness(bsdf: &SurfaceBsdf, lobes: BsdfFlags) -> f32 {
    if lobes.is_diffuse() {
        1.0
    } else if lobes.is_glossy() {
        bsdf.roughness().clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// A path of an event: the camera vertex, the surface vertices and the
/// event.
#[derive(Debug, Clone, Copy)]
pub struct EventPath<'a> {
    /// The camera vertex.
    pub camera: &'a CameraVertex,
    /// The event's surface vertices.
    pub vertices: &'a [SurfaceVertex],
    /// The event.
    pub event: &'a SplatEvent,
}

impl EventPath<'_> {
    /// Roughness of vertex `x_index` (paper numbering): 1 for the camera and
    /// for the light vertex (environment and area lights alike).
    pub fn roughness(&self, index: usize) -> f32 {
        if index == 0 || index >= self.event.last_vertex() {
            return 1.0;
        }
        let vertex = &self.vertices[index - 1];
        if index > self.event.scattering_count() {
            1.0
        } else {
            vertex_roughness(vertex)
        }
    }
}

/// The circle of confusion of the path's first hit, in pixels (diameter on
/// the plane in focus, aperture diameter × |focus − distance| / distance,
/// over the pixel size there).
pub fn circle_of_confusion_pixels(scene: &Scene, path: &EventPath<'_>) -> f32 {
    match path.vertices.first() {
        Some(first) => circle_of_confusion_at(scene, path.camera.origin, first.hit.point),
        None => 0.0,
    }
}

/// The circle of confusion in pixels of a first hit at `point` seen from
/// the lens point `origin` (0 for a pinhole).
pub fn circle_of_confusion_at(scene: &Scene, origin: Vec3, point: Vec3) -> f32 {
    let camera = &scene.camera;
    if camera.lens_radius() <= 0.0 {
        return 0.0;
    }
    let focus = camera.focus_distance();
    let distance = (point - origin).length();
    let diameter = 2.0 * camera.lens_radius() * (focus - distance).abs() / distance;
    diameter / (camera.pixel_size_at_unit_distance() * focus)
}

/// The class of a path.
pub fn classify(scene: &Scene, settings: &LqmcSettings, path: &EventPath<'_>) -> PathClass {
    class_of(
        settings,
        || circle_of_confusion_pixels(scene, path),
        path.vertices[..path.event.scattering_count()]
            .iter()
            .map(vertex_roughness),
        path.event.is_next_event(),
    )
}

/// The class of a path from what decides it: its first hit's circle of
/// confusion in pixels, the roughness ([`vertex_roughness`]) of its
/// scattering vertices in order from the camera, and whether next-event
/// estimation made it. [`classify`] and the seeds' screening
/// ([`super::seed_screen`]) both decide by it.
pub fn class_of(
    settings: &LqmcSettings,
    circle_of_confusion: impl FnOnce() -> f32,
    scattering_roughness: impl DoubleEndedIterator<Item = f32> + ExactSizeIterator,
    is_next_event: bool,
) -> PathClass {
    if circle_of_confusion() > settings.depth_of_field_threshold_pixels {
        return PathClass::DepthOfField;
    }
    let scattering = scattering_roughness.len();
    let chain = scattering_roughness
        .rev()
        .take_while(|roughness| *roughness < settings.caustic_roughness)
        .count();
    if chain > 0 && chain < scattering {
        return PathClass::Caustic;
    }
    if is_next_event {
        PathClass::NextEvent
    } else {
        PathClass::Normal
    }
}

/// Whether the full-path breakup b = k can explore `path`: its light
/// vertex is sampled again, by tracing the last scattering's direction to
/// an emitter or by next-event estimation's light-position numbers (not
/// for a delta light, whose point no number places, nor for an escape to
/// the environment, whose direction the walk takes from the record).
pub fn full_path_explorable(path: &EventPath<'_>) -> bool {
    match path.event.terminal {
        Terminal::Emission { .. } => true,
        Terminal::NextEvent(connection) => !connection.is_delta,
        Terminal::Environment { .. } => false,
    }
}

/// The breakup weights `w_b`, b = 0 .. k: the roughness CDF's unnormalised
/// masses (min roughness of `x_b` and `x_{b+1}`, the light vertex `x_k` and
/// the `x_{k+1}` beyond it counting 1, b = 0 weighted up for depth-of-field
/// paths; b = k only with [`LqmcSettings::full_path_breakup`] and where
/// [`full_path_explorable`]), or the fixed choice; `explorable(b)` says
/// whether `b` has between 1 and 21 explored dimensions.
pub fn breakup_weights(
    settings: &LqmcSettings,
    path: &EventPath<'_>,
    class: PathClass,
    mut explorable: impl FnMut(usize) -> bool,
    weights: &mut Vec<f64>,
) {
    weights.clear();
    let last = path.event.last_vertex();
    let full_path = full_path_explorable(path);
    for b in 0..=last {
        if b == last && !full_path {
            weights.push(0.0);
            continue;
        }
        let roughness = path.roughness(b).min(path.roughness(b + 1)) as f64;
        let mut weight = match settings.breakup {
            BreakupChoice::Fixed(fixed) => {
                if fixed == b && roughness > 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            BreakupChoice::FullPath => {
                if b == last {
                    1.0
                } else {
                    0.0
                }
            }
            BreakupChoice::Roughness => {
                if b == last && !settings.full_path_breakup {
                    0.0
                } else {
                    roughness
                }
            }
        };
        if b == 0 {
            if class == PathClass::DepthOfField {
                weight *= settings.depth_of_field_camera_weight as f64;
            } else if !settings.explore_camera_in_focus {
                weight = 0.0;
            }
        }
        if weight > 0.0 && !explorable(b) {
            weight = 0.0;
        }
        weights.push(weight);
    }
}

/// `P(b | X)` from the weights (0 where they are all zero).
pub fn breakup_probability(weights: &[f64], breakup: usize) -> f64 {
    let total: f64 = weights.iter().sum();
    if total > 0.0 {
        weights.get(breakup).copied().unwrap_or(0.0) / total
    } else {
        0.0
    }
}

/// Draws `b` from the weights with `u ∈ [0, 1)`; `None` if all are zero.
pub fn draw_breakup(weights: &[f64], u: f64) -> Option<usize> {
    let total: f64 = weights.iter().sum();
    if total <= 0.0 {
        return None;
    }
    let target = u * total;
    let mut running = 0.0;
    let mut chosen = None;
    for (index, weight) in weights.iter().enumerate() {
        if *weight <= 0.0 {
            continue;
        }
        chosen = Some(index);
        running += weight;
        if target < running {
            break;
        }
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    /// The CDF's masses are min(roughness(x_b), roughness(x_{b+1})) with the
    /// vertices' own roughness (a rough lobe's α, a medium's √(1 − g²)), 1
    /// for the camera and the light; the draws follow them.
    #[test]
    fn breakup_draws_follow_the_vertices_roughness() {
        let camera = CameraVertex {
            raster: Vec2::ZERO,
            u_lens: [0.5; 2],
            u_time: 0.5,
            u_wavelength: 0.5,
            origin: Vec3::ZERO,
        };
        let vertex = |roughness: f32| SurfaceVertex::in_medium(Vec3::ONE, 0.0, 0, roughness);
        let mut glossy = vertex(0.1);
        glossy.medium = None;
        glossy.sampled = BsdfFlags::GLOSSY | BsdfFlags::TRANSMISSION;
        let mut specular = vertex(0.7);
        specular.medium = None;
        specular.sampled = BsdfFlags::SPECULAR | BsdfFlags::REFLECTION;
        let vertices = [vertex(0.6), glossy, vertex(1.0), specular, vertex(1.0)];
        let event =
            SplatEvent::of_first_vertices(vertices.len(), Terminal::Emission { light_index: 0 });
        let path = EventPath {
            camera: &camera,
            vertices: &vertices,
            event: &event,
        };
        let mut weights = Vec::new();
        // By default b = 0 is left out of paths in focus.
        breakup_weights(
            &LqmcSettings::default(),
            &path,
            PathClass::Normal,
            |_| true,
            &mut weights,
        );
        assert_eq!(weights[0], 0.0);
        assert_eq!(weights[1], 0.1f32 as f64);
        let in_focus_camera = LqmcSettings {
            explore_camera_in_focus: true,
            ..LqmcSettings::default()
        };
        breakup_weights(
            &in_focus_camera,
            &path,
            PathClass::Normal,
            |_| true,
            &mut weights,
        );
        // b = 0 .. 4, and the full path b = k = 5 (light and beyond count 1).
        let expected = [0.6, 0.1, 0.1, 0.0, 0.0, 1.0];
        assert_eq!(weights.len(), expected.len());
        for (weight, expected) in weights.iter().zip(expected) {
            assert!((weight - expected).abs() < 1e-6, "{weights:?}");
        }
        let draws = 100_000;
        let mut counts = [0usize; 6];
        for i in 0..draws {
            let b = draw_breakup(&weights, (i as f64 + 0.5) / draws as f64).unwrap();
            counts[b] += 1;
        }
        let total: f64 = expected.iter().sum();
        for (count, expected) in counts.iter().zip(expected) {
            assert!((*count as f64 / draws as f64 - expected / total).abs() < 1e-3);
        }
    }

    /// `--breakup k` puts all mass on the last vertex, and the full-path
    /// term is left out where the light vertex cannot be sampled again
    /// (escapes to the environment) or when switched off.
    #[test]
    fn full_path_breakup_weights() {
        let camera = CameraVertex {
            raster: Vec2::ZERO,
            u_lens: [0.5; 2],
            u_time: 0.5,
            u_wavelength: 0.5,
            origin: Vec3::ZERO,
        };
        let vertices = [SurfaceVertex::in_medium(Vec3::ONE, 0.0, 0, 1.0); 2];
        let weights_of = |settings: &LqmcSettings, terminal: Terminal| {
            let event = SplatEvent::of_first_vertices(vertices.len(), terminal);
            let path = EventPath {
                camera: &camera,
                vertices: &vertices,
                event: &event,
            };
            let mut weights = Vec::new();
            breakup_weights(settings, &path, PathClass::Normal, |_| true, &mut weights);
            weights
        };
        let emission = Terminal::Emission { light_index: 0 };
        let defaults = LqmcSettings {
            explore_camera_in_focus: true,
            ..LqmcSettings::default()
        };
        let full = LqmcSettings {
            breakup: BreakupChoice::FullPath,
            ..defaults
        };
        assert_eq!(weights_of(&full, emission), vec![0.0, 0.0, 1.0]);
        assert_eq!(weights_of(&defaults, emission), vec![1.0, 1.0, 1.0]);
        let without = LqmcSettings {
            full_path_breakup: false,
            ..defaults
        };
        assert_eq!(weights_of(&without, emission), vec![1.0, 1.0, 0.0]);
        let escape = Terminal::Environment { direction: Vec3::Z };
        assert_eq!(weights_of(&full, escape), vec![0.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn breakup_draw_follows_the_weights() {
        let weights = [0.0, 1.0, 0.0, 3.0];
        assert_eq!(draw_breakup(&weights, 0.0), Some(1));
        assert_eq!(draw_breakup(&weights, 0.24), Some(1));
        assert_eq!(draw_breakup(&weights, 0.26), Some(3));
        assert_eq!(draw_breakup(&weights, 0.999), Some(3));
        assert_eq!(draw_breakup(&[0.0, 0.0], 0.5), None);
        assert!((breakup_probability(&weights, 3) - 0.75).abs() < 1e-12);
        assert_eq!(breakup_probability(&weights, 2), 0.0);
    }
}

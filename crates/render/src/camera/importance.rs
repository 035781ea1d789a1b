//! The camera's importance `We(x, ω)` and the densities of its rays, for
//! light tracing and bidirectional path tracing: the quantities of pbrt-v4's
//! `PerspectiveCamera::We`, `PDF_We` and `SampleWi` (pbrt-v4,
//! `cameras.cpp`; the formulas are pbrt-v4's, the code is ours).
//!
//! # Measures
//!
//! Everything is measured in world space at one time: lens points per unit
//! world area on the lens, directions per unit world solid angle, cosines
//! with the lens plane's unit normal (facing the scene: see
//! [`PerspectiveCamera::lens_normal`]). For a rigid world-from-camera
//! transform (rotation, translation, possibly a reflection, as
//! [`super::look_at`] and the scene loaders make) that normal is the optical
//! axis and the formulas are pbrt-v4's:
//!
//! - `A` is the area of the image rectangle on the camera-space plane
//!   `z = 1` (`4 · tan(fov_x/2) · tan(fov_y/2)`);
//! - `lens_area = π r²`, and 1 for a pinhole (see *Pinhole* below);
//! - `We(x, ω) = 1 / (A · lens_area · cos⁴θ)` for a ray from a lens point
//!   `x` whose direction `ω` reaches the image, 0 otherwise, with `cos θ`
//!   the cosine of `ω` with the lens normal;
//! - `pdf_position = 1 / lens_area`, `pdf_direction = 1 / (A · cos³θ)`: the
//!   densities of [`PerspectiveCamera::generate_ray`]'s rays when the raster
//!   position is uniform over the image and the lens sample uniform.
//!
//! A transform with a scale is handled exactly too: `lens_area` is the
//! world area of the (transformed) lens and `A` becomes the area of the
//! image rectangle on the world plane at unit distance from the lens plane,
//! so the formulas keep their form.
//!
//! `We · cos θ = pdf_position · pdf_direction`, so `∫∫ We cos θ dω dA = 1`
//! over the lens and the image: the importance of the whole image is 1.
//!
//! # Normalisation: what a light tracer splats
//!
//! The film's camera samples estimate, for pixel `p` with centre `c_p`,
//! `I_p = ∫ f(x − c_p) L(x) dx` (raster area in pixels, `L` averaged
//! uniformly over the lens and the shutter): filter importance sampling
//! with a filter `f` normalised to `∫ f = 1` over raster area, every sample
//! weighted 1 ([`crate::film::Film::camera_sample_position`]). Splats are
//! spread with the same normalised `f`, whose weights therefore also
//! integrate to 1 over raster area ([`crate::film::Film::merge_splats`]).
//! Changing variables from raster area to the lens and solid angle
//! (`dx = W·H · pdf_position · pdf_direction · dA dω` for a `W × H` image)
//! gives `I_p = W·H · ∫∫ f(x(ω) − c_p) We L cos θ dω dA`: the importance of
//! one pixel is `W·H · f · We`, which integrates to 1 like the camera
//! sample's filter. `We` stays per *image* (pbrt-v4's); the factor `W·H`
//! (one over the pixel's share of the image, `A_pixel = A / (W·H)`) goes
//! into the splat scale.
//!
//! So a light tracer that traces `N` light paths and splats each camera
//! connection at [`CameraImportanceSample::raster`] with the value
//! `β · f_s · We · |cos θ_ref| / pdf` (`β` the light path's throughput up
//! to the reference point, e.g. `Le / p_area` for a point sampled on an
//! emitter, `f_s` the BSDF there towards `wi` (1 for the emitter point
//! itself), `|cos θ_ref|` the cosine of `wi` with the surface normal there,
//! `We` and `pdf` from [`PerspectiveCamera::sample_incident_importance`],
//! times the visibility) must read the image with
//! `splat_scale = W·H / N`. With one light path per pixel sample
//! (`N = spp · W · H`, pbrt-v4's `LightPathIntegrator`) that is
//! `splat_scale = 1 / spp`, and the pixels equal the path tracer's in
//! expectation. Exactly so for every pixel whose filter support lies inside
//! the image: near the border the path tracer's filter samples may leave
//! the image, where `We` is 0 (as in pbrt-v4).
//!
//! # Time
//!
//! The densities are at a given time. A light tracer draws the time first
//! with [`PerspectiveCamera::time`] (uniform over the shutter) and traces
//! its light path at that time; the camera measurement averages over the
//! shutter with the same uniform density, so the time's density cancels and
//! nothing is divided by it.
//!
//! # Pinhole
//!
//! A pinhole's lens is a point: the position density is a Dirac delta. As
//! in pbrt-v4, its densities use `lens_area = 1`: `pdf_position = 1`,
//! `We = 1 / (A cos⁴θ)` and, for [`PerspectiveCamera::sample_incident_importance`],
//! `pdf = distance² / cos θ`. The deltas cancel in `We / pdf`, which is what
//! an estimator uses; a multiple-importance weight must treat the pinhole's
//! position as a delta (no other strategy can hit the lens point).
//! [`PerspectiveCamera::lens_area`] itself returns the true area, 0.

use glam::{Affine3A, Vec2, Vec3};

use super::PerspectiveCamera;
use crate::sampling::sample_uniform_disk_concentric_trigonometric;

/// The camera's importance for one ray leaving the lens
/// ([`PerspectiveCamera::importance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraImportance {
    /// `We(x, ω) = 1 / (A · lens_area · cos⁴θ)` (see
    /// [`crate::camera::importance`] for the measures and the pinhole's
    /// convention).
    pub value: f32,
    /// The continuous raster position the ray reaches (pixel units, inside
    /// the image): where to splat.
    pub raster: Vec2,
    /// `cos θ`, the cosine of the ray direction with the lens normal
    /// (positive).
    pub lens_cosine: f32,
}

/// The densities with which [`PerspectiveCamera::generate_ray`] produces a
/// ray when its raster position is uniform over the image and its lens
/// sample uniform ([`PerspectiveCamera::pdf_importance`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraRayDensity {
    /// Per unit lens area: `1 / lens_area`, 1 for a pinhole (a delta).
    pub position: f32,
    /// Per unit solid angle: `1 / (A · cos³θ)`, 0 if the direction does not
    /// reach the image.
    pub direction: f32,
}

/// A lens point sampled towards a scene point, with the importance it
/// carries there ([`PerspectiveCamera::sample_incident_importance`],
/// pbrt-v4's `Camera::SampleWi`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraImportanceSample {
    /// Unit direction from the reference point towards the lens point.
    pub wi: Vec3,
    /// The sampled point on the lens, in world space (the camera ray's
    /// origin; for a pinhole the pinhole itself).
    pub lens_point: Vec3,
    /// Distance from the reference point to the lens point.
    pub distance: f32,
    /// `We` of the ray from the lens point towards the reference point.
    pub value: f32,
    /// Density of `wi` per unit solid angle at the reference point:
    /// `distance² / (cos θ · lens_area)` (lens area 1 for a pinhole).
    pub pdf: f32,
    /// The continuous raster position the reference point appears at,
    /// seen from the lens point (inside the image): where to splat.
    pub raster: Vec2,
    /// `cos θ`, the cosine at the lens of the ray towards the reference
    /// point with the lens normal (positive).
    pub lens_cosine: f32,
}

/// The camera's lens plane and image at one time, in world measure: what
/// the importance formulas need beyond the camera-space description.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ImportanceFrame {
    pub(super) world_from_camera: Affine3A,
    pub(super) camera_from_world: Affine3A,
    /// Unit normal of the lens plane in world space, facing the scene
    /// (camera-space `z > 0`).
    pub(super) lens_normal: Vec3,
    /// The lens area the densities use: the world area of the lens, or 1
    /// for a pinhole (the delta convention).
    pub(super) density_lens_area: f32,
    /// The true world area of the lens (0 for a pinhole).
    pub(super) lens_area: f32,
    /// `A`: the area of the image rectangle on the world plane at unit
    /// distance from the lens plane (for a rigid transform, the camera-space
    /// image rectangle on `z = 1`).
    pub(super) image_area: f32,
}

/// True if `value > 0` (false for NaN, so that degenerate geometry is
/// rejected).
#[inline]
fn is_positive(value: f32) -> bool {
    value > 0.0
}

impl ImportanceFrame {
    /// The frame of a camera seen through `world_from_camera`, whose image
    /// plane at camera-space distance 1 has half extents
    /// `screen_half_extent`, with a lens of camera-space radius
    /// `lens_radius`.
    pub(super) fn new(
        world_from_camera: Affine3A,
        screen_half_extent: Vec2,
        lens_radius: f32,
    ) -> Self {
        let axes = world_from_camera.matrix3;
        // The lens plane is spanned by the images of camera x and y; its
        // area scales by |x' × y'|.
        let lens_plane = Vec3::from(axes.x_axis.cross(axes.y_axis));
        let area_scale = lens_plane.length();
        let forward = Vec3::from(axes.z_axis);
        let mut lens_normal = lens_plane / area_scale;
        if lens_normal.dot(forward) < 0.0 {
            lens_normal = -lens_normal;
        }
        // A camera-space depth of 1 is this world distance from the lens
        // plane: the image rectangle on z = 1 (area 4·hx·hy·area_scale in
        // world) lies this far away, and its area at unit distance is that
        // over the distance squared.
        let depth_scale = lens_normal.dot(forward);
        let image_area = 4.0 * screen_half_extent.x * screen_half_extent.y * area_scale
            / (depth_scale * depth_scale);
        let lens_area = std::f32::consts::PI * lens_radius * lens_radius * area_scale;
        Self {
            world_from_camera,
            camera_from_world: world_from_camera.inverse(),
            lens_normal,
            density_lens_area: if lens_radius > 0.0 { lens_area } else { 1.0 },
            lens_area,
            image_area,
        }
    }

    /// `We = 1 / (A · lens_area · cos⁴θ)` for a ray with `cos θ = cosine`.
    #[inline]
    fn importance(&self, cosine: f32) -> f32 {
        let cosine_squared = cosine * cosine;
        1.0 / (self.image_area * self.density_lens_area * cosine_squared * cosine_squared)
    }
}

impl PerspectiveCamera {
    /// The lens plane and image measures at `time` (precomputed for a
    /// static camera).
    #[inline]
    fn importance_frame(&self, time: f32) -> ImportanceFrame {
        match self.static_importance_frame {
            Some(frame) => frame,
            None => ImportanceFrame::new(
                self.world_from_camera(time),
                self.screen_half_extent,
                self.lens_radius,
            ),
        }
    }

    /// True if `raster` lies in the image, `[0, width) × [0, height)`.
    #[inline]
    fn is_inside_image(&self, raster: Vec2) -> bool {
        raster.x >= 0.0
            && raster.y >= 0.0
            && raster.x < self.resolution[0] as f32
            && raster.y < self.resolution[1] as f32
    }

    /// The raster position (inside the image) of the ray leaving the lens
    /// point `origin` in the direction `direction`, if it reaches the image.
    fn raster_of_ray(
        &self,
        frame: &ImportanceFrame,
        origin: Vec3,
        direction: Vec3,
    ) -> Option<Vec2> {
        self.raster_of_ray_anywhere(frame, origin, direction)
            .filter(|raster| self.is_inside_image(*raster))
    }

    /// The raster position of the ray leaving the lens point `origin` in
    /// `direction`, inside the image or not (`None` if it points behind the
    /// lens plane).
    fn raster_of_ray_anywhere(
        &self,
        frame: &ImportanceFrame,
        origin: Vec3,
        direction: Vec3,
    ) -> Option<Vec2> {
        let direction = frame.camera_from_world.transform_vector3(direction);
        if !is_positive(direction.z) {
            return None;
        }
        let on_plane = if self.lens_radius > 0.0 {
            // Every lens ray through a raster point meets the pinhole ray
            // through it on the plane of focus.
            let origin = frame.camera_from_world.transform_point3(origin);
            let focus = origin + direction * ((self.focus_distance - origin.z) / direction.z);
            focus.truncate() / self.focus_distance
        } else {
            direction.truncate() / direction.z
        };
        Some(self.raster_of_plane_point(on_plane))
    }

    /// [`PerspectiveCamera::pdf_importance`] for camera rays whose raster
    /// positions are uniform over the image grown by `margin` pixels per
    /// side (the domain of splatting films and of bidirectional methods'
    /// camera subpaths, [`crate::film::ImagePlane`]): the direction density
    /// is that over the grown rectangle, `1 / (A' · cos³θ)` with `A'` the
    /// grown image's area at unit distance, and 0 outside it.
    pub fn pdf_importance_with_margin(
        &self,
        ray_origin: Vec3,
        ray_direction: Vec3,
        time: f32,
        margin: Vec2,
    ) -> CameraRayDensity {
        let frame = self.importance_frame(time);
        let lens_cosine = frame.lens_normal.dot(ray_direction);
        let [width, height] = self.resolution.map(|size| size as f32);
        let grown = Vec2::new(width, height) + 2.0 * margin;
        let direction = match self.raster_of_ray_anywhere(&frame, ray_origin, ray_direction) {
            Some(raster)
                if lens_cosine > 0.0
                    && raster.x >= -margin.x
                    && raster.y >= -margin.y
                    && raster.x < width + margin.x
                    && raster.y < height + margin.y =>
            {
                let grown_area = frame.image_area * grown.x * grown.y / (width * height);
                1.0 / (grown_area * lens_cosine * lens_cosine * lens_cosine)
            }
            _ => 0.0,
        };
        CameraRayDensity {
            position: 1.0 / frame.density_lens_area,
            direction,
        }
    }

    /// The unit normal of the lens plane in world space at `time`, facing
    /// the scene: the camera's optical axis for a rigid world-from-camera
    /// transform. The cosines of the importance are taken with it. Free for
    /// a static camera; a moving one interpolates its transform.
    pub fn lens_normal(&self, time: f32) -> Vec3 {
        self.importance_frame(time).lens_normal
    }

    /// The world area of the lens at `time`: `π r²` for a rigid transform,
    /// 0 for a pinhole (whose densities use 1 instead: see
    /// [`crate::camera::importance`]).
    pub fn lens_area(&self, time: f32) -> f32 {
        self.importance_frame(time).lens_area
    }

    /// The camera's importance `We(x, ω)` for the ray leaving the lens point
    /// `ray_origin` in the unit direction `ray_direction` at `time` (pbrt-v4's
    /// `PerspectiveCamera::We`), and the raster position the ray reaches:
    /// `None` (importance 0) if the ray points behind the lens plane or
    /// misses the image. `ray_origin` must be a lens point, as
    /// [`PerspectiveCamera::generate_ray`] and
    /// [`PerspectiveCamera::sample_incident_importance`] return (it is not
    /// checked; a pinhole ignores it). The value is per unit lens area and
    /// solid angle, normalised to 1 over the image: see
    /// [`crate::camera::importance`] for the convention and for
    /// what a light tracer splats.
    pub fn importance(
        &self,
        ray_origin: Vec3,
        ray_direction: Vec3,
        time: f32,
    ) -> Option<CameraImportance> {
        let frame = self.importance_frame(time);
        let raster = self.raster_of_ray(&frame, ray_origin, ray_direction)?;
        let lens_cosine = frame.lens_normal.dot(ray_direction);
        (lens_cosine > 0.0).then(|| CameraImportance {
            value: frame.importance(lens_cosine),
            raster,
            lens_cosine,
        })
    }

    /// The densities with which [`PerspectiveCamera::generate_ray`] makes
    /// the ray from `ray_origin` in the unit direction `ray_direction` at
    /// `time` when its raster position is uniform over the image and its
    /// lens sample uniform (pbrt-v4's `PerspectiveCamera::PDF_We`): per unit
    /// lens area `1 / lens_area` (1 for a pinhole, a delta), per unit solid
    /// angle `1 / (A · cos³θ)`, 0 if the direction misses the image or
    /// points behind the lens. For the multiple-importance weights of
    /// bidirectional methods.
    pub fn pdf_importance(
        &self,
        ray_origin: Vec3,
        ray_direction: Vec3,
        time: f32,
    ) -> CameraRayDensity {
        let frame = self.importance_frame(time);
        let lens_cosine = frame.lens_normal.dot(ray_direction);
        let direction = match self.raster_of_ray(&frame, ray_origin, ray_direction) {
            Some(_) if lens_cosine > 0.0 => {
                1.0 / (frame.image_area * lens_cosine * lens_cosine * lens_cosine)
            }
            _ => 0.0,
        };
        CameraRayDensity {
            position: 1.0 / frame.density_lens_area,
            direction,
        }
    }

    /// Samples a lens point towards the world point `reference` at `time`
    /// (pbrt-v4's `PerspectiveCamera::SampleWi`), for the connections of
    /// light tracing and bidirectional methods to the camera: the lens point
    /// from `u_lens` by the concentric mapping [`PerspectiveCamera::generate_ray`]
    /// uses (so `u_lens` means the same in both), uniform on the lens, with
    /// its density converted to solid angle at `reference`. `None` if the
    /// point lies behind the lens plane or appears outside the image.
    ///
    /// `time` is a time in the shutter interval (light tracing draws it
    /// first with [`PerspectiveCamera::time`]). The raster position equals
    /// [`PerspectiveCamera::project`]'s for the same lens sample and time.
    /// Visibility between the two points is the caller's to test.
    pub fn sample_incident_importance(
        &self,
        reference: Vec3,
        time: f32,
        u_lens: [f32; 2],
    ) -> Option<CameraImportanceSample> {
        self.sample_incident_importance_with_margin(reference, time, u_lens, Vec2::ZERO)
    }

    /// [`PerspectiveCamera::sample_incident_importance`] for points that
    /// appear up to `margin` pixels outside the image (per axis): a splat
    /// there still reaches the border pixels through the film's filter,
    /// whose radius the margin should be. The path tracer's camera samples
    /// of a border pixel leave the image by the same filter offsets, so with
    /// the margin a light tracer's border pixels have the same expectation
    /// (without it they are dark by the share of the filter outside).
    pub fn sample_incident_importance_with_margin(
        &self,
        reference: Vec3,
        time: f32,
        u_lens: [f32; 2],
        margin: Vec2,
    ) -> Option<CameraImportanceSample> {
        let frame = self.importance_frame(time);
        let reference_camera = frame.camera_from_world.transform_point3(reference);
        let (lens_camera, on_plane) = if self.lens_radius > 0.0 {
            let lens = (sample_uniform_disk_concentric_trigonometric(u_lens) * self.lens_radius)
                .extend(0.0);
            let along = reference_camera - lens;
            if !is_positive(along.z) {
                return None;
            }
            let focus = lens + along * (self.focus_distance / along.z);
            (lens, focus.truncate() / self.focus_distance)
        } else {
            if !is_positive(reference_camera.z) {
                return None;
            }
            (Vec3::ZERO, reference_camera.truncate() / reference_camera.z)
        };
        let raster = self.raster_of_plane_point(on_plane);
        if !(raster.x >= -margin.x
            && raster.y >= -margin.y
            && raster.x < self.resolution[0] as f32 + margin.x
            && raster.y < self.resolution[1] as f32 + margin.y)
        {
            return None;
        }
        let lens_point = frame.world_from_camera.transform_point3(lens_camera);
        let to_lens = lens_point - reference;
        let distance = to_lens.length();
        if !is_positive(distance) {
            return None;
        }
        let wi = to_lens / distance;
        let lens_cosine = -frame.lens_normal.dot(wi);
        if !is_positive(lens_cosine) {
            return None;
        }
        Some(CameraImportanceSample {
            wi,
            lens_point,
            distance,
            value: frame.importance(lens_cosine),
            pdf: distance * distance / (lens_cosine * frame.density_lens_area),
            raster,
            lens_cosine,
        })
    }
}

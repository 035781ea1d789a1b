//! Cameras: a perspective pinhole or thin-lens camera with a shutter
//! interval, moving between two transforms while the shutter is open, so
//! that time is a real dimension of the primary sample space.
//!
//! Camera space: the camera looks down +z, +y is up and +x is to the right
//! of the image. Raster space: pixel `(0, 0)` is the top-left corner, x
//! grows to the right and y downwards.
//!
//! For light tracing and bidirectional methods, [`importance`] gives the
//! camera's importance `We`, the densities of its rays and the sampling of
//! lens points towards scene points, with the normalisation convention that
//! makes splats agree with the film's camera samples.

use glam::{Affine3A, Quat, Vec2, Vec3, Vec3A};

use crate::sampling::sample_uniform_disk_concentric_trigonometric;

pub mod importance;
use importance::ImportanceFrame;
pub use importance::{CameraImportance, CameraImportanceSample, CameraRayDensity};

/// Which image axis the field of view spans (Mitsuba's `fov_axis`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FovAxis {
    /// The horizontal axis (Mitsuba's default).
    #[default]
    X,
    /// The vertical axis.
    Y,
    /// The shorter image axis (pbrt-v4's convention).
    Smaller,
    /// The longer image axis.
    Larger,
}

/// A ray leaving the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraRay {
    /// Origin in world space (on the lens).
    pub origin: Vec3,
    /// Unit direction in world space.
    pub direction: Vec3,
    /// Time in the shutter interval.
    pub time: f32,
}

/// Why a camera cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// A parameter is outside its range; the message says which.
    #[error("invalid camera: {0}")]
    Invalid(String),
}

/// A perspective camera: a pinhole when the lens radius is 0, otherwise a
/// thin lens focused at `focus_distance`.
#[derive(Debug, Clone, PartialEq)]
pub struct PerspectiveCamera {
    /// World from camera at the shutter's opening and closing.
    world_from_camera: [Affine3A; 2],
    /// The shutter interval.
    shutter: [f32; 2],
    resolution: [u32; 2],
    /// Half extents of the image plane at distance 1 (tan of the half angles).
    screen_half_extent: Vec2,
    lens_radius: f32,
    focus_distance: f32,
    /// Raster to normalised device coordinates: 2 / resolution per axis.
    raster_to_ndc: Vec2,
    /// The world-from-camera transform when it does not change while the
    /// shutter is open (the usual case): no interpolation per ray.
    static_world_from_camera: Option<Affine3A>,
    /// True if that static transform is a rotation (possibly with a
    /// reflection) and a translation, so that it keeps directions unit.
    static_keeps_length: bool,
    /// For a pinhole that does not move while the shutter is open (the
    /// usual case), the raster-to-world map of ray directions, so that a
    /// camera ray costs three multiply-adds and a normalisation.
    static_pinhole: Option<PinholeRays>,
    /// For a camera that does not move while the shutter is open, its lens
    /// plane and image measures in world space, for the importance queries
    /// of light tracing ([`PerspectiveCamera::importance`] and friends).
    static_importance_frame: Option<ImportanceFrame>,
}

/// The rays of a static pinhole camera: every ray starts at `origin`, and
/// the ray through raster position `(x, y)` has the direction of `x ·
/// per_raster_x + y · per_raster_y + at_raster_origin` (the camera's
/// raster-to-image-plane map composed with its world-from-camera rotation:
/// both are linear in the raster position). Measured on the Cornell box
/// (64 × 64, 16 spp, independent sampler): generating a camera ray went from
/// 105 instructions (an out-of-line call, NDC, image plane, normalisation,
/// transform) to about 25 inlined into the render loop.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PinholeRays {
    origin: Vec3,
    per_raster_x: Vec3A,
    per_raster_y: Vec3A,
    at_raster_origin: Vec3A,
}

impl PinholeRays {
    /// The map of the camera whose image plane at distance 1 has half
    /// extents `screen_half_extent`, whose raster-to-NDC scale is
    /// `raster_to_ndc`, seen through `world_from_camera`.
    fn new(world_from_camera: &Affine3A, screen_half_extent: Vec2, raster_to_ndc: Vec2) -> Self {
        // on_plane = ((x·sx − 1)·hx, (1 − y·sy)·hy, 1), linear in x and y.
        let axes = world_from_camera.matrix3;
        Self {
            origin: Vec3::from(world_from_camera.translation),
            per_raster_x: axes.x_axis * (raster_to_ndc.x * screen_half_extent.x),
            per_raster_y: axes.y_axis * -(raster_to_ndc.y * screen_half_extent.y),
            at_raster_origin: axes.z_axis - axes.x_axis * screen_half_extent.x
                + axes.y_axis * screen_half_extent.y,
        }
    }

    /// The unit world direction of the ray through `raster`.
    #[inline]
    fn direction(&self, raster: Vec2) -> Vec3 {
        let direction =
            self.per_raster_x * raster.x + self.per_raster_y * raster.y + self.at_raster_origin;
        Vec3::from(direction.normalize())
    }
}

/// True if the linear part of `transform` is orthonormal to f32 rounding:
/// it maps unit vectors to unit vectors.
fn keeps_length(transform: &Affine3A) -> bool {
    let columns = [
        Vec3::from(transform.matrix3.x_axis),
        Vec3::from(transform.matrix3.y_axis),
        Vec3::from(transform.matrix3.z_axis),
    ];
    const TOLERANCE: f32 = 1e-6;
    columns
        .iter()
        .all(|column| (column.length_squared() - 1.0).abs() <= TOLERANCE)
        && columns[0].dot(columns[1]).abs() <= TOLERANCE
        && columns[1].dot(columns[2]).abs() <= TOLERANCE
        && columns[0].dot(columns[2]).abs() <= TOLERANCE
}

/// Settings of a [`PerspectiveCamera`], with Mitsuba's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct PerspectiveSettings {
    /// World from camera at the shutter's opening.
    pub world_from_camera: Affine3A,
    /// World from camera at the shutter's closing (the same for a static camera).
    pub world_from_camera_end: Affine3A,
    /// Shutter open and close times (default 0, 0: no motion blur).
    pub shutter: [f32; 2],
    /// Image size in pixels.
    pub resolution: [u32; 2],
    /// Field of view in degrees along `fov_axis` (default 45).
    pub fov_degrees: f32,
    /// The axis the field of view spans (default `X`).
    pub fov_axis: FovAxis,
    /// Radius of the thin lens in scene units (default 0: a pinhole).
    pub lens_radius: f32,
    /// Distance of the plane in focus (default 1; unused by a pinhole).
    pub focus_distance: f32,
}

impl Default for PerspectiveSettings {
    fn default() -> Self {
        Self {
            world_from_camera: Affine3A::IDENTITY,
            world_from_camera_end: Affine3A::IDENTITY,
            shutter: [0.0, 0.0],
            resolution: [512, 512],
            fov_degrees: 45.0,
            fov_axis: FovAxis::X,
            lens_radius: 0.0,
            focus_distance: 1.0,
        }
    }
}

/// World from camera for a camera at `eye` looking at `target` with `up`
/// roughly up in the image (+x of camera space points to the image's right).
pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Result<Affine3A, CameraError> {
    let forward = (target - eye).normalize_or_zero();
    let right = forward.cross(up).normalize_or_zero();
    if forward == Vec3::ZERO || right == Vec3::ZERO {
        return Err(CameraError::Invalid(
            "look_at needs distinct eye and target and an up vector not along the view".into(),
        ));
    }
    // Camera +x is the image's right, forward × up in a right-handed world;
    // with +y up and +z forward the camera frame is left-handed, as pbrt's.
    let camera_up = right.cross(forward);
    Ok(Affine3A::from_cols(
        right.into(),
        camera_up.into(),
        forward.into(),
        eye.into(),
    ))
}

impl PerspectiveCamera {
    /// Builds the camera, checking its parameters.
    pub fn new(settings: &PerspectiveSettings) -> Result<Self, CameraError> {
        let [width, height] = settings.resolution;
        if width == 0 || height == 0 {
            return Err(CameraError::Invalid(format!(
                "resolution {width}x{height} has no pixels"
            )));
        }
        if !(settings.fov_degrees > 0.0 && settings.fov_degrees < 180.0) {
            return Err(CameraError::Invalid(format!(
                "field of view {} is not in (0, 180) degrees",
                settings.fov_degrees
            )));
        }
        if !(settings.lens_radius >= 0.0 && settings.lens_radius.is_finite()) {
            return Err(CameraError::Invalid(format!(
                "lens radius {} is negative or not finite",
                settings.lens_radius
            )));
        }
        if settings.lens_radius > 0.0
            && (settings.focus_distance.is_nan() || settings.focus_distance <= 0.0)
        {
            return Err(CameraError::Invalid(format!(
                "focus distance {} must be positive",
                settings.focus_distance
            )));
        }
        if settings.shutter.iter().any(|t| !t.is_finite())
            || settings.shutter[0] > settings.shutter[1]
        {
            return Err(CameraError::Invalid(format!(
                "shutter closes ({}) before it opens ({})",
                settings.shutter[1], settings.shutter[0]
            )));
        }
        let aspect = width as f32 / height as f32;
        let half = (settings.fov_degrees.to_radians() * 0.5).tan();
        let horizontal_axis = match settings.fov_axis {
            FovAxis::X => true,
            FovAxis::Y => false,
            FovAxis::Smaller => width <= height,
            FovAxis::Larger => width >= height,
        };
        let screen_half_extent = if horizontal_axis {
            Vec2::new(half, half / aspect)
        } else {
            Vec2::new(half * aspect, half)
        };
        let static_world_from_camera = (settings.world_from_camera
            == settings.world_from_camera_end
            || settings.shutter[1] <= settings.shutter[0])
            .then_some(settings.world_from_camera);
        let raster_to_ndc = Vec2::new(2.0 / width as f32, 2.0 / height as f32);
        let static_pinhole = static_world_from_camera
            .filter(|_| settings.lens_radius == 0.0)
            .map(|transform| PinholeRays::new(&transform, screen_half_extent, raster_to_ndc));
        let static_importance_frame = static_world_from_camera.map(|transform| {
            ImportanceFrame::new(transform, screen_half_extent, settings.lens_radius)
        });
        Ok(Self {
            world_from_camera: [settings.world_from_camera, settings.world_from_camera_end],
            shutter: settings.shutter,
            resolution: settings.resolution,
            screen_half_extent,
            lens_radius: settings.lens_radius,
            focus_distance: settings.focus_distance,
            raster_to_ndc,
            static_world_from_camera,
            static_keeps_length: static_world_from_camera.as_ref().is_some_and(keeps_length),
            static_pinhole,
            static_importance_frame,
        })
    }

    /// The image size in pixels.
    pub fn resolution(&self) -> [u32; 2] {
        self.resolution
    }

    /// The time for the primary-sample-space number `u_time`.
    #[inline]
    pub fn time(&self, u_time: f32) -> f32 {
        self.shutter[0] + (self.shutter[1] - self.shutter[0]) * u_time
    }

    /// World from camera at `time`: translation and scale interpolated
    /// linearly, rotation by spherical linear interpolation.
    pub fn world_from_camera(&self, time: f32) -> Affine3A {
        if let Some(transform) = self.static_world_from_camera {
            return transform;
        }
        let [start, end] = self.world_from_camera;
        let t = ((time - self.shutter[0]) / (self.shutter[1] - self.shutter[0])).clamp(0.0, 1.0);
        let (scale0, rotation0, translation0) = start.to_scale_rotation_translation();
        let (scale1, rotation1, translation1) = end.to_scale_rotation_translation();
        Affine3A::from_scale_rotation_translation(
            scale0.lerp(scale1, t),
            slerp(rotation0, rotation1, t),
            translation0.lerp(translation1, t),
        )
    }

    /// True if rays depend on the lens number ([`layout::LENS`]): a
    /// pinhole has no lens. A caller may skip asking its sampler for unused
    /// numbers and pass anything in their place; samplers address every
    /// dimension directly, so that changes no other number.
    ///
    /// [`layout::LENS`]: crate::sampler::layout::LENS
    #[inline]
    pub fn uses_lens_sample(&self) -> bool {
        self.lens_radius > 0.0
    }

    /// True if rays depend on the time number ([`layout::TIME`]): a
    /// shutter that opens and closes at the same instant fixes the time.
    ///
    /// [`layout::TIME`]: crate::sampler::layout::TIME
    #[inline]
    pub fn uses_time_sample(&self) -> bool {
        self.shutter[1] > self.shutter[0]
    }

    /// The ray through `raster` (pixel units, continuous) for the lens sample
    /// `u_lens` and the time sample `u_time`. A static pinhole's ray is
    /// computed inline ([`PinholeRays`]); other cameras call
    /// [`PerspectiveCamera::generate_ray_general`].
    #[inline]
    pub fn generate_ray(&self, raster: Vec2, u_lens: [f32; 2], u_time: f32) -> CameraRay {
        let time = self.time(u_time);
        match &self.static_pinhole {
            Some(pinhole) => CameraRay {
                origin: pinhole.origin,
                direction: pinhole.direction(raster),
                time,
            },
            None => self.generate_ray_general(raster, u_lens, time),
        }
    }

    /// The ray of a thin lens or a moving camera, at `time`.
    #[inline(never)]
    fn generate_ray_general(&self, raster: Vec2, u_lens: [f32; 2], time: f32) -> CameraRay {
        let ndc = Vec2::new(
            raster.x * self.raster_to_ndc.x - 1.0,
            1.0 - raster.y * self.raster_to_ndc.y,
        );
        let on_plane = (ndc * self.screen_half_extent).extend(1.0);
        let (origin, direction) = if self.lens_radius > 0.0 {
            let lens = sample_uniform_disk_concentric_trigonometric(u_lens) * self.lens_radius;
            // The pinhole ray through the image point meets the plane of focus
            // here; every lens ray through that point converges there.
            let focus = on_plane * self.focus_distance;
            let origin = lens.extend(0.0);
            (origin, (focus - origin).normalize())
        } else {
            (Vec3::ZERO, on_plane.normalize())
        };
        let transform = self.world_from_camera(time);
        let direction = transform.transform_vector3(direction);
        CameraRay {
            origin: transform.transform_point3(origin),
            // A static rotation keeps the unit direction unit (to rounding).
            direction: if self.static_keeps_length {
                direction
            } else {
                direction.normalize()
            },
            time,
        }
    }
}

/// Where a world point appears on the image seen from a given lens point and
/// time: what light tracing and LQMC's reconnection to the camera need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraProjection {
    /// Continuous raster position (pixel units).
    pub raster: Vec2,
    /// The lens point in world space (the ray origin).
    pub origin: Vec3,
    /// The camera-space cosine of the ray from the lens point to the world
    /// point with the optical axis: the density of the point per unit area
    /// is `focus² / (cosine³ · pixel area at the focus)` times
    /// `|cos θ| / distance²` at the point.
    pub axis_cosine: f32,
}

impl PerspectiveCamera {
    /// The radius of the thin lens (0 for a pinhole).
    pub fn lens_radius(&self) -> f32 {
        self.lens_radius
    }

    /// The distance of the plane in focus.
    pub fn focus_distance(&self) -> f32 {
        self.focus_distance
    }

    /// The width of one pixel on the plane at distance 1 from the camera.
    pub fn pixel_size_at_unit_distance(&self) -> f32 {
        2.0 * self.screen_half_extent.x / self.resolution[0] as f32
    }

    /// The inverse of [`PerspectiveCamera::generate_ray`] for a fixed lens
    /// sample and time: the raster position whose ray from the lens point
    /// passes through `point`, if `point` lies in front of the camera (the
    /// raster position may lie outside the image).
    pub fn project(&self, point: Vec3, u_lens: [f32; 2], u_time: f32) -> Option<CameraProjection> {
        let time = self.time(u_time);
        let transform = self.world_from_camera(time);
        let camera_point = transform.inverse().transform_point3(point);
        if camera_point.z <= 0.0 {
            return None;
        }
        let (lens, on_plane) = if self.lens_radius > 0.0 {
            let lens = (sample_uniform_disk_concentric_trigonometric(u_lens) * self.lens_radius)
                .extend(0.0);
            let along = camera_point - lens;
            let focus = lens + along * (self.focus_distance / along.z);
            (lens, focus / self.focus_distance)
        } else {
            (Vec3::ZERO, camera_point / camera_point.z)
        };
        Some(CameraProjection {
            raster: self.raster_of_plane_point(on_plane.truncate()),
            origin: transform.transform_point3(lens),
            axis_cosine: (camera_point - lens).normalize().z,
        })
    }
}

impl PerspectiveCamera {
    /// The continuous raster position of the camera-space point
    /// `(on_plane, 1)` of the image plane at distance 1 (the inverse of the
    /// raster-to-plane map of [`PerspectiveCamera::generate_ray`]).
    #[inline]
    fn raster_of_plane_point(&self, on_plane: Vec2) -> Vec2 {
        let ndc = on_plane / self.screen_half_extent;
        Vec2::new(
            (ndc.x + 1.0) * 0.5 * self.resolution[0] as f32,
            (1.0 - ndc.y) * 0.5 * self.resolution[1] as f32,
        )
    }
}

/// Spherical linear interpolation taking the shorter arc.
fn slerp(a: Quat, b: Quat, t: f32) -> Quat {
    let b = if a.dot(b) < 0.0 { -b } else { b };
    a.slerp(b, t)
}

#[cfg(test)]
mod tests;

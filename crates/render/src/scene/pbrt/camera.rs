//! The directives before `WorldBegin` that describe the image rather than
//! the world: `Camera`, `Film`, `Sampler`, `PixelFilter`, `Integrator` and
//! `Accelerator`, with pbrt-v4's defaults (perspective camera with a 90°
//! field of view on the shorter image axis, 1280 × 720 pixels, 16 samples per
//! pixel, a Gaussian filter of radius 1.5 and σ = 0.5, `volpath` with
//! maximum depth 5).

use super::parameters::{ParameterList, Position};
use super::parser::Loader;
use crate::camera::{FovAxis, PerspectiveSettings};
use crate::integrators::IntegratorKind;
use crate::scene::description::FilterDescription;
use crate::scene::loader::SceneFileError;
use glam::{Affine3A, DMat4};

/// pbrt-v4's default `maxdepth`.
pub const PBRT_DEFAULT_MAX_DEPTH: i64 = 5;

/// What the image directives set, gathered until the end of the file (the
/// field of view depends on the film's resolution, which may come later).
#[derive(Debug, Clone, PartialEq)]
pub struct CameraSettings {
    pub world_from_camera: DMat4,
    /// `fov` in degrees, spanning the shorter image axis.
    pub fov_degrees: f32,
    pub lens_radius: f32,
    pub focal_distance: f32,
    /// `screenwindow`: x min, x max, y min, y max in screen space.
    pub screen_window: Option<[f32; 4]>,
    pub resolution: [u32; 2],
    pub samples_per_pixel: u64,
    pub filter: FilterDescription,
    /// pbrt's `maxdepth` (scattering events).
    pub pbrt_max_depth: i64,
    /// The integrator the file names, if this renderer has it.
    pub integrator: Option<String>,
    /// The camera's `MediumInterface` outside medium at `Camera`.
    pub medium: Option<String>,
    /// Where `Camera` was (for messages about it).
    pub position: Option<Position>,
}

impl Default for CameraSettings {
    fn default() -> Self {
        Self {
            world_from_camera: DMat4::IDENTITY,
            fov_degrees: 90.0,
            lens_radius: 0.0,
            focal_distance: 1.0e6,
            screen_window: None,
            resolution: [1280, 720],
            samples_per_pixel: 16,
            filter: FilterDescription::Gaussian {
                radius: 1.5,
                sigma: 0.5,
            },
            pbrt_max_depth: PBRT_DEFAULT_MAX_DEPTH,
            integrator: None,
            medium: None,
            position: None,
        }
    }
}

/// pbrt's `maxdepth` (the number of scattering events; 0 shows emitters
/// only) as the project's depth (Mitsuba's path segments; 1 shows emitters
/// only): one more.
pub fn segments_from_pbrt_depth(max_depth: i64) -> u32 {
    (max_depth.clamp(0, u32::MAX as i64 - 1) + 1) as u32
}

impl CameraSettings {
    /// The renderer's camera settings, with warnings for what it cannot show.
    pub fn perspective(&self, warnings: &mut Vec<String>) -> PerspectiveSettings {
        let [width, height] = self.resolution;
        let aspect = width as f32 / height as f32;
        let (fov_degrees, fov_axis) = match self.screen_window {
            None => (self.fov_degrees, FovAxis::Smaller),
            Some([x0, x1, y0, y1]) => {
                let warn = |warnings: &mut Vec<String>, message: &str| match &self.position {
                    Some(position) => warnings.push(position.warning(message)),
                    None => warnings.push(message.to_string()),
                };
                if (x0 + x1).abs() > 1e-4 * (x1 - x0).abs()
                    || (y0 + y1).abs() > 1e-4 * (y1 - y0).abs()
                {
                    warn(
                        warnings,
                        "Camera: an off-centre screenwindow is not supported; the window is centred",
                    );
                }
                let half_width = 0.5 * (x1 - x0).abs();
                let half_height = 0.5 * (y1 - y0).abs();
                if (half_width / half_height - aspect).abs() > 1e-3 * aspect {
                    warn(
                        warnings,
                        "Camera: the screenwindow's aspect ratio differs from the film's; its width decides",
                    );
                }
                let tangent = (self.fov_degrees.to_radians() * 0.5).tan() * half_width;
                (2.0 * tangent.atan().to_degrees(), FovAxis::X)
            }
        };
        let world_from_camera = Affine3A::from_mat4(self.world_from_camera.as_mat4());
        PerspectiveSettings {
            world_from_camera,
            world_from_camera_end: world_from_camera,
            shutter: [0.0, 0.0],
            resolution: self.resolution,
            fov_degrees,
            fov_axis,
            lens_radius: self.lens_radius,
            focus_distance: self.focal_distance,
        }
    }
}

fn positive_resolution(
    parameters: &ParameterList,
    name: &str,
    default: i64,
    position: &Position,
) -> Result<u32, SceneFileError> {
    let value = parameters.integer(name, default)?;
    if !(1..=1 << 20).contains(&value) {
        return Err(position.error(format!(
            "Film: \"integer {name}\" must be between 1 and 1048576, found {value}"
        )));
    }
    Ok(value as u32)
}

impl Loader {
    /// `Camera`: pbrt's camera space is the CTM at this point.
    pub fn camera_directive(
        &mut self,
        kind: &str,
        parameters: &ParameterList,
        world_from_camera: DMat4,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        if kind != "perspective" {
            self.warn(
                position,
                format!(
                    "Camera \"{kind}\" is not supported; a perspective camera with its fov is used"
                ),
            );
        }
        let camera = &mut self.camera;
        camera.world_from_camera = world_from_camera;
        camera.position = Some(position.clone());
        camera.fov_degrees = parameters.float("fov", 90.0)?;
        if !(camera.fov_degrees > 0.0 && camera.fov_degrees < 180.0) {
            return Err(position.error(format!(
                "Camera: \"float fov\" must be between 0 and 180 degrees, found {}",
                camera.fov_degrees
            )));
        }
        camera.lens_radius = parameters.float("lensradius", 0.0)?;
        camera.focal_distance = parameters.float("focaldistance", 1.0e6)?;
        if camera.lens_radius < 0.0 || camera.focal_distance <= 0.0 {
            return Err(position.error(
                "Camera: \"lensradius\" must not be negative and \"focaldistance\" must be positive",
            ));
        }
        camera.screen_window = match parameters.floats("screenwindow")? {
            None => None,
            Some(window)
                if window.len() == 4 && window[0] != window[1] && window[2] != window[3] =>
            {
                Some([window[0], window[1], window[2], window[3]])
            }
            Some(window) => {
                return Err(position.error(format!(
                    "Camera: \"float screenwindow\" needs four numbers x0 x1 y0 y1 with x0 ≠ x1 and y0 ≠ y1, found {window:?}"
                )));
            }
        };
        let frame_aspect_ratio = parameters.optional_float("frameaspectratio")?;
        let shutter_open = parameters.float("shutteropen", 0.0)?;
        let shutter_close = parameters.float("shutterclose", 1.0)?;
        let _ = (shutter_open, shutter_close);
        if frame_aspect_ratio.is_some() {
            self.warn(
                position,
                "Camera: \"frameaspectratio\" is ignored; the film's resolution sets the aspect ratio",
            );
        }
        self.camera.medium = self.state.outside_medium.clone();
        Ok(())
    }

    /// `Film`, `Sampler`, `PixelFilter`, `Integrator` and `Accelerator`.
    pub fn options_directive(
        &mut self,
        directive: &str,
        kind: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        match directive {
            "Film" => {
                if !matches!(kind, "rgb" | "gbuffer" | "spectral") {
                    self.warn(
                        position,
                        format!("Film \"{kind}\" is not known; read as \"rgb\""),
                    );
                }
                self.camera.resolution = [
                    positive_resolution(parameters, "xresolution", 1280, position)?,
                    positive_resolution(parameters, "yresolution", 720, position)?,
                ];
                // The output name is the command line's (`-o`); pbrt's
                // physical film size and output precision do not change the
                // image.
                parameters.string("filename")?;
                parameters.float("diagonal", 35.0)?;
                parameters.bool("savefp16", true)?;
                let iso = parameters.float("iso", 100.0)?;
                let exposure_time = parameters.float("exposuretime", 1.0)?;
                if (iso * exposure_time / 100.0 - 1.0).abs() > 1e-6 {
                    self.warn(
                        position,
                        "Film: \"iso\" and \"exposuretime\" are ignored (the image is not scaled by iso·exposuretime/100)",
                    );
                }
            }
            "Sampler" => {
                self.camera.samples_per_pixel = if kind == "stratified" {
                    let x = parameters.integer("xsamples", 4)?;
                    let y = parameters.integer("ysamples", 4)?;
                    parameters.bool("jitter", true)?;
                    x.clamp(1, 1 << 16) as u64 * y.clamp(1, 1 << 16) as u64
                } else {
                    let samples = parameters.integer("pixelsamples", 16)?;
                    if samples < 1 {
                        return Err(position.error(format!(
                            "Sampler: \"integer pixelsamples\" must be at least 1, found {samples}"
                        )));
                    }
                    samples as u64
                };
                // The sampler itself is the command line's choice.
                parameters.integer("seed", 0)?;
                parameters.string("randomization")?;
            }
            "PixelFilter" => {
                let default_radius = match kind {
                    "box" => 0.5,
                    "gaussian" => 1.5,
                    "triangle" | "mitchell" => 2.0,
                    "sinc" => 4.0,
                    _ => 1.5,
                };
                let x_radius = parameters.float("xradius", default_radius)?;
                let y_radius = parameters.float("yradius", default_radius)?;
                if x_radius != y_radius {
                    self.warn(
                        position,
                        format!("PixelFilter: different x and y radii ({x_radius}, {y_radius}) are not supported; the x radius is used"),
                    );
                }
                if x_radius.is_nan() || x_radius <= 0.0 {
                    return Err(position.error(format!(
                        "PixelFilter: the radius must be positive, found {x_radius}"
                    )));
                }
                self.camera.filter = match kind {
                    "box" => FilterDescription::Box { radius: x_radius },
                    "triangle" => FilterDescription::Tent { radius: x_radius },
                    "gaussian" => FilterDescription::Gaussian {
                        radius: x_radius,
                        sigma: parameters.float("sigma", 0.5)?,
                    },
                    other => {
                        self.warn(
                            position,
                            format!("PixelFilter \"{other}\" is not supported; a Gaussian filter (σ = 0.5) of its radius is used"),
                        );
                        FilterDescription::Gaussian {
                            radius: x_radius,
                            sigma: 0.5,
                        }
                    }
                };
            }
            "Integrator" => {
                self.camera.pbrt_max_depth =
                    parameters.integer("maxdepth", PBRT_DEFAULT_MAX_DEPTH)?;
                if self.camera.pbrt_max_depth < 0 {
                    return Err(position.error(format!(
                        "Integrator: \"integer maxdepth\" must not be negative, found {}",
                        self.camera.pbrt_max_depth
                    )));
                }
                // Settings of pbrt's own path tracers that this renderer
                // decides itself.
                parameters.string("lightsampler")?;
                parameters.bool("regularize", false)?;
                self.camera.integrator = match IntegratorKind::from_name(kind) {
                    Some(_) => Some(kind.to_string()),
                    None => {
                        self.warn(
                            position,
                            format!("Integrator \"{kind}\" is not known to this renderer; the command line's integrator is used"),
                        );
                        None
                    }
                };
            }
            _ => {
                // Accelerator: the renderer builds its own BVH.
                for parameter in &parameters.parameters {
                    parameters.find(&parameter.name);
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_conversion_adds_the_camera_segment() {
        assert_eq!(segments_from_pbrt_depth(0), 1);
        assert_eq!(segments_from_pbrt_depth(1), 2);
        assert_eq!(segments_from_pbrt_depth(5), 6);
        assert_eq!(segments_from_pbrt_depth(65), 66);
    }

    #[test]
    fn a_centred_screen_window_becomes_a_horizontal_fov() {
        let settings = CameraSettings {
            fov_degrees: 90.0,
            screen_window: Some([-2.0, 2.0, -1.0, 1.0]),
            resolution: [200, 100],
            ..CameraSettings::default()
        };
        let mut warnings = Vec::new();
        let perspective = settings.perspective(&mut warnings);
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(perspective.fov_axis, FovAxis::X);
        let expected = 2.0 * 2.0f32.atan().to_degrees();
        assert!((perspective.fov_degrees - expected).abs() < 1e-4);
    }
}

//! Mitsuba's `perspective` and `thinlens` sensors with their `hdrfilm`,
//! reconstruction filter and sampler.
//!
//! Mitsuba's camera looks along +z of its `to_world` with +y up and +x to
//! the *left* of the image; this renderer's camera has +x to the right, so
//! the camera frame is `to_world · diag(−1, 1, 1)`. `fov` is in degrees
//! along `fov_axis` (`x` by default; `diagonal` is converted to `x`);
//! without a `fov`, `focal_length` (default `50mm`) gives the diagonal field
//! of a 36 × 24 mm film. `near_clip` and `far_clip` are read and ignored
//! (this camera does not clip). Defaults: film 768 × 576, Gaussian filter
//! (σ = 0.5, radius 4σ), 4 samples per pixel, thin lens of aperture radius
//! 0.03 focused at distance 1... as listed where they are read.

use super::super::description::FilterDescription;
use super::super::loader::SceneFileError;
use super::values::{Properties, parse_number};
use super::xml::Element;
use super::{Loader, NamedObject};
use crate::camera::FovAxis;
use glam::{Affine3A, Vec3};

/// Diagonal of 35 mm film (36 × 24 mm), for `focal_length`.
const FILM_DIAGONAL_MILLIMETRES: f32 = 43.266_615;

impl Loader {
    /// Reads the `<film>` (resolution and filter).
    fn film(&mut self, element: &Element) -> Result<(), SceneFileError> {
        let properties = Properties::new(element);
        if properties.plugin_type() != "hdrfilm" {
            self.warn(
                element,
                format!(
                    "film type '{}' is read as an hdrfilm",
                    properties.plugin_type()
                ),
            );
        }
        let dimension = |name: &str, default: i64| -> Result<u32, SceneFileError> {
            let value = properties.optional_integer(name)?.unwrap_or(default);
            u32::try_from(value)
                .ok()
                .filter(|&v| (1..=1 << 16).contains(&v))
                .ok_or_else(|| {
                    element
                        .location
                        .error(format!("film {name} {value} must be in 1..=65536"))
                })
        };
        let width = dimension("width", 768)?;
        let height = dimension("height", 576)?;
        self.description.camera.resolution = [width, height];
        for crop in [
            "crop_offset_x",
            "crop_offset_y",
            "crop_width",
            "crop_height",
        ] {
            if let Some(parameter) = properties.get(crop) {
                self.warn(
                    parameter,
                    format!("film '{crop}' is not supported: the whole image is rendered"),
                );
            }
        }
        properties.ignore(&[
            "file_format",
            "pixel_format",
            "component_format",
            "banner",
            "high_quality_edges",
            "sample_border",
            "rfilter",
        ]);
        for object in &properties.objects {
            match object.tag.as_str() {
                "rfilter" => self.filter(object)?,
                other => self.warn(object, format!("<{other}> inside <film> is ignored")),
            }
        }
        self.finish(&properties);
        Ok(())
    }

    /// Reads an `<rfilter>`.
    fn filter(&mut self, element: &Element) -> Result<(), SceneFileError> {
        let properties = Properties::new(element);
        self.description.filter = match properties.plugin_type() {
            "box" => FilterDescription::Box { radius: 0.5 },
            "tent" => FilterDescription::Tent {
                radius: properties.float("radius", 1.0)?,
            },
            "gaussian" => {
                let sigma = properties.float("stddev", 0.5)?;
                FilterDescription::Gaussian {
                    radius: 4.0 * sigma,
                    sigma,
                }
            }
            other => {
                self.warn(
                    element,
                    format!("reconstruction filter '{other}' is not supported: using a Gaussian (σ = 0.5)"),
                );
                FilterDescription::Gaussian {
                    radius: 2.0,
                    sigma: 0.5,
                }
            }
        };
        self.finish(&properties);
        Ok(())
    }

    /// Reads a `<sensor>`.
    pub(super) fn sensor(&mut self, element: &Element) -> Result<(), SceneFileError> {
        if self.have_sensor {
            self.warn(
                element,
                "only the first <sensor> is used; this one is ignored",
            );
            return Ok(());
        }
        self.have_sensor = true;
        let properties = Properties::new(element);
        let kind = properties.plugin_type();
        if !matches!(kind, "perspective" | "thinlens") {
            self.warn(
                element,
                format!("sensor type '{kind}' is not supported: read as 'perspective'"),
            );
        }
        // Films and samplers first: the field of view may depend on the aspect.
        for object in &properties.objects {
            match object.tag.as_str() {
                "film" => self.film(object)?,
                "sampler" => {
                    let sampler = Properties::new(object);
                    if let Some(count) = sampler.optional_integer("sample_count")? {
                        if count < 1 {
                            return Err(object
                                .location
                                .error(format!("sample_count {count} must be at least 1")));
                        }
                        self.description.samples_per_pixel = Some(count as u64);
                    } else {
                        self.description.samples_per_pixel = Some(4);
                    }
                    sampler.ignore(&["seed", "jitter", "scramble_type"]);
                    self.finish(&sampler);
                }
                "medium" => self.description.camera_medium = self.medium(object)?,
                "ref" => match self.referenced(object)? {
                    NamedObject::Medium(index) => self.description.camera_medium = Some(index),
                    other => {
                        return Err(object.location.error(format!(
                            "a sensor can only refer to a medium, not to a {}",
                            other.kind()
                        )));
                    }
                },
                other => self.warn(object, format!("<{other}> inside <sensor> is ignored")),
            }
        }
        let to_world = properties
            .optional_transform("to_world")?
            .unwrap_or(Affine3A::IDENTITY);
        // Mitsuba's +x is the image's left; ours its right.
        let world_from_camera = to_world * Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let camera = &mut self.description.camera;
        camera.world_from_camera = world_from_camera;
        camera.world_from_camera_end = world_from_camera;
        let [width, height] = camera.resolution;
        let (fov, axis) = match properties.optional_float("fov")? {
            Some(fov) => (fov, properties.optional_string("fov_axis")?.unwrap_or("x")),
            None => {
                let focal = properties
                    .optional_string("focal_length")?
                    .unwrap_or("50mm");
                let millimetres = parse_number(focal.trim().trim_end_matches("mm"))
                    .ok()
                    .filter(|f| *f > 0.0)
                    .ok_or_else(|| {
                        element.location.error(format!(
                            "focal_length '{focal}': expected a length such as 50mm"
                        ))
                    })?;
                let fov = 2.0
                    * (FILM_DIAGONAL_MILLIMETRES / (2.0 * millimetres))
                        .atan()
                        .to_degrees();
                (fov, "diagonal")
            }
        };
        let camera = &mut self.description.camera;
        let (fov, axis) = match axis {
            "x" => (fov, FovAxis::X),
            "y" => (fov, FovAxis::Y),
            "smaller" => (fov, FovAxis::Smaller),
            "larger" => (fov, FovAxis::Larger),
            "diagonal" => {
                let (w, h) = (width as f32, height as f32);
                let half = (fov.to_radians() / 2.0).tan() * w / (w * w + h * h).sqrt();
                (2.0 * half.atan().to_degrees(), FovAxis::X)
            }
            other => {
                return Err(element.location.error(format!(
                    "fov_axis '{other}': expected x, y, diagonal, smaller or larger"
                )));
            }
        };
        camera.fov_degrees = fov;
        camera.fov_axis = axis;
        camera.shutter = [
            properties.float("shutter_open", 0.0)?,
            properties.float("shutter_close", 0.0)?,
        ];
        if kind == "thinlens" {
            camera.lens_radius = properties.float("aperture_radius", 0.03)?;
            camera.focus_distance = properties.float("focus_distance", 1.0)?;
        }
        properties.ignore(&[
            "near_clip",
            "far_clip",
            "principal_point_offset_x",
            "principal_point_offset_y",
            "srf",
        ]);
        self.finish(&properties);
        Ok(())
    }
}

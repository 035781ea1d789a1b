//! Area lights whose radiance is a texture over the shape's uv (Mitsuba 3's
//! `area` emitter with a `bitmap` `radiance`).
//!
//! Mitsuba 3.9.1 (`scalar_spectral`) evaluates such a radiance exactly as the
//! same bitmap used as a reflectance: the RGB texel's sigmoid spectrum,
//! without D65 (measured with `emitter.eval` on the `various_emitters` test
//! scene: the ratio to the plain `bitmap` texture is 1 at every wavelength),
//! so the texture is built with [`crate::spectrum::SpectrumUsage::Albedo`]
//! for Mitsuba scenes.
//!
//! Sampling is that of the untextured light — uniform by area over meshes,
//! the subtended cone for spheres, uniform over disks — so the densities for
//! multiple importance sampling are the shape's, as for [`super::Light::Area`].
//! The sampled point's uv comes from its triangle's barycentrics (meshes) or
//! from the shape's hit record at the point (spheres, disks).

use glam::{Vec2, Vec3};

use crate::geometry::{Ray, Shape, ShapeSample};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{SpectrumTexture, TextureContext};

/// A shape emitting a textured radiance from its front side.
#[derive(Debug, Clone)]
pub struct TexturedAreaLight {
    /// The emitting shape.
    pub shape_index: u32,
    /// Emitted radiance over the shape's uv.
    pub radiance: SpectrumTexture,
    /// Emission and sampling use the reversed normal.
    pub flip_normals: bool,
    /// The mean over the texture of the spectrum's largest value, for light
    /// selection by power.
    pub mean_scale: f32,
}

/// Side of the grid on which [`TexturedAreaLight::new`] averages the texture.
const POWER_GRID: usize = 64;

impl TexturedAreaLight {
    /// A textured area light; its power scale is the texture's mean (over a
    /// 64 × 64 grid of uv in [0, 1]², at four visible wavelengths).
    pub fn new(shape_index: u32, radiance: SpectrumTexture, flip_normals: bool) -> Self {
        let wavelengths = SampledWavelengths::sample_visible(0.5);
        let mut sum = 0.0f64;
        for y in 0..POWER_GRID {
            for x in 0..POWER_GRID {
                let uv = Vec2::new(
                    (x as f32 + 0.5) / POWER_GRID as f32,
                    (y as f32 + 0.5) / POWER_GRID as f32,
                );
                let value = radiance.evaluate(
                    &TextureContext {
                        uv,
                        point: Vec3::ZERO,
                    },
                    &wavelengths,
                );
                sum += value.max_component() as f64;
            }
        }
        Self {
            shape_index,
            radiance,
            flip_normals,
            mean_scale: (sum / (POWER_GRID * POWER_GRID) as f64) as f32,
        }
    }

    /// The front normal for a normal as stored in the geometry.
    pub fn front(&self, stored_normal: Vec3) -> Vec3 {
        if self.flip_normals {
            -stored_normal
        } else {
            stored_normal
        }
    }

    /// The radiance at surface coordinates `uv` (emission textures are
    /// looked up by uv only: images and checkerboards).
    pub fn radiance_at(&self, uv: Vec2, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.evaluate(
            &TextureContext {
                uv,
                point: Vec3::ZERO,
            },
            wavelengths,
        )
    }

    /// Radiance leaving a point with stored normal `normal` and uv `uv`
    /// towards `wo` (zero from the back).
    pub fn emitted_radiance(
        &self,
        normal: Vec3,
        uv: Vec2,
        wo: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        if self.front(normal).dot(wo) > 0.0 {
            self.radiance_at(uv, wavelengths)
        } else {
            SampledSpectrum::zero()
        }
    }
}

/// A point on `shape` sampled as [`Shape::sample_from`] samples it (for
/// `reference`; `None` samples uniformly by area as [`Shape::sample_area`]),
/// with the uv of the point.
pub fn sample_with_uv(
    shape: &Shape,
    reference: Option<Vec3>,
    u_primitive: f32,
    u: Vec2,
) -> Option<(ShapeSample, Vec2)> {
    match shape {
        Shape::Mesh(mesh) => {
            let (sample, triangle) = mesh.sample_area(u_primitive, u)?;
            let barycentric = barycentric_of(sample.point, mesh.triangle_vertices(triangle))?;
            let uv = mesh.surface_hit(triangle, barycentric, 0.0, 0.0).uv;
            Some((sample, uv))
        }
        _ => {
            let sample = match reference {
                Some(reference) => shape.sample_from(reference, u_primitive, u)?,
                None => shape.sample_area(u_primitive, u)?,
            };
            let uv = analytic_uv(shape, sample.point, sample.normal)?;
            Some((sample, uv))
        }
    }
}

/// The barycentric weights of `point` (in the triangle's plane) with
/// respect to `vertices`, from the sub-triangle areas; `None` for a
/// degenerate triangle.
fn barycentric_of(point: Vec3, [p0, p1, p2]: [Vec3; 3]) -> Option<[f32; 3]> {
    let normal = (p1 - p0).cross(p2 - p0);
    let area2 = normal.length_squared();
    if !(area2 > 0.0 && area2.is_finite()) {
        return None;
    }
    let b1 = (point - p0).cross(p2 - p0).dot(normal) / area2;
    let b2 = (p1 - p0).cross(point - p0).dot(normal) / area2;
    let (b1, b2) = (b1.clamp(0.0, 1.0), b2.clamp(0.0, 1.0));
    let b0 = (1.0 - b1 - b2).max(0.0);
    Some([b0, b1, b2])
}

/// The uv of `point` on an analytic shape (sphere, disk): the shape's own
/// hit record for a ray arriving along `-normal` from just outside.
fn analytic_uv(shape: &Shape, point: Vec3, normal: Vec3) -> Option<Vec2> {
    let offset = 1e-3 * (1.0 + point.abs().max_element());
    let ray = Ray::new(point + normal * offset, -normal);
    shape
        .intersect_brute_force(&ray, 2.0 * offset)
        .map(|hit| hit.uv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Sphere, Transform, TriangleMesh};
    use glam::Mat4;

    /// The uv of a sampled point is the uv a ray hitting that point sees.
    #[test]
    fn sampled_uv_matches_the_hit_uv() {
        let to_world = Mat4::from_rotation_x(0.4) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let mesh = TriangleMesh::rectangle(&Transform::from_matrix(to_world).unwrap()).unwrap();
        let shapes = [
            Shape::Mesh(mesh),
            Shape::Sphere(Sphere::new(Vec3::new(0.5, 0.2, -0.1), 0.7).unwrap()),
        ];
        for shape in &shapes {
            for i in 0..200 {
                let u = Vec2::new((i as f32 * 0.618_034).fract(), (i as f32 + 0.5) / 200.0);
                let (sample, uv) =
                    sample_with_uv(shape, None, (i as f32 * 0.414_213_5).fract(), u).unwrap();
                let ray = Ray::new(sample.point + sample.normal * 0.01, -sample.normal);
                let hit = shape.intersect_brute_force(&ray, 1.0).unwrap();
                assert!(
                    (hit.uv - uv).abs().max_element() < 1e-3,
                    "{:?} vs {uv:?}",
                    hit.uv
                );
            }
        }
    }

    /// With a constant texture the textured light is the untextured one:
    /// the same samples, radiance and densities for next-event estimation
    /// and light tracing (and the sampled density is `pdf_incident`'s).
    #[test]
    fn a_constant_texture_equals_the_untextured_light() {
        use crate::geometry::Geometry;
        use crate::light::Light;
        use crate::spectrum::{ConstantSpectrum, Spectrum};
        let to_world = Mat4::from_rotation_x(0.4) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let mesh = TriangleMesh::rectangle(&Transform::from_matrix(to_world).unwrap()).unwrap();
        let geometry = Geometry::new(vec![
            Shape::Mesh(mesh),
            Shape::Sphere(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 0.5).unwrap()),
        ])
        .unwrap();
        let spectrum = Spectrum::Constant(ConstantSpectrum::new(1.7).unwrap());
        for shape_index in [0u32, 1] {
            let plain = Light::Area {
                shape_index,
                radiance: spectrum.clone(),
                flip_normals: false,
                scale: 1.7,
            };
            let textured = Light::TexturedArea(Box::new(TexturedAreaLight::new(
                shape_index,
                SpectrumTexture::Constant(spectrum.clone()),
                false,
            )));
            assert!((plain.power(&geometry) - textured.power(&geometry)).abs() < 1e-4);
            let wavelengths = SampledWavelengths::sample_visible(0.37);
            let reference = Vec3::new(0.3, 1.2, 2.0);
            for i in 0..100 {
                let u = [(i as f32 * 0.618_034).fract(), (i as f32 + 0.5) / 100.0];
                let u_primitive = (i as f32 * 0.414_213_5).fract();
                let a = plain.sample_incident(&geometry, reference, u_primitive, u, &wavelengths);
                let b =
                    textured.sample_incident(&geometry, reference, u_primitive, u, &wavelengths);
                assert_eq!(a.is_some(), b.is_some());
                if let (Some(a), Some(b)) = (a, b) {
                    assert!((a.point - b.point).length() < 1e-5);
                    assert!((a.pdf - b.pdf).abs() <= 1e-5 * a.pdf);
                    assert_eq!(a.radiance, b.radiance);
                    let stored = b.normal;
                    let pdf = textured.pdf_incident(&geometry, reference, b.point, stored);
                    assert!((pdf - b.pdf).abs() <= 1e-4 * b.pdf);
                    assert_eq!(
                        plain.emitted_radiance(stored, b.uv, -b.wi, &wavelengths),
                        textured.emitted_radiance(stored, b.uv, -b.wi, &wavelengths)
                    );
                }
                let a = plain.sample_emission(&geometry, u_primitive, u, [0.3, 0.8], &wavelengths);
                let b =
                    textured.sample_emission(&geometry, u_primitive, u, [0.3, 0.8], &wavelengths);
                let (a, b) = (a.unwrap(), b.unwrap());
                assert!((a.origin - b.origin).length() < 1e-5);
                assert!((a.direction - b.direction).length() < 1e-5);
                assert_eq!(a.radiance, b.radiance);
                assert_eq!(a.pdf_position, b.pdf_position);
                assert_eq!(a.pdf_direction, b.pdf_direction);
            }
        }
    }
}

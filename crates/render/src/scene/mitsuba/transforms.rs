//! Mitsuba's `<transform>`: a sequence of `translate`, `rotate`, `scale`,
//! `matrix` and `lookat` operations, each applied *after* the ones before it
//! (the result is `last · … · first`), as Mitsuba composes them.

use super::super::loader::SceneFileError;
use super::values::{parse_number, parse_numbers, parse_vector};
use super::xml::Element;
use glam::{Affine2, Affine3A, Mat3, Mat4, Vec2, Vec3};

/// Mitsuba's `look_at`: columns (left, up, direction, origin), with +z along
/// the view and +x to the image's *left* (Mitsuba's camera convention).
pub fn mitsuba_look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Affine3A> {
    let direction = (target - origin).normalize_or_zero();
    let left = up.cross(direction).normalize_or_zero();
    if direction == Vec3::ZERO || left == Vec3::ZERO {
        return None;
    }
    let new_up = direction.cross(left);
    Some(Affine3A::from_cols(
        left.into(),
        new_up.into(),
        direction.into(),
        origin.into(),
    ))
}

/// An `up` for a look-at without one: the world axis least aligned with the view.
fn some_up(direction: Vec3) -> Vec3 {
    let d = direction.abs();
    if d.x <= d.y && d.x <= d.z {
        Vec3::X
    } else if d.y <= d.z {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// One operation of a `<transform>`.
fn operation(element: &Element) -> Result<Affine3A, SceneFileError> {
    let error = |message: String| {
        element
            .location
            .error(format!("<{}>: {message}", element.tag))
    };
    match element.tag.as_str() {
        "translate" => Ok(Affine3A::from_translation(parse_vector(element, 0.0)?)),
        "scale" => {
            let factors = parse_vector(element, 1.0)?;
            if factors.cmpeq(Vec3::ZERO).any() {
                return Err(error("a scale factor is zero".into()));
            }
            Ok(Affine3A::from_scale(factors))
        }
        "rotate" => {
            let axis = parse_vector(element, 0.0)?;
            let angle = parse_number(element.required("angle")?).map_err(error)?;
            let axis = axis.normalize_or_zero();
            if axis == Vec3::ZERO {
                return Err(error("the rotation axis is zero".into()));
            }
            Ok(Affine3A::from_axis_angle(axis, angle.to_radians()))
        }
        "matrix" => {
            let numbers = parse_numbers(element.required("value")?).map_err(error)?;
            let matrix = match numbers.len() {
                // Row-major in the file; glam takes columns.
                16 => Mat4::from_cols_slice(&numbers).transpose(),
                9 => Mat4::from_mat3(Mat3::from_cols_slice(&numbers).transpose()),
                count => return Err(error(format!("expected 16 or 9 numbers, got {count}"))),
            };
            let bottom = matrix.row(3);
            if (bottom - glam::Vec4::W).abs().max_element() > 1e-6 {
                return Err(error(
                    "projective matrices are not supported (last row must be 0 0 0 1)".into(),
                ));
            }
            if !matrix.is_finite() || matrix.determinant() == 0.0 {
                return Err(error("the matrix is singular or not finite".into()));
            }
            Ok(Affine3A::from_mat4(matrix))
        }
        "lookat" => {
            let vector = |name: &str| -> Result<Option<Vec3>, SceneFileError> {
                element
                    .attribute(name)
                    .map(|text| {
                        let numbers = parse_numbers(text).map_err(error)?;
                        match numbers.as_slice() {
                            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
                            _ => Err(error(format!("'{name}' needs 3 numbers, got '{text}'"))),
                        }
                    })
                    .transpose()
            };
            let origin = vector("origin")?.unwrap_or(Vec3::ZERO);
            let target = vector("target")?.unwrap_or(Vec3::Z);
            let up = match vector("up")? {
                Some(up) => up,
                None => some_up(target - origin),
            };
            mitsuba_look_at(origin, target, up).ok_or_else(|| {
                error("origin and target coincide, or up is parallel to the view".into())
            })
        }
        other => Err(error(format!(
            "unknown transform operation <{other}> (expected translate, rotate, scale, matrix or lookat)"
        ))),
    }
}

/// A `<transform>` element's matrix.
pub fn parse_transform(element: &Element) -> Result<Affine3A, SceneFileError> {
    let mut result = Affine3A::IDENTITY;
    for child in &element.children {
        result = operation(child)? * result;
    }
    if !result.is_finite() {
        return Err(element.location.error("the transform is not finite"));
    }
    Ok(result)
}

/// The 2-D part of a texture's `to_uv` (x and y rows, translation).
pub fn to_uv_2d(matrix: Affine3A) -> Affine2 {
    let m = matrix.matrix3;
    Affine2::from_cols(
        Vec2::new(m.x_axis.x, m.x_axis.y),
        Vec2::new(m.y_axis.x, m.y_axis.y),
        Vec2::new(matrix.translation.x, matrix.translation.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mitsuba::xml::Location;
    use std::path::PathBuf;
    use std::sync::Arc;

    fn element(tag: &str, attributes: &[(&str, &str)], children: Vec<Element>) -> Element {
        Element {
            tag: tag.into(),
            attributes: attributes
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            children,
            location: Location {
                file: Arc::new(PathBuf::from("t.xml")),
                line: 2,
            },
        }
    }

    #[test]
    fn operations_compose_in_document_order() {
        // scale 2, then rotate 90° about z, then translate x by 1:
        // (1, 0, 0) → (2, 0, 0) → (0, 2, 0) → (1, 2, 0).
        let transform = element(
            "transform",
            &[("name", "to_world")],
            vec![
                element("scale", &[("value", "2")], vec![]),
                element("rotate", &[("z", "1"), ("angle", "90")], vec![]),
                element("translate", &[("x", "1")], vec![]),
            ],
        );
        let matrix = parse_transform(&transform).unwrap();
        let p = matrix.transform_point3(Vec3::X);
        assert!((p - Vec3::new(1.0, 2.0, 0.0)).length() < 1e-5, "{p}");
    }

    #[test]
    fn matrix_is_row_major() {
        let transform = element(
            "transform",
            &[],
            vec![element(
                "matrix",
                &[("value", "1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1")],
                vec![],
            )],
        );
        let matrix = parse_transform(&transform).unwrap();
        assert_eq!(Vec3::from(matrix.translation), Vec3::new(5.0, 6.0, 7.0));
    }

    #[test]
    fn look_at_has_x_to_the_left() {
        let transform = element(
            "transform",
            &[],
            vec![element(
                "lookat",
                &[("origin", "0,0,0"), ("target", "0,0,1"), ("up", "0,1,0")],
                vec![],
            )],
        );
        let matrix = parse_transform(&transform).unwrap();
        // Looking along +z with +y up in a right-handed world, the left is +x.
        assert!((Vec3::from(matrix.matrix3.x_axis) - Vec3::X).length() < 1e-6);
        assert!((Vec3::from(matrix.matrix3.z_axis) - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn bad_operations_are_errors_with_line() {
        for bad in [
            element("rotate", &[("angle", "10")], vec![]),
            element("matrix", &[("value", "1 2 3")], vec![]),
            element("shear", &[], vec![]),
            element(
                "lookat",
                &[("origin", "0,0,0"), ("target", "0,0,0")],
                vec![],
            ),
        ] {
            let error = parse_transform(&element("transform", &[], vec![bad]))
                .unwrap_err()
                .to_string();
            assert!(error.starts_with("t.xml:2:"), "{error}");
        }
    }
}

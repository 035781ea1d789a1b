//! Statistical tests of shape sampling in `render::geometry`: chi-square
//! goodness of fit for triangles, disks, rectangle meshes (including unequal
//! triangle areas, exercising the alias table) and sphere solid-angle sampling,
//! and Monte Carlo checks that `E[1/pdf]` equals the subtended solid angle.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use render::geometry::{Disk, Shape, Sphere, Transform, TriangleMesh, coordinate_frame};
use render::statistics::chi_square_test;

mod common;
use common::TestRng;

const P_VALUE_THRESHOLD: f64 = 1e-4;
const SAMPLES: usize = 200_000;
const GRID: usize = 16;

/// Histogram of points of `[0,1]²` on a `GRID × GRID` grid.
fn histogram(points: impl Iterator<Item = (f64, f64)>) -> Vec<u64> {
    let mut counts = vec![0; GRID * GRID];
    for (x, y) in points {
        let i = ((x * GRID as f64) as usize).min(GRID - 1);
        let j = ((y * GRID as f64) as usize).min(GRID - 1);
        counts[j * GRID + i] += 1;
    }
    counts
}

fn assert_uniform_on_square(points: impl Iterator<Item = (f64, f64)>, what: &str) {
    let observed = histogram(points);
    let expected = vec![SAMPLES as f64 / (GRID * GRID) as f64; GRID * GRID];
    let p = chi_square_test(&observed, &expected).p_value;
    assert!(p > P_VALUE_THRESHOLD, "{what}: chi-square p-value {p}");
}

/// Barycentric coordinates `(b1, b2)` of `p` in triangle `(p0, p1, p2)`.
fn barycentric(p: Vec3, [p0, p1, p2]: [Vec3; 3]) -> (f64, f64) {
    let (p, p0, p1, p2) = (p.as_dvec3(), p0.as_dvec3(), p1.as_dvec3(), p2.as_dvec3());
    let normal = (p1 - p0).cross(p2 - p0);
    let area2 = normal.length_squared();
    let b1 = (p - p0).cross(p2 - p0).dot(normal) / area2;
    let b2 = (p1 - p0).cross(p - p0).dot(normal) / area2;
    (b1, b2)
}

#[test]
fn triangle_sampling_is_uniform() {
    let transform = Transform::translate(Vec3::new(1.0, -2.0, 3.0))
        * Transform::rotate(40.0, Vec3::new(1.0, 2.0, 0.5)).unwrap();
    let vertices = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(3.0, 0.5, 0.0),
        Vec3::new(-1.0, 2.0, 0.2),
    ];
    let mesh = TriangleMesh::new(vertices, None, None, vec![[0, 1, 2]], &transform).unwrap();
    let corners = mesh.triangle_vertices(0);
    let area = mesh.surface_area();
    let shape = Shape::Mesh(mesh);
    let mut rng = TestRng(1);
    let mut coordinates = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        let sample = shape.sample_area(rng.uniform(), rng.uniform2()).unwrap();
        assert!((sample.pdf_area - 1.0 / area).abs() < 1e-6 / area);
        coordinates.push(barycentric(sample.point, corners));
    }
    let observed = histogram(coordinates.into_iter());
    // Uniform on {b1, b2 ≥ 0, b1 + b2 ≤ 1}: cells below the diagonal have full
    // area, cells cut by it half, the rest none (total area 1/2).
    let cell = 1.0 / (GRID * GRID) as f64;
    let expected: Vec<f64> = (0..GRID * GRID)
        .map(|k| {
            let (i, j) = (k % GRID, k / GRID);
            let fraction = match (i + j + 1).cmp(&GRID) {
                std::cmp::Ordering::Less => 1.0,
                std::cmp::Ordering::Equal => 0.5,
                std::cmp::Ordering::Greater => 0.0,
            };
            SAMPLES as f64 * fraction * cell * 2.0
        })
        .collect();
    let p = chi_square_test(&observed, &expected).p_value;
    assert!(p > P_VALUE_THRESHOLD, "triangle: p = {p}");
}

#[test]
fn disk_sampling_is_uniform() {
    // An ellipse: rotated, non-uniformly scaled unit disk.
    let transform = Transform::translate(Vec3::new(0.0, 5.0, 0.0))
        * Transform::rotate(70.0, Vec3::new(0.3, 1.0, 0.0)).unwrap()
        * Transform::scale(Vec3::new(2.0, 0.5, 1.0)).unwrap();
    let disk = Disk::new(transform).unwrap();
    let expected_area = std::f32::consts::PI * 2.0 * 0.5;
    assert!((disk.surface_area() - expected_area).abs() < 1e-5);
    let to_object = transform.inverse();
    let mut rng = TestRng(2);
    let points = (0..SAMPLES).map(|_| {
        let sample = disk.sample_area(rng.uniform2());
        let local = to_object.point(sample.point).as_dvec3();
        // Uniform on the disk ⇔ (r², φ/2π) uniform on the square.
        let phi = local.y.atan2(local.x).rem_euclid(2.0 * PI);
        (
            (local.x * local.x + local.y * local.y).min(1.0),
            phi / (2.0 * PI),
        )
    });
    assert_uniform_on_square(points, "disk");
}

#[test]
fn rectangle_mesh_sampling_is_uniform() {
    let transform = Transform::translate(Vec3::new(0.0, 0.0, -4.0))
        * Transform::rotate(25.0, Vec3::Y).unwrap()
        * Transform::scale(Vec3::new(3.0, 1.0, 1.0)).unwrap();
    let rectangle = Shape::Mesh(TriangleMesh::rectangle(&transform).unwrap());
    let to_object = transform.inverse();
    let mut rng = TestRng(3);
    let points = (0..SAMPLES).map(|_| {
        let sample = rectangle
            .sample_area(rng.uniform(), rng.uniform2())
            .unwrap();
        assert!((sample.normal - transform.normal(Vec3::Z).normalize()).length() < 1e-5);
        let local = to_object.point(sample.point).as_dvec3();
        (0.5 * (local.x + 1.0), 0.5 * (local.y + 1.0))
    });
    assert_uniform_on_square(points, "rectangle");

    // The rectangle [0,2]×[0,1] cut into triangles of areas 1/4, 3/4 and 1: the
    // alias table must pick them by area for the union to be uniform.
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let mesh = TriangleMesh::new(
        positions,
        None,
        None,
        vec![[0, 1, 4], [1, 2, 3], [1, 3, 4]],
        &Transform::IDENTITY,
    )
    .unwrap();
    let shape = Shape::Mesh(mesh);
    let points = (0..SAMPLES).map(|_| {
        let sample = shape.sample_area(rng.uniform(), rng.uniform2()).unwrap();
        assert!((sample.pdf_area - 0.5).abs() < 1e-6);
        (0.5 * sample.point.x as f64, sample.point.y as f64)
    });
    assert_uniform_on_square(points, "unequal triangles");
}

/// `(1 - cos θ, φ)` of the direction from `reference` to `point` around the axis
/// towards `center`, with `1 - cos θ = sin²θ/(1 + cos θ)` to avoid cancellation.
fn cone_coordinates(reference: Vec3, center: Vec3, point: Vec3) -> (f64, f64) {
    let axis = (center - reference).as_dvec3().normalize();
    let direction = (point - reference).as_dvec3().normalize();
    let cos_theta = direction.dot(axis);
    let sin2_theta = direction.cross(axis).length_squared();
    let (s, t) = coordinate_frame(axis.as_vec3());
    let phi = direction
        .dot(t.as_dvec3())
        .atan2(direction.dot(s.as_dvec3()))
        .rem_euclid(2.0 * PI);
    (sin2_theta / (1.0 + cos_theta), phi)
}

#[test]
fn sphere_solid_angle_sampling_is_uniform_in_the_cone() {
    let center = Vec3::new(1.0, 2.0, 3.0);
    let radius = 0.5;
    let sphere = Sphere::new(center, radius).unwrap();
    let shape = Shape::Sphere(sphere);
    // A wide cone (distance 1.5 r) and a tiny one (distance 100 r, below the
    // small-angle threshold of the sampler).
    for (distance, seed) in [(0.75f32, 4u64), (50.0, 5)] {
        let reference = center + distance * Vec3::new(0.48, -0.6, 0.64);
        let sin2_max = (radius as f64 / distance as f64).powi(2);
        let one_minus_cos_max = sin2_max / (1.0 + (1.0 - sin2_max).sqrt());
        let mut rng = TestRng(seed);
        let points = (0..SAMPLES).map(|_| {
            let sample = shape
                .sample_from(reference, rng.uniform(), rng.uniform2())
                .unwrap();
            assert!((sample.point.distance(center) - radius).abs() < 1e-5);
            let (one_minus_cos, phi) = cone_coordinates(reference, center, sample.point);
            (
                (one_minus_cos / one_minus_cos_max).min(1.0),
                phi / (2.0 * PI),
            )
        });
        assert_uniform_on_square(points, &format!("sphere cone at distance {distance}"));
    }
    // From inside: uniform by area ⇔ ((1 - z)/2, φ/2π) uniform.
    let mut rng = TestRng(6);
    let points = (0..SAMPLES).map(|_| {
        let sample = shape
            .sample_from(center + Vec3::new(0.1, 0.0, 0.2), 0.0, rng.uniform2())
            .unwrap();
        let n = sample.normal.as_dvec3();
        (
            0.5 * (1.0 - n.z),
            n.y.atan2(n.x).rem_euclid(2.0 * PI) / (2.0 * PI),
        )
    });
    assert_uniform_on_square(points, "sphere from inside");
}

/// Mean and standard error of `values`.
fn mean_and_standard_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Asserts `E[1/pdf_solid_angle] = solid_angle` for samples from `shape` seen
/// from `reference`, within 5 standard errors plus a relative `rounding`
/// allowance for the single-precision pdf.
fn assert_inverse_pdf_integrates_to(
    shape: &Shape,
    reference: Vec3,
    solid_angle: f64,
    rounding: f64,
    seed: u64,
) {
    let mut rng = TestRng(seed);
    let values: Vec<f64> = (0..SAMPLES)
        .filter_map(|_| {
            let sample = shape.sample_from(reference, rng.uniform(), rng.uniform2())?;
            // Samples seen edge-on have zero solid-angle density: their
            // contribution 1/pdf is then taken as 0 (measure-zero set).
            let pdf = sample.solid_angle_pdf(reference) as f64;
            // The pdf function used for MIS must agree with the sample's density.
            let evaluated =
                shape.pdf_solid_angle_from(reference, sample.point, sample.normal) as f64;
            if pdf > 0.0 {
                assert!(
                    (evaluated - pdf).abs() <= 1e-3 * pdf,
                    "pdf {evaluated} vs sampled {pdf}"
                );
            }
            Some(if pdf > 0.0 { 1.0 / pdf } else { 0.0 })
        })
        .collect();
    let (mean, standard_error) = mean_and_standard_error(&values);
    let tolerance = 5.0 * standard_error + rounding * solid_angle;
    assert!(
        (mean - solid_angle).abs() <= tolerance,
        "E[1/pdf] = {mean} ± {standard_error}, expected {solid_angle}"
    );
}

#[test]
fn inverse_solid_angle_pdf_integrates_to_the_solid_angle() {
    // Sphere: 2π(1 - cos θmax) for a wide and a tiny cone.
    let center = Vec3::new(-1.0, 0.5, 2.0);
    let radius = 0.7f32;
    let sphere = Shape::Sphere(Sphere::new(center, radius).unwrap());
    for (distance, seed) in [(1.2f32, 7u64), (3.0, 8), (70.0, 9)] {
        let reference = center + distance * Vec3::new(0.0, 0.6, -0.8);
        let sin2_max = (radius as f64 / distance as f64).powi(2);
        let solid_angle = 2.0 * PI * sin2_max / (1.0 + (1.0 - sin2_max).sqrt());
        // The density is constant, so only rounding of the area/solid-angle
        // conversion in f32 contributes (relative 1e-3 allowed).
        assert_inverse_pdf_integrates_to(&sphere, reference, solid_angle, 1e-3, seed);
    }

    // Triangle: the Van Oosterom–Strackee formula
    // tan(Ω/2) = |a·(b×c)| / (abc + (a·b)c + (a·c)b + (b·c)a).
    let vertices = [
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(1.5, 0.0, 2.5),
        Vec3::new(0.0, 1.0, 1.5),
    ];
    let triangle = Shape::Mesh(
        TriangleMesh::new(
            vertices.to_vec(),
            None,
            None,
            vec![[0, 1, 2]],
            &Transform::IDENTITY,
        )
        .unwrap(),
    );
    let reference = Vec3::new(0.2, 0.1, -0.5);
    let [a, b, c]: [DVec3; 3] = vertices.map(|v| (v - reference).as_dvec3());
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c)).abs();
    let denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    let solid_angle = 2.0 * numerator.atan2(denominator);
    assert_inverse_pdf_integrates_to(&triangle, reference, solid_angle, 1e-4, 10);

    // Disk seen from its axis at height h: 2π(1 - h/√(h² + R²)).
    let radius = 1.5f64;
    let height = 2.0f64;
    let disk = Shape::Disk(
        Disk::new(
            Transform::translate(Vec3::new(0.0, 0.0, 1.0))
                * Transform::scale(Vec3::splat(radius as f32)).unwrap(),
        )
        .unwrap(),
    );
    let solid_angle = 2.0 * PI * (1.0 - height / (height * height + radius * radius).sqrt());
    assert_inverse_pdf_integrates_to(
        &disk,
        Vec3::new(0.0, 0.0, 1.0 + height as f32),
        solid_angle,
        1e-4,
        11,
    );
}

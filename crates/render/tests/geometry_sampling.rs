//! Statistical tests of shape sampling in `render::geometry`: chi-square
//! goodness of fit for triangles, disks, rectangle meshes (including unequal
//! triangle areas, exercising the alias table) and sphere solid-angle sampling,
//! and Monte Carlo checks that `E[1/pdf]` equals the subtended solid angle.

use std::f64::consts::PI;

use glam::{DVec3, Vec2, Vec3};
use render::geometry::{Disk, Shape, Sphere, Transform, TriangleMesh, coordinate_frame};

/// SplitMix64: a tiny deterministic generator for test inputs.
struct TestRng(u64);

impl TestRng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn uniform(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn uniform2(&mut self) -> Vec2 {
        Vec2::new(self.uniform(), self.uniform())
    }
}

/// `ln Γ(x)` for `x > 0`: shift up to `x ≥ 10` with `Γ(x+1) = xΓ(x)`, then the
/// Stirling series to the `x⁻⁵` term (truncation error below 1e-10 there, the next term being 1/(1680 x⁷)).
fn ln_gamma(mut x: f64) -> f64 {
    let mut shift = 0.0;
    while x < 10.0 {
        shift -= x.ln();
        x += 1.0;
    }
    let inverse = 1.0 / x;
    let inverse2 = inverse * inverse;
    shift + (x - 0.5) * x.ln() - x
        + 0.5 * (2.0 * PI).ln()
        + inverse * (1.0 / 12.0 - inverse2 * (1.0 / 360.0 - inverse2 / 1260.0))
}

/// The regularised upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)`:
/// the power series of `P(a, x)` for `x < a + 1`, otherwise the continued fraction
/// of `Q` evaluated with the modified Lentz method.
fn regularized_upper_gamma(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        // P(a, x) = e^{-x} x^a / Γ(a+1) · Σ_n x^n / ((a+1)…(a+n)).
        let (mut term, mut sum, mut denominator) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            denominator += 1.0;
            term *= x / denominator;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        // Q(a, x) = e^{-x} x^a · 1/(x+1-a- 1·(1-a)/(x+3-a- 2·(2-a)/(x+5-a- …))).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut fraction = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            fraction *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        fraction * log_prefactor.exp()
    }
}

/// Pearson's chi-square test of observed counts against expected counts. Bins
/// with expected count below 5 are pooled (and the pool joined to the smallest
/// regular bin if it is still below 5). Returns the p-value.
fn chi_square_p_value(observed: &[f64], expected: &[f64]) -> f64 {
    let mut bins: Vec<(f64, f64)> = Vec::new();
    let (mut pooled_observed, mut pooled_expected) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pooled_observed += o;
            pooled_expected += e;
        } else {
            bins.push((o, e));
        }
    }
    if pooled_expected >= 5.0 {
        bins.push((pooled_observed, pooled_expected));
    } else if pooled_expected > 0.0 || pooled_observed > 0.0 {
        let smallest = bins
            .iter_mut()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("at least one bin with expected count ≥ 5");
        smallest.0 += pooled_observed;
        smallest.1 += pooled_expected;
    }
    let statistic: f64 = bins.iter().map(|(o, e)| (o - e) * (o - e) / e).sum();
    let degrees_of_freedom = (bins.len() - 1) as f64;
    regularized_upper_gamma(0.5 * degrees_of_freedom, 0.5 * statistic)
}

const P_VALUE_THRESHOLD: f64 = 1e-4;
const SAMPLES: usize = 200_000;
const GRID: usize = 16;

/// Histogram of points of `[0,1]²` on a `GRID × GRID` grid.
fn histogram(points: impl Iterator<Item = (f64, f64)>) -> Vec<f64> {
    let mut counts = vec![0.0; GRID * GRID];
    for (x, y) in points {
        let i = ((x * GRID as f64) as usize).min(GRID - 1);
        let j = ((y * GRID as f64) as usize).min(GRID - 1);
        counts[j * GRID + i] += 1.0;
    }
    counts
}

fn assert_uniform_on_square(points: impl Iterator<Item = (f64, f64)>, what: &str) {
    let observed = histogram(points);
    let expected = vec![SAMPLES as f64 / (GRID * GRID) as f64; GRID * GRID];
    let p = chi_square_p_value(&observed, &expected);
    assert!(p > P_VALUE_THRESHOLD, "{what}: chi-square p-value {p}");
}

#[test]
fn chi_square_helper_is_calibrated() {
    // Q(1, x) = e^{-x}; Q(k/2, x/2) for k = 2 is the chi-square tail e^{-x/2}.
    assert!((regularized_upper_gamma(1.0, 2.5) - (-2.5f64).exp()).abs() < 1e-9);
    assert!((regularized_upper_gamma(1.0, 0.3) - (-0.3f64).exp()).abs() < 1e-9);
    // Q(1/2, x) = erfc(√x); erfc(1) = 0.157299207050285.
    assert!((regularized_upper_gamma(0.5, 1.0) - 0.157_299_207_050_285).abs() < 1e-10);
    // The median of chi-square with 100 dof is about 99.3341.
    assert!((regularized_upper_gamma(50.0, 0.5 * 99.3341) - 0.5).abs() < 1e-4);
    assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-9);
    // Gross misfit is detected.
    let observed = vec![150.0, 50.0, 100.0, 100.0];
    assert!(chi_square_p_value(&observed, &[100.0; 4]) < 1e-6);
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
    let p = chi_square_p_value(&observed, &expected);
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

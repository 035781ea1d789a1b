//! Sampling building blocks for shapes: the area-preserving map from the unit
//! square to triangles, an alias table for picking mesh triangles by area,
//! and the sample record shapes return. The disk and sphere maps are the
//! shared warps of [`crate::sampling`].

use glam::{Vec2, Vec3};

use super::GeometryError;

/// A point sampled on a shape's surface with the density it was sampled with,
/// expressed per unit area (see [`ShapeSample::solid_angle_pdf`] for the
/// conversion to solid angle at a reference point).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The sampled point (world space).
    pub point: Vec3,
    /// Unit geometric normal at the point, facing as authored (outward for
    /// spheres, the winding side for triangles, `+z` side for disks).
    pub normal: Vec3,
    /// Probability density with respect to surface area.
    pub pdf_area: f32,
}

impl ShapeSample {
    /// The density of this sample per unit solid angle as seen from `reference`.
    pub fn solid_angle_pdf(&self, reference: Vec3) -> f32 {
        area_pdf_to_solid_angle(self.pdf_area, reference, self.point, self.normal)
    }
}

/// Converts a density per unit area at `point` (with unit `normal`) to a density
/// per unit solid angle at `reference`: `pdf_area · d² / |cos θ|`, where `d` is the
/// distance and `θ` the angle between the normal and the direction to the
/// reference. Returns 0 (rather than infinity) when the point is seen exactly
/// edge-on or coincides with the reference, so callers can reject the sample.
///
/// Computed as `pdf_area · d² · d / |n · (reference − point)|` (the cosine
/// times the distance is the dot product): one square root and one division.
#[inline]
pub fn area_pdf_to_solid_angle(pdf_area: f32, reference: Vec3, point: Vec3, normal: Vec3) -> f32 {
    let to_reference = reference - point;
    let distance_squared = to_reference.length_squared();
    // Zero also when the points coincide.
    let cosine_times_distance = normal.dot(to_reference).abs();
    if cosine_times_distance == 0.0 {
        return 0.0;
    }
    pdf_area * distance_squared * distance_squared.sqrt() / cosine_times_distance
}

/// Uniform barycentric coordinates `(b0, b1, b2)` from a point of the unit square,
/// using the low-distortion area-preserving map of Heitz, "A Low-Distortion Map
/// Between Triangle and Square" (2019): the square is folded along its diagonal
/// so nearby square points stay nearby on the triangle (better for QMC than the
/// square-root parametrisation).
pub fn sample_uniform_triangle(u: Vec2) -> [f32; 3] {
    let (b0, b1) = if u.y > u.x {
        let b0 = 0.5 * u.x;
        (b0, u.y - b0)
    } else {
        let b1 = 0.5 * u.y;
        (u.x - b1, b1)
    };
    [b0, b1, 1.0 - b0 - b1]
}

/// Two unit vectors completing the unit vector `n` to a right-handed orthonormal
/// frame `(s, t, n)`, branch-free except for the sign, after Duff et al.,
/// "Building an Orthonormal Basis, Revisited" (JCGT 2017).
pub fn coordinate_frame(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Walker's alias method (with Vose's linear-time construction) for sampling an
/// index proportional to non-negative weights in O(1) with one uniform number.
#[derive(Clone, Debug)]
pub struct AliasTable {
    /// Per bin: probability of keeping the bin (else take its alias).
    keep_probability: Vec<f32>,
    alias: Vec<u32>,
    /// Normalised probabilities of each index.
    probability: Vec<f32>,
}

impl AliasTable {
    /// Builds the table; fails on an empty list, a negative or non-finite weight,
    /// or an all-zero list.
    pub fn new(weights: &[f32]) -> Result<Self, GeometryError> {
        if weights.is_empty() {
            return Err(GeometryError::InvalidMesh(
                "alias table needs at least one weight".into(),
            ));
        }
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return Err(GeometryError::NonFinite("alias table weight"));
        }
        let total: f64 = weights.iter().map(|&w| w as f64).sum();
        if total <= 0.0 {
            return Err(GeometryError::InvalidMesh(
                "alias table weights sum to zero".into(),
            ));
        }
        let count = weights.len();
        let probability: Vec<f32> = weights.iter().map(|&w| (w as f64 / total) as f32).collect();
        let mut scaled: Vec<f64> = weights
            .iter()
            .map(|&w| w as f64 / total * count as f64)
            .collect();
        let mut keep_probability = vec![1.0f32; count];
        let mut alias: Vec<u32> = (0..count as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..count).partition(|&i| scaled[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            keep_probability[s] = scaled[s] as f32;
            alias[s] = l as u32;
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // Whatever remains is 1 up to rounding.
        for i in small.into_iter().chain(large) {
            keep_probability[i] = 1.0;
            alias[i] = i as u32;
        }
        Ok(Self {
            keep_probability,
            alias,
            probability,
        })
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.probability.len()
    }

    /// Whether there are no entries (never true for a constructed table).
    pub fn is_empty(&self) -> bool {
        self.probability.is_empty()
    }

    /// The probability of index `i`.
    pub fn probability(&self, i: usize) -> f32 {
        self.probability[i]
    }

    /// An index drawn with probability proportional to its weight from `u` in `[0, 1)`.
    pub fn sample(&self, u: f32) -> usize {
        // Entries are indexed by `u32` aliases, so the count fits 32 bits.
        let count = self.len() as u32;
        let (bin, fraction) = alias_bin(u, count as f32, count - 1);
        if fraction < self.keep_probability[bin] {
            bin
        } else {
            self.alias[bin] as usize
        }
    }
}

/// The bin of an alias table of `bin_count` entries (as a float; `last_bin`
/// = count − 1) that `u` in `[0, 1)` falls in, and where in the bin it
/// falls, in `[0, 1)`: the keep-or-alias decision's number. In 32 bits,
/// which convert to and from floats more cheaply than `usize`.
#[inline]
fn alias_bin(u: f32, bin_count: f32, last_bin: u32) -> (usize, f32) {
    let scaled = u * bin_count;
    let bin = (scaled as u32).min(last_bin);
    (bin as usize, scaled - bin as f32)
}

/// One triangle of a mesh prepared for sampling points on it, with the
/// alias-table entry of its bin folded in, so that a sample reads one record
/// for the bin (and a second only when the bin's alias is taken) and computes
/// the point as a corner plus a barycentric combination of two edges, without
/// the cross product and normalisation the vertices alone would need.
#[derive(Clone, Copy, Debug)]
struct SampledTriangle {
    /// The first vertex.
    origin: Vec3,
    /// The second and third vertices minus the first.
    edge1: Vec3,
    edge2: Vec3,
    /// Unit winding normal `edge1 × edge2` (zero for a degenerate triangle,
    /// which the alias table never picks).
    normal: Vec3,
    /// The alias-table bin of the same index: the probability of keeping the
    /// bin, else the index to take.
    keep_probability: f32,
    alias: u32,
}

/// Picks a triangle of a mesh in proportion to its area (the mesh's
/// [`AliasTable`], with the same choice for the same number) and a uniform
/// point on it (Heitz's map, [`sample_uniform_triangle`]), from per-triangle
/// records built once (see [`SampledTriangle`]).
#[derive(Clone, Debug)]
pub struct TriangleSampler {
    triangles: Box<[SampledTriangle]>,
    /// The number of triangles as a float and the last index, for
    /// [`alias_bin`].
    bin_count: f32,
    last_bin: u32,
}

impl TriangleSampler {
    /// The sampler of the triangles `vertices` (world space, in index order)
    /// chosen by `areas`, their area table (one entry per triangle).
    pub fn new(areas: &AliasTable, vertices: impl ExactSizeIterator<Item = [Vec3; 3]>) -> Self {
        assert_eq!(areas.len(), vertices.len());
        let count = u32::try_from(areas.len()).expect("at most 2^32 triangles");
        let triangles = vertices
            .enumerate()
            .map(|(index, [p0, p1, p2])| {
                let (edge1, edge2) = (p1 - p0, p2 - p0);
                SampledTriangle {
                    origin: p0,
                    edge1,
                    edge2,
                    normal: edge1.cross(edge2).normalize_or_zero(),
                    keep_probability: areas.keep_probability[index],
                    alias: areas.alias[index],
                }
            })
            .collect();
        Self {
            triangles,
            bin_count: count as f32,
            last_bin: count - 1,
        }
    }

    /// The triangle `u_triangle` picks (as [`AliasTable::sample`]) and the
    /// point `u` places on it: `(point, unit normal, triangle index)`.
    #[inline]
    pub fn sample(&self, u_triangle: f32, u: Vec2) -> (Vec3, Vec3, usize) {
        let (bin, fraction) = alias_bin(u_triangle, self.bin_count, self.last_bin);
        let record = &self.triangles[bin];
        let (index, triangle) = if fraction < record.keep_probability {
            (bin, record)
        } else {
            let alias = record.alias as usize;
            (alias, &self.triangles[alias])
        };
        let [_, b1, b2] = sample_uniform_triangle(u);
        let point = triangle.origin + b1 * triangle.edge1 + b2 * triangle.edge2;
        (point, triangle.normal, index)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn alias_table_reproduces_weights() {
        let weights = [1.0, 0.0, 3.0, 6.0];
        let table = AliasTable::new(&weights).unwrap();
        let n = 100_000;
        let mut counts = [0usize; 4];
        for i in 0..n {
            counts[table.sample((i as f32 + 0.5) / n as f32)] += 1;
        }
        for (count, weight) in counts.iter().zip(weights) {
            // A stratified sweep reproduces the probabilities to O(count/n).
            assert_abs_diff_eq!(*count as f32 / n as f32, weight / 10.0, epsilon = 1e-3);
        }
        assert!(AliasTable::new(&[]).is_err());
        assert!(AliasTable::new(&[0.0]).is_err());
        assert!(AliasTable::new(&[-1.0, 2.0]).is_err());
    }

    #[test]
    fn triangle_sampler_picks_as_the_alias_table() {
        let triangles = [
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::ZERO, Vec3::Y * 3.0, Vec3::Z],
            [
                Vec3::ONE,
                Vec3::ONE + Vec3::X * 2.0,
                Vec3::ONE + Vec3::Z * 2.0,
            ],
        ];
        let areas: Vec<f32> = triangles
            .iter()
            .map(|[p0, p1, p2]| 0.5 * (*p1 - *p0).cross(*p2 - *p0).length())
            .collect();
        let table = AliasTable::new(&areas).unwrap();
        let sampler = TriangleSampler::new(&table, triangles.into_iter());
        for i in 0..1000 {
            let u_triangle = (i as f32 + 0.5) / 1000.0;
            let u = Vec2::new((i % 31) as f32 / 31.0, (i % 17) as f32 / 17.0);
            let (point, normal, index) = sampler.sample(u_triangle, u);
            assert_eq!(index, table.sample(u_triangle));
            let [p0, p1, p2] = triangles[index];
            let [b0, b1, b2] = sample_uniform_triangle(u);
            let expected = b0 * p0 + b1 * p1 + b2 * p2;
            assert!((point - expected).length() < 1e-5, "{point} {expected}");
            assert_eq!(normal, (p1 - p0).cross(p2 - p0).normalize());
        }
    }

    #[test]
    fn frame_is_orthonormal() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, -0.4, 0.5).normalize(),
            Vec3::X,
        ] {
            let (s, t) = coordinate_frame(n);
            assert_abs_diff_eq!(s.dot(t), 0.0, epsilon = 1e-6);
            assert_abs_diff_eq!(s.dot(n), 0.0, epsilon = 1e-6);
            assert_abs_diff_eq!(s.cross(t).dot(n), 1.0, epsilon = 1e-6);
        }
    }

    #[test]
    fn triangle_map_stays_in_domain() {
        for i in 0..32 {
            for j in 0..32 {
                let u = Vec2::new(i as f32 / 31.0, j as f32 / 31.0);
                let b = sample_uniform_triangle(u);
                assert!(b.iter().all(|&x| x >= -1e-6));
            }
        }
    }
}

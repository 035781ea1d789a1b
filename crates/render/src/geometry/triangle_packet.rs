//! Four triangles stored lane by lane (structure of arrays) and tested against
//! one ray at once with the watertight test of [`super::triangle`] (Woop,
//! Benthin & Wald 2013), four lanes per instruction.
//!
//! Each lane performs exactly the single-precision operations of the scalar
//! test, in the same order, so a packet and the scalar routine agree bit for
//! bit and edges shared by triangles in different packets stay watertight.
//! Where an edge function is exactly zero the scalar routine (with its
//! double-precision recomputation) decides that lane.
//!
//! Two storage layouts feed the same test: [`TrianglePacket`] carries the
//! vertices themselves (three cache lines, no further memory access), and
//! [`IndexedTrianglePacket`] only vertex indices into a shared array of
//! [`SharedVertex`] (one cache line; the vertices, shared by about six
//! triangles in a closed mesh, are gathered and transposed when tested). The
//! second needs a third of the memory, which is what counts once the scene no
//! longer fits in the last-level cache.

use glam::Vec3;

use super::PrimitiveReference;
use super::simd::F32x4;
use super::triangle::WatertightRay;

/// Triangles per packet.
pub(crate) const PACKET_LANES: usize = 4;

/// Up to four triangles of one BVH leaf. Unused lanes hold NaN vertices, for
/// which every comparison of the test is false, so they never report a hit.
///
/// 192 bytes, aligned to 64: exactly three cache lines. Each lane's shape and
/// triangle index are stored beside its vertices (as Embree's leaves store
/// geometry and primitive ids), so a closest-hit query that only needs ids,
/// distance and barycentrics touches no other memory after the traversal.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct TrianglePacket {
    /// `vertices[k][axis][lane]`: coordinate `axis` of vertex `k` of the lane's triangle.
    vertices: [[[f32; PACKET_LANES]; 3]; 3],
    /// Each lane's primitive slot (index into the accelerator's leaf-ordered
    /// primitive list); `u32::MAX` for unused lanes.
    slots: [u32; PACKET_LANES],
    /// Each lane's shape index (`u32::MAX` for unused lanes).
    shape_indices: [u32; PACKET_LANES],
    /// Each lane's triangle index within its mesh (`u32::MAX` for unused lanes).
    primitive_indices: [u32; PACKET_LANES],
}

/// One triangle given to [`TrianglePacket::new`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct PacketTriangle {
    pub(crate) vertices: [Vec3; 3],
    pub(crate) slot: u32,
    pub(crate) reference: PrimitiveReference,
}

impl TrianglePacket {
    /// A packet of one to four triangles.
    pub(crate) fn new(triangles: &[PacketTriangle]) -> Self {
        assert!((1..=PACKET_LANES).contains(&triangles.len()));
        let mut packet = Self {
            vertices: [[[f32::NAN; PACKET_LANES]; 3]; 3],
            slots: [u32::MAX; PACKET_LANES],
            shape_indices: [u32::MAX; PACKET_LANES],
            primitive_indices: [u32::MAX; PACKET_LANES],
        };
        for (lane, triangle) in triangles.iter().enumerate() {
            for (k, vertex) in triangle.vertices.iter().enumerate() {
                for axis in 0..3 {
                    packet.vertices[k][axis][lane] = vertex[axis];
                }
            }
            packet.slots[lane] = triangle.slot;
            packet.shape_indices[lane] = triangle.reference.shape_index;
            packet.primitive_indices[lane] = triangle.reference.primitive_index;
        }
        packet
    }

    /// The primitive slot of `lane`.
    #[inline(always)]
    pub(crate) fn slot(&self, lane: usize) -> u32 {
        self.slots[lane]
    }

    /// The shape and triangle index of `lane`.
    #[inline(always)]
    pub(crate) fn reference(&self, lane: usize) -> PrimitiveReference {
        PrimitiveReference {
            shape_index: self.shape_indices[lane],
            primitive_index: self.primitive_indices[lane],
        }
    }
}

/// Vertex coordinates of four triangles, lane by lane, as the test reads them.
trait LaneVertices {
    /// Coordinate `axis` of vertex `k` of the four lanes.
    fn row(&self, k: usize, axis: usize) -> F32x4;

    /// The three vertices of `lane`'s triangle.
    fn lane_vertices(&self, lane: usize) -> [Vec3; 3] {
        std::array::from_fn(|k| {
            Vec3::new(
                self.row(k, 0).to_array()[lane],
                self.row(k, 1).to_array()[lane],
                self.row(k, 2).to_array()[lane],
            )
        })
    }
}

impl LaneVertices for TrianglePacket {
    #[inline(always)]
    fn row(&self, k: usize, axis: usize) -> F32x4 {
        F32x4::load(&self.vertices[k][axis])
    }
}

/// A vertex of the shared array indexed by [`IndexedTrianglePacket`]s:
/// `x, y, z` and an unused fourth lane, 16-byte aligned so that one load
/// fetches it (and it never straddles a cache line).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(crate) struct SharedVertex([f32; 4]);

impl SharedVertex {
    /// The vertex of unused lanes: NaN coordinates never report a hit.
    pub(crate) const UNUSED: Self = Self([f32::NAN; 4]);

    pub(crate) fn new(position: Vec3) -> Self {
        Self([position.x, position.y, position.z, 0.0])
    }
}

/// Up to four triangles as indices into a shared [`SharedVertex`] array, and
/// their slots: 64 bytes, one cache line. Unused lanes index a
/// [`SharedVertex::UNUSED`] vertex and hold slot `u32::MAX`. Shape and
/// triangle indices are not stored: the accelerator looks them up by slot
/// once the closest hit is known.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(crate) struct IndexedTrianglePacket {
    /// `vertex_indices[k][lane]`: the shared vertex that is vertex `k` of the lane's triangle.
    vertex_indices: [[u32; PACKET_LANES]; 3],
    /// Each lane's primitive slot; `u32::MAX` for unused lanes.
    slots: [u32; PACKET_LANES],
}

/// One triangle given to [`IndexedTrianglePacket::new`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct IndexedPacketTriangle {
    pub(crate) vertex_indices: [u32; 3],
    pub(crate) slot: u32,
}

impl IndexedTrianglePacket {
    /// A packet of one to four triangles; unused lanes get `unused_vertex`
    /// (the index of a [`SharedVertex::UNUSED`] vertex).
    pub(crate) fn new(triangles: &[IndexedPacketTriangle], unused_vertex: u32) -> Self {
        assert!((1..=PACKET_LANES).contains(&triangles.len()));
        let mut packet = Self {
            vertex_indices: [[unused_vertex; PACKET_LANES]; 3],
            slots: [u32::MAX; PACKET_LANES],
        };
        for (lane, triangle) in triangles.iter().enumerate() {
            for k in 0..3 {
                packet.vertex_indices[k][lane] = triangle.vertex_indices[k];
            }
            packet.slots[lane] = triangle.slot;
        }
        packet
    }

    /// The primitive slot of `lane`.
    #[inline(always)]
    pub(crate) fn slot(&self, lane: usize) -> u32 {
        self.slots[lane]
    }

    /// The largest vertex index used (for the builder's check).
    pub(crate) fn max_vertex_index(&self) -> u32 {
        self.vertex_indices
            .iter()
            .flatten()
            .copied()
            .max()
            .unwrap_or(0)
    }

    /// Loads the packet's vertices from `vertices` into lane-by-lane rows.
    #[inline(always)]
    fn gather(&self, vertices: &[SharedVertex]) -> GatheredVertices {
        GatheredVertices {
            rows: std::array::from_fn(|k| {
                let [x, y, z, _] = F32x4::transpose(
                    self.vertex_indices[k].map(|index| F32x4::load(&vertices[index as usize].0)),
                );
                [x, y, z]
            }),
        }
    }
}

/// The vertices of an [`IndexedTrianglePacket`] after gathering.
struct GatheredVertices {
    /// `rows[k][axis]`.
    rows: [[F32x4; 3]; 3],
}

impl LaneVertices for GatheredVertices {
    #[inline(always)]
    fn row(&self, k: usize, axis: usize) -> F32x4 {
        self.rows[k][axis]
    }
}

/// A hit found in a packet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PacketHit {
    /// The lane (triangle) hit.
    pub(crate) lane: usize,
    /// Ray parameter.
    pub(crate) t: f32,
    /// Barycentric weights of the lane's three vertices.
    pub(crate) barycentric: [f32; 3],
}

/// The per-ray data of the watertight test broadcast to four lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PacketRay {
    scalar: WatertightRay,
    /// Origin coordinates along `kx`, `ky`, `kz`.
    origin: [F32x4; 3],
    shear_x: F32x4,
    shear_y: F32x4,
    shear_z: F32x4,
}

/// The lane-wise outcome of the test before the division.
struct LaneResults {
    /// Lanes hit (decided in single precision).
    hits: u32,
    /// Lanes with an edge function exactly zero, to be decided by the scalar test.
    undecided: u32,
    u: F32x4,
    v: F32x4,
    w: F32x4,
    determinant: F32x4,
    /// The scaled ray parameter with the determinant's sign removed.
    scaled_t: F32x4,
    determinant_abs: F32x4,
}

impl PacketRay {
    /// Prepares the ray of `scalar` for packets.
    #[inline]
    pub(crate) fn new(scalar: WatertightRay) -> Self {
        let [kx, ky, kz] = scalar.axes;
        Self {
            scalar,
            origin: {
                let origin = scalar.origin.to_array();
                [kx, ky, kz].map(|axis| F32x4::splat(origin[axis]))
            },
            shear_x: F32x4::splat(scalar.shear_x),
            shear_y: F32x4::splat(scalar.shear_y),
            shear_z: F32x4::splat(scalar.shear_z),
        }
    }

    /// The lane-wise test, the same operations as [`WatertightRay::intersect`].
    #[inline(always)]
    fn test(&self, packet: &impl LaneVertices, t_max: f32) -> LaneResults {
        let [kx, ky, kz] = self.scalar.axes;
        let relative = |k: usize| {
            let x = packet.row(k, kx).sub(self.origin[0]);
            let y = packet.row(k, ky).sub(self.origin[1]);
            let z = packet.row(k, kz).sub(self.origin[2]);
            (x.sub(self.shear_x.mul(z)), y.sub(self.shear_y.mul(z)), z)
        };
        let (ax, ay, az) = relative(0);
        let (bx, by, bz) = relative(1);
        let (cx, cy, cz) = relative(2);
        let u = cx.mul(by).sub(cy.mul(bx));
        let v = ax.mul(cy).sub(ay.mul(cx));
        let w = bx.mul(ay).sub(by.mul(ax));
        let zero = F32x4::splat(0.0);
        let undecided = u.eq(zero).or(v.eq(zero)).or(w.eq(zero));
        let negative = u.lt(zero).or(v.lt(zero)).or(w.lt(zero));
        let positive = u.gt(zero).or(v.gt(zero)).or(w.gt(zero));
        let determinant = u.add(v).add(w);
        let rejected = negative.and(positive).or(determinant.eq(zero));
        let scaled_t = u
            .mul(self.shear_z.mul(az))
            .add(v.mul(self.shear_z.mul(bz)))
            .add(w.mul(self.shear_z.mul(cz)));
        let scaled_t = scaled_t.xor_sign_of(determinant);
        let determinant_abs = determinant.abs();
        let in_range = scaled_t
            .gt(zero)
            .and(scaled_t.lt(F32x4::splat(t_max).mul(determinant_abs)));
        let hits = in_range.and_not(rejected).and_not(undecided).bits();
        LaneResults {
            hits,
            undecided: undecided.bits(),
            u,
            v,
            w,
            determinant,
            scaled_t,
            determinant_abs,
        }
    }

    /// The scalar test of one lane (for lanes with a zero edge function).
    #[cold]
    fn test_lane(&self, packet: &impl LaneVertices, lane: usize, t_max: f32) -> Option<PacketHit> {
        let [p0, p1, p2] = packet.lane_vertices(lane);
        self.scalar
            .intersect(p0, p1, p2, t_max)
            .map(|hit| PacketHit {
                lane,
                t: hit.t,
                barycentric: hit.barycentric,
            })
    }

    /// The closest hit among the packet's triangles with `0 < t < t_max`
    /// (the lowest lane among equal distances).
    #[inline(always)]
    pub(crate) fn closest_hit(&self, packet: &TrianglePacket, t_max: f32) -> Option<PacketHit> {
        self.closest_hit_in(packet, t_max)
    }

    /// [`PacketRay::closest_hit`] for an indexed packet over `vertices`.
    #[inline(always)]
    pub(crate) fn closest_hit_indexed(
        &self,
        packet: &IndexedTrianglePacket,
        vertices: &[SharedVertex],
        t_max: f32,
    ) -> Option<PacketHit> {
        self.closest_hit_in(&packet.gather(vertices), t_max)
    }

    /// [`PacketRay::any_hit`] for an indexed packet over `vertices`.
    #[inline(always)]
    pub(crate) fn any_hit_indexed(
        &self,
        packet: &IndexedTrianglePacket,
        vertices: &[SharedVertex],
        t_max: f32,
    ) -> bool {
        self.any_hit_in(&packet.gather(vertices), t_max)
    }

    #[inline(always)]
    fn closest_hit_in(&self, packet: &impl LaneVertices, t_max: f32) -> Option<PacketHit> {
        let lanes = self.test(packet, t_max);
        let mut best: Option<PacketHit> = None;
        if lanes.hits != 0 {
            let t = lanes.scaled_t.div(lanes.determinant_abs).to_array();
            let mut bits = lanes.hits;
            let mut best_lane = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            while bits != 0 {
                let lane = bits.trailing_zeros() as usize;
                if t[lane] < t[best_lane] {
                    best_lane = lane;
                }
                bits &= bits - 1;
            }
            // Only the winning lane's weights are needed: arrays are made
            // here, not in `test`, so packets without a hit skip the stores.
            let reciprocal = 1.0 / lanes.determinant.to_array()[best_lane];
            best = Some(PacketHit {
                lane: best_lane,
                t: t[best_lane],
                barycentric: [
                    lanes.u.to_array()[best_lane] * reciprocal,
                    lanes.v.to_array()[best_lane] * reciprocal,
                    lanes.w.to_array()[best_lane] * reciprocal,
                ],
            });
        }
        let mut undecided = lanes.undecided;
        while undecided != 0 {
            let lane = undecided.trailing_zeros() as usize;
            undecided &= undecided - 1;
            if let Some(hit) = self.test_lane(packet, lane, t_max)
                && best.is_none_or(|b| hit.t < b.t || (hit.t == b.t && lane < b.lane))
            {
                best = Some(hit);
            }
        }
        best
    }

    /// Whether any of the packet's triangles is hit with `0 < t < t_max`.
    #[inline(always)]
    pub(crate) fn any_hit(&self, packet: &TrianglePacket, t_max: f32) -> bool {
        self.any_hit_in(packet, t_max)
    }

    #[inline(always)]
    fn any_hit_in(&self, packet: &impl LaneVertices, t_max: f32) -> bool {
        let lanes = self.test(packet, t_max);
        if lanes.hits != 0 {
            return true;
        }
        let mut undecided = lanes.undecided;
        while undecided != 0 {
            let lane = undecided.trailing_zeros() as usize;
            undecided &= undecided - 1;
            if self.test_lane(packet, lane, t_max).is_some() {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packets_are_whole_cache_lines() {
        assert_eq!(std::mem::size_of::<TrianglePacket>(), 192);
        assert_eq!(std::mem::align_of::<TrianglePacket>(), 64);
        assert_eq!(std::mem::size_of::<IndexedTrianglePacket>(), 64);
        assert_eq!(std::mem::align_of::<IndexedTrianglePacket>(), 64);
        assert_eq!(std::mem::size_of::<SharedVertex>(), 16);
    }

    /// SplitMix64 in [0, 1).
    fn uniform(state: &mut u64) -> f32 {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    fn point(state: &mut u64) -> Vec3 {
        Vec3::new(uniform(state), uniform(state), uniform(state)) * 2.0 - Vec3::ONE
    }

    /// Every lane agrees bit for bit with the scalar test, for random rays and
    /// triangles, partly filled packets, finite and infinite `t_max`, and rays
    /// aimed exactly at vertices (edge functions of zero).
    #[test]
    fn packets_match_the_scalar_test() {
        let mut state = 5u64;
        let mut hits = 0;
        for round in 0..20_000 {
            let count = 1 + round % PACKET_LANES;
            let triangles: Vec<PacketTriangle> = (0..count)
                .map(|lane| PacketTriangle {
                    vertices: [point(&mut state), point(&mut state), point(&mut state)],
                    slot: lane as u32 * 7,
                    reference: PrimitiveReference {
                        shape_index: lane as u32 * 3,
                        primitive_index: lane as u32 * 5,
                    },
                })
                .collect();
            let packet = TrianglePacket::new(&triangles);
            let origin = 3.0 * point(&mut state);
            let target = if round % 5 == 0 {
                triangles[0].vertices[round % 3]
            } else {
                0.5 * point(&mut state)
            };
            let direction = (target - origin).normalize();
            let t_max = if round % 3 == 0 {
                4.0 * uniform(&mut state)
            } else {
                f32::INFINITY
            };
            let scalar = WatertightRay::new(origin, direction);
            let ray = PacketRay::new(scalar);
            let mut expected: Option<PacketHit> = None;
            for (lane, triangle) in triangles.iter().enumerate() {
                let vertices = triangle.vertices;
                let limit = expected.map_or(t_max, |hit| hit.t);
                if let Some(hit) = scalar.intersect(vertices[0], vertices[1], vertices[2], limit) {
                    expected = Some(PacketHit {
                        lane,
                        t: hit.t,
                        barycentric: hit.barycentric,
                    });
                }
            }
            let actual = ray.closest_hit(&packet, t_max);
            assert_eq!(actual, expected, "round {round}");
            assert_eq!(ray.any_hit(&packet, t_max), expected.is_some());
            // The same triangles as indices into a shared array (vertices in
            // reverse order, the unused vertex first): the same answers, bit
            // for bit.
            let mut shared = vec![SharedVertex::UNUSED];
            let indexed: Vec<IndexedPacketTriangle> = triangles
                .iter()
                .map(|triangle| IndexedPacketTriangle {
                    vertex_indices: std::array::from_fn(|_| 0),
                    slot: triangle.slot,
                })
                .collect();
            let mut indexed = indexed;
            for (lane, triangle) in triangles.iter().enumerate().rev() {
                for k in (0..3).rev() {
                    indexed[lane].vertex_indices[k] = shared.len() as u32;
                    shared.push(SharedVertex::new(triangle.vertices[k]));
                }
            }
            let indexed_packet = IndexedTrianglePacket::new(&indexed, 0);
            assert_eq!(
                ray.closest_hit_indexed(&indexed_packet, &shared, t_max),
                expected,
                "round {round}"
            );
            assert_eq!(
                ray.any_hit_indexed(&indexed_packet, &shared, t_max),
                expected.is_some()
            );
            if let Some(hit) = expected {
                assert_eq!(indexed_packet.slot(hit.lane), hit.lane as u32 * 7);
            }
            if let Some(hit) = actual {
                assert_eq!(packet.slot(hit.lane), hit.lane as u32 * 7);
                assert_eq!(packet.reference(hit.lane).shape_index, hit.lane as u32 * 3);
                assert_eq!(
                    packet.reference(hit.lane).primitive_index,
                    hit.lane as u32 * 5
                );
                hits += 1;
            }
        }
        assert!(hits > 2_000, "only {hits} hits");
    }
}

//! An 8-wide BVH with SIMD traversal: obvhs builds a binary BVH (PLOC, Meister
//! & Bittner 2018, plus parallel reinsertion), which is collapsed here into
//! nodes of eight children whose boxes are tested against a ray in two 4-lane
//! SIMD slab tests, with leaves of triangle packets ([`TrianglePacket`]) tested four
//! at a time with the watertight test.
//!
//! Why not obvhs' own traversal: its compressed 8-wide nodes are decoded child
//! by child, its node test drops boxes closer than `t = 1e-4` (rays that start
//! on a surface can miss the triangle next to their origin) and its callback
//! per primitive keeps triangles out of registers. Here:
//!
//! * a node is 256 bytes (four cache lines): for each group of four children
//!   the six slab planes as `[f32; 4]` rows, and eight child references.
//!   Eight children instead of four (the same SSE code per group) make the
//!   tree shallower: on the 1M-triangle scene of `examples/ray_throughput.rs`
//!   the traversal waits for memory at each level, and 8-wide nodes traced
//!   about 15 % more rays per CPU-second (docs/performance.md, "BVH");
//! * the slab test follows Ize, "Robust BVH Ray Traversal" (JCGT 2(2), 2013):
//!   `t_far` is scaled by `1 + 2γ₃` (pbrt-v4's `Bounds3::IntersectP` uses the
//!   same bound), so rounding can never make a ray miss a box it passes
//!   through, and boxes are accepted from `t = 0`;
//! * closest-hit traversal visits children front to back and skips stacked
//!   nodes whose entry distance lies beyond the closest hit found so far;
//!   any-hit traversal (shadow rays) stops at the first hit;
//! * leaves hold up to [`MAX_LEAF_PRIMITIVES`] primitives, triangles in one
//!   packet; analytic primitives (spheres, disks) are listed by slot and
//!   tested through a callback;
//! * packets store their vertices ([`TrianglePacket`], three cache lines) or,
//!   as an option for scenes short of memory, vertex indices into a shared
//!   vertex array ([`IndexedTrianglePacket`], one cache line; see
//!   [`BuildOptions::shared_vertices`]), a third of the memory but slower:
//!   the vertex reads wait for the packet's;
//! * the collapse can merge sibling leaves into one packet where the surface
//!   area heuristic favours it ([`BuildOptions::merge_leaves`]): fewer, fuller
//!   packets, and the freed child slot lets a deeper node move up;
//! * nodes and packets live in transparent huge pages
//!   ([`super::bvh_memory`]), as Embree's do by default on Linux: with 4 KiB
//!   pages most reads of a large BVH also miss the TLB.

use glam::Vec3;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::ploc::PlocBuilder;

use std::mem::MaybeUninit;

use super::bvh_memory::vec_with_huge_pages;
#[cfg(target_arch = "x86_64")]
use super::simd::{Avx2, F32x8};
use super::simd::{F32x4, prefetch};
use super::triangle::WatertightRay;
use super::triangle_packet::{
    IndexedPacketTriangle, IndexedTrianglePacket, PACKET_LANES, PacketHit, PacketRay,
    PacketTriangle, SharedVertex, TrianglePacket,
};
use super::{PrimitiveReference, Ray};

/// Scenes of at most this many primitives get [`SMALL_SCENE_EXTRA_REINSERTIONS`]
/// more reinsertion passes over all nodes after the build (see
/// [`WideBvh::build`]).
const SMALL_SCENE_PRIMITIVES: usize = 1024;

/// Extra reinsertion passes (batch ratio 1: every node a candidate) for
/// scenes of at most [`SMALL_SCENE_PRIMITIVES`] primitives.
const SMALL_SCENE_EXTRA_REINSERTIONS: usize = 4;

/// Groups of four children per node, each tested with one 4-lane slab test.
const GROUPS: usize = 2;
/// Children per node.
const WIDTH: usize = 4 * GROUPS;

/// A subtree of the binary BVH with at most this many primitives becomes a
/// leaf (one packet of triangles).
const MAX_LEAF_PRIMITIVES: u32 = PACKET_LANES as u32;

/// Child reference bit: the child is a leaf.
const LEAF_BIT: u32 = 1 << 31;
/// Leaf reference bit: the low 30 bits index [`WideBvh::general_leaves`].
const GENERAL_LEAF_BIT: u32 = 1 << 30;
/// Compact leaves: packet count − 1 in bits 27..30, first packet in bits 0..27.
const COMPACT_COUNT_SHIFT: u32 = 27;
const COMPACT_MAX_PACKETS: usize = 8;
const COMPACT_START_MASK: u32 = (1 << COMPACT_COUNT_SHIFT) - 1;
/// The reference of an unused child slot (its box is empty, so never entered).
const EMPTY_CHILD: u32 = u32::MAX;

/// `1 + 2γ₃` with `γₙ = nε/(1 − nε)`, `ε = 2⁻²⁴` (pbrt-v4, section 6.8.1).
const ROBUST_FAR_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Direction components smaller than this in magnitude are replaced by it
/// before taking reciprocals, so slab distances stay finite (no `0 · ∞`).
const MIN_DIRECTION_COMPONENT: f32 = 1e-20;

/// Traversal stack entries kept inline; deeper trees use a heap stack.
const INLINE_STACK: usize = 128;

/// Trees whose nodes and packets take fewer bytes than this stay in the
/// caches, so the traversal does not prefetch the children it will visit:
/// for the Cornell box (a few kilobytes) the prefetches were 1.7 % of the
/// path tracer's instructions and could not save a cache miss.
const PREFETCH_MIN_BYTES: usize = 256 * 1024;

/// [`WIDTH`] children: their boxes as slab planes (`bounds[plane][group][lane]`
/// for child `4 · group + lane`; planes 0–2 the minima of x, y, z and 3–5 the
/// maxima), each plane's eight values contiguous (one 8-lane load, or two
/// 4-lane loads), and their references.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct WideNode {
    bounds: [[[f32; 4]; GROUPS]; 6],
    children: [u32; WIDTH],
}

impl WideNode {
    const EMPTY: Self = Self {
        bounds: [
            [[f32::INFINITY; 4]; GROUPS],
            [[f32::INFINITY; 4]; GROUPS],
            [[f32::INFINITY; 4]; GROUPS],
            [[f32::NEG_INFINITY; 4]; GROUPS],
            [[f32::NEG_INFINITY; 4]; GROUPS],
            [[f32::NEG_INFINITY; 4]; GROUPS],
        ],
        children: [EMPTY_CHILD; WIDTH],
    };

    fn set_child(&mut self, index: usize, aabb: &Aabb, reference: u32) {
        for axis in 0..3 {
            self.bounds[axis][index / 4][index % 4] = aabb.min[axis];
            self.bounds[axis + 3][index / 4][index % 4] = aabb.max[axis];
        }
        self.children[index] = reference;
    }

    /// Plane `plane` of child `index`'s box.
    fn plane(&self, plane: usize, index: usize) -> f32 {
        self.bounds[plane][index / 4][index % 4]
    }
}

/// A leaf that does not fit the compact reference: analytic primitives, or
/// more packets than a compact reference can count.
#[derive(Clone, Copy, Debug)]
struct GeneralLeaf {
    packet_start: u32,
    packet_count: u32,
    analytic_start: u32,
    analytic_count: u32,
}

/// The closest primitive found by [`WideBvh::closest_hit`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ClosestPrimitive {
    /// The primitive's slot (position in [`WideBvh::slot_primitives`]).
    pub(crate) slot: u32,
    /// The primitive's shape and primitive index: stored in the triangle
    /// packets, returned by the callback for analytic primitives.
    pub(crate) reference: PrimitiveReference,
    /// Ray parameter.
    pub(crate) t: f32,
    /// Barycentric weights for triangles (zero for analytic primitives).
    pub(crate) barycentric: [f32; 3],
}

/// Where the leaves' triangles live, and how the traversal tests a packet.
trait TriangleStore {
    /// Starts loading packet `index` (see [`WideBvh::prefetch_children`]).
    fn prefetch(&self, index: usize);
    fn closest_hit(&self, ray: &PacketRay, index: usize, t_max: f32) -> Option<PacketHit>;
    fn any_hit(&self, ray: &PacketRay, index: usize, t_max: f32) -> bool;
    /// The slot and reference of `lane` of packet `index`.
    fn primitive(&self, index: usize, lane: usize) -> (u32, PrimitiveReference);
    fn packet_count(&self) -> usize;
    fn packet_bytes(&self) -> usize;
    /// Bytes of data besides the packets that the traversal reads.
    fn shared_bytes(&self) -> usize;
    /// Triangles (used lanes) in packet `index`.
    fn lanes_used(&self, index: usize) -> usize;
}

/// Packets carrying their vertices and ids.
#[derive(Debug)]
struct VertexPackets(Vec<TrianglePacket>);

impl TriangleStore for VertexPackets {
    #[inline(always)]
    fn prefetch(&self, index: usize) {
        let address = self.0.as_ptr().wrapping_add(index).cast::<u8>();
        prefetch(address);
        prefetch(address.wrapping_add(64));
        prefetch(address.wrapping_add(128));
    }
    #[inline(always)]
    fn closest_hit(&self, ray: &PacketRay, index: usize, t_max: f32) -> Option<PacketHit> {
        ray.closest_hit(&self.0[index], t_max)
    }
    #[inline(always)]
    fn any_hit(&self, ray: &PacketRay, index: usize, t_max: f32) -> bool {
        ray.any_hit(&self.0[index], t_max)
    }
    #[inline(always)]
    fn primitive(&self, index: usize, lane: usize) -> (u32, PrimitiveReference) {
        let packet = &self.0[index];
        (packet.slot(lane), packet.reference(lane))
    }
    fn packet_count(&self) -> usize {
        self.0.len()
    }
    fn packet_bytes(&self) -> usize {
        std::mem::size_of_val(self.0.as_slice())
    }
    fn shared_bytes(&self) -> usize {
        0
    }
    fn lanes_used(&self, index: usize) -> usize {
        (0..PACKET_LANES)
            .filter(|&lane| self.0[index].slot(lane) != u32::MAX)
            .count()
    }
}

/// Packets of vertex indices into a shared vertex array.
#[derive(Debug)]
struct IndexedPackets {
    packets: Vec<IndexedTrianglePacket>,
    /// The shared vertices, with one [`SharedVertex::UNUSED`] at the end.
    vertices: Vec<SharedVertex>,
    /// Each slot's shape and primitive index (unused entries for analytic
    /// slots), read once per closest-hit query.
    references: Vec<PrimitiveReference>,
}

impl TriangleStore for IndexedPackets {
    #[inline(always)]
    fn prefetch(&self, index: usize) {
        prefetch(self.packets.as_ptr().wrapping_add(index));
    }
    #[inline(always)]
    fn closest_hit(&self, ray: &PacketRay, index: usize, t_max: f32) -> Option<PacketHit> {
        ray.closest_hit_indexed(&self.packets[index], &self.vertices, t_max)
    }
    #[inline(always)]
    fn any_hit(&self, ray: &PacketRay, index: usize, t_max: f32) -> bool {
        ray.any_hit_indexed(&self.packets[index], &self.vertices, t_max)
    }
    #[inline(always)]
    fn primitive(&self, index: usize, lane: usize) -> (u32, PrimitiveReference) {
        let slot = self.packets[index].slot(lane);
        (slot, self.references[slot as usize])
    }
    fn packet_count(&self) -> usize {
        self.packets.len()
    }
    fn packet_bytes(&self) -> usize {
        std::mem::size_of_val(self.packets.as_slice())
    }
    fn shared_bytes(&self) -> usize {
        std::mem::size_of_val(self.vertices.as_slice())
    }
    fn lanes_used(&self, index: usize) -> usize {
        (0..PACKET_LANES)
            .filter(|&lane| self.packets[index].slot(lane) != u32::MAX)
            .count()
    }
}

/// The triangles of a [`WideBvh`] in one of the two layouts.
#[derive(Debug)]
enum Triangles {
    Vertices(VertexPackets),
    Indexed(IndexedPackets),
}

/// A triangle given to [`WideBvh::build`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct BuildTriangle {
    pub(crate) vertices: [Vec3; 3],
    /// Indices of the vertices in [`BuildOptions::shared_vertices`] (only
    /// read if those are given).
    pub(crate) vertex_indices: [u32; 3],
    pub(crate) reference: PrimitiveReference,
}

/// Choices of [`WideBvh::build`].
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BuildOptions<'a> {
    /// With shared vertices, leaves hold [`IndexedTrianglePacket`]s indexing
    /// them (`vertices[vertex_indices[k]]` must equal `vertices[k]` of every
    /// [`BuildTriangle`]); without, [`TrianglePacket`]s.
    pub(crate) shared_vertices: Option<&'a [Vec3]>,
    /// Merge sibling leaves whose primitives fit one packet when the merged
    /// box's surface area is below the sum of theirs (see
    /// [`Collapser::merge_best_leaf_pair`]).
    pub(crate) merge_leaves: bool,
}

/// Size and quality figures of a [`WideBvh`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WideBvhStatistics {
    pub(crate) nodes: usize,
    pub(crate) node_bytes: usize,
    pub(crate) leaves: usize,
    pub(crate) packets: usize,
    pub(crate) packet_bytes: usize,
    /// The shared vertex array of indexed packets (0 otherwise).
    pub(crate) shared_vertex_bytes: usize,
    /// Triangles per packet over [`PACKET_LANES`].
    pub(crate) packet_fill: f64,
    /// Surface area heuristic cost with unit cost per node test and per
    /// packet test: `1 + Σ_children A(child)/A(root) · (1 for a node, its
    /// packet count for a leaf)`.
    pub(crate) sah_cost: f64,
    pub(crate) indexed: bool,
}

/// The 8-wide BVH (see the module documentation).
#[derive(Debug)]
pub(crate) struct WideBvh {
    nodes: Vec<WideNode>,
    triangles: Triangles,
    general_leaves: Vec<GeneralLeaf>,
    analytic_slots: Vec<u32>,
    /// For each slot, the index of the primitive (in the order given to
    /// [`WideBvh::build`]); slots are numbered in leaf order.
    slot_primitives: Vec<u32>,
    /// Whether the tree is too deep for the inline traversal stack.
    deep: bool,
    /// Whether the closest-hit traversal prefetches the children it will
    /// visit (trees of at least [`PREFETCH_MIN_BYTES`]).
    prefetch: bool,
    /// Set if the CPU supports AVX2: the traversal then runs as AVX2 code.
    #[cfg(target_arch = "x86_64")]
    avx2: Option<Avx2>,
}

/// A ray's slab test against the eight child boxes of a [`WideNode`]; the
/// traversal is generic over it so that it can be compiled once for the SSE
/// baseline and once for AVX2 (see [`WideBvh::closest_hit`]).
trait NodeTest: Sized {
    /// What it takes to build one (a proof that the CPU can run it).
    type Token: Copy;
    fn new(ray: &Ray, token: Self::Token) -> Self;
    /// The children whose boxes the ray enters within `[0, t_max]` (bit `i`
    /// for child `i`) and their entry distances.
    fn intersect(&self, node: &WideNode, t_max: f32) -> (u32, [f32; WIDTH]);
}

/// The reciprocal direction of the slab test (tiny components replaced by
/// [`MIN_DIRECTION_COMPONENT`]) and, per axis, the plane row entered first
/// and the one left last.
#[inline(always)]
fn slab_setup(ray: &Ray) -> ([f32; 3], [usize; 3], [usize; 3]) {
    let inverse = ray.direction.to_array().map(|d| {
        let d = if d.abs() < MIN_DIRECTION_COMPONENT {
            MIN_DIRECTION_COMPONENT
        } else {
            d
        };
        1.0 / d
    });
    // Rows 0–2 are minima, 3–5 maxima: a negative direction enters at the maximum.
    let negative = inverse.map(|i| usize::from(i < 0.0));
    let near_plane = [0, 1, 2].map(|axis| axis + 3 * negative[axis]);
    let far_plane = [0, 1, 2].map(|axis| axis + 3 - 3 * negative[axis]);
    (inverse, near_plane, far_plane)
}

/// The ray's data for the slab test in two 4-lane groups (SSE, the x86_64
/// baseline).
struct NodeRay {
    origin: [F32x4; 3],
    inverse_direction: [F32x4; 3],
    /// Plane rows entered first and left last along each axis.
    near_plane: [usize; 3],
    far_plane: [usize; 3],
}

impl NodeTest for NodeRay {
    type Token = ();

    #[inline(always)]
    fn new(ray: &Ray, _: ()) -> Self {
        let (inverse, near_plane, far_plane) = slab_setup(ray);
        Self {
            origin: ray.origin.to_array().map(F32x4::splat),
            inverse_direction: inverse.map(F32x4::splat),
            near_plane,
            far_plane,
        }
    }

    #[inline(always)]
    fn intersect(&self, node: &WideNode, t_max: f32) -> (u32, [f32; WIDTH]) {
        let mut bits = 0;
        let mut distances = [0.0; WIDTH];
        for group in 0..GROUPS {
            let slab = |plane: usize, axis: usize| {
                F32x4::load(&node.bounds[plane][group])
                    .sub(self.origin[axis])
                    .mul(self.inverse_direction[axis])
            };
            let near = slab(self.near_plane[0], 0)
                .max(slab(self.near_plane[1], 1))
                .max(slab(self.near_plane[2], 2).max(F32x4::splat(0.0)));
            let far = slab(self.far_plane[0], 0)
                .min(slab(self.far_plane[1], 1))
                .min(slab(self.far_plane[2], 2).min(F32x4::splat(t_max)))
                .mul(F32x4::splat(ROBUST_FAR_SCALE));
            bits |= near.le(far).bits() << (4 * group);
            distances[4 * group..4 * group + 4].copy_from_slice(&near.to_array());
        }
        (bits, distances)
    }
}

/// The ray's data for the slab test of all eight children at once (AVX).
/// The same operations as [`NodeRay`] lane by lane, so the same answers.
#[cfg(target_arch = "x86_64")]
struct WideNodeRay {
    origin: [F32x8; 3],
    inverse_direction: [F32x8; 3],
    near_plane: [usize; 3],
    far_plane: [usize; 3],
    avx2: Avx2,
}

#[cfg(target_arch = "x86_64")]
impl NodeTest for WideNodeRay {
    type Token = Avx2;

    #[inline(always)]
    fn new(ray: &Ray, avx2: Avx2) -> Self {
        let (inverse, near_plane, far_plane) = slab_setup(ray);
        Self {
            origin: ray.origin.to_array().map(|value| F32x8::splat(avx2, value)),
            inverse_direction: inverse.map(|value| F32x8::splat(avx2, value)),
            near_plane,
            far_plane,
            avx2,
        }
    }

    #[inline(always)]
    fn intersect(&self, node: &WideNode, t_max: f32) -> (u32, [f32; WIDTH]) {
        let avx2 = self.avx2;
        let slab = |plane: usize, axis: usize| {
            F32x8::load(avx2, &node.bounds[plane])
                .sub(self.origin[axis])
                .mul(self.inverse_direction[axis])
        };
        let near = slab(self.near_plane[0], 0)
            .max(slab(self.near_plane[1], 1))
            .max(slab(self.near_plane[2], 2).max(F32x8::splat(avx2, 0.0)));
        let far = slab(self.far_plane[0], 0)
            .min(slab(self.far_plane[1], 1))
            .min(slab(self.far_plane[2], 2).min(F32x8::splat(avx2, t_max)))
            .mul(F32x8::splat(avx2, ROBUST_FAR_SCALE));
        (near.le_bits(far), near.to_array())
    }
}

/// The closest hit found so far during a traversal; a triangle's slot and
/// reference are looked up once at the end (for indexed packets they are not
/// in the packet).
enum Closest {
    Nothing,
    Triangle { packet: usize, hit: PacketHit },
    Analytic(ClosestPrimitive),
}

/// A stacked child: its reference and the distance at which the ray enters it.
#[derive(Clone, Copy)]
struct StackEntry {
    reference: u32,
    distance: f32,
}

trait TraversalStack {
    fn push(&mut self, entry: StackEntry);
    fn pop(&mut self) -> Option<StackEntry>;
}

/// A fixed-size stack on the caller's stack frame. Its entries start
/// uninitialised: zeroing 768 bytes per ray cost about 60 instructions (a
/// `memset` call per query, measured with callgrind).
struct InlineStack {
    entries: [MaybeUninit<StackEntry>; INLINE_STACK],
    len: usize,
}

impl InlineStack {
    #[inline(always)]
    fn new() -> Self {
        Self {
            entries: [const { MaybeUninit::uninit() }; INLINE_STACK],
            len: 0,
        }
    }
}

impl TraversalStack for InlineStack {
    #[inline(always)]
    fn push(&mut self, entry: StackEntry) {
        // The build checks that the tree fits (see `WideBvh::deep`); the
        // index is bounds-checked all the same.
        self.entries[self.len] = MaybeUninit::new(entry);
        self.len += 1;
    }
    #[inline(always)]
    fn pop(&mut self) -> Option<StackEntry> {
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: every entry below `len` was written by `push`.
        Some(unsafe { self.entries[self.len].assume_init() })
    }
}

impl TraversalStack for Vec<StackEntry> {
    fn push(&mut self, entry: StackEntry) {
        Vec::push(self, entry);
    }
    fn pop(&mut self) -> Option<StackEntry> {
        Vec::pop(self)
    }
}

/// What a leaf holds.
struct LeafContents {
    packets: std::ops::Range<usize>,
    analytic: std::ops::Range<usize>,
}

impl WideBvh {
    /// Builds the BVH over primitives with boxes `aabbs`; `triangle(i)` gives
    /// primitive `i`'s vertices and its shape and triangle index if it is a
    /// triangle (`None`: analytic, tested through the traversal callbacks).
    /// `aabbs` must not be empty.
    pub(crate) fn build(
        aabbs: &[Aabb],
        triangle: impl Fn(usize) -> Option<BuildTriangle>,
        options: BuildOptions,
    ) -> Self {
        assert!(!aabbs.is_empty());
        // Search distance 24 instead of 14 or a reinsertion ratio of 0.2
        // instead of 0.05 changed the instructions per ray by under 1%
        // (callgrind, sphere_in_box of `examples/ray_throughput.rs`) at
        // 1.5 to 2 times the build time, so the medium preset stays.
        let parameters = obvhs::BvhBuildParams::medium_build();
        let mut binary = PlocBuilder::with_capacity(aabbs.len()).build(
            parameters.ploc_search_distance,
            aabbs,
            (0..aabbs.len() as u32).collect(),
            parameters.sort_precision,
            parameters.search_depth_threshold,
        );
        let mut optimizer = ReinsertionOptimizer::default();
        optimizer.run(&mut binary, parameters.reinsertion_batch_ratio, None);
        if aabbs.len() <= SMALL_SCENE_PRIMITIVES {
            // Small scenes build in microseconds, so reinsertion can consider
            // every node a few more times: on the Cornell box the SAH cost
            // fell from 3.99 to 3.69 and a closest-hit ray took about 11 %
            // fewer instructions (callgrind). Large scenes keep the preset.
            for _ in 0..SMALL_SCENE_EXTRA_REINSERTIONS {
                optimizer.run(&mut binary, 1.0, None);
            }
        }
        // Every packet holds at least one primitive and every node at least
        // two children, so neither array outgrows `aabbs.len()` (the unused
        // capacity is never touched, so never backed by memory).
        let triangles = match options.shared_vertices {
            None => Triangles::Vertices(VertexPackets(vec_with_huge_pages(aabbs.len()))),
            Some(vertices) => {
                assert!(
                    vertices.len() < u32::MAX as usize,
                    "too many shared vertices"
                );
                let mut shared = vec_with_huge_pages(vertices.len() + 1);
                shared.extend(vertices.iter().map(|&v| SharedVertex::new(v)));
                shared.push(SharedVertex::UNUSED);
                Triangles::Indexed(IndexedPackets {
                    packets: vec_with_huge_pages(aabbs.len()),
                    vertices: shared,
                    references: Vec::with_capacity(aabbs.len()),
                })
            }
        };
        Collapser {
            binary: &binary,
            counts: subtree_primitive_counts(&binary),
            triangle: &triangle,
            merge_leaves: options.merge_leaves,
            bvh: WideBvh {
                nodes: vec_with_huge_pages(aabbs.len()),
                triangles,
                general_leaves: Vec::new(),
                analytic_slots: Vec::new(),
                slot_primitives: Vec::with_capacity(aabbs.len()),
                deep: false,
                prefetch: false,
                #[cfg(target_arch = "x86_64")]
                avx2: Avx2::detect(),
            },
        }
        .collapse()
    }

    /// For each slot, the index of its primitive in the build order.
    pub(crate) fn slot_primitives(&self) -> &[u32] {
        &self.slot_primitives
    }

    /// The bytes a traversal may read: nodes, packets and shared vertices.
    fn traversed_bytes(&self) -> usize {
        let (packet_bytes, shared_bytes) = match &self.triangles {
            Triangles::Vertices(triangles) => (triangles.packet_bytes(), triangles.shared_bytes()),
            Triangles::Indexed(triangles) => (triangles.packet_bytes(), triangles.shared_bytes()),
        };
        std::mem::size_of_val(self.nodes.as_slice()) + packet_bytes + shared_bytes
    }

    /// Size and quality figures (see [`WideBvhStatistics`]).
    pub(crate) fn statistics(&self) -> WideBvhStatistics {
        match &self.triangles {
            Triangles::Vertices(triangles) => self.statistics_with(triangles, false),
            Triangles::Indexed(triangles) => self.statistics_with(triangles, true),
        }
    }

    fn statistics_with(&self, triangles: &impl TriangleStore, indexed: bool) -> WideBvhStatistics {
        let half_area = |node: &WideNode, child: usize| {
            let extent: [f32; 3] =
                std::array::from_fn(|axis| node.plane(axis + 3, child) - node.plane(axis, child));
            extent[0] * extent[1] + extent[1] * extent[2] + extent[2] * extent[0]
        };
        let root = &self.nodes[0];
        let mut root_box = Aabb::empty();
        for child in 0..WIDTH {
            if root.children[child] != EMPTY_CHILD {
                root_box = root_box.union(&Aabb::new(
                    std::array::from_fn::<f32, 3, _>(|axis| root.plane(axis, child)).into(),
                    std::array::from_fn::<f32, 3, _>(|axis| root.plane(axis + 3, child)).into(),
                ));
            }
        }
        let root_area = root_box.half_area().max(f32::MIN_POSITIVE) as f64;
        let mut sah_cost = 1.0;
        let mut leaves = 0;
        for node in &self.nodes {
            for child in 0..WIDTH {
                let reference = node.children[child];
                if reference == EMPTY_CHILD {
                    continue;
                }
                let weight = if reference & LEAF_BIT == 0 {
                    1.0
                } else {
                    leaves += 1;
                    self.leaf_contents(reference).packets.len() as f64
                };
                sah_cost += weight * half_area(node, child) as f64 / root_area;
            }
        }
        let packets = triangles.packet_count();
        let used: usize = (0..packets).map(|index| triangles.lanes_used(index)).sum();
        WideBvhStatistics {
            nodes: self.nodes.len(),
            node_bytes: std::mem::size_of_val(self.nodes.as_slice()),
            leaves,
            packets,
            packet_bytes: triangles.packet_bytes(),
            shared_vertex_bytes: triangles.shared_bytes(),
            packet_fill: used as f64 / (packets.max(1) * PACKET_LANES) as f64,
            sah_cost,
            indexed,
        }
    }

    #[inline(always)]
    fn leaf_contents(&self, reference: u32) -> LeafContents {
        if reference & GENERAL_LEAF_BIT == 0 {
            let start = (reference & COMPACT_START_MASK) as usize;
            let count = ((reference & !LEAF_BIT) >> COMPACT_COUNT_SHIFT) as usize + 1;
            LeafContents {
                packets: start..start + count,
                analytic: 0..0,
            }
        } else {
            let leaf = &self.general_leaves[(reference & !(LEAF_BIT | GENERAL_LEAF_BIT)) as usize];
            let packets = leaf.packet_start as usize;
            let analytic = leaf.analytic_start as usize;
            LeafContents {
                packets: packets..packets + leaf.packet_count as usize,
                analytic: analytic..analytic + leaf.analytic_count as usize,
            }
        }
    }

    /// Starts loading the memory of the children in `bits` (their nodes, or
    /// the first packet of compact leaves) while the nearest is visited: on
    /// large scenes the traversal waits for memory more than it computes.
    #[inline(always)]
    fn prefetch_children(&self, triangles: &impl TriangleStore, node: &WideNode, mut bits: u32) {
        while bits != 0 {
            let reference = node.children[bits.trailing_zeros() as usize];
            bits &= bits - 1;
            if reference & LEAF_BIT == 0 {
                let address = self
                    .nodes
                    .as_ptr()
                    .wrapping_add(reference as usize)
                    .cast::<u8>();
                for line in 0..std::mem::size_of::<WideNode>() / 64 {
                    prefetch(address.wrapping_add(64 * line));
                }
            } else if reference & GENERAL_LEAF_BIT == 0 {
                triangles.prefetch((reference & COMPACT_START_MASK) as usize);
            }
        }
    }

    /// The closest primitive hit by `ray` with `0 < t < t_max`.
    /// `analytic(slot, t_max)` tests an analytic primitive and returns its `t`
    /// and its reference.
    /// `ray`'s origin must be finite and its direction finite and non-zero.
    ///
    /// On CPUs with AVX2 the traversal runs as code compiled for AVX2 (one
    /// 8-lane slab test per node, three-operand instructions throughout);
    /// elsewhere as SSE code. Both perform the same IEEE operations (no
    /// fused multiply–add), so the hits are the same bit for bit.
    #[inline]
    pub(crate) fn closest_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> Option<(f32, PrimitiveReference)>,
    ) -> Option<ClosestPrimitive> {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            // SAFETY: the proof says the CPU supports AVX2.
            return unsafe { self.closest_hit_avx2(avx2, ray, t_max, analytic) };
        }
        self.closest_hit_sse(ray, t_max, analytic)
    }

    /// [`WideBvh::closest_hit`] as SSE code. Out of line on x86_64: inlined,
    /// its stack frame and saved registers were set up in the caller for
    /// every ray, AVX2 or not (about 20 instructions per ray, callgrind).
    #[cfg_attr(target_arch = "x86_64", inline(never))]
    fn closest_hit_sse(
        &self,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> Option<(f32, PrimitiveReference)>,
    ) -> Option<ClosestPrimitive> {
        self.closest_hit_for::<NodeRay>((), ray, t_max, analytic)
    }

    /// [`WideBvh::closest_hit`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn closest_hit_avx2(
        &self,
        avx2: Avx2,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> Option<(f32, PrimitiveReference)>,
    ) -> Option<ClosestPrimitive> {
        self.closest_hit_for::<WideNodeRay>(avx2, ray, t_max, analytic)
    }

    #[inline(always)]
    fn closest_hit_for<N: NodeTest>(
        &self,
        token: N::Token,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> Option<(f32, PrimitiveReference)>,
    ) -> Option<ClosestPrimitive> {
        let node_ray = N::new(ray, token);
        match (&self.triangles, self.deep) {
            (Triangles::Vertices(triangles), false) => self.closest_hit_with(
                triangles,
                ray,
                &node_ray,
                t_max,
                analytic,
                InlineStack::new(),
            ),
            (Triangles::Vertices(triangles), true) => {
                self.closest_hit_with(triangles, ray, &node_ray, t_max, analytic, Vec::new())
            }
            (Triangles::Indexed(triangles), false) => self.closest_hit_with(
                triangles,
                ray,
                &node_ray,
                t_max,
                analytic,
                InlineStack::new(),
            ),
            (Triangles::Indexed(triangles), true) => {
                self.closest_hit_with(triangles, ray, &node_ray, t_max, analytic, Vec::new())
            }
        }
    }

    /// Whether `ray` hits any primitive with `0 < t < t_max` (stops at the
    /// first hit). `analytic(slot, t_max)` tests an analytic primitive.
    /// AVX2 or SSE code as for [`WideBvh::closest_hit`].
    #[inline]
    pub(crate) fn any_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> bool,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            // SAFETY: the proof says the CPU supports AVX2.
            return unsafe { self.any_hit_avx2(avx2, ray, t_max, analytic) };
        }
        self.any_hit_sse(ray, t_max, analytic)
    }

    /// [`WideBvh::any_hit`] as SSE code, out of line on x86_64 for the reason
    /// given at [`WideBvh::closest_hit_sse`].
    #[cfg_attr(target_arch = "x86_64", inline(never))]
    fn any_hit_sse(&self, ray: &Ray, t_max: f32, analytic: impl FnMut(u32, f32) -> bool) -> bool {
        self.any_hit_for::<NodeRay>((), ray, t_max, analytic)
    }

    /// [`WideBvh::any_hit`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn any_hit_avx2(
        &self,
        avx2: Avx2,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> bool,
    ) -> bool {
        self.any_hit_for::<WideNodeRay>(avx2, ray, t_max, analytic)
    }

    #[inline(always)]
    fn any_hit_for<N: NodeTest>(
        &self,
        token: N::Token,
        ray: &Ray,
        t_max: f32,
        analytic: impl FnMut(u32, f32) -> bool,
    ) -> bool {
        let node_ray = N::new(ray, token);
        match (&self.triangles, self.deep) {
            (Triangles::Vertices(triangles), false) => self.any_hit_with(
                triangles,
                ray,
                &node_ray,
                t_max,
                analytic,
                InlineStack::new(),
            ),
            (Triangles::Vertices(triangles), true) => {
                self.any_hit_with(triangles, ray, &node_ray, t_max, analytic, Vec::new())
            }
            (Triangles::Indexed(triangles), false) => self.any_hit_with(
                triangles,
                ray,
                &node_ray,
                t_max,
                analytic,
                InlineStack::new(),
            ),
            (Triangles::Indexed(triangles), true) => {
                self.any_hit_with(triangles, ray, &node_ray, t_max, analytic, Vec::new())
            }
        }
    }

    #[inline(always)]
    fn closest_hit_with(
        &self,
        triangles: &impl TriangleStore,
        ray: &Ray,
        node_ray: &impl NodeTest,
        mut t_max: f32,
        mut analytic: impl FnMut(u32, f32) -> Option<(f32, PrimitiveReference)>,
        mut stack: impl TraversalStack,
    ) -> Option<ClosestPrimitive> {
        let packet_ray = PacketRay::new(WatertightRay::new(ray.origin, ray.direction));
        let mut closest = Closest::Nothing;
        let mut current = 0u32;
        loop {
            if current & LEAF_BIT == 0 {
                let node = &self.nodes[current as usize];
                let (mut bits, distances) = node_ray.intersect(node, t_max);
                if bits != 0 {
                    if self.prefetch {
                        self.prefetch_children(triangles, node, bits);
                    }
                    let first = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    if bits == 0 {
                        current = node.children[first];
                        continue;
                    }
                    let second = bits.trailing_zeros() as usize;
                    if bits & (bits - 1) == 0 {
                        // Two children (the most common case): push the far
                        // one, descend into the near one (the second on a tie,
                        // as the general ordering below does).
                        let (near, far) = if distances[first] < distances[second] {
                            (first, second)
                        } else {
                            (second, first)
                        };
                        stack.push(StackEntry {
                            reference: node.children[far],
                            distance: distances[far],
                        });
                        current = node.children[near];
                        continue;
                    }
                    // Three or more children: order them far to near, push all
                    // but the nearest, descend into the nearest.
                    let mut order = [StackEntry {
                        reference: node.children[first],
                        distance: distances[first],
                    }; WIDTH];
                    let mut count = 1;
                    while bits != 0 {
                        let child = bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        let entry = StackEntry {
                            reference: node.children[child],
                            distance: distances[child],
                        };
                        let mut position = count;
                        while position > 0 && order[position - 1].distance < entry.distance {
                            order[position] = order[position - 1];
                            position -= 1;
                        }
                        order[position] = entry;
                        count += 1;
                    }
                    for entry in &order[..count - 1] {
                        stack.push(*entry);
                    }
                    current = order[count - 1].reference;
                    continue;
                }
            } else {
                let contents = self.leaf_contents(current);
                for packet in contents.packets {
                    if let Some(hit) = triangles.closest_hit(&packet_ray, packet, t_max) {
                        t_max = hit.t;
                        closest = Closest::Triangle { packet, hit };
                    }
                }
                for &slot in &self.analytic_slots[contents.analytic] {
                    if let Some((t, reference)) = analytic(slot, t_max) {
                        t_max = t;
                        closest = Closest::Analytic(ClosestPrimitive {
                            slot,
                            reference,
                            t,
                            barycentric: [0.0; 3],
                        });
                    }
                }
            }
            // Next stacked child the ray can still reach before the closest hit.
            loop {
                let Some(entry) = stack.pop() else {
                    return match closest {
                        Closest::Nothing => None,
                        Closest::Triangle { packet, hit } => {
                            let (slot, reference) = triangles.primitive(packet, hit.lane);
                            Some(ClosestPrimitive {
                                slot,
                                reference,
                                t: hit.t,
                                barycentric: hit.barycentric,
                            })
                        }
                        Closest::Analytic(primitive) => Some(primitive),
                    };
                };
                if entry.distance <= t_max * ROBUST_FAR_SCALE {
                    current = entry.reference;
                    break;
                }
            }
        }
    }

    #[inline(always)]
    fn any_hit_with(
        &self,
        triangles: &impl TriangleStore,
        ray: &Ray,
        node_ray: &impl NodeTest,
        t_max: f32,
        mut analytic: impl FnMut(u32, f32) -> bool,
        mut stack: impl TraversalStack,
    ) -> bool {
        // Built at the first leaf: many shadow rays leave the tree from its
        // nodes, and the watertight set-up costs about 40 instructions.
        let mut packet_ray: Option<PacketRay> = None;
        let mut current = 0u32;
        loop {
            if current & LEAF_BIT == 0 {
                let node = &self.nodes[current as usize];
                let (mut bits, _) = node_ray.intersect(node, t_max);
                if bits != 0 {
                    current = node.children[bits.trailing_zeros() as usize];
                    bits &= bits - 1;
                    while bits != 0 {
                        stack.push(StackEntry {
                            reference: node.children[bits.trailing_zeros() as usize],
                            distance: 0.0,
                        });
                        bits &= bits - 1;
                    }
                    continue;
                }
            } else {
                let contents = self.leaf_contents(current);
                let packet_ray = packet_ray.get_or_insert_with(|| {
                    PacketRay::new(WatertightRay::new(ray.origin, ray.direction))
                });
                for packet in contents.packets {
                    if triangles.any_hit(packet_ray, packet, t_max) {
                        return true;
                    }
                }
                for &slot in &self.analytic_slots[contents.analytic] {
                    if analytic(slot, t_max) {
                        return true;
                    }
                }
            }
            match stack.pop() {
                Some(entry) => current = entry.reference,
                None => return false,
            }
        }
    }
}

/// Number of primitives below every node of the binary BVH.
fn subtree_primitive_counts(binary: &Bvh2) -> Vec<u32> {
    let mut preorder = Vec::with_capacity(binary.nodes.len());
    let mut pending = vec![0usize];
    while let Some(index) = pending.pop() {
        preorder.push(index);
        let node = &binary.nodes[index];
        if !node.is_leaf() {
            pending.push(node.first_index as usize);
            pending.push(node.first_index as usize + 1);
        }
    }
    let mut counts = vec![0u32; binary.nodes.len()];
    for &index in preorder.iter().rev() {
        let node = &binary.nodes[index];
        counts[index] = if node.is_leaf() {
            node.prim_count
        } else {
            counts[node.first_index as usize] + counts[node.first_index as usize + 1]
        };
    }
    counts
}

/// A child of a wide node being formed: one binary subtree, or (merged leaves)
/// up to [`MAX_LEAF_PRIMITIVES`] subtrees that become one leaf.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    subtrees: [usize; MAX_LEAF_PRIMITIVES as usize],
    subtree_count: usize,
    aabb: Aabb,
    primitives: u32,
}

/// Turns the binary BVH into the wide one.
struct Collapser<'a, F> {
    binary: &'a Bvh2,
    counts: Vec<u32>,
    triangle: &'a F,
    merge_leaves: bool,
    bvh: WideBvh,
}

impl<F: Fn(usize) -> Option<BuildTriangle>> Collapser<'_, F> {
    fn candidate(&self, index: usize) -> Candidate {
        let mut subtrees = [0; MAX_LEAF_PRIMITIVES as usize];
        subtrees[0] = index;
        Candidate {
            subtrees,
            subtree_count: 1,
            aabb: *self.binary.nodes[index].aabb(),
            primitives: self.counts[index],
        }
    }

    fn becomes_leaf(&self, candidate: &Candidate) -> bool {
        candidate.subtree_count > 1
            || self.binary.nodes[candidate.subtrees[0]].is_leaf()
            || candidate.primitives <= MAX_LEAF_PRIMITIVES
    }

    /// Merges the two leaf candidates whose primitives fit one packet and
    /// whose merged box saves the most surface area (the expected number of
    /// packet tests, by the surface area heuristic, falls from
    /// `A(a) + A(b)` to `A(a ∪ b)` in units of the parent's area); whether a
    /// pair was merged.
    fn merge_best_leaf_pair(&self, children: &mut Vec<Candidate>) -> bool {
        let mut best: Option<(usize, usize, f32)> = None;
        for a in 0..children.len() {
            for b in a + 1..children.len() {
                let (first, second) = (&children[a], &children[b]);
                if !self.becomes_leaf(first)
                    || !self.becomes_leaf(second)
                    || first.primitives + second.primitives > MAX_LEAF_PRIMITIVES
                {
                    continue;
                }
                let saving = first.aabb.half_area() + second.aabb.half_area()
                    - first.aabb.union(&second.aabb).half_area();
                if saving > 0.0 && best.is_none_or(|(_, _, most)| saving > most) {
                    best = Some((a, b, saving));
                }
            }
        }
        let Some((a, b, _)) = best else {
            return false;
        };
        let second = children.swap_remove(b);
        let first = &mut children[a];
        for &subtree in &second.subtrees[..second.subtree_count] {
            first.subtrees[first.subtree_count] = subtree;
            first.subtree_count += 1;
        }
        first.aabb = first.aabb.union(&second.aabb);
        first.primitives += second.primitives;
        true
    }

    /// Opens the small inner subtree (one that would become a leaf of at
    /// most [`MAX_LEAF_PRIMITIVES`]) whose two children's boxes save the most
    /// surface area over its own, into those two children, when a slot is
    /// free: by the surface area heuristic the expected packet tests fall
    /// from `A(node)` to `A(left) + A(right)` (in units of the parent's
    /// area), which matters in small scenes where a 4-triangle subtree can
    /// join distant walls (the Cornell box's right wall and a block face).
    /// The reverse of [`Collapser::merge_best_leaf_pair`], which never
    /// re-merges such a pair (its saving is negative); both lower the sum of
    /// the children's areas, so alternating them terminates. Whether a
    /// subtree was opened.
    fn split_best_small_leaf(&self, children: &mut Vec<Candidate>) -> bool {
        let mut best: Option<(usize, f32)> = None;
        for (position, child) in children.iter().enumerate() {
            let node = &self.binary.nodes[child.subtrees[0]];
            if child.subtree_count > 1 || node.is_leaf() {
                continue;
            }
            let first = node.first_index as usize;
            let saving = child.aabb.half_area()
                - self.binary.nodes[first].aabb().half_area()
                - self.binary.nodes[first + 1].aabb().half_area();
            if saving > 0.0 && best.is_none_or(|(_, most)| saving > most) {
                best = Some((position, saving));
            }
        }
        let Some((position, _)) = best else {
            return false;
        };
        self.open(children, position);
        true
    }

    /// Replaces the candidate at `position` (one inner binary node) by its
    /// two children.
    fn open(&self, children: &mut Vec<Candidate>, position: usize) {
        let opened = children.swap_remove(position).subtrees[0];
        let first = self.binary.nodes[opened].first_index as usize;
        children.extend([self.candidate(first), self.candidate(first + 1)]);
    }

    fn collapse(mut self) -> WideBvh {
        self.bvh.nodes.push(WideNode::EMPTY);
        // (binary node, wide node it fills, depth of the wide node)
        let mut pending = vec![(0usize, 0usize, 1usize)];
        let mut max_depth = 1;
        let root = self.candidate(0);
        if self.becomes_leaf(&root) {
            let reference = self.leaf(&root);
            self.bvh.nodes[0].set_child(0, &root.aabb, reference);
            pending.clear();
        }
        while let Some((binary_index, wide_index, depth)) = pending.pop() {
            max_depth = max_depth.max(depth);
            // Open the largest inner child until there are WIDTH children;
            // merging leaves frees slots for more.
            let first = self.binary.nodes[binary_index].first_index as usize;
            let mut children = vec![self.candidate(first), self.candidate(first + 1)];
            loop {
                if children.len() < WIDTH {
                    let largest = (0..children.len())
                        .filter(|&position| !self.becomes_leaf(&children[position]))
                        .max_by(|&a, &b| {
                            children[a]
                                .aabb
                                .half_area()
                                .total_cmp(&children[b].aabb.half_area())
                        });
                    if let Some(position) = largest {
                        self.open(&mut children, position);
                        continue;
                    }
                }
                if children.len() < WIDTH && self.split_best_small_leaf(&mut children) {
                    continue;
                }
                if !(self.merge_leaves && self.merge_best_leaf_pair(&mut children)) {
                    break;
                }
            }
            let mut node = WideNode::EMPTY;
            for (slot, child) in children.iter().enumerate() {
                let reference = if self.becomes_leaf(child) {
                    self.leaf(child)
                } else {
                    let index = self.bvh.nodes.len();
                    self.bvh.nodes.push(WideNode::EMPTY);
                    pending.push((child.subtrees[0], index, depth + 1));
                    index as u32
                };
                node.set_child(slot, &child.aabb, reference);
            }
            self.bvh.nodes[wide_index] = node;
        }
        // Each level pushes at most WIDTH - 1 entries.
        self.bvh.deep = (WIDTH - 1) * max_depth >= INLINE_STACK;
        self.bvh.prefetch = self.bvh.traversed_bytes() >= PREFETCH_MIN_BYTES;
        self.bvh
    }

    /// Emits the primitives below the candidate's subtrees as a leaf and returns its reference.
    fn leaf(&mut self, candidate: &Candidate) -> u32 {
        let mut primitives = Vec::new();
        let mut pending: Vec<usize> = candidate.subtrees[..candidate.subtree_count]
            .iter()
            .rev()
            .copied()
            .collect();
        while let Some(index) = pending.pop() {
            let node = &self.binary.nodes[index];
            if node.is_leaf() {
                let first = node.first_index as usize;
                primitives.extend_from_slice(
                    &self.binary.primitive_indices[first..first + node.prim_count as usize],
                );
            } else {
                pending.push(node.first_index as usize + 1);
                pending.push(node.first_index as usize);
            }
        }
        let bvh = &mut self.bvh;
        let packet_start = match &bvh.triangles {
            Triangles::Vertices(packets) => packets.0.len(),
            Triangles::Indexed(packets) => packets.packets.len(),
        };
        let analytic_start = bvh.analytic_slots.len();
        let mut triangles = Vec::with_capacity(PACKET_LANES);
        let flush = |triangles: &mut Vec<(BuildTriangle, u32)>, store: &mut Triangles| {
            if triangles.is_empty() {
                return;
            }
            match store {
                Triangles::Vertices(packets) => {
                    let lanes: Vec<PacketTriangle> = triangles
                        .iter()
                        .map(|(triangle, slot)| PacketTriangle {
                            vertices: triangle.vertices,
                            slot: *slot,
                            reference: triangle.reference,
                        })
                        .collect();
                    packets.0.push(TrianglePacket::new(&lanes));
                }
                Triangles::Indexed(packets) => {
                    let lanes: Vec<IndexedPacketTriangle> = triangles
                        .iter()
                        .map(|(triangle, slot)| IndexedPacketTriangle {
                            vertex_indices: triangle.vertex_indices,
                            slot: *slot,
                        })
                        .collect();
                    let unused_vertex = packets.vertices.len() as u32 - 1;
                    let packet = IndexedTrianglePacket::new(&lanes, unused_vertex);
                    assert!(
                        packet.max_vertex_index() <= unused_vertex,
                        "vertex index out of range"
                    );
                    packets.packets.push(packet);
                }
            }
            triangles.clear();
        };
        for &primitive in &primitives {
            let slot = bvh.slot_primitives.len() as u32;
            bvh.slot_primitives.push(primitive);
            let triangle = (self.triangle)(primitive as usize);
            if let Triangles::Indexed(packets) = &mut bvh.triangles {
                packets
                    .references
                    .push(triangle.map_or(UNUSED_REFERENCE, |triangle| triangle.reference));
            }
            match triangle {
                Some(triangle) => {
                    triangles.push((triangle, slot));
                    if triangles.len() == PACKET_LANES {
                        flush(&mut triangles, &mut bvh.triangles);
                    }
                }
                None => bvh.analytic_slots.push(slot),
            }
        }
        flush(&mut triangles, &mut bvh.triangles);
        let packet_count = match &bvh.triangles {
            Triangles::Vertices(packets) => packets.0.len(),
            Triangles::Indexed(packets) => packets.packets.len(),
        } - packet_start;
        let analytic_count = bvh.analytic_slots.len() - analytic_start;
        if analytic_count == 0
            && (1..=COMPACT_MAX_PACKETS).contains(&packet_count)
            && packet_start <= COMPACT_START_MASK as usize
        {
            LEAF_BIT | ((packet_count as u32 - 1) << COMPACT_COUNT_SHIFT) | packet_start as u32
        } else {
            let reference = bvh.general_leaves.len() as u32;
            assert!(reference < GENERAL_LEAF_BIT, "too many BVH leaves");
            bvh.general_leaves.push(GeneralLeaf {
                packet_start: packet_start as u32,
                packet_count: packet_count as u32,
                analytic_start: analytic_start as u32,
                analytic_count: analytic_count as u32,
            });
            LEAF_BIT | GENERAL_LEAF_BIT | reference
        }
    }
}

/// The reference stored for analytic slots among indexed packets' references
/// (never returned: analytic hits carry their own).
const UNUSED_REFERENCE: PrimitiveReference = PrimitiveReference {
    shape_index: u32::MAX,
    primitive_index: u32::MAX,
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Bounds3;

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

    /// Random small triangles: the closest hit and the any-hit answer agree
    /// with testing every triangle, with the inline stack and with the heap
    /// stack of deep trees, for both packet layouts with and without leaf
    /// merging, and every primitive has exactly one slot.
    #[test]
    fn traversal_matches_testing_every_triangle() {
        let mut state = 9u64;
        // Vertices shared in a pool, as in a mesh (the pool is shuffled
        // relative to the triangles).
        let pool: Vec<Vec3> = (0..3000)
            .flat_map(|_| {
                let centre = point(&mut state);
                [0; 3].map(|_| centre + 0.05 * point(&mut state))
            })
            .collect();
        let vertex_indices: Vec<[u32; 3]> = (0..3000u32)
            .map(|i| [0, 1, 2].map(|k| (3 * i + k) * 7 % 9000))
            .collect();
        let triangles: Vec<[Vec3; 3]> = vertex_indices
            .iter()
            .map(|indices| indices.map(|i| pool[i as usize]))
            .collect();
        let aabbs: Vec<Aabb> = triangles
            .iter()
            .map(|t| Bounds3::from_points(*t).to_aabb())
            .collect();
        let build_triangle = |i: usize| {
            Some(BuildTriangle {
                vertices: triangles[i],
                vertex_indices: vertex_indices[i],
                reference: PrimitiveReference {
                    shape_index: 7,
                    primitive_index: i as u32,
                },
            })
        };
        for (shared_vertices, merge_leaves, deep) in [
            (None, false, false),
            (None, true, false),
            (None, true, true),
            (Some(pool.as_slice()), false, false),
            (Some(pool.as_slice()), true, false),
            (Some(pool.as_slice()), true, true),
        ] {
            let mut bvh = WideBvh::build(
                &aabbs,
                build_triangle,
                BuildOptions {
                    shared_vertices,
                    merge_leaves,
                },
            );
            assert!(!bvh.deep);
            let statistics = bvh.statistics();
            assert_eq!(statistics.indexed, shared_vertices.is_some());
            assert!(statistics.packet_fill > 0.5, "{statistics:?}");
            assert!(statistics.sah_cost > 1.0, "{statistics:?}");
            let mut slots = bvh.slot_primitives().to_vec();
            slots.sort_unstable();
            assert_eq!(slots, (0..3000).collect::<Vec<u32>>());
            bvh.deep = deep;
            let mut hits = 0;
            for i in 0..5000 {
                let ray = Ray::new(1.5 * point(&mut state), {
                    let d = point(&mut state);
                    if d == Vec3::ZERO {
                        Vec3::X
                    } else {
                        d.normalize()
                    }
                });
                let t_max = if i % 4 == 0 {
                    uniform(&mut state)
                } else {
                    f32::INFINITY
                };
                let scalar = WatertightRay::new(ray.origin, ray.direction);
                let mut expected: Option<f32> = None;
                for [p0, p1, p2] in &triangles {
                    if let Some(hit) = scalar.intersect(*p0, *p1, *p2, expected.unwrap_or(t_max)) {
                        expected = Some(hit.t);
                    }
                }
                let found = bvh.closest_hit(&ray, t_max, |_, _| None);
                assert_eq!(found.map(|hit| hit.t), expected, "{ray:?}");
                if let Some(hit) = found {
                    let primitive = bvh.slot_primitives()[hit.slot as usize] as usize;
                    assert_eq!(hit.reference.primitive_index as usize, primitive);
                    assert_eq!(hit.reference.shape_index, 7);
                    let [p0, p1, p2] = triangles[primitive];
                    assert_eq!(
                        scalar.intersect(p0, p1, p2, f32::INFINITY).unwrap().t,
                        hit.t
                    );
                    hits += 1;
                }
                assert_eq!(bvh.any_hit(&ray, t_max, |_, _| false), expected.is_some());
                // The SSE traversal (the only one on CPUs without AVX2)
                // finds the same hit, bit for bit.
                #[cfg(target_arch = "x86_64")]
                {
                    let detected = bvh.avx2.take();
                    assert_eq!(bvh.closest_hit(&ray, t_max, |_, _| None), found);
                    assert_eq!(bvh.any_hit(&ray, t_max, |_, _| false), expected.is_some());
                    bvh.avx2 = detected;
                }
            }
            assert!(hits > 300, "only {hits} hits");
        }
    }

    /// Merging leaves on a regular grid of small quads fills packets better
    /// and does not raise the surface area heuristic cost.
    #[test]
    fn merging_leaves_fills_packets() {
        let mut triangles = Vec::new();
        for i in 0..40 {
            for j in 0..40 {
                let corner = |di: i32, dj: i32| {
                    let (x, y) = ((i + di) as f32 / 40.0, (j + dj) as f32 / 40.0);
                    Vec3::new(x, y, 0.1 * (7.0 * x).sin() * (5.0 * y).cos())
                };
                triangles.push([corner(0, 0), corner(1, 0), corner(1, 1)]);
                triangles.push([corner(0, 0), corner(1, 1), corner(0, 1)]);
            }
        }
        let aabbs: Vec<Aabb> = triangles
            .iter()
            .map(|t| Bounds3::from_points(*t).to_aabb())
            .collect();
        let build = |merge_leaves| {
            WideBvh::build(
                &aabbs,
                |i| {
                    Some(BuildTriangle {
                        vertices: triangles[i],
                        vertex_indices: [0; 3],
                        reference: PrimitiveReference {
                            shape_index: 0,
                            primitive_index: i as u32,
                        },
                    })
                },
                BuildOptions {
                    shared_vertices: None,
                    merge_leaves,
                },
            )
            .statistics()
        };
        let (plain, merged) = (build(false), build(true));
        assert!(
            merged.packet_fill > plain.packet_fill,
            "{plain:?} {merged:?}"
        );
        assert!(merged.packets < plain.packets, "{plain:?} {merged:?}");
        assert!(merged.sah_cost <= plain.sah_cost, "{plain:?} {merged:?}");
    }

    /// A single primitive (the root is a leaf) and analytic primitives, which
    /// go through the callbacks with their slots.
    #[test]
    fn single_and_analytic_primitives() {
        let aabbs = [Bounds3::new(Vec3::splat(-1.0), Vec3::splat(1.0)).to_aabb()];
        let bvh = WideBvh::build(&aabbs, |_| None, BuildOptions::default());
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        let reference = PrimitiveReference {
            shape_index: 3,
            primitive_index: 0,
        };
        let hit = bvh.closest_hit(&ray, f32::INFINITY, |slot, t_max| {
            assert_eq!(slot, 0);
            (4.0 < t_max).then_some((4.0, reference))
        });
        assert_eq!(
            hit.map(|h| (h.slot, h.t, h.reference)),
            Some((0, 4.0, reference))
        );
        assert!(
            bvh.closest_hit(&ray, 3.0, |_, t_max| (4.0 < t_max)
                .then_some((4.0, reference)))
                .is_none()
        );
        assert!(bvh.any_hit(&ray, f32::INFINITY, |_, _| true));
        let away = Ray::new(Vec3::new(0.0, 0.0, -5.0), -Vec3::Z);
        assert!(!bvh.any_hit(&away, f32::INFINITY, |_, _| true));
    }
}

/// A diagnostic, not a check: prints the built-in Cornell box's tree (every
/// node's children, leaves with the lanes used per packet, and boxes), e.g.
/// `cargo test -p render --lib dump_cornell -- --ignored --nocapture`.
#[cfg(test)]
mod dump_tree {
    use super::*;

    #[test]
    #[ignore]
    fn dump_cornell_box_tree() {
        let description = crate::scene::builtin::builtin_scene("cornell-box").unwrap();
        let scene = crate::scene::Scene::build(&description).unwrap();
        let geometry = &scene.geometry;
        println!("{}", geometry.accelerator_statistics().unwrap());
        let bvh = geometry.bvh_for_tests();
        for (index, node) in bvh.nodes.iter().enumerate() {
            println!("node {index}");
            for child in 0..WIDTH {
                let reference = node.children[child];
                if reference == EMPTY_CHILD {
                    continue;
                }
                let min: Vec<f32> = (0..3).map(|a| node.plane(a, child)).collect();
                let max: Vec<f32> = (0..3).map(|a| node.plane(a + 3, child)).collect();
                if reference & LEAF_BIT == 0 {
                    println!("  child {child}: node {reference} {min:?} {max:?}");
                } else {
                    let contents = bvh.leaf_contents(reference);
                    let Triangles::Vertices(packets) = &bvh.triangles else {
                        panic!()
                    };
                    let lanes: Vec<usize> = contents
                        .packets
                        .clone()
                        .map(|p| packets.lanes_used(p))
                        .collect();
                    println!("  child {child}: leaf packets {lanes:?} {min:?} {max:?}");
                }
            }
        }
    }
}

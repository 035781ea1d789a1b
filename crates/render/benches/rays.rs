//! Incoherent closest-hit ray throughput of `render::geometry::Geometry`.
//!
//! Each benchmark traces a fixed batch of precomputed rays per iteration; divan's
//! item counter reports rays per second (read `Mitem/s` as Mrays/s).
//!
//! * `cornell_box`: ~36 triangles (walls, light, two boxes) and 2 spheres, rays
//!   from random points inside the box in uniformly random directions;
//! * `displaced_grid`: a procedurally displaced 710 × 710-quad height field
//!   (1,008,200 triangles), rays from a sphere around it aimed at random points
//!   inside its bounds;
//! * each single-threaded and split over a 2-thread rayon pool;
//! * `obvhs_builtin_triangles`: the same million-triangle mesh traced with
//!   obvhs' own `CwBvh::ray_traverse` and its `RtTriangle` (Möller–Trumbore)
//!   intersection, to measure the overhead of our callbacks (watertight test,
//!   primitive enum, hit record construction).

use std::sync::LazyLock;
use std::time::Duration;

use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use glam::{Vec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::rt_triangle::RtTriangle;
use obvhs::triangle::Triangle;
use rayon::prelude::*;
use render::geometry::{
    Geometry, Ray, Shape, Sphere, Transform, TriangleMesh, sample_uniform_sphere,
};

const RAYS_PER_ITERATION: usize = 1 << 16;

fn main() {
    divan::main();
}

/// SplitMix64 for reproducible ray batches.
struct BenchRng(u64);

impl BenchRng {
    fn uniform(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn direction(&mut self) -> Vec3 {
        sample_uniform_sphere(Vec2::new(self.uniform(), self.uniform()))
    }
}

struct Scene {
    geometry: Geometry,
    rays: Vec<Ray>,
}

fn cornell_box() -> Scene {
    let box_transform = |translation: Vec3, angle: f32, scale: Vec3| {
        Transform::translate(translation)
            * Transform::rotate(angle, Vec3::Y).unwrap()
            * Transform::scale(scale).unwrap()
    };
    let wall = |translation: Vec3, angle: f32, axis: Vec3| {
        Shape::from(
            TriangleMesh::rectangle(
                &(Transform::translate(translation) * Transform::rotate(angle, axis).unwrap()),
            )
            .unwrap(),
        )
    };
    let shapes = vec![
        wall(Vec3::new(0.0, -1.0, 0.0), -90.0, Vec3::X), // floor
        wall(Vec3::new(0.0, 1.0, 0.0), 90.0, Vec3::X),   // ceiling
        wall(Vec3::new(0.0, 0.0, -1.0), 0.0, Vec3::Y),   // back
        wall(Vec3::new(-1.0, 0.0, 0.0), 90.0, Vec3::Y),  // left
        wall(Vec3::new(1.0, 0.0, 0.0), -90.0, Vec3::Y),  // right
        TriangleMesh::rectangle(&box_transform(
            Vec3::new(0.0, 0.99, 0.0),
            0.0,
            Vec3::splat(0.25),
        ))
        .unwrap()
        .into(),
        TriangleMesh::cube(&box_transform(
            Vec3::new(-0.35, -0.4, -0.3),
            20.0,
            Vec3::new(0.3, 0.6, 0.3),
        ))
        .unwrap()
        .into(),
        TriangleMesh::cube(&box_transform(
            Vec3::new(0.35, -0.7, 0.3),
            -15.0,
            Vec3::splat(0.3),
        ))
        .unwrap()
        .into(),
        Sphere::new(Vec3::new(0.4, -0.1, 0.3), 0.3).unwrap().into(),
        Sphere::new(Vec3::new(-0.4, 0.4, 0.4), 0.2).unwrap().into(),
    ];
    let geometry = Geometry::new(shapes).unwrap();
    let mut rng = BenchRng(1);
    let rays = (0..RAYS_PER_ITERATION)
        .map(|_| {
            let origin = Vec3::new(
                2.0 * rng.uniform() - 1.0,
                2.0 * rng.uniform() - 1.0,
                2.0 * rng.uniform() - 1.0,
            ) * 0.98;
            Ray::new(origin, rng.direction())
        })
        .collect();
    Scene { geometry, rays }
}

/// Quads per side of the displaced grid: 2 · 710² = 1,008,200 triangles.
const GRID_QUADS: u32 = 710;

fn displaced_grid_mesh() -> TriangleMesh {
    let (positions, indices) = render::geometry::procedural::displaced_grid(GRID_QUADS);
    TriangleMesh::new(positions, None, None, indices, &Transform::IDENTITY).unwrap()
}

fn displaced_grid_rays() -> Vec<Ray> {
    let mut rng = BenchRng(2);
    (0..RAYS_PER_ITERATION)
        .map(|_| {
            let origin = 2.0 * rng.direction();
            let target = Vec3::new(
                2.0 * rng.uniform() - 1.0,
                0.4 * rng.uniform() - 0.2,
                2.0 * rng.uniform() - 1.0,
            );
            Ray::new(origin, (target - origin).normalize())
        })
        .collect()
}

static CORNELL_BOX: LazyLock<Scene> = LazyLock::new(cornell_box);

static DISPLACED_GRID: LazyLock<Scene> = LazyLock::new(|| {
    let start = std::time::Instant::now();
    let geometry = Geometry::new(vec![displaced_grid_mesh().into()]).unwrap();
    eprintln!(
        "displaced grid: {} triangles, BVH built in {:.2?}",
        geometry.primitive_count(),
        start.elapsed()
    );
    Scene {
        geometry,
        rays: displaced_grid_rays(),
    }
});

static TWO_THREADS: LazyLock<rayon::ThreadPool> = LazyLock::new(|| {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
});

fn trace_single_threaded(bencher: Bencher, scene: &Scene) {
    bencher
        .counter(ItemsCount::new(scene.rays.len()))
        .bench(|| {
            let mut hits = 0usize;
            for ray in &scene.rays {
                hits += scene
                    .geometry
                    .intersect(black_box(ray), f32::INFINITY)
                    .is_some() as usize;
            }
            hits
        });
}

fn trace_two_threads(bencher: Bencher, scene: &Scene) {
    bencher
        .counter(ItemsCount::new(scene.rays.len()))
        .bench(|| {
            TWO_THREADS.install(|| {
                scene
                    .rays
                    .par_chunks(1024)
                    .map(|chunk| {
                        chunk
                            .iter()
                            .filter(|ray| {
                                scene
                                    .geometry
                                    .intersect(black_box(ray), f32::INFINITY)
                                    .is_some()
                            })
                            .count()
                    })
                    .sum::<usize>()
            })
        });
}

#[divan::bench(sample_count = 20, sample_size = 1)]
fn cornell_box_single_thread(bencher: Bencher) {
    trace_single_threaded(bencher, &CORNELL_BOX);
}

#[divan::bench(sample_count = 20, sample_size = 1)]
fn cornell_box_two_threads(bencher: Bencher) {
    trace_two_threads(bencher, &CORNELL_BOX);
}

#[divan::bench(sample_count = 20, sample_size = 1)]
fn displaced_grid_single_thread(bencher: Bencher) {
    trace_single_threaded(bencher, &DISPLACED_GRID);
}

#[divan::bench(sample_count = 20, sample_size = 1)]
fn displaced_grid_two_threads(bencher: Bencher) {
    trace_two_threads(bencher, &DISPLACED_GRID);
}

/// obvhs' own triangles and traversal over the same mesh, triangles reordered
/// into BVH leaf order (as obvhs' Cornell box example does).
struct ObvhsScene {
    bvh: CwBvh,
    triangles: Vec<RtTriangle>,
}

static OBVHS_DISPLACED_GRID: LazyLock<ObvhsScene> = LazyLock::new(|| {
    let mesh = displaced_grid_mesh();
    let triangles: Vec<Triangle> = (0..mesh.triangle_count())
        .map(|i| {
            let [v0, v1, v2] = mesh.triangle_vertices(i).map(Vec3A::from);
            Triangle { v0, v1, v2 }
        })
        .collect();
    let bvh = build_cwbvh_from_tris(
        &triangles,
        BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    let triangles = bvh
        .primitive_indices
        .iter()
        .map(|&i| RtTriangle::from(&triangles[i as usize]))
        .collect();
    ObvhsScene { bvh, triangles }
});

#[divan::bench(sample_count = 20, sample_size = 1)]
fn displaced_grid_obvhs_builtin_triangles(bencher: Bencher) {
    let scene = &*OBVHS_DISPLACED_GRID;
    let rays: Vec<obvhs::ray::Ray> = DISPLACED_GRID
        .rays
        .iter()
        .map(|ray| {
            obvhs::ray::Ray::new_inf(
                Vec3A::from(ray.origin),
                Vec3A::from(ray.direction) + Vec3A::ZERO,
            )
        })
        .collect();
    bencher.counter(ItemsCount::new(rays.len())).bench(|| {
        let mut hits = 0usize;
        for ray in &rays {
            let mut hit = obvhs::ray::RayHit::none();
            hits += scene
                .bvh
                .ray_traverse(*black_box(ray), &mut hit, |ray, id| {
                    scene.triangles[id].intersect(ray)
                }) as usize;
        }
        hits
    });
}

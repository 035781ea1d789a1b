//! Incoherent closest-hit ray throughput of [`render::geometry::Geometry`], and an
//! export of the exact triangles and rays so another engine (Embree, through
//! `scripts/perf/embree_throughput.py`) can trace the same work.
//!
//! ```text
//! cargo run --release -p render --example ray_throughput -- [--export DIR] [--threads T] [--rays N] [--runs R] [--scene NAME] [--diagnose] [--leaf-layout vertices|indexed] [--no-merge-leaves] [--layouts]
//! ```
//!
//! `--leaf-layout` and `--no-merge-leaves` choose the BVH's
//! [`AcceleratorOptions`] (default: vertex packets, merged leaves); with
//! `--layouts` every scene is measured with each of the four combinations of
//! vertex/indexed leaves and merging off/on, interleaved, for A/B comparisons
//! in one process. The BVH's size, packet fill and SAH cost are printed.
//!
//! Scenes (deterministic, one triangle mesh each):
//! * `sphere_in_box`: a bumpy latitude–longitude sphere (128 segments × 128
//!   rings, triangle fans at the poles) inside a closed box, 32,524 triangles;
//!   every ray starts inside the box, so every ray hits;
//! * `displaced_grid`: a procedurally displaced 710 × 710-quad height field,
//!   1,008,200 triangles; about half of the rays escape.
//!
//! Rays: origins uniformly random inside the scene's bounds, directions
//! uniformly random on the unit sphere, both from a seeded [`SeekablePcg`].
//!
//! For each scene the throughput (Mrays/s, median of `--runs` runs of all rays)
//! is measured single-threaded and with rayon on `--threads` threads (default:
//! all available), and a checksum is printed: the number of hits and the sum of
//! hit distances (f64).
//!
//! The timed query is [`Geometry::intersect_primitive`]: the closest hit with
//! its distance, shape and triangle index and barycentrics, which is what
//! Embree's `rtcIntersect1` returns, so both engines do the same work. The
//! renderer's [`Geometry::intersect`] also builds the full surface record
//! (point, normals, uv, tangents, which reads the mesh again); it is timed
//! single-threaded as well and reported on its own line.
//!
//! With `--diagnose`, the same triangles also go into an obvhs CWBVH built with
//! the same preset as [`Geometry`] (`medium_build`), traced single-threaded with
//! obvhs' own Möller–Trumbore `RtTriangle` test and no hit record, and the
//! average numbers of nodes visited and triangles tested per ray are counted:
//! this separates the cost of the BVH and its traversal from the cost of our
//! primitive test and hit construction.
//!
//! With `--export DIR`, per scene `<name>.vertices.f32` (vertex count × 3 f32),
//! `<name>.indices.u32` (triangle count × 3 u32), `<name>.origins.f32`,
//! `<name>.directions.f32` (ray count × 3 f32 each) and `<name>.ours_t.f32` (our
//! closest-hit distance per ray, `+inf` for a miss), all raw little-endian, plus
//! `manifest.txt` listing the scene names, are written to `DIR`.

use std::f32::consts::PI;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

// `UVec2` is used unqualified inside obvhs' `traverse!` macro.
use glam::{UVec2, Vec2, Vec3, Vec3A};
use qmc::random::SeekablePcg;
use rayon::prelude::*;
use render::geometry::{
    AcceleratorOptions, Bounds3, Geometry, Ray, Transform, TriangleLeafLayout, TriangleMesh,
    sample_uniform_sphere,
};

/// Command-line options of the example.
struct Options {
    /// Directory the scenes and rays are written to, if any.
    export: Option<PathBuf>,
    /// Threads of the parallel measurement.
    threads: usize,
    /// Rays per scene.
    rays: usize,
    /// Timed runs per measurement (the median is reported).
    runs: usize,
    /// Only the scene of this name, if given.
    scene: Option<String>,
    /// Also trace with obvhs' own traversal and triangles, and count visits.
    diagnose: bool,
    /// The BVH's options.
    accelerator: AcceleratorOptions,
    /// Measure all four layout and merging combinations.
    layouts: bool,
}

fn parse_options() -> Result<Options, String> {
    let mut options = Options {
        export: None,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        rays: 1 << 20,
        runs: 5,
        scene: None,
        diagnose: false,
        accelerator: AcceleratorOptions::default(),
        layouts: false,
    };
    let mut arguments = std::env::args().skip(1);
    while let Some(argument) = arguments.next() {
        let mut value = |name: &str| {
            arguments
                .next()
                .ok_or_else(|| format!("{name} needs a value"))
        };
        let positive = |name: &str, text: String| match text.parse::<usize>() {
            Ok(n) if n > 0 => Ok(n),
            _ => Err(format!("{name} needs a positive integer, got {text:?}")),
        };
        match argument.as_str() {
            "--export" => options.export = Some(PathBuf::from(value("--export")?)),
            "--threads" => options.threads = positive("--threads", value("--threads")?)?,
            "--rays" => options.rays = positive("--rays", value("--rays")?)?,
            "--runs" => options.runs = positive("--runs", value("--runs")?)?,
            "--scene" => options.scene = Some(value("--scene")?),
            "--diagnose" => options.diagnose = true,
            "--leaf-layout" => {
                options.accelerator.leaf_layout = match value("--leaf-layout")?.as_str() {
                    "vertices" => TriangleLeafLayout::Vertices,
                    "indexed" => TriangleLeafLayout::Indexed,
                    other => {
                        return Err(format!(
                            "--leaf-layout needs vertices or indexed, got {other:?}"
                        ));
                    }
                }
            }
            "--no-merge-leaves" => options.accelerator.merge_leaves = false,
            "--layouts" => options.layouts = true,
            "--help" | "-h" => {
                return Err(
                    "usage: ray_throughput [--export DIR] [--threads T] [--rays N] [--runs R] \
                     [--scene NAME] [--diagnose] [--leaf-layout vertices|indexed] \
                     [--no-merge-leaves] [--layouts]"
                        .into(),
                );
            }
            other => return Err(format!("unknown argument {other:?} (try --help)")),
        }
    }
    Ok(options)
}

/// A scene's name, how to build its mesh, and the seed of its rays.
type SceneRecipe = (&'static str, fn() -> SceneMesh, u64);

/// Vertex positions and triangle indices of one test scene.
struct SceneMesh {
    name: &'static str,
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
}

/// A bumpy sphere of `segments` longitudes × `rings` latitude bands (poles as
/// triangle fans, so no degenerate triangles) inside the box `[-1, 1]³`.
fn sphere_in_box(segments: u32, rings: u32) -> SceneMesh {
    let mut positions = vec![Vec3::new(0.0, 0.0, 0.6), Vec3::new(0.0, 0.0, -0.6)];
    let (north, south) = (0u32, 1u32);
    // Latitude rings 1..rings-1, each with `segments` vertices.
    for ring in 1..rings {
        let theta = PI * ring as f32 / rings as f32;
        for segment in 0..segments {
            let phi = 2.0 * PI * segment as f32 / segments as f32;
            let radius = 0.6 * (1.0 + 0.08 * (5.0 * phi).sin() * (7.0 * theta).sin());
            positions.push(
                radius
                    * Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.sin() * phi.sin(),
                        theta.cos(),
                    ),
            );
        }
    }
    let vertex = |ring: u32, segment: u32| 2 + (ring - 1) * segments + segment % segments;
    let mut indices = Vec::new();
    for segment in 0..segments {
        indices.push([north, vertex(1, segment), vertex(1, segment + 1)]);
        indices.push([
            south,
            vertex(rings - 1, segment + 1),
            vertex(rings - 1, segment),
        ]);
    }
    for ring in 1..rings - 1 {
        for segment in 0..segments {
            let (a, b) = (vertex(ring, segment), vertex(ring, segment + 1));
            let (c, d) = (vertex(ring + 1, segment), vertex(ring + 1, segment + 1));
            indices.push([a, c, d]);
            indices.push([a, d, b]);
        }
    }
    // The box [-1, 1]³ as 12 triangles (corner k has coordinates from its bits).
    let first_corner = positions.len() as u32;
    for corner in 0..8u32 {
        let coordinate = |bit: u32| if corner >> bit & 1 == 1 { 1.0 } else { -1.0 };
        positions.push(Vec3::new(coordinate(0), coordinate(1), coordinate(2)));
    }
    let faces = [
        [0, 2, 6, 4],
        [1, 5, 7, 3],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 6, 7, 5],
    ];
    for [a, b, c, d] in faces.map(|face| face.map(|k| first_corner + k)) {
        indices.push([a, b, c]);
        indices.push([a, c, d]);
    }
    SceneMesh {
        name: "sphere_in_box",
        positions,
        indices,
    }
}

/// A height field over `[-1, 1]²` of `quads` × `quads` quads (two triangles each).
fn displaced_grid(quads: u32) -> SceneMesh {
    let (positions, indices) = render::geometry::procedural::displaced_grid(quads);
    SceneMesh {
        name: "displaced_grid",
        positions,
        indices,
    }
}

/// `count` rays with origins uniform in `bounds` and uniform unit directions.
fn incoherent_rays(bounds: Bounds3, count: usize, seed: u64) -> Vec<Ray> {
    let mut random = SeekablePcg::new(seed, 0);
    (0..count)
        .map(|_| {
            let u = Vec3::new(random.next_f32(), random.next_f32(), random.next_f32());
            let origin = bounds.min + u * bounds.diagonal();
            let direction = sample_uniform_sphere(Vec2::new(random.next_f32(), random.next_f32()));
            Ray::new(origin, direction)
        })
        .collect()
}

/// Hit count and sum of hit distances over a batch of rays.
#[derive(Clone, Copy, Default, PartialEq)]
struct Checksum {
    hits: usize,
    distance_sum: f64,
}

impl Checksum {
    fn add(self, t: Option<f32>) -> Self {
        match t {
            Some(t) => Self {
                hits: self.hits + 1,
                distance_sum: self.distance_sum + t as f64,
            },
            None => self,
        }
    }
}

/// Closest hits as Embree reports them (distance, ids, barycentrics).
fn trace_single_threaded(geometry: &Geometry, rays: &[Ray]) -> Checksum {
    rays.iter().fold(Checksum::default(), |sum, ray| {
        let hit = geometry.intersect_primitive(ray, f32::INFINITY);
        sum.add(std::hint::black_box(hit).map(|hit| hit.t))
    })
}

/// Closest hits with the renderer's full surface record.
fn trace_surface_hits(geometry: &Geometry, rays: &[Ray]) -> Checksum {
    rays.iter().fold(Checksum::default(), |sum, ray| {
        let hit = geometry.intersect(ray, f32::INFINITY);
        sum.add(std::hint::black_box(hit).map(|hit| hit.t))
    })
}

/// Rays in chunks of 1024 over the current rayon pool; the per-chunk sums are
/// combined in order, so the checksum does not depend on the thread count.
fn trace_parallel(geometry: &Geometry, rays: &[Ray]) -> Checksum {
    let chunks: Vec<Checksum> = rays
        .par_chunks(1024)
        .map(|chunk| trace_single_threaded(geometry, chunk))
        .collect();
    chunks.iter().fold(Checksum::default(), |a, b| Checksum {
        hits: a.hits + b.hits,
        distance_sum: a.distance_sum + b.distance_sum,
    })
}

/// CPU time consumed so far by the calling thread, from Linux's
/// `/proc/thread-self/schedstat` (first field: nanoseconds on a CPU); `None`
/// elsewhere. Unlike wall-clock time it does not count time the thread waits
/// for a core, so it stays meaningful on a machine shared with other jobs.
fn thread_cpu_time() -> Option<Duration> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let nanoseconds = text.split_whitespace().next()?.parse().ok()?;
    Some(Duration::from_nanos(nanoseconds))
}

/// CPU time consumed so far by all threads of the process (user + system,
/// fields 14 and 15 of Linux's `/proc/self/stat`, in clock ticks of 10 ms);
/// `None` elsewhere.
fn process_cpu_time() -> Option<Duration> {
    let text = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name, which is parenthesised and may hold spaces.
    let fields: Vec<&str> = text.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks: u64 = fields.get(11)?.parse::<u64>().ok()? + fields.get(12)?.parse::<u64>().ok()?;
    Some(Duration::from_millis(ticks * 10))
}

/// Throughputs of one measurement.
struct Rates {
    /// Median wall-clock Mrays/s.
    wall: f64,
    /// Median Mrays/s per CPU-second of the calling thread (meaningful for
    /// single-threaded runs only).
    cpu: Option<f64>,
    /// Mrays/s per CPU-second of the whole process over all runs (10 ms
    /// resolution), meaningful for parallel runs.
    process_cpu: Option<f64>,
}

/// Median Mrays/s of `runs` timed calls, and the checksum of the last call.
fn measure(runs: usize, rays: usize, mut trace: impl FnMut() -> Checksum) -> (Rates, Checksum) {
    let mut wall_rates = Vec::with_capacity(runs);
    let mut cpu_rates = Vec::with_capacity(runs);
    let mut checksum = Checksum::default();
    let megarays = rays as f64 / 1e6;
    let process_start = process_cpu_time();
    for _ in 0..runs {
        let cpu_start = thread_cpu_time();
        let start = Instant::now();
        checksum = std::hint::black_box(trace());
        wall_rates.push(megarays / start.elapsed().as_secs_f64());
        if let (Some(begin), Some(end)) = (cpu_start, thread_cpu_time()) {
            cpu_rates.push(megarays / (end - begin).as_secs_f64());
        }
    }
    let median = |mut rates: Vec<f64>| {
        rates.sort_by(f64::total_cmp);
        rates.get(rates.len() / 2).copied()
    };
    let process_cpu = match (process_start, process_cpu_time()) {
        (Some(begin), Some(end)) if end > begin => {
            Some(runs as f64 * megarays / (end - begin).as_secs_f64())
        }
        _ => None,
    };
    let rates = Rates {
        wall: median(wall_rates).unwrap_or(0.0),
        cpu: median(cpu_rates),
        process_cpu,
    };
    (rates, checksum)
}

fn write_raw(
    directory: &Path,
    file_name: String,
    bytes: impl Iterator<Item = [u8; 4]>,
) -> std::io::Result<()> {
    let mut writer = std::io::BufWriter::new(std::fs::File::create(directory.join(file_name))?);
    for word in bytes {
        writer.write_all(&word)?;
    }
    writer.flush()
}

fn export(
    directory: &Path,
    mesh: &SceneMesh,
    rays: &[Ray],
    geometry: &Geometry,
) -> std::io::Result<()> {
    let floats = |vectors: &[Vec3]| -> Vec<[u8; 4]> {
        vectors
            .iter()
            .flat_map(|v| v.to_array())
            .map(f32::to_le_bytes)
            .collect()
    };
    let name = mesh.name;
    write_raw(
        directory,
        format!("{name}.vertices.f32"),
        floats(&mesh.positions).into_iter(),
    )?;
    write_raw(
        directory,
        format!("{name}.indices.u32"),
        mesh.indices.iter().flatten().map(|i| i.to_le_bytes()),
    )?;
    let origins: Vec<Vec3> = rays.iter().map(|ray| ray.origin).collect();
    let directions: Vec<Vec3> = rays.iter().map(|ray| ray.direction).collect();
    write_raw(
        directory,
        format!("{name}.origins.f32"),
        floats(&origins).into_iter(),
    )?;
    write_raw(
        directory,
        format!("{name}.directions.f32"),
        floats(&directions).into_iter(),
    )?;
    let distances: Vec<f32> = rays
        .par_iter()
        .map(|ray| {
            geometry
                .intersect_primitive(ray, f32::INFINITY)
                .map_or(f32::INFINITY, |hit| hit.t)
        })
        .collect();
    write_raw(
        directory,
        format!("{name}.ours_t.f32"),
        distances.into_iter().map(f32::to_le_bytes),
    )
}

/// Traces `rays` through an obvhs CWBVH over `mesh` with obvhs' own triangle
/// test (see the module documentation) and prints the throughput and the
/// average nodes visited and triangles tested per ray.
fn diagnose(mesh: &SceneMesh, rays: &[Ray], runs: usize) {
    use obvhs::cwbvh::builder::build_cwbvh_from_tris;
    use obvhs::rt_triangle::RtTriangle;
    use obvhs::triangle::Triangle;

    let triangles: Vec<Triangle> = mesh
        .indices
        .iter()
        .map(|triangle| {
            let [v0, v1, v2] = triangle.map(|i| Vec3A::from(mesh.positions[i as usize]));
            Triangle { v0, v1, v2 }
        })
        .collect();
    let bvh = build_cwbvh_from_tris(
        &triangles,
        obvhs::BvhBuildParams::medium_build(),
        &mut Duration::default(),
    );
    let leaf_triangles: Vec<RtTriangle> = bvh
        .primitive_indices
        .iter()
        .map(|&i| RtTriangle::from(&triangles[i as usize]))
        .collect();
    let obvhs_rays: Vec<obvhs::ray::Ray> = rays
        .iter()
        .map(|ray| {
            // `+ 0` turns -0 into +0 (see `Geometry`'s note on obvhs' slab test).
            obvhs::ray::Ray::new_inf(
                Vec3A::from(ray.origin),
                Vec3A::from(ray.direction) + Vec3A::ZERO,
            )
        })
        .collect();
    let trace_builtin = || {
        obvhs_rays.iter().fold(Checksum::default(), |sum, ray| {
            let mut hit = obvhs::ray::RayHit::none();
            let found =
                bvh.ray_traverse(*ray, &mut hit, |ray, id| leaf_triangles[id].intersect(ray));
            sum.add(found.then_some(hit.t))
        })
    };
    let (rates, sum) = measure(runs, rays.len(), trace_builtin);
    let (mut nodes_visited, mut triangles_tested) = (0u64, 0u64);
    for ray in &obvhs_rays {
        let mut traversal_ray = *ray;
        let mut state = bvh.new_traversal(traversal_ray.direction);
        let mut node;
        obvhs::traverse!(
            bvh,
            node,
            state,
            {
                nodes_visited += 1;
                node.intersect_ray(&traversal_ray, state.oct_inv4)
            },
            {
                triangles_tested += 1;
                let t = leaf_triangles[state.primitive_id as usize].intersect(&traversal_ray);
                if t < traversal_ray.tmax {
                    traversal_ray.tmax = t;
                }
            }
        );
    }
    let per_ray = |count: u64| count as f64 / rays.len() as f64;
    println!(
        "  obvhs builtin (Möller–Trumbore, no hit record), 1 thread: {:8.3} Mrays/s ({:.3} per CPU-second), hits {}, sum t {:.6}",
        rates.wall,
        rates.cpu.unwrap_or(f64::NAN),
        sum.hits,
        sum.distance_sum
    );
    println!(
        "  BVH: {} nodes of {} bytes; per ray {:.1} nodes visited, {:.1} triangles tested",
        bvh.nodes.len(),
        std::mem::size_of_val(&bvh.nodes[0]),
        per_ray(nodes_visited),
        per_ray(triangles_tested)
    );
}

/// Measures single-threaded throughput for each leaf layout with and without
/// leaf merging, the four BVHs traced in turn within each of `runs` rounds
/// (so that load from other processes affects them alike); prints medians of
/// wall-clock and CPU-time rates and checks that all find the same hits.
fn compare_layouts(
    triangles: &TriangleMesh,
    rays: &[Ray],
    runs: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut variants = Vec::new();
    for leaf_layout in [TriangleLeafLayout::Vertices, TriangleLeafLayout::Indexed] {
        for merge_leaves in [false, true] {
            let options = AcceleratorOptions {
                leaf_layout,
                merge_leaves,
            };
            let geometry = Geometry::with_options(vec![triangles.clone().into()], options)?;
            if let Some(statistics) = geometry.accelerator_statistics() {
                println!("  {leaf_layout:?}, merge {merge_leaves}: {statistics}");
            }
            variants.push((options, geometry, Vec::new(), Vec::new()));
        }
    }
    let mut reference = None;
    for _ in 0..runs {
        for (_, geometry, wall_rates, cpu_rates) in &mut variants {
            let (rate, sum) = measure(1, rays.len(), || trace_single_threaded(geometry, rays));
            wall_rates.push(rate.wall);
            cpu_rates.push(rate.cpu.unwrap_or(f64::NAN));
            if *reference.get_or_insert(sum) != sum {
                return Err("the layouts' checksums differ".into());
            }
        }
    }
    let median = |values: &mut Vec<f64>| {
        values.sort_by(f64::total_cmp);
        values[values.len() / 2]
    };
    for (options, _, wall_rates, cpu_rates) in &mut variants {
        println!(
            "  {:?}, merge {}: {:8.3} Mrays/s ({:.3} per CPU-second), median of {runs}, 1 thread",
            options.leaf_layout,
            options.merge_leaves,
            median(wall_rates),
            median(cpu_rates)
        );
    }
    Ok(())
}

fn run(options: &Options) -> Result<(), Box<dyn std::error::Error>> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()?;
    if let Some(directory) = &options.export {
        std::fs::create_dir_all(directory)?;
    }
    let scenes: [SceneRecipe; 2] = [
        ("sphere_in_box", || sphere_in_box(128, 128), 1),
        ("displaced_grid", || displaced_grid(710), 2),
    ];
    if let Some(wanted) = &options.scene
        && !scenes.iter().any(|(name, ..)| name == wanted)
    {
        return Err(format!("unknown scene {wanted:?}").into());
    }
    let mut names = Vec::new();
    for (name, make_mesh, seed) in scenes {
        if options.scene.as_ref().is_some_and(|wanted| wanted != name) {
            continue;
        }
        let mesh = make_mesh();
        let start = Instant::now();
        let triangles = TriangleMesh::new(
            mesh.positions.clone(),
            None,
            None,
            mesh.indices.clone(),
            &Transform::IDENTITY,
        )?;
        let geometry = Geometry::with_options(vec![triangles.clone().into()], options.accelerator)?;
        let build_time = start.elapsed();
        let rays = incoherent_rays(geometry.bounds(), options.rays, seed);
        println!(
            "{}: {} triangles, BVH built in {:.2?}, {} rays",
            mesh.name,
            geometry.primitive_count(),
            build_time,
            rays.len()
        );
        if let Some(directory) = &options.export {
            pool.install(|| export(directory, &mesh, &rays, &geometry))?;
            names.push(mesh.name);
        }
        if let Some(statistics) = geometry.accelerator_statistics() {
            println!("  BVH: {statistics}");
        }
        if options.layouts {
            compare_layouts(&triangles, &rays, options.runs)?;
            continue;
        }
        // One untimed warm-up pass (page faults, caches).
        trace_parallel(&geometry, &rays);
        let (single_rate, single_sum) = measure(options.runs, rays.len(), || {
            trace_single_threaded(&geometry, &rays)
        });
        let (parallel_rate, parallel_sum) = measure(options.runs, rays.len(), || {
            pool.install(|| trace_parallel(&geometry, &rays))
        });
        let (surface_rate, surface_sum) = measure(options.runs, rays.len(), || {
            trace_surface_hits(&geometry, &rays)
        });
        let cpu_note = |rate: Option<f64>| {
            rate.map_or(String::new(), |rate| format!(" ({rate:.3} per CPU-second)"))
        };
        println!(
            "  ours   1 thread : {:8.3} Mrays/s{}, median of {}, hits {}, sum t {:.6}",
            single_rate.wall,
            cpu_note(single_rate.cpu),
            options.runs,
            single_sum.hits,
            single_sum.distance_sum
        );
        println!(
            "  ours {:>2} threads: {:8.3} Mrays/s{}, median of {}, hits {}, sum t {:.6}",
            options.threads,
            parallel_rate.wall,
            cpu_note(parallel_rate.process_cpu),
            options.runs,
            parallel_sum.hits,
            parallel_sum.distance_sum
        );
        println!(
            "  ours   1 thread, full surface hit (Geometry::intersect): {:8.3} Mrays/s{}, median of {}",
            surface_rate.wall,
            cpu_note(surface_rate.cpu),
            options.runs
        );
        if options.diagnose {
            diagnose(&mesh, &rays, options.runs);
        }
        // The parallel sum adds the same distances in another order.
        if single_sum.hits != parallel_sum.hits || single_sum != surface_sum {
            return Err("single-threaded, parallel and surface-hit checksums differ".into());
        }
    }
    if let Some(directory) = &options.export {
        std::fs::write(directory.join("manifest.txt"), names.join("\n") + "\n")?;
        println!("exported to {}", directory.display());
    }
    Ok(())
}

fn main() {
    let options = match parse_options() {
        Ok(options) => options,
        Err(message) => {
            eprintln!("{message}");
            std::process::exit(2);
        }
    };
    if let Err(error) = run(&options) {
        eprintln!("error: {error}");
        std::process::exit(1);
    }
}

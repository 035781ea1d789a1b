#!/usr/bin/env python3
"""Closest-hit throughput of Embree 4 on the scenes and rays exported by
`cargo run --release -p render --example ray_throughput -- --export DIR`.

For each scene listed in DIR/manifest.txt, this builds one Embree triangle
geometry from `<name>.vertices.f32` / `<name>.indices.u32` and traces the rays of
`<name>.origins.f32` / `<name>.directions.f32` (closest hit, tnear = 0, tfar =
infinite), in two ways:

* `embreex`: the PyPI binding (`pip install embreex`, Embree 4 bundled). Its
  `EmbreeScene.run(origins, directions, query="DISTANCE")` is a compiled loop of
  `rtcIntersect1` calls that releases the GIL, so 1 thread is one call and 2
  threads are two Python threads on the two halves of the rays.
* `native`: a small C driver compiled here with gcc against
  the libembree4 shipped inside the embreex wheel (minimal declarations of the
  documented Embree 4 C API, no headers needed), tracing with `rtcIntersect1`
  on 1 and 2 pthreads. No Python in the timed loop, so it is Embree's own speed;
  the difference to `embreex` is the binding's overhead.

Each figure is the median of --runs runs over all rays (Mrays/s, wall clock;
single-threaded runs also per CPU-second of the tracing thread, which does not
count time spent waiting for a core on a shared machine). The checksum
(number of hits and float64 sum of hit distances) and a per-ray comparison with
our distances (`<name>.ours_t.f32`) confirm both engines traced the same rays.
The embreex overhead per call is also shown by tracing in batches of several
sizes.

Usage: python3 scripts/perf/embree_throughput.py DIR [--runs 5] [--threads 1 2]
       [--engines embreex native] [--no-batches] [--scene NAME ...]
"""

import argparse
import ctypes
import hashlib
import os
import pathlib
import subprocess
import tempfile
import threading
import time

import numpy as np

# Embree 4 C API (documented in Embree's rtcore_*.h / man pages): only what the
# driver needs. Enum values: RTC_GEOMETRY_TYPE_TRIANGLE = 0,
# RTC_BUFFER_TYPE_INDEX = 0, RTC_BUFFER_TYPE_VERTEX = 1,
# RTC_FORMAT_UINT3 = 0x5003, RTC_FORMAT_FLOAT3 = 0x9003,
# RTC_INVALID_GEOMETRY_ID = 0xffffffff. RTCRayHit is RTCRay (12 x 4 bytes,
# 16-aligned) followed by RTCHit (16-aligned; padded generously here so that
# optional instance fields of any build fit).
NATIVE_DRIVER_SOURCE = r"""
#include <pthread.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>

typedef struct RTCDeviceTy* RTCDevice;
typedef struct RTCSceneTy* RTCScene;
typedef struct RTCGeometryTy* RTCGeometry;
RTCDevice rtcNewDevice(const char* config);
RTCScene rtcNewScene(RTCDevice device);
RTCGeometry rtcNewGeometry(RTCDevice device, int type);
void* rtcSetNewGeometryBuffer(RTCGeometry geometry, int type, unsigned int slot,
                              int format, size_t byteStride, size_t itemCount);
void rtcCommitGeometry(RTCGeometry geometry);
unsigned int rtcAttachGeometry(RTCScene scene, RTCGeometry geometry);
void rtcReleaseGeometry(RTCGeometry geometry);
void rtcCommitScene(RTCScene scene);
int rtcGetDeviceError(RTCDevice device);

struct __attribute__((aligned(16))) Ray {
  float org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar;
  unsigned int mask, id, flags;
};
struct __attribute__((aligned(16))) Hit {
  float ng_x, ng_y, ng_z, u, v;
  unsigned int prim_id, geom_id, inst_id[8];
};
struct __attribute__((aligned(16))) RayHit { struct Ray ray; struct Hit hit; };
void rtcIntersect1(RTCScene scene, struct RayHit* rayhit, void* args);

static RTCDevice device;

/* Builds a scene of one triangle mesh; returns NULL on error. */
RTCScene build_scene(const float* vertices, size_t vertex_count,
                     const unsigned int* indices, size_t triangle_count) {
  if (!device) device = rtcNewDevice(NULL);
  if (!device) return NULL;
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, 0);
  float* v = rtcSetNewGeometryBuffer(geometry, 1, 0, 0x9003, 12, vertex_count);
  unsigned int* i = rtcSetNewGeometryBuffer(geometry, 0, 0, 0x5003, 12, triangle_count);
  if (!v || !i) return NULL;
  for (size_t k = 0; k < 3 * vertex_count; ++k) v[k] = vertices[k];
  for (size_t k = 0; k < 3 * triangle_count; ++k) i[k] = indices[k];
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  return rtcGetDeviceError(device) == 0 ? scene : NULL;
}

struct Job {
  RTCScene scene;
  const float* origins;
  const float* directions;
  float* distances;
  size_t begin, end;
};

static void* trace_range(void* argument) {
  struct Job* job = argument;
  for (size_t r = job->begin; r < job->end; ++r) {
    struct RayHit rayhit;
    const float* o = job->origins + 3 * r;
    const float* d = job->directions + 3 * r;
    rayhit.ray.org_x = o[0]; rayhit.ray.org_y = o[1]; rayhit.ray.org_z = o[2];
    rayhit.ray.dir_x = d[0]; rayhit.ray.dir_y = d[1]; rayhit.ray.dir_z = d[2];
    rayhit.ray.tnear = 0.0f;
    rayhit.ray.tfar = INFINITY;
    rayhit.ray.time = 0.0f;
    rayhit.ray.mask = 0xffffffffu;
    rayhit.ray.id = 0;
    rayhit.ray.flags = 0;
    rayhit.hit.geom_id = 0xffffffffu;
    rayhit.hit.inst_id[0] = 0xffffffffu;
    rtcIntersect1(job->scene, &rayhit, NULL);
    job->distances[r] = rayhit.hit.geom_id == 0xffffffffu ? INFINITY : rayhit.ray.tfar;
  }
  return NULL;
}

/* Traces rays [0, count) on `threads` pthreads (contiguous ranges). */
int trace(RTCScene scene, const float* origins, const float* directions,
          float* distances, size_t count, int threads) {
  pthread_t handles[64];
  struct Job jobs[64];
  if (threads < 1 || threads > 64) return 1;
  for (int t = 0; t < threads; ++t) {
    jobs[t] = (struct Job){scene, origins, directions, distances,
                           count * t / threads, count * (t + 1) / threads};
    if (t > 0 && pthread_create(&handles[t], NULL, trace_range, &jobs[t])) return 1;
  }
  trace_range(&jobs[0]);
  for (int t = 1; t < threads; ++t) pthread_join(handles[t], NULL);
  return 0;
}
"""


def load_scene(directory, name):
    """Vertices (V×3 f32), indices (T×3 u32), origins and directions (R×3 f32),
    and our per-ray distances (R f32, +inf = miss), from the raw files."""

    def read(suffix, dtype):
        return np.fromfile(directory / f"{name}.{suffix}", dtype=dtype)

    vertices = read("vertices.f32", "<f4").reshape(-1, 3)
    indices = read("indices.u32", "<u4").reshape(-1, 3)
    origins = read("origins.f32", "<f4").reshape(-1, 3)
    directions = read("directions.f32", "<f4").reshape(-1, 3)
    ours_path = directory / f"{name}.ours_t.f32"
    ours = np.fromfile(ours_path, dtype="<f4") if ours_path.exists() else None
    if indices.size and indices.max() >= len(vertices):
        raise ValueError(f"{name}: index out of range")
    if origins.shape != directions.shape:
        raise ValueError(f"{name}: origins and directions differ in count")
    return vertices, indices, origins, directions, ours


def median_rate(runs, ray_count, trace):
    """Median wall-clock Mrays/s over `runs` calls of `trace()`, median Mrays/s
    per CPU-second of the calling thread (meaningful when the calling thread
    does all the work: one thread), and the last call's result."""
    wall_rates, cpu_rates, result = [], [], None
    for _ in range(runs):
        cpu_start = time.thread_time()
        start = time.perf_counter()
        result = trace()
        wall_rates.append(ray_count / (time.perf_counter() - start) / 1e6)
        cpu_rates.append(ray_count / max(time.thread_time() - cpu_start, 1e-9) / 1e6)
    return float(np.median(wall_rates)), float(np.median(cpu_rates)), result


def checksum(distances):
    """(hit count, float64 sum of hit distances); misses are +inf or >= 1e30."""
    hit = np.isfinite(distances) & (distances < 1e30)
    return int(hit.sum()), float(distances[hit].astype(np.float64).sum())


def compare(name, engine, distances, ours):
    """Prints how many rays disagree with our distances."""
    if ours is None:
        return
    embree_hit = np.isfinite(distances) & (distances < 1e30)
    ours_hit = np.isfinite(ours)
    only_embree = int((embree_hit & ~ours_hit).sum())
    only_ours = int((ours_hit & ~embree_hit).sum())
    both = embree_hit & ours_hit
    relative = np.abs(distances[both] - ours[both]) / np.maximum(1.0, np.abs(ours[both]))
    differing = int((relative > 1e-4).sum())
    print(
        f"  {name} {engine} vs ours: {only_embree} rays hit only in Embree, "
        f"{only_ours} only in ours, {differing} of {int(both.sum())} common hits "
        f"differ by > 1e-4 (max relative difference {relative.max(initial=0.0):.2e})"
    )


class EmbreexEngine:
    """Embree through the embreex binding."""

    label = "embreex"

    def __init__(self, vertices, indices):
        from embreex import mesh_construction, rtcore_scene

        self.scene = rtcore_scene.EmbreeScene()
        mesh_construction.TriangleMesh(
            self.scene, np.ascontiguousarray(vertices), indices.astype(np.int32)
        )
        # The binding commits the scene (builds the BVH) on the first query.
        self.scene.run(np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))

    def trace(self, origins, directions, threads):
        if threads == 1:
            return self.scene.run(origins, directions, query="DISTANCE")
        parts = np.array_split(np.arange(len(origins)), threads)
        results = [None] * threads

        def work(k):
            rays = slice(parts[k][0], parts[k][-1] + 1)
            results[k] = self.scene.run(origins[rays], directions[rays], query="DISTANCE")

        workers = [threading.Thread(target=work, args=(k,)) for k in range(threads)]
        for worker in workers:
            worker.start()
        for worker in workers:
            worker.join()
        return np.concatenate(results)


def embreex_library_directory():
    import embreex

    directory = pathlib.Path(embreex.__file__).resolve().parent.parent / "embreex.libs"
    libraries = sorted(directory.glob("libembree4*.so*"))
    if not libraries:
        raise FileNotFoundError(f"no libembree4 in {directory}")
    return libraries[0]


def compile_native_driver():
    """Compiles NATIVE_DRIVER_SOURCE (cached by its hash) and loads it."""
    library = embreex_library_directory()
    digest = hashlib.sha256((NATIVE_DRIVER_SOURCE + str(library)).encode()).hexdigest()[:12]
    cache = pathlib.Path(tempfile.gettempdir()) / f"embree_driver_{digest}"
    shared_object = cache / "embree_driver.so"
    if not shared_object.exists():
        cache.mkdir(exist_ok=True)
        source = cache / "embree_driver.c"
        source.write_text(NATIVE_DRIVER_SOURCE)
        subprocess.run(
            ["gcc", "-O2", "-shared", "-fPIC", "-o", str(shared_object), str(source),
             str(library), f"-Wl,-rpath,{library.parent}", "-lpthread", "-lm"],
            check=True,
        )
    driver = ctypes.CDLL(str(shared_object))
    driver.build_scene.restype = ctypes.c_void_p
    driver.build_scene.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_void_p, ctypes.c_size_t]
    driver.trace.restype = ctypes.c_int
    driver.trace.argtypes = [ctypes.c_void_p] * 4 + [ctypes.c_size_t, ctypes.c_int]
    return driver


class NativeEngine:
    """Embree called from C (no Python in the timed loop)."""

    label = "native"
    driver = None

    def __init__(self, vertices, indices):
        if NativeEngine.driver is None:
            NativeEngine.driver = compile_native_driver()
        self.vertices = np.ascontiguousarray(vertices, dtype=np.float32)
        self.indices = np.ascontiguousarray(indices, dtype=np.uint32)
        self.scene = self.driver.build_scene(
            self.vertices.ctypes.data, len(self.vertices), self.indices.ctypes.data, len(self.indices)
        )
        if not self.scene:
            raise RuntimeError("Embree scene construction failed")

    def trace(self, origins, directions, threads):
        distances = np.empty(len(origins), dtype=np.float32)
        status = self.driver.trace(
            self.scene, origins.ctypes.data, directions.ctypes.data, distances.ctypes.data,
            len(origins), threads,
        )
        if status != 0:
            raise RuntimeError("native trace failed")
        return distances


def binding_overhead(engine, origins, directions, runs):
    """Mrays/s of embreex when the rays are traced in batches of several sizes
    (per-call Python overhead shows up at small batches)."""
    rates = []
    for batch in (256, 4096, 65536, len(origins)):
        def trace_batches():
            for start in range(0, len(origins), batch):
                engine.scene.run(origins[start:start + batch], directions[start:start + batch],
                                 query="DISTANCE")
        rate, _, _ = median_rate(runs, len(origins), trace_batches)
        rates.append(f"{batch}: {rate:.3f}")
    print("  embreex 1 thread by batch size (rays per call: Mrays/s): " + ", ".join(rates))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("directory", type=pathlib.Path)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--engines", nargs="+", choices=["embreex", "native"],
                        default=["embreex", "native"], help="which Embree drivers to time")
    parser.add_argument("--no-batches", action="store_true", help="skip the batch-size sweep")
    parser.add_argument("--scene", action="append", help="only these scenes (repeatable)")
    arguments = parser.parse_args()
    if arguments.runs < 1:
        parser.error("--runs must be positive")
    names = (arguments.directory / "manifest.txt").read_text().split()
    if arguments.scene:
        unknown = set(arguments.scene) - set(names)
        if unknown:
            parser.error(f"scenes not in the manifest: {sorted(unknown)}")
        names = [name for name in names if name in arguments.scene]
    engines = [{"embreex": EmbreexEngine, "native": NativeEngine}[e] for e in arguments.engines]
    for name in names:
        vertices, indices, origins, directions, ours = load_scene(arguments.directory, name)
        print(f"{name}: {len(indices)} triangles, {len(origins)} rays")
        if ours is not None:
            hits, total = checksum(ours)
            print(f"  ours (exported)           : hits {hits}, sum t {total:.6f}")
        for engine_type in engines:
            start = time.perf_counter()
            engine = engine_type(vertices, indices)
            print(f"  {engine.label} BVH built in {time.perf_counter() - start:.2f} s")
            engine.trace(origins, directions, 1)  # warm-up
            for threads in arguments.threads:
                rate, cpu_rate, distances = median_rate(
                    arguments.runs, len(origins), lambda: engine.trace(origins, directions, threads)
                )
                hits, total = checksum(distances)
                cpu_note = f" ({cpu_rate:.3f} per CPU-second)" if threads == 1 else ""
                print(
                    f"  {engine.label:>7} {threads} thread(s): {rate:8.3f} Mrays/s{cpu_note}, "
                    f"median of {arguments.runs}, hits {hits}, sum t {total:.6f}"
                )
            compare(name, engine.label, distances, ours)
            if engine.label == "embreex" and not arguments.no_batches:
                binding_overhead(engine, origins, directions, arguments.runs)


if __name__ == "__main__":
    main()

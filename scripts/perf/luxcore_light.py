#!/usr/bin/env python3
"""Light paths per second of LuxCore's LIGHTCPU engine and of `lqmc render
--integrator light` on the same Cornell box, measured side by side.

The scene is Mitsuba's `scenes/cbox/cbox-rgb.xml` (our `builtin:cornell-box`
reproduces it): its eight OBJ meshes (the luminaire moved 0.5 down, as the
XML does), the RGB diffuse reflectances of `fragments/bsdfs-rgb.xml`, the
area light's radiance (18.387, 10.9873, 2.75357) on the luminaire's front,
the camera at (278, 273, -800) looking along +z with a 39.3077° field of
view, a box filter of radius 0.5 and 256 x 256 pixels. LuxCore gets it
through its Python API (`Scene.DefineMesh` for the meshes, properties for
the rest); only the OBJ files are read, nothing is converted by hand. The
OBJ winding gives the luminaire's front face downwards in LuxCore too (with
its triangles reversed, LuxCore's image shows light leaking from the gap
above the luminaire and 6.9 rather than 5.3 rays per path).

Work per path. Both engines trace one light path per sample, connect every
vertex to the camera and also trace one camera ray per path (LuxCore for
directly seen emitters, lqmc only for environments, of which the box has
none). Depth: lqmc's `--max-depth 6` counts segments of the whole path
(Mitsuba's convention), so the light subpath has at most 5 vertices;
LuxCore's `light.maxdepth` counts light-path vertices, so it is set to
`max_depth - 1` = 5 here. Russian roulette: LuxCore's `path.russianroulette`
(depth 3, survival probability clamped below at cap 0.5) and lqmc's
`--rr-depth` are both left at their defaults unless given.

LuxCore: the session is started, run for `--seconds`, and its light-path
count `stats.renderengine.total.samplecount` (one sample per light path in
LIGHTCPU) over the engine's own `stats.renderengine.time` is its rate;
a short warm-up session is run first. Rays per light path (LuxCore's
`stats.renderengine.total.raysec` over `...samplesec`, lqmc's rays/s over
samples/s) are printed too: they show how much work each path does after
Russian roulette, which the two engines decide differently (LuxCore per
bounce on f cos / p clamped to at least `path.russianroulette.cap`, lqmc on
the product since the light, pbrt-v4's rule). lqmc: `--spp` paths per pixel, the
`M samples/s` that `lqmc render` prints (one light path per sample; scene
building and image writing excluded). Runs are interleaved (LuxCore, lqmc,
LuxCore, ...) and medians reported, with the load average before and after.

Usage (from the repository root, after `cargo build --release -p lqmc-cli`):

    pip install pyluxcore
    python3 scripts/perf/luxcore_light.py --runs 5 --seconds 10 --spp 64
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# Vendored in the repository (scenes/external, see its README).
CBOX = Path(__file__).resolve().parents[2] / "scenes/external/mitsuba-data/scenes/cbox"

# fragments/bsdfs-rgb.xml and fragments/shapes.xml of Mitsuba's box.
MATERIALS = {
    "box": (0.45, 0.30, 0.90),
    "white": (0.885809, 0.698859, 0.666422),
    "red": (0.570068, 0.0430135, 0.0443706),
    "green": (0.105421, 0.37798, 0.076425),
    "light": (0.936461, 0.740433, 0.705267),
}
SHAPES = [
    ("cbox_luminaire", "light", -0.5),
    ("cbox_floor", "white", 0.0),
    ("cbox_ceiling", "white", 0.0),
    ("cbox_back", "white", 0.0),
    ("cbox_greenwall", "green", 0.0),
    ("cbox_redwall", "red", 0.0),
    ("cbox_smallbox", "box", 0.0),
    ("cbox_largebox", "box", 0.0),
]
RADIANCE = (18.387, 10.9873, 2.75357)


def read_obj(path, y_offset):
    """Vertices and triangles (fans of polygons) of a simple OBJ file."""
    vertices, triangles = [], []
    for line in path.read_text().splitlines():
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "v":
            x, y, z = map(float, fields[1:4])
            vertices.append((x, y + y_offset, z))
        elif fields[0] == "f":
            corners = [int(field.split("/")[0]) for field in fields[1:]]
            corners = [c - 1 if c > 0 else len(vertices) + c for c in corners]
            for i in range(1, len(corners) - 1):
                triangles.append((corners[0], corners[i], corners[i + 1]))
    return vertices, triangles


def luxcore_scene(pyluxcore):
    scene = pyluxcore.Scene()
    props = pyluxcore.Properties()
    # Mitsuba's camera: fov 39.3077° on the smaller (here either) axis.
    props.SetFromString("""
        scene.camera.type = "perspective"
        scene.camera.lookat.orig = 278 273 -800
        scene.camera.lookat.target = 278 273 -799
        scene.camera.up = 0 1 0
        scene.camera.fieldofview = 39.3077
        scene.camera.cliphither = 10
        scene.camera.clipyon = 2800
        """)
    for name, kd in MATERIALS.items():
        props.Set(pyluxcore.Property(f"scene.materials.{name}.type", "matte"))
        props.Set(pyluxcore.Property(f"scene.materials.{name}.kd", list(kd)))
    # Radiance as given: gain 1, no power normalisation.
    props.Set(pyluxcore.Property("scene.materials.light.emission", list(RADIANCE)))
    props.Set(pyluxcore.Property("scene.materials.light.emission.gain", [1.0, 1.0, 1.0]))
    props.Set(pyluxcore.Property("scene.materials.light.emission.power", 0.0))
    props.Set(pyluxcore.Property("scene.materials.light.emission.efficency", 0.0))
    props.Set(pyluxcore.Property("scene.materials.light.emission.normalizebycolor", False))
    scene.Parse(props)
    triangle_count = 0
    for mesh, material, y_offset in SHAPES:
        vertices, triangles = read_obj(CBOX / "meshes" / f"{mesh}.obj", y_offset)
        triangle_count += len(triangles)
        scene.DefineMesh(f"{mesh}-mesh", vertices, triangles, None, None, None, None)
        objects = pyluxcore.Properties()
        objects.Set(pyluxcore.Property(f"scene.objects.{mesh}.shape", f"{mesh}-mesh"))
        objects.Set(pyluxcore.Property(f"scene.objects.{mesh}.material", material))
        scene.Parse(objects)
    return scene, triangle_count


def render_config(pyluxcore, args, engine):
    """The box with `engine`'s properties (engine, sampler, depths) and the
    film both scripts use: 2 threads by default, a box filter of radius 0.5."""
    scene, _ = luxcore_scene(pyluxcore)
    props = pyluxcore.Properties()
    props.SetFromString(engine + f"""
        native.threads.count = {args.threads}
        film.width = {args.res}
        film.height = {args.res}
        film.filter.type = "BOX"
        film.filter.width = 0.5
        film.outputs.0.type = "RGB_IMAGEPIPELINE"
        film.outputs.0.filename = "luxcore.png"
        """)
    return pyluxcore.RenderConfig(props, scene)


def session_stats(pyluxcore, config, seconds):
    """Runs a session of `config` for `seconds`; its statistics."""
    session = pyluxcore.RenderSession(config)
    session.Start()
    deadline = time.perf_counter() + seconds
    while time.perf_counter() < deadline:
        time.sleep(0.2)
    session.UpdateStats()
    stats = session.GetStats()
    session.Stop()
    return stats


def luxcore_config(pyluxcore, args, seed):
    return render_config(pyluxcore, args, f"""
        renderengine.type = "LIGHTCPU"
        renderengine.seed = {seed + 1}
        sampler.type = "RANDOM"
        light.maxdepth = {args.max_depth - 1}
        path.pathdepth.total = {args.max_depth - 1}
        """)


def luxcore_run(pyluxcore, args, seconds, seed):
    """Light paths per second of one LIGHTCPU session of `seconds`."""
    stats = session_stats(pyluxcore, luxcore_config(pyluxcore, args, seed), seconds)
    paths = stats.Get("stats.renderengine.total.samplecount").GetFloat()
    engine_seconds = stats.Get("stats.renderengine.time").GetFloat()
    rays_per_path = (stats.Get("stats.renderengine.total.raysec").GetFloat()
                     / stats.Get("stats.renderengine.total.samplesec").GetFloat())
    return paths / engine_seconds, paths, engine_seconds, rays_per_path


def lqmc_run(args, seed, output):
    # Not --quiet: the rates are read from lqmc's report on stdout.
    command = [str(args.lqmc), "render", "builtin:cornell-box", "--integrator", "light",
               "--resolution", f"{args.res}x{args.res}", "--max-depth", str(args.max_depth),
               "--threads", str(args.threads), "--spp", str(args.spp),
               "--sampler", args.sampler, "-o", str(output)]
    if args.rr_depth is not None:
        command += ["--rr-depth", str(args.rr_depth)]
    text = subprocess.run(command + ["--seed", str(seed)], check=True,
                          capture_output=True, text=True).stdout
    match = re.search(r"time ([0-9.]+) s, ([0-9.]+) M samples/s, ([0-9.]+) M rays/s", text)
    if match is None:
        sys.exit(f"cannot parse lqmc output:\n{text}")
    rate = float(match.group(2)) * 1e6
    return rate, float(match.group(3)) * 1e6 / rate, " ".join(command)


def describe(name, rates):
    median = statistics.median(rates)
    runs = ", ".join(f"{rate / 1e6:.3f}" for rate in rates)
    print(f"{name:34s} median {median / 1e6:7.3f} M light paths/s  (runs: {runs})")
    return median


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lqmc", type=Path, default=Path("target/release/lqmc"))
    parser.add_argument("--spp", type=int, default=64, help="lqmc light paths per pixel")
    parser.add_argument("--seconds", type=float, default=10.0,
                        help="LuxCore's render time per run")
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--max-depth", type=int, default=6,
                        help="path depth in segments (Mitsuba's convention)")
    parser.add_argument("--rr-depth", type=int, default=None,
                        help="lqmc's --rr-depth (default: lqmc's own)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--sampler", default="independent")
    args = parser.parse_args()
    if args.res != 256:
        sys.exit("builtin:cornell-box is 256x256; keep --res 256")

    import pyluxcore
    pyluxcore.Init()
    print("LuxCore", pyluxcore.Version(), "load before:", os.getloadavg())
    luxcore_run(pyluxcore, args, 2.0, 1000)  # warm-up
    luxcore_rates, lqmc_rates = [], []
    luxcore_rays, lqmc_rays = [], []
    command = ""
    with tempfile.TemporaryDirectory() as directory:
        output = Path(directory) / "light.exr"
        for run in range(args.runs):
            rate, paths, seconds, rays = luxcore_run(pyluxcore, args, args.seconds, run)
            luxcore_rates.append(rate)
            luxcore_rays.append(rays)
            print(f"run {run}: LuxCore {paths:.0f} paths in {seconds:.2f} s, "
                  f"{rays:.2f} rays per path", flush=True)
            rate, rays, command = lqmc_run(args, run, output)
            lqmc_rates.append(rate)
            lqmc_rays.append(rays)
            print(f"run {run}: lqmc {rate / 1e6:.3f} M paths/s, {rays:.2f} rays per path",
                  flush=True)
    print(f"lqmc command: {command} --seed RUN")
    theirs = describe(f"LuxCore {pyluxcore.Version()} LIGHTCPU", luxcore_rates)
    ours = describe(f"lqmc light ({args.sampler})", lqmc_rates)
    print(f"rays per light path: LuxCore {statistics.median(luxcore_rays):.2f}, "
          f"lqmc {statistics.median(lqmc_rays):.2f}")
    print(f"lqmc / LuxCore: {ours / theirs:.2f}x; load after: {os.getloadavg()}")
    sys.stdout.flush()
    # pyluxcore's logging can abort at interpreter shutdown: leave directly.
    os._exit(0)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Paths per second of Mitsuba 3 and of `lqmc render` on the same Cornell box.

The scene is Mitsuba's own `scenes/cbox/cbox-rgb.xml` (our `builtin:cornell-box`
reproduces it: geometry, RGB diffuse materials, emitter radiance
(18.387, 10.9873, 2.75357), camera, box filter, path tracer with max_depth 6).
Both renderers run at the same resolution, depth and samples per pixel on the
same number of threads; paths/s = width * height * spp / seconds.

Russian roulette: the scene's `path` integrator sets no `rr_depth`, so
Mitsuba uses its default 5 (roulette decides from the fifth bounce on, which
with max_depth 6 only affects the last segment). lqmc's default is 3, which
ends most paths earlier and so does less work per path than Mitsuba; the
script passes `--rr-depth` (default 5, Mitsuba's) so both trace the same
number of segments in expectation. Before 2026-12-02 it did not, and the
comparison favoured lqmc.

Mitsuba: only `mi.render` is timed (scene loading excluded), after one small
warm-up render. lqmc: the render time printed by `lqmc render` (it excludes
scene building and image writing); the wall time of the whole process is
reported too.

Usage (from the repository root, after `cargo build --release -p lqmc-cli`):

    pip install mitsuba==3.9.1
    python3 scripts/perf/mitsuba_cbox.py --spp 64 --res 256 --threads 2 --runs 5
"""

import argparse
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# Vendored in the repository (scenes/external, see its README).
SCENE = Path(__file__).resolve().parents[2] / "scenes/external/mitsuba-data/scenes/cbox/cbox-rgb.xml"


def mitsuba_paths_per_second(variant, args):
    """Median paths/s of `mi.render` over `args.runs` runs (different seeds)."""
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(variant)
    dr.set_thread_count(args.threads)
    scene = mi.load_file(str(args.scene), spp=args.spp, res=args.res,
                         max_depth=args.max_depth)
    mi.render(scene, spp=1, seed=1000)  # warm-up (lazy initialisation)
    rates = []
    for run in range(args.runs):
        start = time.perf_counter()
        image = mi.render(scene, spp=args.spp, seed=run)
        seconds = time.perf_counter() - start
        del image
        rates.append(args.res * args.res * args.spp / seconds)
    return mi.__version__, rates


def lqmc_paths_per_second(args):
    """Median paths/s printed by `lqmc render` over `args.runs` runs."""
    rates, wall_rates = [], []
    with tempfile.TemporaryDirectory() as directory:
        output = Path(directory) / "cbox.exr"
        # Not --quiet: the rates are read from lqmc's report on stdout.
        command = [str(args.lqmc), "render", "builtin:cornell-box",
                   "--spp", str(args.spp), "--max-depth", str(args.max_depth),
                   "--rr-depth", str(args.rr_depth),
                   "--sampler", args.sampler, "--threads", str(args.threads),
                   "-o", str(output)]
        for run in range(args.runs):
            start = time.perf_counter()
            text = subprocess.run(command + ["--seed", str(run)], check=True,
                                  capture_output=True, text=True).stdout
            wall = time.perf_counter() - start
            match = re.search(r"time ([0-9.]+) s, ([0-9.]+) M samples/s", text)
            if match is None:
                sys.exit(f"cannot parse lqmc output:\n{text}")
            rates.append(float(match.group(2)) * 1e6)
            wall_rates.append(args.res * args.res * args.spp / wall)
    return " ".join(command), rates, wall_rates


def describe(name, rates):
    median = statistics.median(rates)
    runs = ", ".join(f"{rate / 1e6:.3f}" for rate in rates)
    print(f"{name:28s} median {median / 1e6:7.3f} M paths/s  (runs: {runs})")
    return median


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", type=Path, default=SCENE)
    parser.add_argument("--lqmc", type=Path, default=Path("target/release/lqmc"))
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--res", type=int, default=256,
                        help="square resolution (lqmc's built-in box is 256x256)")
    parser.add_argument("--max-depth", type=int, default=6)
    parser.add_argument("--rr-depth", type=int, default=5,
                        help="lqmc's --rr-depth (Mitsuba's path integrator default: 5)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--sampler", default="independent",
                        help="lqmc sampler (Mitsuba's scene uses independent)")
    parser.add_argument("--variants", default="scalar_spectral,scalar_rgb")
    args = parser.parse_args()
    if args.res != 256:
        sys.exit("builtin:cornell-box is 256x256; keep --res 256")

    medians = {}
    for variant in args.variants.split(","):
        version, rates = mitsuba_paths_per_second(variant, args)
        medians[variant] = describe(f"mitsuba {version} {variant}", rates)
    command, rates, wall_rates = lqmc_paths_per_second(args)
    print(f"lqmc command: {command} --seed RUN")
    ours = describe(f"lqmc ({args.sampler}, render)", rates)
    describe(f"lqmc ({args.sampler}, process)", wall_rates)
    for variant, median in medians.items():
        print(f"lqmc / mitsuba {variant}: {ours / median:.2f}x")


if __name__ == "__main__":
    main()

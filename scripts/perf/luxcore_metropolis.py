#!/usr/bin/env python3
"""Mutations per second of LuxCore's METROPOLIS sampler and of `lqmc render
--integrator pssmlt` (and the path tracer's paths per second) on the same
Cornell box, measured side by side.

The scene is the one of `luxcore_light.py` (Mitsuba's `cbox-rgb.xml`, whose
OBJ meshes LuxCore reads through its Python API; `builtin:cornell-box`
reproduces it). LuxCore: the PATHCPU engine with `sampler.type =
"METROPOLIS"` (Kelemen-style primary-sample-space MLT over its path tracer:
large-step rate 0.4, maximum consecutive rejections 512, image mutation
rate 0.1, its defaults), `path.pathdepth.total = max_depth - 1` (LuxCore
counts vertices after the camera; `--max-depth` counts segments); each
sample is one mutation, so `stats.renderengine.total.samplecount` over
`stats.renderengine.time` is its rate. lqmc: `--integrator pssmlt` (over
the path tracer, Kelemen's kernel, large steps 0.3, 1000 chains, 100 000
bootstrap samples), its rate the `M mutations/s` of the chains' report
(chains only: the bootstrap is reported apart); and `--integrator path
--sampler independent` at the same depth, its `M samples/s`. Runs are
interleaved (LuxCore, lqmc pssmlt, lqmc path, ...) and medians reported,
with the load average before and after.

Usage (from the repository root, after `cargo build --release -p lqmc-cli`):

    pip install pyluxcore
    python3 scripts/perf/luxcore_metropolis.py --runs 5 --seconds 10 --spp 64
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from luxcore_light import render_config, session_stats  # noqa: E402  (the same box)


def luxcore_run(pyluxcore, args, seconds, seed):
    """Mutations per second of one METROPOLIS session of `seconds`."""
    depth = args.max_depth - 1
    config = render_config(pyluxcore, args, f"""
        renderengine.type = "PATHCPU"
        renderengine.seed = {seed + 1}
        sampler.type = "METROPOLIS"
        path.pathdepth.total = {depth}
        path.pathdepth.diffuse = {depth}
        path.pathdepth.glossy = {depth}
        path.pathdepth.specular = {depth}
        """)
    stats = session_stats(pyluxcore, config, seconds)
    samples = stats.Get("stats.renderengine.total.samplecount").GetFloat()
    engine_seconds = stats.Get("stats.renderengine.time").GetFloat()
    return samples / engine_seconds, samples, engine_seconds


def lqmc_run(args, integrator, seed, output):
    # Not --quiet: the rates are read from lqmc's report on stdout.
    command = [str(args.lqmc), "render", "builtin:cornell-box", "--integrator", integrator,
               "--resolution", f"{args.res}x{args.res}", "--max-depth", str(args.max_depth),
               "--threads", str(args.threads), "--spp", str(args.spp),
               "-o", str(output)]
    if integrator == "path":
        command += ["--sampler", "independent"]
    text = subprocess.run(command + ["--seed", str(seed)], check=True,
                          capture_output=True, text=True).stdout
    pattern = (r"([0-9.]+) M mutations/s" if integrator == "pssmlt"
               else r"time [0-9.]+ s, ([0-9.]+) M samples/s")
    match = re.search(pattern, text)
    if match is None:
        sys.exit(f"cannot parse lqmc output:\n{text}")
    return float(match.group(1)) * 1e6, " ".join(command)


def describe(name, rates, unit):
    median = statistics.median(rates)
    runs = ", ".join(f"{rate / 1e6:.3f}" for rate in rates)
    print(f"{name:40s} median {median / 1e6:7.3f} M {unit}/s  (runs: {runs})")
    return median


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lqmc", type=Path, default=Path("target/release/lqmc"))
    parser.add_argument("--spp", type=int, default=64,
                        help="lqmc mutations (pssmlt) and paths (path) per pixel")
    parser.add_argument("--seconds", type=float, default=10.0,
                        help="LuxCore's render time per run")
    parser.add_argument("--res", type=int, default=256)
    parser.add_argument("--max-depth", type=int, default=6,
                        help="path depth in segments (Mitsuba's convention)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--runs", type=int, default=5)
    args = parser.parse_args()
    if args.res != 256:
        sys.exit("builtin:cornell-box is 256x256; keep --res 256")

    import pyluxcore
    pyluxcore.Init()
    print("LuxCore", pyluxcore.Version(), "load before:", os.getloadavg())
    luxcore_run(pyluxcore, args, 2.0, 1000)  # warm-up
    luxcore_rates, pssmlt_rates, path_rates = [], [], []
    commands = {}
    with tempfile.TemporaryDirectory() as directory:
        output = Path(directory) / "image.exr"
        for run in range(args.runs):
            rate, samples, seconds = luxcore_run(pyluxcore, args, args.seconds, run)
            luxcore_rates.append(rate)
            print(f"run {run}: LuxCore {samples:.0f} mutations in {seconds:.2f} s", flush=True)
            for integrator, rates in (("pssmlt", pssmlt_rates), ("path", path_rates)):
                rate, commands[integrator] = lqmc_run(args, integrator, run, output)
                rates.append(rate)
                print(f"run {run}: lqmc {integrator} {rate / 1e6:.3f} M/s", flush=True)
    for command in commands.values():
        print(f"lqmc command: {command} --seed RUN")
    theirs = describe(f"LuxCore {pyluxcore.Version()} PATHCPU METROPOLIS", luxcore_rates,
                      "mutations")
    ours = describe("lqmc pssmlt (over path)", pssmlt_rates, "mutations")
    describe("lqmc path (independent)", path_rates, "paths")
    print(f"lqmc pssmlt / LuxCore METROPOLIS: {ours / theirs:.2f}x; "
          f"load after: {os.getloadavg()}")
    sys.stdout.flush()
    # pyluxcore's logging can abort at interpreter shutdown: leave directly.
    os._exit(0)


if __name__ == "__main__":
    main()

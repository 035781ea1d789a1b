#!/usr/bin/env python3
"""Equal-time RMSE of LQMC and of path tracing (Halton) against a high-spp
path-traced reference, as a markdown table (issue 5; the LQMC paper's
equal-time comparisons, Sec. 6).

For each scene: render (or reuse) a path-traced reference of many samples
per pixel, cached under --reference-dir; then, for every seed, render LQMC
and path tracing with the same time budget (`--time`), interleaved (LQMC,
path, LQMC, path, ...) so that a change of machine load affects both alike;
compare each with the reference (`lqmc compare --json`) and print the median
RMSE and mean absolute deviation (MAD, the paper's measure for high dynamic
range) over the seeds, with their range, and the commands.

"Path tracing" is the scene's default integrator: `path`, or `volpath` for
scenes with participating media (translucent-spheres); the reference uses
the same. Both use the Halton sampler (the default), randomized by the seed
(a random digital shift per dimension since 2026-12-03), so the renders of
different seeds are independent replications; the reference uses seed 1000.

Runs target/release/lqmc (build it with `cargo build --release`); never run
from cargo test. Example:

    python3 scripts/lqmc/equal_time_rmse.py --reference-dir /tmp/lqmc-references \\
        --time 20 --seeds 3 --threads 1
"""

import argparse
import json
import os
import re
import shlex
import statistics
import subprocess
import sys
import time

DEFAULT_SCENES = ["dof-spheres", "glass-sphere-box", "translucent-spheres"]


def run(command, log):
    """Runs `command` (a list), returns its stdout; exits with its stderr on failure."""
    log.append(" ".join(shlex.quote(part) for part in command))
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"equal_time_rmse: {' '.join(command)} failed:\n{result.stderr}")
    return result.stdout


def samples_per_pixel(render_output):
    match = re.search(r"([0-9.]+) samples per pixel", render_output)
    return float(match.group(1)) if match else float("nan")


def render(binary, scene, output, common, extra, log):
    command = [binary, "render", f"builtin:{scene}", "--quiet", "-o", output] + common + extra
    started = time.monotonic()
    stdout = run(command, log)
    return samples_per_pixel(stdout), time.monotonic() - started


def compare(binary, image, reference, log):
    stdout = run([binary, "compare", image, reference, "--json"], log)
    return json.loads(stdout)


def median_and_range(values):
    return statistics.median(values), min(values), max(values)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", default="target/release/lqmc")
    parser.add_argument("--reference-dir", required=True,
                        help="where references are cached (created if missing)")
    parser.add_argument("--work-dir", default=None,
                        help="where the equal-time renders go (default: REFERENCE_DIR/runs)")
    parser.add_argument("--scenes", default=",".join(DEFAULT_SCENES))
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--reference-threads", type=int, default=0,
                        help="threads for the reference (0: all cores)")
    parser.add_argument("--time", type=float, default=10.0,
                        help="seconds per equal-time render")
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1,
                        help="threads per equal-time render (1: least disturbed by load)")
    parser.add_argument("--resolution", default=None, help="WxH (default: the scene's)")
    parser.add_argument("--lqmc-option", action="append", default=[],
                        help="extra option for the LQMC renders (repeatable), e.g. "
                             "--lqmc-option=--breakup=0")
    arguments = parser.parse_args()

    binary = arguments.binary
    if not os.path.exists(binary):
        sys.exit(f"equal_time_rmse: {binary} not found: run `cargo build --release` first")
    os.makedirs(arguments.reference_dir, exist_ok=True)
    work_dir = arguments.work_dir or os.path.join(arguments.reference_dir, "runs")
    os.makedirs(work_dir, exist_ok=True)
    scenes = [scene for scene in arguments.scenes.split(",") if scene]
    resolution = ["--resolution", arguments.resolution] if arguments.resolution else []
    size_tag = arguments.resolution or "native"

    log = []
    rows = []
    started_at = time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())
    load_at_start = os.getloadavg()
    for scene in scenes:
        reference = os.path.join(
            arguments.reference_dir,
            f"{scene}-{size_tag}-path-{arguments.reference_spp}spp.exr")
        if not os.path.exists(reference):
            print(f"rendering the reference of {scene} ({arguments.reference_spp} spp) ...",
                  file=sys.stderr)
            render(binary, scene, reference,
                   resolution + ["--threads", str(arguments.reference_threads), "--seed", "1000"],
                   ["--spp", str(arguments.reference_spp)], log)
        else:
            log.append(f"# reusing the reference {reference}")
        results = {"lqmc": [], "path": []}
        for seed in range(arguments.seeds):
            for method in ("lqmc", "path"):
                image = os.path.join(work_dir, f"{scene}-{size_tag}-{method}-seed{seed}.exr")
                extra = ["--integrator", "lqmc"] + arguments.lqmc_option if method == "lqmc" else []
                print(f"{scene}: {method}, seed {seed}, {arguments.time} s ...", file=sys.stderr)
                spp, seconds = render(
                    binary, scene, image,
                    resolution + ["--threads", str(arguments.threads), "--seed", str(seed),
                                  "--time", str(arguments.time)],
                    extra, log)
                comparison = compare(binary, image, reference, log)
                results[method].append({
                    "spp": spp,
                    "seconds": seconds,
                    "rmse": comparison["rmse"],
                    "mad": comparison["mean_absolute_deviation"],
                })
        for method, runs in results.items():
            rmse = median_and_range([run["rmse"] for run in runs])
            mad = median_and_range([run["mad"] for run in runs])
            spp = statistics.median(run["spp"] for run in runs)
            rows.append((scene, method, spp, rmse, mad))

    finished_at = time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())
    load_at_end = os.getloadavg()
    options = " ".join(arguments.lqmc_option) or "defaults"
    print(f"Equal time {arguments.time:g} s per render, {arguments.threads} thread(s), "
          f"{arguments.seeds} seeds (LQMC and path tracing interleaved), resolution "
          f"{arguments.resolution or 'of the scene'}; reference: path tracing, "
          f"{arguments.reference_spp} spp, Halton. Median over seeds [min, max]. "
          f"LQMC options: {options}. Measured {started_at} to {finished_at}, load average "
          f"(1/5/15 min) {load_at_start[0]:.1f}/{load_at_start[1]:.1f}/{load_at_start[2]:.1f} "
          f"at the start, {load_at_end[0]:.1f}/{load_at_end[1]:.1f}/{load_at_end[2]:.1f} "
          f"at the end.\n")
    print("| scene | method | spp | RMSE | MAD | RMSE / path's |")
    print("|---|---|---|---|---|---|")
    path_rmse = {scene: rmse[0] for scene, method, _, rmse, _ in rows if method == "path"}
    for scene, method, spp, rmse, mad in rows:
        name = "LQMC" if method == "lqmc" else "path tracing (Halton)"
        ratio = rmse[0] / path_rmse[scene] if path_rmse.get(scene) else float("nan")
        print(f"| {scene} | {name} | {spp:.0f} | {rmse[0]:.4g} [{rmse[1]:.4g}, {rmse[2]:.4g}] "
              f"| {mad[0]:.4g} [{mad[1]:.4g}, {mad[2]:.4g}] | {ratio:.3f} |")
    print("\nCommands:\n")
    print("```sh")
    for line in log:
        print(line)
    print("```")


if __name__ == "__main__":
    main()

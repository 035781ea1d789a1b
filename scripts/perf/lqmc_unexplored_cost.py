#!/usr/bin/env python3
"""What LQMC's seeds cost where little or nothing is explored (issue 34, item 1).

Renders each scene with `path` (`volpath` in media), with LQMC's defaults,
with LQMC exploring nothing (`--skip-class caustic`: every class off, so the
path tracer renders the seeds) and with LQMC's seeds splatted
(`--splat-film`, the film before issue 34), interleaved run by run, and
prints the median render time (the time `lqmc render` prints: scene building
and image writing excluded) and samples per second of each, and each
configuration's time over the path tracer's.

Usage (from the repository root, after `cargo build --release -p lqmc-cli`):

    python3 scripts/perf/lqmc_unexplored_cost.py --runs 5

The results quoted in docs/integrators/lqmc.md were made with the defaults
below on the project's 2-core machine.
"""

import argparse
import re
import statistics
import subprocess
import sys
import tempfile

SCENES = [
    # (scene, path tracer, resolution, spp)
    ("builtin:cornell-box", "path", "256x256", 64),
    ("builtin:glass-sphere-box", "path", "256x192", 64),
    ("builtin:translucent-spheres", "volpath", "192x144", 16),
]

CONFIGURATIONS = [
    ("path tracer", []),
    ("lqmc", ["--integrator", "lqmc"]),
    ("lqmc, nothing explored", ["--integrator", "lqmc", "--skip-class", "caustic"]),
    ("lqmc --splat-film", ["--integrator", "lqmc", "--splat-film"]),
]


def render_seconds(binary, scene, arguments, resolution, spp, threads, output):
    command = [
        binary, "render", scene, "--resolution", resolution, "--spp", str(spp),
        "--threads", str(threads), "--seed", "1", "-o", output,
    ] + arguments
    result = subprocess.run(command, capture_output=True, text=True, check=True)
    match = re.search(r"^time ([0-9.]+) s", result.stdout + result.stderr, re.MULTILINE)
    if not match:
        sys.exit(f"no render time in the output of {' '.join(command)}")
    return float(match.group(1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default="target/release/lqmc")
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--threads", type=int, default=2)
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        output = f"{directory}/image.exr"
        print("| scene | configuration | median render time (s) | M samples/s | ÷ path tracer |")
        print("|---|---|---|---|---|")
        for scene, path_tracer, resolution, spp in SCENES:
            times = {name: [] for name, _ in CONFIGURATIONS}
            for _ in range(options.runs):
                for name, arguments in CONFIGURATIONS:
                    arguments = arguments or ["--integrator", path_tracer]
                    times[name].append(render_seconds(
                        options.binary, scene, arguments, resolution, spp,
                        options.threads, output))
            width, height = map(int, resolution.split("x"))
            samples = width * height * spp
            baseline = statistics.median(times["path tracer"])
            for name, _ in CONFIGURATIONS:
                median = statistics.median(times[name])
                label = path_tracer if name == "path tracer" else name
                print(f"| {scene} {resolution} {spp} spp | {label} | {median:.3f} | "
                      f"{samples / median / 1e6:.2f} | {median / baseline:.2f} |")


if __name__ == "__main__":
    main()

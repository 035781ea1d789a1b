#!/usr/bin/env python3
"""Issue 15: is a one-sided z-test error a bias or a heavier tail?

Renders one of Mitsuba's test scenes K times (independent sampler, seeds
0 .. K-1, `spp` samples per pixel each) with Mitsuba 3 `scalar_spectral`
and/or with lqmc (`target/release/lqmc render ... --sampler independent`),
and applies to every render the per-pixel z-test Mitsuba's `test_renders.py`
uses: image, reference (`refs/*_ref_spectral.exr`) and per-sample variance
(`refs/*_ref_spectral_var.exr`) are converted to CIE XYZ (Mitsuba's
`Bitmap.convert`, linear), the variance is floored at 1e-4, and
z = (image - reference) / sqrt(variance / spp) per pixel and channel.

Printed per renderer (all K renders pooled):

* the number of pixel-channels with |z| > 3.29 (two-sided 0.001), split into
  below (z < -3.29) and above, and the mean z;
* the image mean (all pixels, X+Y+Z) relative to the reference's, the mean
  over the K renders with its standard error (from their spread);
* the per-sample variance estimated across the K renders (K-1 degrees of
  freedom per pixel, times spp) summed over the image, relative to the
  reference's variance image: a much larger ratio for one renderer means a
  heavier tail in its sample distribution;
* the mean per-pixel skewness of the K render values.

Usage (pip install mitsuba==3.9.1 numpy; cargo build --release -p lqmc-cli):

    python3 scripts/reference/one_sided_error.py \
        participating_media/test_homo_area_light_volpath.xml \
        --integrator volpath --renders 16 --spp 64 [--only lqmc|mitsuba]

A scene path is relative to scenes/external/mitsuba-data/tests/scenes.
"""

import argparse
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes/external/mitsuba-data/tests/scenes"


def to_xyz(mi, rgb):
    bitmap = mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32), mi.Bitmap.PixelFormat.RGB)
    return np.array(bitmap.convert(mi.Bitmap.PixelFormat.XYZ, mi.Struct.Type.Float32, False))


def read_rgb(mi, path):
    bitmap = mi.Bitmap(str(path))
    layers = dict(bitmap.split())
    for name in ("<root>", ""):
        if name in layers:
            return np.array(layers[name])[:, :, :3]
    return np.array(bitmap)[:, :, :3]


def reference_files(scene):
    folder = scene.parent / "refs"
    stem = scene.stem
    for suffix in ("_path", "_volpath", "_volpathmis", "_direct", "_ptracer"):
        if stem.endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    return folder / f"{stem}_ref_spectral.exr", folder / f"{stem}_ref_spectral_var.exr"


def mitsuba_samples(mi, scene_path, count):
    """`count` one-sample images (seeds 0 .. count-1), in XYZ."""
    scene = mi.load_file(str(scene_path), spp=1)
    return np.stack([to_xyz(mi, np.array(mi.render(scene, seed=seed, spp=1))[:, :, :3])
                     for seed in range(count)])


def lqmc_samples(mi, scene_path, count, integrator, lqmc, seed_offset, extra):
    """`count` one-sample images of lqmc (seeds seed_offset ..), in XYZ."""
    images = []
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "sample.exr"
        for seed in range(count):
            command = [str(lqmc), "render", str(scene_path), "--sampler", "independent",
                       "--spp", "1", "--seed", str(seed + seed_offset), "--quiet", "-o", str(out)]
            if integrator:
                command += ["--integrator", integrator]
            subprocess.run(command + extra, check=True, stdout=subprocess.DEVNULL)
            images.append(to_xyz(mi, read_rgb(mi, out)))
    return np.stack(images)


def mitsuba_renders(mi, scene_path, renders, spp):
    scene = mi.load_file(str(scene_path), spp=spp)
    return np.stack([to_xyz(mi, np.array(mi.render(scene, seed=1000 + seed, spp=spp))[:, :, :3])
                     for seed in range(renders)])


def lqmc_renders(mi, scene_path, renders, spp, integrator, lqmc, extra):
    images = []
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "render.exr"
        for seed in range(renders):
            command = [str(lqmc), "render", str(scene_path), "--sampler", "independent",
                       "--spp", str(spp), "--seed", str(1000 + seed), "--quiet", "-o", str(out)]
            if integrator:
                command += ["--integrator", integrator]
            subprocess.run(command + extra, check=True, stdout=subprocess.DEVNULL)
            images.append(to_xyz(mi, read_rgb(mi, out)))
    return np.stack(images)


def summarise_means(name, images, reference, variance):
    """K renders of spp samples: the image mean with its error, and the
    z-test of their mean (K spp samples) against the reference."""
    renders = images.shape[0]
    relative = images.sum(axis=(1, 2, 3)) / reference.sum() - 1.0
    error = relative.std(ddof=1) / np.sqrt(renders)
    mean = images.mean(axis=0)
    per_channel = mean.sum(axis=(0, 1)) / reference.sum(axis=(0, 1)) - 1.0
    channel_error = (images.sum(axis=(1, 2)) / reference.sum(axis=(0, 1))).std(axis=0, ddof=1) / np.sqrt(renders)
    # The reference's own error (32768 samples per pixel, pixels independent).
    reference_error = np.sqrt(variance.sum() / 32768) / reference.sum()
    print(f"{name}: image mean {100 * relative.mean():+.3f} +- {100 * error:.3f} % of the reference "
          f"(reference's own error {100 * reference_error:.3f} %); X, Y, Z "
          + ", ".join(f"{100 * v:+.3f} +- {100 * e:.3f} %" for v, e in zip(per_channel, channel_error)))
    return images


def z_summary(z):
    below = int(np.sum(z < -3.29))
    above = int(np.sum(z > 3.29))
    return f"|z| > 3.29 in {below + above} ({below} below, {above} above), mean z {z.mean():+.3f}"


def summarise(name, samples, renders, reference, variance):
    """Splits `samples` (N one-sample XYZ images) into `renders` renders."""
    spp = samples.shape[0] // renders
    samples = samples[: renders * spp].astype(np.float64)
    per_render = samples.reshape(renders, spp, *samples.shape[1:])
    images = per_render.mean(axis=1)  # K x H x W x 3
    reference_samples = 32768  # Mitsuba's references: 32k samples per pixel
    floored = np.maximum(variance, 1e-4)
    # Mitsuba's test_renders.py: the reference's per-sample variance.
    z_reference = (images - reference) / np.sqrt(floored / spp)
    # The renderer's own per-pixel sample variance (as a film reports it),
    # floored likewise, plus the reference's variance of its mean.
    own = np.maximum(per_render.var(axis=1, ddof=1), 1e-4) / spp + variance / reference_samples
    z_own = (images - reference) / np.sqrt(own)
    relative_means = images.sum(axis=(1, 2, 3)) / reference.sum() - 1.0
    total = samples.shape[0]
    overall = samples.mean(axis=0).sum() / reference.sum() - 1.0
    overall_error = samples.sum(axis=(1, 2, 3)).std(ddof=1) / np.sqrt(total) / reference.sum()
    # The per-sample distribution, pooled over all N samples per pixel.
    mean = samples.mean(axis=0)
    centred = samples - mean
    m2 = (centred**2).mean(axis=0)
    m3 = (centred**3).mean(axis=0)
    m4 = (centred**4).mean(axis=0)
    valid = m2 > 1e-8
    skewness = np.median(m3[valid] / m2[valid] ** 1.5)
    kurtosis = np.median(m4[valid] / m2[valid] ** 2)
    variance_ratio = m2.sum() / variance.sum()
    # All N samples as one render, both tests.
    z_all_reference = (mean - reference) / np.sqrt(floored / total)
    own_all = np.maximum(samples.var(axis=0, ddof=1), 1e-4) / total + variance / reference_samples
    z_all_own = (mean - reference) / np.sqrt(own_all)
    print(f"{name}: {renders} x {spp} spp")
    print(f"  Mitsuba's z-test (reference variance): {z_summary(z_reference)}")
    print(f"  z-test with the render's own variance: {z_summary(z_own)}")
    print(f"  all {total} samples as one image: reference variance: {z_summary(z_all_reference)}; "
          f"own variance: {z_summary(z_all_own)}")
    print(f"  image mean {100 * relative_means.mean():+.3f} % of the reference "
          f"({100 * overall:+.3f} +- {100 * overall_error:.3f} % over all {total} samples)")
    print(f"  per-sample variance / reference variance {variance_ratio:.3f}; per pixel "
          f"(median) skewness {skewness:.2f}, kurtosis {kurtosis:.1f}; largest sample "
          f"/ reference {samples.max() / max(reference.max(), 1e-9):.1f} x the reference's largest pixel")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("--integrator", default=None, help="lqmc's --integrator")
    parser.add_argument("--renders", type=int, default=16)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--only", choices=["lqmc", "mitsuba"])
    parser.add_argument("--seed-offset", type=int, default=0, help="lqmc seeds start here")
    parser.add_argument("--lqmc", default=str(REPO / "target/release/lqmc"))
    parser.add_argument("--means", action="store_true",
                        help="K renders of spp samples each: image means only (for many samples)")
    parser.add_argument("--tag", default="", help="names lqmc's cached samples (a build)")
    parser.add_argument("extra", nargs="*", help="more lqmc options (after --)")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant("scalar_spectral")
    scene = SCENES / args.scene
    reference_path, variance_path = reference_files(scene)
    reference = to_xyz(mi, read_rgb(mi, reference_path))
    variance = to_xyz(mi, read_rgb(mi, variance_path))
    print(f"{args.scene}: reference {reference_path.name}, XYZ sums {reference.sum(axis=(0, 1))}")
    if args.means:
        # Many samples: K renders of spp each, image means only.
        if args.only != "lqmc":
            started = time.time()
            images = mitsuba_renders(mi, scene, args.renders, args.spp)
            summarise_means(f"Mitsuba 3.9.1, {args.renders} x {args.spp} spp "
                            f"({time.time() - started:.0f} s)", images, reference, variance)
        if args.only != "mitsuba":
            started = time.time()
            images = lqmc_renders(mi, scene, args.renders, args.spp, args.integrator, args.lqmc,
                                  args.extra)
            summarise_means(f"lqmc, {args.renders} x {args.spp} spp ({time.time() - started:.0f} s)",
                            images, reference, variance)
        return
    count = args.renders * args.spp
    cache = Path(tempfile.gettempdir()) / "one_sided_error"
    cache.mkdir(exist_ok=True)

    def cached(name, make):
        path = cache / f"{name}.npy"
        if path.exists():
            return np.load(path)
        samples = make()
        np.save(path, samples.astype(np.float32))
        return samples

    key = f"{scene.stem}_{count}"
    if args.only != "lqmc":
        started = time.time()
        samples = cached(f"mitsuba_{key}", lambda: mitsuba_samples(mi, scene, count))
        summarise(f"Mitsuba 3.9.1 ({time.time() - started:.0f} s)", samples, args.renders,
                  reference, variance)
    if args.only != "mitsuba":
        started = time.time()
        samples = cached(f"lqmc_{key}_{args.seed_offset}_{'_'.join(args.extra)}{args.tag}",
                         lambda: lqmc_samples(mi, scene, count, args.integrator, args.lqmc,
                                              args.seed_offset, args.extra))
        summarise(f"lqmc ({time.time() - started:.0f} s)", samples, args.renders, reference,
                  variance)


if __name__ == "__main__":
    main()

//! End-to-end tests of `lqmc render` and `lqmc scenes`.

#[path = "../../render/tests/support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use std::process::{Command, Output};

fn lqmc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lqmc"))
        .args(args)
        .output()
        .expect("the lqmc binary runs")
}

/// A fresh directory for this test's files, removed when dropped.
fn temporary_directory(name: &str) -> ScratchDirectory {
    ScratchDirectory::new(name)
}

#[test]
fn scenes_lists_every_builtin() {
    let output = lqmc(&["scenes"]);
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).unwrap();
    for name in [
        "cornell-box",
        "dof-spheres",
        "glass-sphere-box",
        "office",
        "furnace",
    ] {
        assert!(text.contains(&format!("builtin:{name}")), "{name} missing");
    }
}

#[test]
fn render_writes_exr_and_png_with_metadata_and_reports_rates() {
    let directory = temporary_directory("render");
    let exr = directory.join("furnace.exr");
    let output = lqmc(&[
        "render",
        "builtin:furnace",
        "--resolution",
        "8x8",
        "--spp",
        "4",
        "--sampler",
        "sobol",
        "--seed",
        "5",
        "--rr-depth",
        "5",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let text = String::from_utf8(output.stdout).unwrap();
    for expected in [
        "samples/s",
        "rays/s",
        "NaN/Inf samples dropped",
        "4.0 samples per pixel",
        "peak resident memory",
    ] {
        assert!(text.contains(expected), "'{expected}' missing in {text}");
    }
    let contents = render::image::read_exr(&exr).unwrap();
    assert_eq!((contents.image.width(), contents.image.height()), (8, 8));
    assert_eq!(
        contents.metadata.get("sampler").map(String::as_str),
        Some("sobol")
    );
    assert_eq!(contents.metadata.get("spp").map(String::as_str), Some("4"));
    assert_eq!(contents.metadata.get("seed").map(String::as_str), Some("5"));
    assert_eq!(
        contents.metadata.get("randomization").map(String::as_str),
        Some("seeded")
    );
    assert_eq!(
        contents.metadata.get("integrator").map(String::as_str),
        Some("path")
    );
    assert!(contents.metadata.contains_key("renderTimeSeconds"));
    // The peak resident memory of the render, in bytes: at least the film.
    let peak: u64 = contents.metadata["peakResidentBytes"].parse().unwrap();
    assert!(peak > 1 << 20, "{peak}");
    assert_eq!(
        contents.metadata.get("rrDepth").map(String::as_str),
        Some("5")
    );
    // The furnace is 1 everywhere; 64 pixels × 4 samples average close to it.
    let mean = contents.image.mean();
    assert!(mean.iter().all(|&m| (m - 1.0).abs() < 0.1), "{mean:?}");
    assert!(directory.join("furnace.png").exists());
}

#[test]
fn time_budget_stops_and_still_writes() {
    let directory = temporary_directory("time");
    let pfm = directory.join("box.pfm");
    let output = lqmc(&[
        "render",
        "builtin:cornell-box",
        "--resolution",
        "16x16",
        "--time",
        "0.3",
        "-o",
        pfm.to_str().unwrap(),
    ]);
    assert!(output.status.success());
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(text.contains("time budget reached"), "{text}");
    assert!(render::image::read_pfm(&pfm).is_ok());
}

/// BDPT renders a scene with participating media from the CLI (volumetric
/// BDPT), writing an image without NaN/Inf samples.
#[test]
fn bdpt_renders_media() {
    let directory = temporary_directory("bdpt_media");
    let pfm = directory.join("spheres.pfm");
    let output = lqmc(&[
        "render",
        "builtin:translucent-spheres",
        "--integrator",
        "bdpt",
        "--spp",
        "4",
        "--resolution",
        "16x12",
        "-o",
        pfm.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{output:?}");
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(text.contains("0 NaN/Inf samples dropped"), "{text}");
    let image = render::image::read_pfm(&pfm).unwrap();
    assert!(image.pixels().iter().flatten().any(|&value| value > 0.0));
}

/// PSSMLT from the CLI, over path tracing and BDPT (media included), and
/// MMLT: mutations per pixel, the chains' report and no NaN/Inf.
#[test]
fn pssmlt_and_mmlt_render_and_report_their_chains() {
    let directory = temporary_directory("pssmlt");
    for (scene, integrator, base) in [
        ("builtin:cornell-box", "pssmlt", Some("path")),
        ("builtin:translucent-spheres", "pssmlt", Some("bdpt")),
        ("builtin:cornell-box", "mmlt", None),
    ] {
        let pfm = directory.join(format!("{integrator}-{}.pfm", base.unwrap_or("")));
        let mut args = vec!["render", scene, "--integrator", integrator];
        if let Some(base) = base {
            args.extend(["--mlt-base", base]);
        }
        args.extend([
            "--mlt-kernel",
            "gaussian",
            "--mlt-sigma",
            "0.02",
            "--mlt-bootstrap",
            "5000",
            "--mlt-chains",
            "64",
            "--spp",
            "4",
            "--resolution",
            "16x12",
            "-o",
            pfm.to_str().unwrap(),
        ]);
        let output = lqmc(&args);
        assert!(output.status.success(), "{output:?}");
        let text = String::from_utf8(output.stdout).unwrap();
        assert!(
            text.contains(&format!("with {integrator}: 4 mutations per pixel")),
            "{text}"
        );
        assert!(text.contains("0 NaN/Inf samples dropped"), "{text}");
        assert!(text.contains(" chains, normalisation b = "), "{text}");
        assert!(text.contains("bootstrap samples"), "{text}");
        assert!(text.contains("M mutations/s"), "{text}");
        assert!(text.contains("acceptance: large steps"), "{text}");
        let image = render::image::read_pfm(&pfm).unwrap();
        assert!(image.pixels().iter().flatten().any(|&value| value > 0.0));
    }
}

/// ERPT from the CLI with QMC seeds and per-dimension steps: the chains'
/// report and no NaN/Inf.
#[test]
fn erpt_renders_and_reports_its_chains() {
    let directory = temporary_directory("erpt");
    let pfm = directory.join("erpt.pfm");
    let output = lqmc(&[
        "render",
        "builtin:cornell-box",
        "--integrator",
        "erpt",
        "--sampler",
        "sobol",
        "--erpt-chain-length",
        "20",
        "--erpt-chains-per-sample",
        "2",
        "--mlt-step-scale",
        "0=4,1=4",
        "--mlt-bootstrap",
        "5000",
        "--spp",
        "2",
        "--resolution",
        "16x12",
        "-o",
        pfm.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{output:?}");
    let text = String::from_utf8(output.stdout).unwrap();
    assert!(
        text.contains("with erpt / sobol: 2.0 samples per pixel"),
        "{text}"
    );
    assert!(text.contains("0 NaN/Inf samples dropped"), "{text}");
    assert!(text.contains("erpt: Markov chains:"), "{text}");
    assert!(text.contains("5000 bootstrap samples"), "{text}");
    let image = render::image::read_pfm(&pfm).unwrap();
    assert!(image.pixels().iter().flatten().any(|&value| value > 0.0));
}

/// VCM from the CLI in every mode: iterations and merges reported, no
/// NaN/Inf, and the peak memory.
#[test]
fn vcm_renders_and_reports_its_merges() {
    let directory = temporary_directory("vcm");
    for mode in ["vcm", "bpt", "bpm", "ppm"] {
        let pfm = directory.join(format!("{mode}.pfm"));
        let output = lqmc(&[
            "render",
            "builtin:cornell-box",
            "--integrator",
            "vcm",
            "--vcm-mode",
            mode,
            "--vcm-radius",
            "0.02",
            "--spp",
            "3",
            "--resolution",
            "16x12",
            "-o",
            pfm.to_str().unwrap(),
        ]);
        assert!(output.status.success(), "{output:?}");
        let text = String::from_utf8(output.stdout).unwrap();
        assert!(
            text.contains("with vcm / halton: 3.0 samples per pixel"),
            "{text}"
        );
        assert!(text.contains("0 NaN/Inf samples dropped"), "{text}");
        assert!(
            text.contains(&format!("vcm ({mode}): 3 iterations")),
            "{text}"
        );
        assert!(text.contains("M merges/s"), "{text}");
        assert!(text.contains("peak resident memory"), "{text}");
        let image = render::image::read_pfm(&pfm).unwrap();
        assert!(image.pixels().iter().flatten().any(|&value| value > 0.0));
    }
}

#[test]
fn bad_render_input_is_one_line_and_status_two() {
    let cases: &[&[&str]] = &[
        &["render", "builtin:teapot"],
        &["render", "no-such-file.xml"],
        &["render", "builtin:furnace", "--spp", "0"],
        &["render", "builtin:furnace", "--resolution", "0x4"],
        &["render", "builtin:furnace", "--time", "-1"],
        &["render", "builtin:furnace", "--max-depth", "0"],
        &["render", "builtin:furnace", "-o", "image.txt"],
        &["render", "builtin:furnace", "--sampler", "zsobol"],
        &["render", "builtin:furnace", "--randomize", "sometimes"],
        &["render", "builtin:furnace", "--integrator", "sppm"],
        &["render", "builtin:furnace", "--vcm-radius", "0.01"],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "vcm",
            "--vcm-mode",
            "sppm",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "vcm",
            "--vcm-radius",
            "0",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "vcm",
            "--vcm-alpha",
            "1.5",
        ],
        &[
            "render",
            "builtin:furnace",
            "--strategy-images",
            "strategies",
        ],
        &["render", "builtin:furnace", "--bdpt-skip-eye-connections"],
        &["render", "builtin:furnace", "--mlt-base", "bdpt"],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "pssmlt",
            "--mlt-base",
            "vcm",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "pssmlt",
            "--mlt-large-step",
            "1.5",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "pssmlt",
            "--mlt-kernel",
            "cauchy",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "pssmlt",
            "--mlt-sigma",
            "0.1",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "pssmlt",
            "--mlt-chains",
            "0",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "pssmlt",
            "--erpt-chain-length",
            "5",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "erpt",
            "--mlt-base",
            "bdpt",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "erpt",
            "--erpt-chain-length",
            "0",
        ],
        &[
            "render",
            "builtin:furnace",
            "--integrator",
            "erpt",
            "--mlt-step-scale",
            "0:4",
        ],
    ];
    for args in cases {
        let output = lqmc(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("lqmc: "), "{args:?}: {stderr}");
    }
}

/// `--randomize none` keeps Halton's points whatever the seed (paths of at
/// most 6 segments use far fewer than the 256 Halton dimensions, so the
/// images are identical); the default makes the seed change the image.
#[test]
fn randomize_none_ignores_the_seed_and_seeded_does_not() {
    let directory = temporary_directory("randomize");
    let render_with = |name: &str, seed: &str, randomize: &str| {
        let exr = directory.join(name);
        let output = lqmc(&[
            "render",
            "builtin:cornell-box",
            "--resolution",
            "8x8",
            "--spp",
            "2",
            "--seed",
            seed,
            "--randomize",
            randomize,
            "--quiet",
            "-o",
            exr.to_str().unwrap(),
        ]);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        render::image::read_exr(&exr).unwrap()
    };
    let first = render_with("none-1.exr", "1", "none");
    let second = render_with("none-2.exr", "2", "none");
    assert_eq!(
        first.metadata.get("randomization").map(String::as_str),
        Some("none")
    );
    assert_eq!(first.image, second.image);
    let seeded_first = render_with("seeded-1.exr", "1", "seeded");
    let seeded_second = render_with("seeded-2.exr", "2", "seeded");
    assert_ne!(seeded_first.image, seeded_second.image);
}

/// `--integrator bdpt --strategy-images DIR` writes one EXR per strategy
/// next to the image.
#[test]
fn bdpt_writes_strategy_images() {
    let directory = temporary_directory("bdpt-strategies");
    let exr = directory.join("bdpt.exr");
    let strategies = directory.join("strategies");
    let output = lqmc(&[
        "render",
        "builtin:cornell-box",
        "--integrator",
        "bdpt",
        "--resolution",
        "16x16",
        "--spp",
        "2",
        "--max-depth",
        "3",
        "--quiet",
        "--strategy-images",
        strategies.to_str().unwrap(),
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // Depth 3: s + t − 1 ≤ 3, (1, 1) left to (0, 2).
    for name in [
        "s0_t2", "s0_t3", "s0_t4", "s1_t2", "s1_t3", "s2_t1", "s2_t2", "s3_t1",
    ] {
        assert!(
            strategies.join(format!("{name}.exr")).exists(),
            "{name}.exr missing"
        );
    }
    assert!(!strategies.join("s1_t1.exr").exists());
    assert!(exr.exists());
}

/// `lqmc render` of the Cornell box at 8x8 into `exr`, with `extra`.
fn render_small_cornell_box(exr: &std::path::Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        "builtin:cornell-box",
        "--resolution",
        "8x8",
        "-o",
        exr.to_str().unwrap(),
    ];
    args.extend(extra);
    lqmc(&args)
}

/// `--quiet` prints nothing at all on success, for one render and for a
/// render of replications (the loader's warnings and the report included).
#[test]
fn quiet_renders_print_nothing() {
    let directory = temporary_directory("quiet");
    let exr = directory.join("quiet.exr");
    for extra in [&[][..], &["--replications", "2"][..]] {
        let output = render_small_cornell_box(&exr, &[&["--spp", "2", "--quiet"], extra].concat());
        assert!(output.status.success(), "{extra:?}: {output:?}");
        assert!(output.stdout.is_empty(), "{extra:?}: {output:?}");
        assert!(output.stderr.is_empty(), "{extra:?}: {output:?}");
    }
}

/// The error line of one render says what it measured, or nothing when the
/// render has no estimate (one sample per pixel, no batches); no line of a
/// successful render is labelled an error.
#[test]
fn the_error_line_says_what_it_measured_or_nothing() {
    let directory = temporary_directory("error_line");
    let exr = directory.join("image.exr");
    let render_text = |extra: &[&str]| {
        let output = render_small_cornell_box(&exr, extra);
        assert!(output.status.success(), "{extra:?}: {output:?}");
        let text = String::from_utf8(output.stdout).unwrap();
        assert!(
            text.lines()
                .all(|line| !line.to_lowercase().starts_with("error")),
            "{extra:?}: {text}"
        );
        text
    };
    let one_sample = render_text(&["--spp", "1"]);
    assert!(!one_sample.contains("per pixel 0.00 %"), "{one_sample}");
    assert!(!one_sample.contains("relative"), "{one_sample}");
    let samples = render_text(&["--spp", "4", "--sampler", "independent"]);
    assert!(
        samples.contains("expected relative RMSE per pixel"),
        "{samples}"
    );
    assert!(!samples.contains("image mean"), "{samples}");
    let passes = render_text(&[
        "--spp",
        "4",
        "--integrator",
        "light",
        "--sampler",
        "independent",
    ]);
    assert!(
        passes.contains("relative standard error of the image mean")
            && passes.contains("(from 4 independent passes)"),
        "{passes}"
    );
    let replications = render_text(&["--spp", "4", "--replications", "2"]);
    assert!(
        replications.contains("relative standard error of the image mean"),
        "{replications}"
    );
}

/// `lqmc --help` names every command in its about text.
#[test]
fn help_names_every_command() {
    let output = lqmc(&["--help"]);
    assert!(output.status.success());
    let help = String::from_utf8(output.stdout).unwrap();
    // clap wraps at 100 columns without a terminal: the about text is the
    // first paragraph, and a command's own line is indented by two spaces
    // (its wrapped description by more).
    let about = help
        .lines()
        .take_while(|line| !line.trim().is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    let commands: Vec<&str> = help
        .lines()
        .skip_while(|line| !line.starts_with("Commands:"))
        .skip(1)
        .take_while(|line| line.starts_with("  "))
        .filter(|line| !line.starts_with("   "))
        .filter_map(|line| line.split_whitespace().next())
        .filter(|name| *name != "help")
        .collect();
    for command in [
        "render", "merge", "scenes", "compare", "points", "lattice", "study",
    ] {
        assert!(commands.contains(&command), "{command} not listed: {help}");
    }
    for command in &commands {
        assert!(about.contains(command), "{command} not in '{about}'");
    }
}

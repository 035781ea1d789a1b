//! Options belong to their integrators: every integrator-specific option of
//! `lqmc render`, given with each integrator that does not read it, exits
//! with status 2 and one line naming the option, that integrator and the
//! ones that read it (checked before the scene is loaded, so these runs are
//! fast); given with one that reads it, it renders.

#[path = "../../render/tests/support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use std::process::{Command, Output};

const INTEGRATORS: [&str; 9] = [
    "path", "volpath", "lqmc", "light", "bdpt", "pssmlt", "erpt", "mmlt", "vcm",
];
const LQMC: &[&str] = &["lqmc"];
const BDPT: &[&str] = &["bdpt"];
const VCM: &[&str] = &["vcm"];
const METROPOLIS: &[&str] = &["pssmlt", "erpt", "mmlt"];
/// Every integrator but mmlt, whose chains draw every number of their own.
const SAMPLER_USERS: &[&str] = &[
    "path", "volpath", "lqmc", "light", "bdpt", "pssmlt", "erpt", "vcm",
];
/// Few bootstrap samples, for fast Metropolis renders.
const SHORT_BOOTSTRAP: &[&str] = &["--mlt-bootstrap", "64"];

/// An integrator-specific option: its arguments, the integrators that read
/// it, and further arguments a render with the first reader needs.
struct Case {
    arguments: &'static [&'static str],
    readers: &'static [&'static str],
    render_with: &'static [&'static str],
}

const fn case(
    arguments: &'static [&'static str],
    readers: &'static [&'static str],
    render_with: &'static [&'static str],
) -> Case {
    Case {
        arguments,
        readers,
        render_with,
    }
}

/// Every integrator-specific option of `lqmc render`
/// ([`every_integrator_option_of_the_help_is_a_case`] keeps it complete).
const CASES: &[Case] = &[
    case(
        &["--mis", "power"],
        &["path", "lqmc", "bdpt", "pssmlt", "erpt", "mmlt", "vcm"],
        &[],
    ),
    case(
        &["--pattern-size", "1"],
        &["path", "volpath", "lqmc", "light", "bdpt", "erpt", "vcm"],
        &["--sampler", "independent"],
    ),
    case(&["--splat-film"], &["path", "volpath", "lqmc"], &[]),
    case(&["--sampler", "independent"], SAMPLER_USERS, &[]),
    case(&["--randomize", "none"], SAMPLER_USERS, &[]),
    case(&["--explore", "aperture,image"], LQMC, &[]),
    case(&["--breakup", "2"], LQMC, &[]),
    case(&["--lattice-size", "normal=23"], LQMC, &[]),
    case(&["--aperture-tiles", "caustic=4"], LQMC, &[]),
    case(&["--image-tiles", "normal=24"], LQMC, &[]),
    case(&["--direction-tiles", "normal=8"], LQMC, &[]),
    case(&["--wavelength-tiles", "2"], LQMC, &[]),
    case(&["--time-tiles", "2"], LQMC, &[]),
    case(&["--medium-image-tiles", "6"], LQMC, &[]),
    case(&["--skip-class", "caustic"], LQMC, &[]),
    case(&["--explore-class", "normal"], LQMC, &[]),
    case(&["--explore-wavelength-alone"], LQMC, &[]),
    case(&["--explore-camera-in-focus"], LQMC, &[]),
    case(&["--no-jitter"], LQMC, &[]),
    case(&["--lattice-scramble", "all"], LQMC, &[]),
    case(&["--class-selection", "fixed"], LQMC, &[]),
    case(&["--stats"], LQMC, &[]),
    case(&["--density", "DIR/density.exr"], LQMC, &[]),
    case(&["--bdpt-skip-eye-connections"], BDPT, &[]),
    case(&["--strategy-images", "DIR/strategies"], BDPT, &[]),
    case(&["--mlt-base", "bdpt"], &["pssmlt"], SHORT_BOOTSTRAP),
    case(&["--mlt-direct-spp", "1"], &["pssmlt"], SHORT_BOOTSTRAP),
    case(&["--mlt-large-step", "0.5"], METROPOLIS, SHORT_BOOTSTRAP),
    case(&["--mlt-kernel", "gaussian"], METROPOLIS, SHORT_BOOTSTRAP),
    case(
        &["--mlt-sigma", "0.02"],
        METROPOLIS,
        &["--mlt-kernel", "gaussian", "--mlt-bootstrap", "64"],
    ),
    case(&["--mlt-bootstrap", "64"], METROPOLIS, &[]),
    case(
        &["--mlt-step-scale", "0=2,1=2"],
        METROPOLIS,
        SHORT_BOOTSTRAP,
    ),
    case(&["--mlt-chains", "4"], &["pssmlt", "mmlt"], SHORT_BOOTSTRAP),
    case(&["--erpt-chain-length", "10"], &["erpt"], SHORT_BOOTSTRAP),
    case(
        &["--erpt-chains-per-sample", "2"],
        &["erpt"],
        SHORT_BOOTSTRAP,
    ),
    case(&["--vcm-mode", "bpt"], VCM, &[]),
    case(&["--vcm-radius", "0.01"], VCM, &[]),
    case(&["--vcm-alpha", "0.5"], VCM, &[]),
];

fn lqmc(args: &[String]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lqmc"))
        .args(args)
        .output()
        .expect("the lqmc binary runs")
}

/// `lqmc render` of a tiny Cornell box with `integrator` and `extra`
/// (`DIR` in them replaced by `directory`).
fn render_arguments(directory: &ScratchDirectory, integrator: &str, extra: &[&str]) -> Vec<String> {
    let directory = directory.to_str().unwrap();
    let mut args: Vec<String> = [
        "render",
        "builtin:cornell-box",
        "--integrator",
        integrator,
        "--resolution",
        "4x4",
        "--spp",
        "1",
        "--threads",
        "1",
        "--quiet",
        "-o",
        &format!("{directory}/{integrator}.exr"),
    ]
    .iter()
    .map(|arg| arg.to_string())
    .collect();
    args.extend(extra.iter().map(|arg| arg.replace("DIR", directory)));
    args
}

/// `--name`, the option of a case.
fn option(case: &Case) -> &'static str {
    case.arguments[0]
}

#[test]
fn an_option_given_to_an_integrator_that_does_not_read_it_exits_2_naming_both() {
    let directory = ScratchDirectory::new("option_ownership_refused");
    let runs: Vec<(&Case, &str)> = CASES
        .iter()
        .flat_map(|case| {
            INTEGRATORS
                .iter()
                .filter(|integrator| !case.readers.contains(integrator))
                .map(move |integrator| (case, *integrator))
        })
        .collect();
    std::thread::scope(|scope| {
        for chunk in runs.chunks(runs.len().div_ceil(4)) {
            let directory = &directory;
            scope.spawn(move || {
                for (case, integrator) in chunk {
                    let output = lqmc(&render_arguments(directory, integrator, case.arguments));
                    let stderr = String::from_utf8_lossy(&output.stderr);
                    let what = format!("{} with {integrator}", option(case));
                    assert_eq!(output.status.code(), Some(2), "{what}: {stderr}");
                    assert_eq!(stderr.lines().count(), 1, "{what}: {stderr}");
                    assert!(stderr.starts_with("lqmc: "), "{what}: {stderr}");
                    assert!(
                        stderr.contains(&format!("{} is an option of", option(case))),
                        "{what}: {stderr}"
                    );
                    assert!(
                        stderr.contains(&format!("not of {integrator}")),
                        "{what}: {stderr}"
                    );
                    for reader in case.readers {
                        assert!(stderr.contains(reader), "{what}: {reader} in {stderr}");
                    }
                    assert!(output.stdout.is_empty(), "{what}");
                }
            });
        }
    });
    assert!(!directory.join("strategies").exists());
}

#[test]
fn an_option_given_to_an_integrator_that_reads_it_renders() {
    let directory = ScratchDirectory::new("option_ownership_accepted");
    for case in CASES {
        let reader = case.readers[0];
        let extra = [case.arguments, case.render_with].concat();
        let output = lqmc(&render_arguments(&directory, reader, &extra));
        assert!(
            output.status.success(),
            "{} with {reader}: {}",
            option(case),
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

/// Without `--integrator` the rule applies to the integrator the scene
/// renders with: path for the Cornell box, volpath in a scene with media.
#[test]
fn the_rule_applies_to_the_integrator_chosen_for_the_scene() {
    for (scene, extra, chosen) in [
        ("builtin:cornell-box", ["--breakup", "2"], "path"),
        (
            "builtin:translucent-spheres",
            ["--mis", "balance"],
            "volpath",
        ),
    ] {
        let mut args: Vec<String> = ["render", scene, "--spp", "1"]
            .iter()
            .map(|arg| arg.to_string())
            .collect();
        args.extend(extra.iter().map(|arg| arg.to_string()));
        let output = lqmc(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.contains(&format!("{} is an option of", extra[0]))
                && stderr.contains(&format!("not of {chosen} (the integrator this scene")),
            "{stderr}"
        );
    }
}

/// Options read only under a condition: pssmlt reads the sampler only for
/// its direct-light pass, and the volume walks of lqmc, erpt and pssmlt
/// over paths weigh by the balance heuristic in scenes with media.
#[test]
fn options_read_only_under_a_condition_are_refused_where_it_fails() {
    let directory = ScratchDirectory::new("option_ownership_conditional");
    let refused: &[(&str, &[&str], &str)] = &[
        (
            "pssmlt",
            &["--sampler", "sobol"],
            "--sampler is read by pssmlt only for its direct-light pass",
        ),
        (
            "pssmlt",
            &["--randomize", "none"],
            "--randomize is read by pssmlt only for its direct-light pass",
        ),
    ];
    let in_media: &[(&str, &[&str])] = &[
        ("lqmc", &[]),
        ("erpt", SHORT_BOOTSTRAP),
        ("pssmlt", SHORT_BOOTSTRAP),
    ];
    let mut runs: Vec<(Vec<String>, String)> = refused
        .iter()
        .map(|(integrator, extra, message)| {
            (
                render_arguments(&directory, integrator, extra),
                message.to_string(),
            )
        })
        .collect();
    for (integrator, extra) in in_media {
        let mut args = render_arguments(
            &directory,
            integrator,
            &[[*extra, &["--mis", "power"]].concat()].concat(),
        );
        args[1] = "builtin:translucent-spheres".into();
        runs.push((
            args,
            format!("--mis does not apply to {integrator} in a scene with participating media"),
        ));
    }
    for (args, message) in runs {
        let output = lqmc(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(&message), "{args:?}: {stderr}");
    }
    // Where the condition holds, they render.
    let accepted: &[(&str, &[&str])] = &[
        (
            "pssmlt",
            &[
                "--sampler",
                "sobol",
                "--mlt-direct-spp",
                "1",
                "--mlt-bootstrap",
                "64",
            ],
        ),
        (
            "pssmlt",
            &[
                "--mis",
                "power",
                "--mlt-base",
                "bdpt",
                "--mlt-bootstrap",
                "64",
            ],
        ),
        ("mmlt", &["--mis", "power", "--mlt-bootstrap", "64"]),
    ];
    for (integrator, extra) in accepted {
        let mut args = render_arguments(&directory, integrator, extra);
        if extra.contains(&"--mis") {
            args[1] = "builtin:translucent-spheres".into();
        }
        let output = lqmc(&args);
        assert!(
            output.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
    }
}

/// The table above covers every option under an integrator's heading in
/// `lqmc render --help`.
#[test]
fn every_integrator_option_of_the_help_is_a_case() {
    let output = lqmc(&["render".to_string(), "-h".to_string()]);
    assert!(output.status.success());
    let help = String::from_utf8(output.stdout).unwrap();
    let mut heading = "";
    let mut checked = 0;
    for line in help.lines() {
        if !line.starts_with(' ') && line.ends_with(':') {
            heading = line;
            continue;
        }
        let integrator_heading = ["LQMC", "BDPT", "Metropolis", "VCM", "Path tracer"]
            .iter()
            .any(|name| heading.starts_with(name));
        // An option's own line starts with it, indented by a few spaces;
        // wrapped help text (clap wraps at 100 columns without a terminal)
        // is indented to the description column and may name options too.
        let indentation = line.len() - line.trim_start().len();
        if indentation > 8 || !line.trim_start().starts_with('-') {
            continue;
        }
        let Some(long) = line.split_whitespace().find(|word| word.starts_with("--")) else {
            continue;
        };
        let shared_but_owned = ["--mis", "--pattern-size", "--sampler", "--randomize"];
        if integrator_heading || shared_but_owned.contains(&long) {
            assert!(
                CASES.iter().any(|case| option(case) == long),
                "{long} (under {heading}) has no case"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, CASES.len(), "{help}");
}

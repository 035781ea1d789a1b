//! End-to-end tests of `lqmc points` and `lqmc lattice`: output formats,
//! values against the library and external references, and bad input.

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

fn stdout(output: &Output) -> String {
    assert!(
        output.status.success(),
        "lqmc failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout.clone()).unwrap()
}

/// Parses CSV lines of numbers.
fn parse_points(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter(|line| !line.starts_with('#'))
        .map(|line| line.split(',').map(|v| v.parse().unwrap()).collect())
        .collect()
}

#[test]
fn halton_prints_round_trip_csv() {
    let output = stdout(&lqmc(&["points", "halton", "--count", "4", "--dims", "3"]));
    let points = parse_points(&output);
    assert_eq!(points.len(), 4);
    assert_eq!(points[1], vec![0.5, 1.0 / 3.0, 0.2]);
    assert_eq!(points[3], vec![0.75, 1.0 / 9.0, 0.6]);
}

#[test]
fn start_offsets_the_indices() {
    let all = parse_points(&stdout(&lqmc(&[
        "points", "sobol", "--count", "8", "--dims", "4",
    ])));
    let tail = parse_points(&stdout(&lqmc(&[
        "points", "sobol", "--count", "3", "--dims", "4", "--start", "5",
    ])));
    assert_eq!(&all[5..], &tail[..]);
}

#[test]
fn json_has_the_documented_fields() {
    let output = stdout(&lqmc(&[
        "points",
        "hammersley",
        "--count",
        "4",
        "--dims",
        "2",
        "--json",
        "--discrepancy",
    ]));
    let line = output.trim();
    assert!(line.starts_with(
        r#"{"sequence":"hammersley","dims":2,"indices":[0,1,2,3],"points":[[0.0,0.0],[0.25,0.5],"#
    ));
    for key in ["l2_star", "centered", "wrap_around", "mixture"] {
        assert!(
            line.contains(&format!("\"{key}\":")),
            "{key} missing in {line}"
        );
    }
}

#[test]
fn single_point_discrepancy_matches_closed_form() {
    // The first Halton point is the origin. Warnock's formula for one point x
    // gives D² = 3^−d − 2·Π_j (1 − x_j²)/2 + Π_j (1 − x_j), so for x = 0 in
    // d = 3 dimensions D² = 3^−3 − 2^−2 + 1.
    let output = stdout(&lqmc(&[
        "points",
        "halton",
        "--count",
        "1",
        "--dims",
        "3",
        "--discrepancy",
    ]));
    let value: f64 = output
        .lines()
        .find_map(|line| line.strip_prefix("# l2_star: "))
        .unwrap()
        .parse()
        .unwrap();
    let expected = (1.0 - 2f64.powi(-2) + 3f64.powi(-3)).sqrt();
    assert!((value - expected).abs() < 1e-12, "{value} vs {expected}");
}

#[test]
fn pixel_samples_fall_in_their_pixel() {
    let output = stdout(&lqmc(&[
        "points",
        "halton",
        "--count",
        "5",
        "--dims",
        "3",
        "--scramble",
        "faure",
        "--pixel",
        "5,2",
        "--resolution",
        "17,7",
    ]));
    for point in parse_points(&output) {
        assert_eq!((point[0].floor(), point[1].floor()), (5.0, 2.0));
        assert!((0.0..1.0).contains(&point[2]));
    }
}

#[test]
fn lattice_json_reports_generator_and_error() {
    let output = stdout(&lqmc(&[
        "lattice", "--points", "7", "--dims", "1", "--json",
    ]));
    // In one dimension e² = π²/(3 N²) with γ = 1 (here γ = 1/S = 1).
    let e2 = std::f64::consts::PI.powi(2) / (3.0 * 49.0);
    let line = output.trim();
    assert!(
        line.starts_with(r#"{"points":7,"dims":1,"generator":[1],"e2":"#),
        "{line}"
    );
    let value: f64 = line
        .rsplit_once(':')
        .unwrap()
        .1
        .trim_end_matches('}')
        .parse()
        .unwrap();
    assert!((value - e2).abs() < 1e-12);
}

#[test]
fn lattice_points_match_lattice_command() {
    let generator_line = stdout(&lqmc(&["lattice", "--points", "23", "--dims", "3"]));
    let generator: Vec<u64> = generator_line
        .lines()
        .find_map(|line| line.strip_prefix("generator: "))
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    let points = parse_points(&stdout(&lqmc(&[
        "points", "lattice", "--count", "23", "--dims", "3",
    ])));
    for (i, point) in points.iter().enumerate() {
        for (j, &value) in point.iter().enumerate() {
            let expected = ((i as u64 * generator[j]) % 23) as f64 / 23.0;
            assert_eq!(value, expected);
        }
    }
}

#[test]
fn plot_writes_an_svg() {
    let directory = ScratchDirectory::new("plot");
    let path = directory.join("points.svg");
    let path_text = path.to_str().unwrap();
    stdout(&lqmc(&[
        "points",
        "sobol",
        "--count",
        "64",
        "--scramble",
        "owen",
        "--plot",
        path_text,
    ]));
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.starts_with("<svg"));
    assert!(svg.contains("local exploration"));
}

/// Bad input: one line on stderr and exit status 2.
#[test]
fn bad_input_is_one_line_and_status_two() {
    let cases: &[&[&str]] = &[
        &["points", "sobolev", "--count", "3"],
        &["points", "halton", "--count", "0"],
        &["points", "halton", "--count", "3", "--dims", "0"],
        &["points", "halton", "--count", "3", "--dims", "5000"],
        &["points", "sobol", "--count", "3", "--dims", "30000"],
        &["points", "niederreiter", "--count", "3", "--dims", "1000"],
        &["points", "sobol", "--count", "3", "--start", "4294967295"],
        &["points", "halton", "--count", "3", "--scramble", "xor"],
        &["points", "lattice", "--count", "1"],
        &["points", "hammersley", "--count", "8", "--size", "4"],
        &[
            "points",
            "sobol",
            "--count",
            "3",
            "--pixel",
            "1,1",
            "--resolution",
            "4,4",
        ],
        &[
            "points",
            "halton",
            "--count",
            "3",
            "--pixel",
            "9,1",
            "--resolution",
            "4,4",
        ],
        &["points", "halton", "--count", "3", "--pixel", "1"],
        &["lattice", "--points", "1", "--dims", "3"],
        &["lattice", "--points", "7", "--dims", "0"],
        &[
            "lattice",
            "--points",
            "7",
            "--dims",
            "3",
            "--weights",
            "1,2",
        ],
        &["lattice", "--points", "7", "--dims", "2", "--weights", "-1"],
        &["frobnicate"],
    ];
    for args in cases {
        let output = lqmc(args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("lqmc: "), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

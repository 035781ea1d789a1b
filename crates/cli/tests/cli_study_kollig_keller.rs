//! End-to-end test of `lqmc study kollig-keller`: a tiny study of the
//! office whose table (errors per seed and count, rates, samples relative to
//! MC) is recomputed here from the master and the images it wrote, and bad
//! input.

#[path = "../../render/tests/support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use render::image::read_exr;
use serde_json::Value;
use std::process::{Command, Output};

fn lqmc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lqmc"))
        .args(args)
        .output()
        .expect("the lqmc binary runs")
}

fn assert_close(found: f64, expected: f64, what: &str) {
    let tolerance = 1e-6 * expected.abs().max(found.abs()) + 1e-12;
    assert!(
        (found - expected).abs() <= tolerance,
        "{what}: table {found}, recomputed {expected}"
    );
}

fn channels(image: &render::image::Image) -> Vec<f64> {
    image
        .pixels()
        .iter()
        .flat_map(|pixel| pixel.iter().map(|&value| f64::from(value)))
        .collect()
}

/// The least-squares fit of log e on log n: (log a, b).
fn fit(points: &[(f64, f64)]) -> (f64, f64) {
    let points: Vec<(f64, f64)> = points
        .iter()
        .filter(|(_, error)| *error > 0.0)
        .map(|(count, error)| (count.ln(), error.ln()))
        .collect();
    let n = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / n;
    let slope = points
        .iter()
        .map(|p| (p.0 - mean_x) * (p.1 - mean_y))
        .sum::<f64>()
        / points.iter().map(|p| (p.0 - mean_x).powi(2)).sum::<f64>();
    (mean_y - slope * mean_x, slope)
}

#[test]
fn kollig_keller_tables_match_the_images_it_wrote() {
    let directory = ScratchDirectory::new("kollig-keller-study");
    let output = lqmc(&[
        "study",
        "kollig-keller",
        "--scene",
        "office",
        "--resolution",
        "12x9",
        "--master-spp",
        "256",
        "--counts",
        "1,2,4,8",
        "--seeds",
        "2",
        "--methods",
        "mc,qmc-halton,rqmc-padded-16,latin-supercube",
        "--keep-images",
        "--quiet",
        "--threads",
        "2",
        "-o",
        directory.as_path().to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let master = read_exr(directory.as_path().join("master.exr")).unwrap();
    let master_values = channels(&master.image);
    let master_variance = channels(&master.layers["variance"]);
    let master_variance = master_variance.iter().sum::<f64>() / master_variance.len() as f64;
    let table: Value = serde_json::from_str(
        &std::fs::read_to_string(directory.as_path().join("table.json")).unwrap(),
    )
    .unwrap();
    assert_close(
        table["master_variance"].as_f64().unwrap(),
        master_variance,
        "master variance",
    );
    assert_eq!(table["max_depth"], 3);
    assert_eq!(table["skip_eye_connections"], true);
    let methods = table["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 4);
    let mut curves = Vec::new();
    for method in methods {
        let name = method["name"].as_str().unwrap();
        let counts: Vec<u64> = method["counts"]
            .as_array()
            .unwrap()
            .iter()
            .map(|count| count.as_u64().unwrap())
            .collect();
        assert_eq!(counts, [1, 2, 4, 8]);
        // QMC is deterministic: one render per count.
        let seeds = if name == "qmc-halton" { 1 } else { 2 };
        let mut errors = Vec::new();
        for (index, &count) in counts.iter().enumerate() {
            let squares = method["squared_errors_per_seed"][index].as_array().unwrap();
            assert_eq!(squares.len(), seeds, "{name}");
            let mut sum = 0.0;
            for (seed, square) in squares.iter().enumerate() {
                let image = read_exr(
                    directory
                        .as_path()
                        .join(format!("images/{name}-n{count}-seed{seed}.exr")),
                )
                .unwrap();
                let values = channels(&image.image);
                let mse = values
                    .iter()
                    .zip(&master_values)
                    .map(|(a, b)| (a - b).powi(2))
                    .sum::<f64>()
                    / values.len() as f64;
                let expected = mse - master_variance;
                assert_close(square.as_f64().unwrap(), expected, name);
                sum += expected;
            }
            let error = (sum / seeds as f64).max(0.0).sqrt();
            assert_close(method["errors"][index].as_f64().unwrap(), error, "error");
            errors.push((count as f64, error));
        }
        let (_, rate) = fit(&errors);
        assert_close(method["rate"].as_f64().unwrap(), rate, "rate");
        curves.push((name.to_string(), errors));
    }
    // Samples relative to MC from the two fits.
    let (mc_log_scale, mc_rate) = fit(&curves[0].1);
    for (method, (name, errors)) in methods.iter().zip(&curves) {
        let (log_scale, rate) = fit(errors);
        let relative = method["samples_relative_to_mc"].as_f64();
        if !(rate < 0.0 && mc_rate < 0.0) {
            assert!(relative.is_none(), "{name}: no ratio without fits");
            continue;
        }
        let log_ratio = curves[0]
            .1
            .iter()
            .map(|(count, _)| {
                let log_mc_error = mc_log_scale + mc_rate * count.ln();
                (log_mc_error - log_scale) / rate - count.ln()
            })
            .sum::<f64>()
            / 4.0;
        assert_close(relative.unwrap(), log_ratio.exp(), name);
    }
    let markdown = std::fs::read_to_string(directory.as_path().join("table.md")).unwrap();
    for name in ["mc", "qmc-halton", "rqmc-padded-16", "latin-supercube"] {
        assert!(markdown.contains(&format!("| {name} |")), "{markdown}");
    }
    for plot in [
        "convergence.svg",
        "convergence.png",
        "samples-relative-to-mc.svg",
        "samples-relative-to-mc.png",
    ] {
        assert!(directory.as_path().join(plot).is_file(), "{plot}");
    }
}

#[test]
fn bad_kollig_keller_input_is_a_usage_error() {
    let directory = ScratchDirectory::new("kollig-keller-bad");
    for extra in [
        vec!["--methods", "qmc-halton"],
        vec!["--methods", "mc,owen"],
        vec!["--counts", "0,4"],
        vec!["--scene", "no-such-scene"],
    ] {
        let mut args = vec![
            "study",
            "kollig-keller",
            "--quiet",
            "-o",
            directory.as_path().to_str().unwrap(),
        ];
        args.extend(extra.iter().copied());
        let output = lqmc(&args);
        assert_eq!(output.status.code(), Some(2), "{extra:?}");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
    }
}

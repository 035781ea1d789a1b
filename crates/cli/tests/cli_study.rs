//! End-to-end tests of `lqmc study`: a small `equal-time` study on the
//! Cornell box whose tables are recomputed here from the images it wrote,
//! the reuse of its reference, a reference given as a file, and bad input;
//! a tiny `kollig-keller` study of the office recomputed the same way; a
//! tiny `lattice-structure` study of the Cornell box likewise.

#[path = "../../render/tests/support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use render::image::{Image, read_exr, read_png, write_exr};
use serde_json::Value;
use std::path::Path;
use std::process::{Command, Output};

/// The relative MSE's offset, as `render::image::compare` defines it.
const EPSILON: f64 = 1e-2;

fn lqmc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lqmc"))
        .args(args)
        .output()
        .expect("the lqmc binary runs")
}

/// A small study of the Cornell box writing to `directory`, with `extra`
/// arguments after the common ones.
fn study(directory: &Path, extra: &[&str]) -> Output {
    study_command(directory, extra)
        .output()
        .expect("the lqmc binary runs")
}

/// The command of [`study`].
fn study_command(directory: &Path, extra: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_lqmc"));
    command.args([
        "study",
        "equal-time",
        "builtin:cornell-box",
        "--resolution",
        "24x18",
        "--threads",
        "2",
        "-o",
        directory.to_str().unwrap(),
    ]);
    command.args(extra);
    command
}

fn assert_success(output: &Output) {
    assert!(
        output.status.success(),
        "status {:?}: {}",
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
}

fn read_table(directory: &Path) -> Value {
    let text = std::fs::read_to_string(directory.join("table.json")).unwrap();
    serde_json::from_str(&text).expect("table.json is JSON")
}

/// Asserts `found` equals `expected` within 1e-9 relative.
fn assert_close(found: f64, expected: f64, what: &str) {
    let tolerance = 1e-9 * expected.abs().max(found.abs()) + 1e-300;
    assert!(
        (found - expected).abs() <= tolerance,
        "{what}: table {found}, recomputed {expected}"
    );
}

fn number(value: &Value) -> f64 {
    value
        .as_f64()
        .unwrap_or_else(|| panic!("{value} is a number"))
}

fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let middle = sorted.len() / 2;
    if sorted.len() % 2 == 1 {
        sorted[middle]
    } else {
        (sorted[middle - 1] + sorted[middle]) / 2.0
    }
}

/// Asserts a `{median, min, max}` object of the table against `values`.
fn assert_spread(table: &Value, values: &[f64], what: &str) {
    assert_close(number(&table["median"]), median(values), what);
    let min = values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert_close(number(&table["min"]), min, what);
    assert_close(number(&table["max"]), max, what);
}

/// The values of every channel of every pixel.
fn values(image: &Image) -> Vec<f64> {
    image
        .pixels()
        .iter()
        .flat_map(|pixel| pixel.map(f64::from))
        .collect()
}

/// RMSE, relative MSE and mean absolute deviation of `image` against
/// `reference` (all values are finite in these renders).
fn errors(image: &[f64], reference: &[f64]) -> (f64, f64, f64) {
    let count = image.len() as f64;
    let mut squared = 0.0;
    let mut relative = 0.0;
    let mut absolute = 0.0;
    for (&a, &b) in image.iter().zip(reference) {
        squared += (a - b) * (a - b);
        relative += (a - b) * (a - b) / (b * b + EPSILON);
        absolute += (a - b).abs();
    }
    ((squared / count).sqrt(), relative / count, absolute / count)
}

/// The seeds' mean bias: the relative difference of the channel-averaged
/// means of the seeds' average image and the reference.
fn bias(images: &[Vec<f64>], reference: &[f64]) -> f64 {
    let seeds = images.len() as f64;
    let average: f64 = images.iter().flatten().sum::<f64>() / seeds;
    let reference_sum: f64 = reference.iter().sum();
    (average - reference_sum) / reference_sum
}

/// The seeds' flicker: the mean over values of the standard deviation
/// across seeds (K − 1) over √(reference² + ε).
fn flicker(images: &[Vec<f64>], reference: &[f64]) -> f64 {
    let seeds = images.len() as f64;
    let mut sum = 0.0;
    for (index, &r) in reference.iter().enumerate() {
        let mean = images.iter().map(|image| image[index]).sum::<f64>() / seeds;
        let variance = images
            .iter()
            .map(|image| (image[index] - mean).powi(2))
            .sum::<f64>()
            / (seeds - 1.0);
        sum += variance.sqrt() / (r * r + EPSILON).sqrt();
    }
    sum / reference.len() as f64
}

#[test]
fn equal_time_tables_match_the_images_it_wrote() {
    let directory = ScratchDirectory::new("study-equal-time");
    let output_directory = directory.join("study");
    let output = study(
        &output_directory,
        &[
            "--integrators",
            "path,lqmc",
            "--time",
            "0.2",
            "--budgets",
            "0.1,0.2",
            "--seeds",
            "2",
            "--reference-spp",
            "32",
        ],
    );
    assert_success(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("rendering the reference"), "{stderr}");
    assert!(stderr.contains("[8/8]"), "{stderr}");

    let table = read_table(&output_directory);
    assert_eq!(table["scene"], "builtin:cornell-box");
    assert_eq!(table["seeds"], 2);
    assert_eq!(table["threads"], 2);
    assert_eq!(table["reference"]["source"], "rendered");
    assert_eq!(table["reference"]["spp"], 32);
    let reference_file = read_exr(output_directory.join("reference.exr")).unwrap();
    assert_eq!(
        (reference_file.image.width(), reference_file.image.height()),
        (24, 18)
    );
    for (key, value) in [
        ("spp", "32"),
        ("seed", "1000003"),
        ("integrator", "path"),
        ("sampler", "halton"),
        ("scene", "builtin:cornell-box"),
    ] {
        assert_eq!(
            reference_file.metadata.get(key).map(String::as_str),
            Some(value),
            "{key}"
        );
    }
    let reference = values(&reference_file.image);

    let rows = table["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4, "2 budgets x 2 integrators");
    let mut median_rmse_of_path = f64::NAN;
    for (index, row) in rows.iter().enumerate() {
        let integrator = row["integrator"].as_str().unwrap();
        let budget = number(&row["budget_seconds"]);
        assert_eq!(integrator, ["path", "lqmc"][index % 2]);
        assert_eq!(budget, [0.1, 0.2][index / 2]);
        let seeds = row["seeds"].as_array().unwrap();
        assert_eq!(seeds.len(), 2);
        let mut images = Vec::new();
        let mut per_seed = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut per_seed_memory = Vec::new();
        for (seed, entry) in seeds.iter().enumerate() {
            assert_eq!(entry["seed"], seed as u64);
            let name = entry["image"].as_str().unwrap();
            assert_eq!(
                name,
                format!("images/{integrator}-b{budget}-seed{seed}.exr")
            );
            let contents = read_exr(output_directory.join(name)).unwrap();
            let metadata = |key: &str| contents.metadata.get(key).cloned().unwrap_or_default();
            assert_eq!(metadata("integrator"), integrator);
            assert_eq!(metadata("seed"), seed.to_string());
            assert_eq!(metadata("timeBudgetSeconds"), budget.to_string());
            assert_eq!(metadata("spp"), entry["whole_passes"].to_string());
            // The render's peak memory, as its image says.
            assert_eq!(
                metadata("peakResidentBytes"),
                entry["peak_resident_bytes"].to_string()
            );
            per_seed_memory.push(number(&entry["peak_resident_bytes"]) / 1e6);
            let image = values(&contents.image);
            let (rmse, relative_mse, mad) = errors(&image, &reference);
            let what = format!("{integrator} at {budget} s, seed {seed}");
            assert_close(number(&entry["rmse"]), rmse, &format!("RMSE of {what}"));
            assert_close(
                number(&entry["relative_mse"]),
                relative_mse,
                &format!("relative MSE of {what}"),
            );
            assert_close(number(&entry["mad"]), mad, &format!("MAD of {what}"));
            per_seed.0.push(rmse);
            per_seed.1.push(relative_mse);
            per_seed.2.push(mad);
            per_seed.3.push(number(&entry["spp"]));
            assert!(number(&entry["spp"]) >= 1.0, "{what} rendered samples");
            images.push(image);
        }
        let what = format!("{integrator} at {budget} s");
        assert_spread(&row["rmse"], &per_seed.0, &format!("RMSE of {what}"));
        assert_spread(
            &row["relative_mse"],
            &per_seed.1,
            &format!("rel. MSE of {what}"),
        );
        assert_spread(&row["mad"], &per_seed.2, &format!("MAD of {what}"));
        assert_spread(&row["spp"], &per_seed.3, &format!("spp of {what}"));
        assert_spread(
            &row["peak_memory_mb"],
            &per_seed_memory,
            &format!("peak memory of {what}"),
        );
        assert_close(
            number(&row["mean_bias"]),
            bias(&images, &reference),
            &format!("mean bias of {what}"),
        );
        assert_close(
            number(&row["flicker"]),
            flicker(&images, &reference),
            &format!("flicker of {what}"),
        );
        if integrator == "path" {
            median_rmse_of_path = median(&per_seed.0);
        }
        assert_close(
            number(&row["rmse_ratio_to_first"]),
            median(&per_seed.0) / median_rmse_of_path,
            &format!("RMSE ratio of {what}"),
        );
    }

    let markdown = std::fs::read_to_string(output_directory.join("table.md")).unwrap();
    for expected in [
        "builtin:cornell-box at 24x18",
        "load average",
        "| budget (s) | integrator | spp | RMSE | relative MSE | MAD | mean bias | flicker | RMSE / path's | peak memory (MB) |",
        "| 0.2 | lqmc |",
        "lqmc study equal-time builtin:cornell-box --resolution 24x18",
    ] {
        assert!(
            markdown.contains(expected),
            "'{expected}' missing in {markdown}"
        );
    }
    assert!(markdown.trim_end().ends_with("```"), "{markdown}");

    let svg = std::fs::read_to_string(output_directory.join("error-vs-time.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("lqmc"), "{svg}");
    let plot = read_png(output_directory.join("error-vs-time.png")).unwrap();
    assert_eq!((plot.width(), plot.height()), (800, 560));
    // The default crop: a 9x9 square (min(24, 18) / 2), enlarged 15 times to
    // 135 px; reference, path and lqmc with 4-pixel gaps.
    let crops = read_png(output_directory.join("crops.png")).unwrap();
    assert_eq!((crops.width(), crops.height()), (3 * 135 + 2 * 4, 135));
    assert_eq!(table["crop"]["enlargement"], 15);

    // Again with the same reference options: the reference is reused, not
    // rendered again; a reference of other spp is rendered again.
    let reference_bytes = std::fs::read(output_directory.join("reference.exr")).unwrap();
    let fewer_renders = [
        "--integrators",
        "path:splat",
        "--time",
        "0.05",
        "--budgets",
        "0.05",
        "--seeds",
        "1",
    ];
    let output = study(
        &output_directory,
        &[&fewer_renders[..], &["--reference-spp", "32"]].concat(),
    );
    assert_success(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("reusing the reference"), "{stderr}");
    assert!(!stderr.contains("rendering the reference"), "{stderr}");
    assert_eq!(
        read_table(&output_directory)["reference"]["source"],
        "reused"
    );
    assert_eq!(
        std::fs::read(output_directory.join("reference.exr")).unwrap(),
        reference_bytes
    );
    // `:splat` renders with --splat-film, and says so in the table and the
    // image's metadata.
    let table_of_splat = read_table(&output_directory);
    assert_eq!(table_of_splat["integrators"][0]["label"], "path:splat");
    assert_eq!(table_of_splat["integrators"][0]["splat_film"], true);
    let image_of_splat = table_of_splat["rows"][0]["seeds"][0]["image"]
        .as_str()
        .unwrap()
        .to_string();
    let splat_file = read_exr(output_directory.join(&image_of_splat)).unwrap();
    assert_eq!(
        splat_file.metadata.get("film").map(String::as_str),
        Some("splat")
    );
    let flicker_of_one_seed = &read_table(&output_directory)["rows"][0]["flicker"];
    assert!(flicker_of_one_seed.is_null(), "{flicker_of_one_seed}");

    let output = study(
        &output_directory,
        &[&fewer_renders[..], &["--reference-spp", "16"]].concat(),
    );
    assert_success(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("does not match (spp `32`, not `16`)"),
        "{stderr}"
    );
    assert!(stderr.contains("rendering the reference"), "{stderr}");

    // A reference given as a file, with a crop, run in `directory`: the
    // absolute paths inside it are written relative to it.
    let given = directory.join("given-reference.exr");
    std::fs::write(&given, &reference_bytes).unwrap();
    let with_file = directory.join("with-file");
    let output = study_command(
        &with_file,
        &[
            &fewer_renders[..],
            &[
                "--reference",
                given.to_str().unwrap(),
                "--crop",
                "0,0,24,18",
            ],
        ]
        .concat(),
    )
    .current_dir(&*directory)
    .output()
    .unwrap();
    assert_success(&output);
    let table = read_table(&with_file);
    assert_eq!(table["reference"]["source"], "file");
    assert_eq!(table["reference"]["image"], "given-reference.exr");
    let command = table["command"].as_str().unwrap();
    assert!(
        command.contains("-o with-file") && command.contains("--reference given-reference.exr"),
        "{command}"
    );
    let markdown = std::fs::read_to_string(with_file.join("table.md")).unwrap();
    assert!(
        markdown.contains("Reference: the image given-reference.exr."),
        "{markdown}"
    );
    let directory_name = directory.to_str().unwrap();
    assert!(!markdown.contains(directory_name), "{markdown}");
    let crops = read_png(directory.join("with-file").join("crops.png")).unwrap();
    // 18 px tall, enlarged 8 times to 144 px.
    assert_eq!((crops.width(), crops.height()), (2 * 24 * 8 + 4, 144));

    // The same reference with its own noise: a variance image whose mean is
    // subtracted from every render's squared error and relative MSE.
    let given_image = read_exr(&given).unwrap().image;
    let mut variance_image = Image::new(24, 18);
    let reference_values = values(&given_image);
    let mut variances = Vec::new();
    for (index, pixel) in variance_image.pixels_mut().iter_mut().enumerate() {
        // Uneven, so that the relative correction is not the plain one scaled.
        let variance = 1e-5 * (1 + index % 5) as f32;
        *pixel = [variance; 3];
        variances.extend([f64::from(variance); 3]);
    }
    let variance_path = directory.join("given-variance.exr");
    write_exr(&variance_path, &variance_image, &[], &Default::default()).unwrap();
    let with_noise = directory.join("with-noise");
    let output = study(
        &with_noise,
        &[
            &fewer_renders[..],
            &[
                "--reference",
                given.to_str().unwrap(),
                "--reference-variance",
                variance_path.to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    assert_success(&output);
    let table = read_table(&with_noise);
    let count = variances.len() as f64;
    let mean_variance = variances.iter().sum::<f64>() / count;
    let mean_relative_variance = variances
        .iter()
        .zip(&reference_values)
        .map(|(variance, r)| variance / (r * r + EPSILON))
        .sum::<f64>()
        / count;
    assert_close(
        number(&table["reference"]["mean_variance"]),
        mean_variance,
        "mean variance",
    );
    for row in table["rows"].as_array().unwrap() {
        for entry in row["seeds"].as_array().unwrap() {
            let name = entry["image"].as_str().unwrap();
            let image = values(&read_exr(with_noise.join(name)).unwrap().image);
            let (rmse, relative_mse, mad) = errors(&image, &reference_values);
            assert_close(
                number(&entry["rmse"]),
                (rmse * rmse - mean_variance).max(0.0).sqrt(),
                &format!("corrected RMSE of {name}"),
            );
            assert_close(
                number(&entry["relative_mse"]),
                (relative_mse - mean_relative_variance).max(0.0),
                &format!("corrected relative MSE of {name}"),
            );
            assert_close(number(&entry["mad"]), mad, &format!("MAD of {name}"));
        }
    }
    let markdown = std::fs::read_to_string(with_noise.join("table.md")).unwrap();
    assert!(
        markdown.contains("is subtracted from each render's squared error"),
        "{markdown}"
    );
}

/// A scratch directory with an 8×8 black `small.exr`, and the path of an
/// output directory in it that bad input must not create.
fn bad_input_directory(prefix: &str) -> (ScratchDirectory, std::path::PathBuf, std::path::PathBuf) {
    let directory = ScratchDirectory::new(prefix);
    let small_reference = directory.join("small.exr");
    write_exr(
        &small_reference,
        &Image::new(8, 8),
        &[],
        &Default::default(),
    )
    .unwrap();
    let output_directory = directory.join("never-written");
    (directory, small_reference, output_directory)
}

/// Asserts that `output` is a usage error: status 2, one line on stderr
/// that contains `expected`, and no `output_directory` created.
fn assert_refused(output: &Output, expected: &str, what: &str, output_directory: &Path) {
    assert_eq!(output.status.code(), Some(2), "{what}");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(expected),
        "{what}: '{expected}' not in {stderr}"
    );
    assert!(!output_directory.exists(), "{what} created the output");
}

#[test]
fn bad_study_input_is_one_line_and_status_two_before_rendering() {
    let (_directory, small_reference, output_directory) = bad_input_directory("study-bad-input");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--integrators", "path,sppm", "--reference-spp", "4"],
            "unknown integrator `sppm` (known: path, volpath, lqmc, light, bdpt, pssmlt,",
        ),
        (
            vec!["--integrators", "path:owen", "--reference-spp", "4"],
            "unknown sampler `owen`",
        ),
        (vec![], "a reference is needed"),
        (
            vec![
                "--integrators",
                "path,lqmc[--mlt-chains 8]",
                "--reference-spp",
                "4",
            ],
            "`lqmc[--mlt-chains 8]`: --mlt-chains is an option of pssmlt and mmlt, not of lqmc",
        ),
        (
            vec![
                "--integrators",
                "path,lqmc[--breakup 2]",
                "--breakup",
                "1",
                "--reference-spp",
                "4",
            ],
            "`lqmc[--breakup 2]`: the argument '--breakup <B|k|cdf>' cannot be used multiple times",
        ),
        (
            vec![
                "--integrators",
                "path,lqmc[--density x.exr]",
                "--reference-spp",
                "4",
            ],
            "--density is for `lqmc render`",
        ),
        (
            vec!["--reference-spp", "4", "--reference-variance", "v.exr"],
            "--reference-variance",
        ),
        (
            vec!["--reference-spp", "4", "--crop", "20,10,10,10"],
            "lies outside the 24x18 image",
        ),
        (
            vec!["--reference", small_reference.to_str().unwrap()],
            "is 8x8, but the study renders 24x18",
        ),
        (
            vec!["--reference-spp", "4", "--seeds", "0"],
            "--seeds must be at least 1",
        ),
        (
            vec!["--reference-spp", "4", "--time=0"],
            "--time must be a positive",
        ),
        (
            vec!["--reference-spp", "4", "--time=-1"],
            "--time must be a positive",
        ),
        (
            vec!["--reference-spp", "4", "--budgets", "0.1,0"],
            "--budgets must be a positive",
        ),
        (
            vec!["--reference-spp", "0"],
            "--reference-spp must be at least 1",
        ),
        (
            vec![
                "--integrators",
                "path,bdpt",
                "--reference-spp",
                "4",
                "--breakup",
                "2",
            ],
            "--breakup is an option of lqmc, none of the study's integrators (path and bdpt)",
        ),
        (
            vec![
                "--integrators",
                "erpt",
                "--reference-spp",
                "4",
                "--mlt-chains",
                "8",
            ],
            "--mlt-chains is an option of pssmlt and mmlt, none of the study's integrators (erpt)",
        ),
    ];
    for (extra, expected) in cases {
        let mut args = extra.clone();
        if !args.iter().any(|arg| arg.starts_with("--time")) {
            args.extend(["--time", "0.1"]);
        }
        let output = study(&output_directory, &args);
        assert_refused(&output, expected, &format!("{extra:?}"), &output_directory);
    }
}

/// The channels of `image` in order, as `f64`.
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

/// `lqmc study kollig-keller`: a tiny study of the office whose table
/// (errors per seed and count, rates, samples relative to MC) is recomputed
/// from the master and the images it wrote.
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
    assert_success(&output);
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

/// A triangle's area and RGB radiance, as the per-triangle CSV has them.
type Triangle = (f64, [f64; 3]);

/// `lqmc study heinrich-keller` on the built-in room (small counts): the
/// mutual deviations per pattern, the deviations from each master and
/// between the masters in table.json are recomputed from the per-triangle
/// CSV it wrote (areas and RGB radiances), by the paper's area-weighted
/// RGB distance; the plot and the markdown are written; a bad pattern is a
/// usage error.
#[test]
fn heinrich_keller_tables_match_the_triangles_it_wrote() {
    let directory = ScratchDirectory::new("heinrich-keller-study");
    let csv = directory.join("triangles.csv");
    let output = lqmc(&[
        "study",
        "heinrich-keller",
        "--counts",
        "1000,4e3,16000",
        "--bounces",
        "2",
        "--patterns",
        "random,halton,hammersley",
        "--threads",
        "2",
        "--quiet",
        "--per-triangle",
        csv.to_str().unwrap(),
        "-o",
        directory.to_str().unwrap(),
    ]);
    assert_success(&output);
    for name in ["table.md", "convergence.svg", "convergence.png"] {
        assert!(directory.join(name).is_file(), "{name} missing");
    }
    let table = read_table(&directory);
    let counts: Vec<u64> = table["counts"]
        .as_array()
        .unwrap()
        .iter()
        .map(|value| value.as_u64().unwrap())
        .collect();
    assert_eq!(counts, [1000, 4000, 16000]);
    assert_eq!(table["measure"].as_str(), Some("integral"));
    // pattern -> count -> triangle -> (area, rgb)
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut radiances: std::collections::BTreeMap<(String, u64), Vec<Triangle>> =
        Default::default();
    for line in text.lines().skip(1) {
        let fields: Vec<&str> = line.split(',').collect();
        let parse = |index: usize| fields[index].parse::<f64>().unwrap();
        let (area, integral) = (parse(3), [parse(7), parse(8), parse(9)]);
        // The per-area radiance is the integral over the area.
        for (channel, value) in integral.iter().enumerate() {
            assert_close(parse(4 + channel) * area, *value, line);
        }
        // The default measure is the integral (Eq. 14 over the triangle).
        radiances
            .entry((fields[0].to_string(), fields[1].parse().unwrap()))
            .or_default()
            .push((area, integral));
    }
    let deviation = |a: &[Triangle], b: &[Triangle]| {
        let (mut weighted, mut total) = (0.0, 0.0);
        for ((area, x), (_, y)) in a.iter().zip(b) {
            let squared: f64 = (0..3).map(|c| (x[c] - y[c]).powi(2)).sum();
            weighted += area * squared;
            total += area;
        }
        (weighted / total).sqrt()
    };
    let patterns = table["patterns"].as_array().unwrap();
    assert_eq!(patterns.len(), 3);
    for pattern in patterns {
        let name = pattern["name"].as_str().unwrap().to_string();
        let of = |count: u64| &radiances[&(name.clone(), count)];
        assert_eq!(of(1000).len(), 276);
        let matrix = pattern["mutual_deviations"].as_array().unwrap();
        for (row, values) in matrix.iter().enumerate() {
            for (column, value) in values.as_array().unwrap().iter().enumerate() {
                assert_close(
                    number(value),
                    deviation(of(counts[row + 1]), of(counts[column])),
                    &format!("{name} {} vs {}", counts[row + 1], counts[column]),
                );
            }
        }
        let from_master = pattern["deviation_from_master"].as_array().unwrap();
        for (index, value) in from_master.iter().enumerate() {
            assert_close(
                number(value),
                deviation(of(counts[index]), of(16000)),
                &format!("{name} {} vs master", counts[index]),
            );
        }
    }
    for entry in table["between_masters"].as_array().unwrap() {
        let first = entry["first"].as_str().unwrap().to_string();
        let second = entry["second"].as_str().unwrap().to_string();
        assert_close(
            number(&entry["deviation"]),
            deviation(&radiances[&(first, 16000)], &radiances[&(second, 16000)]),
            "between masters",
        );
    }
    let bad = lqmc(&[
        "study",
        "heinrich-keller",
        "--patterns",
        "faure",
        "-o",
        directory.to_str().unwrap(),
    ]);
    assert_eq!(bad.status.code(), Some(2));
}

/// Entries with options of their own: two modes of LQMC in one study, each
/// rendered with the study's options and its own, named by them.
#[test]
fn entries_with_their_own_options_are_modes_of_one_integrator() {
    let directory = ScratchDirectory::new("study-modes");
    let output_directory = directory.join("modes");
    let output = study(
        &output_directory,
        &[
            "--integrators",
            "lqmc,lqmc[--class-selection fixed --explore-class normal]",
            "--no-jitter",
            "--time",
            "0.05",
            "--budgets",
            "0.05",
            "--seeds",
            "1",
            "--reference-spp",
            "4",
        ],
    );
    assert_success(&output);
    let table = read_table(&output_directory);
    let rows = table["rows"].as_array().unwrap();
    let labels: Vec<&str> = rows
        .iter()
        .map(|row| row["integrator"].as_str().unwrap())
        .collect();
    assert_eq!(
        labels,
        [
            "lqmc",
            "lqmc[--class-selection fixed --explore-class normal]"
        ]
    );
    let image = rows[1]["seeds"][0]["image"].as_str().unwrap();
    assert_eq!(
        image,
        "images/lqmc-class-selection-fixed-explore-class-normal-b0.05-seed0.exr"
    );
    assert!(output_directory.join(image).exists());
}

/// The luminance error render − reference with its mean removed, as
/// `lattice-structure` defines it.
fn luminance_error(image: &Image, reference: &Image) -> Vec<f64> {
    let luminance = |pixel: &[f32; 3]| {
        0.2126 * f64::from(pixel[0]) + 0.7152 * f64::from(pixel[1]) + 0.0722 * f64::from(pixel[2])
    };
    let error: Vec<f64> = image
        .pixels()
        .iter()
        .zip(reference.pixels())
        .map(|(a, b)| luminance(a) - luminance(b))
        .collect();
    let mean = error.iter().sum::<f64>() / error.len() as f64;
    error.iter().map(|value| value - mean).collect()
}

/// The periodogram |DFT(error)|² / (W·H) by a direct DFT, row-major by
/// frequency index.
fn periodogram(error: &[f64], width: usize, height: usize) -> Vec<f64> {
    let mut spectrum = Vec::with_capacity(width * height);
    for ky in 0..height {
        for kx in 0..width {
            let (mut re, mut im) = (0.0, 0.0);
            for y in 0..height {
                for x in 0..width {
                    let phase = -std::f64::consts::TAU
                        * ((kx * x) as f64 / width as f64 + (ky * y) as f64 / height as f64);
                    re += error[y * width + x] * phase.cos();
                    im += error[y * width + x] * phase.sin();
                }
            }
            spectrum.push((re * re + im * im) / (width * height) as f64);
        }
    }
    spectrum
}

/// The radial power per ring and the peak ratio of a spectrum, as
/// `lattice-structure` defines them.
fn spectrum_measures(spectrum: &[f64], width: usize, height: usize) -> (Vec<f64>, f64) {
    let side = width.min(height);
    let rings = side / 2 + 1;
    let mut ring_values = vec![Vec::new(); rings];
    let mut off_axis = Vec::new();
    let signed = |k: usize, n: usize| {
        if 2 * k >= n {
            k as i64 - n as i64
        } else {
            k as i64
        }
    };
    for ky in 0..height {
        for kx in 0..width {
            let (sx, sy) = (signed(kx, width), signed(ky, height));
            let (fx, fy) = (sx as f64 / width as f64, sy as f64 / height as f64);
            let ring = ((fx * fx + fy * fy).sqrt() * side as f64).round() as usize;
            let power = spectrum[ky * width + kx];
            if ring < rings {
                ring_values[ring].push(power);
                if sx != 0 && sy != 0 {
                    off_axis.push((power, ring));
                }
            }
        }
    }
    let radial: Vec<f64> = ring_values
        .iter()
        .map(|values| values.iter().sum::<f64>() / values.len() as f64)
        .collect();
    let medians: Vec<f64> = ring_values.iter().map(|values| median(values)).collect();
    let peak = off_axis
        .iter()
        .filter(|(_, ring)| *ring > 0 && ring_values[*ring].len() >= 32)
        .map(|(power, ring)| power / medians[*ring])
        .fold(0.0, f64::max);
    (radial, peak)
}

/// Σ ρ(d) over the lags 0 < max(|dx|, |dy|) ≤ `max_lag`.
fn autocorrelation_sum(error: &[f64], width: usize, height: usize, max_lag: i64) -> f64 {
    let energy: f64 = error.iter().map(|e| e * e).sum();
    let (w, h) = (width as i64, height as i64);
    let mut correlation = 0.0;
    for dy in -max_lag..=max_lag {
        for dx in -max_lag..=max_lag {
            if (dx, dy) == (0, 0) {
                continue;
            }
            for y in 0..h {
                for x in 0..w {
                    let (u, v) = (x + dx, y + dy);
                    if (0..w).contains(&u) && (0..h).contains(&v) {
                        correlation +=
                            error[(y * w + x) as usize] * error[(v * w + u) as usize] / energy;
                    }
                }
            }
        }
    }
    correlation
}

/// A tiny `lattice-structure` study of the Cornell box with normal paths
/// explored: its table recomputed from the images it wrote (RMSE, and the
/// luminance error's spectrum by a direct DFT: radial power, peak ratio,
/// autocorrelation sum).
#[test]
fn lattice_structure_tables_match_the_images_it_wrote() {
    let directory = ScratchDirectory::new("study-lattice-structure");
    let reference_path = directory.join("reference.exr");
    let output_directory = directory.join("study");
    assert_success(&lqmc(&[
        "render",
        "builtin:cornell-box",
        "--resolution",
        "24x18",
        "--spp",
        "32",
        "--threads",
        "2",
        "--quiet",
        "-o",
        reference_path.to_str().unwrap(),
    ]));
    let output = lqmc(&[
        "study",
        "lattice-structure",
        "builtin:cornell-box",
        "--resolution",
        "24x18",
        "--threads",
        "2",
        "--spp",
        "2",
        "--seeds",
        "2",
        "--max-lag",
        "1",
        "--explore-class",
        "normal",
        "--reference",
        reference_path.to_str().unwrap(),
        "-o",
        output_directory.to_str().unwrap(),
    ]);
    assert_success(&output);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("[6/6] seed 1, scramble all"), "{stderr}");
    for file in ["table.md", "spectrum.svg", "spectrum.png", "crops.png"] {
        assert!(output_directory.join(file).exists(), "{file}");
    }
    let table = read_table(&output_directory);
    assert_eq!(table["study"], "lattice-structure");
    assert_eq!(table["spp"], 2);
    assert_eq!(
        table["explored_classes"],
        "normal (N = 23), caustic (N = 97)"
    );
    let reference = read_exr(&reference_path).unwrap().image;
    let reference_values = values(&reference);
    let rows = table["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for (row, scramble) in rows.iter().zip(["none", "image", "all"]) {
        assert_eq!(row["scramble"], scramble);
        let seeds = row["seeds"].as_array().unwrap();
        assert_eq!(seeds.len(), 2);
        let mut per_seed = (Vec::new(), Vec::new(), Vec::new());
        let mut spectra = Vec::new();
        for (seed, entry) in seeds.iter().enumerate() {
            let name = entry["image"].as_str().unwrap();
            assert_eq!(name, format!("images/{scramble}-seed{seed}.exr"));
            let contents = read_exr(output_directory.join(name)).unwrap();
            let metadata = |key: &str| contents.metadata.get(key).cloned().unwrap_or_default();
            assert_eq!(metadata("latticeScramble"), scramble);
            assert_eq!(metadata("seed"), seed.to_string());
            assert_eq!(metadata("integrator"), "lqmc");
            let what = format!("{scramble}, seed {seed}");
            let (rmse, ..) = errors(&values(&contents.image), &reference_values);
            assert_close(number(&entry["rmse"]), rmse, &format!("RMSE of {what}"));
            let error = luminance_error(&contents.image, &reference);
            let spectrum = periodogram(&error, 24, 18);
            let (radial, peak) = spectrum_measures(&spectrum, 24, 18);
            let correlation = autocorrelation_sum(&error, 24, 18, 1);
            spectra.push(spectrum);
            let table_radial = entry["radial_power"].as_array().unwrap();
            assert_eq!(table_radial.len(), radial.len());
            for (ring, (found, expected)) in table_radial.iter().zip(&radial).enumerate() {
                assert!(
                    (number(found) - expected).abs() <= 1e-9 * expected.abs() + 1e-15,
                    "{what}: ring {ring}: {found} against {expected}"
                );
            }
            assert_close(
                number(&entry["peak_ratio"]),
                peak,
                &format!("peak of {what}"),
            );
            assert!(peak > 1.0, "{what}: {peak}");
            assert_close(
                number(&entry["autocorrelation_sum"]),
                correlation,
                &format!("autocorrelation of {what}"),
            );
            per_seed.0.push(rmse);
            per_seed.1.push(peak);
            per_seed.2.push(correlation);
        }
        assert_spread(&row["rmse"], &per_seed.0, scramble);
        assert_spread(&row["peak_ratio"], &per_seed.1, scramble);
        assert_spread(&row["autocorrelation_sum"], &per_seed.2, scramble);
        // The peak of the seeds' mean spectrum.
        let mean: Vec<f64> = (0..spectra[0].len())
            .map(|k| spectra.iter().map(|spectrum| spectrum[k]).sum::<f64>() / 2.0)
            .collect();
        let (_, mean_peak) = spectrum_measures(&mean, 24, 18);
        assert_close(
            number(&row["mean_spectrum"]["peak_ratio"]),
            mean_peak,
            &format!("peak of the mean spectrum of {scramble}"),
        );
    }
    assert_eq!(
        table["white_noise"]["radial_power_median"]
            .as_array()
            .unwrap()
            .len(),
        10
    );
    let markdown = std::fs::read_to_string(output_directory.join("table.md")).unwrap();
    assert!(
        markdown.contains("| white noise, 2 image(s) of this size |"),
        "{markdown}"
    );
}

#[test]
fn bad_lattice_structure_input_is_a_usage_error() {
    let (_directory, small_reference, output_directory) =
        bad_input_directory("study-lattice-structure-bad-input");
    let reference = small_reference.to_str().unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["--reference", reference],
            "is 8x8, but the study renders 24x18",
        ),
        (
            vec!["--reference", reference, "--lattice-scramble", "all"],
            "list the scrambles with --scrambles",
        ),
        (
            vec!["--reference", reference, "--scrambles", "none,swap"],
            "unknown scramble `swap`",
        ),
        (
            vec!["--reference", reference, "--seeds", "0"],
            "--seeds must be at least 1",
        ),
        (
            vec!["--reference", reference, "--vcm-radius", "0.1"],
            "--vcm-radius is an option of vcm, none of the study's integrators (lqmc)",
        ),
    ];
    for (extra, expected) in cases {
        let mut args = vec![
            "study",
            "lattice-structure",
            "builtin:cornell-box",
            "--resolution",
            "24x18",
            "--spp",
            "1",
            "-o",
            output_directory.to_str().unwrap(),
        ];
        args.extend(&extra);
        let output = lqmc(&args);
        assert_refused(&output, expected, &format!("{extra:?}"), &output_directory);
    }
}

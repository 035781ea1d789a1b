//! End-to-end tests of `lqmc compare`.

#[path = "../../render/tests/support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use render::image::{Image, write_pfm};

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

fn write(directory: &std::path::Path, name: &str, pixels: Vec<[f32; 3]>) -> String {
    let path = directory.join(name);
    let image = Image::from_pixels(pixels.len(), 1, pixels).unwrap();
    write_pfm(&path, &image).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn compare_prints_error_measures_and_the_z_test_as_json() {
    let directory = temporary_directory("compare");
    let image = write(&directory, "image.pfm", vec![[1.0; 3], [2.0; 3], [1.0; 3]]);
    let reference = write(&directory, "reference.pfm", vec![[1.0; 3]; 3]);
    let variance = write(&directory, "variance.pfm", vec![[1.0; 3]; 3]);
    let output = lqmc(&[
        "compare",
        &image,
        &reference,
        "--variance",
        &variance,
        "--spp",
        "100",
        "--json",
    ]);
    assert!(output.status.success(), "{output:?}");
    let text = String::from_utf8(output.stdout).unwrap();
    // Differences 0, 1, 0 per channel: RMSE sqrt(1/3), mean +33 %.
    assert!(text.contains("\"rmse\":0.5773502691896"), "{text}");
    assert!(
        text.contains("\"relative_mean_difference\":0.333333333333"),
        "{text}"
    );
    // The pixel 1.0 off is 10 standard errors away; the other two pass.
    assert!(text.contains("\"passed_pixels\":2"), "{text}");
    assert!(text.contains("\"pixels\":3"), "{text}");
}

#[test]
fn compare_reports_bad_input_in_one_line() {
    let directory = temporary_directory("compare-errors");
    let one = write(&directory, "one.pfm", vec![[1.0; 3]]);
    let two = write(&directory, "two.pfm", vec![[1.0; 3]; 2]);
    for (args, expected) in [
        (vec!["compare", &one, &two], "expected 1x1"),
        (vec!["compare", &one, "missing.exr"], "missing.exr"),
        (
            vec!["compare", &one, &one, "--variance", &one],
            "pass --spp N",
        ),
    ] {
        let output = lqmc(&args);
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
    }
}

//! `lqmc merge`: combines replication parts (`lqmc render --replication
//! I/R`) into their mean, the variance of the mean from their spread, and
//! the error estimate — the same pixels, bit for bit, as one render of
//! those replications (`render::replication`).

/// Prints a line to stdout, ignoring a closed pipe.
macro_rules! say {
    ($($argument:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($argument)*);
    }};
}

use crate::error::{CliError, usage};
use crate::replications::{
    describe_estimate, format_indices, insert_estimate, keys, parse_indices, parse_region,
};
use clap::Args;
use render::image::{ExrContents, Image, Metadata, VARIANCE_LAYER, read_exr, write_exr, write_png};
use render::replication::ReplicationAccumulator;
use std::path::{Path, PathBuf};

/// Arguments of `lqmc merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The parts: EXR files written by `lqmc render --replication I/R`,
    /// any subset of one set.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged image (.exr); a PNG is written beside it.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The pixels whose mean luminance the error is measured over,
    /// x,y,width,height (default: the parts' region, else the image).
    #[arg(long, value_name = "X,Y,W,H", value_parser = parse_region)]
    pub region: Option<[usize; 4]>,
    /// Exposure of the PNG in stops.
    #[arg(long, default_value_t = 0.0)]
    pub exposure: f32,
}

/// One part: its file, replication index and contents.
struct Part {
    path: PathBuf,
    index: u64,
    contents: ExrContents,
}

/// The metadata value `key` of a part, or an error that names the file.
fn required<'a>(path: &Path, metadata: &'a Metadata, key: &str) -> Result<&'a str, CliError> {
    metadata.get(key).map(String::as_str).ok_or_else(|| {
        usage(format!(
            "{} is not a replication part (no `{key}` in its metadata): render parts with lqmc render --replication I/R",
            path.display()
        ))
    })
}

/// Reads a part and checks that it holds one replication.
fn read_part(path: &Path) -> Result<Part, CliError> {
    let contents = read_exr(path).map_err(|error| usage(error.to_string()))?;
    let metadata = &contents.metadata;
    for key in [keys::SET, keys::SETTINGS_HASH, "seed", "scene"] {
        required(path, metadata, key)?;
    }
    let indices_text = required(path, metadata, keys::INDICES)?;
    let indices = parse_indices(indices_text).ok_or_else(|| {
        usage(format!(
            "{}: `{}` = `{indices_text}` is not a list of replication indices",
            path.display(),
            keys::INDICES
        ))
    })?;
    let [index] = indices.as_slice() else {
        return Err(usage(format!(
            "{} holds replications {indices_text} already (a merged render): merge the parts it was made of",
            path.display()
        )));
    };
    Ok(Part {
        path: path.to_path_buf(),
        index: *index,
        contents,
    })
}

/// The first `; `-separated setting that differs between two fingerprints.
fn first_difference(a: &str, b: &str) -> String {
    a.split("; ")
        .zip(b.split("; "))
        .find(|(left, right)| left != right)
        .map(|(left, right)| format!("{left} vs {right}"))
        .unwrap_or_else(|| "the settings differ".to_string())
}

/// Checks that `part` belongs to the same replication set as `first`.
fn check_same_set(first: &Part, part: &Part) -> Result<(), CliError> {
    let (a, b) = (&first.contents.metadata, &part.contents.metadata);
    let differs = |key: &str| a.get(key) != b.get(key);
    let reason = if differs(keys::SETTINGS_HASH) {
        Some(first_difference(
            a.get(keys::SETTINGS).map_or("", String::as_str),
            b.get(keys::SETTINGS).map_or("", String::as_str),
        ))
    } else if differs("seed") {
        Some(format!(
            "seed {} vs {}",
            a.get("seed").map_or("?", String::as_str),
            b.get("seed").map_or("?", String::as_str)
        ))
    } else if differs(keys::SET) {
        Some(format!(
            "a set of {} replications vs {}",
            a.get(keys::SET).map_or("?", String::as_str),
            b.get(keys::SET).map_or("?", String::as_str)
        ))
    } else if first.contents.image.width() != part.contents.image.width()
        || first.contents.image.height() != part.contents.image.height()
    {
        Some("the resolutions differ".to_string())
    } else {
        None
    };
    match reason {
        Some(reason) => Err(usage(format!(
            "{} and {} are not replications of one render ({reason}): refusing to mix them",
            first.path.display(),
            part.path.display()
        ))),
        None => Ok(()),
    }
}

/// Runs `lqmc merge`.
pub fn run(args: &MergeArgs) -> Result<(), CliError> {
    let is_exr = args
        .output
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("exr"));
    if !is_exr {
        return Err(usage(format!(
            "cannot write {}: the merged image is an EXR file (it carries the variance layer and the metadata)",
            args.output.display()
        )));
    }
    let mut parts = args
        .parts
        .iter()
        .map(|path| read_part(path))
        .collect::<Result<Vec<_>, _>>()?;
    for part in &parts[1..] {
        check_same_set(&parts[0], part)?;
    }
    parts.sort_by_key(|part| part.index);
    for pair in parts.windows(2) {
        if pair[0].index == pair[1].index {
            return Err(usage(format!(
                "replication {} is given twice ({} and {})",
                pair[0].index,
                pair[0].path.display(),
                pair[1].path.display()
            )));
        }
    }
    let first = &parts[0];
    let (width, height) = (first.contents.image.width(), first.contents.image.height());
    let region = match args.region {
        Some(region) => Some(region),
        None => first
            .contents
            .metadata
            .get(keys::REGION)
            .and_then(|text| parse_region(text).ok()),
    };
    let mut accumulator = ReplicationAccumulator::new(width, height, region)
        .map_err(|error| usage(format!("--region: {error}")))?;
    for part in &parts {
        accumulator
            .add(part.index, &part.contents.image)
            .map_err(|error| usage(format!("{}: {error}", part.path.display())))?;
    }
    let estimate = accumulator.estimate();

    // The first part's metadata, with what describes the merge.
    let mut metadata = first.contents.metadata.clone();
    for key in [
        keys::REPLICATION_SEED,
        keys::RELATIVE_ERROR,
        keys::RELATIVE_RMSE,
        keys::STANDARD_ERROR,
        keys::REGION_MEAN,
        keys::REGION,
    ] {
        metadata.remove(key);
    }
    let indices = accumulator.indices();
    metadata.insert(keys::INDICES.into(), format_indices(&indices));
    let sum = |key: &str| -> Option<f64> {
        parts
            .iter()
            .map(|part| part.contents.metadata.get(key)?.parse::<f64>().ok())
            .sum()
    };
    if let Some(spp) = sum("spp") {
        metadata.insert("spp".into(), format!("{spp}"));
    }
    if let Some(seconds) = sum("renderTimeSeconds") {
        metadata.insert("renderTimeSeconds".into(), format!("{seconds:.3}"));
    }
    let region_used = region.unwrap_or([0, 0, width, height]);
    insert_estimate(&mut metadata, &estimate, region_used);
    let image = accumulator.mean_image();
    let variance = if accumulator.count() >= 2 {
        accumulator.variance_image()
    } else {
        first
            .contents
            .layers
            .get(VARIANCE_LAYER)
            .cloned()
            .unwrap_or_else(|| Image::new(width, height))
    };
    let failed = |error: render::image::ImageError| CliError::Failure(error.to_string());
    write_exr(
        &args.output,
        &image,
        &[(VARIANCE_LAYER, &variance)],
        &metadata,
    )
    .map_err(failed)?;
    let png = args.output.with_extension("png");
    write_png(&png, &image, args.exposure, &metadata).map_err(failed)?;

    let set = first
        .contents
        .metadata
        .get(keys::SET)
        .cloned()
        .unwrap_or_default();
    let missing = set
        .parse::<u64>()
        .ok()
        .map(|size| {
            (0..size)
                .filter(|index| indices.binary_search(index).is_err())
                .collect::<Vec<_>>()
        })
        .filter(|missing| !missing.is_empty())
        .map(|missing| format!("; not merged: {}", format_indices(&missing)))
        .unwrap_or_default();
    say!(
        "merged {} replication{} ({}) of a set of {set}{missing}: {} {}x{height}, {} samples per pixel in all",
        indices.len(),
        if indices.len() == 1 { "" } else { "s" },
        format_indices(&indices),
        first
            .contents
            .metadata
            .get("scene")
            .map_or("?", String::as_str),
        width,
        metadata.get("spp").map_or("?", String::as_str),
    );
    let whole_image = [0, 0, width, height];
    say!(
        "{}",
        describe_estimate(
            &estimate,
            Some(region_used).filter(|used| *used != whole_image)
        )
    );
    say!("wrote {} and {}", args.output.display(), png.display());
    Ok(())
}

//! Renders made of independent replications on the command line: which
//! replications `lqmc render` is asked for (`--replications R`,
//! `--replication I/R`, `--target-error E`), the metadata that ties a part
//! to its set, and the error line printed at the end. The statistics are
//! `render::replication`'s.

use crate::error::{CliError, usage};
use render::image::Metadata;
use render::renderer::RenderSettings;
use render::replication::{ErrorEstimate, PixelRegion};

/// Metadata keys of a render of replications.
pub mod keys {
    /// The size `R` of the replication set the render belongs to (`open`
    /// for a render to a target error, whose set has no fixed size).
    pub const SET: &str = "replicationSet";
    /// The replications the image is the mean of, e.g. `0-3,6`.
    pub const INDICES: &str = "replicationIndices";
    /// Samples per pixel of one replication (`time` for time-limited ones).
    pub const SAMPLES_PER_REPLICATION: &str = "replicationSpp";
    /// The seed of a single replication (the render's `seed` is the base).
    pub const REPLICATION_SEED: &str = "replicationSeed";
    /// Everything that must agree for replications to be merged.
    pub const SETTINGS: &str = "replicationSettings";
    /// A hash of [`SETTINGS`].
    pub const SETTINGS_HASH: &str = "replicationSettingsHash";
    /// The estimated relative standard error of the region's mean.
    pub const RELATIVE_ERROR: &str = "relativeStandardError";
    /// The expected relative RMSE of the region's pixels.
    pub const RELATIVE_RMSE: &str = "relativeRmse";
    /// The region's mean luminance and its standard error.
    pub const REGION_MEAN: &str = "regionMeanLuminance";
    /// Its standard error.
    pub const STANDARD_ERROR: &str = "regionStandardError";
    /// The region the error is measured over, `x,y,w,h`.
    pub const REGION: &str = "errorRegion";
}

/// The replications a render is split into, outside one render's passes.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplicationRequest {
    /// The first replication's index.
    pub first: u64,
    /// Replications to render (with a target: at least this many).
    pub count: u64,
    /// The set's size `R`; `None` for a render to a target error.
    pub set_size: Option<u64>,
    /// Samples per pixel of each replication; `None` when time limits them.
    pub samples_per_replication: Option<u64>,
    /// Stop at this relative standard error.
    pub target_error: Option<f64>,
}

impl ReplicationRequest {
    /// True for one replication of a larger set (`--replication I/R`).
    pub fn is_part(&self) -> bool {
        self.count == 1 && self.set_size.is_some_and(|size| size > 1)
    }
}

/// Parses `I/R` of `--replication`.
pub fn parse_replication(text: &str) -> Result<(u64, u64), String> {
    let parsed = text.split_once('/').and_then(|(index, count)| {
        Some((
            index.trim().parse::<u64>().ok()?,
            count.trim().parse::<u64>().ok()?,
        ))
    });
    match parsed {
        Some((index, count)) if count >= 1 && index < count => Ok((index, count)),
        Some((index, count)) => Err(format!(
            "replication {index} of {count} does not exist (expected I/R with 0 <= I < R)"
        )),
        None => Err(format!("expected I/R (e.g. 3/8), got '{text}'")),
    }
}

/// Parses `x,y,w,h` of `--target-region`.
pub fn parse_region(text: &str) -> Result<PixelRegion, String> {
    let values: Vec<usize> = text
        .split(',')
        .map(|value| value.trim().parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected x,y,w,h (four non-negative integers), got '{text}'"))?;
    match values.as_slice() {
        [x, y, width, height] if *width > 0 && *height > 0 => Ok([*x, *y, *width, *height]),
        [_, _, _, _] => Err(format!("the region '{text}' is empty")),
        _ => Err(format!(
            "expected x,y,w,h (four non-negative integers), got '{text}'"
        )),
    }
}

/// What the replication options ask for.
pub struct ReplicationOptions {
    /// `--replications R` (without `--pattern-size`).
    pub replications: Option<u64>,
    /// `--replication I/R`.
    pub replication: Option<(u64, u64)>,
    /// `--target-error E`.
    pub target_error: Option<f64>,
    /// `--spp N`: the samples per pixel of the whole set.
    pub samples_per_pixel: Option<u64>,
    /// Whether `--time` is given.
    pub timed: bool,
}

/// The replications to render, if the options split the render into
/// independent replications; `default_spp` is the scene's suggestion (or
/// 16). `--spp` counts the whole set's samples per pixel, each replication
/// rendering its share.
pub fn replication_request(
    options: &ReplicationOptions,
    default_spp: u64,
) -> Result<Option<ReplicationRequest>, CliError> {
    if options.replication.is_some() && options.replications.is_some() {
        return Err(usage(
            "--replication I/R renders one replication of R; --replications R renders them all: give one",
        ));
    }
    if options.replication.is_some() && options.target_error.is_some() {
        return Err(usage(
            "--target-error decides how many replications to render; it cannot be one part of a set (--replication)",
        ));
    }
    if let Some(error) = options.target_error
        && !(error > 0.0 && error.is_finite())
    {
        return Err(usage(format!(
            "--target-error must be a positive relative error (0.01 is 1 %), got {error}"
        )));
    }
    let (first, count, set_size) = match (options.replication, options.replications) {
        (Some((index, set)), _) => (index, 1, Some(set)),
        (None, Some(count)) => (0, count, options.target_error.is_none().then_some(count)),
        // A render to a target starts with four replications: the first
        // estimate of the error needs a few.
        (None, None) if options.target_error.is_some() => (0, 4, None),
        (None, None) => return Ok(None),
    };
    if options.target_error.is_some() && count < 2 {
        return Err(usage(
            "--target-error needs at least 2 replications to estimate the error (--replications)",
        ));
    }
    let split = set_size.unwrap_or(count);
    let total = match (options.samples_per_pixel, options.timed) {
        (Some(spp), _) => Some(spp),
        // Time-limited replications: each gets its share of the time.
        (None, true) if options.target_error.is_none() => None,
        (None, _) => Some(default_spp),
    };
    let samples_per_replication = match total {
        Some(spp) if spp % split != 0 => {
            return Err(usage(format!(
                "{spp} samples per pixel do not split into {split} replications: --spp must be a multiple of R (each replication renders spp / R)"
            )));
        }
        Some(spp) => Some(spp / split),
        None => None,
    };
    Ok(Some(ReplicationRequest {
        first,
        count,
        set_size,
        samples_per_replication,
        target_error: options.target_error,
    }))
}

/// Everything that must agree for two replications to belong to one
/// render: scene, parameters, resolution and every setting that changes
/// the image, except the seed (stored apart) and the thread count (which
/// changes nothing).
pub fn settings_fingerprint(
    scene_name: &str,
    definitions: &[(String, String)],
    resolution: [u32; 2],
    settings: &RenderSettings,
) -> String {
    format!(
        "scene={scene_name}; defines={definitions:?}; resolution={}x{}; integrator={:?}; sampler={}; randomization={}; pattern={:?}; spp={}; time={:?}; max_depth={}; rr_depth={}; mis={:?}; splat_film={}; tile={}",
        resolution[0],
        resolution[1],
        settings.integrator,
        settings.sampler.name(),
        settings.randomization.name(),
        settings.pattern_size,
        settings.samples_per_pixel,
        settings.time_budget.map(|time| time.as_secs_f64()),
        settings.max_depth,
        settings.russian_roulette_depth,
        settings.heuristic,
        settings.splat_film,
        settings.tile_size,
    )
}

/// FNV-1a (64 bit) of `text`, as 16 hexadecimal digits: a short check
/// that two fingerprints agree.
pub fn fingerprint_hash(text: &str) -> String {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.bytes() {
        hash ^= u64::from(byte);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{hash:016x}")
}

/// `indices` (ascending) as ranges: `0-3,6,8-9`.
pub fn format_indices(indices: &[u64]) -> String {
    let mut parts = Vec::new();
    let mut position = 0;
    while position < indices.len() {
        let start = indices[position];
        let mut end = start;
        while position + 1 < indices.len() && indices[position + 1] == end + 1 {
            position += 1;
            end += 1;
        }
        parts.push(if start == end {
            start.to_string()
        } else {
            format!("{start}-{end}")
        });
        position += 1;
    }
    parts.join(",")
}

/// The indices of `0-3,6,8-9`.
pub fn parse_indices(text: &str) -> Option<Vec<u64>> {
    let mut indices = Vec::new();
    for part in text.split(',') {
        match part.split_once('-') {
            Some((start, end)) => {
                let (start, end) = (start.parse::<u64>().ok()?, end.parse::<u64>().ok()?);
                if end < start || end - start > 1 << 24 {
                    return None;
                }
                indices.extend(start..=end);
            }
            None => indices.push(part.parse().ok()?),
        }
    }
    Some(indices)
}

/// Adds the error estimate to `metadata`.
pub fn insert_estimate(metadata: &mut Metadata, estimate: &ErrorEstimate, region: PixelRegion) {
    if estimate.is_estimated() {
        metadata.insert(
            keys::RELATIVE_ERROR.into(),
            format!("{:.6e}", estimate.relative_error()),
        );
        metadata.insert(
            keys::STANDARD_ERROR.into(),
            format!("{:.6e}", estimate.standard_error),
        );
        metadata.insert(
            keys::RELATIVE_RMSE.into(),
            format!("{:.6e}", estimate.pixel_relative_error),
        );
    }
    metadata.insert(
        keys::REGION_MEAN.into(),
        format!("{:.9e}", estimate.region_mean),
    );
    metadata.insert(
        keys::REGION.into(),
        format!("{},{},{},{}", region[0], region[1], region[2], region[3]),
    );
}

/// The line printed about the error of a render of replications.
pub fn describe_estimate(estimate: &ErrorEstimate, region: Option<PixelRegion>) -> String {
    let what = match region {
        Some([x, y, width, height]) => format!("the mean of region {x},{y},{width},{height}"),
        None => "the image mean".to_string(),
    };
    if !estimate.is_estimated() {
        return format!(
            "one replication, so no estimate of its error ({what} is {:.6}; --replications R renders R independent ones)",
            estimate.region_mean
        );
    }
    format!(
        "relative standard error of {what} {:.3} % (mean luminance {:.6} ± {:.6}, from {} independent replications); expected relative RMSE per pixel {:.2} %",
        100.0 * estimate.relative_error(),
        estimate.region_mean,
        estimate.standard_error,
        estimate.replications,
        100.0 * estimate.pixel_relative_error,
    )
}

/// The relative standard error of the mean of `values` (their standard
/// deviation over `√n`, over their mean), if there are at least two.
pub fn relative_standard_error(values: &[f64]) -> Option<f64> {
    let count = values.len() as f64;
    if values.len() < 2 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / count;
    let variance = values
        .iter()
        .map(|value| (value - mean).powi(2))
        .sum::<f64>()
        / (count - 1.0);
    Some((variance / count).sqrt() / mean.abs())
}

/// What the error of one render (no `--replications`) can be estimated
/// from.
pub struct ErrorEvidence<'a> {
    /// The mean luminance of each of the render's batches (Kollig & Keller's
    /// replications, passes, groups of chains); empty without batches.
    pub batch_means: &'a [f64],
    /// What the batches are, e.g. `independent passes`.
    pub batches: &'a str,
    /// Whether the batches are independent.
    pub independent: bool,
    /// Whether the variance layer is an estimate (from at least two
    /// batches or samples per pixel).
    pub variance_estimated: bool,
}

/// The line printed about the error of one render: the image mean's
/// relative standard error from the render's batches (if there are two or
/// more), and the root mean square of the per-pixel standard errors its
/// variance layer estimates over the mean pixel value (if it is an
/// estimate and the image is not black); `None` when the render has no
/// estimate of its error.
pub fn describe_single_render_error(
    image: &render::image::Image,
    variance: &render::image::Image,
    evidence: &ErrorEvidence,
) -> Option<String> {
    let channel_mean = |image: &render::image::Image| {
        image
            .pixels()
            .iter()
            .flatten()
            .map(|value| f64::from(*value))
            .sum::<f64>()
            / (3 * image.pixels().len()).max(1) as f64
    };
    let (mean, variance_mean) = (channel_mean(image), channel_mean(variance));
    let batches = evidence.batches;
    let count = evidence.batch_means.len();
    let image_mean = relative_standard_error(evidence.batch_means).map(|error| {
        if evidence.independent {
            format!(
                "relative standard error of the image mean {:.3} % (from {count} {batches})",
                100.0 * error
            )
        } else {
            format!(
                "relative standard error of the image mean about {:.3} % (from {count} {batches}, which the sampler's QMC points correlate: --replications R gives an unbiased estimate)",
                100.0 * error
            )
        }
    });
    let per_pixel = (evidence.variance_estimated && mean != 0.0).then(|| {
        format!(
            "expected relative RMSE per pixel {:.2} % (from the variance layer)",
            100.0 * variance_mean.sqrt() / mean.abs()
        )
    });
    let parts: Vec<String> = image_mean.into_iter().chain(per_pixel).collect();
    (!parts.is_empty()).then(|| parts.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(
        replications: Option<u64>,
        replication: Option<(u64, u64)>,
        target_error: Option<f64>,
        spp: Option<u64>,
    ) -> ReplicationOptions {
        ReplicationOptions {
            replications,
            replication,
            target_error,
            samples_per_pixel: spp,
            timed: false,
        }
    }

    #[test]
    fn indices_round_trip_as_ranges() {
        for indices in [vec![0, 1, 2, 3], vec![5], vec![0, 2, 3, 4, 9, 11, 12]] {
            let text = format_indices(&indices);
            assert_eq!(parse_indices(&text), Some(indices));
        }
        assert_eq!(format_indices(&[0, 1, 2, 3, 6]), "0-3,6");
        assert_eq!(parse_indices("3-1"), None);
        assert_eq!(parse_indices("x"), None);
    }

    #[test]
    fn replication_and_region_options_parse_and_refuse_nonsense() {
        assert_eq!(parse_replication("3/8"), Ok((3, 8)));
        assert!(parse_replication("8/8").is_err());
        assert!(parse_replication("3").is_err());
        assert_eq!(parse_region("1,2,3,4"), Ok([1, 2, 3, 4]));
        assert!(parse_region("1,2,0,4").is_err());
        assert!(parse_region("1,2,3").is_err());
    }

    #[test]
    fn spp_counts_the_whole_set() {
        let part = replication_request(&options(None, Some((3, 8)), None, Some(64)), 16)
            .unwrap()
            .unwrap();
        assert_eq!((part.first, part.count, part.set_size), (3, 1, Some(8)));
        assert_eq!(part.samples_per_replication, Some(8));
        assert!(part.is_part());
        let whole = replication_request(&options(Some(4), None, None, None), 16)
            .unwrap()
            .unwrap();
        assert_eq!(whole.samples_per_replication, Some(4));
        let target = replication_request(&options(None, None, Some(0.01), Some(32)), 16)
            .unwrap()
            .unwrap();
        assert_eq!((target.count, target.set_size), (4, None));
        assert_eq!(target.samples_per_replication, Some(8));
        assert!(
            replication_request(&options(None, None, None, Some(8)), 16)
                .unwrap()
                .is_none()
        );
        for bad in [
            options(Some(3), None, None, Some(16)),
            options(Some(4), Some((0, 4)), None, Some(16)),
            options(None, Some((0, 4)), Some(0.01), Some(16)),
            options(None, None, Some(-1.0), Some(16)),
            options(Some(1), None, Some(0.01), Some(16)),
        ] {
            assert!(replication_request(&bad, 16).is_err());
        }
    }

    #[test]
    fn relative_standard_error_of_a_mean() {
        assert_eq!(relative_standard_error(&[1.0]), None);
        // Mean 2, sample variance 1, over √3.
        let error = relative_standard_error(&[1.0, 2.0, 3.0]).unwrap();
        assert!((error - (1.0f64 / 3.0).sqrt() / 2.0).abs() < 1e-12);
    }

    /// The error line says what it measured, or nothing without an
    /// estimate; it is never labelled an error.
    #[test]
    fn single_render_error_line_says_what_it_measured_or_nothing() {
        let image = render::image::Image::from_pixels(2, 1, vec![[1.0; 3], [3.0; 3]]).unwrap();
        let variance = render::image::Image::from_pixels(2, 1, vec![[0.04; 3]; 2]).unwrap();
        let evidence = |batch_means, variance_estimated| ErrorEvidence {
            batch_means,
            batches: "independent passes",
            independent: true,
            variance_estimated,
        };
        assert_eq!(
            describe_single_render_error(&image, &variance, &evidence(&[], false)),
            None
        );
        assert_eq!(
            describe_single_render_error(&image, &variance, &evidence(&[2.0], false)),
            None
        );
        let per_pixel =
            describe_single_render_error(&image, &variance, &evidence(&[], true)).unwrap();
        assert_eq!(
            per_pixel,
            "expected relative RMSE per pixel 10.00 % (from the variance layer)"
        );
        let both =
            describe_single_render_error(&image, &variance, &evidence(&[1.0, 3.0], true)).unwrap();
        assert!(
            both.starts_with("relative standard error of the image mean 50.000 % (from 2 independent passes); expected relative RMSE per pixel"),
            "{both}"
        );
        assert!(!both.contains("error:"), "{both}");
    }

    #[test]
    fn fingerprint_hash_is_fnv1a() {
        // FNV-1a 64 of "a" (the published test vector).
        assert_eq!(fingerprint_hash("a"), "af63dc4c8601ec8c");
    }
}

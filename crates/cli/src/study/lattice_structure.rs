//! `lqmc study lattice-structure`: does LQMC's error show the lattice? The
//! scene is rendered with LQMC once per lattice scramble (`none`, `image`,
//! `all`; `--lattice-scramble`) and seed, at the same samples per pixel, and
//! each render's error against a reference is measured for structure
//! beyond white noise: its radially averaged power spectrum, the largest
//! off-axis peak of the spectrum over the median at its radius, and the
//! autocorrelation summed over small lags (see [`super::error_structure`]),
//! with the RMSE. A scramble changes only the explorations' lattice
//! mapping: with one seed the seed paths are the same under every
//! scramble, so the seeds pair the scrambles.
//!
//! The measures are computed from the EXR files the study writes, read
//! back, so that the table can be recomputed from the images beside it.

use super::StudySceneArgs;
use super::crops::{CropRectangle, write_crop_strip};
use super::equal_time::prepare_output_directory;
use super::error_plot::{ErrorCurve, ErrorPoint, write_error_plot};
use super::error_structure::{
    ErrorStructure, MIN_RING_FREQUENCIES, SpectrumStructure, error_structure, luminance_error,
    mean_spectrum, ring_count, ring_frequency, spectrum_structure, white_noise_structure,
};
use super::formatting::{
    command_line, format_significant, load_average, shown_path, spread_json, spread_text,
    utc_timestamp,
};
use super::measures::{Spread, spread};
use super::study_renders::{
    RenderContext, definitions_text, print_report, read_reference, read_study_image,
    stop_on_interrupt, write_tables,
};
use crate::error::{CliError, usage};
use crate::integrator_options::ownership::check_study_options;
use crate::json::Json;
use crate::render_command::{build_scene, load_scene_description};
use clap::{ArgMatches, Args};
use render::image::Image;
use render::image::compare::compare_images;
use render::integrators::lqmc::{LatticeScramble, LqmcDetails, LqmcSettings, PathClass};
use render::integrators::{IntegratorKind, IntegratorSettings};
use render::sampler::SamplerKind;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Arguments of `lqmc study lattice-structure`.
#[derive(Args, Debug)]
pub struct LatticeStructureArgs {
    #[command(flatten)]
    pub scene: StudySceneArgs,
    /// The reference image (.exr or .pfm) at the study's resolution, e.g.
    /// a path tracer's render of many samples (`lqmc render SCENE
    /// --integrator path --spp 4096`).
    #[arg(long, value_name = "REF.exr")]
    pub reference: PathBuf,
    /// Samples per pixel of every render.
    #[arg(long, value_name = "N")]
    pub spp: u64,
    /// The lattice scrambles compared, comma-separated among none, image
    /// and all.
    #[arg(long, value_name = "LIST", default_value = "none,image,all")]
    pub scrambles: String,
    /// Renders per scramble, with seeds 0..K.
    #[arg(long, value_name = "K", default_value_t = 3)]
    pub seeds: u64,
    /// The largest lag (in pixels, along each axis) of the autocorrelation
    /// sum.
    #[arg(long, value_name = "L", default_value_t = 2)]
    pub max_lag: usize,
    /// The crop of crops.png, X,Y,W,H in pixels (default: a centred square
    /// of side min(width, height)/2).
    #[arg(long, value_name = "X,Y,W,H")]
    pub crop: Option<String>,
    /// The output directory.
    #[arg(
        short,
        long,
        value_name = "DIR",
        default_value = "study-lattice-structure"
    )]
    pub output: PathBuf,
    /// No progress lines on stderr.
    #[arg(long)]
    pub quiet: bool,
}

/// One render of the study, as it ran.
struct RenderRecord {
    scramble: LatticeScramble,
    seed: u64,
    /// The image, relative to the output directory.
    image: String,
    seconds: f64,
    /// LQMC's explorations and valid members (all classes).
    explorations: u64,
    valid_members: u64,
}

/// One render's measures, from its image as written.
struct SeedMeasures<'a> {
    record: &'a RenderRecord,
    rmse: f64,
    structure: ErrorStructure,
}

/// The structure measures of several error images (the seeds' renders of
/// one scramble, or white-noise images), summarised.
struct StructureSummary {
    /// Per seed's peak ratio: median and range.
    peak_ratio: Spread,
    /// Per seed's autocorrelation sum: median and range.
    autocorrelation_sum: Spread,
    /// Per ring, the median over the seeds of the radial power, and the range.
    radial_power: Vec<Spread>,
    /// The radial average and the peak of the seeds' mean spectrum.
    mean_spectrum: SpectrumStructure,
}

impl StructureSummary {
    /// The summary of `structures`, of `width`×`height` images.
    fn of(structures: &[&ErrorStructure], width: usize, height: usize) -> Self {
        let values = |measure: fn(&ErrorStructure) -> f64| {
            spread(
                &structures
                    .iter()
                    .map(|structure| measure(structure))
                    .collect::<Vec<_>>(),
            )
        };
        let mean = mean_spectrum(
            structures
                .iter()
                .map(|structure| structure.spectrum.as_slice()),
        );
        Self {
            peak_ratio: values(|structure| structure.structure.peak_ratio),
            autocorrelation_sum: values(|structure| structure.autocorrelation_sum),
            radial_power: (0..ring_count(width, height))
                .map(|ring| {
                    spread(
                        &structures
                            .iter()
                            .map(|structure| structure.structure.radial_power[ring])
                            .collect::<Vec<_>>(),
                    )
                })
                .collect(),
            mean_spectrum: spectrum_structure(&mean, width, height),
        }
    }
}

/// The measures of one scramble over the seeds.
struct Row<'a> {
    scramble: LatticeScramble,
    seeds: Vec<SeedMeasures<'a>>,
    rmse: Spread,
    structure: StructureSummary,
}

/// What the report says about how the study ran.
struct StudyConditions {
    scene: String,
    resolution: (usize, usize),
    threads: usize,
    seeds: u64,
    samples_per_pixel: u64,
    max_lag: usize,
    reference: String,
    explored_classes: String,
    crop: CropRectangle,
    started: String,
    finished: String,
    load_at_start: String,
    load_at_end: String,
    command: String,
}

/// Parses `--scrambles`: distinct names among none, image, all.
fn parse_scrambles(list: &str) -> Result<Vec<LatticeScramble>, CliError> {
    let known = || {
        LatticeScramble::ALL
            .iter()
            .map(|(_, name)| *name)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut scrambles = Vec::new();
    for name in list
        .split(',')
        .map(str::trim)
        .filter(|name| !name.is_empty())
    {
        let scramble = LatticeScramble::from_name(name).ok_or_else(|| {
            usage(format!(
                "--scrambles: unknown scramble `{name}` (known: {})",
                known()
            ))
        })?;
        if scrambles.contains(&scramble) {
            return Err(usage(format!("--scrambles: `{name}` is listed twice")));
        }
        scrambles.push(scramble);
    }
    if scrambles.is_empty() {
        return Err(usage(format!(
            "--scrambles needs at least one of {}",
            known()
        )));
    }
    Ok(scrambles)
}

/// The file name of a render's image (relative to the output directory).
fn image_name(scramble: LatticeScramble, seed: u64) -> String {
    format!("images/{}-seed{seed}.exr", scramble.name())
}

/// The classes LQMC explores with their lattice sizes, e.g. `normal (N =
/// 313), caustic (N = 97)`.
fn explored_classes_text(settings: &LqmcSettings) -> String {
    let explored: Vec<String> = PathClass::ALL
        .iter()
        .map(|&class| (class, settings.class_parameters(class)))
        .filter(|(_, parameters)| parameters.explore)
        .map(|(class, parameters)| format!("{} (N = {})", class.name(), parameters.lattice_size))
        .collect();
    if explored.is_empty() {
        "none".into()
    } else {
        explored.join(", ")
    }
}

/// Runs `lqmc study lattice-structure`; `matches` are its arguments as
/// clap parsed them.
pub fn run(args: &LatticeStructureArgs, matches: &ArgMatches) -> Result<(), CliError> {
    args.scene.validate()?;
    if args.seeds == 0 {
        return Err(usage("--seeds must be at least 1"));
    }
    if args.spp == 0 {
        return Err(usage("--spp must be at least 1"));
    }
    if args.max_lag == 0 {
        return Err(usage("--max-lag must be at least 1"));
    }
    if args.scene.integrators.lqmc.lattice_scramble.is_some() {
        return Err(usage(
            "--lattice-scramble is what the study varies: list the scrambles with --scrambles",
        ));
    }
    let scrambles = parse_scrambles(&args.scrambles)?;
    check_study_options(matches, &[IntegratorKind::Lqmc])?;
    let description = load_scene_description(
        &args.scene.scene,
        &args.scene.define,
        args.scene.resolution,
        args.quiet,
    )?;
    let [width, height] = description.camera.resolution;
    let (width, height) = (width as usize, height as usize);
    let crop = match &args.crop {
        Some(text) => CropRectangle::parse(text, width, height)?,
        None => CropRectangle::centred_square(width, height),
    };
    let reference = read_reference(&args.reference, width, height)?;
    let IntegratorSettings::Lqmc(lqmc) = args.scene.integrators.settings(IntegratorKind::Lqmc)?
    else {
        unreachable!("LQMC's options give LQMC's settings");
    };
    let scene = build_scene(&args.scene.scene, &description)?;
    prepare_output_directory(&args.output)?;

    let stop = stop_on_interrupt();
    let context = RenderContext {
        scene_args: &args.scene,
        scene: &scene,
        stop: &stop,
        definitions: definitions_text(&args.scene.define),
    };
    let started = utc_timestamp(SystemTime::now());
    let load_at_start = load_average();
    // Seeds outermost: a change of load hits every scramble alike.
    let total = args.seeds as usize * scrambles.len();
    let mut records = Vec::with_capacity(total);
    for seed in 0..args.seeds {
        for &scramble in &scrambles {
            let mut settings = lqmc;
            settings.lattice_scramble = scramble;
            let mut request = context.request(
                IntegratorSettings::Lqmc(settings),
                SamplerKind::Halton,
                seed,
                args.scene.threads,
            );
            request.samples_per_pixel = Some(args.spp);
            let name = image_name(scramble, seed);
            let written = context.render_to(
                &request.settings(&scene),
                &args.output.join(&name),
                &[("latticeScramble", scramble.name().to_string())],
            )?;
            let statistics = written
                .details
                .as_ref()
                .and_then(|details| details.as_any().downcast_ref::<LqmcDetails>())
                .map(|details| details.statistics)
                .unwrap_or_default();
            if !args.quiet {
                let rmse = compare_images(&written.image, &reference, None)
                    .map(|comparison| format_significant(comparison.rmse, 4))
                    .unwrap_or_else(|_| "—".into());
                eprintln!(
                    "[{}/{total}] seed {seed}, scramble {}: {} spp in {:.3} s, {} explorations, RMSE {rmse}",
                    records.len() + 1,
                    scramble.name(),
                    args.spp,
                    written.seconds,
                    statistics.explorations.iter().sum::<u64>(),
                );
            }
            records.push(RenderRecord {
                scramble,
                seed,
                image: name,
                seconds: written.seconds,
                explorations: statistics.explorations.iter().sum(),
                valid_members: statistics.valid_members.iter().sum(),
            });
        }
    }
    let finished = utc_timestamp(SystemTime::now());
    let load_at_end = load_average();

    let rows = measure_rows(&records, &scrambles, &reference, args, (width, height))?;
    // White noise, one image per seed, for the scale of every measure.
    let white_images: Vec<ErrorStructure> = (0..args.seeds)
        .map(|stream| white_noise_structure(width, height, args.max_lag, stream))
        .collect();
    let white = StructureSummary::of(&white_images.iter().collect::<Vec<_>>(), width, height);
    let conditions = StudyConditions {
        scene: args.scene.scene.clone(),
        resolution: (width, height),
        threads: args.scene.effective_threads(),
        seeds: args.seeds,
        samples_per_pixel: args.spp,
        max_lag: args.max_lag,
        reference: shown_path(&args.reference),
        explored_classes: explored_classes_text(&lqmc),
        crop,
        started,
        finished,
        load_at_start,
        load_at_end,
        command: command_line(),
    };
    let markdown = markdown_table(&conditions, &rows, &white);
    let (table_md, table_json) = write_tables(
        &args.output,
        &markdown,
        &json_table(&conditions, &rows, &white),
    )?;
    let svg = args.output.join("spectrum.svg");
    let png = args.output.join("spectrum.png");
    write_error_plot(
        &svg,
        &png,
        &format!(
            "{} {width}x{height}, {} spp, {} seeds: luminance error",
            conditions.scene, conditions.samples_per_pixel, conditions.seeds
        ),
        "frequency (cycles per pixel)",
        "radially averaged power (median over seeds; bars: min to max)",
        &spectrum_curves(&rows, width, height),
    )?;
    let crops = args.output.join("crops.png");
    write_crops(&crops, &conditions, &reference, &records, &args.output)?;

    print_report(
        &markdown,
        &[&table_md, &table_json, &svg, &png, &crops],
        &args.output.join("images"),
    );
    Ok(())
}

/// The measures of every scramble, from the images as written.
fn measure_rows<'a>(
    records: &'a [RenderRecord],
    scrambles: &[LatticeScramble],
    reference: &Image,
    args: &LatticeStructureArgs,
    (width, height): (usize, usize),
) -> Result<Vec<Row<'a>>, CliError> {
    scrambles
        .iter()
        .map(|&scramble| {
            let seeds = records
                .iter()
                .filter(|record| record.scramble == scramble)
                .map(|record| {
                    let image = read_study_image(&args.output, &record.image)?;
                    let rmse = compare_images(&image, reference, None)
                        .map_err(|error| CliError::Failure(error.to_string()))?
                        .rmse;
                    let error = luminance_error(&image, reference);
                    Ok(SeedMeasures {
                        record,
                        rmse,
                        structure: error_structure(&error, width, height, args.max_lag),
                    })
                })
                .collect::<Result<Vec<_>, CliError>>()?;
            let structures: Vec<&ErrorStructure> =
                seeds.iter().map(|seed| &seed.structure).collect();
            Ok(Row {
                scramble,
                rmse: spread(&seeds.iter().map(|seed| seed.rmse).collect::<Vec<_>>()),
                structure: StructureSummary::of(&structures, width, height),
                seeds,
            })
        })
        .collect()
}

/// The markdown report: conditions, the table, the measures' definitions
/// and the command line.
fn markdown_table(
    conditions: &StudyConditions,
    rows: &[Row<'_>],
    white: &StructureSummary,
) -> String {
    let (width, height) = conditions.resolution;
    let mut text = format!(
        "# Lattice-structure study: {scene}\n\n\
         Scene {scene} at {width}x{height}, LQMC with Halton seeds at {spp} spp, {threads} thread(s) per render, \
         explored classes {classes}; seeds 0 to {last_seed} per lattice scramble (one seed gives every scramble the \
         same seed paths); renders interleaved (seed, then scramble). Reference: the image {reference}. Measured \
         {started} to {finished}; load average (1/5/15 min) {load_start} at the start, {load_end} at the end. Each \
         entry is the median over the seeds with [min, max].\n\n",
        scene = conditions.scene,
        spp = conditions.samples_per_pixel,
        threads = conditions.threads,
        classes = conditions.explored_classes,
        last_seed = conditions.seeds - 1,
        reference = conditions.reference,
        started = conditions.started,
        finished = conditions.finished,
        load_start = conditions.load_at_start,
        load_end = conditions.load_at_end,
    );
    text += &format!(
        "| lattice scramble | RMSE | peak ratio | peak ratio of the mean spectrum | autocorrelation sum (lags ≤ {}) | explorations | valid members | seconds |\n",
        conditions.max_lag
    );
    text += "|---|---|---|---|---|---|---|---|\n";
    for row in rows {
        let median_of = |value: fn(&SeedMeasures<'_>) -> f64| {
            spread(&row.seeds.iter().map(value).collect::<Vec<_>>()).median
        };
        text += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} |\n",
            row.scramble.name(),
            spread_text(&row.rmse),
            spread_text(&row.structure.peak_ratio),
            format_significant(row.structure.mean_spectrum.peak_ratio, 4),
            spread_text(&row.structure.autocorrelation_sum),
            median_of(|seed| seed.record.explorations as f64),
            median_of(|seed| seed.record.valid_members as f64),
            format_significant(median_of(|seed| seed.record.seconds), 3),
        );
    }
    text += &format!(
        "| white noise, {} image(s) of this size | — | {} | {} | {} | — | — | — |\n",
        conditions.seeds,
        spread_text(&white.peak_ratio),
        format_significant(white.mean_spectrum.peak_ratio, 4),
        spread_text(&white.autocorrelation_sum),
    );
    let crop = conditions.crop;
    text += &format!(
        "\nMeasures, of the luminance error e = Y(render) − Y(reference) (Y = 0.2126 R + 0.7152 G + 0.0722 B; its \
         mean removed; non-finite pixels count 0): RMSE over pixels and the three channels, as `lqmc compare`; the \
         power spectrum P(k) = |DFT(e)|² / (W·H) (white noise of variance σ² gives σ² everywhere), averaged over \
         rings of width 1/{min_side} cycles per pixel (spectrum.svg, .png); **peak ratio**, the largest P(k) at \
         an off-axis frequency (neither component 0) over the median of P on its ring, over the rings of at least \
         {min_ring} frequencies up to ½ cycle per pixel: a pattern that repeats over the image makes a peak; the \
         same of the mean of the seeds' spectra, where a pattern every seed repeats at the same frequencies \
         stands out of the noise; \
         **autocorrelation sum**, Σ ρ(d) over the lags 0 < max(|dx|, |dy|) ≤ {lag}, ρ(d) = Σ e(x) e(x + d) / Σ e(x)² \
         over the pixel pairs inside the image: about 0 for white noise, positive for an error that comes in \
         blobs. The last row measures Gaussian white noise of the same size, one image per seed (fixed \
         pseudo-random streams). \
         Explorations and valid members: LQMC's counts over all classes (median over the seeds).\n\n\
         Files: images/SCRAMBLE-seedK.exr, table.json (every number, per seed too, and the radial spectra), \
         spectrum.svg and .png, crops.png (the crop {x},{y},{w},{h} of the reference, then of each scramble's \
         seed-0 render, enlarged {scale}×).\n\n\
         Command:\n\n```sh\n{command}\n```\n",
        min_side = width.min(height),
        min_ring = MIN_RING_FREQUENCIES,
        lag = conditions.max_lag,
        x = crop.x,
        y = crop.y,
        w = crop.width,
        h = crop.height,
        scale = crop.enlargement(),
        command = conditions.command,
    );
    text
}

/// The JSON of one error image's structure.
fn structure_json(structure: &ErrorStructure) -> Vec<(&'static str, Json)> {
    let mut fields = spectrum_json(&structure.structure);
    fields.push((
        "autocorrelation_sum",
        Json::Number(structure.autocorrelation_sum),
    ));
    fields
}

/// The JSON of a spectrum's radial average and peak.
fn spectrum_json(structure: &SpectrumStructure) -> Vec<(&'static str, Json)> {
    vec![
        ("peak_ratio", Json::Number(structure.peak_ratio)),
        ("peak_frequency", Json::numbers(&structure.peak_frequency)),
        ("radial_power", Json::numbers(&structure.radial_power)),
    ]
}

/// The JSON of a summary of several error images.
fn summary_json(summary: &StructureSummary) -> Vec<(&'static str, Json)> {
    vec![
        ("peak_ratio", spread_json(&summary.peak_ratio)),
        (
            "autocorrelation_sum",
            spread_json(&summary.autocorrelation_sum),
        ),
        (
            "radial_power_median",
            Json::numbers(
                &summary
                    .radial_power
                    .iter()
                    .map(|spread| spread.median)
                    .collect::<Vec<_>>(),
            ),
        ),
        (
            "mean_spectrum",
            Json::object(spectrum_json(&summary.mean_spectrum)),
        ),
    ]
}

/// The JSON report: the conditions and every number, per seed too.
fn json_table(conditions: &StudyConditions, rows: &[Row<'_>], white: &StructureSummary) -> Json {
    let (width, height) = conditions.resolution;
    let frequencies: Vec<f64> = (0..ring_count(width, height))
        .map(|ring| ring_frequency(ring, width, height))
        .collect();
    let rows_json = rows
        .iter()
        .map(|row| {
            let seeds = row
                .seeds
                .iter()
                .map(|seed| {
                    let record = seed.record;
                    let mut fields = vec![
                        ("seed", Json::Integer(record.seed)),
                        ("image", Json::String(record.image.clone())),
                        ("seconds", Json::Number(record.seconds)),
                        ("explorations", Json::Integer(record.explorations)),
                        ("valid_members", Json::Integer(record.valid_members)),
                        ("rmse", Json::Number(seed.rmse)),
                    ];
                    fields.extend(structure_json(&seed.structure));
                    Json::object(fields)
                })
                .collect();
            let mut fields = vec![
                ("scramble", Json::String(row.scramble.name().into())),
                ("seeds", Json::Array(seeds)),
                ("rmse", spread_json(&row.rmse)),
            ];
            fields.extend(summary_json(&row.structure));
            Json::object(fields)
        })
        .collect();
    let crop = conditions.crop;
    Json::object(vec![
        ("study", Json::String("lattice-structure".into())),
        ("scene", Json::String(conditions.scene.clone())),
        ("resolution", Json::integers(&[width as u64, height as u64])),
        ("threads", Json::Integer(conditions.threads as u64)),
        ("seeds", Json::Integer(conditions.seeds)),
        ("spp", Json::Integer(conditions.samples_per_pixel)),
        ("sampler", Json::String(SamplerKind::Halton.name().into())),
        (
            "explored_classes",
            Json::String(conditions.explored_classes.clone()),
        ),
        ("reference", Json::String(conditions.reference.clone())),
        ("max_lag", Json::Integer(conditions.max_lag as u64)),
        (
            "min_ring_frequencies",
            Json::Integer(MIN_RING_FREQUENCIES as u64),
        ),
        ("ring_frequencies", Json::numbers(&frequencies)),
        ("crop", crop.json()),
        ("started", Json::String(conditions.started.clone())),
        ("finished", Json::String(conditions.finished.clone())),
        (
            "load_average_start",
            Json::String(conditions.load_at_start.clone()),
        ),
        (
            "load_average_end",
            Json::String(conditions.load_at_end.clone()),
        ),
        ("rows", Json::Array(rows_json)),
        ("white_noise", Json::object(summary_json(white))),
        ("command", Json::String(conditions.command.clone())),
    ])
}

/// The plot's lines: each scramble's radial power per ring (ring 0, the
/// removed mean, left out), median over the seeds with the range.
fn spectrum_curves(rows: &[Row<'_>], width: usize, height: usize) -> Vec<ErrorCurve> {
    rows.iter()
        .map(|row| ErrorCurve {
            label: row.scramble.name().to_string(),
            points: row
                .structure
                .radial_power
                .iter()
                .enumerate()
                .skip(1)
                .filter(|(_, spread)| spread.min > 0.0)
                .map(|(ring, spread)| ErrorPoint {
                    x: ring_frequency(ring, width, height),
                    median: spread.median,
                    min: spread.min,
                    max: spread.max,
                })
                .collect(),
        })
        .collect()
}

/// Writes the strip of crops: the reference, then each scramble's render of
/// seed 0, tone-mapped as `lqmc render`'s PNG.
fn write_crops(
    path: &Path,
    conditions: &StudyConditions,
    reference: &Image,
    records: &[RenderRecord],
    directory: &Path,
) -> Result<(), CliError> {
    let first_seed: Vec<&RenderRecord> = records.iter().filter(|record| record.seed == 0).collect();
    let renders = first_seed
        .iter()
        .map(|record| read_study_image(directory, &record.image))
        .collect::<Result<Vec<_>, CliError>>()?;
    let panels: Vec<(String, &Image)> = std::iter::once(("reference".to_string(), reference))
        .chain(
            first_seed
                .iter()
                .map(|record| record.scramble.name().to_string())
                .zip(&renders),
        )
        .collect();
    write_crop_strip(path, &panels, conditions.crop, &[])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scramble_lists_parse_and_refuse_repeats() {
        assert_eq!(
            parse_scrambles("none, all").unwrap(),
            [LatticeScramble::None, LatticeScramble::All]
        );
        assert!(parse_scrambles("image,image").is_err());
        assert!(parse_scrambles("swap").is_err());
        assert!(parse_scrambles(",").is_err());
        assert_eq!(
            image_name(LatticeScramble::Image, 2),
            "images/image-seed2.exr"
        );
    }
}

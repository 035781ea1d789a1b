//! Fits the linear sRGB → spectrum coefficient table with the project's own
//! fitter ([`RgbToSpectrumTable::generate`]) and writes it in the format of
//! [`RgbToSpectrumTable::to_bytes`]: by default the table the renderer
//! embeds, `crates/render/data/spectra/srgb_to_spectrum_table_64.bin`.
//!
//! ```text
//! cargo run --release -p render --example rgb_to_spectrum_table -- [--resolution R] [-o FILE]
//! ```
//!
//! Run it from the repository root after changing the fitter; the unit test
//! `stored_table_is_what_the_fitter_produces` fails until the stored table
//! is regenerated.

use std::path::PathBuf;
use std::time::Instant;

use render::spectrum::{DEFAULT_RGB_TABLE_RESOLUTION, RgbToSpectrumTable};

/// Where the renderer's embedded table lives, relative to the repository root.
const DEFAULT_OUTPUT: &str = "crates/render/data/spectra/srgb_to_spectrum_table_64.bin";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut resolution = DEFAULT_RGB_TABLE_RESOLUTION;
    let mut output = PathBuf::from(DEFAULT_OUTPUT);
    let mut arguments = std::env::args().skip(1);
    while let Some(argument) = arguments.next() {
        match argument.as_str() {
            "--resolution" => {
                let value = arguments.next().ok_or("--resolution needs a value")?;
                resolution = value
                    .parse()
                    .map_err(|_| format!("--resolution: `{value}` is not a whole number"))?;
            }
            "-o" | "--output" => {
                output = PathBuf::from(arguments.next().ok_or("-o needs a file name")?);
            }
            other => {
                return Err(format!(
                    "unknown argument `{other}` (usage: [--resolution R] [-o FILE])"
                )
                .into());
            }
        }
    }
    let start = Instant::now();
    let table = RgbToSpectrumTable::generate(resolution)?;
    let bytes = table.to_bytes();
    std::fs::write(&output, &bytes)
        .map_err(|error| format!("cannot write {}: {error}", output.display()))?;
    println!(
        "fitted the R = {resolution} table in {:.2?}; wrote {} bytes to {}",
        start.elapsed(),
        bytes.len(),
        output.display()
    );
    Ok(())
}

//! The files a render writes: the image (EXR, PFM or PNG) and a PNG beside
//! it, LQMC's density and BDPT's strategy images; checked before anything
//! is rendered.

use crate::error::{CliError, usage};
use render::image::{Image, ImageError, ImageFormat, Metadata, write_exr, write_png};
use render::renderer::RenderOutput;
use std::path::{Path, PathBuf};

/// The format of the output `path` by its extension, or a usage error.
pub fn output_format(path: &Path) -> Result<ImageFormat, CliError> {
    ImageFormat::from_path(path).map_err(|_| {
        usage(format!(
            "cannot write {}: the output must end in .exr, .pfm or .png",
            path.display()
        ))
    })
}

/// A failure to write an image: not the user's input (status 1).
pub fn write_failure(error: ImageError) -> CliError {
    CliError::Failure(error.to_string())
}

/// Reports an output file that cannot be written before anything is
/// rendered: its directory must exist and take a new file.
pub fn check_writable(path: &Path) -> Result<(), CliError> {
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !directory.is_dir() {
        return Err(usage(format!(
            "cannot write {}: the directory {} does not exist",
            path.display(),
            directory.display()
        )));
    }
    let probe = directory.join(format!(".lqmc-write-check-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(error) => Err(usage(format!("cannot write {}: {error}", path.display()))),
    }
}

/// Creates the directory of `--strategy-images` (reported before rendering,
/// not after).
pub fn create_strategy_directory(directory: &Path) -> Result<(), CliError> {
    std::fs::create_dir_all(directory).map_err(|error| {
        usage(format!(
            "--strategy-images: cannot create {}: {error}",
            directory.display()
        ))
    })
}

/// Writes the PNG of `image` beside `output` unless the output is a PNG;
/// returns what it wrote.
pub fn write_png_beside(
    output: &Path,
    format: ImageFormat,
    image: &Image,
    exposure: f32,
    metadata: &Metadata,
) -> Result<Option<String>, CliError> {
    if format == ImageFormat::Png {
        return Ok(None);
    }
    let png = output.with_extension("png");
    write_png(&png, image, exposure, metadata).map_err(write_failure)?;
    Ok(Some(png.display().to_string()))
}

/// Writes LQMC's density image to `path` if the render made one; returns
/// what it wrote.
pub fn write_density(
    path: &Path,
    output: &RenderOutput,
    metadata: &Metadata,
) -> Result<Option<String>, CliError> {
    let Some(layers) = output.auxiliary_image("density") else {
        return Ok(None);
    };
    let named: Vec<(&str, &Image)> = layers[1..]
        .iter()
        .map(|(name, image)| (*name, image))
        .collect();
    write_exr(path, &layers[0].1, &named, metadata).map_err(write_failure)?;
    Ok(Some(path.display().to_string()))
}

/// Writes BDPT's strategy images into `directory` if the render made them;
/// returns what it wrote.
pub fn write_strategy_images(
    directory: &Path,
    output: &RenderOutput,
    metadata: &Metadata,
) -> Result<Option<String>, CliError> {
    let Some(layers) = output.auxiliary_image("strategies") else {
        return Ok(None);
    };
    for (name, image) in layers {
        write_exr(directory.join(format!("{name}.exr")), image, &[], metadata)
            .map_err(write_failure)?;
    }
    Ok(Some(format!(
        "{} strategy images in {}",
        layers.len(),
        directory.display()
    )))
}

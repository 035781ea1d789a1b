//! Render-time participating media from the scene description: the media
//! with their spectra and phase functions checked, and the media references
//! of shapes and of the camera checked against them.

use crate::medium::{HomogeneousMedium, MediumInterface, MediumSpectra, PhaseFunction};
use crate::scene::SceneError;
use crate::scene::description::{
    MediumCoefficients, MediumDescription, PhaseDescription, ShapeDescription,
};
use crate::scene::spectra::{SpectrumUsage, build_spectrum};

/// The description's media, in order.
pub(in crate::scene) fn media(
    descriptions: &[MediumDescription],
) -> Result<Vec<HomogeneousMedium>, SceneError> {
    descriptions
        .iter()
        .enumerate()
        .map(|(index, medium)| build_medium(medium, index))
        .collect()
}

/// The media on the two sides of shape `index`, `None` if it names none
/// (the ray keeps its medium when crossing it), checked against the
/// `media_count` media.
pub(in crate::scene) fn medium_interface(
    shape: &ShapeDescription,
    index: usize,
    media_count: usize,
) -> Result<Option<MediumInterface>, SceneError> {
    if shape.interior_medium.is_none() && shape.exterior_medium.is_none() {
        return Ok(None);
    }
    let what = || format!("shape {index}");
    Ok(Some(MediumInterface {
        interior: checked_medium(shape.interior_medium, media_count, what)?,
        exterior: checked_medium(shape.exterior_medium, media_count, what)?,
    }))
}

/// The camera's medium checked against the `media_count` media.
pub(in crate::scene) fn camera_medium(
    medium: Option<usize>,
    media_count: usize,
) -> Result<Option<u32>, SceneError> {
    checked_medium(medium, media_count, || "camera medium".into())
}

/// A medium reference as an index, or an error naming `what` if there are
/// only `media_count` media.
fn checked_medium(
    medium: Option<usize>,
    media_count: usize,
    what: impl FnOnce() -> String,
) -> Result<Option<u32>, SceneError> {
    match medium {
        Some(index) if index >= media_count => Err(SceneError::Parameter {
            what: what(),
            message: format!("medium {index} does not exist (the scene has {media_count})"),
        }),
        other => Ok(other.map(|index| index as u32)),
    }
}

/// The render-time medium of a description: spectra from colours (albedos
/// as reflectances, coefficients as unbounded quantities), checked scale
/// and phase parameter.
fn build_medium(
    description: &MediumDescription,
    index: usize,
) -> Result<HomogeneousMedium, SceneError> {
    let what = |name: &str| format!("medium {index} {name}");
    if !(description.scale.is_finite() && description.scale >= 0.0) {
        return Err(SceneError::Parameter {
            what: what("scale"),
            message: format!("must be finite and non-negative, not {}", description.scale),
        });
    }
    let spectra = match &description.coefficients {
        MediumCoefficients::AlbedoExtinction { albedo, sigma_t } => {
            MediumSpectra::AlbedoExtinction {
                albedo: build_spectrum(albedo, SpectrumUsage::Albedo, &what("albedo"))?,
                sigma_t: build_spectrum(sigma_t, SpectrumUsage::Unbounded, &what("sigma_t"))?,
            }
        }
        MediumCoefficients::AbsorptionScattering { sigma_a, sigma_s } => {
            MediumSpectra::AbsorptionScattering {
                sigma_a: build_spectrum(sigma_a, SpectrumUsage::Unbounded, &what("sigma_a"))?,
                sigma_s: build_spectrum(sigma_s, SpectrumUsage::Unbounded, &what("sigma_s"))?,
            }
        }
    };
    let phase = match description.phase {
        PhaseDescription::Isotropic => PhaseFunction::Isotropic,
        PhaseDescription::HenyeyGreenstein { g } => {
            if !(g.is_finite() && g > -1.0 && g < 1.0) {
                return Err(SceneError::Parameter {
                    what: what("phase function"),
                    message: format!("Henyey-Greenstein g must lie in (-1, 1), not {g}"),
                });
            }
            PhaseFunction::henyey_greenstein(g)
        }
    };
    Ok(HomogeneousMedium::new(spectra, description.scale, phase))
}

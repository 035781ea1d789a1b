//! Turning the scene description's [`SpectrumDescription`]s into
//! [`Spectrum`]s, according to what the quantity is ([`SpectrumUsage`]).

use super::SceneError;
use super::description::SpectrumDescription;
use crate::spectrum::{
    BlackbodyNormalisation, BlackbodySpectrum, CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, ConstantSpectrum,
    PiecewiseLinearSpectrum, RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum,
    Spectrum, d65_illuminant,
};

/// What a spectral quantity is: it decides how an RGB triple is lifted to a
/// spectrum (Jakob–Hanika sigmoid for reflectances, scaled sigmoid for
/// unbounded quantities, scaled sigmoid times D65 for illuminants).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpectrumUsage {
    /// A reflectance or transmittance in [0, 1].
    Albedo,
    /// A non-negative quantity that may exceed 1 (η, κ, σ).
    Unbounded,
    /// Emitted radiance, intensity or irradiance.
    Illuminant,
}

fn parameter_error(what: &str, error: impl std::fmt::Display) -> SceneError {
    SceneError::Parameter {
        what: what.to_string(),
        message: error.to_string(),
    }
}

/// The spectrum a description stands for, used as `usage`; `what` names the
/// parameter in errors.
pub fn build_spectrum(
    description: &SpectrumDescription,
    usage: SpectrumUsage,
    what: &str,
) -> Result<Spectrum, SceneError> {
    let error = |e| parameter_error(what, e);
    Ok(match description {
        SpectrumDescription::Rgb(rgb) => match usage {
            SpectrumUsage::Albedo => {
                Spectrum::RgbAlbedo(RgbAlbedoSpectrum::new(*rgb).map_err(error)?)
            }
            SpectrumUsage::Unbounded => {
                Spectrum::RgbUnbounded(RgbUnboundedSpectrum::new(*rgb).map_err(error)?)
            }
            SpectrumUsage::Illuminant => {
                Spectrum::RgbIlluminant(RgbIlluminantSpectrum::new(*rgb).map_err(error)?)
            }
        },
        SpectrumDescription::Constant(value) => {
            Spectrum::Constant(ConstantSpectrum::new(*value).map_err(error)?)
        }
        SpectrumDescription::Sampled {
            wavelengths,
            values,
        } => {
            if wavelengths.len() != values.len() {
                return Err(parameter_error(
                    what,
                    format!(
                        "{} wavelengths but {} values",
                        wavelengths.len(),
                        values.len()
                    ),
                ));
            }
            let samples: Vec<(f32, f32)> = wavelengths
                .iter()
                .copied()
                .zip(values.iter().copied())
                .collect();
            Spectrum::PiecewiseLinear(PiecewiseLinearSpectrum::new(&samples).map_err(error)?)
        }
        SpectrumDescription::Named(name) => named_spectrum(name)
            .ok_or_else(|| parameter_error(what, format!("unknown named spectrum '{name}'")))?,
        SpectrumDescription::Blackbody { temperature } => Spectrum::Blackbody(
            BlackbodySpectrum::new(*temperature, BlackbodyNormalisation::PeakOne).map_err(error)?,
        ),
        SpectrumDescription::Scaled { scale, spectrum } => {
            if !(scale.is_finite() && *scale >= 0.0) {
                return Err(parameter_error(
                    what,
                    format!("scale must be finite and non-negative, got {scale}"),
                ));
            }
            let inner = build_spectrum(spectrum, usage, what)?;
            match inner {
                Spectrum::Constant(constant) => Spectrum::Constant(
                    ConstantSpectrum::new(constant.evaluate(0.0) * scale).map_err(error)?,
                ),
                other => Spectrum::DenselySampled(
                    other
                        .to_densely_sampled(CIE_LAMBDA_MIN, CIE_LAMBDA_MAX)
                        .map_err(error)?
                        .scaled(*scale),
                ),
            }
        }
    })
}

/// Spectra known by name.
///
/// - `stdillum-D65`: the CIE D65 illuminant.
/// - `metal-NAME-eta`, `metal-NAME-k`: η and κ of a measured conductor, for
///   pbrt-v4's `metal-Ag`, `-Al`, `-Au`, `-Cu`, `-MgO`, `-TiO2` and every
///   other name of Mitsuba 3's conductor list (`metal-Cu_palik-eta`, …), so
///   that a Mitsuba loader maps `<string name="material" value="Au"/>` to
///   `metal-Au-eta` / `metal-Au-k` (and `none` to `metal-none-eta` /
///   `metal-none-k`, zero, a perfect mirror). The data are Mitsuba 3.9.1's
///   tables (luxpop.com, Palik 1985; see [`crate::material::measured_conductor`]),
///   also for the pbrt-v4 names, whose own tables (from refractiveindex.info)
///   differ slightly. pbrt-v4's `metal-CuZn` (brass) is not available.
///
/// Loaders map their own names onto these.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    if name == "stdillum-D65" {
        return Some(Spectrum::DenselySampled(d65_illuminant().clone()));
    }
    let metal = name.strip_prefix("metal-")?;
    if let Some(conductor) = metal.strip_suffix("-eta") {
        return crate::material::measured_conductor(conductor).map(|measured| measured.eta);
    }
    if let Some(conductor) = metal.strip_suffix("-k") {
        return crate::material::measured_conductor(conductor).map(|measured| measured.k);
    }
    None
}

/// The indices of refraction Mitsuba 3 knows by name for its dielectrics'
/// `int_ior` / `ext_ior` (the table in Mitsuba 3's `dielectric` plugin
/// documentation, values at 589 nm, after Pedrotti's *Introduction to
/// Optics* and refractiveindex.info). Names are matched exactly, as Mitsuba
/// does.
pub fn named_ior(name: &str) -> Option<f32> {
    MITSUBA_NAMED_IORS
        .iter()
        .find(|(known, _)| *known == name)
        .map(|&(_, ior)| ior)
}

/// Mitsuba 3's named indices of refraction (checked against Mitsuba 3.9.1 by
/// `scripts/golden/mitsuba_bsdf_golden.py`).
pub const MITSUBA_NAMED_IORS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

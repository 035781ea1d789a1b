//! The renderer's spectral core: hero-wavelength spectral rendering in the
//! manner of pbrt-v4 (Pharr, Jakob and Humphreys, *Physically Based Rendering*,
//! 4th ed., chapter 4.5).
//!
//! Light is carried at [`SPECTRUM_SAMPLE_COUNT`] wavelengths per path
//! ([`SampledWavelengths`], importance-sampled over the visible range) as a
//! [`SampledSpectrum`]. Scene quantities are [`Spectrum`]s, evaluated at those
//! wavelengths: constants, measured tables, blackbodies, and RGB values lifted to
//! smooth spectra with the Jakob–Hanika sigmoid model ([`RgbToSpectrumTable`],
//! fitted by this module). [`to_xyz`] turns a path's sampled spectrum into an
//! unbiased CIE XYZ estimate, from which the film derives linear sRGB.
//!
//! Units: wavelengths in nm. XYZ follows pbrt-v4's normalisation
//! (X = ∫ S x̄ dλ / [`CIE_Y_INTEGRAL`]), so the constant spectrum 1 has Y = 1, and
//! the D65 white of RGB illuminants ([`d65_illuminant`]) is scaled to Y = 1 too.

mod blackbody;
mod cie;
mod colour;
mod constant;
mod densely_sampled;
mod error;
mod lanes;
mod padded_table;
mod piecewise_linear;
mod rgb_spectra;
mod rgb_to_spectrum_table;
mod sampled_spectrum;
mod sigmoid;
mod spectrum_enum;
mod wavelengths;

pub use blackbody::{BlackbodyNormalisation, BlackbodySpectrum, WIEN_DISPLACEMENT, planck};
pub use cie::{
    CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, CIE_Y_INTEGRAL, cie_x, cie_y, cie_z, d65_illuminant,
    d65_relative,
};
pub use colour::{
    LINEAR_SRGB_TO_XYZ, XYZ_TO_LINEAR_SRGB, apply_matrix, linear_srgb_luminance,
    linear_srgb_luminance_f64, linear_srgb_to_xyz, srgb_decode, srgb_encode, to_linear_srgb,
    to_luminance, to_xyz, xyz_to_linear_srgb,
};
pub use constant::ConstantSpectrum;
pub use densely_sampled::DenselySampledSpectrum;
pub use error::SpectrumError;
pub use piecewise_linear::PiecewiseLinearSpectrum;
pub use rgb_spectra::{
    RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum, SpectrumUsage,
};
pub use rgb_to_spectrum_table::{
    DEFAULT_RGB_TABLE_RESOLUTION, MAX_NORMALISED_COEFFICIENT, RgbToSpectrumTable,
    STORED_SRGB_TABLE_BYTES, TABLE_MAGIC,
};
pub use sampled_spectrum::SampledSpectrum;
pub use sigmoid::{RgbSigmoidPolynomial, algebraic_sigmoid};
pub use spectrum_enum::Spectrum;
pub use wavelengths::{
    SPECTRUM_SAMPLE_COUNT, SampledWavelengths, VISIBLE_LAMBDA_MAX, VISIBLE_LAMBDA_MIN,
    sample_visible_wavelength, visible_wavelength_cdf, visible_wavelength_pdf,
};

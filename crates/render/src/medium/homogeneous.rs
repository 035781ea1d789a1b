//! A homogeneous medium: absorption σa and scattering σs constant in space,
//! spectral (evaluated per sampled wavelength), with a phase function.

use super::phase::PhaseFunction;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};

/// How the coefficients are stored: as the scene file gave them, so that
/// Mitsuba's (albedo, σt) and pbrt's (σa, σs) both evaluate exactly.
#[derive(Debug, Clone)]
pub enum MediumSpectra {
    /// Single-scattering albedo and extinction: σs = albedo·σt, σa = σt − σs.
    AlbedoExtinction { albedo: Spectrum, sigma_t: Spectrum },
    /// Absorption and scattering.
    AbsorptionScattering {
        sigma_a: Spectrum,
        sigma_s: Spectrum,
    },
}

/// The coefficients of a medium at the wavelengths of a path (per unit length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MediumProperties {
    /// Absorption σa.
    pub sigma_a: SampledSpectrum,
    /// Scattering σs.
    pub sigma_s: SampledSpectrum,
}

impl MediumProperties {
    /// Extinction σt = σa + σs.
    pub fn sigma_t(&self) -> SampledSpectrum {
        self.sigma_a + self.sigma_s
    }
}

/// A homogeneous participating medium.
#[derive(Debug, Clone)]
pub struct HomogeneousMedium {
    spectra: MediumSpectra,
    /// A factor on both coefficients (scene units).
    scale: f32,
    /// The phase function.
    pub phase: PhaseFunction,
}

impl HomogeneousMedium {
    /// A medium with the given coefficients, scaled by `scale` (which must be
    /// finite and non-negative; values are clamped to 0 at evaluation if a
    /// spectrum goes negative).
    pub fn new(spectra: MediumSpectra, scale: f32, phase: PhaseFunction) -> Self {
        Self {
            spectra,
            scale,
            phase,
        }
    }

    /// σa and σs at `wavelengths`; negative values become 0 and an albedo
    /// is clamped to [0, 1], so that σa ≥ 0.
    pub fn coefficients(&self, wavelengths: &SampledWavelengths) -> MediumProperties {
        let (sigma_a, sigma_s) = match &self.spectra {
            MediumSpectra::AlbedoExtinction { albedo, sigma_t } => {
                let albedo = albedo.sample(wavelengths).clamp(0.0, 1.0);
                let sigma_t = sigma_t.sample(wavelengths).clamp_zero();
                let sigma_s = albedo * sigma_t;
                (sigma_t - sigma_s, sigma_s)
            }
            MediumSpectra::AbsorptionScattering { sigma_a, sigma_s } => (
                sigma_a.sample(wavelengths).clamp_zero(),
                sigma_s.sample(wavelengths).clamp_zero(),
            ),
        };
        MediumProperties {
            sigma_a: sigma_a * self.scale,
            sigma_s: sigma_s * self.scale,
        }
    }

    /// The transmittance exp(−σt·distance) per wavelength (Beer–Lambert);
    /// 1 where σt is 0, even for an infinite distance.
    pub fn transmittance(
        &self,
        distance: f32,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        transmittance(self.coefficients(wavelengths).sigma_t(), distance)
    }
}

/// exp(−σt·distance) per component, with 0·∞ taken as 0 (no extinction).
pub fn transmittance(sigma_t: SampledSpectrum, distance: f32) -> SampledSpectrum {
    sigma_t.map(|sigma| {
        if sigma <= 0.0 {
            1.0
        } else {
            (-sigma * distance).exp()
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::ConstantSpectrum;

    fn constant(value: f32) -> Spectrum {
        Spectrum::Constant(ConstantSpectrum::new(value).unwrap())
    }

    #[test]
    fn albedo_extinction_splits_into_absorption_and_scattering() {
        let medium = HomogeneousMedium::new(
            MediumSpectra::AlbedoExtinction {
                albedo: constant(0.8),
                sigma_t: constant(2.0),
            },
            1.5,
            PhaseFunction::Isotropic,
        );
        let wavelengths = SampledWavelengths::sample_visible(0.3);
        let coefficients = medium.coefficients(&wavelengths);
        for i in 0..4 {
            assert!((coefficients.sigma_s[i] - 2.4).abs() < 1e-5);
            assert!((coefficients.sigma_a[i] - 0.6).abs() < 1e-5);
        }
    }

    /// Beer–Lambert in closed form, and multiplicative over sub-segments.
    #[test]
    fn transmittance_closed_form() {
        let medium = HomogeneousMedium::new(
            MediumSpectra::AbsorptionScattering {
                sigma_a: constant(0.25),
                sigma_s: constant(0.5),
            },
            2.0,
            PhaseFunction::Isotropic,
        );
        let wavelengths = SampledWavelengths::sample_visible(0.7);
        for distance in [0.0f32, 0.1, 1.0, 3.7] {
            let t = medium.transmittance(distance, &wavelengths);
            let expected = (-1.5 * distance).exp();
            for i in 0..4 {
                assert!((t[i] - expected).abs() < 1e-6, "{distance}: {}", t[i]);
            }
            let split = medium.transmittance(distance * 0.3, &wavelengths)
                * medium.transmittance(distance * 0.7, &wavelengths);
            assert!((split[0] - expected).abs() < 1e-6);
        }
        assert_eq!(medium.transmittance(f32::INFINITY, &wavelengths)[0], 0.0);
        assert_eq!(
            transmittance(SampledSpectrum::zero(), f32::INFINITY)[2],
            1.0
        );
    }
}

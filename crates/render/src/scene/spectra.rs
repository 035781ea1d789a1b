//! Turning the scene description's [`SpectrumDescription`]s into
//! [`Spectrum`]s, according to what the quantity is ([`SpectrumUsage`]).

use super::SceneError;
use super::build::parameter_error;
use super::description::SpectrumDescription;
/// Where it lives, with the RGB spectra it chooses between; named here for
/// the loaders.
pub use crate::spectrum::SpectrumUsage;
use crate::spectrum::{
    BlackbodyNormalisation, BlackbodySpectrum, CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, ConstantSpectrum,
    PiecewiseLinearSpectrum, RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum,
    Spectrum, d65_illuminant,
};

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
///   differ slightly. pbrt-v4's `metal-CuZn-eta` / `metal-CuZn-k` (brass,
///   which Mitsuba does not have) use pbrt-v4's own table ([`pbrt_brass`]).
///
/// - `glass-BK7`, `glass-BAF10`, `glass-FK51A`, `glass-LASF9`, `glass-F5`,
///   `glass-F10`, `glass-F11` (also spelt `glass-SF5`, …): pbrt-v4's
///   dispersive glasses, refractiveindex.info data (public domain, CC0) as
///   pbrt-v4 tabulates them.
///
/// Loaders map their own names onto these.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    if name == "stdillum-D65" {
        return Some(Spectrum::DenselySampled(d65_illuminant().clone()));
    }
    if let Some(glass) = name.strip_prefix("glass-") {
        return pbrt_glass(glass);
    }
    let metal = name.strip_prefix("metal-")?;
    match metal {
        "CuZn-eta" => return pbrt_brass(&BRASS_ETA),
        "CuZn-k" => return pbrt_brass(&BRASS_K),
        _ => {}
    }
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

/// η of brass (CuZn), 290–890 nm in 10 nm steps: pbrt-v4's `CuZn_eta` table
/// (`src/pbrt/util/spectrum.cpp`; refractiveindex.info data, CC0), the
/// spectrum behind its `metal-CuZn-eta`.
const BRASS_ETA: [f32; 61] = [
    1.358, 1.388, 1.419, 1.446, 1.473, 1.494, 1.504, 1.503, 1.497, 1.487, 1.471, 1.445, 1.405,
    1.350, 1.278, 1.191, 1.094, 0.994, 0.900, 0.816, 0.745, 0.686, 0.639, 0.602, 0.573, 0.549,
    0.527, 0.505, 0.484, 0.468, 0.460, 0.450, 0.452, 0.449, 0.445, 0.444, 0.444, 0.445, 0.444,
    0.444, 0.445, 0.446, 0.448, 0.450, 0.452, 0.455, 0.457, 0.458, 0.460, 0.464, 0.469, 0.473,
    0.478, 0.481, 0.483, 0.486, 0.490, 0.494, 0.500, 0.507, 0.515,
];

/// κ of brass (CuZn) at the wavelengths of [`BRASS_ETA`]: pbrt-v4's `CuZn_k`.
const BRASS_K: [f32; 61] = [
    1.688, 1.731, 1.764, 1.789, 1.807, 1.815, 1.815, 1.815, 1.818, 1.818, 1.813, 1.805, 1.794,
    1.786, 1.784, 1.797, 1.829, 1.883, 1.957, 2.046, 2.145, 2.250, 2.358, 2.464, 2.568, 2.668,
    2.765, 2.860, 2.958, 3.059, 3.159, 3.253, 3.345, 3.434, 3.522, 3.609, 3.695, 3.778, 3.860,
    3.943, 4.025, 4.106, 4.186, 4.266, 4.346, 4.424, 4.501, 4.579, 4.657, 4.737, 4.814, 4.890,
    4.965, 5.039, 5.115, 5.192, 5.269, 5.346, 5.423, 5.500, 5.575,
];

/// A brass table ([`BRASS_ETA`] or [`BRASS_K`]) as a piecewise-linear
/// spectrum over 290, 300, …, 890 nm.
fn pbrt_brass(values: &[f32; 61]) -> Option<Spectrum> {
    let samples: Vec<(f32, f32)> = values
        .iter()
        .enumerate()
        .map(|(index, &value)| (290.0 + 10.0 * index as f32, value))
        .collect();
    PiecewiseLinearSpectrum::new(&samples)
        .ok()
        .map(Spectrum::PiecewiseLinear)
}

/// pbrt-v4's named glass index spectra (refractiveindex.info, CC0), as
/// (nm, η) pairs, with the digits of the published tables (more than f32
/// holds).
#[allow(clippy::excessive_precision)]
fn pbrt_glass(name: &str) -> Option<Spectrum> {
    let samples: &[f32] = match name {
        "BK7" => &[
            300.0, 1.5527703, 322.0, 1.5458699, 344.0, 1.5404467, 366.0, 1.5360905, 388.0,
            1.5325277, 410.0, 1.5295688, 432.0, 1.5270784, 454.0, 1.5249578, 476.0, 1.5231332,
            498.0, 1.5215483, 520.0, 1.5201597, 542.0, 1.5189335, 564.0, 1.5178426, 586.0,
            1.5168656, 608.0, 1.5159847, 630.0, 1.5151856, 652.0, 1.5144567, 674.0, 1.5137879,
            696.0, 1.5131711, 718.0, 1.5125994, 740.0, 1.5120669, 762.0, 1.5115686, 784.0,
            1.5111002, 806.0, 1.5106581, 828.0, 1.5102390, 850.0, 1.5098401, 872.0, 1.5094592,
            894.0, 1.5090940, 916.0, 1.5087427,
        ],
        "BAF10" => &[
            350.0, 1.7126881, 371.0, 1.7044510, 393.0, 1.6978540, 414.0, 1.6924598, 436.0,
            1.6879748, 457.0, 1.6841935, 479.0, 1.6809676, 500.0, 1.6781871, 522.0, 1.6757684,
            543.0, 1.6736475, 565.0, 1.6717738, 586.0, 1.6701074, 608.0, 1.6686160, 629.0,
            1.6672737, 651.0, 1.6660589, 672.0, 1.6649539, 694.0, 1.6639441, 715.0, 1.6630169,
            737.0, 1.6621619, 758.0, 1.6613703, 780.0, 1.6606343, 801.0, 1.6599475, 823.0,
            1.6593043, 844.0, 1.6586996, 866.0, 1.6581293, 887.0, 1.6575897, 909.0, 1.6570774,
        ],
        "FK51A" => &[
            290.0, 1.5145777, 312.0, 1.5092113, 334.0, 1.5049962, 356.0, 1.5016154, 378.0,
            1.4988559, 400.0, 1.4965696, 422.0, 1.4946507, 444.0, 1.4930216, 466.0, 1.4916244,
            488.0, 1.4904151, 511.0, 1.4893595, 533.0, 1.4884311, 555.0, 1.4876086, 577.0,
            1.4868753, 599.0, 1.4862172, 621.0, 1.4856234, 643.0, 1.4850844, 665.0, 1.4845927,
            687.0, 1.4841419, 709.0, 1.4837265, 732.0, 1.4833421, 754.0, 1.4829847, 776.0,
            1.4826510, 798.0, 1.4823381, 820.0, 1.4820437, 842.0, 1.4817655, 864.0, 1.4815017,
            886.0, 1.4812507, 908.0, 1.4810110,
        ],
        "LASF9" => &[
            370.0, 1.9199726, 391.0, 1.9057858, 412.0, 1.8945402, 433.0, 1.8854122, 455.0,
            1.8778636, 476.0, 1.8715257, 497.0, 1.8661363, 519.0, 1.8615035, 540.0, 1.8574835,
            561.0, 1.8539662, 583.0, 1.8508659, 604.0, 1.8481148, 625.0, 1.8456588, 646.0,
            1.8434540, 668.0, 1.8414644, 689.0, 1.8396605, 710.0, 1.8380175, 732.0, 1.8365148,
            753.0, 1.8351349, 774.0, 1.8338630, 796.0, 1.8326864, 817.0, 1.8315942, 838.0,
            1.8305770, 859.0, 1.8296266, 881.0, 1.8287360, 902.0, 1.8278990,
        ],
        "F5" | "SF5" => &[
            370.0, 1.7286550, 391.0, 1.7170152, 412.0, 1.7079037, 433.0, 1.7005724, 455.0,
            1.6945473, 476.0, 1.6895110, 497.0, 1.6852423, 519.0, 1.6815811, 540.0, 1.6784090,
            561.0, 1.6756361, 583.0, 1.6731929, 604.0, 1.6710248, 625.0, 1.6690884, 646.0,
            1.6673487, 668.0, 1.6657770, 689.0, 1.6643498, 710.0, 1.6630477, 732.0, 1.6618544,
            753.0, 1.6607560, 774.0, 1.6597410, 796.0, 1.6587993, 817.0, 1.6579225, 838.0,
            1.6571031, 859.0, 1.6563348, 881.0, 1.6556121, 902.0, 1.6549301,
        ],
        "F10" | "SF10" => &[
            380.0, 1.7905789, 401.0, 1.7776075, 422.0, 1.7673621, 443.0, 1.7590649, 464.0,
            1.7522128, 486.0, 1.7464636, 507.0, 1.7415759, 528.0, 1.7373738, 549.0, 1.7337261,
            570.0, 1.7305325, 592.0, 1.7277152, 613.0, 1.7252129, 634.0, 1.7229766, 655.0,
            1.7209666, 676.0, 1.7191505, 698.0, 1.7175016, 719.0, 1.7159976, 740.0, 1.7146200,
            761.0, 1.7133529, 782.0, 1.7121830, 804.0, 1.7110989, 825.0, 1.7100907, 846.0,
            1.7091500, 867.0, 1.7082695, 888.0, 1.7074427, 910.0, 1.7066640,
        ],
        "F11" | "SF11" => &[
            370.0, 1.8700216, 391.0, 1.8516256, 412.0, 1.8374708, 433.0, 1.8262324, 455.0,
            1.8170947, 476.0, 1.8095242, 497.0, 1.8031556, 519.0, 1.7977291, 540.0, 1.7930549,
            561.0, 1.7889904, 583.0, 1.7854266, 604.0, 1.7822787, 625.0, 1.7794794, 646.0,
            1.7769751, 668.0, 1.7747222, 689.0, 1.7726850, 710.0, 1.7708340, 732.0, 1.7691447,
            753.0, 1.7675964, 774.0, 1.7661718, 796.0, 1.7648559, 817.0, 1.7636363, 838.0,
            1.7625018, 859.0, 1.7614432, 881.0, 1.7604522, 902.0, 1.7595216,
        ],
        _ => return None,
    };
    PiecewiseLinearSpectrum::from_interleaved(samples)
        .ok()
        .map(Spectrum::PiecewiseLinear)
}

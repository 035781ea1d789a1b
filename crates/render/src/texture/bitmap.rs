//! Image textures: a file decoded once into per-texel data shared (through an
//! `Arc` and a process-wide cache of weak references) by every texture that
//! reads it with the same encoding, flip, scale and invert.
//!
//! Three kinds of per-texel data serve the three kinds of texture:
//!
//! - [`SpectrumBitmap`]: Jakob–Hanika sigmoid coefficients (and a scale for
//!   unbounded and illuminant uses) computed for every texel at load time, so
//!   a lookup costs a few sigmoid evaluations and no table lookup. Bilinear
//!   filtering interpolates the four texels' *spectra*, as Mitsuba 3's
//!   spectral `bitmap` does (pbrt-v4 interpolates RGB and upsamples after;
//!   the two differ only where neighbouring texels differ in hue).
//! - [`FloatBitmap`]: one value per texel — the value of a grey image, the
//!   luminance of an RGB one (Mitsuba 3's `eval_1`; pbrt-v4 averages the
//!   channels instead, which is the same for grey images).
//! - [`RgbBitmap`]: linear RGB per texel, for data that is not a colour
//!   (normal maps).
//!
//! Decoding: 8/16-bit files are linearised with the sRGB curve unless the
//! description says otherwise ([`ColourEncoding`]); then each value is
//! multiplied by `scale` and, with `invert`, replaced by 1 − value and
//! clamped at 0 (pbrt-v4's order). A `flip_vertically` texture stores its
//! rows bottom-up, so that lookups always use [`super::TexelLookup`]'s
//! top-left origin.

use std::any::Any;
use std::collections::HashMap;
use std::fmt;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock, Weak};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::error::TextureError;
use super::texel_lookup::TexelLookup;
use crate::image::{TextureImage, TransferCurve, read_texture_image, srgb_to_linear};
use crate::spectrum::{
    RgbSigmoidPolynomial, RgbToSpectrumTable, SampledSpectrum, SampledWavelengths, SpectrumUsage,
    d65_illuminant, linear_srgb_luminance,
};

/// How a bitmap's values are encoded.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ColourEncoding {
    /// Values are linear already.
    Linear,
    /// The sRGB transfer curve (8-bit PNG/JPEG images by default).
    Srgb,
    /// A power law with the given exponent.
    Gamma(f32),
}

/// Per-texel data of one decoded image (row-major, top row first).
#[derive(Clone, PartialEq)]
pub struct TexelData<T> {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// `width · height` texels.
    pub texels: Vec<T>,
}

impl<T> fmt::Debug for TexelData<T> {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(formatter, "TexelData({}x{})", self.width, self.height)
    }
}

/// How a file's values are turned into linear texel values.
#[derive(Debug, Clone, PartialEq)]
pub struct BitmapSource {
    /// The image file (already resolved by the loader).
    pub filename: PathBuf,
    /// `None`: what the file declares.
    pub encoding: Option<ColourEncoding>,
    /// Store the rows bottom-up (pbrt-v4's v = 0 at the bottom).
    pub flip_vertically: bool,
    /// Factor on every value.
    pub scale: f32,
    /// Use 1 − value.
    pub invert: bool,
}

/// What per-texel data a cache entry holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum DataKind {
    Spectrum(SpectrumUsage),
    Float,
    Rgb,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct CacheKey {
    filename: PathBuf,
    encoding: String,
    flip_vertically: bool,
    scale_bits: u32,
    invert: bool,
    kind: DataKind,
}

type Cache = Mutex<HashMap<CacheKey, Box<dyn Any + Send + Sync>>>;

fn cache() -> &'static Cache {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The texel data for `source` and `kind`, from the cache if another texture
/// still holds it, otherwise made by `make` from the decoded linear values.
fn cached<T: Send + Sync + 'static>(
    source: &BitmapSource,
    kind: DataKind,
    what: &str,
    make: impl FnOnce(&LinearImage) -> Vec<T>,
) -> Result<Arc<TexelData<T>>, TextureError> {
    let key = CacheKey {
        filename: source.filename.clone(),
        encoding: format!("{:?}", source.encoding),
        flip_vertically: source.flip_vertically,
        scale_bits: source.scale.to_bits(),
        invert: source.invert,
        kind,
    };
    if let Some(entry) = cache().lock().ok().and_then(|cache| {
        cache
            .get(&key)
            .and_then(|entry| entry.downcast_ref::<Weak<TexelData<T>>>())
            .and_then(Weak::upgrade)
    }) {
        return Ok(entry);
    }
    let image = LinearImage::load(source, what)?;
    let data = Arc::new(TexelData {
        width: image.width,
        height: image.height,
        texels: make(&image),
    });
    if let Ok(mut cache) = cache().lock() {
        cache.retain(|_, entry| {
            entry
                .downcast_ref::<Weak<TexelData<T>>>()
                .is_none_or(|weak| weak.strong_count() > 0)
        });
        cache.insert(key, Box::new(Arc::downgrade(&data)));
    }
    Ok(data)
}

/// A decoded image with linear values, scale and invert applied, rows in
/// lookup order.
struct LinearImage {
    width: usize,
    height: usize,
    channels: usize,
    values: Vec<f32>,
}

impl LinearImage {
    fn load(source: &BitmapSource, what: &str) -> Result<Self, TextureError> {
        let image = read_texture_image(&source.filename).map_err(|error| TextureError {
            what: what.to_string(),
            message: error.to_string(),
        })?;
        if image.width == 0 || image.height == 0 {
            return Err(TextureError {
                what: what.to_string(),
                message: format!("'{}' is an empty image", source.filename.display()),
            });
        }
        Ok(Self::from_texture_image(image, source))
    }

    fn from_texture_image(image: TextureImage, source: &BitmapSource) -> Self {
        let TextureImage {
            width,
            height,
            channels,
            values,
            transfer,
        } = image;
        let decode: Box<dyn Fn(f32) -> f32 + Sync> = match (source.encoding, transfer) {
            (Some(ColourEncoding::Linear), _) | (None, TransferCurve::Linear) => {
                Box::new(|value| value)
            }
            (Some(ColourEncoding::Srgb), _) | (None, TransferCurve::Srgb) => {
                Box::new(srgb_to_linear)
            }
            (Some(ColourEncoding::Gamma(gamma)), _) => {
                Box::new(move |value: f32| value.max(0.0).powf(gamma))
            }
        };
        let (scale, invert) = (source.scale, source.invert);
        let row_length = width * channels;
        let mut linear = Vec::with_capacity(values.len());
        for row in 0..height {
            let stored = if source.flip_vertically {
                height - 1 - row
            } else {
                row
            };
            linear.extend(
                values[stored * row_length..(stored + 1) * row_length]
                    .iter()
                    .map(|&value| {
                        let value = decode(value) * scale;
                        if invert {
                            (1.0 - value).max(0.0)
                        } else {
                            value
                        }
                    }),
            );
        }
        Self {
            width,
            height,
            channels,
            values: linear,
        }
    }

    fn rgb(&self, index: usize) -> [f32; 3] {
        let start = index * self.channels;
        if self.channels == 1 {
            [self.values[start]; 3]
        } else {
            [
                self.values[start],
                self.values[start + 1],
                self.values[start + 2],
            ]
        }
    }

    fn texel_count(&self) -> usize {
        self.width * self.height
    }
}

/// A texel of a [`SpectrumBitmap`]: the spectrum `scale · S(c₀λ² + c₁λ + c₂)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmoidTexel {
    /// The sigmoid polynomial.
    pub polynomial: RgbSigmoidPolynomial,
    /// 1 for reflectances, 2 max(r, g, b) for unbounded quantities.
    pub scale: f32,
}

impl SigmoidTexel {
    /// The texel for linear `rgb` used as `usage` (sRGB coefficient table):
    /// reflectances are clamped to [0, 1]; unbounded values and illuminants
    /// (whose D65 factor is applied per lookup) are scaled as
    /// [`crate::spectrum::RgbUnboundedSpectrum`] does.
    pub fn new(rgb: [f32; 3], usage: SpectrumUsage) -> Self {
        let table = RgbToSpectrumTable::srgb();
        let rgb = rgb.map(|value| {
            if value.is_finite() {
                value.max(0.0)
            } else {
                0.0
            }
        });
        match usage {
            SpectrumUsage::Albedo => Self {
                polynomial: table.lookup(rgb),
                scale: 1.0,
            },
            SpectrumUsage::Unbounded | SpectrumUsage::Illuminant => {
                let scale = 2.0 * rgb[0].max(rgb[1]).max(rgb[2]);
                if scale > 0.0 {
                    Self {
                        polynomial: table.lookup(rgb.map(|value| value / scale)),
                        scale,
                    }
                } else {
                    Self {
                        polynomial: RgbSigmoidPolynomial::constant(0.0),
                        scale: 0.0,
                    }
                }
            }
        }
    }

    /// The spectrum at the sampled wavelengths (without any D65 factor).
    fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        self.polynomial.sample(wavelengths) * self.scale
    }
}

/// A spectrum-valued image texture (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumBitmap {
    lookup: TexelLookup,
    data: Arc<TexelData<SigmoidTexel>>,
    illuminant: bool,
}

impl SpectrumBitmap {
    /// Loads (or shares) the image of `source` for use as `usage`, looked up
    /// with `lookup`'s filter, wrap and transform (its size is replaced by the
    /// image's). `what` names the parameter in errors.
    pub fn load(
        source: &BitmapSource,
        usage: SpectrumUsage,
        lookup: TexelLookup,
        what: &str,
    ) -> Result<Self, TextureError> {
        let kind = DataKind::Spectrum(usage);
        let data = cached(source, kind, what, |image| {
            (0..image.texel_count())
                .into_par_iter()
                .map(|index| SigmoidTexel::new(image.rgb(index), usage))
                .collect()
        })?;
        Ok(Self::from_data(data, usage, lookup))
    }

    /// A texture over already computed texels.
    pub fn from_data(
        data: Arc<TexelData<SigmoidTexel>>,
        usage: SpectrumUsage,
        lookup: TexelLookup,
    ) -> Self {
        Self {
            lookup: TexelLookup {
                width: data.width,
                height: data.height,
                ..lookup
            },
            data,
            illuminant: usage == SpectrumUsage::Illuminant,
        }
    }

    /// The spectrum at surface uv `uv`.
    pub fn evaluate(&self, uv: Vec2, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        let footprint = self.lookup.footprint(uv);
        let mut result = SampledSpectrum::zero();
        for (&texel, &weight) in footprint
            .texels
            .iter()
            .zip(&footprint.weights)
            .take(footprint.count)
        {
            if weight != 0.0 {
                result += self.data.texels[texel].sample(wavelengths) * weight;
            }
        }
        if self.illuminant {
            result *= d65_illuminant().sample(wavelengths);
        }
        result
    }

    /// How the image is addressed.
    pub fn lookup(&self) -> &TexelLookup {
        &self.lookup
    }
}

/// A scalar image texture (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct FloatBitmap {
    lookup: TexelLookup,
    data: Arc<TexelData<f32>>,
}

impl FloatBitmap {
    /// Loads (or shares) the image of `source` as scalars.
    pub fn load(
        source: &BitmapSource,
        lookup: TexelLookup,
        what: &str,
    ) -> Result<Self, TextureError> {
        let data = cached(source, DataKind::Float, what, |image| {
            (0..image.texel_count())
                .map(|index| {
                    if image.channels == 1 {
                        image.values[index]
                    } else {
                        linear_srgb_luminance(image.rgb(index))
                    }
                })
                .collect()
        })?;
        Ok(Self::from_data(data, lookup))
    }

    /// A texture over given texel values.
    pub fn from_data(data: Arc<TexelData<f32>>, lookup: TexelLookup) -> Self {
        Self {
            lookup: TexelLookup {
                width: data.width,
                height: data.height,
                ..lookup
            },
            data,
        }
    }

    /// The value at surface uv `uv`.
    pub fn evaluate(&self, uv: Vec2) -> f32 {
        let footprint = self.lookup.footprint(uv);
        (0..footprint.count)
            .map(|i| self.data.texels[footprint.texels[i]] * footprint.weights[i])
            .sum()
    }

    /// ∂value/∂(u, v) at `uv` (see [`TexelLookup::gradient`]).
    pub fn gradient(&self, uv: Vec2) -> Vec2 {
        self.lookup.gradient(uv, |texel| self.data.texels[texel])
    }
}

/// A linear-RGB image texture (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RgbBitmap {
    lookup: TexelLookup,
    data: Arc<TexelData<[f32; 3]>>,
}

impl RgbBitmap {
    /// Loads (or shares) the image of `source` as linear RGB.
    pub fn load(
        source: &BitmapSource,
        lookup: TexelLookup,
        what: &str,
    ) -> Result<Self, TextureError> {
        let data = cached(source, DataKind::Rgb, what, |image| {
            (0..image.texel_count())
                .map(|index| image.rgb(index))
                .collect()
        })?;
        Ok(Self::from_data(data, lookup))
    }

    /// A texture over given texel values.
    pub fn from_data(data: Arc<TexelData<[f32; 3]>>, lookup: TexelLookup) -> Self {
        Self {
            lookup: TexelLookup {
                width: data.width,
                height: data.height,
                ..lookup
            },
            data,
        }
    }

    /// The RGB value at surface uv `uv`.
    pub fn evaluate(&self, uv: Vec2) -> Vec3 {
        let footprint = self.lookup.footprint(uv);
        (0..footprint.count)
            .map(|i| Vec3::from(self.data.texels[footprint.texels[i]]) * footprint.weights[i])
            .sum()
    }
}

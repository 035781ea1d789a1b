//! Textures: lookups (filtering, wrapping, uv transform) against Mitsuba 3's
//! `bitmap` and `checkerboard` (golden values from
//! `scripts/texture_reference.py`), decoding, spectral upsampling, and the
//! bump-map, normal-map and mask material adapters.

#[path = "support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Affine2, Vec2, Vec3};
use render::geometry::{Sphere, SurfaceHit};
use render::material::{
    Material, ShadingFrame, SurfaceAdapter, SurfaceBsdf, bump_mapped_frame, normal_mapped_frame,
};
use render::scene::build::{build_float_texture, build_spectrum_texture};
use render::scene::description::{
    ColourEncoding, MaterialDescription, SpectrumDescription, TextureDescription, TextureFilter,
    TextureWrap,
};
use render::scene::spectra::SpectrumUsage;
use render::spectrum::{SampledWavelengths, Spectrum};
use render::statistics::chi_square_test;
use render::texture::{
    BitmapSource, Checkerboard, FloatBitmap, FloatTexture, RgbBitmap, SpectrumBitmap, TexelData,
    TexelLookup, TextureContext,
};

const REFERENCE: &str = include_str!("../../../scripts/texture_reference.txt");

fn textures_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/external/mitsuba-data/common/textures")
}

/// The reference lines whose first word is `tag`, split into words.
fn reference(tag: &str) -> Vec<Vec<&'static str>> {
    REFERENCE
        .lines()
        .map(|line| line.split_whitespace().collect::<Vec<_>>())
        .filter(|words| words.first() == Some(&tag))
        .collect()
}

fn number(word: &str) -> f32 {
    word.parse().unwrap()
}

fn lookup(filter: TextureFilter, wrap: TextureWrap) -> TexelLookup {
    TexelLookup {
        width: 1,
        height: 1,
        filter,
        wrap,
        to_uv: Affine2::IDENTITY,
    }
}

fn context(u: f32, v: f32) -> TextureContext {
    TextureContext {
        uv: Vec2::new(u, v),
        point: Vec3::ZERO,
    }
}

/// The 3×2 image of the reference script (row 0 at the top).
fn synthetic() -> Arc<TexelData<[f32; 3]>> {
    let texels = (0..6)
        .map(|i| {
            let base = 0.3 * i as f32;
            [base, base + 0.1, base + 0.2]
        })
        .collect();
    Arc::new(TexelData {
        width: 3,
        height: 2,
        texels,
    })
}

#[test]
fn filtering_and_wrapping_match_mitsuba() {
    let lines = reference("synthetic");
    assert_eq!(lines.len(), 66);
    for words in lines {
        let filter = match words[1] {
            "nearest" => TextureFilter::Nearest,
            _ => TextureFilter::Bilinear,
        };
        let wrap = match words[2] {
            "repeat" => TextureWrap::Repeat,
            "mirror" => TextureWrap::Mirror,
            _ => TextureWrap::Clamp,
        };
        let texture = RgbBitmap::from_data(synthetic(), lookup(filter, wrap));
        let uv = Vec2::new(number(words[3]), number(words[4]));
        let ours = texture.evaluate(uv);
        let expected = Vec3::new(number(words[5]), number(words[6]), number(words[7]));
        assert!(
            (ours - expected).abs().max_element() < 1e-5,
            "{words:?}: ours {ours}"
        );
    }
}

#[test]
fn hand_computed_lookups() {
    // Bilinear at a texel centre is that texel; halfway between two texels
    // the mean; nearest picks the texel containing uv.
    let bilinear = RgbBitmap::from_data(
        synthetic(),
        lookup(TextureFilter::Bilinear, TextureWrap::Clamp),
    );
    let centre = bilinear.evaluate(Vec2::new(1.5 / 3.0, 0.25));
    assert!((centre - Vec3::new(0.3, 0.4, 0.5)).abs().max_element() < 1e-6);
    let between = bilinear.evaluate(Vec2::new(1.0 / 3.0, 0.25));
    assert!((between - Vec3::new(0.15, 0.25, 0.35)).abs().max_element() < 1e-6);
    let nearest = RgbBitmap::from_data(
        synthetic(),
        lookup(TextureFilter::Nearest, TextureWrap::Repeat),
    );
    assert_eq!(
        nearest.evaluate(Vec2::new(0.7, 0.6)),
        Vec3::new(1.5, 1.6, 1.7)
    );
    // to_uv: a scale of 2 tiles the image twice.
    let tiled = RgbBitmap::from_data(
        synthetic(),
        TexelLookup {
            to_uv: Affine2::from_scale(Vec2::splat(2.0)),
            ..lookup(TextureFilter::Nearest, TextureWrap::Repeat)
        },
    );
    assert_eq!(
        tiled.evaluate(Vec2::new(0.85, 0.3)),
        Vec3::new(1.5, 1.6, 1.7)
    );
}

/// Writes a 2×2 24-bit BMP with the given top-left grey level (others 0).
fn write_grey_bmp(path: &Path, level: u8) {
    let mut file = Vec::new();
    file.extend_from_slice(b"BM");
    file.extend_from_slice(&(54u32 + 16).to_le_bytes());
    file.extend_from_slice(&0u32.to_le_bytes());
    file.extend_from_slice(&54u32.to_le_bytes());
    for value in [40u32, 2, (-2i32) as u32] {
        file.extend_from_slice(&value.to_le_bytes());
    }
    file.extend_from_slice(&1u16.to_le_bytes());
    file.extend_from_slice(&24u16.to_le_bytes());
    file.extend_from_slice(&[0; 24]);
    file.extend_from_slice(&[level, level, level, 0, 0, 0, 0, 0]);
    file.extend_from_slice(&[0; 8]);
    std::fs::write(path, file).unwrap();
}

#[test]
fn encodings_scale_invert_and_flip() {
    let directory = ScratchDirectory::new("texture");
    let path = directory.join("grey.bmp");
    write_grey_bmp(&path, 128);
    let encoded = 128.0f32 / 255.0;
    let top_left = Vec2::new(0.25, 0.25);
    let value = |encoding, scale, invert, flip_vertically, uv| {
        let source = BitmapSource {
            filename: path.clone(),
            encoding,
            flip_vertically,
            scale,
            invert,
        };
        FloatBitmap::load(
            &source,
            lookup(TextureFilter::Nearest, TextureWrap::Repeat),
            "test",
        )
        .unwrap()
        .evaluate(uv)
    };
    // 8-bit files decode with the sRGB curve by default.
    let srgb = ((encoded + 0.055) / 1.055).powf(2.4);
    assert!((value(None, 1.0, false, false, top_left) - srgb).abs() < 1e-6);
    assert!((value(Some(ColourEncoding::Srgb), 1.0, false, false, top_left) - srgb).abs() < 1e-6);
    assert!(
        (value(Some(ColourEncoding::Linear), 1.0, false, false, top_left) - encoded).abs() < 1e-6
    );
    let gamma = encoded.powf(2.2);
    assert!(
        (value(
            Some(ColourEncoding::Gamma(2.2)),
            1.0,
            false,
            false,
            top_left
        ) - gamma)
            .abs()
            < 1e-6
    );
    assert!((value(None, 2.0, false, false, top_left) - 2.0 * srgb).abs() < 1e-6);
    assert!((value(None, 1.0, true, false, top_left) - (1.0 - srgb)).abs() < 1e-6);
    assert_eq!(value(None, 1.0, true, false, Vec2::new(0.75, 0.25)), 1.0);
    // Flipped, the top-left texel is found at the bottom-left.
    assert_eq!(value(None, 1.0, false, true, top_left), 0.0);
    assert!((value(None, 1.0, false, true, Vec2::new(0.25, 0.75)) - srgb).abs() < 1e-6);
    // A missing file is an error naming the path.
    let missing = TextureDescription::Bitmap {
        filename: directory.join("missing.png"),
        encoding: None,
        filter: TextureFilter::Bilinear,
        wrap: TextureWrap::Repeat,
        to_uv: Affine2::IDENTITY,
        flip_vertically: false,
        scale: 1.0,
        invert: false,
    };
    let error = build_spectrum_texture(&missing, SpectrumUsage::Albedo, "reflectance")
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("missing.png") && error.contains("reflectance"),
        "{error}"
    );
}

fn wood(filter: TextureFilter) -> TextureDescription {
    TextureDescription::Bitmap {
        filename: textures_dir().join("wood.jpg"),
        encoding: None,
        filter,
        wrap: TextureWrap::Repeat,
        to_uv: Affine2::IDENTITY,
        flip_vertically: false,
        scale: 1.0,
        invert: false,
    }
}

#[test]
fn wood_jpeg_matches_mitsuba() {
    let source = BitmapSource {
        filename: textures_dir().join("wood.jpg"),
        encoding: None,
        flip_vertically: false,
        scale: 1.0,
        invert: false,
    };
    let rgb = RgbBitmap::load(
        &source,
        lookup(TextureFilter::Bilinear, TextureWrap::Repeat),
        "wood",
    )
    .unwrap();
    let mut largest = 0.0f32;
    for words in reference("wood_rgb") {
        let uv = Vec2::new(number(words[1]), number(words[2]));
        let expected = Vec3::new(number(words[3]), number(words[4]), number(words[5]));
        let difference = (rgb.evaluate(uv) - expected).abs().max_element();
        largest = largest.max(difference);
    }
    // Mitsuba stores 8-bit textures as half floats (relative error 2⁻¹¹) and
    // decodes JPEG with libjpeg; one 8-bit level is ≈ 0.003 in linear terms here.
    eprintln!("wood.jpg: largest RGB difference from Mitsuba {largest}");
    assert!(largest < 2e-3, "largest RGB difference {largest}");

    let texture = build_spectrum_texture(
        &wood(TextureFilter::Bilinear),
        SpectrumUsage::Albedo,
        "wood",
    )
    .unwrap();
    let mut largest = 0.0f32;
    for words in reference("wood_spectral") {
        let uv = Vec2::new(number(words[1]), number(words[2]));
        let lambdas = [3, 4, 5, 6].map(|i| number(words[i]));
        let wavelengths = SampledWavelengths::from_parts(lambdas, [1.0; 4]).unwrap();
        let ours = texture.evaluate(&context(uv.x, uv.y), &wavelengths);
        for i in 0..4 {
            let expected = number(words[7 + i]);
            largest = largest.max((ours[i] - expected).abs());
        }
    }
    // Both use the Jakob–Hanika model, but with different coefficient tables
    // (Mitsuba's and ours, fitted independently): spectra agree to a few 10⁻³.
    eprintln!("wood.jpg: largest spectral difference from Mitsuba {largest}");
    assert!(largest < 1e-2, "largest spectral difference {largest}");
}

#[test]
fn spectral_upsampling_per_usage() {
    let data = Arc::new(TexelData {
        width: 1,
        height: 1,
        texels: vec![[0.8, 0.4, 0.2]],
    });
    let wavelengths =
        SampledWavelengths::from_parts([450.0, 520.0, 600.0, 680.0], [1.0; 4]).unwrap();
    for (usage, spectrum) in [
        (
            SpectrumUsage::Albedo,
            SpectrumDescription::Rgb([0.8, 0.4, 0.2]),
        ),
        (
            SpectrumUsage::Unbounded,
            SpectrumDescription::Rgb([0.8, 0.4, 0.2]),
        ),
        (
            SpectrumUsage::Illuminant,
            SpectrumDescription::Rgb([0.8, 0.4, 0.2]),
        ),
    ] {
        let texels = Arc::new(TexelData {
            width: 1,
            height: 1,
            texels: vec![render::texture::SigmoidTexel::new(data.texels[0], usage)],
        });
        let bitmap = SpectrumBitmap::from_data(
            texels,
            usage,
            lookup(TextureFilter::Bilinear, TextureWrap::Repeat),
        );
        let constant =
            build_spectrum_texture(&TextureDescription::Constant(spectrum), usage, "c").unwrap();
        let ours = bitmap.evaluate(Vec2::new(0.3, 0.6), &wavelengths);
        let expected = constant.evaluate(&context(0.0, 0.0), &wavelengths);
        for i in 0..4 {
            assert!(
                (ours[i] - expected[i]).abs() <= 1e-5 * expected[i].abs().max(1.0),
                "{usage:?}: {ours:?} vs {expected:?}"
            );
        }
    }
}

#[test]
fn checkerboard_matches_mitsuba() {
    // Mitsuba's board has squares of side ½ of its transformed uv with color0
    // at the origin: ours with even = color0 and to_uv scaled by 2 after.
    let to_uv = Affine2::from_scale(Vec2::splat(2.0)) * Affine2::from_scale(Vec2::new(3.0, 2.0));
    let description = TextureDescription::Checkerboard {
        even: Box::new(TextureDescription::Constant(SpectrumDescription::Constant(
            0.1,
        ))),
        odd: Box::new(TextureDescription::Constant(SpectrumDescription::Constant(
            0.7,
        ))),
        to_uv,
    };
    let float = build_float_texture(&description, "checkerboard").unwrap();
    let spectral =
        build_spectrum_texture(&description, SpectrumUsage::Albedo, "checkerboard").unwrap();
    let wavelengths = SampledWavelengths::sample_visible(0.3);
    let lines = reference("checker");
    assert!(lines.len() >= 8);
    for words in lines {
        let at = context(number(words[1]), number(words[2]));
        let expected = number(words[3]);
        assert_eq!(float.evaluate(&at), expected, "{words:?}");
        assert_eq!(
            spectral.evaluate(&at, &wavelengths)[2],
            expected,
            "{words:?}"
        );
    }
    // pbrt's convention directly: unit squares, even at the origin.
    let board = Checkerboard {
        even: 1,
        odd: 2,
        to_uv: Affine2::IDENTITY,
    };
    assert_eq!(*board.select(Vec2::new(0.5, 0.5)), 1);
    assert_eq!(*board.select(Vec2::new(1.5, 0.5)), 2);
    assert_eq!(*board.select(Vec2::new(-0.5, 0.5)), 2);
    assert_eq!(*board.select(Vec2::new(-0.5, -0.5)), 1);
}

#[test]
fn bump_texture_value_and_gradient_match_mitsuba() {
    let source = BitmapSource {
        filename: textures_dir().join("floor_tiles_bumpmap.png"),
        encoding: Some(ColourEncoding::Linear),
        flip_vertically: false,
        scale: 1.0,
        invert: false,
    };
    let height = FloatBitmap::load(
        &source,
        lookup(TextureFilter::Bilinear, TextureWrap::Repeat),
        "bump",
    )
    .unwrap();
    for words in reference("bump") {
        let uv = Vec2::new(number(words[1]), number(words[2]));
        let (value, gradient) = (
            number(words[3]),
            Vec2::new(number(words[4]), number(words[5])),
        );
        // Mitsuba's half-float storage: 2⁻¹¹ relative per texel, times the
        // resolution 2048 in the gradient.
        assert!((height.evaluate(uv) - value).abs() < 1e-3, "{words:?}");
        let ours = height.gradient(uv);
        assert!(
            (ours - gradient).abs().max_element() < 0.05,
            "{words:?}: {ours}"
        );
    }
}

#[test]
fn gradient_of_a_linear_ramp() {
    // h(x) = texel column / 10 on an 8×4 image: ∂h/∂s = W/10 per unit s.
    let texels = (0..32).map(|i| (i % 8) as f32 / 10.0).collect();
    let data = Arc::new(TexelData {
        width: 8,
        height: 4,
        texels,
    });
    let ramp = FloatBitmap::from_data(
        data.clone(),
        TexelLookup {
            to_uv: Affine2::from_scale(Vec2::new(0.5, 1.0)),
            ..lookup(TextureFilter::Bilinear, TextureWrap::Clamp)
        },
    );
    // s = u/2, so ∂h/∂u = 0.8 / 2.
    let gradient = ramp.gradient(Vec2::new(0.6, 0.4));
    assert!(
        (gradient - Vec2::new(0.4, 0.0)).abs().max_element() < 1e-5,
        "{gradient}"
    );
    let nearest = FloatBitmap::from_data(data, lookup(TextureFilter::Nearest, TextureWrap::Clamp));
    assert_eq!(nearest.gradient(Vec2::new(0.3, 0.3)), Vec2::ZERO);
}

fn plane_hit() -> SurfaceHit {
    SurfaceHit {
        t: 1.0,
        point: Vec3::ZERO,
        geometric_normal: Vec3::Z,
        shading_normal: Vec3::Z,
        uv: Vec2::new(0.3, 0.4),
        dpdu: Vec3::new(2.0, 0.0, 0.0),
        dpdv: Vec3::new(0.0, 3.0, 0.0),
        shape_index: 0,
        primitive_index: 0,
        time: 0.0,
    }
}

fn assert_close(a: Vec3, b: Vec3, tolerance: f32) {
    assert!((a - b).abs().max_element() < tolerance, "{a} vs {b}");
}

#[test]
fn bump_map_of_constant_and_linear_heights() {
    let hit = plane_hit();
    let frame = ShadingFrame::from_normal_and_tangent(hit.shading_normal, hit.dpdu).unwrap();
    // A constant height leaves the frame as it is.
    let flat = bump_mapped_frame(&frame, hit.geometric_normal, hit.dpdu, hit.dpdv, Vec2::ZERO);
    assert_close(flat.normal(), Vec3::Z, 1e-6);
    assert_close(flat.tangent(), Vec3::X, 1e-6);
    // h = a·u + b·v: ∂p/∂u' = (2, 0, a), ∂p/∂v' = (0, 3, b), n' ∝ (−3a, −2b, 6).
    let (a, b) = (0.5, -0.25);
    let bumped = bump_mapped_frame(
        &frame,
        hit.geometric_normal,
        hit.dpdu,
        hit.dpdv,
        Vec2::new(a, b),
    );
    assert_close(
        bumped.normal(),
        Vec3::new(-3.0 * a, -2.0 * b, 6.0).normalize(),
        1e-6,
    );
    assert!(bumped.tangent().dot(bumped.normal()).abs() < 1e-6);
    assert!(bumped.tangent().dot(hit.dpdu) > 0.0);

    // The same through the material: a ramp texture of slope 0.5 per unit u,
    // scaled by 2, gives ∂h/∂u = 1.
    let texels = (0..16).map(|i| (i % 4) as f32 * 0.5 / 4.0).collect();
    let height = FloatTexture::Bitmap(FloatBitmap::from_data(
        Arc::new(TexelData {
            width: 4,
            height: 4,
            texels,
        }),
        lookup(TextureFilter::Bilinear, TextureWrap::Clamp),
    ));
    let material = Material::BumpMap {
        options: Default::default(),
        height,
        scale: 2.0,
        nested: Box::new(
            Material::diffuse(Spectrum::Constant(
                render::spectrum::ConstantSpectrum::new(0.5).unwrap(),
            ))
            .unwrap(),
        ),
    };
    let wavelengths = SampledWavelengths::sample_visible(0.5);
    let surface = material.surface_bsdf_at(&hit, &wavelengths);
    assert_close(
        surface.frame.normal(),
        Vec3::new(-3.0, 0.0, 6.0).normalize(),
        1e-5,
    );
    assert_eq!(surface.adapter.unperturbed_normal, Some(Vec3::Z));
    // A direction below the unperturbed surface but above the bumped one
    // does not scatter.
    let wo = Vec3::new(0.0, 0.3, 1.0).normalize();
    let leaking = Vec3::new(-1.0, 0.0, -0.1).normalize();
    assert!(surface.frame.to_local(leaking).z > 0.0);
    assert!(surface.evaluate(wo, leaking, &wavelengths).is_black());
    assert_eq!(surface.pdf(wo, leaking), 0.0);
}

#[test]
fn normal_map_identity_and_tilt() {
    let hit = plane_hit();
    let frame = ShadingFrame::from_normal_and_tangent(Vec3::new(0.0, 0.6, 0.8), hit.dpdu).unwrap();
    let identity = normal_mapped_frame(&frame, Vec3::new(0.5, 0.5, 1.0));
    assert_close(identity.normal(), frame.normal(), 1e-6);
    assert_close(identity.tangent(), frame.tangent(), 1e-6);
    assert_close(identity.bitangent(), frame.bitangent(), 1e-6);
    // (1, 0.5, 0.5) encodes the tangent direction itself.
    let tilted = normal_mapped_frame(&frame, Vec3::new(1.0, 0.5, 0.5));
    assert_close(tilted.normal(), frame.tangent(), 1e-6);
    // Through the material with a constant RGB texture.
    let material = Material::NormalMap {
        options: Default::default(),
        normals: render::texture::RgbTexture::Constant(Vec3::new(0.5, 0.5, 1.0)),
        nested: Box::new(Material::Mirror),
    };
    let wavelengths = SampledWavelengths::sample_visible(0.5);
    let surface = material.surface_bsdf_at(&hit, &wavelengths);
    assert_close(surface.frame.normal(), Vec3::Z, 1e-6);
    assert_close(surface.frame.tangent(), Vec3::X, 1e-6);
}

fn masked_diffuse(opacity: f32) -> SurfaceBsdf {
    let material = Material::Mask {
        opacity: FloatTexture::Constant(opacity),
        nested: Box::new(
            Material::diffuse(Spectrum::Constant(
                render::spectrum::ConstantSpectrum::new(0.6).unwrap(),
            ))
            .unwrap(),
        ),
    };
    material.surface_bsdf_at(&plane_hit(), &SampledWavelengths::sample_visible(0.5))
}

#[test]
fn mask_lobe_choice_is_consistent() {
    let opacity = 0.3;
    let surface = masked_diffuse(opacity);
    let flags = surface.flags();
    assert!(flags.is_non_specular() && flags.is_specular() && flags.is_transmissive());
    let wo = Vec3::new(0.2, -0.1, 0.9).normalize();
    let mut wavelengths = SampledWavelengths::sample_visible(0.5);
    // Stratified component samples with a fixed direction sample: the
    // pass-through fraction is 1 − α up to one stratum, and every sample
    // agrees with evaluate/pdf (nested) or has weight 1 (pass-through).
    let count = 10_000;
    let mut pass_through = 0usize;
    for i in 0..count {
        let u_component = (i as f32 + 0.5) / count as f32;
        let u = [
            ((i * 7919) % count) as f32 / count as f32,
            ((i * 104_729) % count) as f32 / count as f32,
        ];
        let sample = surface
            .sample(wo, u_component, u, &mut wavelengths)
            .unwrap();
        if sample.is_specular() {
            pass_through += 1;
            assert_close(sample.wi, -wo, 1e-6);
            assert!(sample.is_transmission() && sample.eta == 1.0);
            let weight = sample.value * (sample.wi.z.abs() / sample.pdf);
            assert!((weight[0] - 1.0).abs() < 1e-5);
        } else {
            let value = surface.evaluate(wo, sample.wi, &wavelengths);
            let pdf = surface.pdf(wo, sample.wi);
            assert!((value[0] - sample.value[0]).abs() < 1e-5 * value[0]);
            assert!((pdf - sample.pdf).abs() < 1e-4 * pdf);
        }
    }
    let expected = (1.0 - opacity) * count as f32;
    assert!(
        (pass_through as f32 - expected).abs() <= 1.0,
        "{pass_through}"
    );

    // Chi-square of the lobe choice with pseudo-random component samples
    // (a fixed-seed xorshift: the test is deterministic).
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let trials = 20_000;
    let mut observed = [0u64; 2];
    for _ in 0..trials {
        let sample = surface
            .sample(wo, next(), [next(), next()], &mut wavelengths)
            .unwrap();
        observed[usize::from(sample.is_specular())] += 1;
    }
    let expected = [
        opacity as f64 * trials as f64,
        (1.0 - opacity as f64) * trials as f64,
    ];
    let result = chi_square_test(&observed, &expected);
    assert!(result.p_value > 1e-3, "{result:?} {observed:?}");

    // Opaque and fully transparent masks.
    let opaque = masked_diffuse(1.0);
    assert!(!opaque.flags().is_specular());
    let invisible = masked_diffuse(0.0);
    assert!(!invisible.flags().is_non_specular());
    let sample = invisible
        .sample(wo, 0.0, [0.5, 0.5], &mut wavelengths)
        .unwrap();
    assert_close(sample.wi, -wo, 1e-6);
    assert_eq!(invisible.pdf(wo, Vec3::Z), 0.0);
    assert_eq!(SurfaceAdapter::NONE.opacity, 1.0);
}

#[test]
fn sphere_dpdv_is_the_derivative_of_the_parameterisation() {
    let sphere = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0).unwrap();
    // Points on the sphere at (θ, φ) and their uv = (φ/2π, (π − θ)/π).
    let point = |u: f32, v: f32| {
        let (phi, theta) = (u * std::f32::consts::TAU, std::f32::consts::PI * (1.0 - v));
        Vec3::new(1.0, 2.0, 3.0)
            + 2.0
                * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                )
    };
    let (u, v, h) = (0.3f32, 0.35f32, 1e-3f32);
    let p = point(u, v);
    let origin = p + 3.0 * (p - Vec3::new(1.0, 2.0, 3.0));
    let direction = (p - origin).normalize();
    let t = (p - origin).length();
    let hit = sphere.surface_hit(origin, direction, t, 0.0);
    assert!(
        (hit.uv - Vec2::new(u, v)).abs().max_element() < 1e-4,
        "{}",
        hit.uv
    );
    let dpdv = (point(u, v + h) - point(u, v - h)) / (2.0 * h);
    let dpdu = (point(u + h, v) - point(u - h, v)) / (2.0 * h);
    assert_close(hit.dpdv, dpdv, 2e-2);
    assert_close(hit.dpdu, dpdu, 2e-2);
}

/// A masked sphere (opacity 0.4) filling the view under a constant
/// environment of radiance 1. White inside the mask (albedo 1), every path
/// ends in the environment with throughput 1, so each pixel is 1 whatever
/// the mask does — provided the pass-through lobe, next-event estimation and
/// MIS fit together (a double count or a missing share would show). Black
/// inside, light reaches the camera only through both walls: (1 − 0.4)².
#[test]
fn masked_spheres_in_a_furnace() {
    for (nested, expected) in [
        (MaterialDescription::diffuse_rgb([1.0, 1.0, 1.0]), 1.0),
        (MaterialDescription::Black, 0.36),
    ] {
        masked_sphere_in_a_furnace(nested, expected);
    }
}

fn masked_sphere_in_a_furnace(
    nested: render::scene::description::MaterialDescription,
    expected: f64,
) {
    use render::camera::{FovAxis, PerspectiveSettings, look_at};
    use render::renderer::{RenderSettings, render};
    use render::sampler::SamplerKind;
    use render::scene::Scene;
    use render::scene::description::{
        FilterDescription, LightDescription, SceneDescription, ShapeDescription, ShapeGeometry,
    };
    use std::sync::atomic::AtomicBool;

    let world = look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y).unwrap();
    let description = SceneDescription {
        name: "masked-furnace".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [8, 8],
            fov_degrees: 10.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            MaterialDescription::Mask {
                opacity: TextureDescription::Constant(SpectrumDescription::Constant(0.4)),
                nested: Box::new(nested),
            },
        )],
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([1.0, 1.0, 1.0]),
        }],
        max_depth: Some(64),
        samples_per_pixel: Some(32),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    };
    let scene = Scene::build(&description).unwrap();
    let settings = RenderSettings {
        sampler: SamplerKind::Sobol,
        samples_per_pixel: 32,
        max_depth: 64,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    let image = output.film.image(1.0);
    let variance = output.film.variance_image();
    let count = image.pixels().len() as f64;
    for channel in 0..3 {
        let mean = image
            .pixels()
            .iter()
            .map(|p| p[channel] as f64)
            .sum::<f64>()
            / count;
        let variance_of_mean = variance
            .pixels()
            .iter()
            .map(|p| p[channel] as f64)
            .sum::<f64>()
            / (count * count);
        // 5 standard errors; 1e-3 for the D65 white's sRGB (within 2e-4 of 1).
        let bound = 5.0 * variance_of_mean.sqrt() + 1e-3;
        assert!(
            (mean - expected).abs() < bound,
            "channel {channel}: mean {mean} vs {expected}, bound {bound}"
        );
    }
}

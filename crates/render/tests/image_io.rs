//! Round trips and error messages of the image readers and writers, and
//! reading a reference render of the Cornell box by Tungsten.

use std::path::Path;

#[path = "support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use render::image::{
    Image, ImageError, Metadata, VARIANCE_LAYER, linear_to_srgb, read_exr, read_image, read_pfm,
    read_png, write_exr, write_image, write_pfm, write_png,
};

/// A fresh directory for this test's files, removed when dropped.
fn scratch_directory(name: &str) -> ScratchDirectory {
    ScratchDirectory::new(&format!("image-io-{name}"))
}

/// A deterministic test image with values spread over many binades,
/// negatives, zeros and (optionally) special values.
fn test_image(width: usize, height: usize, special_values: bool) -> Image {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut pixels = Vec::with_capacity(width * height);
    for _ in 0..width * height {
        let mut pixel = [0.0f32; 3];
        for value in &mut pixel {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let bits = (state >> 32) as u32;
            let mantissa = (bits & 0xffff) as f32 / 65536.0;
            let exponent = ((bits >> 16) % 40) as i32 - 20;
            let sign = if bits >> 31 == 1 { -1.0 } else { 1.0 };
            *value = sign * mantissa * (exponent as f32).exp2();
        }
        pixels.push(pixel);
    }
    if special_values {
        pixels[0] = [f32::INFINITY, f32::NEG_INFINITY, -0.0];
        pixels[1] = [f32::MIN_POSITIVE / 8.0, f32::MAX, f32::MIN];
    }
    Image::from_pixels(width, height, pixels).unwrap()
}

fn assert_bit_identical(expected: &Image, actual: &Image) {
    assert_eq!(
        (expected.width(), expected.height()),
        (actual.width(), actual.height())
    );
    for (index, (a, b)) in expected.pixels().iter().zip(actual.pixels()).enumerate() {
        assert_eq!(
            a.map(f32::to_bits),
            b.map(f32::to_bits),
            "pixel {index}: {a:?} vs {b:?}"
        );
    }
}

fn render_metadata() -> Metadata {
    [
        ("integrator", "path"),
        ("sampler", "lqmc-halton"),
        ("spp", "64"),
        ("seed", "7"),
        ("render time", "12.5 s"),
    ]
    .into_iter()
    .map(|(key, value)| (key.to_string(), value.to_string()))
    .collect()
}

#[test]
fn exr_round_trip_is_bit_exact_with_layers_and_metadata() {
    let directory = scratch_directory("exr");
    let path = directory.join("round_trip.exr");
    let image = test_image(37, 23, true);
    let variance = test_image(37, 23, false);
    let metadata = render_metadata();
    write_exr(&path, &image, &[(VARIANCE_LAYER, &variance)], &metadata).unwrap();
    let contents = read_exr(&path).unwrap();
    assert_bit_identical(&image, &contents.image);
    assert_bit_identical(&variance, &contents.layers[VARIANCE_LAYER]);
    assert_eq!(contents.layers.len(), 1);
    for (key, value) in &metadata {
        assert_eq!(contents.metadata.get(key), Some(value), "metadata '{key}'");
    }

    // Through the extension-driven entry points too.
    let path = directory.join("plain.EXR");
    write_image(&path, &image, &metadata).unwrap();
    assert_bit_identical(&image, &read_image(&path).unwrap());
}

#[test]
fn exr_rejects_reserved_metadata_keys_and_mismatched_layers() {
    let directory = scratch_directory("exr-errors");
    let path = directory.join("bad.exr");
    let image = test_image(4, 4, false);
    let metadata: Metadata = [("channels".to_string(), "x".to_string())].into();
    let message = write_exr(&path, &image, &[], &metadata)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("bad.exr") && message.contains("reserved"),
        "{message}"
    );
    let small = test_image(2, 2, false);
    let message = write_exr(&path, &image, &[("variance", &small)], &Metadata::new())
        .unwrap_err()
        .to_string();
    assert!(message.contains("2x2"), "{message}");
}

#[test]
fn pfm_round_trip_is_bit_exact() {
    let directory = scratch_directory("pfm");
    let path = directory.join("round_trip.pfm");
    let image = test_image(19, 11, true);
    write_pfm(&path, &image).unwrap();
    assert_bit_identical(&image, &read_pfm(&path).unwrap());
    write_image(&path, &image, &Metadata::new()).unwrap();
    assert_bit_identical(&image, &read_image(&path).unwrap());
}

#[test]
fn pfm_reads_big_endian_grey_bottom_to_top() {
    let directory = scratch_directory("pfm-grey");
    let path = directory.join("grey.pfm");
    // 2x2 grey, big-endian (positive scale), rows bottom to top.
    let mut bytes = b"Pf\n2 2\n4.0\n".to_vec();
    for value in [1.0f32, 2.0, 3.0, 4.0] {
        bytes.extend_from_slice(&value.to_be_bytes());
    }
    std::fs::write(&path, bytes).unwrap();
    let image = read_pfm(&path).unwrap();
    assert_eq!(image.pixels(), &[[3.0; 3], [4.0; 3], [1.0; 3], [2.0; 3]]);
}

#[test]
fn png_round_trip_is_within_quantisation() {
    let directory = scratch_directory("png");
    let path = directory.join("round_trip.png");
    let width = 32;
    let pixels = (0..width * 8)
        .map(|index| {
            let t = index as f32 / (width * 8 - 1) as f32;
            [t, t * t, 1.0 - t]
        })
        .collect();
    let image = Image::from_pixels(width, 8, pixels).unwrap();
    write_png(&path, &image, 0.0, &render_metadata()).unwrap();
    let decoded = read_png(&path).unwrap();
    assert_eq!((decoded.width(), decoded.height()), (width, 8));
    // Quantisation to 256 levels of the encoded value: half a level.
    for (original, read) in image.pixels().iter().zip(decoded.pixels()) {
        for channel in 0..3 {
            let error = (linear_to_srgb(original[channel]) - linear_to_srgb(read[channel])).abs();
            assert!(error <= 0.5 / 255.0 + 1e-5, "{original:?} vs {read:?}");
        }
    }

    // Exposure: one stop down halves linear values before encoding.
    let bright = Image::from_pixels(1, 1, vec![[0.5, 1.0, 1.5]]).unwrap();
    write_png(&path, &bright, -1.0, &Metadata::new()).unwrap();
    let read = read_png(&path).unwrap().pixels()[0];
    for (channel, expected) in [0.25f32, 0.5, 0.75].into_iter().enumerate() {
        let error = (linear_to_srgb(expected) - linear_to_srgb(read[channel])).abs();
        assert!(error <= 0.5 / 255.0 + 1e-5, "{read:?}");
    }
}

#[test]
fn png_clamps_and_zeroes_nan() {
    let directory = scratch_directory("png-clamp");
    let path = directory.join("clamp.png");
    let image = Image::from_pixels(1, 1, vec![[f32::NAN, -3.0, 42.0]]).unwrap();
    write_image(&path, &image, &Metadata::new()).unwrap();
    assert_eq!(read_image(&path).unwrap().pixels()[0], [0.0, 0.0, 1.0]);
}

fn expect_message(result: Result<Image, ImageError>, path: &Path, words: &[&str]) {
    let message = result.expect_err("reading should fail").to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    for word in words {
        assert!(message.contains(word), "'{word}' missing in: {message}");
    }
}

#[test]
fn errors_name_the_file_and_the_problem() {
    let directory = scratch_directory("errors");
    for extension in ["exr", "pfm", "png"] {
        let missing = directory.join(format!("missing.{extension}"));
        expect_message(read_image(&missing), &missing, &["cannot read"]);
    }

    let truncated = directory.join("truncated.pfm");
    let mut bytes = b"PF\n4 4\n-1\n".to_vec();
    bytes.extend(std::iter::repeat_n(0u8, 100));
    std::fs::write(&truncated, bytes).unwrap();
    expect_message(
        read_image(&truncated),
        &truncated,
        &["truncated", "192 bytes", "100"],
    );

    let header_only = directory.join("header_only.pfm");
    std::fs::write(&header_only, b"PF\n4").unwrap();
    expect_message(
        read_image(&header_only),
        &header_only,
        &["truncated", "header"],
    );

    let not_pfm = directory.join("not.pfm");
    std::fs::write(&not_pfm, b"P6\n4 4\n255\n").unwrap();
    expect_message(read_image(&not_pfm), &not_pfm, &["not a valid PFM", "P6"]);

    let unknown = directory.join("image.tga");
    expect_message(read_image(&unknown), &unknown, &["unsupported", ".exr"]);
    let message = write_image(&unknown, &Image::new(1, 1), &Metadata::new())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("image.tga") && message.contains("unsupported"),
        "{message}"
    );

    // A truncated EXR and PNG: valid files cut in half.
    let image = test_image(16, 16, false);
    for extension in ["exr", "png"] {
        let whole = directory.join(format!("whole.{extension}"));
        write_image(&whole, &image, &Metadata::new()).unwrap();
        let bytes = std::fs::read(&whole).unwrap();
        let cut = directory.join(format!("cut.{extension}"));
        std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        expect_message(read_image(&cut), &cut, &[]);
        let garbage = directory.join(format!("garbage.{extension}"));
        std::fs::write(&garbage, b"this is not an image").unwrap();
        expect_message(read_image(&garbage), &garbage, &["not a valid"]);
    }
}

#[test]
fn reads_tungsten_cornell_box_reference() {
    // Vendored in the repository (scenes/external/bitterli, CC0).
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/external/bitterli/cornell-box/TungstenRender.exr");
    let path = path.as_path();
    let contents = read_exr(path).unwrap();
    let image = &contents.image;
    let mean = image.mean();
    println!(
        "Tungsten Cornell box: {}x{}, mean RGB {:?}, layers {:?}, metadata {:?}",
        image.width(),
        image.height(),
        mean,
        contents.layers.keys().collect::<Vec<_>>(),
        contents.metadata
    );
    assert!(image.width() > 0 && image.height() > 0);
    assert!(
        mean.iter()
            .all(|&channel| channel.is_finite() && channel > 0.0)
    );
}

#[test]
fn exr_reads_half_rgba_and_grey_files() {
    use exr::prelude::{
        AnyChannel, AnyChannels, Encoding, FlatSamples, Image as ExrImage, Layer, LayerAttributes,
        SmallVec, WritableImage, f16,
    };
    let directory = scratch_directory("exr-half");
    // Half RGBA written by the exr crate (as Tungsten writes half RGB).
    let values = [0.5f32, 1.0, 2.0, 0.125, 65504.0, -3.0];
    let path = directory.join("half.exr");
    let half = |offset: usize| {
        FlatSamples::F16(
            (0..6)
                .map(|index| f16::from_f32(values[(index + offset) % 6]))
                .collect(),
        )
    };
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (offset, name) in ["R", "G", "B", "A"].into_iter().enumerate() {
        channels.push(AnyChannel::new(name, half(offset)));
    }
    let layer = Layer::new(
        (3, 2),
        LayerAttributes::default(),
        Encoding::SMALL_FAST_LOSSLESS,
        AnyChannels::sort(channels),
    );
    ExrImage::from_layer(layer).write().to_file(&path).unwrap();
    let image = read_image(&path).unwrap();
    assert_eq!((image.width(), image.height()), (3, 2));
    for (index, pixel) in image.pixels().iter().enumerate() {
        assert_eq!(
            *pixel,
            [
                values[index % 6],
                values[(index + 1) % 6],
                values[(index + 2) % 6]
            ]
        );
    }

    // A luminance-only file is replicated into RGB.
    let path = directory.join("grey.exr");
    let grey: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::from_vec(vec![AnyChannel::new(
        "Y",
        FlatSamples::F32(values.to_vec()),
    )]);
    let layer = Layer::new(
        (2, 3),
        LayerAttributes::default(),
        Encoding::UNCOMPRESSED,
        AnyChannels::sort(grey),
    );
    ExrImage::from_layer(layer).write().to_file(&path).unwrap();
    let image = read_image(&path).unwrap();
    assert_eq!((image.width(), image.height()), (2, 3));
    assert_eq!(image.pixel(1, 2), Some([values[5]; 3]));
}

#[test]
fn png_reads_16_bit_grey_alpha() {
    let directory = scratch_directory("png16");
    let path = directory.join("grey16.png");
    let levels = [0u16, 1000, 32768, 65535];
    let file = std::fs::File::create(&path).unwrap();
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), 2, 2);
    encoder.set_color(png::ColorType::GrayscaleAlpha);
    encoder.set_depth(png::BitDepth::Sixteen);
    let mut writer = encoder.write_header().unwrap();
    let data: Vec<u8> = levels
        .iter()
        .flat_map(|&level| [level.to_be_bytes(), 7u16.to_be_bytes()].concat())
        .collect();
    writer.write_image_data(&data).unwrap();
    writer.finish().unwrap();
    let image = read_png(&path).unwrap();
    for (pixel, level) in image.pixels().iter().zip(levels) {
        let expected = render::image::srgb_to_linear(level as f32 / 65535.0);
        assert_eq!(*pixel, [expected; 3]);
    }
}

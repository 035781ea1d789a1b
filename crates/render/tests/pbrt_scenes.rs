//! The pbrt-v4 loader on real scenes: Bitterli's pbrt-v4 conversions of the
//! Cornell box and Veach's MIS scene (`scenes/external/bitterli/`) load,
//! and the Cornell box renders to the image mean of Tungsten's reference.
//!
//! The reference `TungstenRender.exr` (1024 × 1024, half float, PIZ; the
//! project's EXR reader reads it) is an RGB render. We render at 128 × 128
//! with the scene's own triangle filter (the image mean is the mean
//! radiance over the image plane at any resolution) and check, with the
//! issue's 2 % tolerance: the luminance of the image mean against
//! Tungsten's, every channel against Mitsuba 3's spectral render of the same
//! scene (see [`MITSUBA_SPECTRAL_MEAN`] for why blue is not compared with
//! Tungsten), and red and green in each image half against Tungsten (3 %),
//! which catches a mirrored camera. Our standard error (about 0.3 % in R
//! and G, 0.6 % in B) is printed.

#[path = "support/scratch_directory.rs"]
mod scratch_directory;
use scratch_directory::ScratchDirectory;

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use render::image::read_image;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::{MaterialDescription, ShapeGeometry};
use render::scene::loader::{LoadOptions, LoadedScene, load_scene_file};

fn bitterli(scene: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/external/bitterli")
        .join(scene)
}

fn load(scene: &str) -> LoadedScene {
    let path = bitterli(scene).join("scene-v4.pbrt");
    load_scene_file(&path, &LoadOptions::default())
        .unwrap_or_else(|error| panic!("{}: {error}", path.display()))
}

#[test]
fn cornell_box_loads_with_the_files_settings() {
    let loaded = load("cornell-box");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let description = &loaded.description;
    assert_eq!(description.camera.resolution, [1024, 1024]);
    assert_eq!(description.samples_per_pixel, Some(64));
    // pbrt's maxdepth 65 scattering events = 66 segments.
    assert_eq!(description.max_depth, Some(66));
    assert_eq!(description.shapes.len(), 8);
    assert_eq!(
        description
            .shapes
            .iter()
            .filter(|s| s.emission.is_some())
            .count(),
        1
    );
    // The camera at (0, 1, 6.8) looks down world −z.
    let eye = description
        .camera
        .world_from_camera
        .transform_point3(glam::Vec3::ZERO);
    assert!(
        (eye - glam::Vec3::new(0.0, 1.0, 6.8)).length() < 1e-5,
        "{eye}"
    );
    Scene::build(description).expect("the Cornell box builds");
}

#[test]
fn veach_mis_loads() {
    let loaded = load("veach-mis");
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let description = &loaded.description;
    assert_eq!(description.camera.resolution, [1280, 720]);
    assert_eq!(description.max_depth, Some(4));
    let spheres = description
        .shapes
        .iter()
        .filter(|s| matches!(s.geometry, ShapeGeometry::Sphere { .. }))
        .count();
    // Three spherical lights of different sizes (the fourth light of the
    // original scene is not in the pbrt conversion).
    assert_eq!(spheres, 3);
    let rough_conductors = description
        .shapes
        .iter()
        .filter(|s| {
            matches!(
                &s.material,
                MaterialDescription::Conductor {
                    roughness: Some(r),
                    ..
                } if !r.remap
            )
        })
        .count();
    assert_eq!(rough_conductors, 4);
    // Rendering it waits for the rough conductors (another branch); until
    // then building reports them as unsupported.
}

/// Image means of the same Cornell box (Bitterli's `scene.xml`) rendered by
/// Mitsuba 3.9.1 `scalar_spectral` at 128 × 128, 256 spp, depth 66, tent
/// filter:
///
/// ```python
/// mi.set_variant("scalar_spectral")
/// scene = mi.load_file(".../cornell-box/scene.xml", integrator="path",
///                      resx=128, resy=128, spp=256, max_depth=66)
/// np.array(mi.render(scene, spp=256))[..., :3].reshape(-1, 3).mean(axis=0)
/// ```
///
/// `scalar_rgb` gives (0.19626, 0.12754, 0.03610), Tungsten's image to
/// 0.01 %: Tungsten renders in RGB. A spectral renderer's product of the
/// lifted reflectance and emission spectra is not the product of their RGB
/// values, which shifts the saturated blue channel by −4 % (Mitsuba) — not a
/// loader error, so the blue channel is compared with Mitsuba's spectral
/// render, and Tungsten is compared by luminance and in red and green.
const MITSUBA_SPECTRAL_MEAN: [f64; 3] = [0.194_852_4, 0.126_627_31, 0.034_737_18];

fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Mean of the columns `[from, to)` of an image given as rows of pixels.
fn column_mean(pixels: &[[f64; 3]], width: usize, from: usize, to: usize) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut count = 0.0;
    for (index, pixel) in pixels.iter().enumerate() {
        if (from..to).contains(&(index % width)) {
            for channel in 0..3 {
                sum[channel] += pixel[channel];
            }
            count += 1.0;
        }
    }
    sum.map(|s| s / count)
}

#[test]
fn cornell_box_image_mean_matches_tungsten() {
    let reference_path = bitterli("cornell-box").join("TungstenRender.exr");
    let reference = read_image(&reference_path)
        .unwrap_or_else(|error| panic!("{}: {error}", reference_path.display()));
    let reference_pixels: Vec<[f64; 3]> = reference
        .pixels()
        .iter()
        .map(|p| p.map(f64::from))
        .collect();
    let reference_mean = reference.mean();

    let mut description = load("cornell-box").description;
    const SIDE: usize = 128;
    const SAMPLES: u64 = 64;
    description.camera.resolution = [SIDE as u32; 2];
    let scene = Scene::build(&description).expect("the Cornell box builds");
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: SAMPLES,
        max_depth: description.max_depth.unwrap(),
        threads: 2,
        seed: 7,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {})
        .expect("the Cornell box renders");
    let mut pixels = Vec::with_capacity(SIDE * SIDE);
    let mut variance = [0.0; 3];
    for y in 0..SIDE {
        for x in 0..SIDE {
            let pixel = output.film.pixel(x, y).unwrap();
            pixels.push(pixel.weighted_mean());
            for (sum, value) in variance.iter_mut().zip(pixel.variance_of_mean()) {
                *sum += value;
            }
        }
    }
    let count = (SIDE * SIDE) as f64;
    let mean = column_mean(&pixels, SIDE, 0, SIDE);
    for channel in 0..3 {
        let sigma = variance[channel].sqrt() / count;
        eprintln!(
            "channel {channel}: ours {:.5} ± {sigma:.5}, Tungsten {:.5} (ratio {:.4}), Mitsuba spectral {:.5} (ratio {:.4})",
            mean[channel],
            reference_mean[channel],
            mean[channel] / reference_mean[channel],
            MITSUBA_SPECTRAL_MEAN[channel],
            mean[channel] / MITSUBA_SPECTRAL_MEAN[channel],
        );
        let ratio = mean[channel] / MITSUBA_SPECTRAL_MEAN[channel];
        assert!(
            (ratio - 1.0).abs() < 0.02,
            "channel {channel}: image mean {} vs Mitsuba spectral {} (ratio {ratio})",
            mean[channel],
            MITSUBA_SPECTRAL_MEAN[channel]
        );
    }
    let ratio = luminance(mean) / luminance(reference_mean);
    eprintln!("luminance: ratio to Tungsten {ratio:.4}");
    assert!(
        (ratio - 1.0).abs() < 0.02,
        "luminance ratio to Tungsten {ratio}"
    );
    // Red and green per half image: the red wall on the left, the green
    // one on the right, as in Tungsten's image (a mirrored camera fails).
    let half = |pixels: &[[f64; 3]], width: usize, left: bool| {
        if left {
            column_mean(pixels, width, 0, width / 2)
        } else {
            column_mean(pixels, width, width / 2, width)
        }
    };
    for left in [true, false] {
        let ours = half(&pixels, SIDE, left);
        let theirs = half(&reference_pixels, reference.width(), left);
        for channel in 0..2 {
            let ratio = ours[channel] / theirs[channel];
            eprintln!(
                "{} half, channel {channel}: ratio to Tungsten {ratio:.4}",
                if left { "left" } else { "right" }
            );
            assert!(
                (ratio - 1.0).abs() < 0.03,
                "{} half, channel {channel}: {} vs Tungsten's {} (ratio {ratio})",
                if left { "left" } else { "right" },
                ours[channel],
                theirs[channel]
            );
        }
    }
}

/// Truncated and corrupted copies of a real scene give a scene or an error,
/// never a panic (a small deterministic stand-in for the fuzz target).
#[test]
fn truncated_and_corrupted_files_never_panic() {
    let original = std::fs::read(bitterli("cornell-box").join("scene-v4.pbrt")).unwrap();
    let directory = ScratchDirectory::new("pbrt-corrupt");
    let path = directory.join("scene.pbrt");
    let mut variants: Vec<Vec<u8>> = (0..original.len())
        .step_by(97)
        .map(|end| original[..end].to_vec())
        .collect();
    for (index, replacement) in (0..original.len())
        .step_by(89)
        .zip([b'"', b'[', b']', b'#', b'x', b'-', b'\n'].iter().cycle())
    {
        let mut corrupted = original.clone();
        corrupted[index] = *replacement;
        variants.push(corrupted);
    }
    let mut loaded = 0;
    for bytes in &variants {
        std::fs::write(&path, bytes).unwrap();
        if let Ok(scene) = load_scene_file(&path, &LoadOptions::default()) {
            loaded += 1;
            let mut description = scene.description;
            description.camera.resolution = [4, 4];
            let _ = Scene::build(&description);
        }
    }
    assert!(loaded > 0);
}

/// A scene written here: a diffuse sphere (pbrt's default material,
/// reflectance 0.5) under a uniform infinite light of radiance 1. A convex
/// Lambertian surface sees the whole sky and nothing else, so it reflects
/// exactly 0.5; the sky shows 1. Checks the camera (LookAt, fov), the
/// infinite light, the default material and the depth convention
/// (`maxdepth 1`: one scattering event is enough) end to end.
#[test]
fn a_diffuse_sphere_under_a_uniform_sky_reflects_half() {
    let directory = ScratchDirectory::new("pbrt-sky");
    let path = directory.join("sky.pbrt");
    std::fs::write(
        &path,
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
         Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
         Sampler \"sobol\" \"integer pixelsamples\" 256\nPixelFilter \"box\"\n\
         Integrator \"path\" \"integer maxdepth\" 1\n\
         WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\nShape \"sphere\" \"float radius\" 1\n",
    )
    .unwrap();
    let loaded = load_scene_file(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let description = loaded.description;
    assert_eq!(description.max_depth, Some(2));
    let scene = Scene::build(&description).expect("the scene builds");
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: description.samples_per_pixel.unwrap(),
        max_depth: description.max_depth.unwrap(),
        threads: 2,
        seed: 3,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    // The sphere (radius 1 at distance 5 under a 30° fov) covers the centre;
    // the corners see the sky.
    for (x, y, expected) in [(7, 7, 0.5), (8, 8, 0.5), (0, 0, 1.0), (15, 15, 1.0)] {
        let pixel = output.film.pixel(x, y).unwrap();
        let mean = pixel.weighted_mean();
        let variance = pixel.variance_of_mean();
        for channel in 0..3 {
            let tolerance = 4.0 * variance[channel].sqrt() + 0.01 * expected;
            assert!(
                (mean[channel] - expected).abs() < tolerance,
                "pixel ({x}, {y}) channel {channel}: {} (expected {expected} ± {tolerance})",
                mean[channel]
            );
        }
    }
}

/// The directional albedo at normal incidence of a layered BSDF, from
/// `count` of its samples (mean weight and standard error).
fn normal_incidence_albedo(
    sample: impl Fn(f32, [f32; 2]) -> Option<render::material::BsdfSample>,
    count: usize,
) -> (f64, f64) {
    let mut state = 0x1234_5678_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let weights: Vec<f64> = (0..count)
        .map(|_| {
            let (a, b, c) = (next(), next(), next());
            sample(a, [b, c]).map_or(0.0, |s| f64::from(s.value[0] * s.wi.z.abs() / s.pdf))
        })
        .collect();
    let n = count as f64;
    let mean = weights.iter().sum::<f64>() / n;
    let variance = weights.iter().map(|w| (w - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// Renders `material` (a pbrt `Material` line) on a unit sphere under a
/// uniform sky of radiance 1 with one bounce, and checks the centre 2 × 2
/// pixels against `expected` ± (4σ of the render + `tolerance`).
fn furnace_sphere(name: &str, material: &str, expected: f64, tolerance: f64) -> LoadedScene {
    let directory = ScratchDirectory::new(&format!("pbrt-furnace-{name}"));
    let path = directory.join("furnace.pbrt");
    std::fs::write(
        &path,
        format!(
            "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\n\
             Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\n\
             Sampler \"sobol\" \"integer pixelsamples\" 128\nPixelFilter \"box\"\n\
             Integrator \"path\" \"integer maxdepth\" 1\n\
             WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
             {material}\n\
             Shape \"sphere\" \"float radius\" 1\n"
        ),
    )
    .unwrap();
    let loaded = load_scene_file(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let description = &loaded.description;
    let scene = Scene::build(description).expect("the furnace scene builds");
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: description.samples_per_pixel.unwrap(),
        max_depth: description.max_depth.unwrap(),
        threads: 2,
        seed: 5,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    // The centre 2 × 2 pixels see the sphere nearly head-on (cos θ > 0.97).
    for (x, y) in [(3, 3), (4, 4), (3, 4), (4, 3)] {
        let pixel = output.film.pixel(x, y).unwrap();
        let mean = pixel.weighted_mean();
        let variance = pixel.variance_of_mean();
        for channel in 0..3 {
            let sigma = variance[channel].sqrt();
            eprintln!(
                "{name} ({x}, {y}) channel {channel}: {:.4} ± {sigma:.4} (expected {expected:.4})",
                mean[channel]
            );
            assert!(
                (mean[channel] - expected).abs() < 4.0 * sigma + tolerance,
                "{name} pixel ({x}, {y}) channel {channel}: {} ± {sigma} vs {expected}",
                mean[channel]
            );
        }
    }
    loaded
}

/// pbrt-v4's `coateddiffuse` end to end: a white base under a smooth coating
/// with a clear layer of thickness 0 reflects all light (the walk follows
/// the internal reflections up to `maxdepth` 100), so a sphere of it under a
/// uniform sky of radiance 1 shows 1 everywhere — a white furnace through
/// the loader, `Scene::build`, the stochastic BSDF and the path tracer's
/// MIS (which takes the BSDF's density estimate). A rough coating (pbrt
/// roughness 0.3, α = √0.3) loses its microfacet model's energy: the render
/// must show the BSDF's own albedo at normal incidence (estimated from its
/// samples; the centre pixels' cosines are within 3 % of 1, where the
/// albedo is flat, hence 1 % tolerance).
#[test]
fn a_white_coated_diffuse_sphere_in_a_furnace_reflects_everything() {
    use render::material::{
        CoatedDiffuseBsdf, MicrofacetDistribution, MicrofacetKind, TransportMode,
    };
    use render::spectrum::SampledSpectrum;
    let loaded = furnace_sphere(
        "coated-smooth",
        "Material \"coateddiffuse\" \"rgb reflectance\" [1 1 1] \"float thickness\" 0 \
         \"integer maxdepth\" 100 \"float roughness\" 0",
        1.0,
        0.01,
    );
    assert!(matches!(
        loaded.description.shapes[0].material,
        MaterialDescription::CoatedDiffuse { max_depth: 100, .. }
    ));
    let alpha = 0.3f32.sqrt();
    let bsdf = CoatedDiffuseBsdf::new(
        SampledSpectrum::splat(1.0),
        1.5,
        Some(MicrofacetDistribution::new(
            MicrofacetKind::Ggx,
            alpha,
            alpha,
        )),
        0.0,
        SampledSpectrum::splat(0.0),
        0.0,
        100,
        1,
    );
    let wo = glam::Vec3::Z;
    let (albedo, error) = normal_incidence_albedo(
        |u_component, u| bsdf.sample(wo, u_component, u, TransportMode::Radiance),
        40_000,
    );
    eprintln!("rough coated diffuse: albedo at normal incidence {albedo:.4} ± {error:.4}");
    assert!(albedo < 1.0 && albedo > 0.5);
    furnace_sphere(
        "coated-rough",
        "Material \"coateddiffuse\" \"rgb reflectance\" [1 1 1] \"float thickness\" 0 \
         \"integer maxdepth\" 100 \"float roughness\" 0.3",
        albedo,
        4.0 * error + 0.01,
    );
}

/// pbrt-v4's `coatedconductor` end to end: a perfect conductor (η = κ = 0,
/// reflectance 1) under a smooth coating with a clear layer of thickness 0
/// reflects everything (a delta BSDF: the walk's internal reflections sum
/// to 1); with a rough coating and a rough conductor the render shows the
/// BSDF's own albedo at normal incidence, which is below 1 (single-
/// scattering microfacets) — through the loader's prefixed parameters,
/// the division of the conductor's index by the coating's, and the path
/// tracer's MIS with the layered density estimate.
#[test]
fn a_perfect_coated_conductor_sphere_in_a_furnace() {
    use render::material::{
        CoatedConductorBsdf, ConductorReflectance, MicrofacetDistribution, MicrofacetKind,
        TransportMode,
    };
    use render::spectrum::SampledSpectrum;
    let loaded = furnace_sphere(
        "coatedconductor-smooth",
        "Material \"coatedconductor\" \"float conductor.eta\" 0 \"float conductor.k\" 0 \
         \"float thickness\" 0 \"integer maxdepth\" 100",
        1.0,
        0.01,
    );
    assert!(matches!(
        loaded.description.shapes[0].material,
        MaterialDescription::CoatedConductor { max_depth: 100, .. }
    ));
    let ggx = |roughness: f32| {
        let alpha = roughness.sqrt();
        MicrofacetDistribution::new(MicrofacetKind::Ggx, alpha, alpha)
    };
    let bsdf = CoatedConductorBsdf::new(
        1.5,
        Some(ggx(0.1)),
        ConductorReflectance::Fresnel {
            eta: SampledSpectrum::splat(0.0),
            k: SampledSpectrum::splat(0.0),
        },
        Some(ggx(0.05)),
        0.0,
        SampledSpectrum::splat(0.0),
        0.0,
        100,
        1,
    );
    let wo = glam::Vec3::Z;
    let (albedo, error) = normal_incidence_albedo(
        |u_component, u| bsdf.sample(wo, u_component, u, TransportMode::Radiance),
        40_000,
    );
    eprintln!("rough coated conductor: albedo at normal incidence {albedo:.4} ± {error:.4}");
    assert!(albedo < 1.0 && albedo > 0.5);
    furnace_sphere(
        "coatedconductor-rough",
        "Material \"coatedconductor\" \"float conductor.eta\" 0 \"float conductor.k\" 0 \
         \"float thickness\" 0 \"integer maxdepth\" 100 \"float interface.roughness\" 0.1 \
         \"float conductor.roughness\" 0.05",
        albedo,
        4.0 * error + 0.01,
    );
}

//! Bidirectional path tracing (`--integrator bdpt`) converges to the path
//! tracer's image: the image-mean t-test and the per-pixel z-test of
//! [`path_comparison`], with variances from independent seeds, on the
//! built-in scenes it handles, with the independent sampler and with
//! randomized QMC (Halton, randomized by the seed); pbrt-v4's furnace gives
//! one; the balance and power heuristics agree.

use render::integrators::bdpt::BdptSettings;
use render::integrators::{IntegratorKind, IntegratorSettings};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use std::sync::atomic::AtomicBool;

mod path_comparison;
use path_comparison::{
    SEEDS, Tested, assert_matches_path, builtin, mean_and_error, render_with, values,
};

const BDPT: Tested = Tested {
    integrator: IntegratorKind::Bdpt,
    sampler: SamplerKind::Independent,
};

const BDPT_HALTON: Tested = Tested {
    integrator: IntegratorKind::Bdpt,
    sampler: SamplerKind::Halton,
};

#[test]
fn bdpt_matches_path_tracing_in_the_cornell_box() {
    assert_matches_path(
        "cornell-box",
        &builtin("cornell-box"),
        BDPT,
        4096,
        64,
        None,
        true,
    );
}

#[test]
fn bdpt_with_halton_matches_path_tracing_in_the_cornell_box() {
    assert_matches_path(
        "cornell-box (Halton)",
        &builtin("cornell-box"),
        BDPT_HALTON,
        4096,
        64,
        None,
        true,
    );
}

/// Kollig & Keller's samplers: quasi-Monte Carlo sequences over the whole
/// image (randomized by the seed, so that renders are independent) and
/// randomized point sets (Cranley–Patterson rotated Hammersley, padded
/// replications, Latin supercube), in the Cornell box.
#[test]
fn bdpt_with_kollig_keller_samplers_matches_path_tracing() {
    let scene = builtin("cornell-box");
    for sampler in [
        SamplerKind::GlobalSobol,
        SamplerKind::GlobalNiederreiter,
        SamplerKind::Hammersley,
        SamplerKind::Padded,
        SamplerKind::LatinSupercube,
    ] {
        assert_matches_path(
            &format!("cornell-box ({})", sampler.name()),
            &scene,
            Tested {
                integrator: IntegratorKind::Bdpt,
                sampler,
            },
            4096,
            32,
            None,
            true,
        );
    }
}

#[test]
fn bdpt_matches_path_tracing_in_the_office() {
    assert_matches_path("office", &builtin("office"), BDPT, 4096, 64, None, true);
}

/// A thin lens and a sky (a constant environment): the lens point and the
/// vertices at infinity.
#[test]
fn bdpt_matches_path_tracing_with_depth_of_field_and_a_sky() {
    assert_matches_path(
        "dof-spheres",
        &builtin("dof-spheres"),
        BDPT,
        4096,
        64,
        None,
        true,
    );
}

/// The Cornell box with every surface but the light's normal-mapped to a
/// constant tangent-space normal tilted about 13° from the geometric one
/// (RGB (0.6, 0.5, 0.95) encodes (0.2, 0, 0.9)): the shading normals differ
/// from the geometric ones everywhere, and directions near the horizon lie
/// on different sides of the two.
fn normal_mapped_cornell_box() -> render::scene::Scene {
    normal_mapped_cornell_box_with([0.6, 0.5, 0.95], Default::default())
}

/// [`normal_mapped_cornell_box`] with tangent-space normal `rgb` and the
/// perturbation `options`.
fn normal_mapped_cornell_box_with(
    rgb: [f32; 3],
    options: render::material::PerturbationOptions,
) -> render::scene::Scene {
    use render::scene::description::{
        MaterialDescription, SpectrumDescription, TextureDescription,
    };
    let mut description =
        path_comparison::small(render::scene::builtin::builtin_scene("cornell-box").unwrap());
    for shape in &mut description.shapes {
        if shape.emission.is_none() {
            let nested = std::mem::replace(&mut shape.material, MaterialDescription::Black);
            shape.material = MaterialDescription::NormalMap {
                normals: TextureDescription::Constant(SpectrumDescription::Rgb(rgb)),
                nested: Box::new(nested),
                options,
            };
        }
    }
    render::scene::Scene::build(&description).unwrap()
}

/// Shading normals from a normal map: the adjoint correction on the light
/// subpath, the shading cosines of the connections and the densities of the
/// MIS weights. 16 × 1024 BDPT samples against 65,536 path-traced ones per
/// pixel (the connections' value itself is checked exactly, without noise,
/// by `material::bsdf`'s test of both transport modes).
#[test]
fn bdpt_matches_path_tracing_with_a_normal_map() {
    assert_matches_path(
        "normal-mapped cornell-box",
        &normal_mapped_cornell_box(),
        BDPT,
        65536,
        1024,
        None,
        true,
    );
}

/// Mitsuba 3.7.1's `flip_invalid_normals` and shadowing term on a normal
/// map tilted about 37° (RGB (0.8, 0.5, 0.9) encodes (0.6, 0, 0.8)): the
/// frame then depends on the camera-side direction, which light subpaths
/// sample from the two frames with probability ½ each. 16 × 256 BDPT
/// samples against 16,384 path-traced ones per pixel.
#[test]
fn bdpt_matches_path_tracing_with_flipped_normals() {
    assert_matches_path(
        "cornell-box, normals flipped as Mitsuba's",
        &normal_mapped_cornell_box_with(
            [0.8, 0.5, 0.9],
            render::material::PerturbationOptions::MITSUBA,
        ),
        BDPT,
        16384,
        256,
        None,
        true,
    );
}

/// `dof-spheres` with a sun: a directional light (irradiance 2, from above
/// and to the side) added to its sky and area light, or (`sun_only`)
/// instead of them.
fn sunlit_spheres(sun_only: bool) -> render::scene::Scene {
    use render::scene::description::{LightDescription, SpectrumDescription};
    let mut description =
        path_comparison::small(render::scene::builtin::builtin_scene("dof-spheres").unwrap());
    if sun_only {
        description.lights.clear();
        for shape in &mut description.shapes {
            shape.emission = None;
        }
    }
    description.lights.push(LightDescription::Directional {
        direction: glam::Vec3::new(0.5, -1.0, 0.4).normalize(),
        irradiance: SpectrumDescription::Rgb([2.0, 1.9, 1.7]),
    });
    render::scene::Scene::build(&description).unwrap()
}

/// A directional light, the only light: its light subpaths start on the
/// disk that covers the scene, and every strategy but the camera's reaching
/// it (a delta in direction) shares the paths.
#[test]
fn bdpt_matches_path_tracing_under_a_directional_light() {
    assert_matches_path(
        "dof-spheres, sun only",
        &sunlit_spheres(true),
        BDPT,
        4096,
        64,
        None,
        true,
    );
}

/// A directional light with a sky and an area light: the light subpaths
/// start at all three kinds of light.
#[test]
fn bdpt_matches_path_tracing_with_a_sun_a_sky_and_an_area_light() {
    assert_matches_path(
        "dof-spheres with a sun",
        &sunlit_spheres(false),
        BDPT,
        4096,
        64,
        None,
        true,
    );
}

/// The path tracer is the noisy one in the caustic (see `light_tracing.rs`):
/// the image mean is asserted, the per-pixel test reported.
#[test]
fn bdpt_matches_path_tracing_around_a_glass_sphere() {
    assert_matches_path(
        "glass-sphere-box",
        &builtin("glass-sphere-box"),
        BDPT,
        4096,
        64,
        None,
        false,
    );
}

/// The image means of `SEEDS` renders with `heuristic`.
fn image_means(
    name: &str,
    heuristic: render::integrators::MisHeuristic,
    spp: u64,
    max_depth: u32,
) -> Vec<f64> {
    image_means_of(name, IntegratorKind::Bdpt.into(), heuristic, spp, max_depth)
}

/// The image means of `SEEDS` renders with `integrator` and `heuristic`.
fn image_means_of(
    name: &str,
    integrator: IntegratorSettings,
    heuristic: render::integrators::MisHeuristic,
    spp: u64,
    max_depth: u32,
) -> Vec<f64> {
    let scene = builtin(name);
    (0..SEEDS)
        .map(|seed| {
            let settings = RenderSettings {
                integrator: integrator.clone(),
                sampler: SamplerKind::Independent,
                samples_per_pixel: spp,
                seed,
                max_depth,
                heuristic,
                ..RenderSettings::default()
            };
            let image = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {})
                .unwrap()
                .image();
            values(&image).sum::<f64>() / (image.pixels().len() * 3) as f64
        })
        .collect()
}

/// pbrt-v4's analytic furnace: every pixel is 1 (the depth limit of 64
/// segments leaves 0.5^63 of it out).
#[test]
fn bdpt_in_the_furnace_gives_one() {
    let means = image_means("furnace", render::integrators::MisHeuristic::Balance, 8, 64);
    let (mean, error) = mean_and_error(&means);
    let t = (mean - 1.0) / error;
    eprintln!("furnace (bdpt): mean {mean:.5} ± {error:.5} (t = {t:.2})");
    assert!(t.abs() < 4.5, "furnace mean {mean} ± {error}");
}

/// The balance and power heuristics weigh the same strategies differently
/// but both sum to one: the images agree in the mean.
#[test]
fn balance_and_power_heuristics_agree() {
    use render::integrators::MisHeuristic;
    let (balance, balance_error) =
        mean_and_error(&image_means("cornell-box", MisHeuristic::Balance, 16, 6));
    let (power, power_error) =
        mean_and_error(&image_means("cornell-box", MisHeuristic::Power, 16, 6));
    let t = (balance - power) / (balance_error.powi(2) + power_error.powi(2)).sqrt();
    eprintln!(
        "cornell-box: balance {balance:.5} ± {balance_error:.5}, power {power:.5} ± {power_error:.5} (t = {t:.2})"
    );
    assert!(t.abs() < 4.5, "balance {balance} vs power {power}");
}

/// Without the light-tracing strategies (Kollig & Keller's OFFICE setting)
/// the other strategies' weights still sum to one: the image mean is the
/// full BDPT's.
#[test]
fn without_camera_connections_the_image_is_the_same() {
    use render::integrators::MisHeuristic;
    let without = IntegratorSettings::Bdpt(BdptSettings {
        camera_connections: false,
        ..BdptSettings::default()
    });
    let (full, full_error) = mean_and_error(&image_means("office", MisHeuristic::Balance, 64, 3));
    let (skipped, skipped_error) = mean_and_error(&image_means_of(
        "office",
        without,
        MisHeuristic::Balance,
        64,
        3,
    ));
    let t = (full - skipped) / (full_error.powi(2) + skipped_error.powi(2)).sqrt();
    eprintln!(
        "office, depth 3: all strategies {full:.5} ± {full_error:.5}, without t = 1 {skipped:.5} ± {skipped_error:.5} (t = {t:.2})"
    );
    assert!(t.abs() < 4.5, "{full} vs {skipped}");
}

/// The strategy images (pbrt-v4's `visualizestrategies`) sum to the image:
/// every contribution is in exactly one of them.
#[test]
fn strategy_images_sum_to_the_image() {
    let scene = builtin("glass-sphere-box");
    let settings = RenderSettings {
        integrator: IntegratorSettings::Bdpt(BdptSettings {
            strategy_images: true,
            ..BdptSettings::default()
        }),
        samples_per_pixel: 4,
        max_depth: 5,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    let layers = output.auxiliary_image("strategies").unwrap();
    let names: Vec<&str> = layers.iter().map(|(name, _)| *name).collect();
    for expected in ["s0_t2", "s0_t3", "s1_t2", "s2_t1", "s2_t2", "s3_t1"] {
        assert!(
            names.contains(&expected),
            "{expected} missing from {names:?}"
        );
    }
    // Depth 5: no strategy of more than six vertices.
    assert!(!names.iter().any(|name| {
        let (s, t) = name[1..].split_once("_t").unwrap();
        s.parse::<usize>().unwrap() + t.parse::<usize>().unwrap() > 6
    }));
    let image = output.image();
    let mut sum = vec![0.0f64; image.pixels().len() * 3];
    for (_, layer) in layers {
        for (total, value) in sum.iter_mut().zip(values(layer)) {
            *total += value;
        }
    }
    for (index, (total, value)) in sum.iter().zip(values(&image)).enumerate() {
        assert!(
            (total - value).abs() <= 1e-4 * value.abs() + 1e-6,
            "pixel channel {index}: strategies sum to {total}, image {value}"
        );
    }
}

/// Every image is finite and not black in a scene BDPT handles, at every
/// depth from emitters only (1) to six segments.
#[test]
fn depths_from_one_segment_on() {
    let scene = builtin("cornell-box");
    let mut previous = 0.0;
    for max_depth in 1..=6 {
        let (image, _) = render_with(
            &scene,
            IntegratorKind::Bdpt,
            SamplerKind::Independent,
            4,
            0,
            max_depth,
        );
        let sum: f64 = values(&image).sum();
        assert!(sum.is_finite() && sum > 0.0, "depth {max_depth}: {sum}");
        // More segments add light.
        assert!(
            sum > previous * 0.99,
            "depth {max_depth}: {sum} after {previous}"
        );
        previous = sum;
    }
}

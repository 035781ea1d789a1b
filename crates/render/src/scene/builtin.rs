//! Built-in scenes (`builtin:NAME`): small analytic or classic scenes that
//! need no files, for tests, benchmarks and the default render.

use super::description::{
    FilterDescription, LightDescription, MaterialDescription, MediumCoefficients,
    MediumDescription, MicrofacetDistribution, PhaseDescription, RoughnessDescription,
    SceneDescription, ShapeDescription, ShapeGeometry, SpectrumDescription, TextureDescription,
    polygon_mesh,
};
use crate::camera::{FovAxis, PerspectiveSettings, look_at};
use glam::{Affine3A, Quat, Vec3};

/// The built-in scenes: name and a one-line description.
pub const BUILTIN_SCENES: [(&str, &str); 9] = [
    (
        "cornell-box",
        "Mitsuba 3's RGB Cornell box (cbox-rgb.xml): diffuse walls and boxes, one area light",
    ),
    (
        "dof-spheres",
        "diffuse spheres at several depths on a plane, thin lens, an area light (LQMC Fig. 7 kind)",
    ),
    (
        "glass-sphere-box",
        "a box with a glass sphere and a small ceiling light: a caustic (Kollig-Keller GLASS SPHERE kind)",
    ),
    (
        "office",
        "a diffuse room, two rectangular ceiling luminaires and a small spherical lamp (Kollig-Keller OFFICE kind)",
    ),
    (
        "furnace",
        "inside a closed sphere with diffuse albedo 0.5 emitting 0.5: every pixel is exactly 1",
    ),
    (
        "translucent-spheres",
        "dielectric spheres filled with scattering media on a plane, shallow depth of field (LQMC teapot kind; volpath)",
    ),
    (
        "volumetric-caustic",
        "a coloured beam refracted by a glass sphere in a foggy room: a volumetric caustic (LQMC Fig. 12 kind; volpath)",
    ),
    (
        "heinrich-keller",
        "a furnished diffuse room of 276 triangles with two rectangular ceiling lights (Heinrich & Keller's test scene kind)",
    ),
    (
        "ajar-door",
        "a room lit only through a door ajar from a second room's ceiling light; glossy floor, gold and plastic spheres (LQMC Fig. 8 kind; scenes/ajar-door/ajar-door.xml)",
    ),
];

/// The scene used when none is named.
pub const DEFAULT_SCENE: &str = "cornell-box";

/// The built-in scene `name`, or `None` if there is no such scene.
pub fn builtin_scene(name: &str) -> Option<SceneDescription> {
    match name {
        "cornell-box" => Some(cornell_box()),
        "dof-spheres" => Some(dof_spheres()),
        "glass-sphere-box" => Some(glass_sphere_box()),
        "office" => Some(office()),
        "furnace" => Some(furnace()),
        "translucent-spheres" => Some(translucent_spheres()),
        "volumetric-caustic" => Some(volumetric_caustic()),
        "heinrich-keller" => Some(heinrich_keller_room()),
        "ajar-door" => Some(ajar_door()),
        _ => None,
    }
}

fn diffuse(r: f32, g: f32, b: f32) -> MaterialDescription {
    MaterialDescription::diffuse_rgb([r, g, b])
}

fn camera(
    eye: [f32; 3],
    target: [f32; 3],
    fov_degrees: f32,
    fov_axis: FovAxis,
    resolution: [u32; 2],
) -> PerspectiveSettings {
    let world = look_at(eye.into(), target.into(), Vec3::Y).expect("valid built-in camera");
    PerspectiveSettings {
        world_from_camera: world,
        world_from_camera_end: world,
        resolution,
        fov_degrees,
        fov_axis,
        ..Default::default()
    }
}

/// A box-shaped block: top, four sides and bottom from the four corners of
/// its footprint (counter-clockwise seen from above) and its height.
fn block(footprint: [[f32; 2]; 4], height: f32) -> ShapeGeometry {
    let top: Vec<[f32; 3]> = footprint.iter().map(|c| [c[0], height, c[1]]).collect();
    let bottom: Vec<[f32; 3]> = footprint.iter().rev().map(|c| [c[0], 0.0, c[1]]).collect();
    let mut sides: Vec<Vec<[f32; 3]>> = Vec::new();
    for i in 0..4 {
        let (a, b) = (footprint[i], footprint[(i + 1) % 4]);
        sides.push(vec![
            [b[0], 0.0, b[1]],
            [b[0], height, b[1]],
            [a[0], height, a[1]],
            [a[0], 0.0, a[1]],
        ]);
    }
    let mut polygons: Vec<&[[f32; 3]]> = vec![&top, &bottom];
    polygons.extend(sides.iter().map(Vec::as_slice));
    polygon_mesh(&polygons)
}

/// Mitsuba 3's `scenes/cbox/cbox-rgb.xml`, geometry from its OBJ files
/// (the classic Cornell box measurements), materials and emitter as there.
fn cornell_box() -> SceneDescription {
    let white = diffuse(0.885809, 0.698859, 0.666422);
    let boxes = diffuse(0.45, 0.30, 0.90);
    let quad = |corners: [[f32; 3]; 4]| polygon_mesh(&[&corners]);
    let shapes = vec![
        ShapeDescription::new(
            // Lowered by 0.5 as in Mitsuba's scene, to sit just below the ceiling.
            quad([
                [343.0, 548.3, 227.0],
                [343.0, 548.3, 332.0],
                [213.0, 548.3, 332.0],
                [213.0, 548.3, 227.0],
            ]),
            diffuse(0.936461, 0.740433, 0.705267),
        )
        .emitting([18.387, 10.9873, 2.75357]),
        ShapeDescription::new(
            quad([
                [552.8, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 559.2],
                [549.6, 0.0, 559.2],
            ]),
            white.clone(),
        ),
        ShapeDescription::new(
            quad([
                [556.0, 548.8, 0.0],
                [556.0, 548.8, 559.2],
                [0.0, 548.8, 559.2],
                [0.0, 548.8, 0.0],
            ]),
            white.clone(),
        ),
        ShapeDescription::new(
            quad([
                [549.6, 0.0, 559.2],
                [0.0, 0.0, 559.2],
                [0.0, 548.8, 559.2],
                [556.0, 548.8, 559.2],
            ]),
            white,
        ),
        ShapeDescription::new(
            quad([
                [0.0, 0.0, 559.2],
                [0.0, 0.0, 0.0],
                [0.0, 548.8, 0.0],
                [0.0, 548.8, 559.2],
            ]),
            diffuse(0.105421, 0.37798, 0.076425),
        ),
        ShapeDescription::new(
            quad([
                [552.8, 0.0, 0.0],
                [549.6, 0.0, 559.2],
                [556.0, 548.8, 559.2],
                [556.0, 548.8, 0.0],
            ]),
            diffuse(0.570068, 0.0430135, 0.0443706),
        ),
        ShapeDescription::new(
            block(
                [[130.0, 65.0], [82.0, 225.0], [240.0, 272.0], [290.0, 114.0]],
                165.0,
            ),
            boxes.clone(),
        ),
        ShapeDescription::new(
            block(
                [
                    [423.0, 247.0],
                    [265.0, 296.0],
                    [314.0, 456.0],
                    [472.0, 406.0],
                ],
                330.0,
            ),
            boxes,
        ),
    ];
    SceneDescription {
        name: "cornell-box".into(),
        camera: camera(
            [278.0, 273.0, -800.0],
            [278.0, 273.0, -799.0],
            39.3077,
            FovAxis::Smaller,
            [256, 256],
        ),
        filter: FilterDescription::Box { radius: 0.5 },
        shapes,
        lights: Vec::new(),
        max_depth: Some(6),
        // Few enough that `lqmc render` with no arguments takes a few seconds.
        samples_per_pixel: Some(16),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

/// A ground plane facing +y of half-size `half`.
fn ground(half: f32, material: MaterialDescription) -> ShapeDescription {
    ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: Affine3A::from_rotation_x(-std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(half)),
        },
        material,
    )
}

/// A rectangle light facing down at height `height`, half-size `half`.
fn ceiling_light(center: [f32; 3], half: [f32; 2], radiance: [f32; 3]) -> ShapeDescription {
    ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: Affine3A::from_translation(center.into())
                * Affine3A::from_rotation_x(std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::new(half[0], half[1], 1.0)),
        },
        MaterialDescription::Black,
    )
    .emitting(radiance)
}

fn dof_spheres() -> SceneDescription {
    let colours = [
        [0.8, 0.2, 0.2],
        [0.8, 0.6, 0.2],
        [0.2, 0.7, 0.3],
        [0.2, 0.4, 0.8],
        [0.6, 0.3, 0.8],
    ];
    let mut shapes = vec![
        ground(20.0, diffuse(0.6, 0.6, 0.6)),
        ceiling_light([0.0, 6.0, 3.0], [1.5, 1.5], [12.0, 12.0, 12.0]),
    ];
    for (i, colour) in colours.iter().enumerate() {
        let depth = 1.0 + 1.6 * i as f32;
        let x = -1.2 + 0.6 * i as f32;
        shapes.push(ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::new(x, 0.5, depth),
                radius: 0.5,
            },
            diffuse(colour[0], colour[1], colour[2]),
        ));
    }
    let eye = Vec3::new(0.0, 1.0, -3.0);
    let focus = Vec3::new(0.0, 0.5, 4.2);
    let mut camera = camera(eye.into(), focus.into(), 40.0, FovAxis::X, [320, 240]);
    camera.lens_radius = 0.12;
    camera.focus_distance = (focus - eye).length();
    SceneDescription {
        name: "dof-spheres".into(),
        camera,
        filter: FilterDescription::Gaussian {
            radius: 1.5,
            sigma: 0.5,
        },
        shapes,
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([0.05, 0.06, 0.08]),
        }],
        max_depth: Some(8),
        samples_per_pixel: Some(64),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

/// The five walls of a box [−1, 1]³ open towards −z, seen from inside.
fn open_box(left: MaterialDescription, right: MaterialDescription) -> Vec<ShapeDescription> {
    let white = diffuse(0.75, 0.75, 0.75);
    let wall = |rotation: Quat, translation: [f32; 3]| ShapeGeometry::Rectangle {
        to_world: Affine3A::from_rotation_translation(rotation, translation.into()),
    };
    use std::f32::consts::FRAC_PI_2;
    vec![
        // Floor (normal +y), ceiling (−y), back (−z), left (+x), right (−x).
        ShapeDescription::new(
            wall(Quat::from_rotation_x(-FRAC_PI_2), [0.0, -1.0, 0.0]),
            white.clone(),
        ),
        ShapeDescription::new(
            wall(Quat::from_rotation_x(FRAC_PI_2), [0.0, 1.0, 0.0]),
            white.clone(),
        ),
        ShapeDescription::new(
            wall(Quat::from_rotation_y(std::f32::consts::PI), [0.0, 0.0, 1.0]),
            white,
        ),
        ShapeDescription::new(
            wall(Quat::from_rotation_y(FRAC_PI_2), [-1.0, 0.0, 0.0]),
            left,
        ),
        ShapeDescription::new(
            wall(Quat::from_rotation_y(-FRAC_PI_2), [1.0, 0.0, 0.0]),
            right,
        ),
    ]
}

fn glass_sphere_box() -> SceneDescription {
    let mut shapes = open_box(diffuse(0.63, 0.065, 0.05), diffuse(0.14, 0.45, 0.091));
    shapes.push(ceiling_light(
        [0.0, 0.995, 0.0],
        [0.15, 0.15],
        [60.0, 60.0, 60.0],
    ));
    shapes.push(ShapeDescription::new(
        ShapeGeometry::Sphere {
            center: Vec3::new(0.25, -0.6, 0.1),
            radius: 0.4,
        },
        MaterialDescription::smooth_dielectric(1.5),
    ));
    shapes.push(ShapeDescription::new(
        ShapeGeometry::Cube {
            to_world: Affine3A::from_scale_rotation_translation(
                Vec3::new(0.2, 0.35, 0.2),
                Quat::from_rotation_y(0.4),
                Vec3::new(-0.45, -0.65, 0.45),
            ),
        },
        diffuse(0.75, 0.75, 0.75),
    ));
    SceneDescription {
        name: "glass-sphere-box".into(),
        camera: camera(
            [0.0, 0.0, -3.4],
            [0.0, 0.0, 0.0],
            40.0,
            FovAxis::X,
            [256, 256],
        ),
        filter: FilterDescription::Box { radius: 0.5 },
        shapes,
        lights: Vec::new(),
        max_depth: Some(12),
        samples_per_pixel: Some(64),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

fn office() -> SceneDescription {
    use std::f32::consts::FRAC_PI_2;
    // A room 6 wide (x), 3 high (y), 5 deep (z), seen from near the front wall.
    let wall_material = diffuse(0.7, 0.66, 0.58);
    let rect = |rotation: Quat, scale: [f32; 2], translation: [f32; 3]| ShapeGeometry::Rectangle {
        to_world: Affine3A::from_scale_rotation_translation(
            Vec3::new(scale[0], scale[1], 1.0),
            rotation,
            translation.into(),
        ),
    };
    let mut shapes = vec![
        ShapeDescription::new(
            rect(
                Quat::from_rotation_x(-FRAC_PI_2),
                [3.0, 2.5],
                [0.0, 0.0, 2.5],
            ),
            diffuse(0.35, 0.3, 0.25),
        ),
        ShapeDescription::new(
            rect(
                Quat::from_rotation_x(FRAC_PI_2),
                [3.0, 2.5],
                [0.0, 3.0, 2.5],
            ),
            diffuse(0.8, 0.8, 0.8),
        ),
        ShapeDescription::new(
            rect(
                Quat::from_rotation_y(std::f32::consts::PI),
                [3.0, 1.5],
                [0.0, 1.5, 5.0],
            ),
            wall_material.clone(),
        ),
        ShapeDescription::new(
            rect(Quat::IDENTITY, [3.0, 1.5], [0.0, 1.5, 0.0]),
            wall_material.clone(),
        ),
        ShapeDescription::new(
            rect(
                Quat::from_rotation_y(FRAC_PI_2),
                [2.5, 1.5],
                [-3.0, 1.5, 2.5],
            ),
            wall_material.clone(),
        ),
        ShapeDescription::new(
            rect(
                Quat::from_rotation_y(-FRAC_PI_2),
                [2.5, 1.5],
                [3.0, 1.5, 2.5],
            ),
            diffuse(0.5, 0.6, 0.7),
        ),
        ceiling_light([-1.2, 2.98, 2.5], [0.6, 0.15], [12.0, 11.5, 10.0]),
        ceiling_light([1.2, 2.98, 2.5], [0.6, 0.15], [12.0, 11.5, 10.0]),
        // Desk top and a cabinet.
        ShapeDescription::new(
            ShapeGeometry::Cube {
                to_world: Affine3A::from_scale_rotation_translation(
                    Vec3::new(0.8, 0.025, 0.4),
                    Quat::IDENTITY,
                    Vec3::new(0.5, 0.75, 3.8),
                ),
            },
            diffuse(0.45, 0.3, 0.18),
        ),
        ShapeDescription::new(
            ShapeGeometry::Cube {
                to_world: Affine3A::from_scale_rotation_translation(
                    Vec3::new(0.25, 0.36, 0.35),
                    Quat::IDENTITY,
                    Vec3::new(1.0, 0.36, 3.8),
                ),
            },
            diffuse(0.6, 0.6, 0.62),
        ),
        // The small spherical lamp on the desk.
        ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::new(0.2, 0.86, 3.85),
                radius: 0.06,
            },
            MaterialDescription::Black,
        )
        .emitting([40.0, 32.0, 20.0]),
    ];
    shapes.push(ShapeDescription::new(
        ShapeGeometry::Cube {
            to_world: Affine3A::from_scale_rotation_translation(
                Vec3::new(0.3, 0.45, 0.3),
                Quat::from_rotation_y(0.3),
                Vec3::new(-1.8, 0.45, 3.6),
            ),
        },
        diffuse(0.3, 0.35, 0.5),
    ));
    SceneDescription {
        name: "office".into(),
        camera: camera(
            [-2.2, 1.6, 0.4],
            [0.6, 0.9, 3.8],
            60.0,
            FovAxis::X,
            [320, 240],
        ),
        filter: FilterDescription::Box { radius: 0.5 },
        shapes,
        lights: Vec::new(),
        max_depth: Some(8),
        samples_per_pixel: Some(64),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

/// pbrt-v4's analytic test: inside a closed sphere of diffuse albedo ρ = 0.5
/// emitting L_e = 0.5, every path sees L = L_e / (1 − ρ) = 1.
fn furnace() -> SceneDescription {
    SceneDescription {
        name: "furnace".into(),
        camera: camera([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 60.0, FovAxis::X, [64, 64]),
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![
            ShapeDescription::new(
                ShapeGeometry::Sphere {
                    center: Vec3::ZERO,
                    radius: 1.0,
                },
                diffuse(0.5, 0.5, 0.5),
            )
            .emitting([0.5, 0.5, 0.5])
            .flipped(),
        ],
        lights: Vec::new(),
        // Deep enough that the truncated series 1 − 2^−D is 1 in f32.
        max_depth: Some(100),
        samples_per_pixel: Some(16),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

/// A medium given by Mitsuba's parameters (RGB albedo, scalar extinction).
fn albedo_medium(albedo: [f32; 3], sigma_t: f32, phase: PhaseDescription) -> MediumDescription {
    MediumDescription {
        coefficients: MediumCoefficients::AlbedoExtinction {
            albedo: SpectrumDescription::Rgb(albedo),
            sigma_t: SpectrumDescription::Constant(sigma_t),
        },
        scale: 1.0,
        phase,
    }
}

/// Three glass spheres filled with scattering media (a milky white, a jade
/// green, a wax red) at different depths on a diffuse plane, lit by a large
/// area light and a dim sky, seen through a thin lens focused on the middle
/// one: subsurface-like transport under a shallow depth of field, the kind
/// of the LQMC paper's translucent teapot. Needs `--integrator volpath`
/// (the default for scenes with media).
fn translucent_spheres() -> SceneDescription {
    let media = vec![
        albedo_medium(
            [0.99, 0.98, 0.96],
            12.0,
            PhaseDescription::HenyeyGreenstein { g: 0.3 },
        ),
        albedo_medium(
            [0.45, 0.95, 0.65],
            8.0,
            PhaseDescription::HenyeyGreenstein { g: 0.5 },
        ),
        albedo_medium([0.97, 0.55, 0.35], 10.0, PhaseDescription::Isotropic),
    ];
    let mut shapes = vec![
        ground(20.0, diffuse(0.5, 0.5, 0.5)),
        ceiling_light([-1.0, 4.0, 1.5], [1.2, 1.2], [10.0, 10.0, 10.0]),
    ];
    for (index, (x, z)) in [(-0.9f32, 0.6f32), (0.1, 2.0), (1.1, 3.6)]
        .into_iter()
        .enumerate()
    {
        let mut sphere = ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::new(x, 0.5, z),
                radius: 0.5,
            },
            // Rough glass (GGX, α = 0.1): the translucent look.
            MaterialDescription::Dielectric {
                interior_ior: SpectrumDescription::Constant(1.5),
                exterior_ior: 1.0,
                roughness: Some(RoughnessDescription {
                    distribution: MicrofacetDistribution::Ggx,
                    alpha_u: TextureDescription::Constant(SpectrumDescription::Constant(0.1)),
                    alpha_v: TextureDescription::Constant(SpectrumDescription::Constant(0.1)),
                    remap: false,
                }),
            },
        );
        sphere.interior_medium = Some(index);
        shapes.push(sphere);
    }
    let eye = Vec3::new(0.0, 1.2, -2.6);
    let focus = Vec3::new(0.1, 0.5, 2.0);
    let mut camera = camera(eye.into(), focus.into(), 40.0, FovAxis::X, [128, 96]);
    camera.lens_radius = 0.1;
    camera.focus_distance = (focus - eye).length();
    SceneDescription {
        name: "translucent-spheres".into(),
        camera,
        filter: FilterDescription::Gaussian {
            radius: 1.5,
            sigma: 0.5,
        },
        shapes,
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([0.08, 0.09, 0.12]),
        }],
        media,
        camera_medium: None,
        max_depth: Some(32),
        samples_per_pixel: Some(16),
        russian_roulette_depth: None,
        integrator: Some("volpath".into()),
    }
}

/// A closed grey room filled with thin fog (the camera inside it). A warm
/// coloured beam leaves a black collimator tube on the left wall and passes
/// through a smooth glass sphere, which focuses it into a bright cone in the
/// fog behind the sphere: a volumetric caustic, reachable only by paths that
/// scatter in the fog and then refract twice on the way to the light (the
/// kind of the LQMC paper's Fig. 12). A dim ceiling light shows the room.
/// Needs `--integrator volpath`.
fn volumetric_caustic() -> SceneDescription {
    let fog = MediumDescription {
        coefficients: MediumCoefficients::AbsorptionScattering {
            sigma_a: SpectrumDescription::Constant(0.01),
            sigma_s: SpectrumDescription::Constant(0.25),
        },
        scale: 1.0,
        phase: PhaseDescription::HenyeyGreenstein { g: 0.4 },
    };
    // The room [−3, 3] × [0, 3] × [−3, 3] (diffuse is two-sided, so the
    // cube's outward normals do not matter).
    let room = ShapeDescription::new(
        ShapeGeometry::Cube {
            to_world: Affine3A::from_scale_rotation_translation(
                Vec3::new(3.0, 1.5, 3.0),
                Quat::IDENTITY,
                Vec3::new(0.0, 1.5, 0.0),
            ),
        },
        diffuse(0.4, 0.4, 0.4),
    );
    // A square tube along +x from x = −3 to −1.8 at height 1.5, open at the
    // end facing the sphere, with the emitter at its closed end.
    let (x0, x1, y, h) = (-3.0f32, -1.8f32, 1.5f32, 0.12f32);
    let tube = polygon_mesh(&[
        &[
            [x0, y - h, -h],
            [x1, y - h, -h],
            [x1, y - h, h],
            [x0, y - h, h],
        ],
        &[
            [x0, y + h, -h],
            [x0, y + h, h],
            [x1, y + h, h],
            [x1, y + h, -h],
        ],
        &[
            [x0, y - h, -h],
            [x0, y + h, -h],
            [x1, y + h, -h],
            [x1, y - h, -h],
        ],
        &[
            [x0, y - h, h],
            [x1, y - h, h],
            [x1, y + h, h],
            [x0, y + h, h],
        ],
    ]);
    let emitter = ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: Affine3A::from_translation(Vec3::new(x0 + 0.01, y, 0.0))
                * Affine3A::from_rotation_y(std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::new(h, h, 1.0)),
        },
        MaterialDescription::Black,
    )
    .emitting([5000.0, 2000.0, 500.0]);
    let mut sphere = ShapeDescription::new(
        ShapeGeometry::Sphere {
            center: Vec3::new(-0.6, y, 0.0),
            radius: 0.6,
        },
        MaterialDescription::smooth_dielectric(1.5),
    );
    // Clear glass inside, fog outside.
    sphere.exterior_medium = Some(0);
    let eye = Vec3::new(0.5, 1.9, -2.8);
    let target = Vec3::new(0.3, 1.4, 0.0);
    SceneDescription {
        name: "volumetric-caustic".into(),
        camera: camera(eye.into(), target.into(), 70.0, FovAxis::X, [128, 96]),
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![
            room,
            ShapeDescription::new(tube, MaterialDescription::Black),
            emitter,
            sphere,
            // A dim ceiling light so that the room shows.
            ceiling_light([0.0, 2.99, 1.0], [0.5, 0.5], [0.8, 0.8, 0.8]),
        ],
        lights: Vec::new(),
        media: vec![fog],
        camera_medium: Some(0),
        max_depth: Some(12),
        samples_per_pixel: Some(16),
        russian_roulette_depth: None,
        integrator: Some("volpath".into()),
    }
}

/// An axis-aligned box from `min` to `max` as a mesh of 6 quads (12
/// triangles), wound outwards.
fn cuboid(min: [f32; 3], max: [f32; 3]) -> ShapeGeometry {
    let [x0, y0, z0] = min;
    let [x1, y1, z1] = max;
    polygon_mesh(&[
        &[[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]], // bottom (−y)
        &[[x0, y1, z0], [x0, y1, z1], [x1, y1, z1], [x1, y1, z0]], // top (+y)
        &[[x0, y0, z0], [x0, y1, z0], [x1, y1, z0], [x1, y0, z0]], // front (−z)
        &[[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], // back (+z)
        &[[x0, y0, z0], [x0, y0, z1], [x0, y1, z1], [x0, y1, z0]], // left (−x)
        &[[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]], // right (+x)
    ])
}

/// One planar quad (2 triangles) from its corners in order.
fn quad(corners: [[f32; 3]; 4]) -> ShapeGeometry {
    polygon_mesh(&[&corners])
}

/// A table or chair: a top box and four legs of square section `leg`
/// under its corners, down to the floor (5 boxes, 60 triangles).
fn four_legged(top_min: [f32; 3], top_max: [f32; 3], leg: f32) -> Vec<ShapeGeometry> {
    let [x0, y0, z0] = top_min;
    let [x1, _, z1] = top_max;
    let mut parts = vec![cuboid(top_min, top_max)];
    for (x, z) in [
        (x0, z0),
        (x1 - leg, z0),
        (x0, z1 - leg),
        (x1 - leg, z1 - leg),
    ] {
        parts.push(cuboid([x, 0.0, z], [x + leg, y0, z + leg]));
    }
    parts
}

/// The kind of scene Heinrich & Keller (1994) measure radiance per triangle
/// in (their Table 1: a furnished room of 276 triangles, untextured):
/// a closed room 6 × 3 × 5 with two rectangular ceiling lights facing down,
/// a table and two chairs, a cabinet, a shelf, a sofa, a rug, a door, a
/// window and a picture, all diffuse with RGB reflectances. Every surface
/// is a triangle mesh (276 triangles: the room 12, the lights 4, the
/// table 60, the chairs 144, the four boxes 48, the four flat quads 8), so
/// that the particle study can report each triangle's radiance.
fn heinrich_keller_room() -> SceneDescription {
    let (width, height, depth) = (6.0f32, 3.0f32, 5.0f32);
    let mut shapes = vec![
        // The room's shell: floor, ceiling and four walls.
        ShapeDescription::new(
            quad([
                [0.0, 0.0, 0.0],
                [0.0, 0.0, depth],
                [width, 0.0, depth],
                [width, 0.0, 0.0],
            ]),
            diffuse(0.55, 0.45, 0.35),
        ),
        ShapeDescription::new(
            quad([
                [0.0, height, 0.0],
                [width, height, 0.0],
                [width, height, depth],
                [0.0, height, depth],
            ]),
            diffuse(0.8, 0.8, 0.8),
        ),
        ShapeDescription::new(
            quad([
                [0.0, 0.0, depth],
                [0.0, height, depth],
                [width, height, depth],
                [width, 0.0, depth],
            ]),
            diffuse(0.7, 0.65, 0.55),
        ),
        ShapeDescription::new(
            quad([
                [0.0, 0.0, 0.0],
                [width, 0.0, 0.0],
                [width, height, 0.0],
                [0.0, height, 0.0],
            ]),
            diffuse(0.7, 0.65, 0.55),
        ),
        ShapeDescription::new(
            quad([
                [0.0, 0.0, 0.0],
                [0.0, height, 0.0],
                [0.0, height, depth],
                [0.0, 0.0, depth],
            ]),
            diffuse(0.45, 0.55, 0.7),
        ),
        ShapeDescription::new(
            quad([
                [width, 0.0, 0.0],
                [width, 0.0, depth],
                [width, height, depth],
                [width, height, 0.0],
            ]),
            diffuse(0.7, 0.65, 0.55),
        ),
    ];
    // Two ceiling lights just below the ceiling, wound to face down.
    let light_y = height - 0.01;
    for (x0, z0) in [(1.5f32, 1.6f32), (3.5, 2.8)] {
        let (x1, z1) = (x0 + 1.0, z0 + 0.6);
        shapes.push(
            ShapeDescription::new(
                quad([
                    [x0, light_y, z0],
                    [x1, light_y, z0],
                    [x1, light_y, z1],
                    [x0, light_y, z1],
                ]),
                MaterialDescription::Black,
            )
            .emitting([8.0, 7.5, 6.5]),
        );
    }
    let wood = diffuse(0.5, 0.32, 0.18);
    for part in four_legged([2.2, 0.72, 2.0], [3.8, 0.77, 3.0], 0.07) {
        shapes.push(ShapeDescription::new(part, wood.clone()));
    }
    for (x, colour) in [(1.4f32, [0.7, 0.2, 0.15]), (4.1, [0.2, 0.35, 0.6])] {
        let seat = four_legged([x, 0.43, 2.25], [x + 0.45, 0.47, 2.7], 0.05);
        for part in seat {
            shapes.push(ShapeDescription::new(
                part,
                diffuse(colour[0], colour[1], colour[2]),
            ));
        }
        let back_x = if x < 3.0 { x } else { x + 0.41 };
        shapes.push(ShapeDescription::new(
            cuboid([back_x, 0.47, 2.25], [back_x + 0.04, 0.95, 2.7]),
            diffuse(colour[0], colour[1], colour[2]),
        ));
    }
    for (min, max, colour) in [
        ([0.1, 0.0, 4.3], [1.3, 1.9, 4.9], [0.6, 0.55, 0.45]), // cabinet
        ([4.6, 0.0, 4.6], [5.9, 2.1, 4.95], [0.35, 0.25, 0.15]), // shelf
        ([4.3, 0.0, 0.3], [5.8, 0.45, 1.2], [0.25, 0.5, 0.3]), // sofa seat
        ([4.3, 0.45, 0.3], [5.8, 0.9, 0.5], [0.25, 0.5, 0.3]), // sofa back
    ] {
        shapes.push(ShapeDescription::new(
            cuboid(min, max),
            diffuse(colour[0], colour[1], colour[2]),
        ));
    }
    for (corners, colour) in [
        // A rug just above the floor.
        (
            [
                [1.8, 0.005, 1.7],
                [1.8, 0.005, 3.3],
                [4.2, 0.005, 3.3],
                [4.2, 0.005, 1.7],
            ],
            [0.6, 0.15, 0.2],
        ),
        // A door on the left wall, a window on the back wall, a picture on
        // the right wall, each just off its wall.
        (
            [
                [0.005, 0.0, 1.0],
                [0.005, 2.1, 1.0],
                [0.005, 2.1, 2.0],
                [0.005, 0.0, 2.0],
            ],
            [0.4, 0.3, 0.2],
        ),
        (
            [
                [2.0, 1.0, 4.995],
                [2.0, 2.2, 4.995],
                [4.0, 2.2, 4.995],
                [4.0, 1.0, 4.995],
            ],
            [0.85, 0.9, 0.95],
        ),
        (
            [
                [5.995, 1.2, 2.0],
                [5.995, 1.2, 3.2],
                [5.995, 2.0, 3.2],
                [5.995, 2.0, 2.0],
            ],
            [0.8, 0.65, 0.2],
        ),
    ] {
        shapes.push(ShapeDescription::new(
            quad(corners),
            diffuse(colour[0], colour[1], colour[2]),
        ));
    }
    SceneDescription {
        name: "heinrich-keller".into(),
        camera: camera(
            [3.0, 1.7, 0.25],
            [3.0, 1.0, 4.0],
            75.0,
            FovAxis::X,
            [128, 96],
        ),
        filter: FilterDescription::Box { radius: 0.5 },
        shapes,
        lights: Vec::new(),
        media: Vec::new(),
        camera_medium: None,
        max_depth: Some(5),
        samples_per_pixel: Some(16),
        russian_roulette_depth: None,
        integrator: None,
    }
}

/// The ajar door's Mitsuba file, embedded: one definition that lqmc and
/// other renderers (Mitsuba 3) render alike.
const AJAR_DOOR_XML: &str = include_str!("../../../../scenes/ajar-door/ajar-door.xml");

/// The LQMC paper's Fig. 8 kind of scene (and Veach's door): a room lit
/// only through the gaps of a door ajar, from a light in the next room
/// (see the file's comment).
fn ajar_door() -> SceneDescription {
    let loaded = super::mitsuba::load_text(
        AJAR_DOOR_XML,
        std::path::Path::new("scenes/ajar-door/ajar-door.xml"),
        &super::loader::LoadOptions::default(),
    )
    .expect(
        "the embedded ajar-door scene loads (tested: every_listed_scene_exists_and_has_a_light)",
    );
    let mut description = loaded.description;
    description.name = "ajar-door".into();
    description
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_listed_scene_exists_and_has_a_light() {
        for (name, _) in BUILTIN_SCENES {
            let scene = builtin_scene(name).unwrap();
            assert_eq!(scene.name, name);
            let emitters = scene.shapes.iter().filter(|s| s.emission.is_some()).count();
            assert!(emitters + scene.lights.len() > 0, "{name}");
        }
        assert!(builtin_scene("teapot").is_none());
        assert!(builtin_scene(DEFAULT_SCENE).is_some());
    }

    /// The ajar door's camera sees no emitter (at depth 1, emitters only,
    /// the image is black) and light reaches the room through the gaps.
    #[test]
    fn the_ajar_door_hides_its_light() {
        use crate::renderer::{RenderSettings, render};
        let mut description = builtin_scene("ajar-door").unwrap();
        description.camera.resolution = [32, 24];
        let scene = crate::scene::Scene::build(&description).unwrap();
        let mean = |max_depth| {
            let settings = RenderSettings {
                samples_per_pixel: 4,
                max_depth,
                threads: 2,
                ..RenderSettings::default()
            };
            render(
                &scene,
                &settings,
                &std::sync::atomic::AtomicBool::new(false),
                &|_, _| {},
            )
            .unwrap()
            .image()
            .mean()
        };
        assert_eq!(mean(1), [0.0f64; 3]);
        let lit = mean(8);
        assert!(lit.iter().all(|&channel| channel > 0.0), "{lit:?}");
    }

    #[test]
    fn block_faces_point_outwards() {
        let ShapeGeometry::Mesh {
            positions,
            triangles,
            ..
        } = block([[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]], 1.0)
        else {
            unreachable!()
        };
        let centre = Vec3::new(0.5, 0.5, 0.5);
        for [a, b, c] in triangles {
            let (a, b, c) = (
                positions[a as usize],
                positions[b as usize],
                positions[c as usize],
            );
            let normal = (b - a).cross(c - a);
            assert!(normal.dot(a - centre) > 0.0, "inward face {a} {b} {c}");
        }
    }

    #[test]
    fn cuboid_faces_point_outwards() {
        let ShapeGeometry::Mesh {
            positions,
            triangles,
            ..
        } = cuboid([0.0, 1.0, 2.0], [1.0, 3.0, 2.5])
        else {
            unreachable!()
        };
        assert_eq!(triangles.len(), 12);
        let centre = Vec3::new(0.5, 2.0, 2.25);
        for [a, b, c] in triangles {
            let (a, b, c) = (
                positions[a as usize],
                positions[b as usize],
                positions[c as usize],
            );
            let normal = (b - a).cross(c - a);
            assert!(
                normal.dot((a + b + c) / 3.0 - centre) > 0.0,
                "inward face {a} {b} {c}"
            );
        }
    }

    /// Heinrich & Keller's kind of room: 276 triangles, all in meshes, two
    /// rectangular lights (2 triangles each) facing down into the room, every
    /// other surface diffuse; closed: rays from inside in every direction of
    /// a grid hit a surface.
    #[test]
    fn heinrich_keller_room_has_276_triangles_and_two_rectangular_lights() {
        let description = heinrich_keller_room();
        let mut triangles = 0;
        let mut lights = 0;
        for shape in &description.shapes {
            let ShapeGeometry::Mesh {
                positions,
                triangles: faces,
                ..
            } = &shape.geometry
            else {
                panic!("not a mesh: {:?}", shape.geometry);
            };
            triangles += faces.len();
            if shape.emission.is_some() {
                lights += 1;
                assert_eq!(faces.len(), 2);
                for [a, b, c] in faces {
                    let (a, b, c) = (
                        positions[*a as usize],
                        positions[*b as usize],
                        positions[*c as usize],
                    );
                    assert!((b - a).cross(c - a).y < 0.0, "a light faces up");
                }
            } else {
                assert!(
                    matches!(shape.material, MaterialDescription::Diffuse { .. }),
                    "{:?}",
                    shape.material
                );
            }
        }
        assert_eq!(triangles, 276);
        assert_eq!(lights, 2);
        let scene = crate::scene::Scene::build(&description).unwrap();
        for i in 0..16 {
            for j in 0..32 {
                let theta = (i as f32 + 0.5) * std::f32::consts::PI / 16.0;
                let phi = j as f32 * std::f32::consts::TAU / 32.0;
                let direction = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                let ray = crate::geometry::Ray::with_time(Vec3::new(3.0, 1.5, 1.0), direction, 0.0);
                assert!(
                    scene.geometry.intersect(&ray, f32::INFINITY).is_some(),
                    "escaped along {direction}"
                );
            }
        }
    }
}

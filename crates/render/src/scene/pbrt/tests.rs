//! Tests of the pbrt-v4 loader on small scenes written to a temporary
//! directory.

use super::load;
use crate::camera::FovAxis;
use crate::scene::description::{
    FilterDescription, LightDescription, MaterialDescription, MediumCoefficients, SceneDescription,
    ShapeGeometry, SpectrumDescription, TextureDescription,
};
use crate::scene::loader::{LoadOptions, LoadedScene, SceneFileError};
use crate::test_support::ScratchDirectory;
use glam::{Vec3, Vec3A};
use std::path::Path;

/// A fresh directory with the given files (name, contents), removed when
/// the returned guard is dropped.
fn scene_directory(files: &[(&str, &str)]) -> ScratchDirectory {
    let directory = ScratchDirectory::new("pbrt-test");
    for (name, contents) in files {
        let path = directory.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, contents).unwrap();
    }
    directory
}

fn load_files(files: &[(&str, &str)]) -> Result<LoadedScene, SceneFileError> {
    let directory = scene_directory(files);
    load(&directory.join(files[0].0), &LoadOptions::default())
}

fn load_source(source: &str) -> LoadedScene {
    load_files(&[("scene.pbrt", source)]).unwrap_or_else(|error| panic!("{error}"))
}

fn error_of(source: &str) -> String {
    load_files(&[("scene.pbrt", source)])
        .unwrap_err()
        .to_string()
}

const TRIANGLE: &str =
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n";

fn mesh_positions(description: &SceneDescription, index: usize) -> Vec<Vec3> {
    match &description.shapes[index].geometry {
        ShapeGeometry::Mesh { positions, .. } => positions.clone(),
        other => panic!("expected a mesh, found {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn defaults_without_camera_film_or_integrator() {
    let loaded = load_source(&format!("WorldBegin\n{TRIANGLE}"));
    let description = &loaded.description;
    assert_eq!(description.camera.resolution, [1280, 720]);
    assert_eq!(description.camera.fov_degrees, 90.0);
    assert_eq!(description.camera.fov_axis, FovAxis::Smaller);
    assert_eq!(description.samples_per_pixel, Some(16));
    // pbrt's default maxdepth 5 scattering events = 6 segments.
    assert_eq!(description.max_depth, Some(6));
    assert_eq!(
        description.filter,
        FilterDescription::Gaussian {
            radius: 1.5,
            sigma: 0.5
        }
    );
    assert_eq!(
        description.shapes[0].material,
        MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(SpectrumDescription::Constant(0.5)),
            two_sided: true
        }
    );
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn image_directives_set_resolution_samples_filter_depth() {
    let loaded = load_source(&format!(
        "Integrator \"path\" \"integer maxdepth\" [ 3 ]\n\
         Sampler \"halton\" \"integer pixelsamples\" 64\n\
         PixelFilter \"box\"\n\
         Film \"rgb\" \"integer xresolution\" [ 300 ] \"integer yresolution\" [ 200 ] \"string filename\" \"out.exr\"\n\
         Camera \"perspective\" \"float fov\" [ 30 ] \"float lensradius\" 0.1 \"float focaldistance\" 4\n\
         WorldBegin\n{TRIANGLE}"
    ));
    let description = &loaded.description;
    assert_eq!(description.camera.resolution, [300, 200]);
    assert_eq!(description.samples_per_pixel, Some(64));
    assert_eq!(description.max_depth, Some(4));
    assert_eq!(description.integrator.as_deref(), Some("path"));
    assert_eq!(description.filter, FilterDescription::Box { radius: 0.5 });
    assert_eq!(description.camera.fov_degrees, 30.0);
    assert_eq!(description.camera.lens_radius, 0.1);
    assert_eq!(description.camera.focus_distance, 4.0);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn the_camera_takes_the_inverse_ctm_in_pbrts_left_handed_frame() {
    let loaded = load_source(&format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n{TRIANGLE}"
    ));
    let world_from_camera = loaded.description.camera.world_from_camera;
    assert!(close(
        world_from_camera.transform_point3(Vec3::ZERO),
        Vec3::new(0.0, 0.0, 5.0)
    ));
    // Camera +z (the view direction) is world −z; camera +x (the image's
    // right) is world −x, as pbrt renders it.
    assert!(close(
        world_from_camera.transform_vector3(Vec3::Z),
        -Vec3::Z
    ));
    assert!(close(
        world_from_camera.transform_vector3(Vec3::X),
        -Vec3::X
    ));
    assert!(close(world_from_camera.transform_vector3(Vec3::Y), Vec3::Y));
}

#[test]
fn transforms_compose_in_pbrts_order() {
    // Translate then Scale: a point p goes to T(S(p)).
    let loaded = load_source(&format!(
        "WorldBegin\nTranslate 1 0 0\nScale 2 2 2\n{TRIANGLE}\
         AttributeBegin\nRotate 90 0 0 1\n{TRIANGLE}AttributeEnd\n\
         ConcatTransform [1 0 0 0  0 1 0 0  0 0 1 0  0 0 3 1]\n{TRIANGLE}\
         Transform [1 0 0 0  0 1 0 0  0 0 1 0  0 5 0 1]\n{TRIANGLE}\
         Identity\n{TRIANGLE}"
    ));
    let description = &loaded.description;
    let p = mesh_positions(description, 0);
    assert!(close(p[1], Vec3::new(3.0, 0.0, 0.0)), "{p:?}");
    // Rotate 90° about z after T·S: (1,0,0) → S: (2,0,0)? No: R first, then S, then T.
    let p = mesh_positions(description, 1);
    assert!(close(p[1], Vec3::new(1.0, 2.0, 0.0)), "{p:?}");
    // The attribute block restored T·S; ConcatTransform appends a z shift of 3
    // (before the scale): (1,0,0) → (1,0,3) → (2,0,6) → (3,0,6).
    let p = mesh_positions(description, 2);
    assert!(close(p[1], Vec3::new(3.0, 0.0, 6.0)), "{p:?}");
    // Transform replaces the CTM (its last four numbers are the translation).
    let p = mesh_positions(description, 3);
    assert!(close(p[1], Vec3::new(1.0, 5.0, 0.0)), "{p:?}");
    let p = mesh_positions(description, 4);
    assert!(close(p[1], Vec3::new(1.0, 0.0, 0.0)), "{p:?}");
}

#[test]
fn coordinate_systems_and_transform_blocks() {
    let loaded = load_source(&format!(
        "Translate 0 0 -2\nCamera \"perspective\"\nWorldBegin\n\
         Translate 4 0 0\nCoordinateSystem \"shifted\"\nIdentity\n\
         TransformBegin\nTranslate 0 1 0\nTransformEnd\n\
         CoordSysTransform \"shifted\"\n{TRIANGLE}\
         CoordSysTransform \"camera\"\n{TRIANGLE}\
         CoordSysTransform \"world\"\n{TRIANGLE}\
         CoordSysTransform \"nowhere\"\n"
    ));
    let description = &loaded.description;
    assert!(close(
        mesh_positions(description, 0)[0],
        Vec3::new(4.0, 0.0, 0.0)
    ));
    // The camera sits at world z = 2 (camera-from-world translates by −2).
    assert!(close(
        mesh_positions(description, 1)[0],
        Vec3::new(0.0, 0.0, 2.0)
    ));
    assert!(close(mesh_positions(description, 2)[0], Vec3::ZERO));
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(
        loaded.warnings[0].contains("scene.pbrt:16:"),
        "{:?}",
        loaded.warnings
    );
    assert!(loaded.warnings[0].contains("nowhere"));
}

#[test]
fn reverse_orientation_and_mirrors_rewind_triangles() {
    let loaded = load_source(&format!(
        "WorldBegin\n{TRIANGLE}AttributeBegin\nReverseOrientation\n{TRIANGLE}AttributeEnd\n\
         AttributeBegin\nScale 1 1 -1\n{TRIANGLE}AttributeEnd\n{TRIANGLE}"
    ));
    let normal = |index: usize| match &loaded.description.shapes[index].geometry {
        ShapeGeometry::Mesh {
            positions,
            triangles,
            ..
        } => {
            let [a, b, c] = triangles[0].map(|i| positions[i as usize]);
            (b - a).cross(c - a).normalize()
        }
        _ => unreachable!(),
    };
    assert!(close(normal(0), Vec3::Z));
    assert!(close(normal(1), -Vec3::Z));
    // The mirror maps the object's +z normal to −z, and pbrt keeps it so.
    assert!(close(normal(2), -Vec3::Z));
    // AttributeEnd restored the orientation.
    assert!(close(normal(3), Vec3::Z));
}

#[test]
fn named_materials_textures_and_area_lights() {
    let loaded = load_source(&format!(
        "WorldBegin\n\
         Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n\
         Texture \"bumps\" \"float\" \"constant\" \"float value\" 0.25\n\
         MakeNamedMaterial \"red\" \"string type\" \"diffuse\" \"texture reflectance\" \"checks\"\n\
         MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"float roughness\" 0.01\n\
         MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"float eta\" 1.33\n\
         NamedMaterial \"red\"\n{TRIANGLE}\
         NamedMaterial \"gold\"\n{TRIANGLE}\
         AttributeBegin\nMaterial \"coateddiffuse\" \"float roughness\" 0 \"texture displacement\" \"bumps\"\n\
         AreaLightSource \"diffuse\" \"rgb L\" [4 5 6] \"float scale\" 2\n{TRIANGLE}AttributeEnd\n\
         NamedMaterial \"glass\"\n{TRIANGLE}"
    ));
    let shapes = &loaded.description.shapes;
    let MaterialDescription::Diffuse {
        reflectance: TextureDescription::Checkerboard { even, odd, to_uv },
        ..
    } = &shapes[0].material
    else {
        panic!("{:?}", shapes[0].material)
    };
    assert_eq!(
        **even,
        TextureDescription::Constant(SpectrumDescription::Rgb([1.0, 0.0, 0.0]))
    );
    assert_eq!(
        **odd,
        TextureDescription::Constant(SpectrumDescription::Rgb([0.0, 0.0, 1.0]))
    );
    assert_eq!(to_uv.matrix2.x_axis.x, 4.0);
    let MaterialDescription::Conductor { eta, roughness, .. } = &shapes[1].material else {
        panic!("{:?}", shapes[1].material)
    };
    assert_eq!(*eta, SpectrumDescription::Named("metal-Au-eta".into()));
    // Roughness 0.01 remapped to α = 0.1: rough, with the remap flag.
    assert!(roughness.as_ref().is_some_and(|r| r.remap));
    let MaterialDescription::BumpMap { height, nested, .. } = &shapes[2].material else {
        panic!("{:?}", shapes[2].material)
    };
    assert_eq!(
        *height,
        TextureDescription::Constant(SpectrumDescription::Constant(0.25))
    );
    assert!(matches!(
        **nested,
        MaterialDescription::CoatedDiffuse {
            roughness: None,
            thickness: 0.01,
            interior_ior: 1.5,
            ..
        }
    ));
    assert_eq!(
        shapes[2].emission,
        Some(SpectrumDescription::Scaled {
            scale: 2.0,
            spectrum: Box::new(SpectrumDescription::Rgb([4.0, 5.0, 6.0]))
        })
    );
    // The area light ended with its attribute block.
    assert_eq!(shapes[3].emission, None);
    assert_eq!(
        shapes[3].material,
        MaterialDescription::Dielectric {
            interior_ior: SpectrumDescription::Constant(1.33),
            exterior_ior: 1.0,
            roughness: None
        }
    );
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn area_light_power_is_spread_over_the_area() {
    // A unit-area square emitting power π·(area)·L = π for L = 1.
    let loaded = load_source(
        "WorldBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 5000 \"float power\" 3.14159265\n\
         Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n",
    );
    let shape = &loaded.description.shapes[0];
    let emission = shape.emission.clone().unwrap();
    let luminance = super::spectrum_values::luminance(
        &emission,
        &super::parameters::Position {
            file: std::sync::Arc::from(Path::new("x")),
            line: 1,
        },
    )
    .unwrap();
    assert!((luminance - 1.0).abs() < 1e-3, "{luminance}");
    let ShapeGeometry::Mesh { triangles, .. } = &shape.geometry else {
        panic!()
    };
    assert_eq!(triangles.len(), 2);
}

#[test]
fn lights_spheres_disks_and_media() {
    let loaded = load_source(
        "WorldBegin\n\
         LightSource \"point\" \"rgb I\" [1 1 1] \"point3 from\" [0 2 0]\n\
         AttributeBegin\nTranslate 1 0 0\nLightSource \"spot\" \"float coneangle\" 20 \"point3 to\" [0 -1 0]\nAttributeEnd\n\
         LightSource \"distant\" \"point3 from\" [0 0 1] \"point3 to\" [0 0 0] \"float illuminance\" 2\n\
         LightSource \"infinite\" \"rgb L\" [0.5 0.5 0.5]\n\
         MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [2 2 2] \"float g\" 0.5\n\
         AttributeBegin\nMediumInterface \"fog\" \"\"\nTranslate 0 3 0\nScale 2 2 2\nShape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n\
         AttributeBegin\nReverseOrientation\nShape \"disk\" \"float radius\" 2 \"float height\" 1\nAttributeEnd\n",
    );
    let description = &loaded.description;
    assert_eq!(
        description.lights[0],
        LightDescription::Point {
            position: Vec3::new(0.0, 2.0, 0.0),
            intensity: SpectrumDescription::Rgb([1.0; 3])
        }
    );
    let LightDescription::Spot {
        to_world,
        cutoff_degrees,
        falloff_start_degrees,
        ..
    } = &description.lights[1]
    else {
        panic!("{:?}", description.lights[1])
    };
    assert_eq!((*cutoff_degrees, *falloff_start_degrees), (20.0, 15.0));
    assert!(close(to_world.transform_point3(Vec3::ZERO), Vec3::X));
    assert!(close(to_world.transform_vector3(Vec3::Z), -Vec3::Y));
    assert_eq!(
        description.lights[2],
        LightDescription::Directional {
            direction: -Vec3::Z,
            irradiance: SpectrumDescription::Scaled {
                scale: 2.0,
                spectrum: Box::new(SpectrumDescription::Rgb([1.0; 3]))
            }
        }
    );
    assert_eq!(
        description.lights[3],
        LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([0.5; 3])
        }
    );
    let sphere = &description.shapes[0];
    assert!(matches!(
        sphere.geometry,
        ShapeGeometry::Sphere { center, radius } if close(center, Vec3::new(0.0, 3.0, 0.0)) && radius == 1.0
    ));
    assert_eq!(
        (sphere.interior_medium, sphere.exterior_medium),
        (Some(0), None)
    );
    assert!(matches!(
        description.media[0].coefficients,
        MediumCoefficients::AbsorptionScattering { .. }
    ));
    let disk = &description.shapes[1];
    let ShapeGeometry::Disk { to_world } = disk.geometry else {
        panic!()
    };
    assert_eq!(to_world.translation, Vec3A::new(0.0, 0.0, 1.0));
    assert_eq!(
        to_world.transform_vector3(Vec3::X),
        Vec3::new(2.0, 0.0, 0.0)
    );
    assert!(disk.flip_normals);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn object_instances_apply_the_instance_transform_after_the_definition() {
    let loaded = load_source(&format!(
        "WorldBegin\nObjectBegin \"tri\"\nTranslate 0 0 1\n{TRIANGLE}ObjectEnd\n\
         AttributeBegin\nTranslate 10 0 0\nObjectInstance \"tri\"\nAttributeEnd\nObjectInstance \"tri\"\n"
    ));
    let description = &loaded.description;
    assert_eq!(description.shapes.len(), 2);
    assert!(close(
        mesh_positions(description, 0)[0],
        Vec3::new(10.0, 0.0, 1.0)
    ));
    assert!(close(
        mesh_positions(description, 1)[0],
        Vec3::new(0.0, 0.0, 1.0)
    ));
}

#[test]
fn include_and_import_resolve_against_the_main_files_directory() {
    let directory = scene_directory(&[
        (
            "scene.pbrt",
            "WorldBegin\nInclude \"geometry/a.pbrt\"\nImport \"geometry/b.pbrt\"\n\
             Shape \"sphere\"\n",
        ),
        // Names inside included files are relative to the main file's
        // directory too (pbrt-v4).
        (
            "geometry/a.pbrt",
            "Material \"dielectric\"\nInclude \"geometry/c.pbrt\"\n",
        ),
        ("geometry/c.pbrt", TRIANGLE),
        // Import's graphics-state changes do not leak.
        (
            "geometry/b.pbrt",
            "Material \"conductor\"\nTranslate 5 0 0\n",
        ),
    ]);
    let loaded = load(&directory.join("scene.pbrt"), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let shapes = &loaded.description.shapes;
    assert_eq!(shapes.len(), 2);
    assert!(matches!(
        shapes[0].material,
        MaterialDescription::Dielectric { .. }
    ));
    // Include is textual: the dielectric stays; Import's conductor and
    // translation do not.
    assert!(matches!(
        shapes[1].material,
        MaterialDescription::Dielectric { .. }
    ));
    assert!(matches!(
        shapes[1].geometry,
        ShapeGeometry::Sphere { center, .. } if center == Vec3::ZERO
    ));
}

#[test]
fn missing_files_name_the_path_looked_for() {
    let message = load_files(&[("scene.pbrt", "WorldBegin\n\nInclude \"nothere.pbrt\"\n")])
        .unwrap_err()
        .to_string();
    assert!(message.contains("scene.pbrt:3:"), "{message}");
    assert!(message.contains("nothere.pbrt"), "{message}");
    let message =
        error_of("WorldBegin\nShape \"plymesh\" \"string filename\" \"meshes/bunny.ply.gz\"\n");
    assert!(message.contains("scene.pbrt:2:"), "{message}");
    assert!(message.contains("meshes/bunny.ply.gz"), "{message}");
    assert!(message.contains("looked for"), "{message}");
    let message = error_of(
        "WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"wood.png\"\n",
    );
    assert!(
        message.contains("wood.png") && message.contains("looked for"),
        "{message}"
    );
    let missing = Path::new("/nonexistent/lqmc/scene.pbrt");
    let message = load(missing, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("/nonexistent/lqmc/scene.pbrt"),
        "{message}"
    );
}

#[test]
fn parameter_errors_name_file_line_and_expectation() {
    let message = error_of("WorldBegin\nShape \"sphere\"\n   \"integer radius\" [ 1 ]\n");
    assert!(
        message.starts_with(&"scene.pbrt:3:".to_string()) || message.contains("scene.pbrt:3:"),
        "{message}"
    );
    assert!(message.contains("'float'"), "{message}");
    let message = error_of("WorldBegin\nShape \"sphere\" \"float radius\" [ one ]\n");
    assert!(
        message.contains("scene.pbrt:2:") && message.contains("expected a number"),
        "{message}"
    );
    let message = error_of("WorldBegin\nShape \"sphere\" \"double radius\" 1\n");
    assert!(
        message.contains("unknown parameter type 'double'"),
        "{message}"
    );
    let message = error_of("WorldBegin\nShape \"sphere\" \"float radius\" [ 1\n");
    assert!(message.contains("expected ']'"), "{message}");
    let message = error_of("WorldBegin\nTranslate 1 2\n");
    assert!(
        message.contains("Translate: expected a number"),
        "{message}"
    );
    let message = error_of("WorldBegin\nAttributeEnd\n");
    assert!(
        message.contains("AttributeEnd without a matching AttributeBegin"),
        "{message}"
    );
    let message = error_of("WorldBegin\nNamedMaterial \"nope\"\nShape \"sphere\"\n");
    assert!(
        message.contains("scene.pbrt:2:") && message.contains("\"nope\""),
        "{message}"
    );
    let message = error_of(
        "WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]\n",
    );
    assert!(message.contains("vertex index 3"), "{message}");
    let message = error_of("WorldBegin\n\"float radius\" 1\n");
    assert!(message.contains("expected a directive"), "{message}");
}

#[test]
fn unknown_directives_plugins_and_parameters_are_warnings() {
    let loaded = load_source(&format!(
        "Integrator \"path_guiding_integrator\" \"integer maxdepth\" 7 \"float guiding\" 1\n\
         Camera \"realistic\" \"float fov\" 40\n\
         FancyDirective \"x\" 1 2 [ 3 ]\n\
         WorldBegin\n\
         Shape \"curve\" \"point3 P\" [0 0 0 1 1 1 2 2 2 3 3 3]\n\
         Material \"hair\"\n\
         LightSource \"goniometric\"\n\
         Shape \"sphere\" \"float radius\" 1 \"float unknownthing\" 3\n\
         {TRIANGLE}"
    ));
    let warnings = loaded.warnings.join("\n");
    assert!(
        warnings.contains("scene.pbrt:1: Integrator \"path_guiding_integrator\""),
        "{warnings}"
    );
    assert!(warnings.contains("command line's integrator"), "{warnings}");
    assert!(warnings.contains("\"float guiding\""), "{warnings}");
    assert!(
        warnings.contains("scene.pbrt:2: Camera \"realistic\""),
        "{warnings}"
    );
    assert!(
        warnings.contains("scene.pbrt:3: unknown directive 'FancyDirective'"),
        "{warnings}"
    );
    assert!(
        warnings.contains("scene.pbrt:5: Shape \"curve\""),
        "{warnings}"
    );
    assert!(
        warnings.contains("scene.pbrt:6: Material \"hair\""),
        "{warnings}"
    );
    assert!(
        warnings.contains("scene.pbrt:7: LightSource \"goniometric\""),
        "{warnings}"
    );
    assert!(
        warnings.contains("scene.pbrt:8: Shape \"sphere\": parameter \"float unknownthing\""),
        "{warnings}"
    );
    let description = &loaded.description;
    assert_eq!(description.integrator, None);
    assert_eq!(description.max_depth, Some(8));
    assert_eq!(description.camera.fov_degrees, 40.0);
    // The curve was skipped; the sphere and the triangle are there, the
    // triangle with the fallback material of the unknown "hair".
    assert_eq!(description.shapes.len(), 2);
}

#[test]
fn spectra_inline_named_blackbody_and_from_files() {
    let directory = scene_directory(&[
        (
            "scene.pbrt",
            "WorldBegin\n\
             Material \"diffuse\" \"spectrum reflectance\" [400 0.2 500 0.4 600 0.6]\n\
             Shape \"sphere\"\n\
             Material \"diffuse\" \"spectrum reflectance\" \"spd/refl.spd\"\n\
             Shape \"sphere\"\n\
             Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n\
             Shape \"sphere\"\n",
        ),
        ("spd/refl.spd", "# wavelength value\n400 0.1\n700 0.9\n"),
    ]);
    let loaded = load(&directory.join("scene.pbrt"), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let shapes = &loaded.description.shapes;
    let reflectance = |index: usize| match &shapes[index].material {
        MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(spectrum),
            ..
        } => spectrum.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(
        reflectance(0),
        SpectrumDescription::Sampled {
            wavelengths: vec![400.0, 500.0, 600.0],
            values: vec![0.2, 0.4, 0.6]
        }
    );
    assert_eq!(
        reflectance(1),
        SpectrumDescription::Sampled {
            wavelengths: vec![400.0, 700.0],
            values: vec![0.1, 0.9]
        }
    );
    assert!(matches!(
        &shapes[2].material,
        MaterialDescription::Dielectric { interior_ior: SpectrumDescription::Named(name), .. } if name == "glass-BK7"
    ));
    let message =
        error_of("WorldBegin\nMaterial \"diffuse\" \"spectrum reflectance\" \"missing.spd\"\n");
    assert!(
        message.contains("missing.spd") && message.contains("looked for"),
        "{message}"
    );
}

#[test]
fn a_screen_window_and_a_wide_film() {
    let loaded = load_source(&format!(
        "Film \"rgb\" \"integer xresolution\" 400 \"integer yresolution\" 100\n\
         Camera \"perspective\" \"float fov\" 45 \"float screenwindow\" [-4 4 -1 1]\nWorldBegin\n{TRIANGLE}"
    ));
    let camera = &loaded.description.camera;
    assert_eq!(camera.fov_axis, FovAxis::X);
    let expected = 2.0 * (4.0 * 22.5f32.to_radians().tan()).atan().to_degrees();
    assert!((camera.fov_degrees - expected).abs() < 1e-3);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

/// A PLY mesh (ASCII and gzip-compressed binary-equivalent) through
/// `plymesh`. Reading PLY files is `mesh_files::read_ply`'s job (the
/// Mitsuba loader's branch); this test runs once that is merged.
#[test]
fn ply_meshes_plain_and_gzipped() {
    use std::io::Write;
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let directory = scene_directory(&[
        (
            "scene.pbrt",
            "WorldBegin\nTranslate 0 0 2\nShape \"plymesh\" \"string filename\" \"meshes/tri.ply\"\n\
             Shape \"plymesh\" \"string filename\" \"meshes/tri.ply.gz\"\n",
        ),
        ("meshes/tri.ply", ply),
    ]);
    let mut encoder = flate2::write::GzEncoder::new(
        std::fs::File::create(directory.join("meshes/tri.ply.gz")).unwrap(),
        flate2::Compression::default(),
    );
    encoder.write_all(ply.as_bytes()).unwrap();
    encoder.finish().unwrap();
    let loaded = load(&directory.join("scene.pbrt"), &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    for index in 0..2 {
        let positions = mesh_positions(&loaded.description, index);
        assert!(
            close(positions[1], Vec3::new(1.0, 0.0, 2.0)),
            "{positions:?}"
        );
    }
}

#[test]
fn brass_named_spectra_load_and_build() {
    let loaded = load_source(&format!(
        "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
         Material \"conductor\" \"spectrum eta\" \"metal-CuZn-eta\" \"spectrum k\" \"metal-CuZn-k\"\n{TRIANGLE}"
    ));
    let MaterialDescription::Conductor { eta, k, .. } = &loaded.description.shapes[0].material
    else {
        panic!("{:?}", loaded.description.shapes[0].material)
    };
    assert_eq!(*eta, SpectrumDescription::Named("metal-CuZn-eta".into()));
    assert_eq!(*k, SpectrumDescription::Named("metal-CuZn-k".into()));
    crate::scene::Scene::build(&loaded.description).expect("a brass triangle builds");
    // pbrt-v4's table: η = 0.527, κ = 2.765 at 550 nm; linear in between.
    let eta = crate::scene::spectra::named_spectrum("metal-CuZn-eta").unwrap();
    let k = crate::scene::spectra::named_spectrum("metal-CuZn-k").unwrap();
    assert!((eta.evaluate(550.0) - 0.527).abs() < 1e-6);
    assert!((k.evaluate(555.0) - 0.5 * (2.765 + 2.860)).abs() < 1e-5);
    assert!((eta.evaluate(890.0) - 0.515).abs() < 1e-6);
}

#[test]
fn coated_conductors_read_prefixed_parameters_with_pbrts_defaults() {
    let loaded = load_source(&format!(
        "WorldBegin\n\
         Material \"coatedconductor\"\n{TRIANGLE}\
         Material \"coatedconductor\" \"float interface.roughness\" 0.04 \"float interface.eta\" 1.3 \
         \"spectrum conductor.eta\" \"metal-Au-eta\" \"spectrum conductor.k\" \"metal-Au-k\" \
         \"float conductor.uroughness\" 0.09 \"float conductor.vroughness\" 0.16 \
         \"float thickness\" 0.2 \"rgb albedo\" [0.5 0.5 0.5] \"float g\" 0.3 \
         \"integer maxdepth\" 20 \"integer nsamples\" 2\n{TRIANGLE}\
         Material \"coatedconductor\" \"rgb reflectance\" [0.9 0.6 0.3] \"bool remaproughness\" false \
         \"float conductor.roughness\" 0.2\n{TRIANGLE}"
    ));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let shapes = &loaded.description.shapes;
    let MaterialDescription::CoatedConductor {
        interface_ior,
        interface_roughness,
        conductor_eta,
        conductor_k,
        conductor_roughness,
        thickness,
        albedo,
        g,
        max_depth,
        samples,
    } = &shapes[0].material
    else {
        panic!("{:?}", shapes[0].material)
    };
    assert_eq!(*interface_ior, 1.5);
    assert!(interface_roughness.is_none() && conductor_roughness.is_none());
    assert_eq!(
        *conductor_eta,
        SpectrumDescription::Named("metal-Cu-eta".into())
    );
    assert_eq!(
        *conductor_k,
        SpectrumDescription::Named("metal-Cu-k".into())
    );
    assert_eq!((*thickness, *g, *max_depth, *samples), (0.01, 0.0, 10, 1));
    assert_eq!(
        *albedo,
        TextureDescription::Constant(SpectrumDescription::Constant(0.0))
    );
    let MaterialDescription::CoatedConductor {
        interface_ior,
        interface_roughness: Some(interface),
        conductor_eta,
        conductor_roughness: Some(conductor),
        thickness: 0.2,
        g: 0.3,
        max_depth: 20,
        samples: 2,
        ..
    } = &shapes[1].material
    else {
        panic!("{:?}", shapes[1].material)
    };
    assert_eq!(*interface_ior, 1.3);
    assert!(interface.remap);
    assert_eq!(
        interface.alpha_u,
        TextureDescription::Constant(SpectrumDescription::Constant(0.04))
    );
    assert_eq!(
        *conductor_eta,
        SpectrumDescription::Named("metal-Au-eta".into())
    );
    assert_eq!(
        (&conductor.alpha_u, &conductor.alpha_v),
        (
            &TextureDescription::Constant(SpectrumDescription::Constant(0.09)),
            &TextureDescription::Constant(SpectrumDescription::Constant(0.16))
        )
    );
    // An artist's reflectance: η = 1, κ from r, as for `conductor`.
    let MaterialDescription::CoatedConductor {
        conductor_eta,
        conductor_roughness: Some(conductor),
        ..
    } = &shapes[2].material
    else {
        panic!("{:?}", shapes[2].material)
    };
    assert_eq!(*conductor_eta, SpectrumDescription::Constant(1.0));
    assert!(!conductor.remap);
    let error = error_of(&format!(
        "WorldBegin\nMaterial \"coatedconductor\" \"rgb reflectance\" [0.5 0.5 0.5] \
         \"spectrum conductor.eta\" \"metal-Au-eta\"\n{TRIANGLE}"
    ));
    assert!(error.contains("not both"), "{error}");
    let error = error_of(&format!(
        "WorldBegin\nMaterial \"coatedconductor\" \"integer maxdepth\" 0\n{TRIANGLE}"
    ));
    assert!(error.contains("\"maxdepth\" must be at least 1"), "{error}");
}

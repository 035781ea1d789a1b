//! Tests of the Mitsuba loader on small scene files written to a temporary
//! directory.

use super::super::description::{
    FilterDescription, LightDescription, MaterialDescription, MediumCoefficients,
    MicrofacetDistribution, PhaseDescription, ShapeGeometry, SpectrumDescription,
    TextureDescription,
};
use super::super::loader::{LoadOptions, LoadedScene, SceneFileError};
use super::load;
use crate::camera::FovAxis;
use crate::test_support::ScratchDirectory;
use glam::{Affine2, Vec2, Vec3};
use std::path::{Path, PathBuf};

/// A fresh directory for one test, removed when the guard is dropped.
fn directory() -> ScratchDirectory {
    ScratchDirectory::new("mitsuba")
}

fn write(directory: &Path, name: &str, text: &str) -> PathBuf {
    let path = directory.join(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(&path, text).unwrap();
    path
}

fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n")
}

fn load_text(body: &str) -> Result<LoadedScene, SceneFileError> {
    let directory = directory();
    let path = write(&directory, "scene.xml", &scene(body));
    load(&path, &LoadOptions::default())
}

fn loaded(body: &str) -> LoadedScene {
    load_text(body).unwrap_or_else(|error| panic!("{error}"))
}

fn error(body: &str) -> String {
    load_text(body)
        .expect_err("the scene must not load")
        .to_string()
}

const TRIANGLE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";

#[test]
fn sensor_film_filter_and_sampler() {
    let scene = loaded(
        r#"<sensor type="perspective">
            <float name="fov" value="30"/>
            <string name="fov_axis" value="y"/>
            <float name="near_clip" value="0.1"/>
            <transform name="to_world">
                <lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/>
            </transform>
            <film type="hdrfilm">
                <integer name="width" value="32"/>
                <integer name="height" value="16"/>
                <rfilter type="tent"/>
            </film>
            <sampler type="independent"><integer name="sample_count" value="7"/></sampler>
        </sensor>"#,
    );
    let description = &scene.description;
    assert_eq!(description.camera.resolution, [32, 16]);
    assert_eq!(description.camera.fov_degrees, 30.0);
    assert_eq!(description.camera.fov_axis, FovAxis::Y);
    assert_eq!(description.samples_per_pixel, Some(7));
    assert_eq!(description.filter, FilterDescription::Tent { radius: 1.0 });
    // Looking from +z towards the origin with +y up: the camera's forward
    // is −z, and its +x (the image's right) is +x in world space (Mitsuba's
    // own +x, the image's left, is −x).
    let frame = description.camera.world_from_camera;
    assert!((Vec3::from(frame.matrix3.z_axis) - Vec3::NEG_Z).length() < 1e-6);
    assert!((Vec3::from(frame.matrix3.x_axis) - Vec3::X).length() < 1e-6);
    assert!((Vec3::from(frame.translation) - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn mitsuba_defaults_without_parameters() {
    let scene = loaded(r#"<sensor type="thinlens"><film type="hdrfilm"/></sensor>"#);
    let camera = &scene.description.camera;
    assert_eq!(camera.resolution, [768, 576]);
    assert_eq!(camera.fov_axis, FovAxis::X);
    // 50 mm on 35 mm film: 46.8° diagonally, converted to x for 768 × 576.
    let diagonal_half = (43.266_615f32 / 100.0).atan();
    let expected = 2.0 * (diagonal_half.tan() * 0.8).atan().to_degrees();
    assert!(
        (camera.fov_degrees - expected).abs() < 1e-3,
        "{}",
        camera.fov_degrees
    );
    assert_eq!(camera.lens_radius, 0.03);
    assert!(matches!(
        scene.description.filter,
        FilterDescription::Gaussian {
            sigma: 0.5,
            radius: 2.0
        }
    ));
}

#[test]
fn no_sensor_is_a_warning() {
    let scene = loaded("");
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    assert!(scene.warnings[0].contains("no <sensor>"));
}

#[test]
fn shapes_and_transforms() {
    let directory = directory();
    write(&directory, "meshes/tri.obj", TRIANGLE_OBJ);
    let path = write(
        &directory,
        "scene.xml",
        &scene(
            r#"<sensor type="perspective"/>
            <shape type="obj">
                <string name="filename" value="meshes/tri.obj"/>
                <transform name="to_world">
                    <scale value="2"/>
                    <translate x="1"/>
                </transform>
            </shape>
            <shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>
            <shape type="cube"/>
            <shape type="disk"><transform name="to_world"><rotate x="1" angle="90"/></transform></shape>
            <shape type="sphere">
                <point name="center" x="1" y="0" z="0"/>
                <float name="radius" value="0.5"/>
                <transform name="to_world"><scale value="2"/></transform>
            </shape>"#,
        ),
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    let shapes = &scene.description.shapes;
    assert_eq!(shapes.len(), 5);
    let ShapeGeometry::Mesh { positions, uvs, .. } = &shapes[0].geometry else {
        panic!("{:?}", shapes[0].geometry)
    };
    // Scale, then translate: (1, 0, 0) → (2, 0, 0) → (3, 0, 0).
    assert_eq!(positions[1], Vec3::new(3.0, 0.0, 0.0));
    // OBJ texture coordinates are flipped as Mitsuba does.
    assert_eq!(uvs.as_ref().unwrap()[2], Vec2::new(0.0, 0.0));
    assert_eq!(uvs.as_ref().unwrap()[0], Vec2::new(0.0, 1.0));
    assert!(shapes[1].flip_normals);
    assert!(matches!(shapes[2].geometry, ShapeGeometry::Cube { .. }));
    let ShapeGeometry::Disk { to_world } = shapes[3].geometry else {
        panic!()
    };
    assert!((to_world.transform_vector3(Vec3::Z) - Vec3::NEG_Y).length() < 1e-6);
    let ShapeGeometry::Sphere { center, radius } = shapes[4].geometry else {
        panic!()
    };
    assert_eq!((center, radius), (Vec3::new(2.0, 0.0, 0.0), 1.0));
    // The default BSDF is a one-sided diffuse of 0.5.
    assert_eq!(
        shapes[2].material,
        MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(SpectrumDescription::Constant(0.5)),
            two_sided: false
        }
    );
}

#[test]
fn bsdfs_with_defaults_refs_and_adapters() {
    let scene = loaded(
        r#"<bsdf type="twosided" id="white">
               <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.7, 0.6"/></bsdf>
           </bsdf>
           <bsdf type="dielectric" id="glass">
               <string name="int_ior" value="water"/>
               <float name="ext_ior" value="1.0"/>
           </bsdf>
           <bsdf type="roughconductor" id="gold">
               <string name="material" value="Au"/>
               <string name="distribution" value="ggx"/>
               <float name="alpha_u" value="0.2"/>
               <float name="alpha_v" value="0.3"/>
           </bsdf>
           <bsdf type="conductor" id="mirror"/>
           <bsdf type="roughplastic" id="plastic">
               <rgb name="diffuse_reflectance" value="0.1"/>
           </bsdf>
           <bsdf type="mask" id="masked">
               <float name="opacity" value="0.25"/>
               <ref id="white"/>
           </bsdf>
           <bsdf type="null" id="nothing"/>
           <bsdf type="thindielectric" id="thin"/>
           <shape type="cube"><ref id="white"/></shape>
           <shape type="cube"><ref id="glass"/></shape>
           <shape type="cube"><ref id="gold"/></shape>
           <shape type="cube"><ref id="mirror"/></shape>
           <shape type="cube"><ref id="plastic"/></shape>
           <shape type="cube"><ref id="masked"/></shape>
           <shape type="cube"><ref id="nothing"/></shape>
           <shape type="cube"><ref id="thin"/></shape>
           <sensor type="perspective"/>"#,
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let materials: Vec<&MaterialDescription> = scene
        .description
        .shapes
        .iter()
        .map(|shape| &shape.material)
        .collect();
    let white = MaterialDescription::Diffuse {
        reflectance: TextureDescription::Constant(SpectrumDescription::Rgb([0.8, 0.7, 0.6])),
        two_sided: true,
    };
    assert_eq!(materials[0], &white);
    assert_eq!(
        materials[1],
        &MaterialDescription::Dielectric {
            interior_ior: SpectrumDescription::Constant(1.333),
            exterior_ior: 1.0,
            roughness: None
        }
    );
    let MaterialDescription::Conductor {
        eta,
        k,
        roughness: Some(roughness),
        two_sided: false,
        ..
    } = materials[2]
    else {
        panic!("{:?}", materials[2])
    };
    assert_eq!(eta, &SpectrumDescription::Named("metal-Au-eta".into()));
    assert_eq!(k, &SpectrumDescription::Named("metal-Au-k".into()));
    assert_eq!(roughness.distribution, MicrofacetDistribution::Ggx);
    assert_eq!(
        roughness.alpha_v,
        TextureDescription::Constant(SpectrumDescription::Constant(0.3))
    );
    assert_eq!(materials[3], &MaterialDescription::Mirror);
    let MaterialDescription::Plastic {
        interior_ior,
        roughness: Some(roughness),
        nonlinear: false,
        ..
    } = materials[4]
    else {
        panic!("{:?}", materials[4])
    };
    // Polypropylene in air, Beckmann α = 0.1 by default.
    assert!((interior_ior - 1.49 / 1.000277).abs() < 1e-6);
    assert_eq!(roughness.distribution, MicrofacetDistribution::Beckmann);
    assert_eq!(
        roughness.alpha_u,
        TextureDescription::Constant(SpectrumDescription::Constant(0.1))
    );
    assert_eq!(
        materials[5],
        &MaterialDescription::Mask {
            opacity: TextureDescription::Constant(SpectrumDescription::Constant(0.25)),
            nested: Box::new(white.clone())
        }
    );
    assert_eq!(materials[6], &MaterialDescription::Interface);
    let MaterialDescription::ThinDielectric { interior_ior, .. } = materials[7] else {
        panic!()
    };
    assert!((interior_ior - 1.5046 / 1.000277).abs() < 1e-6);
}

#[test]
fn textures_and_checkerboard_scale() {
    let directory = directory();
    std::fs::write(directory.join("t.png"), b"not read at load time").unwrap();
    let path = write(
        &directory,
        "scene.xml",
        &scene(
            r#"<texture type="checkerboard" id="board">
                   <rgb name="color0" value="1"/>
                   <transform name="to_uv"><scale x="3" y="5"/></transform>
               </texture>
               <shape type="cube">
                   <bsdf type="diffuse"><ref name="reflectance" id="board"/></bsdf>
               </shape>
               <shape type="cube">
                   <bsdf type="diffuse">
                       <texture name="reflectance" type="bitmap">
                           <string name="filename" value="t.png"/>
                           <boolean name="raw" value="true"/>
                           <string name="filter_type" value="nearest"/>
                       </texture>
                   </bsdf>
               </shape>
               <sensor type="perspective"/>"#,
        ),
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    let MaterialDescription::Diffuse { reflectance, .. } = &scene.description.shapes[0].material
    else {
        panic!()
    };
    let TextureDescription::Checkerboard { even, odd, to_uv } = reflectance else {
        panic!("{reflectance:?}")
    };
    assert_eq!(
        **even,
        TextureDescription::Constant(SpectrumDescription::Rgb([1.0; 3]))
    );
    assert_eq!(
        **odd,
        TextureDescription::Constant(SpectrumDescription::Constant(0.2))
    );
    assert_eq!(*to_uv, Affine2::from_scale(Vec2::new(6.0, 10.0)));
    let MaterialDescription::Diffuse { reflectance, .. } = &scene.description.shapes[1].material
    else {
        panic!()
    };
    let TextureDescription::Bitmap {
        filename,
        encoding,
        filter,
        ..
    } = reflectance
    else {
        panic!()
    };
    assert_eq!(filename, &directory.join("t.png"));
    assert_eq!(
        *encoding,
        Some(crate::scene::description::ColourEncoding::Linear)
    );
    assert_eq!(*filter, crate::scene::description::TextureFilter::Nearest);
}

#[test]
fn emitters() {
    let scene = loaded(
        r#"<shape type="rectangle">
               <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter>
           </shape>
           <emitter type="point"><point name="position" x="1" y="2" z="3"/><rgb name="intensity" value="5"/></emitter>
           <emitter type="spot"><float name="cutoff_angle" value="40"/></emitter>
           <emitter type="directional"><vector name="direction" value="0, 0, -2"/></emitter>
           <emitter type="constant"><spectrum name="radiance" value="0.5"/></emitter>
           <sensor type="perspective"/>"#,
    );
    assert_eq!(
        scene.description.shapes[0].emission,
        Some(SpectrumDescription::Rgb([1.0, 2.0, 3.0]))
    );
    let lights = &scene.description.lights;
    assert_eq!(
        lights[0],
        LightDescription::Point {
            position: Vec3::new(1.0, 2.0, 3.0),
            intensity: SpectrumDescription::Rgb([5.0; 3])
        }
    );
    let LightDescription::Spot {
        cutoff_degrees,
        falloff_start_degrees,
        ..
    } = lights[1]
    else {
        panic!()
    };
    assert_eq!((cutoff_degrees, falloff_start_degrees), (40.0, 30.0));
    assert_eq!(
        lights[2],
        LightDescription::Directional {
            direction: Vec3::NEG_Z,
            irradiance: SpectrumDescription::Rgb([1.0; 3])
        }
    );
    assert_eq!(
        lights[3],
        LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Constant(0.5)
        }
    );
}

#[test]
fn media_by_reference_and_nested() {
    let scene = loaded(
        r#"<medium type="homogeneous" id="fog">
               <rgb name="sigma_t" value="1, 2, 3"/>
               <float name="scale" value="0.5"/>
               <phase type="hg"><float name="g" value="0.3"/></phase>
           </medium>
           <shape type="sphere">
               <bsdf type="null"/>
               <ref name="interior" id="fog"/>
               <medium type="homogeneous" name="exterior"/>
           </shape>
           <sensor type="perspective"><ref id="fog"/></sensor>"#,
    );
    let description = &scene.description;
    assert_eq!(description.media.len(), 2);
    assert_eq!(description.shapes[0].interior_medium, Some(0));
    assert_eq!(description.shapes[0].exterior_medium, Some(1));
    assert_eq!(description.camera_medium, Some(0));
    assert_eq!(description.media[0].scale, 0.5);
    assert_eq!(
        description.media[0].phase,
        PhaseDescription::HenyeyGreenstein { g: 0.3 }
    );
    assert_eq!(
        description.media[1].coefficients,
        MediumCoefficients::AlbedoExtinction {
            albedo: SpectrumDescription::Constant(0.75),
            sigma_t: SpectrumDescription::Constant(1.0)
        }
    );
}

#[test]
fn integrators_and_depth() {
    let depth = |body: &str| {
        let scene = loaded(&format!("{body}<sensor type=\"perspective\"/>"));
        (
            scene.description.max_depth,
            scene.description.integrator,
            scene.warnings,
        )
    };
    let (max_depth, integrator, warnings) =
        depth(r#"<integrator type="path"><integer name="max_depth" value="5"/></integrator>"#);
    assert_eq!((max_depth, integrator.as_deref()), (Some(5), Some("path")));
    assert!(warnings.is_empty());
    let (max_depth, ..) =
        depth(r#"<integrator type="volpath"><integer name="max_depth" value="-1"/></integrator>"#);
    assert_eq!(max_depth, Some(u32::MAX));
    let (max_depth, integrator, _) =
        depth(r#"<integrator type="moment"><integrator type="direct"/></integrator>"#);
    assert_eq!(
        (max_depth, integrator.as_deref()),
        (Some(2), Some("direct"))
    );
    let (max_depth, integrator, warnings) = depth(
        r#"<integrator type="path_guiding_integrator"><integer name="max_depth" value="30"/></integrator>"#,
    );
    assert_eq!(max_depth, Some(30));
    assert_eq!(integrator.as_deref(), Some("path_guiding_integrator"));
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].contains("scene.xml:2:") && warnings[0].contains("path_guiding_integrator"),
        "{warnings:?}"
    );
}

#[test]
fn integrators_russian_roulette_depth() {
    let rr_depth = |body: &str| {
        loaded(&format!("{body}<sensor type=\"perspective\"/>"))
            .description
            .russian_roulette_depth
    };
    // Mitsuba's default where the integrator names none.
    assert_eq!(rr_depth(r#"<integrator type="path"/>"#), Some(5));
    assert_eq!(
        rr_depth(r#"<integrator type="volpath"><integer name="rr_depth" value="2"/></integrator>"#),
        Some(2)
    );
    // No integrator element: the renderer's own default applies.
    assert_eq!(rr_depth(""), None);
    let message = error(
        r#"<integrator type="path"><integer name="rr_depth" value="0"/></integrator><sensor type="perspective"/>"#,
    );
    assert!(message.contains("rr_depth 0"), "{message}");
}

#[test]
fn parameters_defaults_and_command_line() {
    let directory = directory();
    let path = write(
        &directory,
        "scene.xml",
        &scene(
            r#"<default name="spp" value="16"/>
               <default name="res" value="8"/>
               <sensor type="perspective">
                   <film type="hdrfilm">
                       <integer name="width" value="$res"/>
                       <integer name="height" value="$res"/>
                   </film>
                   <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
               </sensor>"#,
        ),
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(scene.description.samples_per_pixel, Some(16));
    assert_eq!(scene.description.camera.resolution, [8, 8]);
    let options = LoadOptions {
        parameters: vec![("spp".into(), "3".into())],
    };
    let scene = load(&path, &options).unwrap();
    assert_eq!(scene.description.samples_per_pixel, Some(3));
    assert_eq!(scene.description.camera.resolution, [8, 8]);
}

#[test]
fn undefined_parameter_is_an_error_with_line() {
    let message =
        error("<sensor type=\"perspective\">\n<float name=\"fov\" value=\"$fov\"/>\n</sensor>");
    assert!(message.contains("scene.xml:3:"), "{message}");
    assert!(message.contains("$fov"), "{message}");
}

#[test]
fn includes_relative_to_the_including_file_and_search_paths() {
    let directory = directory();
    write(&directory, "common/meshes/tri.obj", TRIANGLE_OBJ);
    write(
        &directory,
        "tests/fragments/part.xml",
        r#"<scene version="2.0.0">
               <default name="colour" value="0.25"/>
               <shape type="obj">
                   <string name="filename" value="meshes/tri.obj"/>
                   <bsdf type="diffuse"><rgb name="reflectance" value="$colour"/></bsdf>
               </shape>
               <sensor type="perspective"/>
           </scene>"#,
    );
    let path = write(
        &directory,
        "tests/scene.xml",
        r#"<scene version="2.0.0">
               <path value="../common"/>
               <include filename="fragments/part.xml"/>
           </scene>"#,
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    assert_eq!(scene.description.shapes.len(), 1);
    assert_eq!(
        scene.description.shapes[0].material,
        MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(SpectrumDescription::Rgb([0.25; 3])),
            two_sided: false
        }
    );
}

#[test]
fn missing_files_name_the_paths_looked_at() {
    let message =
        error(r#"<shape type="obj"><string name="filename" value="nowhere.obj"/></shape>"#);
    assert!(message.contains("scene.xml:2:"), "{message}");
    assert!(
        message.contains("nowhere.obj") && message.contains("looked for"),
        "{message}"
    );
    let message = error(r#"<include filename="missing.xml"/>"#);
    assert!(message.contains("missing.xml"), "{message}");
    let message =
        error(r#"<emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>"#);
    assert!(message.contains("sky.exr"), "{message}");
}

#[test]
fn unknown_elements_and_plugins_are_warnings() {
    let scene = loaded(
        r#"<teapot/>
           <shape type="serialized"/>
           <bsdf type="hair" id="h"/>
           <emitter type="sunsky"/>
           <shape type="cube"><float name="wobble" value="1"/><ref id="h"/></shape>
           <sensor type="perspective"/>"#,
    );
    let warnings = scene.warnings.join("\n");
    for expected in [
        "scene.xml:2: unknown element <teapot>",
        "scene.xml:3: shape type 'serialized'",
        "scene.xml:4: unknown bsdf type 'hair'",
        "scene.xml:5: emitter type 'sunsky'",
        "scene.xml:6: parameter 'wobble'",
    ] {
        assert!(warnings.contains(expected), "{expected} not in\n{warnings}");
    }
    assert_eq!(scene.description.shapes.len(), 1);
}

#[test]
fn malformed_input_is_an_error_with_file_and_line() {
    for (body, line, expected) in [
        (
            "<shape type=\"cube\">\n<float name=\"x\" value=\"1\"",
            4,
            "malformed XML",
        ),
        (
            "\n<shape type=\"sphere\"><float name=\"radius\" value=\"big\"/></shape>",
            3,
            "big",
        ),
        (
            "\n\n<shape type=\"cube\"><ref id=\"nothing\"/></shape>",
            4,
            "nothing",
        ),
        (
            "<bsdf type=\"dielectric\">\n<string name=\"int_ior\" value=\"jelly\"/></bsdf>",
            3,
            "jelly",
        ),
        (
            "<bsdf type=\"conductor\"><string name=\"material\" value=\"Xx\"/></bsdf>",
            2,
            "Xx",
        ),
        (
            "<shape type=\"cube\"><transform name=\"to_world\"><scale value=\"0\"/></transform></shape>",
            2,
            "zero",
        ),
        (
            "<shape type=\"cube\"><rgb name=\"to_world\" value=\"1\"/></shape>",
            2,
            "<transform>",
        ),
        ("<emitter type=\"area\"/>", 2, "nested"),
        (
            "<bsdf type=\"diffuse\" id=\"a\"/><bsdf type=\"diffuse\" id=\"a\"/>",
            2,
            "twice",
        ),
    ] {
        let message = error(body);
        assert!(
            message.contains(&format!("scene.xml:{line}:")) && message.contains(expected),
            "{body}: {message}"
        );
    }
}

#[test]
fn wrong_root_and_version() {
    let directory = directory();
    let path = write(&directory, "a.xml", "<bsdf type=\"diffuse\"/>");
    let message = load(&path, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(message.contains("expected <scene>"), "{message}");
    let path = write(&directory, "b.xml", "<scene version=\"9.0\"/>");
    let message = load(&path, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("b.xml:1:") && message.contains("9.0"),
        "{message}"
    );
}

#[test]
fn legacy_camel_case_names_are_converted() {
    let directory = directory();
    let path = write(
        &directory,
        "old.xml",
        r#"<scene version="0.6.0">
               <integrator type="path"><integer name="maxDepth" value="4"/></integrator>
               <shape type="cube">
                   <transform name="toWorld"><translate x="2"/></transform>
                   <bsdf type="dielectric"><float name="intIOR" value="1.7"/></bsdf>
               </shape>
               <sensor type="perspective"/>
           </scene>"#,
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.description.max_depth, Some(4));
    let ShapeGeometry::Cube { to_world } = scene.description.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(Vec3::from(to_world.translation), Vec3::new(2.0, 0.0, 0.0));
}

#[test]
fn include_cycles_are_errors() {
    let directory = directory();
    write(
        &directory,
        "a.xml",
        r#"<scene version="3.0.0"><include filename="b.xml"/></scene>"#,
    );
    let path = write(
        &directory,
        "b.xml",
        r#"<scene version="3.0.0"><include filename="a.xml"/></scene>"#,
    );
    let message = load(&path, &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(message.contains("include cycle"), "{message}");
}

#[test]
fn included_files_may_name_files_relative_to_the_main_scene() {
    // As Mitsuba's participating_media tests do: include/base.xml includes
    // "include/preamble.xml", found from the main scene's directory.
    let directory = directory();
    write(
        &directory,
        "media/include/preamble.xml",
        r#"<scene version="2.0.0"><sensor type="perspective"/></scene>"#,
    );
    write(
        &directory,
        "media/include/base.xml",
        r#"<scene version="2.0.0"><include filename="include/preamble.xml"/></scene>"#,
    );
    let path = write(
        &directory,
        "media/scene.xml",
        r#"<scene version="2.0.0"><include filename="include/base.xml"/></scene>"#,
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    assert!(
        scene
            .warnings
            .iter()
            .all(|warning| !warning.contains("no <sensor>")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn checkerboard_roughness_follows_mitsubas_float_evaluation() {
    // Mitsuba 3.9.1's checkerboard eval_1 (what roughness reads) gives color1
    // at uv (0.1, 0.1), its eval (spectra) color0: the float use swaps them.
    let board = |name: &str, color0: f32, color1: f32| {
        format!(
            r#"<texture name="{name}" type="checkerboard">
                   <float name="color0" value="{color0}"/><float name="color1" value="{color1}"/>
               </texture>"#
        )
    };
    let directory = directory();
    let path = write(
        &directory,
        "scene.xml",
        &scene(&format!(
            r#"<shape type="cube">
                   <bsdf type="roughconductor">{}{}</bsdf>
               </shape>
               <shape type="cube">
                   <bsdf type="diffuse">{}</bsdf>
               </shape>
               <sensor type="perspective"/>"#,
            board("alpha_u", 0.05, 0.3),
            board("alpha_v", 0.3, 0.05),
            board("reflectance", 0.05, 0.3),
        )),
    );
    let scene = load(&path, &LoadOptions::default()).unwrap();
    let constant = |value: f32| TextureDescription::Constant(SpectrumDescription::Constant(value));
    let MaterialDescription::Conductor {
        roughness: Some(roughness),
        ..
    } = &scene.description.shapes[0].material
    else {
        panic!("{:?}", scene.description.shapes[0].material)
    };
    let TextureDescription::Checkerboard { even, odd, .. } = &roughness.alpha_u else {
        panic!("{:?}", roughness.alpha_u)
    };
    assert_eq!((&**even, &**odd), (&constant(0.3), &constant(0.05)));
    let TextureDescription::Checkerboard { even, .. } = &roughness.alpha_v else {
        panic!("{:?}", roughness.alpha_v)
    };
    assert_eq!(**even, constant(0.05));
    let MaterialDescription::Diffuse { reflectance, .. } = &scene.description.shapes[1].material
    else {
        panic!()
    };
    let TextureDescription::Checkerboard { even, .. } = reflectance else {
        panic!("{reflectance:?}")
    };
    assert_eq!(**even, constant(0.05));
}

#[test]
fn references_to_objects_defined_later() {
    // Mitsuba's Cornell box refers to an area emitter defined after the shape.
    let scene = loaded(
        r#"<shape type="rectangle">
               <ref id="white"/>
               <ref id="lamp"/>
               <ref name="interior" id="fog"/>
           </shape>
           <shape type="cube"><ref id="white"/></shape>
           <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.9"/></bsdf>
           <emitter type="area" id="lamp"><rgb name="radiance" value="4"/></emitter>
           <medium type="homogeneous" id="fog"/>
           <sensor type="perspective"/>"#,
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let description = &scene.description;
    assert_eq!(description.shapes.len(), 2);
    assert_eq!(
        description.shapes[0].emission,
        Some(SpectrumDescription::Rgb([4.0; 3]))
    );
    assert_eq!(description.shapes[1].emission, None);
    assert_eq!(
        description.shapes[0].material,
        description.shapes[1].material
    );
    assert_eq!(description.media.len(), 1, "the medium is read once");
    assert!(description.lights.is_empty());
}

#[test]
fn principled_bsdfs_read_every_parameter() {
    let scene = loaded(
        r#"<bsdf type="principled" id="disney">
               <rgb name="base_color" value="0.2, 0.8, 0.1"/>
               <float name="specular" value="0.7"/>
               <texture name="metallic" type="checkerboard">
                   <float name="color0" value="0.7"/>
                   <float name="color1" value="0.1"/>
               </texture>
               <float name="clearcoat_sampling_rate" value="2"/>
           </bsdf>
           <bsdf type="principledthin" id="thin">
               <float name="eta" value="1.33"/>
               <float name="diff_trans" value="1.4"/>
           </bsdf>
           <shape type="cube"><ref id="disney"/></shape>
           <shape type="cube"><ref id="thin"/></shape>
           <sensor type="perspective"/>"#,
    );
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let constant = |value: f32| TextureDescription::Constant(SpectrumDescription::Constant(value));
    let MaterialDescription::Principled(disney) = &scene.description.shapes[0].material else {
        panic!("{:?}", scene.description.shapes[0].material)
    };
    assert!(!disney.thin);
    let eta = crate::material::principled_eta_from_specular(0.7);
    assert_eq!(disney.eta, constant(eta));
    assert_eq!(disney.roughness, constant(0.5));
    assert!(matches!(
        disney.metallic,
        TextureDescription::Checkerboard { .. }
    ));
    assert_eq!(disney.sampling_rates.clearcoat, 2.0);
    let MaterialDescription::Principled(thin) = &scene.description.shapes[1].material else {
        panic!("{:?}", scene.description.shapes[1].material)
    };
    assert!(thin.thin);
    assert_eq!(thin.eta, constant(1.33));
    assert_eq!(thin.diff_trans, constant(1.4));
    assert_eq!(thin.base_color, constant(0.5));
}

#[test]
fn principled_rejects_both_eta_and_specular() {
    let message = error(
        r#"<bsdf type="principled" id="disney">
               <float name="eta" value="1.5"/>
               <float name="specular" value="0.5"/>
           </bsdf>
           <shape type="cube"><ref id="disney"/></shape>
           <sensor type="perspective"/>"#,
    );
    assert!(message.contains("either 'eta' or 'specular'"), "{message}");
}

/// A textured `area` emitter becomes the shape's emission texture (a
/// constant one stays a plain emission); a `projector` is read with its
/// defaults (a 50 mm lens: the diagonal field of view of 35 mm film), an
/// explicit `fov`/`fov_axis`, and a bad `fov_axis` is an error naming it.
#[test]
fn textured_area_emitters_and_projectors() {
    let scene = loaded(
        r#"<shape type="rectangle">
             <emitter type="area">
               <texture name="radiance" type="checkerboard"/>
             </emitter>
           </shape>
           <shape type="rectangle">
             <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter>
           </shape>
           <emitter type="projector">
             <texture name="irradiance" type="checkerboard"/>
           </emitter>
           <emitter type="projector">
             <float name="scale" value="3"/>
             <float name="fov" value="30"/>
             <string name="fov_axis" value="y"/>
           </emitter>"#,
    );
    let shapes = &scene.description.shapes;
    assert!(matches!(
        shapes[0].emission_texture,
        Some(TextureDescription::Checkerboard { .. })
    ));
    assert!(shapes[0].emission.is_none());
    assert_eq!(
        shapes[1].emission,
        Some(SpectrumDescription::Rgb([1.0, 2.0, 3.0]))
    );
    assert!(shapes[1].emission_texture.is_none());
    use super::super::description::ProjectorFovAxis;
    match &scene.description.lights[..] {
        [
            LightDescription::Projector {
                scale: 1.0,
                fov_degrees: default_fov,
                fov_axis: ProjectorFovAxis::Diagonal,
                ..
            },
            LightDescription::Projector {
                scale: 3.0,
                fov_degrees: 30.0,
                fov_axis: ProjectorFovAxis::Y,
                ..
            },
        ] => {
            // 2 atan(43.27 / 100).
            assert!((default_fov - 46.793).abs() < 1e-2, "{default_fov}");
        }
        other => panic!("{other:?}"),
    }
    // Mitsuba 3.9.1's horizontal field of view for the default on a
    // 100 × 67 image (flower.bmp) is 39.5415°.
    let tan_half = ProjectorFovAxis::Diagonal.tan_half_horizontal(46.793, 100.0, 67.0);
    assert!((2.0 * tan_half.atan().to_degrees() - 39.5415).abs() < 2e-3);
    let message = error(
        r#"<emitter type="projector"><float name="fov" value="30"/>
           <string name="fov_axis" value="sideways"/></emitter>"#,
    );
    assert!(message.contains("fov_axis 'sideways'"), "{message}");
}

/// `normalmap` and `bumpmap` take Mitsuba 3.7.1's `flip_invalid_normals`
/// and `use_shadowing_function`, both on unless the file turns them off.
#[test]
fn normal_and_bump_maps_take_mitsubas_flip_and_shadowing_options() {
    use crate::material::PerturbationOptions;
    let options_of = |bsdf: &str| {
        let scene = loaded(&format!(r#"<shape type="sphere">{bsdf}</shape>"#));
        match &scene.description.shapes[0].material {
            MaterialDescription::NormalMap { options, .. }
            | MaterialDescription::BumpMap { options, .. } => *options,
            other => panic!("not a perturbed material: {other:?}"),
        }
    };
    let normal_map = |extra: &str| {
        format!(
            r#"<bsdf type="normalmap">{extra}
                <texture name="normalmap" type="rawconstant"><vector name="value" value="0.5, 0.5, 1"/></texture>
                <bsdf type="diffuse"/>
            </bsdf>"#
        )
    };
    assert_eq!(options_of(&normal_map("")), PerturbationOptions::MITSUBA);
    assert_eq!(
        options_of(&normal_map(
            r#"<boolean name="flip_invalid_normals" value="false"/>
               <boolean name="use_shadowing_function" value="false"/>"#
        )),
        PerturbationOptions::default()
    );
    let bump_map = r#"<bsdf type="bumpmap">
            <boolean name="use_shadowing_function" value="false"/>
            <texture type="checkerboard"/>
            <bsdf type="diffuse"/>
        </bsdf>"#;
    assert_eq!(
        options_of(bump_map),
        PerturbationOptions {
            flip_invalid_normals: true,
            shadowing_function: false,
        }
    );
}

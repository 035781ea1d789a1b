//! Every rough and layered material description builds into a material
//! (`Scene::build`'s `material()`), with the parameters carried over, and bad
//! parameters give clear errors.

use render::material::{Material, MicrofacetKind};
use render::scene::builtin::builtin_scene;
use render::scene::description::{
    MaterialDescription, MicrofacetDistribution, RoughnessDescription, SpectrumDescription,
    TextureDescription,
};
use render::scene::spectra::{SpectrumUsage, build_spectrum};
use render::scene::{Scene, SceneError};

fn constant(value: f32) -> TextureDescription {
    TextureDescription::Constant(SpectrumDescription::Constant(value))
}

fn roughness(
    distribution: MicrofacetDistribution,
    alpha_u: f32,
    alpha_v: f32,
) -> RoughnessDescription {
    RoughnessDescription {
        distribution,
        alpha_u: constant(alpha_u),
        alpha_v: constant(alpha_v),
        remap: false,
    }
}

/// The Cornell box with its first shape made of `material`.
fn build_with(material: MaterialDescription) -> Result<Material, SceneError> {
    let mut description = builtin_scene("cornell-box").expect("the Cornell box");
    description.shapes[0].material = material;
    let scene = Scene::build(&description)?;
    Ok(scene.shapes[0].material.clone().expect("not black"))
}

fn gold() -> (SpectrumDescription, SpectrumDescription) {
    (
        SpectrumDescription::Named("metal-Au-eta".into()),
        SpectrumDescription::Named("metal-Au-k".into()),
    )
}

#[test]
fn rough_conductor_builds() {
    let (eta, k) = gold();
    let material = build_with(MaterialDescription::Conductor {
        eta,
        k,
        specular_reflectance: Some(constant(0.8)),
        roughness: Some(roughness(MicrofacetDistribution::Ggx, 0.25, 0.05)),
        two_sided: false,
    })
    .unwrap();
    let Material::RoughConductor {
        roughness: Some(roughness),
        two_sided: false,
        specular_reflectance: Some(_),
        ..
    } = material
    else {
        panic!("{material:?}");
    };
    assert_eq!(roughness.kind, MicrofacetKind::Ggx);
    // Smooth, one-sided conductors go the same way; two-sided plain ones stay
    // the smooth conductor.
    let (eta, k) = gold();
    let smooth = build_with(MaterialDescription::Conductor {
        eta,
        k,
        specular_reflectance: None,
        roughness: None,
        two_sided: true,
    })
    .unwrap();
    assert!(matches!(smooth, Material::Conductor { .. }));
}

#[test]
fn dielectrics_build_with_exterior_index() {
    let material = build_with(MaterialDescription::Dielectric {
        interior_ior: SpectrumDescription::Constant(1.5046),
        exterior_ior: 1.000277,
        roughness: Some(roughness(MicrofacetDistribution::Beckmann, 0.02, 0.02)),
    })
    .unwrap();
    let Material::RoughDielectric { eta, .. } = material else {
        panic!("{material:?}");
    };
    assert!((eta.evaluate(550.0) - 1.5046 / 1.000277).abs() < 1e-6);
    let smooth = build_with(MaterialDescription::Dielectric {
        interior_ior: SpectrumDescription::Constant(1.333),
        exterior_ior: 1.5,
        roughness: None,
    })
    .unwrap();
    let Material::Dielectric { eta } = smooth else {
        panic!("{smooth:?}");
    };
    assert!((eta.evaluate(550.0) - 1.333 / 1.5).abs() < 1e-6);
    let thin = build_with(MaterialDescription::ThinDielectric {
        interior_ior: 1.333,
        exterior_ior: 1.000277,
    })
    .unwrap();
    assert!(
        matches!(thin, Material::ThinDielectric { eta } if (eta - 1.333 / 1.000277).abs() < 1e-6)
    );
    let error = build_with(MaterialDescription::ThinDielectric {
        interior_ior: -1.0,
        exterior_ior: 1.0,
    })
    .unwrap_err();
    assert!(error.to_string().contains("positive"), "{error}");
}

#[test]
fn plastics_and_two_sided_build() {
    let rough = build_with(MaterialDescription::Plastic {
        diffuse_reflectance: TextureDescription::Constant(SpectrumDescription::Rgb([
            0.02, 0.2, 0.1,
        ])),
        interior_ior: 1.5046,
        exterior_ior: 1.000277,
        roughness: Some(roughness(MicrofacetDistribution::Ggx, 0.1, 0.1)),
        nonlinear: true,
        two_sided: false,
    })
    .unwrap();
    assert!(matches!(
        rough,
        Material::Plastic {
            coating: Some(_),
            nonlinear: true,
            ..
        }
    ));
    let two_sided = build_with(MaterialDescription::TwoSided {
        front: Box::new(MaterialDescription::Plastic {
            diffuse_reflectance: constant(0.5),
            interior_ior: 1.49,
            exterior_ior: 1.0,
            roughness: None,
            nonlinear: false,
            two_sided: false,
        }),
        back: Box::new(MaterialDescription::Black),
    })
    .unwrap();
    assert!(matches!(two_sided, Material::TwoSided { .. }));
    // Mitsuba's roughplastic takes a constant α: a textured one is refused.
    let textured = RoughnessDescription {
        alpha_u: TextureDescription::Checkerboard {
            even: Box::new(constant(0.1)),
            odd: Box::new(constant(0.3)),
            to_uv: glam::Affine2::IDENTITY,
        },
        ..roughness(MicrofacetDistribution::Ggx, 0.1, 0.1)
    };
    let error = build_with(MaterialDescription::Plastic {
        diffuse_reflectance: constant(0.5),
        interior_ior: 1.49,
        exterior_ior: 1.0,
        roughness: Some(textured),
        nonlinear: false,
        two_sided: false,
    })
    .unwrap_err();
    assert!(matches!(error, SceneError::Unsupported { .. }), "{error}");
}

#[test]
fn named_metals_resolve() {
    for name in ["Ag", "Al", "Au", "Cu", "MgO", "TiO2", "Cu_palik", "none"] {
        for part in ["eta", "k"] {
            let description = SpectrumDescription::Named(format!("metal-{name}-{part}"));
            build_spectrum(&description, SpectrumUsage::Unbounded, "test")
                .unwrap_or_else(|e| panic!("{name} {part}: {e}"));
        }
    }
    // pbrt-v4's glasses: BK7 at the sodium D line (586–608 nm entries).
    let bk7 = build_spectrum(
        &SpectrumDescription::Named("glass-BK7".into()),
        SpectrumUsage::Unbounded,
        "test",
    )
    .unwrap();
    assert!((bk7.evaluate(589.3) - 1.5168).abs() < 2e-4);
    for name in ["BAF10", "FK51A", "LASF9", "F5", "SF10", "F11"] {
        let glass = build_spectrum(
            &SpectrumDescription::Named(format!("glass-{name}")),
            SpectrumUsage::Unbounded,
            "test",
        )
        .unwrap();
        assert!(
            glass.evaluate(600.0) > 1.4 && glass.evaluate(600.0) < 2.0,
            "{name}"
        );
    }
    let error = build_spectrum(
        &SpectrumDescription::Named("metal-Unobtainium-eta".into()),
        SpectrumUsage::Unbounded,
        "conductor eta",
    )
    .unwrap_err();
    assert!(
        error.to_string().contains("metal-Unobtainium-eta"),
        "{error}"
    );
}

//! Tests of `render::material::Material` (validation, the BSDF it builds at a
//! hit, dispersion) and of world-space BSDFs placed in a shading frame.

use glam::Vec3;
use render::material::{
    Bsdf, BsdfFlags, BsdfModel, ConductorBsdf, DielectricBsdf, DiffuseBsdf, Material,
    MaterialError, ShadingFrame, TransportMode, fresnel_complex,
};
use render::spectrum::{
    ConstantSpectrum, PiecewiseLinearSpectrum, RgbAlbedoSpectrum, RgbUnboundedSpectrum,
    SampledSpectrum, SampledWavelengths, Spectrum,
};

fn constant(value: f32) -> Spectrum {
    ConstantSpectrum::new(value).unwrap().into()
}

fn wavelengths() -> SampledWavelengths {
    SampledWavelengths::sample_visible(0.61)
}

/// A Cauchy-like glass index, 1.53 at 400 nm falling to 1.51 at 700 nm, over
/// the whole visible range.
fn dispersive_glass() -> Spectrum {
    PiecewiseLinearSpectrum::new(&[(360.0, 1.535), (400.0, 1.53), (700.0, 1.51), (830.0, 1.505)])
        .unwrap()
        .into()
}

#[test]
fn diffuse_material_samples_its_reflectance_two_sided() {
    let reflectance: Spectrum = RgbAlbedoSpectrum::new([0.2, 0.5, 0.8]).unwrap().into();
    let material = Material::diffuse(reflectance.clone()).unwrap();
    let lambdas = wavelengths();
    let bsdf = material.bsdf(&lambdas);
    let BsdfModel::Diffuse(diffuse) = bsdf.model() else {
        panic!("expected a diffuse BSDF, got {bsdf:?}");
    };
    assert!(diffuse.is_two_sided());
    assert_eq!(diffuse.reflectance(), reflectance.sample(&lambdas));
    assert_eq!(bsdf.transport_mode(), TransportMode::Radiance);
    assert_eq!(bsdf.flags(), BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE);
    // Seen from behind, a two-sided diffuse surface still reflects.
    let below = Vec3::new(0.0, 0.6, -0.8);
    let mut sampled = lambdas;
    assert!(bsdf.sample(below, 0.5, [0.3, 0.6], &mut sampled).is_some());
}

#[test]
fn diffuse_reflectance_is_clamped_to_one() {
    let bright: Spectrum = RgbUnboundedSpectrum::new([3.0, 3.0, 3.0]).unwrap().into();
    let bsdf = Material::diffuse(bright).unwrap().bsdf(&wavelengths());
    let BsdfModel::Diffuse(diffuse) = bsdf.model() else {
        panic!("expected a diffuse BSDF");
    };
    assert!(diffuse.reflectance().max_component() <= 1.0);
    let black = Material::diffuse(constant(0.0))
        .unwrap()
        .bsdf(&wavelengths());
    assert!(black.flags().is_empty());
    let mut lambdas = wavelengths();
    assert!(
        black
            .sample(Vec3::Z, 0.5, [0.5, 0.5], &mut lambdas)
            .is_none()
    );
}

#[test]
fn validation_rejects_bad_spectra() {
    let negative: Spectrum = PiecewiseLinearSpectrum::new(&[(360.0, 0.5), (830.0, -0.5)])
        .unwrap()
        .into();
    match Material::diffuse(negative.clone()) {
        Err(MaterialError::InvalidSpectrumValue { lambda, value, .. }) => {
            assert!(value < 0.0 && lambda > 360.0);
        }
        other => panic!("expected an error, got {other:?}"),
    }
    assert!(Material::conductor(constant(0.2), negative.clone()).is_err());
    assert!(Material::conductor(negative.clone(), constant(3.0)).is_err());
    assert!(Material::dielectric(negative).is_err());
    assert_eq!(
        Material::dielectric(constant(0.0)),
        Err(MaterialError::NonPositiveIndexOfRefraction { value: 0.0 })
    );
    assert!(Material::Mirror.validate().is_ok());
    assert!(Material::dielectric(dispersive_glass()).is_ok());
    assert!(Material::conductor(constant(0.2), constant(3.0)).is_ok());
    // The low-level constructors validate their sampled values too.
    assert!(DiffuseBsdf::new(SampledSpectrum::new([0.5, -0.1, 0.5, 0.5])).is_err());
    assert!(DiffuseBsdf::new(SampledSpectrum::splat(f32::NAN)).is_err());
    assert!(
        ConductorBsdf::new(
            SampledSpectrum::splat(f32::INFINITY),
            SampledSpectrum::splat(1.0)
        )
        .is_err()
    );
    assert!(DielectricBsdf::new(0.0).is_err());
    assert!(DielectricBsdf::new(-1.5).is_err());
    assert!(DielectricBsdf::new(f32::NAN).is_err());
}

#[test]
fn a_partial_index_table_is_index_matched_outside_its_range() {
    // Defined on 500–600 nm only: 0 elsewhere, which pbrt-v4 (and we) read
    // as η = 1. Validation accepts it (with a logged warning).
    let partial: Spectrum = PiecewiseLinearSpectrum::new(&[(500.0, 1.5), (600.0, 1.5)])
        .unwrap()
        .into();
    let material = Material::dielectric(partial).unwrap();
    let outside = SampledWavelengths::from_parts([400.0, 500.0, 550.0, 600.0], [0.01; 4]).unwrap();
    let BsdfModel::Dielectric(dielectric) = *material.bsdf(&outside).model() else {
        panic!("expected a dielectric");
    };
    assert_eq!(dielectric.eta(), 1.0);
    let inside = SampledWavelengths::from_parts([550.0, 500.0, 400.0, 600.0], [0.01; 4]).unwrap();
    let BsdfModel::Dielectric(dielectric) = *material.bsdf(&inside).model() else {
        panic!("expected a dielectric");
    };
    assert_eq!(dielectric.eta(), 1.5);
}

#[test]
fn dispersive_glass_terminates_secondary_wavelengths_when_sampled() {
    let dispersive = Material::dielectric(dispersive_glass()).unwrap();
    let plain = Material::dielectric(constant(1.5)).unwrap();
    let lambdas = wavelengths();
    let bsdf = dispersive.bsdf(&lambdas);
    let BsdfModel::Dielectric(dielectric) = *bsdf.model() else {
        panic!("expected a dielectric");
    };
    assert!(dielectric.is_dispersive());
    assert_eq!(
        dielectric.eta(),
        dispersive_glass().evaluate(lambdas.hero())
    );
    let wo = Vec3::new(0.3, 0.0, 0.95).normalize();
    for u_component in [0.01, 0.9] {
        let mut sampled = lambdas;
        bsdf.sample(wo, u_component, [0.5, 0.5], &mut sampled)
            .unwrap();
        assert!(sampled.secondary_terminated());
        assert_eq!(sampled.pdf()[0], lambdas.pdf()[0] / 4.0);
        assert_eq!(sampled.lambdas(), lambdas.lambdas());
    }
    let mut sampled = lambdas;
    plain
        .bsdf(&lambdas)
        .sample(wo, 0.9, [0.5, 0.5], &mut sampled)
        .unwrap();
    assert_eq!(sampled, lambdas, "constant η keeps all wavelengths");
    // Different hero wavelengths refract in different directions.
    let blue = SampledWavelengths::from_parts([400.0, 500.0, 600.0, 700.0], [0.01; 4]).unwrap();
    let red = SampledWavelengths::from_parts([700.0, 400.0, 500.0, 600.0], [0.01; 4]).unwrap();
    let (mut blue_copy, mut red_copy) = (blue, red);
    let blue_wi = dispersive
        .bsdf(&blue)
        .sample(wo, 0.9, [0.0; 2], &mut blue_copy)
        .unwrap()
        .wi;
    let red_wi = dispersive
        .bsdf(&red)
        .sample(wo, 0.9, [0.0; 2], &mut red_copy)
        .unwrap()
        .wi;
    assert!(
        blue_wi.x.abs() < red_wi.x.abs(),
        "blue bends more: {blue_wi} vs {red_wi}"
    );
}

#[test]
fn conductor_and_mirror_materials() {
    let lambdas = wavelengths();
    let metal = Material::conductor(constant(0.27), constant(2.78)).unwrap();
    let wo = Vec3::new(0.6, 0.0, 0.8);
    let mut sampled = lambdas;
    let sample = metal
        .bsdf(&lambdas)
        .sample(wo, 0.5, [0.5, 0.5], &mut sampled)
        .unwrap();
    let expected = fresnel_complex(0.8, 0.27, 2.78);
    for weight in sample.weight().values() {
        assert!((weight - expected).abs() < 1e-6);
    }
    let mirror = Material::Mirror.bsdf(&lambdas);
    let sample = mirror.sample(wo, 0.5, [0.5, 0.5], &mut sampled).unwrap();
    assert!(
        sample
            .weight()
            .values()
            .iter()
            .all(|w| (w - 1.0).abs() < 1e-6)
    );
    assert_eq!(mirror.flags(), BsdfFlags::REFLECTION | BsdfFlags::SPECULAR);
}

#[test]
fn transport_mode_changes_only_refraction() {
    let lambdas = wavelengths();
    let glass = Material::dielectric(constant(1.5)).unwrap().bsdf(&lambdas);
    let importance = glass.with_transport_mode(TransportMode::Importance);
    assert_eq!(importance.transport_mode(), TransportMode::Importance);
    let wo = Vec3::Z;
    let (mut a, mut b) = (lambdas, lambdas);
    let radiance_sample = glass.sample(wo, 0.5, [0.5, 0.5], &mut a).unwrap();
    let importance_sample = importance.sample(wo, 0.5, [0.5, 0.5], &mut b).unwrap();
    assert!(radiance_sample.is_transmission());
    let ratio = radiance_sample.value[0] / importance_sample.value[0];
    assert!((ratio - 1.0 / 2.25).abs() < 1e-6);
    let diffuse: Bsdf = DiffuseBsdf::new(SampledSpectrum::splat(0.5))
        .unwrap()
        .into();
    let (mut a, mut b) = (lambdas, lambdas);
    assert_eq!(
        diffuse.sample(wo, 0.5, [0.2, 0.4], &mut a),
        diffuse
            .with_transport_mode(TransportMode::Importance)
            .sample(wo, 0.5, [0.2, 0.4], &mut b)
    );
}

#[test]
fn surface_bsdf_works_in_world_space() {
    let lambdas = wavelengths();
    let normal = Vec3::new(0.3, -0.4, 0.5).normalize();
    let frame = ShadingFrame::from_normal(normal).unwrap();
    let wo = Vec3::new(0.2, 0.1, 1.0).normalize();
    assert!(wo.dot(normal) > 0.0);

    // A mirror reflects about the shading normal.
    let mirror = Material::Mirror.surface_bsdf(frame, &lambdas);
    let mut sampled = lambdas;
    let sample = mirror.sample(wo, 0.5, [0.5, 0.5], &mut sampled).unwrap();
    let expected = 2.0 * wo.dot(normal) * normal - wo;
    assert!((sample.wi - expected).length() < 1e-5);

    // A diffuse surface: world-space wi on the normal's side, with consistent
    // value and pdf.
    let diffuse = Material::diffuse(constant(0.5))
        .unwrap()
        .surface_bsdf(frame, &lambdas);
    for step in 0..100 {
        let u = [
            (step as f32 + 0.5) / 100.0,
            ((step as f32 + 0.5) * 0.618_034).fract(),
        ];
        let sample = diffuse.sample(wo, 0.5, u, &mut sampled).unwrap();
        assert!(sample.wi.dot(normal) > 0.0);
        assert!((sample.wi.length() - 1.0).abs() < 1e-5);
        let pdf = diffuse.pdf(wo, sample.wi);
        assert!((pdf - sample.pdf).abs() < 1e-5 * pdf.max(1e-3));
        assert!((pdf - sample.wi.dot(normal) / std::f32::consts::PI).abs() < 1e-5);
        assert_eq!(diffuse.evaluate(wo, sample.wi, &lambdas), sample.value);
    }
    assert!(diffuse.flags().is_diffuse());
}

#[test]
fn evaluate_with_pdf_equals_evaluate_and_pdf() {
    let lambdas = wavelengths();
    let normal = Vec3::new(0.3, -0.4, 0.5).normalize();
    let hit = render::geometry::SurfaceHit {
        t: 1.0,
        point: Vec3::new(0.5, 1.0, -2.0),
        geometric_normal: normal,
        shading_normal: normal,
        uv: glam::Vec2::new(0.3, 0.4),
        dpdu: Vec3::X,
        dpdv: normal.cross(Vec3::X),
        shape_index: 0,
        primitive_index: 0,
        time: 0.0,
    };
    let materials = [
        Material::diffuse(constant(0.5)).unwrap(),
        Material::Mask {
            opacity: render::texture::FloatTexture::Constant(0.3),
            nested: Box::new(Material::diffuse(constant(0.7)).unwrap()),
        },
        Material::TwoSided {
            front: Box::new(Material::diffuse(constant(0.2)).unwrap()),
            back: Box::new(Material::diffuse(constant(0.9)).unwrap()),
        },
        Material::Mirror,
    ];
    let directions = [
        Vec3::new(0.2, 0.1, 1.0).normalize(),
        Vec3::new(-0.7, 0.2, 0.1).normalize(),
        -normal,
        Vec3::new(0.1, 0.9, -0.3).normalize(),
    ];
    for material in &materials {
        let surface = material.surface_bsdf_at(&hit, &lambdas);
        for wo in directions {
            for wi in directions {
                let (value, pdf) = surface.evaluate_with_pdf(wo, wi, &lambdas);
                assert_eq!(value, surface.evaluate(wo, wi, &lambdas), "{material:?}");
                assert_eq!(pdf, surface.pdf(wo, wi), "{material:?}");
            }
        }
    }
}

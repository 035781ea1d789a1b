//! Tests of every sampler: range, determinism, random access, and that the
//! numbers are uniform (tolerances from the variance of uniform values).

use super::*;
use qmc::halton::{Halton, HaltonScramble};
use std::sync::Arc;

fn all_samplers() -> Vec<Box<dyn PixelSampler>> {
    let mut samplers: Vec<Box<dyn PixelSampler>> = SamplerKind::ALL
        .iter()
        .map(|(kind, _)| kind.create(7, (16, 9), 64))
        .collect();
    let points: Arc<dyn qmc::PointSet> = Arc::new(Halton::new(8, HaltonScramble::Owen, 3).unwrap());
    samplers.push(Box::new(PointSetSampler::new(points, "owen-halton", 7)));
    samplers
}

#[test]
fn numbers_are_in_unit_interval_and_repeatable() {
    for mut sampler in all_samplers() {
        let name = sampler.name();
        for sample in 0..8 {
            sampler.start_pixel_sample((3, 4), sample);
            let first: Vec<f32> = (0..300).map(|d| sampler.get(d)).collect();
            assert!(first.iter().all(|v| (0.0..1.0).contains(v)), "{name}");
            // Random access (reverse order) gives the same numbers.
            sampler.start_pixel_sample((3, 4), sample);
            for d in (0..300).rev() {
                assert_eq!(sampler.get(d), first[d], "{name} dim {d}");
            }
            // A clone positioned at the same sample agrees.
            let mut clone = sampler.clone_sampler();
            clone.start_pixel_sample((3, 4), sample);
            assert_eq!(clone.get(17), first[17], "{name}");
        }
    }
}

#[test]
fn pixels_and_samples_get_different_numbers() {
    for mut sampler in all_samplers() {
        let name = sampler.name();
        sampler.start_pixel_sample((1, 1), 0);
        let a: Vec<f32> = (0..12).map(|d| sampler.get(d)).collect();
        sampler.start_pixel_sample((2, 1), 0);
        let b: Vec<f32> = (0..12).map(|d| sampler.get(d)).collect();
        sampler.start_pixel_sample((1, 1), 1);
        let c: Vec<f32> = (0..12).map(|d| sampler.get(d)).collect();
        assert_ne!(a, b, "{name}");
        assert_ne!(a, c, "{name}");
    }
}

#[test]
fn every_dimension_is_uniform_on_average() {
    // Over n pixel samples the mean of a dimension has standard error
    // sqrt(1/(12 n)) for independent uniforms; QMC samplers do better.
    let n = 4096u64;
    let bound = 5.0 * (1.0 / (12.0 * n as f64)).sqrt();
    for mut sampler in all_samplers() {
        let name = sampler.name();
        for dimension in [0usize, 1, 5, layout::vertex(3, 4), 255, 256, 300] {
            let mut sum = 0.0f64;
            for sample in 0..n {
                // Spread over pixels so the per-pixel randomizations average out.
                let pixel = ((sample % 16) as u32, ((sample / 16) % 9) as u32);
                sampler.start_pixel_sample(pixel, sample / 144);
                sum += sampler.get(dimension) as f64;
            }
            let mean = sum / n as f64;
            assert!((mean - 0.5).abs() < bound, "{name} dim {dimension}: {mean}");
        }
    }
}

#[test]
fn halton_film_dimensions_stratify_each_pixel() {
    // With 2^a 3^b ≥ resolution, six consecutive samples of a pixel have
    // film positions (dims 0, 1) in distinct cells of a 2×3 grid of the pixel.
    let mut sampler = SamplerKind::Halton.create(1, (5, 4), 6);
    for pixel in [(0u32, 0u32), (4, 3), (2, 1)] {
        let mut cells = [false; 6];
        for sample in 0..6 {
            sampler.start_pixel_sample(pixel, sample);
            let [x, y] = sampler.get_2d(layout::FILM);
            let cell = (x * 2.0) as usize + 2 * (y * 3.0) as usize;
            assert!(!cells[cell], "pixel {pixel:?} sample {sample}");
            cells[cell] = true;
        }
    }
}

#[test]
fn sobol_first_samples_of_a_pixel_are_a_net() {
    // The first 16 samples of a pixel, dims (0, 1), put one point in every
    // cell of a 4×4 grid: Owen scrambling keeps the (0, 4, 2)-net.
    let mut sampler = SamplerKind::Sobol.create(9, (4, 4), 16);
    let mut cells = [0u32; 16];
    for sample in 0..16 {
        sampler.start_pixel_sample((2, 3), sample);
        let [x, y] = sampler.get_2d(0);
        cells[(x * 4.0) as usize + 4 * (y * 4.0) as usize] += 1;
    }
    assert!(cells.iter().all(|&c| c == 1), "{cells:?}");
}

#[test]
fn layout_blocks_do_not_overlap() {
    assert_eq!(layout::vertex(0, 0), layout::CAMERA_DIMENSIONS);
    assert_eq!(
        layout::vertex(1, 0),
        layout::vertex(0, layout::FREE_FLIGHT) + 1
    );
    assert_eq!(SamplerKind::from_name("sobol"), Some(SamplerKind::Sobol));
    assert_eq!(SamplerKind::from_name("zsobol"), None);
}

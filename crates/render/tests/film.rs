//! The film: deterministic merging across thread counts, filter-weighted
//! means, rejection of non-finite samples, and the variance estimate.

use qmc::random::SeekablePcg;
use rayon::prelude::*;
use render::film::{
    BoxFilter, Film, FilmError, FilmTile, Filter, GaussianFilter, PixelBounds, SampleOutcome,
    SplatBuffer, TriangleFilter,
};
use render::image::{Metadata, VARIANCE_LAYER, read_exr};

fn all_filters() -> Vec<Filter> {
    vec![
        Filter::Box(BoxFilter::default()),
        Filter::Triangle(TriangleFilter::default()),
        Filter::Gaussian(GaussianFilter::default()),
    ]
}

/// A synthetic "radiance" at a raster position, with some noise from `random`.
fn radiance(position: [f32; 2], random: &mut SeekablePcg) -> [f32; 3] {
    let base = (position[0] * 0.37).sin() * (position[1] * 0.21).cos() + 1.0;
    [base * random.next_f32(), base, 2.0 * random.next_f32()]
}

/// Renders `tile` with 8 samples per pixel; every pixel has its own random
/// stream, so the tile is the same whichever thread renders it.
fn render_tile(film: &Film, bounds: PixelBounds) -> FilmTile {
    let mut tile = film.new_tile(bounds).unwrap();
    for y in bounds.min[1]..bounds.max[1] {
        for x in bounds.min[0]..bounds.max[0] {
            let mut random = SeekablePcg::new(11, (y * 1000 + x) as u64);
            for _ in 0..8 {
                let camera =
                    film.camera_sample_position([x, y], [random.next_f32(), random.next_f32()]);
                let rgb = radiance(camera.raster_position, &mut random);
                tile.add_sample([x, y], rgb, camera.weight).unwrap();
            }
        }
    }
    tile
}

/// The splats of work unit `unit`: light-tracing-like contributions at
/// random positions (some outside the film).
fn render_splats(film: &Film, unit: usize) -> SplatBuffer {
    let mut random = SeekablePcg::new(23, unit as u64);
    let mut buffer = SplatBuffer::new();
    let [width, height] = film.resolution().map(|size| size as f32);
    for _ in 0..500 {
        let position = [
            random.next_f32() * (width + 4.0) - 2.0,
            random.next_f32() * (height + 4.0) - 2.0,
        ];
        buffer.add(position, [random.next_f32(), 0.5, random.next_f32() * 3.0]);
    }
    buffer
}

fn render_with_threads(threads: usize, filter: Filter) -> (Vec<u32>, Vec<u32>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut film = Film::new([45, 31], filter).unwrap();
    let tile_bounds = film.tile_bounds(8).unwrap();
    let (tiles, buffers): (Vec<FilmTile>, Vec<SplatBuffer>) = pool.install(|| {
        let tiles = tile_bounds
            .par_iter()
            .map(|&bounds| render_tile(&film, bounds))
            .collect();
        let buffers = (0..16)
            .into_par_iter()
            .map(|unit| render_splats(&film, unit))
            .collect();
        (tiles, buffers)
    });
    for tile in &tiles {
        film.merge_tile(tile).unwrap();
    }
    for buffer in &buffers {
        film.merge_splats(buffer);
    }
    let bits = |image: render::image::Image| {
        image
            .pixels()
            .iter()
            .flat_map(|pixel| pixel.map(f32::to_bits))
            .collect::<Vec<u32>>()
    };
    (bits(film.image(1.0 / 8.0)), bits(film.variance_image()))
}

#[test]
fn merging_in_a_fixed_order_is_bit_identical_across_thread_counts() {
    for filter in all_filters() {
        let one_thread = render_with_threads(1, filter);
        let two_threads = render_with_threads(2, filter);
        assert!(one_thread == two_threads, "{filter:?}: images differ");
        assert!(one_thread.0.iter().any(|&bits| bits != 0));
    }
}

/// The banded parallel merge (`merge_splat_buffers`, bands of rows over
/// the pool's threads) adds to every pixel in the same order as merging
/// the buffers one after the other: bit-identical images for 1, 2 and 3
/// threads (3 bands of 11, 11 and 9 rows: splats whose filter straddles
/// a band boundary are split between bands).
#[test]
fn parallel_splat_merge_is_bit_identical_to_the_sequential_one() {
    for filter in all_filters() {
        let mut sequential = Film::new([45, 31], filter).unwrap();
        let buffers: Vec<SplatBuffer> = (0..16)
            .map(|unit| render_splats(&sequential, unit))
            .collect();
        for buffer in &buffers {
            sequential.merge_splats(buffer);
        }
        let expected: Vec<u32> = sequential
            .image(1.0)
            .pixels()
            .iter()
            .flat_map(|pixel| pixel.map(f32::to_bits))
            .collect();
        assert!(expected.iter().any(|&bits| bits != 0));
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut banded = Film::new([45, 31], filter).unwrap();
            pool.install(|| banded.merge_splat_buffers(&buffers.iter().collect::<Vec<_>>()));
            let bits: Vec<u32> = banded
                .image(1.0)
                .pixels()
                .iter()
                .flat_map(|pixel| pixel.map(f32::to_bits))
                .collect();
            assert!(bits == expected, "{filter:?}, {threads} threads");
        }
    }
}

#[test]
fn atomic_splats_agree_with_merged_buffers_up_to_rounding() {
    let filter = Filter::Gaussian(GaussianFilter::default());
    let mut merged = Film::new([20, 10], filter).unwrap();
    let atomic = Film::new([20, 10], filter).unwrap();
    let buffers: Vec<SplatBuffer> = (0..8).map(|unit| render_splats(&merged, unit)).collect();
    for buffer in &buffers {
        merged.merge_splats(buffer);
    }
    buffers.par_iter().for_each(|buffer| {
        for splat in buffer.splats() {
            atomic.add_splat(splat.raster_position, splat.rgb);
        }
    });
    let (a, b) = (merged.image(1.0), atomic.image(1.0));
    for (x, y) in a.pixels().iter().zip(b.pixels()) {
        for channel in 0..3 {
            assert!((x[channel] - y[channel]).abs() <= 1e-5 * x[channel].abs().max(1.0));
        }
    }
}

#[test]
fn filter_weighted_mean_of_a_constant_is_the_constant() {
    let constant = [0.25f32, 1.5, 3.0];
    for filter in all_filters() {
        let mut film = Film::new([6, 5], filter).unwrap();
        let mut tile = film.new_tile(film.pixel_bounds()).unwrap();
        let mut random = SeekablePcg::new(5, 0);
        for y in 0..5 {
            for x in 0..6 {
                for _ in 0..37 {
                    let camera =
                        film.camera_sample_position([x, y], [random.next_f32(), random.next_f32()]);
                    assert_eq!(camera.weight, 1.0);
                    tile.add_sample([x, y], constant, camera.weight).unwrap();
                }
            }
        }
        film.merge_tile(&tile).unwrap();
        let image = film.image(0.0);
        for pixel in image.pixels() {
            for channel in 0..3 {
                assert!(
                    (pixel[channel] - constant[channel]).abs() <= 1e-6 * constant[channel],
                    "{filter:?}: {pixel:?}"
                );
            }
        }
        // A constant has no variance.
        assert!(
            film.variance_image()
                .pixels()
                .iter()
                .all(|pixel| pixel.iter().all(|&v| v.abs() < 1e-10))
        );
        assert!(film.sample_counts().iter().all(|&count| count == 37));
    }
}

/// The film splats a Gaussian separably (one factor per row and column);
/// every pixel must get exactly `evaluate`'s value, as per-pixel evaluation
/// gave, also near the image border and for wide filters.
#[test]
fn gaussian_splats_equal_the_filter_value_per_pixel() {
    for filter in [
        GaussianFilter::default(),
        GaussianFilter::new([3.0, 1.0], 1.2).unwrap(),
        GaussianFilter::new([5.0, 5.0], 2.0).unwrap(),
    ] {
        let mut random = SeekablePcg::new(5, 0);
        for _ in 0..40 {
            let position = [
                random.next_f32() * 12.0 - 1.0,
                random.next_f32() * 9.0 - 1.0,
            ];
            let mut film = Film::new([10, 7], Filter::Gaussian(filter)).unwrap();
            let mut buffer = SplatBuffer::new();
            buffer.add(position, [1.0, 2.0, 0.5]);
            film.merge_splats(&buffer);
            for y in 0..7 {
                for x in 0..10 {
                    let offset = [
                        (x as f64 + 0.5 - position[0] as f64) as f32,
                        (y as f64 + 0.5 - position[1] as f64) as f32,
                    ];
                    let weight = filter.evaluate(offset) as f64;
                    let inside = [0, 1].into_iter().all(|axis| {
                        offset[axis] > -filter.radius()[axis]
                            && offset[axis] <= filter.radius()[axis]
                    });
                    let expected = if inside { weight } else { 0.0 };
                    assert_eq!(
                        film.splat(x, y),
                        Some([expected, 2.0 * expected, 0.5 * expected]),
                        "{filter:?} at {position:?}, pixel ({x}, {y})"
                    );
                }
            }
        }
    }
}

#[test]
fn splats_keep_their_energy_and_land_where_they_fall() {
    // Box (radius 0.5) and triangle (radius 2) filters are partitions of
    // unity on the pixel lattice: an interior splat's total is preserved.
    for filter in [
        Filter::Box(BoxFilter::default()),
        Filter::Triangle(TriangleFilter::default()),
    ] {
        let mut film = Film::new([16, 16], filter).unwrap();
        let mut buffer = SplatBuffer::new();
        buffer.add([7.3, 8.9], [1.0, 2.0, 4.0]);
        buffer.add([8.0, 8.0], [1.0, 1.0, 1.0]); // on a pixel corner
        film.merge_splats(&buffer);
        let image = film.image(0.5);
        let mut total = [0.0f64; 3];
        for pixel in image.pixels() {
            for channel in 0..3 {
                total[channel] += pixel[channel] as f64;
            }
        }
        let expected = [1.0, 1.5, 2.5];
        for channel in 0..3 {
            assert!(
                (total[channel] - expected[channel]).abs() < 1e-5,
                "{filter:?}: {total:?}"
            );
        }
    }
    // With the box filter a splat goes to the pixel containing it.
    let mut film = Film::new([4, 4], Filter::Box(BoxFilter::default())).unwrap();
    let mut buffer = SplatBuffer::new();
    buffer.add([2.0, 1.999], [3.0, 3.0, 3.0]);
    film.merge_splats(&buffer);
    assert_eq!(film.splat(2, 1), Some([3.0; 3]));
    assert_eq!(
        film.image(1.0)
            .pixels()
            .iter()
            .filter(|pixel| pixel[0] != 0.0)
            .count(),
        1
    );
}

#[test]
fn nonfinite_samples_are_counted_and_excluded() {
    let mut film = Film::new([2, 2], Filter::default()).unwrap();
    let mut tile = film.new_tile(film.pixel_bounds()).unwrap();
    let bad_samples = [
        ([f32::NAN, 0.0, 0.0], 1.0),
        ([0.0, f32::INFINITY, 0.0], 1.0),
        ([0.0, 0.0, f32::NEG_INFINITY], 1.0),
        ([1.0, 1.0, 1.0], -0.5),
        ([1.0, 1.0, 1.0], f32::NAN),
    ];
    for (rgb, weight) in bad_samples {
        assert_eq!(
            tile.add_sample([1, 1], rgb, weight),
            Ok(SampleOutcome::Rejected)
        );
    }
    assert_eq!(
        tile.add_sample([1, 1], [2.0, 4.0, 6.0], 1.0),
        Ok(SampleOutcome::Accepted)
    );
    assert_eq!(
        tile.add_sample([1, 1], [-2.0, 0.0, 2.0], 1.0),
        Ok(SampleOutcome::Accepted)
    );
    assert_eq!(tile.rejected_samples(), 5);
    film.merge_tile(&tile).unwrap();

    let mut buffer = SplatBuffer::new();
    assert_eq!(
        buffer.add([0.5, 0.5], [f32::NAN, 0.0, 0.0]),
        SampleOutcome::Rejected
    );
    assert_eq!(
        buffer.add([f32::INFINITY, 0.5], [1.0, 0.0, 0.0]),
        SampleOutcome::Rejected
    );
    film.merge_splats(&buffer);
    assert_eq!(
        film.add_splat([0.5, 0.5], [0.0, f32::NAN, 0.0]),
        SampleOutcome::Rejected
    );

    assert_eq!(film.nonfinite_samples(), 8);
    assert_eq!(film.sample_counts(), vec![0, 0, 0, 2]);
    let image = film.image(1.0);
    assert_eq!(image.pixel(1, 1), Some([0.0, 2.0, 4.0]));
    assert!(
        image
            .pixels()
            .iter()
            .flatten()
            .all(|value| value.is_finite())
    );
    // Variance of the mean of {2, −2}, {4, 0}, {6, 2}: s² = 8, / n = 4.
    assert_eq!(film.variance_image().pixel(1, 1), Some([4.0, 4.0, 4.0]));
}

/// The variance of the unbiased sample variance of `n` draws from a
/// distribution with variance `sigma2` and excess kurtosis `kurtosis`:
/// `σ⁴ (2 / (n − 1) + κ / n)`.
fn variance_of_sample_variance(sigma2: f64, kurtosis: f64, n: f64) -> f64 {
    sigma2 * sigma2 * (2.0 / (n - 1.0) + kurtosis / n)
}

#[test]
fn variance_estimate_matches_uniform_variance() {
    // Uniform on [0, 1): σ² = 1/12, excess kurtosis −6/5.
    let (sigma2, kurtosis) = (1.0 / 12.0, -1.2);

    // One pixel, many samples, split over several tiles (exercising the
    // pairwise merge).
    let samples_per_tile = 5000u64;
    let tiles = 4u64;
    let n = (samples_per_tile * tiles) as f64;
    let mut film = Film::new([3, 3], Filter::Box(BoxFilter::default())).unwrap();
    let mut random = SeekablePcg::new(99, 0);
    for _ in 0..tiles {
        let mut tile = film
            .new_tile(PixelBounds {
                min: [1, 1],
                max: [2, 2],
            })
            .unwrap();
        for _ in 0..samples_per_tile {
            let values = [random.next_f32(), random.next_f32(), random.next_f32()];
            tile.add_sample([1, 1], values, 1.0).unwrap();
        }
        film.merge_tile(&tile).unwrap();
    }
    let variance_of_mean = film.variance_image().pixel(1, 1).unwrap();
    // s²/n has standard deviation sqrt(Var(s²)) / n; allow 5 of them.
    let tolerance = 5.0 * variance_of_sample_variance(sigma2, kurtosis, n).sqrt() / n;
    for value in variance_of_mean {
        let error = (value as f64 - sigma2 / n).abs();
        assert!(
            error < tolerance,
            "variance of mean {value} vs {} (tolerance {tolerance})",
            sigma2 / n
        );
    }

    // Many pixels with few samples: the average of the estimates is
    // unbiased for σ²/n.
    let (width, height, per_pixel) = (64usize, 64usize, 16u64);
    let mut film = Film::new([width, height], Filter::Box(BoxFilter::default())).unwrap();
    let mut tile = film.new_tile(film.pixel_bounds()).unwrap();
    for y in 0..height {
        for x in 0..width {
            for _ in 0..per_pixel {
                let value = random.next_f32();
                tile.add_sample([x, y], [value; 3], 1.0).unwrap();
            }
        }
    }
    film.merge_tile(&tile).unwrap();
    let pixels = (width * height) as f64;
    let n = per_pixel as f64;
    let average = film.variance_image().mean()[0];
    let tolerance = 5.0 * (variance_of_sample_variance(sigma2, kurtosis, n) / pixels).sqrt() / n;
    assert!(
        (average - sigma2 / n).abs() < tolerance,
        "{average} vs {} ± {tolerance}",
        sigma2 / n
    );
}

#[test]
fn bad_film_requests_are_errors() {
    assert_eq!(
        Film::new([0, 4], Filter::default()).unwrap_err(),
        FilmError::InvalidResolution { resolution: [0, 4] }
    );
    let film = Film::new([4, 4], Filter::default()).unwrap();
    let outside = PixelBounds {
        min: [2, 2],
        max: [5, 4],
    };
    let message = film.new_tile(outside).unwrap_err().to_string();
    assert!(message.contains("4x4"), "{message}");
    let mut tile = film
        .new_tile(PixelBounds {
            min: [0, 0],
            max: [2, 2],
        })
        .unwrap();
    assert!(tile.add_sample([3, 0], [1.0; 3], 1.0).is_err());
    assert!(film.tile_bounds(0).is_err());
    let tiles = film.tile_bounds(3).unwrap();
    assert_eq!(tiles.len(), 4);
    assert_eq!(tiles.iter().map(PixelBounds::area).sum::<usize>(), 16);
}

#[test]
fn film_writes_exr_with_variance_layer() {
    let mut film = Film::new([5, 3], Filter::default()).unwrap();
    let mut tile = film.new_tile(film.pixel_bounds()).unwrap();
    for (index, value) in [1.0f32, 3.0, 5.0].into_iter().enumerate() {
        tile.add_sample([index, 1], [value; 3], 1.0).unwrap();
        tile.add_sample([index, 1], [value + 2.0; 3], 1.0).unwrap();
    }
    film.merge_tile(&tile).unwrap();
    let path = std::env::temp_dir().join(format!("lqmc-film-{}.exr", std::process::id()));
    let metadata: Metadata = [("spp".to_string(), "2".to_string())].into();
    film.write(&path, 1.0, &metadata).unwrap();
    let contents = read_exr(&path).unwrap();
    assert_eq!(contents.image, film.image(1.0));
    assert_eq!(contents.layers[VARIANCE_LAYER], film.variance_image());
    assert_eq!(contents.layers[VARIANCE_LAYER].pixel(0, 1), Some([1.0; 3]));
    assert_eq!(contents.metadata["spp"], "2");
    std::fs::remove_file(&path).ok();
}

//! Tests of every sampler: range, determinism, random access, and that the
//! numbers are uniform (tolerances from the variance of uniform values).

use super::*;
use qmc::halton::{Halton, HaltonScramble};
use std::sync::Arc;

fn all_samplers() -> Vec<Box<dyn PixelSampler>> {
    let mut samplers: Vec<Box<dyn PixelSampler>> = SamplerKind::ALL
        .iter()
        .map(|(kind, _)| {
            kind.create(7, Randomization::Seeded, (16, 9), 64, None)
                .unwrap()
        })
        .collect();
    let points: Arc<dyn qmc::PointSet> = Arc::new(Halton::new(8, HaltonScramble::Owen, 3).unwrap());
    samplers.push(Box::new(PointSetSampler::new(
        points,
        "owen-halton",
        7,
        Randomization::Seeded,
        None,
    )));
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
    let mut sampler = SamplerKind::Halton
        .create(1, Randomization::Seeded, (5, 4), 6, None)
        .unwrap();
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
    let mut sampler = SamplerKind::Sobol
        .create(9, Randomization::Seeded, (4, 4), 16, None)
        .unwrap();
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

/// Sampler, seed, pixel, sample index and the numbers of
/// [`GOLDEN_DIMENSIONS`].
type GoldenRow = (SamplerKind, u64, (u32, u32), u64, [u32; 8]);

/// The dimensions of [`GOLDEN_NUMBERS`].
const GOLDEN_DIMENSIONS: [usize; 8] = [0, 1, 2, 5, 17, 255, 256, 300];

/// Numbers (`f32` bits) of the samplers before seeds randomized Halton,
/// recorded from that code (commit b484c5f) on a 16×9 image with 64 spp:
/// sampler, seed, pixel, sample index, then the numbers of
/// [`GOLDEN_DIMENSIONS`].
#[rustfmt::skip]
const GOLDEN_NUMBERS: [GoldenRow; 18] = [
    (SamplerKind::Halton, 0, (0, 0), 0, [0, 0, 0, 0, 0, 0, 995817472, 1059218940]),
    (SamplerKind::Halton, 0, (3, 4), 1, [1060110336, 1050129446, 1043395196, 1064291754, 1063536173, 1063405028, 1037872872, 1063133566]),
    (SamplerKind::Halton, 0, (15, 8), 7, [1063387136, 1054410052, 1059168463, 1036483728, 1057494391, 1032446453, 1059972005, 1061087258]),
    (SamplerKind::Halton, 5, (0, 0), 0, [0, 0, 0, 0, 0, 0, 1063096842, 1049681450]),
    (SamplerKind::Halton, 5, (3, 4), 1, [1060110336, 1050129446, 1043395196, 1064291754, 1063536173, 1063405028, 1058359043, 1052496916]),
    (SamplerKind::Halton, 5, (15, 8), 7, [1063387136, 1054410052, 1059168463, 1036483728, 1057494391, 1032446453, 1052988404, 1041624836]),
    (SamplerKind::Sobol, 0, (0, 0), 0, [1065017913, 1021933508, 1055263116, 1059003899, 1051819120, 1057085948, 1058289800, 1065345599]),
    (SamplerKind::Sobol, 0, (3, 4), 1, [1054295057, 1063110486, 1064068776, 1047791831, 1028282763, 1062269439, 1056797774, 1043868233]),
    (SamplerKind::Sobol, 0, (15, 8), 7, [1040575146, 1045464459, 1052614608, 1055472717, 1054674645, 1061607467, 1041310127, 1042854952]),
    (SamplerKind::Sobol, 5, (0, 0), 0, [1049451121, 1037423427, 1035786581, 1052091152, 1003649426, 1058598594, 1061292444, 1058391175]),
    (SamplerKind::Sobol, 5, (3, 4), 1, [1041828678, 1039581642, 1033601445, 1059149195, 1047048418, 1061159948, 1051698064, 1036107932]),
    (SamplerKind::Sobol, 5, (15, 8), 7, [1057486235, 1063646774, 1020979641, 1062305048, 1062298973, 1050164866, 1064544599, 1060371945]),
    (SamplerKind::Lattice, 0, (0, 0), 0, [1060827014, 1044814242, 1036940751, 1057968379, 1062490953, 1063678879, 1045881700, 1063759585]),
    (SamplerKind::Lattice, 0, (3, 4), 1, [1062640395, 1064965485, 1064656002, 1058887552, 1059532015, 1064704003, 1060448872, 1055757098]),
    (SamplerKind::Lattice, 0, (15, 8), 7, [1052562398, 1018321191, 1058246032, 1059208883, 1058807232, 1055828916, 1045023332, 1042954376]),
    (SamplerKind::Lattice, 5, (0, 0), 0, [1057606213, 1047316222, 1034919382, 1062445551, 1047061534, 1034836656, 1063067591, 1063866968]),
    (SamplerKind::Lattice, 5, (3, 4), 1, [1060519979, 1049290908, 1054195615, 1053160899, 1058444483, 1009148352, 1055815238, 1064775927]),
    (SamplerKind::Lattice, 5, (15, 8), 7, [1052502056, 1059677885, 1056961032, 1050017060, 1062640458, 1042220252, 1058099551, 1041535832]),
];

/// The numbers of `kind` at a golden pixel sample.
fn numbers_at(
    kind: SamplerKind,
    seed: u64,
    randomization: Randomization,
    pixel: (u32, u32),
    sample: u64,
) -> [u32; 8] {
    let mut sampler = kind.create(seed, randomization, (16, 9), 64, None).unwrap();
    sampler.start_pixel_sample(pixel, sample);
    GOLDEN_DIMENSIONS.map(|dimension| sampler.get(dimension).to_bits())
}

/// `Randomization::None` is the old Halton sampler bit for bit, whatever
/// the seed (which reaches only the MT19937 past dimension 256); seeded
/// Sobol and lattice are the old ones (they were already keyed by the seed).
#[test]
fn no_randomization_reproduces_the_old_samplers() {
    for (kind, seed, pixel, sample, golden) in GOLDEN_NUMBERS {
        let randomization = match kind {
            SamplerKind::Halton => Randomization::None,
            _ => Randomization::Seeded,
        };
        assert_eq!(
            numbers_at(kind, seed, randomization, pixel, sample),
            golden,
            "{kind:?} seed {seed} {pixel:?} sample {sample}"
        );
    }
}

/// Without randomization Sobol and lattice use seed 0's per-pixel scrambles
/// and shifts for every seed; only the PCG streams past the point set (the
/// lattice's 32 dimensions) follow the seed.
#[test]
fn no_randomization_fixes_the_sobol_and_lattice_scrambles() {
    for (kind, seed, pixel, sample, golden) in GOLDEN_NUMBERS {
        if kind == SamplerKind::Halton || seed == 0 {
            continue;
        }
        let seed_zero = GOLDEN_NUMBERS
            .iter()
            .find(|row| row.0 == kind && row.1 == 0 && row.2 == pixel && row.3 == sample)
            .unwrap()
            .4;
        let numbers = numbers_at(kind, seed, Randomization::None, pixel, sample);
        for (position, dimension) in GOLDEN_DIMENSIONS.iter().enumerate() {
            let in_point_set = kind == SamplerKind::Sobol || *dimension < 32;
            let expected = if in_point_set {
                seed_zero[position]
            } else {
                golden[position]
            };
            assert_eq!(
                numbers[position], expected,
                "{kind:?} dimension {dimension}"
            );
        }
    }
}

/// Seeded, every sampler gives other numbers for another seed (in every
/// dimension: a coincidence has probability about 2^-24 per number) and the
/// same numbers for the same seed.
#[test]
fn seeds_change_every_number_and_repeat() {
    for (kind, _) in SamplerKind::ALL {
        for (pixel, sample) in [((0u32, 0u32), 0u64), ((3, 4), 1), ((15, 8), 7)] {
            let first = numbers_at(kind, 1, Randomization::Seeded, pixel, sample);
            let again = numbers_at(kind, 1, Randomization::Seeded, pixel, sample);
            let other = numbers_at(kind, 2, Randomization::Seeded, pixel, sample);
            assert_eq!(first, again, "{kind:?}");
            for (position, dimension) in GOLDEN_DIMENSIONS.iter().enumerate() {
                assert_ne!(
                    first[position], other[position],
                    "{kind:?} {pixel:?} sample {sample} dimension {dimension}"
                );
            }
        }
    }
}

/// Without randomization the Halton points (below dimension 256) are the
/// same for every seed.
#[test]
fn no_randomization_keeps_halton_points_for_every_seed() {
    let first = numbers_at(SamplerKind::Halton, 1, Randomization::None, (3, 4), 2);
    let other = numbers_at(SamplerKind::Halton, 2, Randomization::None, (3, 4), 2);
    assert_eq!(first[..6], other[..6]);
    assert_ne!(first[6..], other[6..]);
}

/// The seeded Halton sampler's film position stays in its pixel and
/// stratifies it, as the enumeration inverts the digital shifts.
#[test]
fn seeded_halton_film_dimensions_stratify_each_pixel() {
    for seed in [3u64, 4] {
        let mut sampler = SamplerKind::Halton
            .create(seed, Randomization::Seeded, (5, 4), 6, None)
            .unwrap();
        for pixel in [(0u32, 0u32), (4, 3), (2, 1)] {
            let mut cells = [false; 6];
            for sample in 0..6 {
                sampler.start_pixel_sample(pixel, sample);
                let [x, y] = sampler.get_2d(layout::FILM);
                let cell = (x * 2.0) as usize + 2 * (y * 3.0) as usize;
                assert!(!cells[cell], "seed {seed} pixel {pixel:?} sample {sample}");
                cells[cell] = true;
            }
        }
    }
}

/// The first `m` samples of a pixel: dimension `dimension` of each.
fn replication_values(
    sampler: &mut dyn PixelSampler,
    pixel: (u32, u32),
    replication: u64,
    m: u64,
    dimension: usize,
) -> Vec<f64> {
    (0..m)
        .map(|point| {
            sampler.start_pixel_sample(pixel, replication * m + point);
            f64::from(sampler.get(dimension))
        })
        .collect()
}

/// Whether `values` put one value in each of `m` equal intervals.
fn stratified(values: &[f64], m: usize) -> bool {
    let mut cells = vec![0; m];
    for value in values {
        cells[((value * m as f64) as usize).min(m - 1)] += 1;
    }
    cells.iter().all(|&count| count == 1)
}

#[test]
fn padded_replications_repeat_the_pattern_in_every_pair() {
    let m = 16u64;
    let mut sampler = SamplerKind::Padded
        .create(3, Randomization::Seeded, (8, 8), 64, Some(m))
        .unwrap();
    for replication in 0..4 {
        let first = replication_values(sampler.as_mut(), (2, 5), replication, m, 0);
        assert!(stratified(&first, m as usize), "{first:?}");
        // Pair k holds the same pattern point, shifted by its own rotation:
        // the difference to pair 0 is one constant modulo one.
        for dimension in [2, 10, 40] {
            let other = replication_values(sampler.as_mut(), (2, 5), replication, m, dimension);
            let offsets: Vec<f64> = first
                .iter()
                .zip(&other)
                .map(|(a, b)| (b - a).rem_euclid(1.0))
                .collect();
            let spread = offsets
                .iter()
                .map(|offset| {
                    let d = (offset - offsets[0]).abs();
                    d.min(1.0 - d)
                })
                .fold(0.0f64, f64::max);
            assert!(spread < 1e-5, "dimension {dimension}: {offsets:?}");
        }
    }
    // Replications have their own rotations.
    let a = replication_values(sampler.as_mut(), (2, 5), 0, m, 0);
    let b = replication_values(sampler.as_mut(), (2, 5), 1, m, 0);
    assert_ne!(a, b);
}

#[test]
fn latin_supercube_permutes_each_pair_and_deterministic_points_are_unshifted() {
    let m = 8u64;
    let mut sampler = SamplerKind::LatinSupercube
        .create(5, Randomization::None, (4, 4), 8, Some(m))
        .unwrap();
    let grid: Vec<f64> = (0..m).map(|i| (i as f64 + 0.5) / m as f64).collect();
    let mut orders = Vec::new();
    for dimension in [0, 2, 4, 6, 8, 10] {
        let mut values = replication_values(sampler.as_mut(), (1, 2), 0, m, dimension);
        orders.push(values.clone());
        values.sort_by(f64::total_cmp);
        // Without randomization the pattern's own first coordinate, centred.
        for (value, expected) in values.iter().zip(&grid) {
            assert!((value - expected).abs() < 1e-6, "{dimension}: {values:?}");
        }
    }
    // The pairs are permuted independently: not all in one order.
    assert!(orders.iter().any(|order| *order != orders[0]));
    // Randomized: each pair still one point per 1/m interval.
    let mut sampler = SamplerKind::LatinSupercube
        .create(5, Randomization::Seeded, (4, 4), 8, Some(m))
        .unwrap();
    for dimension in [0, 3, 17] {
        let values = replication_values(sampler.as_mut(), (1, 2), 3, m, dimension);
        assert!(stratified(&values, m as usize), "{dimension}: {values:?}");
    }
}

#[test]
fn global_sequences_give_each_pixel_a_consecutive_block() {
    use qmc::digital_scramble::{DigitalOrder, DigitalSequence};
    let sobol = qmc::sobol::Sobol::new(8, DigitalOrder::Natural).unwrap();
    let niederreiter = qmc::niederreiter::Niederreiter::new(8, DigitalOrder::Natural).unwrap();
    let sequences: [(SamplerKind, &dyn DigitalSequence); 2] = [
        (SamplerKind::GlobalSobol, &sobol),
        (SamplerKind::GlobalNiederreiter, &niederreiter),
    ];
    for (kind, sequence) in sequences {
        // 12 samples per pixel: blocks of 16 points; pixel (2, 1) of a
        // 5-pixel-wide image is pixel number 7.
        let mut sampler = kind
            .create(0, Randomization::None, (5, 3), 12, None)
            .unwrap();
        for sample in [0u64, 5, 11] {
            sampler.start_pixel_sample((2, 1), sample);
            for dimension in [0usize, 3, 7] {
                let expected = qmc::digital_scramble::bits_to_unit(
                    sequence.sample_bits(7 * 16 + sample, dimension),
                );
                assert!(
                    (f64::from(sampler.get(dimension)) - expected).abs() < 1e-6,
                    "{kind:?} sample {sample} dimension {dimension}"
                );
            }
        }
        // Randomized, a pixel's first 16 points still stratify dimension 0.
        let mut sampler = kind
            .create(4, Randomization::Seeded, (5, 3), 16, None)
            .unwrap();
        let values = replication_values(sampler.as_mut(), (4, 2), 0, 16, 0);
        assert!(stratified(&values, 16), "{kind:?}: {values:?}");
    }
}

#[test]
fn replications_of_point_sets_are_independent_rotations() {
    let m = 8u64;
    for kind in [
        SamplerKind::Hammersley,
        SamplerKind::Lattice,
        SamplerKind::Sobol,
    ] {
        let mut sampler = kind
            .create(2, Randomization::Seeded, (4, 4), 32, Some(m))
            .unwrap();
        let a = replication_values(sampler.as_mut(), (3, 3), 0, m, 0);
        let b = replication_values(sampler.as_mut(), (3, 3), 1, m, 0);
        assert!(stratified(&a, m as usize), "{kind:?}: {a:?}");
        assert!(stratified(&b, m as usize), "{kind:?}: {b:?}");
        assert_ne!(a, b, "{kind:?}");
    }
    assert_eq!(
        SamplerKind::Halton
            .create(0, Randomization::Seeded, (2, 2), 8, Some(4))
            .err(),
        Some(SamplerError::NoReplications("halton"))
    );
    assert_eq!(
        SamplerKind::Padded
            .create(0, Randomization::Seeded, (2, 2), 8, Some(0))
            .err(),
        Some(SamplerError::PatternSize(0))
    );
}

#[test]
fn time_budgets_get_bounded_patterns_and_blocks() {
    // A time budget's unlimited samples per pixel: the sequences' blocks
    // still fit 2^32 points, and the point sets replicate a small pattern.
    let unlimited = u64::MAX / (1 << 32);
    for kind in [SamplerKind::GlobalSobol, SamplerKind::GlobalNiederreiter] {
        let mut sampler = kind
            .create(1, Randomization::Seeded, (64, 48), unlimited, None)
            .unwrap();
        // Far pixels and late samples are still served by the sequence:
        // their first 16 samples stratify dimension 0.
        let values = replication_values(sampler.as_mut(), (63, 47), 0, 16, 0);
        assert!(stratified(&values, 16), "{kind:?}: {values:?}");
    }
    for kind in [
        SamplerKind::Hammersley,
        SamplerKind::Padded,
        SamplerKind::LatinSupercube,
    ] {
        let mut sampler = kind
            .create(1, Randomization::Seeded, (8, 8), unlimited, None)
            .unwrap();
        let m = TIMED_PATTERN_SIZE;
        for replication in [0, 5, 1000] {
            let values = replication_values(sampler.as_mut(), (7, 7), replication, m, 0);
            assert!(
                stratified(&values, m as usize),
                "{kind:?} {replication}: {values:?}"
            );
        }
    }
}

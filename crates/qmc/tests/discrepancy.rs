//! Tests of `qmc::discrepancy` against scipy 1.17 golden values, published
//! reference designs, and brute-force star discrepancies.

use qmc::PointSet;
use qmc::discrepancy::{
    L2Discrepancy, centered_l2_discrepancy, flatten_rows, gather_points, l2_discrepancy,
    l2_star_discrepancy, mixture_l2_discrepancy, point_set_l2_discrepancy,
    point_set_star_discrepancy, star_discrepancy, wrap_around_l2_discrepancy,
};

mod golden {
    include!("golden/discrepancy.rs");
}

/// Agreement asked for with scipy once its conventions are undone.
const SCIPY_TOLERANCE: f64 = 1e-10;

#[test]
fn matches_scipy_golden_values() {
    for case in golden::DISCREPANCY_CASES {
        let dims = case.dimensions;
        let centered = centered_l2_discrepancy(case.points, dims).unwrap();
        let wrap_around = wrap_around_l2_discrepancy(case.points, dims).unwrap();
        let mixture = mixture_l2_discrepancy(case.points, dims).unwrap();
        let star = l2_star_discrepancy(case.points, dims).unwrap();
        for (label, ours, scipy_squared) in [
            ("CD", centered, case.centered_squared),
            ("WD", wrap_around, case.wrap_around_squared),
            ("MD", mixture, case.mixture_squared),
            ("L2-star", star, case.l2_star * case.l2_star),
        ] {
            let scipy_root = scipy_squared.sqrt();
            assert!(
                (ours - scipy_root).abs() <= SCIPY_TOLERANCE,
                "{} {label}: ours {ours}, scipy (root) {scipy_root}",
                case.name
            );
            assert!(
                (ours * ours - scipy_squared).abs() <= SCIPY_TOLERANCE,
                "{} {label}: ours squared {}, scipy {scipy_squared}",
                case.name,
                ours * ours
            );
        }
        assert!(
            (star - case.l2_star).abs() <= SCIPY_TOLERANCE,
            "{}",
            case.name
        );
    }
}

/// Fang et al. 2006 six-point designs, given as levels 1..=6 mapped to (2k−1)/12.
fn fang_design(levels: &[[u32; 2]]) -> Vec<f64> {
    levels
        .iter()
        .flat_map(|row| row.iter().map(|&level| (2.0 * level as f64 - 1.0) / 12.0))
        .collect()
}

#[test]
fn fang_six_point_designs() {
    let first = fang_design(&[[1, 3], [2, 6], [3, 2], [4, 5], [5, 1], [6, 4]]);
    let second = fang_design(&[[1, 5], [2, 4], [3, 3], [4, 2], [5, 1], [6, 6]]);
    let first_squared = centered_l2_discrepancy(&first, 2).unwrap().powi(2);
    let second_squared = centered_l2_discrepancy(&second, 2).unwrap().powi(2);
    assert!((first_squared - 0.0081).abs() <= 1e-4, "{first_squared}");
    assert!((second_squared - 0.0105).abs() <= 1e-4, "{second_squared}");
    // scipy's docstring example is the first design (scaled from [0.5, 6.5]).
    assert!((first_squared - 0.008142039609053464).abs() <= 1e-14);
}

#[test]
fn zhou_seven_by_six_two_level_design() {
    // Zhou, Fang, Ning 2013, Example 4: levels 1, 2 mapped to 1/4, 3/4; the
    // published values (MD 2.5000, WD 1.3680, CD 0.3172) are squared discrepancies.
    let levels: [[u32; 6]; 7] = [
        [2, 1, 1, 2, 2, 2],
        [1, 2, 2, 2, 2, 2],
        [2, 1, 1, 1, 1, 1],
        [1, 1, 1, 1, 2, 2],
        [1, 2, 2, 2, 1, 1],
        [2, 2, 2, 2, 1, 1],
        [2, 2, 2, 1, 2, 2],
    ];
    let points: Vec<f64> = levels
        .iter()
        .flatten()
        .map(|&level| (2.0 * level as f64 - 1.0) / 4.0)
        .collect();
    let mixture = mixture_l2_discrepancy(&points, 6).unwrap();
    let wrap_around = wrap_around_l2_discrepancy(&points, 6).unwrap();
    let centered = centered_l2_discrepancy(&points, 6).unwrap();
    assert!((mixture.powi(2) - 2.5000).abs() <= 1e-4, "{mixture}");
    assert!(
        (wrap_around.powi(2) - 1.3680).abs() <= 1e-4,
        "{wrap_around}"
    );
    assert!((centered.powi(2) - 0.3172).abs() <= 1e-4, "{centered}");
}

#[test]
fn l2_star_of_the_point_all_ones() {
    for dims in 1..=64 {
        let value = l2_star_discrepancy(&vec![1.0; dims], dims).unwrap();
        let expected = 3f64.powi(-(dims as i32)).sqrt();
        assert!(
            (value - expected).abs() <= 1e-12 * expected,
            "d={dims}: {value} vs {expected}"
        );
    }
}

#[test]
fn wrap_around_is_shift_invariant() {
    let points: Vec<f64> = (0..34)
        .flat_map(|i| [i as f64 / 34.0, (i * 21 % 34) as f64 / 34.0])
        .collect();
    let shifted: Vec<f64> = points
        .iter()
        .enumerate()
        .map(|(k, &x)| (x + [0.3141, 0.6180][k % 2]) % 1.0)
        .collect();
    let before = wrap_around_l2_discrepancy(&points, 2).unwrap();
    let after = wrap_around_l2_discrepancy(&shifted, 2).unwrap();
    assert!((before - after).abs() < 1e-12, "{before} vs {after}");
}

/// Exact star discrepancy by direct counting at every critical corner (O(n^(d+1))).
fn brute_force_star(points: &[f64], dims: usize) -> f64 {
    let count = points.len() / dims;
    let mut axes: Vec<Vec<f64>> = (0..dims)
        .map(|k| {
            let mut axis: Vec<f64> = points.iter().skip(k).step_by(dims).copied().collect();
            axis.push(1.0);
            axis
        })
        .collect();
    for axis in &mut axes {
        axis.sort_by(f64::total_cmp);
        axis.dedup();
    }
    let mut corners: Vec<Vec<f64>> = vec![vec![]];
    for axis in &axes {
        corners = corners
            .iter()
            .flat_map(|prefix| {
                axis.iter().map(move |&t| {
                    let mut corner = prefix.clone();
                    corner.push(t);
                    corner
                })
            })
            .collect();
    }
    let mut best: f64 = 0.0;
    for corner in &corners {
        let volume: f64 = corner.iter().product();
        let mut closed = 0;
        let mut open = 0;
        for point in points.chunks_exact(dims) {
            if point.iter().zip(corner).all(|(x, t)| x <= t) {
                closed += 1;
            }
            if point.iter().zip(corner).all(|(x, t)| x < t) {
                open += 1;
            }
        }
        best = best
            .max(closed as f64 / count as f64 - volume)
            .max(volume - open as f64 / count as f64);
    }
    best
}

fn radical_inverse_base2(index: u64) -> f64 {
    index.reverse_bits() as f64 * (1.0 / 18_446_744_073_709_551_616.0)
}

/// Deterministic test points from SplitMix64 (no dependence on other modules).
fn pseudo_random_points(seed: u64, count: usize) -> Vec<f64> {
    (0..count as u64)
        .map(|i| qmc::hash::to_unit_f64(qmc::hash::hash2(seed, i)))
        .collect()
}

#[test]
fn van_der_corput_star_discrepancy() {
    // The first 2^k points are {i / 2^k}: D* = 1 / 2^k.
    for k in 0..8 {
        let count = 1u64 << k;
        let points: Vec<f64> = (0..count).map(radical_inverse_base2).collect();
        let value = star_discrepancy(&points, 1).unwrap();
        assert!(
            (value - 1.0 / count as f64).abs() < 1e-15,
            "n={count}: {value}"
        );
    }
    // Other n: against direct counting.
    for count in 1..40u64 {
        let points: Vec<f64> = (0..count).map(radical_inverse_base2).collect();
        let value = star_discrepancy(&points, 1).unwrap();
        assert!((value - brute_force_star(&points, 1)).abs() < 1e-15);
    }
    // n = 3: {0, 1/4, 1/2}; the worst box is [0, 1/2], holding all points: 1 - 1/2.
    let three: Vec<f64> = (0..3).map(radical_inverse_base2).collect();
    assert!((star_discrepancy(&three, 1).unwrap() - 0.5).abs() < 1e-15);
}

fn hammersley_2d(count: u64) -> Vec<f64> {
    (0..count)
        .flat_map(|i| [i as f64 / count as f64, radical_inverse_base2(i)])
        .collect()
}

#[test]
fn hammersley_star_discrepancy_against_brute_force_and_grid() {
    // Grid corners (2a + 1) / (2 G) never coincide with a coordinate here; the
    // grid supremum over half-open boxes is a lower bound of D* and, by moving
    // each critical corner by less than 1/G per axis, within 2/G of it.
    const GRID: usize = 256;
    let mut grid: Vec<f64> = (0..GRID)
        .map(|a| (2 * a + 1) as f64 / (2 * GRID) as f64)
        .collect();
    grid.push(1.0);
    for count in [1u64, 2, 3, 5, 8, 13, 16, 32] {
        let points = hammersley_2d(count);
        let exact = star_discrepancy(&points, 2).unwrap();
        assert!(
            (exact - brute_force_star(&points, 2)).abs() < 1e-15,
            "n={count}"
        );
        let mut grid_sup: f64 = 0.0;
        for &t1 in &grid {
            for &t2 in &grid {
                let inside = points
                    .chunks_exact(2)
                    .filter(|p| p[0] < t1 && p[1] < t2)
                    .count();
                grid_sup = grid_sup.max((inside as f64 / count as f64 - t1 * t2).abs());
            }
        }
        assert!(grid_sup <= exact + 1e-15, "n={count}: {grid_sup} > {exact}");
        assert!(
            grid_sup >= exact - 2.0 / GRID as f64,
            "n={count}: {grid_sup} << {exact}"
        );
    }
}

#[test]
fn star_discrepancy_of_random_and_tied_points_matches_brute_force() {
    for seed in 0..20u64 {
        for dims in [1usize, 2] {
            let count = 1 + (seed as usize * 7) % 30;
            let mut points = pseudo_random_points(seed, count * dims);
            if seed % 2 == 1 {
                // Coarse values force ties and exact zeros.
                for value in &mut points {
                    *value = (*value * 5.0).floor() / 5.0;
                }
            }
            let exact = star_discrepancy(&points, dims).unwrap();
            let brute = brute_force_star(&points, dims);
            assert!(
                (exact - brute).abs() < 1e-15,
                "seed {seed} d={dims}: {exact} vs {brute}"
            );
        }
    }
    // Points at the closed end, 1, count in closed boxes only.
    let ones = [1.0, 1.0, 0.5, 1.0];
    assert!((star_discrepancy(&ones, 2).unwrap() - brute_force_star(&ones, 2)).abs() < 1e-15);
}

/// A minimal 2-D Hammersley point set for the `PointSet` helpers.
struct TestHammersley {
    count: u64,
}

impl PointSet for TestHammersley {
    fn dimensions(&self) -> usize {
        2
    }
    fn len(&self) -> Option<u64> {
        Some(self.count)
    }
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        if dimension == 0 {
            index as f64 / self.count as f64
        } else {
            radical_inverse_base2(index)
        }
    }
}

#[test]
fn point_set_helpers_gather_the_requested_range() {
    let set = TestHammersley { count: 16 };
    let gathered = gather_points(&set, 4, 8, 2).unwrap();
    assert_eq!(gathered.len(), 16);
    assert_eq!(gathered[0], 0.25);
    assert_eq!(gathered[1], radical_inverse_base2(4));
    let full = hammersley_2d(16);
    assert_eq!(
        point_set_star_discrepancy(&set, 0, 16, 2).unwrap(),
        star_discrepancy(&full, 2).unwrap()
    );
    assert_eq!(
        point_set_l2_discrepancy(L2Discrepancy::Mixture, &set, 0, 16, 2).unwrap(),
        mixture_l2_discrepancy(&full, 2).unwrap()
    );
    assert!(gather_points(&set, 10, 8, 2).is_err());
    assert!(gather_points(&set, 0, 8, 3).is_err());
    assert!(point_set_star_discrepancy(&set, 0, 8, 3).is_err());

    let rows: Vec<Vec<f64>> = full.chunks(2).map(<[f64]>::to_vec).collect();
    let (flat, dims) = flatten_rows(&rows).unwrap();
    assert_eq!((flat.as_slice(), dims), (full.as_slice(), 2));
}

#[test]
fn l2_kinds_dispatch_and_stay_fast_for_1024_points_in_4_dimensions() {
    let points = pseudo_random_points(7, 1024 * 4);
    let start = std::time::Instant::now();
    let values: Vec<f64> = [
        L2Discrepancy::Star,
        L2Discrepancy::Centered,
        L2Discrepancy::WrapAround,
        L2Discrepancy::Mixture,
    ]
    .iter()
    .map(|&kind| l2_discrepancy(kind, &points, 4).unwrap())
    .collect();
    let elapsed = start.elapsed();
    println!("four L2 discrepancies of 1024 points in 4 dims: {elapsed:?}");
    assert_eq!(values[0], l2_star_discrepancy(&points, 4).unwrap());
    assert_eq!(values[3], mixture_l2_discrepancy(&points, 4).unwrap());
    // Generous bound (the machine is shared); the target is ~50 ms per measure.
    assert!(elapsed.as_secs_f64() < 2.0, "{elapsed:?}");
}

/// For a rank-1 lattice, WD² = (4/3)^s · e²(z) with the Korobov-space (P₂)
/// squared worst-case error for product weights γ_j = 3/(8π²) (see
/// docs/qmc.md, "Reference values"): since 3/2 − x(1 − x) = 4/3 · (1 + γ ω(x)) with
/// ω(x) = 2π²(x² − x + 1/6). This is scipy's squared "WD" convention.
#[test]
fn wrap_around_of_a_lattice_is_its_scaled_p2_error() {
    let weight = 3.0 / (8.0 * std::f64::consts::PI.powi(2));
    let omega = |x: f64| 2.0 * std::f64::consts::PI.powi(2) * (x * x - x + 1.0 / 6.0);
    for (count, generator) in [
        (34u64, vec![1u64, 21]),
        (97, vec![1, 19, 33]),
        (7, vec![1, 3]),
    ] {
        let dims = generator.len();
        let points: Vec<f64> = (0..count)
            .flat_map(|k| {
                generator
                    .iter()
                    .map(move |&z| (k * z % count) as f64 / count as f64)
            })
            .collect();
        let squared_error = -1.0
            + points
                .chunks_exact(dims)
                .map(|p| p.iter().map(|&x| 1.0 + weight * omega(x)).product::<f64>())
                .sum::<f64>()
                / count as f64;
        let wrap_around = wrap_around_l2_discrepancy(&points, dims).unwrap();
        let expected = (4.0f64 / 3.0).powi(dims as i32) * squared_error;
        assert!(
            (wrap_around.powi(2) - expected).abs() < 1e-13,
            "N={count}: {} vs {expected}",
            wrap_around.powi(2)
        );
    }
}

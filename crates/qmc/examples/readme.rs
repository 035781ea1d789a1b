//! The example of `docs/qmc.md`, kept compiling by `cargo test`.

use qmc::PointSet;
use qmc::digital_scramble::{DigitalOrder, DigitalScramble, Scrambled};
use qmc::halton::{Halton, HaltonScramble, PixelEnumeration};
use qmc::lattice_table::lqmc_lattice_entry;
use qmc::sobol::Sobol;

fn main() -> Result<(), qmc::PointSetError> {
    // Faure-permuted Halton, and the 3rd sample of pixel (5, 2) of a 640x480 image.
    let halton = Halton::new(16, HaltonScramble::Faure, 0)?;
    let pixels = PixelEnumeration::new(640, 480)?;
    let index = pixels.sample_index(&halton, (5, 2), 3)?;
    let x = halton.sample(index, 0) * pixels.scale.0 as f64; // in [5, 6)

    // Owen-scrambled Sobol (hash-based, Burley 2020).
    let sobol = Scrambled::new(
        Sobol::new(8, DigitalOrder::Natural)?,
        DigitalScramble::HashOwen,
        42,
    );
    let u = sobol.sample(1000, 7);

    // The LQMC lattice for N = 313 points in 12 dimensions, and the
    // Cranley–Patterson shift that makes a seed point a member of the lattice.
    let entry = lqmc_lattice_entry(313, 12)?;
    let closest = entry.closest_point_search().closest_point(&[0.3; 12])?;
    println!("{x} {u} shift {:?}", closest.shift);
    Ok(())
}

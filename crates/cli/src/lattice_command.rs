//! `lqmc lattice`: component-by-component construction of a rank-1 lattice.

/// Prints a line to stdout, ignoring a closed pipe (e.g. `| head`): results
/// are already written to files or complete, so there is nothing to report.
macro_rules! say {
    ($($argument:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($argument)*);
    }};
}

use crate::error::{CliError, usage};
use crate::json::Json;
use clap::Args;
use qmc::cbc::{ProductWeights, cbc};

/// Arguments of `lqmc lattice`.
#[derive(Args, Debug)]
pub struct LatticeArgs {
    /// Number of lattice points N (at least 2).
    #[arg(long)]
    pub points: u64,
    /// Dimensions S (at least 1).
    #[arg(long)]
    pub dims: usize,
    /// Product weights γ_j: one value for every dimension or S comma-separated
    /// values (default 1/S, as the LQMC authors used).
    #[arg(long, value_delimiter = ',')]
    pub weights: Vec<f64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// Runs `lqmc lattice`.
pub fn run(args: &LatticeArgs) -> Result<(), CliError> {
    if args.points < 2 {
        return Err(usage(format!(
            "--points must be at least 2 (N >= 2), got {}",
            args.points
        )));
    }
    if args.dims == 0 {
        return Err(usage("--dims must be at least 1"));
    }
    let weights = match args.weights.as_slice() {
        [] => ProductWeights::lqmc_default(args.dims),
        [single] => ProductWeights::Constant(*single),
        many if many.len() == args.dims => ProductWeights::PerDimension(many.to_vec()),
        many => {
            return Err(usage(format!(
                "--weights needs 1 or {} values, got {}",
                args.dims,
                many.len()
            )));
        }
    };
    weights.validate(args.dims)?;
    let result = cbc(args.points, args.dims, &weights)?;
    let generator = result.lattice.generator();
    let squared_error = result.squared_error();
    if args.json {
        let json = Json::object(vec![
            ("points", Json::Integer(args.points)),
            ("dims", Json::Integer(args.dims as u64)),
            ("generator", Json::integers(generator)),
            ("e2", Json::Number(squared_error)),
        ]);
        say!("{}", json.render());
    } else {
        let generator: Vec<String> = generator.iter().map(u64::to_string).collect();
        say!("points: {}", args.points);
        say!("dims: {}", args.dims);
        say!("generator: {}", generator.join(","));
        say!("e2: {squared_error:?}");
    }
    Ok(())
}

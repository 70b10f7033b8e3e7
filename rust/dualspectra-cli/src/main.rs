//! `dualspectra`: the command-line interface. One subcommand per file in `commands/`,
//! each `commands::<name>::run(args) -> Result<(), CliError>`; errors are printed by
//! [`error::report`] as one line and mapped to an exit code.

/// `println!` that ends the program quietly on a closed pipe ([`output::print_line`]).
macro_rules! outln {
    () => {
        $crate::output::print_line(format_args!(""))
    };
    ($($arg:tt)*) => {
        $crate::output::print_line(format_args!($($arg)*))
    };
}

mod commands;
mod error;
mod input;
mod output;
mod render;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Partial shape localization by multi-metric Hamiltonian spectra matching.
#[derive(Debug, Parser)]
#[command(name = "dualspectra", version, about, propagate_version = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// The k smallest Laplace-Beltrami eigenvalues of a mesh (Dirichlet on its boundary).
    Spectrum(commands::spectrum::Args),
    /// Gaussian curvature per vertex (angle defect) and its one-ring mean.
    Curvature(commands::curvature::Args),
    /// Find the region of FULL that PARTIAL (a deformed, cut copy) corresponds to.
    Localize(commands::localize::Args),
    /// Rank full shapes for a partial: which one is it a part of, and where.
    Search(commands::search::Args),
    /// Prepare a full shape once and save it (.dsprep) for later searches.
    Prepare(commands::prepare::Args),
    /// Describe a library of full shapes once (.dsscreen) for the search's screen.
    Index(commands::index::Args),
    /// Run and score the localizer on a dataset in the SHREC'16 layout.
    Bench(commands::bench::Args),
    /// Dual ShapeDNA distances between shapes and their 2-D MDS embedding.
    Similarity(commands::similarity::Args),
    /// Localize a procedural partial shape (no data needed), score it and draw it (demo.png).
    Demo(commands::demo::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Spectrum(args) => commands::spectrum::run(args),
        Command::Curvature(args) => commands::curvature::run(args),
        Command::Localize(args) => commands::localize::run(args),
        Command::Search(args) => commands::search::run(args),
        Command::Prepare(args) => commands::prepare::run(args),
        Command::Index(args) => commands::index::run(args),
        Command::Bench(args) => commands::bench::run(args),
        Command::Similarity(args) => commands::similarity::run(args),
        Command::Demo(args) => commands::demo::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            error::report(&e);
            e.exit_code()
        }
    }
}

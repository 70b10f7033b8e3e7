//! `dualspectra`: the command-line interface. One subcommand per file in `commands/`,
//! each `commands::<name>::run(args) -> Result<(), CliError>`; errors are printed by
//! [`error::report`] as one line and mapped to an exit code.

mod commands;
mod error;
mod input;
mod output;

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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Spectrum(args) => commands::spectrum::run(args),
        Command::Curvature(args) => commands::curvature::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            error::report(&e);
            e.exit_code()
        }
    }
}

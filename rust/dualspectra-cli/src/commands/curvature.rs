//! `dualspectra curvature MESH [--json OUT]`
//!
//! Per vertex: the angle-defect Gaussian curvature $K_i = (2\pi - \sum\theta)/a_i$
//! ($\pi - \sum\theta$ on the boundary, $a_i$ the lumped area) and its one-ring mean, the
//! curvature the scale-invariant metric uses (docs/algorithm.md, "Discrete operators"), both
//! from `dualspectra::shape::Shape`. Writes
//! `{"gaussian_curvature": [...], "smoothed": [...], "warnings": [...]}` to `OUT` with
//! `--json`, to standard output otherwise. Arrays follow the file's vertex
//! numbering; a vertex that reading dropped (isolated with `--drop-isolated`, or the tip
//! of a removed two-sided flap) gets `null`, and `"warnings"` says how many were dropped
//! and why, and how many non-manifold vertices were split (a split vertex gets its first
//! copy's values); each warning is also printed on standard error.

use crate::error::CliError;
use crate::input::{read_input_mesh, read_warnings, to_file_vertices};
use crate::output::{print_stdout, to_json_line, write_text};
use dualspectra::shape::Shape;
use serde::Serialize;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file: .off, .obj or .ply (ASCII or binary).
    #[arg(value_name = "MESH")]
    pub mesh: PathBuf,
    /// Write the JSON to this file instead of standard output.
    #[arg(long, value_name = "OUT")]
    pub json: Option<PathBuf>,
    /// Drop vertices that belong to no face instead of failing (they get null).
    #[arg(long)]
    pub drop_isolated: bool,
}

#[derive(Serialize)]
struct Output {
    gaussian_curvature: Vec<Option<f64>>,
    smoothed: Vec<Option<f64>>,
    /// What reading dropped (the reason for every `null`) or split; empty if nothing.
    warnings: Vec<String>,
}

pub fn run(args: Args) -> Result<(), CliError> {
    let (mesh, report) = read_input_mesh(&args.mesh, args.drop_isolated)?;
    let warnings = read_warnings(&report);
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.mesh.display());
    }
    let shape = Shape::new(mesh);
    let output = Output {
        gaussian_curvature: to_file_vertices(shape.gaussian_curvature(), &report),
        smoothed: to_file_vertices(shape.smoothed_curvature(), &report),
        warnings,
    };
    let text = to_json_line(&output)?;
    match &args.json {
        Some(out) => write_text(out, &text),
        None => print_stdout(&text),
    }
}

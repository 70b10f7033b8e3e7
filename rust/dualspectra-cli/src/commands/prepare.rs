//! `dualspectra prepare FULL [-o OUT.dsprep] [localize options]`
//!
//! Prepares a full shape once (`dualspectra::Localizer::new`: its scale, optimisation mesh,
//! descriptors and starts) and saves it (`Localizer::save`, format in
//! `dualspectra::localizer::persist`), so that `search` and later runs load it instead of
//! preparing it again. The file keeps the options (they are the ones every search on it
//! uses) and the file's vertex numbering (results name FULL's vertices). `OUT` defaults to
//! FULL with the extension `.dsprep`.

use super::localize::{progress_bar, LocalizeOptions};
use crate::error::CliError;
use crate::input::read_input_mesh;
use crate::output::check_output_path;
use dualspectra::localizer::EXTENSION;
use dualspectra::localizer::HostNumbering;
use dualspectra::mesh::io::ReadReport;
use dualspectra::{Localizer, Options, Progress, TriMesh};
use std::path::{Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// The full shape: .off, .obj or .ply.
    #[arg(value_name = "FULL")]
    pub full: PathBuf,
    /// Where to write the prepared shape (default: FULL with the extension .dsprep).
    #[arg(short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub options: LocalizeOptions,
    /// Drop vertices that belong to no face instead of failing (results still name the
    /// file's vertices).
    #[arg(long)]
    pub drop_isolated: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The file's vertex numbering when reading changed it (dropped or split vertices).
pub fn host_numbering(mesh: &TriMesh, report: &ReadReport) -> Option<HostNumbering> {
    let identity = report.file_vertices == mesh.n_vertices() && report.kept_vertices.iter().enumerate().all(|(i, &k)| k as usize == i);
    (!identity).then(|| HostNumbering { n_host_vertices: report.file_vertices, kept: report.kept_vertices.clone() })
}

/// Read a mesh file and prepare it, keeping the file's vertex numbering.
pub fn prepare_file(path: &Path, options: &Options, drop_isolated: bool, progress: &Progress) -> Result<(Localizer, TriMesh), CliError> {
    let (mesh, report) = read_input_mesh(path, drop_isolated)?;
    let mut localizer = Localizer::with_progress(&mesh, options, progress)?;
    localizer.set_host_numbering(host_numbering(&mesh, &report))?;
    if let Some(w) = crate::commands::localize::repair_warning(&path.display().to_string(), &report) {
        eprintln!("warning: {w}");
    }
    Ok((localizer, mesh))
}

pub fn run(args: Args) -> Result<(), CliError> {
    let options = args.options.to_options()?;
    let output = args.output.clone().unwrap_or_else(|| args.full.with_extension(EXTENSION));
    check_output_path(&output, &[&args.full])?;
    let (bar, progress) = progress_bar(args.quiet, "prepare");
    let prepared = prepare_file(&args.full, &options, args.drop_isolated, &progress);
    bar.finish_and_clear();
    let (localizer, _) = prepared?;
    for w in localizer.warnings() {
        eprintln!("warning: {w}");
    }
    localizer.save(&output).map_err(|e| match e {
        dualspectra::Error::Io { path, source } => CliError::Output { path, source },
        other => CliError::Core(other),
    })?;
    let bytes = std::fs::metadata(&output).map(|m| m.len()).unwrap_or(0);
    outln!(
        "prepared {} ({} vertices, {} optimisation vertices) in {:.2} s: {} ({:.1} MB)",
        args.full.display(),
        localizer.n_vertices(),
        localizer.optimisation_vertices(),
        localizer.preparation_seconds(),
        output.display(),
        bytes as f64 / 1e6
    );
    Ok(())
}

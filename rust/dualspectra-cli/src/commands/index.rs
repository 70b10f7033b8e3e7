//! `dualspectra index FULL... -o LIBRARY.dsscreen`
//!
//! Describes a library of full shapes once for `search`'s screen (`dualspectra::Screen`:
//! a few SHOT descriptors per shape, about 64 KB each) and saves it, so that `search PARTIAL
//! LIBRARY.dsscreen` ranks the whole library in a fraction of a second and localizes only the
//! most promising shapes. A FULL is a mesh (.off, .obj, .ply), a prepared shape (.dsprep) or
//! a folder of these; the file keeps each shape's path relative to its own folder, and
//! `search` opens the shortlisted shapes from there.

use super::localize::progress_bar;
use super::search::{describe_for_screen, expand_fulls};
use crate::error::CliError;
use crate::output::check_output_path;
use dualspectra::search::SCREEN_EXTENSION;
use dualspectra::Screen;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Full shapes: meshes (.off, .obj, .ply), prepared shapes (.dsprep), or folders of them.
    #[arg(value_name = "FULL", num_args = 1.., required = true)]
    pub fulls: Vec<PathBuf>,
    /// Where to write the library's screen (extension .dsscreen).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Drop vertices that belong to no face instead of failing.
    #[arg(long)]
    pub drop_isolated: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// `path` as the screen file at `output` stores it: relative to `output`'s folder when it is
/// inside it, else absolute.
fn stored_path(path: &Path, output: &Path) -> Result<String, CliError> {
    let absolute = |p: &Path| std::path::absolute(p).map_err(|source| CliError::Core(dualspectra::Error::Io { path: p.to_path_buf(), source }));
    let file = absolute(path)?;
    let folder = absolute(output)?.parent().map(Path::to_path_buf).unwrap_or_default();
    let stored = file.strip_prefix(&folder).map(Path::to_path_buf).unwrap_or(file);
    stored.to_str().map(str::to_string).ok_or_else(|| CliError::Usage(format!("{}: the path is not UTF-8", path.display())))
}

pub fn run(args: Args) -> Result<(), CliError> {
    if !args.output.extension().is_some_and(|e| e.eq_ignore_ascii_case(SCREEN_EXTENSION)) {
        return Err(CliError::Usage(format!("{}: the output's extension must be .{SCREEN_EXTENSION}", args.output.display())));
    }
    let paths = expand_fulls(&args.fulls)?;
    let inputs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    check_output_path(&args.output, &inputs)?;
    let t = Instant::now();
    let (bar, progress) = progress_bar(args.quiet, "index");
    let mut screen = describe_for_screen(&paths, args.drop_isolated, &progress)?;
    bar.finish_and_clear();
    let labels = paths.iter().map(|p| stored_path(p, &args.output)).collect::<Result<Vec<_>, _>>()?;
    screen.set_labels(labels)?;
    screen.save(&args.output)?;
    let (per_model, basis) = screen.bytes();
    outln!(
        "{}: {} shapes described in {:.1} s ({} bytes per shape, {} for the basis)",
        args.output.display(),
        screen.len(),
        t.elapsed().as_secs_f64(),
        per_model,
        basis
    );
    Ok(())
}

/// The shapes of a screen file, as paths (stored relative to its folder).
pub fn screen_paths(screen: &Screen, file: &Path) -> Vec<PathBuf> {
    let folder = file.parent().unwrap_or(Path::new(""));
    screen.labels().iter().map(|l| folder.join(l)).collect()
}

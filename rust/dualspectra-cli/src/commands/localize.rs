//! `dualspectra localize FULL PARTIAL [--mode dual|lbo|si] [--k K] [--alpha A] [--plane-cuts N] [--scale S]
//! [--json OUT] [--ply OUT] [--png OUT]`
//!
//! Finds the region of `FULL` that `PARTIAL` (a deformed, cut copy) corresponds to, with
//! `dualspectra::localize` (docs/algorithm.md, whole pipeline). Writes the result as JSON
//! (`region`: 0-based vertex indices of FULL; `confidence`; `scale`; `cost`; `seconds`; `mode`;
//! `optimisation_vertices`; `n_starts`; `timings`; the eigenvalues at the optimum and the partial's target spectra) to `OUT`
//! with `--json`, else to standard output; `--ply` writes FULL with the region coloured
//! (vertex colours), `--png` a picture of FULL from the front and the back with the region
//! in red. A progress bar runs on standard error.

use crate::error::CliError;
use crate::input::read_input_mesh;
use crate::output::{check_output_path, print_stdout, to_json_line, write_text};
use crate::render::{region_picture, write_png};
use dualspectra::localizer::{OptionKind, OPTIONS, REMOVED_OPTIONS};
use dualspectra::{Localization, Localizer, Options, Progress, Timings, TriMesh};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The localizer's options shared by `localize` and `bench`: one flag per entry of the
/// library's option table (`--name` with `-` for `_`), help, range and default from it. The
/// library's removed options stay hidden flags, so that giving one is the library's error
/// saying it was removed (not clap's "unexpected argument").
#[derive(Debug, Clone, Default)]
pub struct LocalizeOptions {
    /// The flags given, as (option name, text).
    given: Vec<(&'static str, String)>,
}

/// Older spellings kept as aliases of a flag.
const ALIASES: &[(&str, &str)] = &[("max_iterations", "iterations")];

impl clap::FromArgMatches for LocalizeOptions {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut o = LocalizeOptions::default();
        o.update_from_arg_matches(matches)?;
        Ok(o)
    }
    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        let names = OPTIONS.iter().map(|s| s.name).chain(REMOVED_OPTIONS.iter().map(|r| r.0));
        for name in names {
            if let Some(v) = matches.get_one::<String>(name) {
                self.given.push((name, v.clone()));
            }
        }
        Ok(())
    }
}

impl clap::Args for LocalizeOptions {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        let defaults = serde_json::to_value(Options::default()).unwrap_or_default();
        let cmd = REMOVED_OPTIONS.iter().fold(cmd, |cmd, &(name, ..)| {
            cmd.arg(clap::Arg::new(name).long(name.replace('_', "-")).hide(true).allow_negative_numbers(true))
        });
        OPTIONS.iter().fold(cmd, |cmd, spec| {
            let default = defaults[spec.name].to_string().trim_matches('"').to_string();
            let range = match spec.kind {
                OptionKind::Int { min, max } => format!("{min}..={max}"),
                OptionKind::Float { min, max } => format!("{min}..={max}"),
                OptionKind::Choice { choices } => choices.join(", "),
                OptionKind::ChoiceOrPositive { choices, .. } => format!("{} or a positive number", choices.join(", ")),
            };
            let mut arg = clap::Arg::new(spec.name)
                .long(spec.name.replace('_', "-"))
                .value_name(spec.name.to_ascii_uppercase())
                .allow_negative_numbers(true)
                .help(format!("{} [{range}; default: {default}]", spec.doc));
            if let OptionKind::Choice { choices } = spec.kind {
                arg = arg.value_parser(clap::builder::PossibleValuesParser::new(choices.iter().copied()));
            }
            for &(name, alias) in ALIASES {
                if name == spec.name {
                    arg = arg.visible_alias(alias);
                }
            }
            cmd.arg(arg)
        })
    }
    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl LocalizeOptions {
    /// The names of the options given as flags.
    pub fn given_names(&self) -> Vec<&'static str> {
        self.given.iter().map(|(name, _)| *name).collect()
    }

    /// The library options, checked (a bad value is a usage error naming the flag's option).
    pub fn to_options(&self) -> Result<Options, CliError> {
        self.to_options_from(Options::default())
    }

    /// The flags given, set on `base` (a command's own defaults), checked.
    pub fn to_options_from(&self, base: Options) -> Result<Options, CliError> {
        let mut o = base;
        for (name, text) in &self.given {
            o.set_str(name, text).map_err(|e| CliError::Usage(format!("--{}: {}", name.replace('_', "-"), core_message(&e))))?;
        }
        o.validate().map_err(|e| CliError::Usage(core_message(&e)))?;
        Ok(o)
    }
}

/// The message of a core error without its "invalid argument: " prefix.
fn core_message(e: &dualspectra::Error) -> String {
    match e {
        dualspectra::Error::InvalidArgument(m) => m.clone(),
        other => other.to_string(),
    }
}

#[derive(Debug, clap::Args)]
pub struct Args {
    /// The full shape: .off, .obj or .ply.
    #[arg(value_name = "FULL")]
    pub full: PathBuf,
    /// The partial shape (a deformed, cut copy of part of FULL).
    #[arg(value_name = "PARTIAL")]
    pub partial: PathBuf,
    #[command(flatten)]
    pub options: LocalizeOptions,
    /// Write the result JSON to this file (otherwise it goes to standard output).
    #[arg(long, value_name = "OUT")]
    pub json: Option<PathBuf>,
    /// Write FULL as PLY with the region coloured (red) and the rest grey.
    #[arg(long, value_name = "OUT")]
    pub ply: Option<PathBuf>,
    /// Write a PNG picture of FULL, front and back (along its principal axes), with the
    /// region in red.
    #[arg(long, value_name = "OUT")]
    pub png: Option<PathBuf>,
    /// Drop vertices that belong to no face instead of failing (indices then refer to the
    /// mesh after dropping).
    #[arg(long)]
    pub drop_isolated: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// The JSON written by `localize` (and per pair by `bench`).
#[derive(Debug, Serialize)]
pub struct Output<'a> {
    pub region: Vec<usize>,
    /// In [0, 1]: the estimated probability that the region overlaps the true one with
    /// IoU >= 0.5 ([`Localization::confidence`]).
    pub confidence: f64,
    /// The factor the partial's coordinates were multiplied by ([`Localization::scale`]: 1 with
    /// `--scale same`, the estimate with `--scale auto`).
    pub scale: f64,
    pub cost: f64,
    pub seconds: f64,
    /// Every option the localizer ran with.
    pub options: &'a Options,
    pub n_vertices_full: usize,
    pub n_vertices_partial: usize,
    /// Vertices of the optimisation mesh used ([`Localization::optimisation_vertices`]).
    pub optimisation_vertices: usize,
    pub n_starts: usize,
    pub selected_start: usize,
    pub timings: &'a Timings,
    pub eigenvalues_regular: &'a [f64],
    pub eigenvalues_si: &'a [f64],
    pub target_regular: &'a [f64],
    pub target_si: &'a [f64],
    pub warnings: &'a [String],
}

impl<'a> Output<'a> {
    pub fn new(
        loc: &'a Localization,
        options: &'a Options,
        seconds: f64,
        full: &TriMesh,
        partial: &TriMesh,
    ) -> Self {
        Output {
            region: region_indices(&loc.region),
            confidence: loc.confidence,
            scale: loc.scale,
            cost: loc.cost,
            seconds,
            options,
            n_vertices_full: full.n_vertices(),
            n_vertices_partial: partial.n_vertices(),
            optimisation_vertices: loc.optimisation_vertices,
            n_starts: loc.n_starts,
            selected_start: loc.selected_start,
            timings: &loc.timings,
            eigenvalues_regular: &loc.eigenvalues_regular,
            eigenvalues_si: &loc.eigenvalues_si,
            target_regular: &loc.target_regular,
            target_si: &loc.target_si,
            warnings: &loc.warnings,
        }
    }
}

/// 0-based indices of the `true` entries.
pub fn region_indices(mask: &[bool]) -> Vec<usize> {
    mask.iter()
        .enumerate()
        .filter(|(_, &b)| b)
        .map(|(i, _)| i)
        .collect()
}

/// Colours for a region: red inside, light grey outside.
pub fn region_colors(mask: &[bool]) -> Vec<[u8; 3]> {
    mask.iter()
        .map(|&b| if b { [220, 40, 40] } else { [190, 190, 190] })
        .collect()
}

/// A progress bar on standard error (hidden when `quiet` or stderr is not a terminal)
/// and a [`Progress`] that drives it with the stage name as message.
pub fn progress_bar(quiet: bool, prefix: &str) -> (ProgressBar, Progress) {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(1000)
    };
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix(prefix.to_string());
    let b = bar.clone();
    let progress = Progress::new(move |fraction, stage| {
        b.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
        b.set_message(stage.to_string());
        true
    });
    (bar, progress)
}

/// Run the localizer with a progress bar; returns the result and the wall-clock seconds.
/// A mesh the localizer cannot use (a closed partial, ...) is an error naming its file
/// (`full_path`, `partial_path`).
pub fn localize_with_bar(
    (full, full_path): (&TriMesh, &Path),
    (partial, partial_path): (&TriMesh, &Path),
    options: &Options,
    quiet: bool,
    prefix: &str,
) -> Result<(Localization, f64), CliError> {
    let (bar, progress) = progress_bar(quiet, prefix);
    let t = Instant::now();
    let result = Localizer::with_progress(full, options, &progress.sub(0.0, 0.05))
        .map_err(|e| e.in_file(full_path))
        .and_then(|localizer| localizer.locate(partial, &progress.sub(0.05, 1.0)).map_err(|e| e.in_file(partial_path)));
    bar.finish_and_clear();
    Ok((result?, t.elapsed().as_secs_f64()))
}

/// Write `mesh` as binary PLY with the region colours.
pub fn write_region_ply(path: &Path, mesh: &TriMesh, region: &[bool]) -> Result<(), CliError> {
    dualspectra::mesh::io::write_ply(path, mesh, Some(&region_colors(region)), true).map_err(|e| {
        match e {
            dualspectra::Error::Io { path, source } => CliError::Output { path, source },
            other => CliError::Core(other),
        }
    })
}

/// What reading repaired in a file, as a warning (`None` if nothing).
pub fn repair_warning(what: &str, report: &dualspectra::mesh::io::ReadReport) -> Option<String> {
    let kept = report.kept_vertices.len() - report.n_copies();
    let dropped = report.file_vertices - kept;
    let mut parts = Vec::new();
    if dropped > 0 || report.duplicate_faces_removed > 0 {
        parts.push(format!(
            "reading removed {} repeated triangle(s) and dropped {dropped} vertex(es)",
            report.duplicate_faces_removed
        ));
    }
    parts.extend(report.non_manifold_warning());
    (!parts.is_empty()).then(|| format!("{what}: {}; indices refer to the file's vertices", parts.join("; ")))
}

pub fn run(args: Args) -> Result<(), CliError> {
    let options = args.options.to_options()?;
    for out in [&args.json, &args.ply, &args.png].into_iter().flatten() {
        check_output_path(out, &[&args.full, &args.partial])?;
    }
    let (full, full_report) = read_input_mesh(&args.full, args.drop_isolated)?;
    let (partial, partial_report) = read_input_mesh(&args.partial, args.drop_isolated)?;
    let (mut loc, seconds) =
        localize_with_bar((&full, &args.full), (&partial, &args.partial), &options, args.quiet, "localize")?;
    let repairs: Vec<String> =
        [repair_warning("FULL", &full_report), repair_warning("PARTIAL", &partial_report)].into_iter().flatten().collect();
    loc.warnings.splice(0..0, repairs);
    let mut out = Output::new(&loc, &options, seconds, &full, &partial);
    // Indices of the file's vertices (reading may have dropped some, or split one into
    // copies: a vertex is in the region if any of its copies is).
    out.region = out.region.iter().map(|&i| full_report.kept_vertices[i] as usize).collect();
    out.region.sort_unstable();
    out.region.dedup();
    out.n_vertices_full = full_report.file_vertices;
    out.n_vertices_partial = partial_report.file_vertices;
    let text = to_json_line(&out)?;
    if let Some(path) = &args.ply {
        write_region_ply(path, &full, &loc.region)?;
    }
    if let Some(path) = &args.png {
        let name = args.full.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let caption = format!(
            "{name}: region {} of {} vertices, confidence {:.2}",
            out.region.len(),
            out.n_vertices_full,
            loc.confidence
        );
        write_png(path, &region_picture(&full, &loc.region, &caption)?)?;
    }
    for w in &loc.warnings {
        eprintln!("warning: {w}");
    }
    match &args.json {
        Some(path) => {
            write_text(path, &text)?;
            let scale = match options.scale {
                dualspectra::Scale::Auto => format!(", scale {:.4} (estimated)", loc.scale),
                _ => String::new(),
            };
            outln!(
                "region: {} of {} vertices, confidence {:.2}{scale}, cost {:.6e}, {:.2} s ({} starts)",
                out.region.len(),
                full_report.file_vertices,
                loc.confidence,
                loc.cost,
                seconds,
                loc.n_starts
            );
        }
        None => print_stdout(&text)?,
    }
    Ok(())
}

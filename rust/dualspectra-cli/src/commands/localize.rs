//! `dualspectra localize FULL PARTIAL [--mode dual|lbo|si] [--k K] [--alpha A] [--seed N]
//! [--json OUT] [--ply OUT]`
//!
//! Finds the region of `FULL` that `PARTIAL` (a deformed, cut copy) corresponds to, with
//! `dualspectra::localize` (ALGORITHM.md, whole pipeline). Writes the result as JSON
//! (`region`: 0-based vertex indices of FULL; `cost`; `seconds`; `mode`; `n_starts`;
//! `timings`; the eigenvalues at the optimum and the partial's target spectra) to `OUT`
//! with `--json`, else to standard output; `--ply` writes FULL with the region coloured
//! (vertex colours). A progress bar runs on standard error.

use crate::error::CliError;
use crate::input::read_input_mesh;
use crate::output::{to_json_line, write_text};
use dualspectra::localize::HessianModel;
use dualspectra::{Localization, Mode, Options, Progress, Selection, StartShape, Timings, TriMesh};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ModeArg {
    /// k regular + k scale-invariant eigenvalues (the paper's method).
    Dual,
    /// 2k Laplace-Beltrami eigenvalues only.
    Lbo,
    /// 2k scale-invariant eigenvalues only.
    Si,
}

impl From<ModeArg> for Mode {
    fn from(m: ModeArg) -> Mode {
        match m {
            ModeArg::Dual => Mode::Dual,
            ModeArg::Lbo => Mode::Lbo,
            ModeArg::Si => Mode::Si,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum HessianArg {
    /// Finite differences of the gradient (two eigensolves per inner step, as Manopt).
    FiniteDifference,
    /// Gauss-Newton model from the gradient's eigenpairs (no extra eigensolve).
    GaussNewton,
}

impl From<HessianArg> for HessianModel {
    fn from(h: HessianArg) -> HessianModel {
        match h {
            HessianArg::FiniteDifference => HessianModel::FiniteDifference,
            HessianArg::GaussNewton => HessianModel::GaussNewton,
        }
    }
}

/// A value among the library's names of a named option (`--starts`, `--selection`): help
/// lists `names`, the library parses the value.
fn library_names_parser<T, const N: usize>(
    names: [&'static str; N],
) -> impl clap::builder::TypedValueParser<Value = T>
where
    T: std::str::FromStr<Err = dualspectra::Error> + Clone + Send + Sync + 'static,
{
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(names).try_map(|s| s.parse::<T>())
}

/// The localizer's options shared by `localize` and `bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct LocalizeOptions {
    /// Which spectra are matched.
    #[arg(long, value_enum, default_value_t = ModeArg::Dual)]
    pub mode: ModeArg,
    /// Eigenvalues per spectrum (dual: k + k; lbo, si: 2k) [default: the library's, 20].
    #[arg(long, value_name = "K")]
    pub k: Option<usize>,
    /// Exponent of the scale-invariant metric [default: 0.33].
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Seed of every random choice (results are deterministic for a given seed).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub seed: u64,
    /// Farthest-point centres of the starts (3 starts each; 4 with `--starts gaussian` or
    /// `balls-and-wide-gaussians`, 2 with `area-ball`) [default: the library's, 4; the paper
    /// used 10].
    #[arg(long, value_name = "N")]
    pub centers: Option<usize>,
    /// The starting potentials around each centre: balls-and-wide-bumps (a well on the ball
    /// of the partial's area, one on everything but a ball, a wide Gaussian bump),
    /// balls-and-wide-gaussians (and a wide Gaussian well), gaussian (the reference's, two
    /// widths, both signs), area-ball (the two balls) [default: the library's,
    /// balls-and-wide-bumps].
    #[arg(long, value_name = "SHAPE", value_parser = library_names_parser::<StartShape, 4>(StartShape::ALL.map(StartShape::name)))]
    pub starts: Option<StartShape>,
    /// Further starts from the full shape's first N eigenfunctions, two each (the region on
    /// either side of a level set, with the partial's area) [default: the library's, 0].
    #[arg(long, value_name = "N")]
    pub spectral_cuts: Option<usize>,
    /// Plane-cut starts: the side of a plane with the partial's area, normal to the first N
    /// of 26 directions (6: both ways along the full shape's principal axes; 14: and the
    /// diagonals; 26: and the face diagonals) [default: the library's, 6].
    #[arg(long, value_name = "N")]
    pub plane_cuts: Option<usize>,
    /// Trust-region iterations per start [default: the library's, 25].
    #[arg(long, value_name = "N")]
    pub iterations: Option<usize>,
    /// Further trust-region iterations for the starts whose cost still fell by more than 10%
    /// over their last 10 iterations; 0 = none [default: the library's].
    #[arg(long, value_name = "N")]
    pub extra_iterations: Option<usize>,
    /// Vertices of the decimated full shape the potential is optimised on; 0 = no decimation
    /// [default: the library's].
    #[arg(long, value_name = "N")]
    pub resolution: Option<usize>,
    /// Successive halving: keep this many starts (per kind) to the full iteration budget,
    /// dropping the costliest at 1/8, 1/4, 1/2 of it; 0 = run every start fully
    /// [default: the library's].
    #[arg(long, value_name = "N")]
    pub finalists: Option<usize>,
    /// The trust region's model Hessian [default: the library's].
    #[arg(long, value_enum, value_name = "MODEL")]
    pub hessian: Option<HessianArg>,
    /// How the result is chosen among the optimised starts: gated (the lowest descriptor
    /// score among the regions whose own spectra fit within 3x of the best), region (the
    /// region's spectra alone), descriptors (the paper's rule), cost (the lowest final cost)
    /// [default: the library's, gated].
    #[arg(long, value_name = "RULE", value_parser = library_names_parser::<Selection, 4>(Selection::ALL.map(Selection::name)))]
    pub selection: Option<Selection>,
}

impl LocalizeOptions {
    /// The library options, checked.
    pub fn to_options(&self) -> Result<Options, CliError> {
        let mut o = Options {
            mode: self.mode.into(),
            seed: self.seed,
            ..Options::default()
        };
        if let Some(k) = self.k {
            if k == 0 {
                return Err(CliError::Usage("--k must be at least 1".into()));
            }
            o.k = k;
        }
        for (name, v, field) in [
            ("--centers", self.centers, &mut o.centers),
            ("--iterations", self.iterations, &mut o.max_iterations),
        ] {
            if let Some(v) = v {
                if v == 0 {
                    return Err(CliError::Usage(format!("{name} must be at least 1")));
                }
                *field = v;
            }
        }
        if let Some(r) = self.resolution {
            o.resolution = r;
        }
        if let Some(n) = self.spectral_cuts {
            o.spectral_cuts = n;
        }
        if let Some(n) = self.plane_cuts {
            o.plane_cuts = n;
        }
        if let Some(f) = self.finalists {
            o.finalists = f;
        }
        if let Some(e) = self.extra_iterations {
            o.extra_iterations = e;
        }
        if let Some(h) = self.hessian {
            o.hessian = h.into();
        }
        if let Some(s) = self.starts {
            o.start_shape = s;
        }
        if let Some(s) = self.selection {
            o.selection = s;
        }
        if let Some(a) = self.alpha {
            if !a.is_finite() {
                return Err(CliError::Usage(format!("--alpha must be finite, got {a}")));
            }
            o.alpha = a;
        }
        Ok(o)
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
    pub cost: f64,
    pub seconds: f64,
    pub mode: Mode,
    pub k: usize,
    pub alpha: f64,
    pub seed: u64,
    pub n_vertices_full: usize,
    pub n_vertices_partial: usize,
    pub n_starts: usize,
    pub selected_start: usize,
    /// The rule that chose `selected_start`.
    pub selection: Selection,
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
        options: &Options,
        seconds: f64,
        full: &TriMesh,
        partial: &TriMesh,
    ) -> Self {
        Output {
            region: region_indices(&loc.region),
            cost: loc.cost,
            seconds,
            mode: options.mode,
            k: options.k,
            alpha: options.alpha,
            seed: options.seed,
            n_vertices_full: full.n_vertices(),
            n_vertices_partial: partial.n_vertices(),
            n_starts: loc.n_starts,
            selected_start: loc.selected_start,
            selection: options.selection,
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
pub fn localize_with_bar(
    full: &TriMesh,
    partial: &TriMesh,
    options: &Options,
    quiet: bool,
    prefix: &str,
) -> Result<(Localization, f64), CliError> {
    let (bar, progress) = progress_bar(quiet, prefix);
    let t = Instant::now();
    let result = dualspectra::localize(full, partial, options, &progress);
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

pub fn run(args: Args) -> Result<(), CliError> {
    let options = args.options.to_options()?;
    let (full, _) = read_input_mesh(&args.full, args.drop_isolated)?;
    let (partial, _) = read_input_mesh(&args.partial, args.drop_isolated)?;
    let (loc, seconds) = localize_with_bar(&full, &partial, &options, args.quiet, "localize")?;
    let out = Output::new(&loc, &options, seconds, &full, &partial);
    let text = to_json_line(&out)?;
    if let Some(path) = &args.ply {
        write_region_ply(path, &full, &loc.region)?;
    }
    for w in &loc.warnings {
        eprintln!("warning: {w}");
    }
    match &args.json {
        Some(path) => {
            write_text(path, &text)?;
            println!(
                "region: {} of {} vertices, cost {:.6e}, {:.2} s ({} starts)",
                out.region.len(),
                full.n_vertices(),
                loc.cost,
                seconds,
                loc.n_starts
            );
        }
        None => print!("{text}"),
    }
    Ok(())
}

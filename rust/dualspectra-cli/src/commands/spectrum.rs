//! `dualspectra spectrum MESH --k K [--metric regular|si] [--alpha A] [--json OUT]`
//!
//! The `k` smallest eigenvalues $\mu$ of $W\phi = \mu M\phi$ (cotangent stiffness $W$,
//! lumped mass $M = A$ for `regular`, $M = \mathrm{diag}(s)A$ with
//! $s = (\epsilon + K_{smooth}^2)^{\alpha/2}$ for `si`), homogeneous Dirichlet conditions
//! on the boundary vertices if the mesh has a boundary (docs/algorithm.md, "Spectra"). Computed
//! by `dualspectra::shape::Shape::dirichlet_spectrum` on the mesh as given (no rescaling;
//! $\epsilon = 10^{-8}$ in the mesh's units). Prints `{"eigenvalues": [...]}` (ascending)
//! and also writes it to `OUT` with `--json`. A file with non-manifold edges or vertices is
//! read split (`dualspectra::mesh::io`), with a warning on standard error.

use crate::error::CliError;
use crate::input::read_input_mesh;
use crate::output::{print_stdout, to_json_line, write_text};
use dualspectra::geometry::metric::{DEFAULT_ALPHA, DEFAULT_EPS};
use dualspectra::shape::{Metric, Shape};
use serde::Serialize;
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MetricArg {
    /// The surface's own metric (Laplace-Beltrami operator).
    Regular,
    /// The scale-invariant metric (curvature-weighted mass).
    Si,
}

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Mesh file: .off, .obj or .ply (ASCII or binary).
    #[arg(value_name = "MESH")]
    pub mesh: PathBuf,
    /// Number of eigenvalues (at least 1, fewer than the interior vertices).
    #[arg(long, default_value_t = 20)]
    pub k: usize,
    /// Metric of the Laplacian.
    #[arg(long, value_enum, default_value_t = MetricArg::Regular)]
    pub metric: MetricArg,
    /// Exponent of the scale-invariant metric (only with `--metric si`) [default: 0.33].
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub alpha: Option<f64>,
    /// Also write the JSON to this file.
    #[arg(long, value_name = "OUT")]
    pub json: Option<PathBuf>,
    /// Drop vertices that belong to no face instead of failing.
    #[arg(long)]
    pub drop_isolated: bool,
}

#[derive(Serialize)]
struct Output<'a> {
    eigenvalues: &'a [f64],
}

pub fn run(args: Args) -> Result<(), CliError> {
    if let Some(out) = &args.json {
        crate::output::check_output_path(out, &[&args.mesh])?;
    }
    let alpha = match (args.metric, args.alpha) {
        (MetricArg::Regular, Some(_)) => {
            return Err(CliError::Usage("--alpha applies only to --metric si".into()));
        }
        (_, Some(a)) if !a.is_finite() => return Err(CliError::Usage(format!("--alpha must be finite, got {a}"))),
        (_, a) => a.unwrap_or(DEFAULT_ALPHA),
    };
    if args.k == 0 {
        return Err(CliError::Usage("--k must be at least 1".into()));
    }
    let (mesh, report) = read_input_mesh(&args.mesh, args.drop_isolated)?;
    if let Some(w) = report.non_manifold_warning() {
        eprintln!("warning: {}: {w}", args.mesh.display());
    }
    let shape = Shape::with_metric_params(mesh, alpha, DEFAULT_EPS);
    let metric = match args.metric {
        MetricArg::Regular => Metric::Regular,
        MetricArg::Si => Metric::ScaleInvariant,
    };
    let spectrum = shape
        .dirichlet_spectrum(metric, args.k)
        .map_err(|e| in_file(e, &args.mesh))?;
    let text = to_json_line(&Output {
        eigenvalues: &spectrum.values,
    })?;
    if let Some(out) = &args.json {
        write_text(out, &text)?;
    }
    print_stdout(&text)
}

/// Name the mesh in argument and numerical errors that arise from it (e.g. `k` too large).
fn in_file(e: dualspectra::Error, path: &std::path::Path) -> CliError {
    match e {
        dualspectra::Error::InvalidArgument(m) => CliError::Usage(format!("{}: {m}", path.display())),
        dualspectra::Error::Numerical(m) => {
            CliError::Core(dualspectra::Error::Numerical(format!("{}: {m}", path.display())))
        }
        other => CliError::Core(other),
    }
}

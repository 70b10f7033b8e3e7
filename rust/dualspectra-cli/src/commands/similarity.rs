//! `dualspectra similarity MESH... [--k K] [--json OUT] [--svg OUT]`
//!
//! Spectral distances between full shapes (the paper's section 3, Fig. 3): each shape is
//! scaled to unit area and described by its `k` smallest nonzero eigenvalues of the
//! regular and of the scale-invariant Laplacian, each Weyl-normalised
//! ($\hat\lambda_i = A\lambda_i/(4\pi i)$); the distance is the Euclidean distance of
//! $\log\hat\lambda$ (see `dualspectra::evaluation::similarity`). Prints the dual
//! (LBO + SI-LBO) distance matrix; `--json` writes both the dual and the LBO-only matrices
//! and their 2-D classical MDS embeddings; `--svg` plots the two embeddings side by side
//! (LBO left, dual right, points labelled by file stem, coloured by the stem without
//! trailing digits, e.g. `cat0`, `cat_3` -> `cat`).

use super::localize::progress_bar;
use crate::error::CliError;
use crate::input::read_input_mesh;
use crate::output::{to_json_line, write_text};
use dualspectra::evaluation::similarity::{
    classical_mds, distance_matrix, dual_shape_dna, Descriptor, DualShapeDna, Mds,
};
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Full (closed or open) shapes: .off, .obj or .ply; at least two.
    #[arg(value_name = "MESH", num_args = 1.., required = true)]
    pub meshes: Vec<PathBuf>,
    /// Nonzero eigenvalues per metric.
    #[arg(long, value_name = "K", default_value_t = 20)]
    pub k: usize,
    /// Write names, spectra, distance matrices and MDS coordinates as JSON.
    #[arg(long, value_name = "OUT")]
    pub json: Option<PathBuf>,
    /// Write the 2-D MDS embeddings (LBO only vs dual) as SVG.
    #[arg(long, value_name = "OUT")]
    pub svg: Option<PathBuf>,
    /// Drop vertices that belong to no face instead of failing.
    #[arg(long)]
    pub drop_isolated: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

#[derive(Serialize)]
struct Embedding {
    distances: Vec<Vec<f64>>,
    mds: Mds,
}

#[derive(Serialize)]
struct Output<'a> {
    names: &'a [String],
    k: usize,
    spectra: &'a [DualShapeDna],
    dual: Embedding,
    lbo: Embedding,
}

/// File stem of a path (the label of a point).
pub fn stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.display().to_string())
}

/// Group of a label: the label without trailing digits, `_` and `-` (`cat_3` -> `cat`).
pub fn group_of(label: &str) -> String {
    let g = label.trim_end_matches(|c: char| c.is_ascii_digit() || c == '_' || c == '-');
    if g.is_empty() {
        label.to_string()
    } else {
        g.to_string()
    }
}

fn embed(dnas: &[DualShapeDna], which: Descriptor) -> Result<Embedding, CliError> {
    let desc = dnas
        .iter()
        .map(|d| d.descriptor(which))
        .collect::<Result<Vec<_>, _>>()?;
    let distances = distance_matrix(&desc)?;
    let mds = classical_mds(&distances, 2)?;
    Ok(Embedding { distances, mds })
}

/// Two scatter panels (LBO only, dual) of labelled 2-D points, as an SVG document.
pub fn mds_svg(names: &[String], panels: &[(&str, &Mds)]) -> Result<String, CliError> {
    use plotters::prelude::*;
    let draw_err =
        |e: &dyn std::fmt::Display| CliError::Internal(format!("cannot draw the SVG plot: {e}"));
    let groups: Vec<String> = names.iter().map(|n| group_of(n)).collect();
    let mut distinct: Vec<&String> = groups.iter().collect();
    distinct.sort();
    distinct.dedup();
    let palette = [
        RGBColor(200, 30, 30),
        RGBColor(30, 90, 200),
        RGBColor(30, 150, 60),
        RGBColor(120, 60, 160),
        RGBColor(230, 130, 0),
        RGBColor(0, 150, 160),
        RGBColor(150, 110, 40),
        RGBColor(220, 60, 160),
    ];
    let color_of =
        |g: &String| palette[distinct.iter().position(|d| *d == g).unwrap_or(0) % palette.len()];
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| draw_err(&e))?;
        let areas = root.split_evenly((1, panels.len().max(1)));
        for (area, (title, mds)) in areas.iter().zip(panels) {
            let xs: Vec<f64> = mds.coords.iter().map(|c| c[0]).collect();
            let ys: Vec<f64> = mds.coords.iter().map(|c| c[1]).collect();
            let range = |v: &[f64]| {
                let (lo, hi) = v
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                        (a.min(x), b.max(x))
                    });
                let pad = ((hi - lo) * 0.15).max(1e-6);
                (lo - pad)..(hi + pad)
            };
            let mut chart = ChartBuilder::on(area)
                .caption(*title, ("sans-serif", 18))
                .margin(15)
                .x_label_area_size(30)
                .y_label_area_size(40)
                .build_cartesian_2d(range(&xs), range(&ys))
                .map_err(|e| draw_err(&e))?;
            chart
                .configure_mesh()
                .x_desc("MDS 1")
                .y_desc("MDS 2")
                .draw()
                .map_err(|e| draw_err(&e))?;
            for (i, name) in names.iter().enumerate() {
                let c = color_of(&groups[i]);
                let p = (xs[i], ys[i]);
                chart
                    .draw_series(std::iter::once(Circle::new(p, 5, c.filled())))
                    .map_err(|e| draw_err(&e))?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        name.clone(),
                        p,
                        ("sans-serif", 12).into_font().color(&c),
                    )))
                    .map_err(|e| draw_err(&e))?;
            }
        }
        root.present().map_err(|e| draw_err(&e))?;
    }
    Ok(svg)
}

pub fn run(args: Args) -> Result<(), CliError> {
    let inputs: Vec<&std::path::Path> = args.meshes.iter().map(|m| m.as_path()).collect();
    for out in [&args.json, &args.svg].into_iter().flatten() {
        crate::output::check_output_path(out, &inputs)?;
    }
    if args.meshes.len() < 2 {
        return Err(CliError::Usage(
            "similarity needs at least two meshes".into(),
        ));
    }
    if args.k == 0 {
        return Err(CliError::Usage("--k must be at least 1".into()));
    }
    let names: Vec<String> = args.meshes.iter().map(|p| stem(p)).collect();
    let (bar, _) = progress_bar(args.quiet, "similarity");
    bar.set_length(args.meshes.len() as u64);
    let mut dnas = Vec::with_capacity(args.meshes.len());
    for (i, path) in args.meshes.iter().enumerate() {
        bar.set_message(names[i].clone());
        let (mesh, report) = read_input_mesh(path, args.drop_isolated)?;
        if let Some(w) = report.non_manifold_warning() {
            bar.suspend(|| eprintln!("warning: {}: {w}", path.display()));
        }
        let dna = dual_shape_dna(&mesh, args.k).map_err(|e| match e {
            dualspectra::Error::InvalidArgument(m) => {
                CliError::Usage(format!("{}: {m}", path.display()))
            }
            dualspectra::Error::Numerical(m) => CliError::Core(dualspectra::Error::Numerical(
                format!("{}: {m}", path.display()),
            )),
            other => CliError::Core(other),
        })?;
        dnas.push(dna);
        bar.set_position(i as u64 + 1);
    }
    bar.finish_and_clear();
    let dual = embed(&dnas, Descriptor::Dual)?;
    let lbo = embed(&dnas, Descriptor::Lbo)?;
    let w = names
        .iter()
        .map(|n| n.len())
        .max()
        .unwrap_or(4)
        .clamp(4, 24);
    outln!(
        "dual ShapeDNA distances (k = {} regular + {} scale-invariant eigenvalues):",
        args.k, args.k
    );
    let header: String = names.iter().map(|n| format!(" {n:>w$}")).collect();
    outln!("{:<w$}{header}", "");
    for (n, row) in names.iter().zip(&dual.distances) {
        let cells: String = row.iter().map(|d| format!(" {d:>w$.4}")).collect();
        outln!("{n:<w$}{cells}");
    }
    if let Some(path) = &args.svg {
        let svg = mds_svg(
            &names,
            &[
                (&format!("LBO only (k = {})", args.k), &lbo.mds),
                (
                    &format!("LBO + SI-LBO (k = {} + {})", args.k, args.k),
                    &dual.mds,
                ),
            ],
        )?;
        write_text(path, &svg)?;
    }
    if let Some(path) = &args.json {
        let out = Output {
            names: &names,
            k: args.k,
            spectra: &dnas,
            dual,
            lbo,
        };
        write_text(path, &to_json_line(&out)?)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_strip_trailing_indices() {
        assert_eq!(group_of("cat0"), "cat");
        assert_eq!(group_of("cat_13"), "cat");
        assert_eq!(group_of("david"), "david");
        assert_eq!(group_of("123"), "123");
    }

    #[test]
    fn svg_has_a_labelled_point_per_shape() {
        let names = vec!["cat0".to_string(), "cat1".to_string(), "horse0".to_string()];
        let mds = Mds {
            coords: vec![vec![0.0, 0.0], vec![0.1, 0.0], vec![1.0, 1.0]],
            eigenvalues: vec![1.0, 0.1],
        };
        let svg = mds_svg(&names, &[("a", &mds), ("b", &mds)]).unwrap();
        assert!(svg.starts_with("<svg"));
        assert_eq!(svg.matches("<circle").count(), 6);
        assert!(svg.contains("horse0"));
    }
}

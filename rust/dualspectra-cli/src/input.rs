//! Reading the input mesh of a command.

use crate::error::CliError;
use dualspectra::mesh::io::{read_mesh_with_report, ReadOptions, ReadReport};
use dualspectra::TriMesh;
use std::path::Path;

/// Read a mesh file (format from the extension). Polygons are fan-triangulated,
/// two-sided flaps removed and non-manifold edges and vertices split (see
/// `dualspectra::mesh::io`); isolated vertices are an error unless `drop_isolated`.
pub fn read_input_mesh(path: &Path, drop_isolated: bool) -> Result<(TriMesh, ReadReport), CliError> {
    let options = ReadOptions {
        drop_isolated,
        ..ReadOptions::default()
    };
    Ok(read_mesh_with_report(path, &options)?)
}

/// Per-vertex values of the mesh scattered back to the file's vertex numbering, `None`
/// at vertices reading dropped. A vertex split into copies (non-manifold) takes its first
/// copy's value (the one of its lowest face's fan).
pub fn to_file_vertices(values: &[f64], report: &ReadReport) -> Vec<Option<f64>> {
    let mut out = vec![None; report.file_vertices];
    for (&v, &file_index) in values.iter().zip(&report.kept_vertices) {
        out[file_index as usize].get_or_insert(v);
    }
    out
}

/// What reading changed in the file's vertices, one sentence per reason (empty if
/// nothing): dropped vertices (their values are `null` in per-vertex outputs) and
/// non-manifold vertices split into copies.
pub fn read_warnings(report: &ReadReport) -> Vec<String> {
    let mut warnings = Vec::new();
    if report.flap_vertices_dropped > 0 {
        warnings.push(format!(
            "dropped {} vertices used only by repeated triangles (the tips of two-sided flaps: a triangle \
             listed in both orientations; {} repeated triangles removed), their values are null",
            report.flap_vertices_dropped, report.duplicate_faces_removed
        ));
    }
    if report.isolated_dropped > 0 {
        warnings.push(format!(
            "dropped {} vertices that belong to no face (--drop-isolated), their values are null",
            report.isolated_dropped
        ));
    }
    if let Some(w) = report.non_manifold_warning() {
        warnings.push(format!("{w}; a split vertex's values are its first copy's"));
    }
    warnings
}

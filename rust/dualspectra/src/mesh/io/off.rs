//! OFF reader and writer.
//!
//! Layout: a header keyword (`OFF`, optionally prefixed by `ST`, `C`, `N` for texture,
//! colour and normal variants), then `nv nf ne` (on the header line or the next), then
//! `nv` vertex lines (`x y z`, further values ignored), then `nf` face lines
//! (`n i0 .. i{n-1}`, further values such as a colour ignored). `#` starts a comment.
//! The reader is line-based (one record per line), as written by MeshLab, CGAL, libigl
//! and the SHREC'16 files. Binary OFF and 4-D/n-D OFF are rejected.

use super::{content_lines, parse_error, RawMesh};
use crate::error::Result;
use crate::mesh::TriMesh;
use std::io::Write;
use std::path::Path;

pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<RawMesh> {
    let text = String::from_utf8_lossy(bytes);
    let mut lines = content_lines(&text);
    let (line_no, header) = lines
        .next()
        .ok_or_else(|| parse_error(path, "bad header: the file is empty"))?;
    let mut tokens = header.split_whitespace();
    let keyword = tokens.next().unwrap_or("");
    check_keyword(keyword).map_err(|m| parse_error(path, format!("line {line_no}: bad header: {m}")))?;
    let rest: Vec<&str> = tokens.collect();
    if rest.first().is_some_and(|t| t.eq_ignore_ascii_case("BINARY")) {
        return Err(parse_error(
            path,
            format!("line {line_no}: binary OFF is not supported (save as ASCII OFF, or PLY)"),
        ));
    }
    let (count_line, counts) = if rest.is_empty() {
        let (l, c) = lines
            .next()
            .ok_or_else(|| parse_error(path, "bad header: the file ends before the vertex and face counts"))?;
        (l, c.split_whitespace().collect::<Vec<_>>())
    } else {
        (line_no, rest)
    };
    let count = |i: usize| counts.get(i).and_then(|t| t.parse::<usize>().ok());
    let (Some(nv), Some(nf)) = (count(0), count(1)) else {
        return Err(parse_error(
            path,
            format!(
                "line {count_line}: bad header: expected vertex, face and edge counts, found '{}'",
                counts.join(" ")
            ),
        ));
    };
    let mut raw = RawMesh::new();
    // Capacity hints are capped so that a lying header cannot exhaust memory.
    raw.positions.reserve(nv.min(1 << 24));
    raw.offsets.reserve(nf.min(1 << 24));
    for v in 0..nv {
        let (l, line) = lines
            .next()
            .ok_or_else(|| parse_error(path, format!("the file ends after {v} of {nv} vertices (truncated?)")))?;
        let mut xyz = [0.0; 3];
        let mut it = line.split_whitespace();
        for c in &mut xyz {
            let tok = it.next().ok_or_else(|| {
                parse_error(
                    path,
                    format!("line {l}: vertex {v} has fewer than 3 coordinates: '{line}'"),
                )
            })?;
            *c = tok
                .parse::<f64>()
                .map_err(|_| parse_error(path, format!("line {l}: vertex {v}: '{tok}' is not a number")))?;
        }
        raw.positions.push(xyz);
    }
    for f in 0..nf {
        let (l, line) = lines
            .next()
            .ok_or_else(|| parse_error(path, format!("the file ends after {f} of {nf} faces (truncated?)")))?;
        let mut it = line.split_whitespace();
        let first = it.next().unwrap_or("");
        let k: usize = first.parse().map_err(|_| {
            parse_error(
                path,
                format!("line {l}: face {f}: vertex count '{first}' is not a non-negative integer"),
            )
        })?;
        for j in 0..k {
            let tok = it.next().ok_or_else(|| {
                parse_error(
                    path,
                    format!("line {l}: face {f} lists {k} vertices but gives only {j} indices"),
                )
            })?;
            let i: u64 = tok.parse().map_err(|_| {
                parse_error(
                    path,
                    format!("line {l}: face {f}: vertex index '{tok}' is not a non-negative integer"),
                )
            })?;
            raw.indices.push(i);
        }
        raw.end_polygon();
    }
    Ok(raw)
}

fn check_keyword(keyword: &str) -> std::result::Result<(), String> {
    let Some(prefix) = keyword.strip_suffix("OFF") else {
        return Err(format!("expected 'OFF', found '{keyword}'"));
    };
    let mut p = prefix.strip_prefix("ST").unwrap_or(prefix);
    p = p.strip_prefix('C').unwrap_or(p);
    p = p.strip_prefix('N').unwrap_or(p);
    match p {
        "" => Ok(()),
        "4" | "n" | "4n" => Err(format!("'{keyword}' (4-D or n-D OFF) is not supported")),
        _ => Err(format!("expected 'OFF', found '{keyword}'")),
    }
}

pub(super) fn write(w: &mut impl Write, mesh: &TriMesh) -> std::io::Result<()> {
    writeln!(w, "OFF")?;
    writeln!(w, "{} {} 0", mesh.n_vertices(), mesh.n_faces())?;
    for p in mesh.vertices() {
        writeln!(w, "{:?} {:?} {:?}", p[0], p[1], p[2])?;
    }
    for f in mesh.faces() {
        writeln!(w, "3 {} {} {}", f[0], f[1], f[2])?;
    }
    Ok(())
}

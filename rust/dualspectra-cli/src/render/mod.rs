//! Pictures of a result: the full shape with its region, seen from the front and the back
//! along its principal axes, written as PNG (`demo`, `localize --png`, `search --png`).
//!
//! The view frame is the vertices' principal axes (eigenvectors of their covariance): the
//! longest axis points up the picture, the second to the right, and the camera looks along
//! the shortest, where the silhouette is largest; the back view turns the shape half a turn
//! about the up axis, so a region on either side is seen. Each axis's sign makes its
//! largest coordinate positive, so a shape modelled upright stays upright when its longest
//! axis is its height. Drawing: [`raster`]; labels: [`font`].

mod font;
mod raster;

use crate::error::CliError;
use raster::{cross, dot, normalize, sub, Camera, PALETTE};
use dualspectra::TriMesh;
use std::path::Path;

type V3 = [f64; 3];

/// An RGB image, 8 bits per channel, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<u8>,
}

impl Image {
    /// A `width` x `height` image filled with `color`.
    pub fn new(width: usize, height: usize, color: [u8; 3]) -> Self {
        Image { width, height, rgb: color.repeat(width * height) }
    }
    pub fn get(&self, x: usize, y: usize) -> [u8; 3] {
        let k = 3 * (y * self.width + x);
        [self.rgb[k], self.rgb[k + 1], self.rgb[k + 2]]
    }
    pub fn set(&mut self, x: usize, y: usize, c: [u8; 3]) {
        let k = 3 * (y * self.width + x);
        self.rgb[k..k + 3].copy_from_slice(&c);
    }
    /// Copy `other` with its top-left corner at (`x`, `y`), clipped.
    pub fn blit(&mut self, other: &Image, x: usize, y: usize) {
        for oy in 0..other.height.min(self.height.saturating_sub(y)) {
            for ox in 0..other.width.min(self.width.saturating_sub(x)) {
                self.set(x + ox, y + oy, other.get(ox, oy));
            }
        }
    }
}

/// Why a shape cannot be drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderError(pub String);

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl From<RenderError> for CliError {
    fn from(e: RenderError) -> Self {
        CliError::Internal(format!("cannot draw the picture: {e}"))
    }
}

/// Which side of the shape a view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Front,
    Back,
}

/// A triangle mesh ready to be drawn: its vertices, faces and principal frame.
pub struct Shape<'a> {
    vertices: &'a [V3],
    faces: &'a [[u32; 3]],
    center: V3,
    /// Right, up, towards the viewer (front view).
    axes: [V3; 3],
}

/// Shape of a margin around the drawing: a fraction of the smaller picture side.
const MARGIN: f64 = 0.05;

impl<'a> Shape<'a> {
    /// Check the arrays (indices in range, finite coordinates, points spanning a plane at
    /// least) and find the principal frame.
    pub fn new(vertices: &'a [V3], faces: &'a [[u32; 3]]) -> Result<Self, RenderError> {
        if vertices.is_empty() {
            return Err(RenderError("the mesh has no vertex".into()));
        }
        if let Some(i) = vertices.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(RenderError(format!("vertex {i} has a coordinate that is not finite")));
        }
        let n = vertices.len();
        if let Some(f) = faces.iter().position(|f| f.iter().any(|&i| i as usize >= n)) {
            return Err(RenderError(format!("face {f} has a vertex index out of range (the mesh has {n} vertices)")));
        }
        let center = vertices.iter().fold([0.0; 3], |s, p| [s[0] + p[0], s[1] + p[1], s[2] + p[2]]).map(|s| s / n as f64);
        let mut cov = [[0.0; 3]; 3];
        for p in vertices {
            let d = sub(*p, center);
            for i in 0..3 {
                for j in 0..3 {
                    cov[i][j] += d[i] * d[j] / n as f64;
                }
            }
        }
        let (values, vectors) = symmetric_eigen3(cov);
        // Largest first.
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
        let (l1, l2) = (values[order[0]], values[order[1]]);
        if !(l2 > 1e-20 * l1.max(f64::MIN_POSITIVE)) || !(l1 > 0.0) {
            return Err(RenderError("the mesh's points lie on one line (or at one point): it has no surface to draw".into()));
        }
        let oriented = |v: V3| {
            let k = (0..3).max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs())).unwrap_or(0);
            if v[k] < 0.0 { v.map(|c| -c) } else { v }
        };
        let up = oriented(vectors[order[0]]);
        let right = oriented(vectors[order[1]]);
        let toward = normalize(cross(right, up));
        Ok(Shape { vertices, faces, center, axes: [right, up, toward] })
    }

    /// The camera rows of a side: the back view is turned half a turn about the up axis.
    fn rows(&self, side: Side) -> [V3; 3] {
        let [r, u, t] = self.axes;
        match side {
            Side::Front => [r, u, t],
            Side::Back => [r.map(|c| -c), u, t.map(|c| -c)],
        }
    }

    /// The smallest and largest coordinates of the vertices along the first two `rows`.
    fn extent(&self, rows: &[V3; 3]) -> ([f64; 2], [f64; 2]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in self.vertices {
            let d = sub(*p, self.center);
            for i in 0..2 {
                let c = dot(rows[i], d);
                lo[i] = lo[i].min(c);
                hi[i] = hi[i].max(c);
            }
        }
        (lo, hi)
    }

    /// The height of a view `width` wide that fits the shape's silhouette, kept between
    /// half and 1.6 times the width.
    pub fn fitted_height(&self, width: usize) -> usize {
        let (lo, hi) = self.extent(&self.rows(Side::Front));
        let aspect = (hi[1] - lo[1]) / (hi[0] - lo[0]).max(f64::MIN_POSITIVE);
        let inner = (1.0 - 2.0 * MARGIN) * width as f64;
        ((inner * aspect + 2.0 * MARGIN * width as f64).round() as usize).clamp(width / 2, width * 8 / 5)
    }

    /// One view, `width` x `height`, the shape fitted inside a margin. `region`: one flag
    /// per vertex.
    pub fn view(&self, region: &[bool], side: Side, width: usize, height: usize) -> Result<Image, RenderError> {
        if region.len() != self.vertices.len() {
            return Err(RenderError(format!("{} region flags for {} vertices", region.len(), self.vertices.len())));
        }
        let rows = self.rows(side);
        let (lo, hi) = self.extent(&rows);
        let margin = MARGIN * width.min(height) as f64;
        let span = [(hi[0] - lo[0]).max(f64::MIN_POSITIVE), (hi[1] - lo[1]).max(f64::MIN_POSITIVE)];
        let scale = ((width as f64 - 2.0 * margin) / span[0]).min((height as f64 - 2.0 * margin) / span[1]).max(0.0);
        let origin = [
            0.5 * width as f64 - scale * 0.5 * (lo[0] + hi[0]),
            0.5 * height as f64 + scale * 0.5 * (lo[1] + hi[1]),
        ];
        let camera = Camera { rows, center: self.center, scale, origin };
        Ok(raster::draw(self.vertices, self.faces, region, &camera, &PALETTE, width, height))
    }

    /// The front and back views side by side, `width` x `height` in all.
    pub fn views(&self, region: &[bool], width: usize, height: usize) -> Result<Image, RenderError> {
        let half = width / 2;
        let mut image = Image::new(width, height, PALETTE.background);
        image.blit(&self.view(region, Side::Front, half, height)?, 0, 0);
        image.blit(&self.view(region, Side::Back, width - half, height)?, half, 0);
        Ok(image)
    }
}

/// Eigenvalues and unit eigenvectors of a symmetric 3 x 3 matrix by cyclic Jacobi rotations
/// (Golub and Van Loan, Matrix Computations, section 8.5).
fn symmetric_eigen3(mut a: [[f64; 3]; 3]) -> ([f64; 3], [V3; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= f64::EPSILON.powi(2) * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A <- J^T A J, V <- V J with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let vectors = [0, 1, 2].map(|j| [v[0][j], v[1][j], v[2][j]]);
    ([a[0][0], a[1][1], a[2][2]], vectors)
}

/// Height of a caption strip above a picture.
const CAPTION: usize = 26;
const TEXT_SCALE: usize = 2;
const TEXT: [u8; 3] = [40, 40, 40];
/// Gap between the cells of a composed picture.
const GAP: usize = 12;

/// `picture` under a strip with `caption` (cut to the width).
pub fn captioned(caption: &str, picture: &Image) -> Image {
    let mut image = Image::new(picture.width, picture.height + CAPTION, PALETTE.background);
    let text = font::fit_text(caption, picture.width.saturating_sub(12), TEXT_SCALE);
    font::draw_text(&mut image, 6, (CAPTION - font::GLYPH.1 * TEXT_SCALE) / 2 + 2, &text, TEXT_SCALE, TEXT);
    image.blit(picture, 0, CAPTION);
    image
}

/// `cells` (of one size) in rows of `columns`, separated by a gap.
pub fn grid(cells: &[Image], columns: usize) -> Image {
    let columns = columns.clamp(1, cells.len().max(1));
    let rows = cells.len().div_ceil(columns);
    let (w, h) = cells.first().map_or((0, 0), |c| (c.width, c.height));
    let mut image = Image::new(
        columns * w + (columns - 1) * GAP,
        (rows * h + rows.saturating_sub(1) * GAP).max(1),
        PALETTE.background,
    );
    for (i, cell) in cells.iter().enumerate() {
        image.blit(cell, (i % columns) * (w + GAP), (i / columns) * (h + GAP));
    }
    image
}

/// Width of one view (front or back) in each command's picture; the height fits the shape.
const LOCALIZE_VIEW: usize = 360;
const DEMO_VIEW: usize = 260;
const SEARCH_VIEW: usize = 170;
/// Shapes per row of the `search` picture.
const SEARCH_COLUMNS: usize = 3;

/// `localize --png`: the full shape with its region, front and back, under `caption`.
pub fn region_picture(mesh: &TriMesh, region: &[bool], caption: &str) -> Result<Image, RenderError> {
    let shape = Shape::new(mesh.vertices(), mesh.faces())?;
    Ok(captioned(caption, &shape.views(region, 2 * LOCALIZE_VIEW, shape.fitted_height(LOCALIZE_VIEW))?))
}

/// `demo`: the found region (front and back) beside the ground truth (front and back).
pub fn demo_picture(mesh: &TriMesh, found: (&[bool], &str), truth: (&[bool], &str)) -> Result<Image, RenderError> {
    let shape = Shape::new(mesh.vertices(), mesh.faces())?;
    let height = shape.fitted_height(DEMO_VIEW);
    let panel = |(region, caption): (&[bool], &str)| {
        shape.views(region, 2 * DEMO_VIEW, height).map(|views| captioned(caption, &views))
    };
    Ok(grid(&[panel(found)?, panel(truth)?], 2))
}

/// One shape of the `search` picture: its label (`rank. name`), its score's text, and the
/// mesh with its region (`None`: the partial could not be located on it).
pub struct Ranked<'a> {
    pub label: String,
    pub score: String,
    pub mesh: &'a TriMesh,
    pub region: Option<&'a [bool]>,
}

/// `search --png`: each ranked shape small, front and back with its region, labelled with
/// rank, name (cut to fit) and score, in rows of three (cells of one size: the tallest
/// shape's).
pub fn ranking_picture(ranked: &[Ranked]) -> Result<Image, RenderError> {
    let width = 2 * SEARCH_VIEW;
    let shapes = ranked.iter().map(|r| Shape::new(r.mesh.vertices(), r.mesh.faces())).collect::<Result<Vec<_>, _>>()?;
    let height = shapes.iter().map(|s| s.fitted_height(SEARCH_VIEW)).max().unwrap_or(SEARCH_VIEW);
    let mut cells = Vec::with_capacity(ranked.len());
    for (r, shape) in ranked.iter().zip(&shapes) {
        let none = vec![false; r.mesh.n_vertices()];
        let views = shape.views(r.region.unwrap_or(&none), width, height)?;
        let score = format!("  {}", r.score);
        let room = (width - 12).saturating_sub(font::text_width(&score, TEXT_SCALE) + font::GLYPH.0 * TEXT_SCALE);
        cells.push(captioned(&format!("{}{score}", font::fit_text(&r.label, room, TEXT_SCALE)), &views));
    }
    Ok(grid(&cells, SEARCH_COLUMNS))
}

/// Write `image` as an 8-bit RGB PNG.
pub fn write_png(path: &Path, image: &Image) -> Result<(), CliError> {
    let out_err = |source: std::io::Error| CliError::Output { path: path.to_path_buf(), source };
    let file = std::fs::File::create(path).map_err(out_err)?;
    let (w, h) = (u32::try_from(image.width), u32::try_from(image.height));
    let (Ok(w), Ok(h)) = (w, h) else {
        return Err(CliError::Internal(format!("{}: picture too large", path.display())));
    };
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::High);
    let png_err = |e: png::EncodingError| match e {
        png::EncodingError::IoError(source) => out_err(source),
        other => CliError::Internal(format!("{}: cannot encode PNG: {other}", path.display())),
    };
    let mut writer = encoder.write_header().map_err(png_err)?;
    writer.write_image_data(&image.rgb).map_err(png_err)?;
    writer.finish().map_err(png_err)
}

#[cfg(test)]
mod tests {
    use super::*;
    use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticParams};
    use dualspectra::mesh::generate::icosphere;

    /// Pixels drawn in the region's colour (red over green: the shape is grey, the
    /// background white, the outline a darker shade of either).
    fn region_pixels(image: &Image) -> usize {
        (0..image.height).flat_map(|y| (0..image.width).map(move |x| (x, y))).filter(|&(x, y)| {
            let [r, g, _] = image.get(x, y);
            r as i32 > g as i32 + 20
        }).count()
    }

    /// Pixels not of the background colour.
    fn covered_pixels(image: &Image) -> usize {
        (0..image.height).flat_map(|y| (0..image.width).map(move |x| (x, y))).filter(|&(x, y)| image.get(x, y) != PALETTE.background).count()
    }

    /// An ellipsoid with distinct axes (3, 2, 1), so that the principal frame is defined.
    fn ellipsoid() -> TriMesh {
        icosphere(3).map_positions(|p| [3.0 * p[0], 2.0 * p[1], p[2]]).unwrap()
    }

    #[test]
    fn pictures_have_the_requested_size() {
        let mesh = ellipsoid();
        let shape = Shape::new(mesh.vertices(), mesh.faces()).unwrap();
        let region = vec![false; mesh.n_vertices()];
        for (w, h) in [(1, 1), (2, 3), (101, 57), (320, 240), (57, 400)] {
            let image = shape.views(&region, w, h).unwrap();
            assert_eq!((image.width, image.height, image.rgb.len()), (w, h, 3 * w * h));
        }
        let cells = vec![Image::new(30, 20, [0; 3]); 5];
        let g = grid(&cells, 3);
        assert_eq!((g.width, g.height), (3 * 30 + 2 * GAP, 2 * 20 + GAP));
        assert_eq!(captioned("x", &cells[0]).height, 20 + CAPTION);
    }

    #[test]
    fn the_ranking_picture_has_a_cell_per_shape_and_no_region_for_a_failure() {
        let (a, b) = (ellipsoid(), icosphere(2));
        let region_a: Vec<bool> = a.vertices().iter().map(|p| p[0] > 1.0).collect();
        let entry = |label: &str, mesh, region| Ranked { label: label.into(), score: "1.00e-3".into(), mesh, region };
        let ranked = [
            entry("1. a_shape_with_a_name_far_too_long_for_its_cell.off", &a, Some(region_a.as_slice())),
            entry("2. sphere.off", &b, None),
            entry("3. a.off", &a, Some(region_a.as_slice())),
            entry("4. b.off", &b, None),
        ];
        let image = ranking_picture(&ranked).unwrap();
        let shape = Shape::new(a.vertices(), a.faces()).unwrap();
        let cell_h = CAPTION + shape.fitted_height(SEARCH_VIEW).max(Shape::new(b.vertices(), b.faces()).unwrap().fitted_height(SEARCH_VIEW));
        assert_eq!((image.width, image.height), (3 * 2 * SEARCH_VIEW + 2 * GAP, 2 * cell_h + GAP));
        let cell = |i: usize| {
            let mut c = Image::new(2 * SEARCH_VIEW, cell_h - CAPTION, [0; 3]);
            let (x0, y0) = ((i % 3) * (2 * SEARCH_VIEW + GAP), (i / 3) * (cell_h + GAP) + CAPTION);
            for y in 0..c.height {
                for x in 0..c.width {
                    c.set(x, y, image.get(x0 + x, y0 + y));
                }
            }
            c
        };
        assert!(region_pixels(&cell(0)) > 0 && region_pixels(&cell(2)) > 0);
        assert_eq!(region_pixels(&cell(1)) + region_pixels(&cell(3)), 0, "no region drawn for a failed match");
        assert!(covered_pixels(&cell(1)) > 0, "the shape itself is drawn");
    }

    #[test]
    fn region_pixels_exist_iff_the_region_is_not_empty_and_grow_with_it() {
        let mesh = ellipsoid();
        let shape = Shape::new(mesh.vertices(), mesh.faces()).unwrap();
        let n = mesh.n_vertices();
        let draw = |region: &[bool]| region_pixels(&shape.views(region, 400, 300).unwrap());
        assert_eq!(draw(&vec![false; n]), 0, "an empty region draws no region pixel");
        // One vertex, at a pole of the shortest axis (seen face-on from the front or back).
        let pole = (0..n).max_by(|&a, &b| mesh.vertices()[a][2].total_cmp(&mesh.vertices()[b][2])).unwrap();
        let mut one = vec![false; n];
        one[pole] = true;
        assert!(draw(&one) > 0, "a one-vertex region is seen");
        // Nested regions (caps x > t, growing): nested drawings, so counts that never fall.
        let counts: Vec<usize> = [2.5, 1.5, 0.5, -0.5, -1.5, -2.5, -4.0]
            .iter()
            .map(|&t| draw(&mesh.vertices().iter().map(|p| p[0] > t).collect::<Vec<_>>()))
            .collect();
        assert!(counts.windows(2).all(|w| w[0] < w[1]), "region pixels grow with the region: {counts:?}");
        let all = shape.views(&vec![true; n], 400, 300).unwrap();
        assert!(region_pixels(&all) as f64 >= 0.95 * covered_pixels(&all) as f64, "a whole region colours the whole shape");
    }

    #[test]
    fn front_and_back_show_silhouettes_of_one_area() {
        let pair = synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() }).unwrap();
        for mesh in [ellipsoid(), pair.full] {
            let shape = Shape::new(mesh.vertices(), mesh.faces()).unwrap();
            let region = vec![false; mesh.n_vertices()];
            let front = covered_pixels(&shape.view(&region, Side::Front, 300, 300).unwrap());
            let back = covered_pixels(&shape.view(&region, Side::Back, 300, 300).unwrap());
            assert!(front > 300 * 300 / 10, "the shape fills the view: {front} pixels");
            let diff = front.abs_diff(back) as f64 / front as f64;
            assert!(diff < 0.02, "front {front} and back {back} silhouettes differ by {:.1}%", 100.0 * diff);
        }
    }

    #[test]
    fn degenerate_meshes_are_errors_not_panics() {
        let line: Vec<V3> = (0..10).map(|i| [i as f64, 2.0 * i as f64, -(i as f64)]).collect();
        let faces: Vec<[u32; 3]> = (0..8).map(|i| [i, i + 1, i + 2]).collect();
        let err = Shape::new(&line, &faces).err().expect("collinear points are refused");
        assert!(err.0.contains("one line"), "{err}");
        let point = vec![[1.0, 1.0, 1.0]; 3];
        assert!(Shape::new(&point, &[[0, 1, 2]]).is_err());
        assert!(Shape::new(&[], &[]).is_err());
        assert!(Shape::new(&[[0.0, 0.0, f64::NAN], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[[0, 1, 2]]).is_err());
        assert!(Shape::new(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], &[[0, 1, 3]]).is_err());
        // A flat mesh (one plane) is drawn, seen face-on; a wrong region length is an error.
        let flat = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        let shape = Shape::new(&flat, &[[0, 1, 2], [1, 3, 2]]).unwrap();
        assert!(covered_pixels(&shape.views(&[false; 4], 64, 32).unwrap()) > 64 * 32 / 4);
        assert!(shape.views(&[false; 3], 64, 32).is_err());
        // A mesh without faces: a blank picture.
        let shape = Shape::new(&flat, &[]).unwrap();
        assert_eq!(covered_pixels(&shape.views(&[true; 4], 64, 32).unwrap()), 0);
    }

    #[test]
    fn the_png_decodes_to_the_image() {
        let mesh = ellipsoid();
        let shape = Shape::new(mesh.vertices(), mesh.faces()).unwrap();
        let region: Vec<bool> = mesh.vertices().iter().map(|p| p[1] > 0.5).collect();
        let image = captioned("rank 1: ellipsoid.off 1.2e-3", &shape.views(&region, 161, 90).unwrap());
        let path = std::env::temp_dir().join(format!("dualspectra_render_{}.png", std::process::id()));
        write_png(&path, &image).unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width as usize, info.height as usize), (image.width, image.height));
        assert_eq!((info.color_type, info.bit_depth), (png::ColorType::Rgb, png::BitDepth::Eight));
        assert_eq!(&buf[..info.buffer_size()], &image.rgb[..]);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn principal_axes_of_a_known_covariance() {
        let a = [[4.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 1.0]];
        let (values, vectors) = symmetric_eigen3(a);
        for (l, v) in values.iter().zip(vectors) {
            for i in 0..3 {
                let av = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
                assert!((av - l * v[i]).abs() < 64.0 * f64::EPSILON * 4.0, "A v = l v");
            }
            assert!((dot(v, v) - 1.0).abs() < 16.0 * f64::EPSILON);
        }
        assert!((values.iter().sum::<f64>() - 8.0).abs() < 64.0 * f64::EPSILON, "trace kept");
    }
}

//! A software rasteriser: orthographic camera, z-buffer, two-sided Gouraud Lambert shading,
//! a per-vertex region drawn in its own colour, a light outline where depth jumps.
//!
//! A view maps a point $p$ to camera coordinates $q = R\,(p - c)$ (rows of $R$: the
//! screen's right, up and towards-the-viewer axes), then to pixels
//! $x = x_0 + s\,q_x$, $y = y_0 - s\,q_y$; the z-buffer keeps the largest $q_z$.
//! The shade at a vertex is $a + (1 - a)\max(0, \pm n \cdot l)$ (the sign turns the
//! normal towards the viewer, so open meshes and inner sides are lit), interpolated
//! barycentrically; a pixel is drawn in the region colour where the interpolated region
//! indicator is at least 1/2, so the region's edge runs through the midpoints of the
//! edges that leave it.

use super::Image;

type V3 = [f64; 3];

pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
pub fn normalize(a: V3) -> V3 {
    let n = dot(a, a).sqrt();
    if n > 0.0 {
        [a[0] / n, a[1] / n, a[2] / n]
    } else {
        [0.0; 3]
    }
}

/// Colours of a drawing.
#[derive(Debug, Clone, Copy)]
pub struct Palette {
    pub background: [u8; 3],
    pub surface: [u8; 3],
    pub region: [u8; 3],
}

/// Red region on a light grey shape on white (the PLY files' colours).
pub const PALETTE: Palette = Palette { background: [255, 255, 255], surface: [190, 190, 190], region: [220, 40, 40] };

/// Ambient share $a$ of the shade.
const AMBIENT: f64 = 0.3;
/// Subpixels per pixel side (box-filtered: smooth edges).
const SUPERSAMPLE: usize = 2;
/// Darkening of outline subpixels.
const OUTLINE: f64 = 0.55;

/// An orthographic camera: rotation rows, centre, pixel scale and image origin.
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    pub rows: [V3; 3],
    pub center: V3,
    pub scale: f64,
    pub origin: [f64; 2],
}

impl Camera {
    /// Camera coordinates of a point.
    pub fn camera_coordinates(&self, p: V3) -> V3 {
        let d = sub(p, self.center);
        [dot(self.rows[0], d), dot(self.rows[1], d), dot(self.rows[2], d)]
    }
}

/// Draw `faces` of `vertices` seen by `camera` into a `width` x `height` image; `region` is
/// one flag per vertex. Zero-area (after projection) triangles cover no pixel.
pub fn draw(
    vertices: &[V3],
    faces: &[[u32; 3]],
    region: &[bool],
    camera: &Camera,
    palette: &Palette,
    width: usize,
    height: usize,
) -> Image {
    let (w, h) = (width * SUPERSAMPLE, height * SUPERSAMPLE);
    let ss = SUPERSAMPLE as f64;
    let light = normalize([-0.35, 0.55, 1.0]);
    let normals = vertex_normals(vertices, faces);
    let cam: Vec<V3> = vertices.iter().map(|&p| camera.camera_coordinates(p)).collect();
    let screen: Vec<[f64; 2]> = cam
        .iter()
        .map(|q| [ss * (camera.origin[0] + camera.scale * q[0]), ss * (camera.origin[1] - camera.scale * q[1])])
        .collect();
    let mut depth = vec![f64::NEG_INFINITY; w * h];
    let mut color = vec![[0.0f64; 3]; w * h];
    let fcol = |c: [u8; 3]| [c[0] as f64, c[1] as f64, c[2] as f64];
    let (surface, inside) = (fcol(palette.surface), fcol(palette.region));
    for f in faces {
        let [a, b, c] = f.map(|i| i as usize);
        let (pa, pb, pc) = (screen[a], screen[b], screen[c]);
        let area = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
        if !(area.abs() > 1e-12) {
            continue;
        }
        // Towards the viewer: +z in camera space.
        let facing = cross(sub(cam[b], cam[a]), sub(cam[c], cam[a]))[2];
        let sign = if facing >= 0.0 { 1.0 } else { -1.0 };
        let shade = [a, b, c].map(|v| {
            let n = camera_normal(camera, normals[v]);
            AMBIENT + (1.0 - AMBIENT) * (sign * dot(n, light)).max(0.0)
        });
        let inreg = [a, b, c].map(|v| if region[v] { 1.0 } else { 0.0 });
        let zs = [cam[a][2], cam[b][2], cam[c][2]];
        let xmin = pa[0].min(pb[0]).min(pc[0]).floor().max(0.0) as usize;
        let ymin = pa[1].min(pb[1]).min(pc[1]).floor().max(0.0) as usize;
        let xmax = (pa[0].max(pb[0]).max(pc[0]).ceil() as i64).clamp(0, w as i64) as usize;
        let ymax = (pa[1].max(pb[1]).max(pc[1]).ceil() as i64).clamp(0, h as i64) as usize;
        for y in ymin..ymax {
            let py = y as f64 + 0.5;
            for x in xmin..xmax {
                let px = x as f64 + 0.5;
                let l0 = ((pb[0] - px) * (pc[1] - py) - (pb[1] - py) * (pc[0] - px)) / area;
                let l1 = ((pc[0] - px) * (pa[1] - py) - (pc[1] - py) * (pa[0] - px)) / area;
                let l2 = 1.0 - l0 - l1;
                if l0 < 0.0 || l1 < 0.0 || l2 < 0.0 {
                    continue;
                }
                let z = l0 * zs[0] + l1 * zs[1] + l2 * zs[2];
                let k = y * w + x;
                if z <= depth[k] {
                    continue;
                }
                depth[k] = z;
                let s = l0 * shade[0] + l1 * shade[1] + l2 * shade[2];
                let base = if l0 * inreg[0] + l1 * inreg[1] + l2 * inreg[2] >= 0.5 { inside } else { surface };
                color[k] = base.map(|c| c * s);
            }
        }
    }
    outline(&depth, &mut color, w, h, depth_jump(&cam));
    downsample(&depth, &color, palette.background, width, height)
}

/// Depth difference between neighbouring subpixels that counts as an edge: 3% of the
/// view's depth range.
fn depth_jump(cam: &[V3]) -> f64 {
    let (lo, hi) = cam.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| (lo.min(q[2]), hi.max(q[2])));
    0.03 * (hi - lo).max(0.0)
}

/// Darken covered subpixels next to the background or across a depth jump.
fn outline(depth: &[f64], color: &mut [[f64; 3]], w: usize, h: usize, jump: f64) {
    let mut edge = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            let k = y * w + x;
            if depth[k] == f64::NEG_INFINITY {
                continue;
            }
            let neighbours = [(x.wrapping_sub(1), y), (x + 1, y), (x, y.wrapping_sub(1)), (x, y + 1)];
            edge[k] = neighbours.iter().any(|&(nx, ny)| {
                if nx >= w || ny >= h {
                    return true;
                }
                // The nearer of two subpixels across a jump keeps its colour.
                let d = depth[ny * w + nx];
                d == f64::NEG_INFINITY || depth[k] + jump < d
            });
        }
    }
    for (c, e) in color.iter_mut().zip(edge) {
        if e {
            *c = c.map(|v| v * OUTLINE);
        }
    }
}

/// Box-filter the subpixels down to `width` x `height`, the background where uncovered.
fn downsample(depth: &[f64], color: &[[f64; 3]], background: [u8; 3], width: usize, height: usize) -> Image {
    let w = width * SUPERSAMPLE;
    let n = (SUPERSAMPLE * SUPERSAMPLE) as f64;
    let mut image = Image::new(width, height, background);
    for y in 0..height {
        for x in 0..width {
            let mut sum = [0.0; 3];
            for dy in 0..SUPERSAMPLE {
                for dx in 0..SUPERSAMPLE {
                    let k = (y * SUPERSAMPLE + dy) * w + x * SUPERSAMPLE + dx;
                    let c = if depth[k] == f64::NEG_INFINITY { background.map(f64::from) } else { color[k] };
                    for i in 0..3 {
                        sum[i] += c[i];
                    }
                }
            }
            image.set(x, y, sum.map(|s| (s / n).round().clamp(0.0, 255.0) as u8));
        }
    }
    image
}

/// Area-weighted vertex normals (unit; zero for a vertex in no face of positive area).
pub fn vertex_normals(vertices: &[V3], faces: &[[u32; 3]]) -> Vec<V3> {
    let mut n = vec![[0.0; 3]; vertices.len()];
    for f in faces {
        let [a, b, c] = f.map(|i| i as usize);
        let fnorm = cross(sub(vertices[b], vertices[a]), sub(vertices[c], vertices[a]));
        for v in [a, b, c] {
            for i in 0..3 {
                n[v][i] += fnorm[i];
            }
        }
    }
    n.into_iter().map(normalize).collect()
}

fn camera_normal(camera: &Camera, n: V3) -> V3 {
    [dot(camera.rows[0], n), dot(camera.rows[1], n), dot(camera.rows[2], n)]
}

//! Shape similarity from truncated spectra: the dual ShapeDNA of the paper's section 3
//! (Fig. 3), classical multidimensional scaling (MDS) to the plane.
//!
//! **Descriptor.** For a shape with metric area $A_g = \sum_i m_i$ (mass of the metric),
//! take its $k$ smallest nonzero eigenvalues $\lambda_1 \le \dots \le \lambda_k$ of
//! $W\phi = \lambda M\phi$ (closed mesh: the zero eigenvalue is skipped; with a boundary:
//! Dirichlet eigenvalues) for the regular metric ($M = A$) and the scale-invariant metric
//! ($M = \mathrm{diag}(s) A$). Each spectrum is normalised by Weyl's law,
//! $$\hat\lambda_i = \frac{A_g\,\lambda_i}{4\pi i},$$
//! which tends to 1 as $i \to \infty$ on any surface (Weyl 1911; for the SI metric the
//! area is the metric's own, as in the paper's Theorem 1). This removes the global scale
//! (the regular spectrum scales as $c^{-2}$ when the shape is scaled by $c$, and $A_g$ as
//! $c^2$) and puts both spectra on the same footing ("we normalize each spectrum to
//! balance the two", paper section 3). The descriptor is $\log\hat\lambda$ of the regular
//! spectrum, the SI spectrum, or both concatenated (dual).
//!
//! **Distance.** Euclidean distance between descriptors:
//! $d(X, Y) = \lVert \log\hat\lambda^X - \log\hat\lambda^Y \rVert_2$, i.e. relative
//! differences of the eigenvalues (log makes it symmetric in over- and underestimation).
//!
//! **MDS.** Classical (Torgerson) scaling: $B = -\tfrac12 J D^{\circ 2} J$ with
//! $J = I - \tfrac1n \mathbf{1}\mathbf{1}^\top$; the coordinates are the top eigenvectors of
//! $B$ scaled by the square roots of their (positive) eigenvalues. Exact for distances of
//! points in the plane.

use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::shape::{Metric, Shape};
use faer::Mat;
use serde::{Deserialize, Serialize};

/// The $k$ smallest nonzero eigenvalues of both metrics, with the metric areas.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DualShapeDna {
    pub regular: Vec<f64>,
    pub si: Vec<f64>,
    /// $\sum_i a_i$ (surface area from the lumped mass).
    pub area_regular: f64,
    /// $\sum_i s_i a_i$.
    pub area_si: f64,
}

/// Which spectra a descriptor uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Descriptor {
    /// Regular (Laplace-Beltrami) spectrum only.
    Lbo,
    /// Scale-invariant spectrum only.
    Si,
    /// Both, concatenated (the paper's dual ShapeDNA).
    Dual,
}

fn spectrum_without_zero(shape: &Shape, metric: Metric, k: usize) -> Result<Vec<f64>> {
    if k == 0 {
        return Err(Error::InvalidArgument("k must be at least 1".into()));
    }
    if shape.has_boundary() {
        Ok(shape.dirichlet_spectrum(metric, k)?.values)
    } else {
        // Closed: the constant function has eigenvalue 0; skip it.
        let v = shape.dirichlet_spectrum(metric, k + 1)?.values;
        Ok(v[1..].to_vec())
    }
}

/// Dual ShapeDNA of `mesh` with `k` eigenvalues per metric, after scaling the mesh to unit
/// area (the curvature threshold $\epsilon$ of the SI metric has units, so this is what makes
/// the SI spectrum independent of the mesh's units; the localizer does the same).
pub fn dual_shape_dna(mesh: &TriMesh, k: usize) -> Result<DualShapeDna> {
    let c = 1.0 / mesh.area().sqrt();
    let unit = mesh.map_positions(|p| [p[0] * c, p[1] * c, p[2] * c])?;
    dual_shape_dna_of_shape(&Shape::new(unit), k)
}

/// Dual ShapeDNA of a [`Shape`] as it is (no rescaling), `k` eigenvalues per metric.
pub fn dual_shape_dna_of_shape(shape: &Shape, k: usize) -> Result<DualShapeDna> {
    let regular = spectrum_without_zero(shape, Metric::Regular, k)?;
    let si = spectrum_without_zero(shape, Metric::ScaleInvariant, k)?;
    let area_regular = shape.metric_mass(Metric::Regular).iter().sum();
    let area_si = shape.metric_mass(Metric::ScaleInvariant).iter().sum();
    Ok(DualShapeDna {
        regular,
        si,
        area_regular,
        area_si,
    })
}

/// Weyl normalisation $\hat\lambda_i = A\lambda_i / (4\pi i)$, $i$ 1-based.
pub fn weyl_normalise(values: &[f64], area: f64) -> Vec<f64> {
    values
        .iter()
        .enumerate()
        .map(|(i, &l)| area * l / (4.0 * std::f64::consts::PI * (i + 1) as f64))
        .collect()
}

impl DualShapeDna {
    /// The descriptor vector (module doc): $\log\hat\lambda$ of the chosen spectra.
    /// Errors if an eigenvalue is not positive (a second zero eigenvalue: several components).
    pub fn descriptor(&self, which: Descriptor) -> Result<Vec<f64>> {
        let mut out = Vec::new();
        let mut push = |vals: &[f64], area: f64, name: &str| -> Result<()> {
            for (i, v) in weyl_normalise(vals, area).into_iter().enumerate() {
                if !(v > 0.0 && v.is_finite()) {
                    return Err(Error::Numerical(format!(
                        "{name} eigenvalue {} is {} (not positive: is the mesh connected?)",
                        i + 1,
                        vals[i]
                    )));
                }
                out.push(v.ln());
            }
            Ok(())
        };
        if matches!(which, Descriptor::Lbo | Descriptor::Dual) {
            push(&self.regular, self.area_regular, "regular")?;
        }
        if matches!(which, Descriptor::Si | Descriptor::Dual) {
            push(&self.si, self.area_si, "scale-invariant")?;
        }
        Ok(out)
    }
}

/// Symmetric matrix of Euclidean distances between descriptors (all of the same length).
pub fn distance_matrix(descriptors: &[Vec<f64>]) -> Result<Vec<Vec<f64>>> {
    let n = descriptors.len();
    if let Some(d) = descriptors.first() {
        if let Some(j) = descriptors.iter().position(|x| x.len() != d.len()) {
            return Err(Error::InvalidArgument(format!(
                "descriptor {j} has length {}, descriptor 0 has {}",
                descriptors[j].len(),
                d.len()
            )));
        }
    }
    let mut m = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in i + 1..n {
            let d = descriptors[i]
                .iter()
                .zip(&descriptors[j])
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            m[i][j] = d;
            m[j][i] = d;
        }
    }
    Ok(m)
}

/// Classical MDS embedding.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mds {
    /// `coords[i]` = coordinates of item `i` (length `dim`; zero in dimensions whose
    /// eigenvalue is not positive).
    pub coords: Vec<Vec<f64>>,
    /// The top `dim` eigenvalues of $B$, descending.
    pub eigenvalues: Vec<f64>,
}

/// Classical MDS of a distance matrix into `dim` dimensions (module doc). The matrix must
/// be square, symmetric and finite.
pub fn classical_mds(distances: &[Vec<f64>], dim: usize) -> Result<Mds> {
    let n = distances.len();
    if let Some(i) = distances.iter().position(|r| r.len() != n) {
        return Err(Error::InvalidArgument(format!(
            "distance matrix row {i} has {} entries, expected {n}",
            distances[i].len()
        )));
    }
    for i in 0..n {
        for j in 0..n {
            let (a, b) = (distances[i][j], distances[j][i]);
            if !a.is_finite() || (a - b).abs() > 1e-9 * (a.abs() + b.abs()).max(f64::MIN_POSITIVE) {
                return Err(Error::InvalidArgument(format!(
                    "distance matrix is not finite and symmetric at ({i}, {j})"
                )));
            }
        }
    }
    if n == 0 {
        return Ok(Mds {
            coords: vec![],
            eigenvalues: vec![],
        });
    }
    let d2 = Mat::<f64>::from_fn(n, n, |i, j| distances[i][j] * distances[i][j]);
    let row_mean: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| d2[(i, j)]).sum::<f64>() / n as f64)
        .collect();
    let all_mean = row_mean.iter().sum::<f64>() / n as f64;
    let b = Mat::<f64>::from_fn(n, n, |i, j| {
        -0.5 * (d2[(i, j)] - row_mean[i] - row_mean[j] + all_mean)
    });
    let (s, u) = crate::spectra::symmetric_eigen(b.as_ref()).map_err(|e| Error::Numerical(format!("MDS eigendecomposition failed: {e:?}")))?;
    // Ascending order: the top `dim` are the last ones.
    let mut coords = vec![vec![0.0; dim]; n];
    let mut eigenvalues = Vec::with_capacity(dim);
    for c in 0..dim {
        if c >= n {
            eigenvalues.push(0.0);
            continue;
        }
        let col = n - 1 - c;
        let lambda = s[col];
        eigenvalues.push(lambda);
        if lambda > 0.0 {
            let r = lambda.sqrt();
            for (i, row) in coords.iter_mut().enumerate() {
                row[c] = u[(i, col)] * r;
            }
        }
    }
    Ok(Mds {
        coords,
        eigenvalues,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;

    fn dist(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
            .sqrt()
    }

    #[test]
    fn mds_recovers_planar_configurations() {
        let pts: Vec<Vec<f64>> = vec![
            vec![0.0, 0.0],
            vec![3.0, 0.0],
            vec![0.0, 4.0],
            vec![-2.0, 1.5],
            vec![1.0, -7.0],
            vec![5.5, 2.25],
        ];
        for scale in [1e-6, 1.0, 1e6] {
            let p: Vec<Vec<f64>> = pts
                .iter()
                .map(|x| x.iter().map(|v| v * scale).collect())
                .collect();
            let d = distance_matrix(&p).unwrap();
            let mds = classical_mds(&d, 2).unwrap();
            let e = distance_matrix(&mds.coords).unwrap();
            for i in 0..p.len() {
                for j in 0..p.len() {
                    assert!(
                        (e[i][j] - d[i][j]).abs() <= 1e-9 * scale * 10.0,
                        "{i} {j}: {} vs {}",
                        e[i][j],
                        d[i][j]
                    );
                }
            }
            assert!(mds.eigenvalues[0] >= mds.eigenvalues[1]);
        }
    }

    #[test]
    fn distance_matrix_is_symmetric_with_zero_diagonal() {
        let x: Vec<Vec<f64>> = (0..7)
            .map(|i| {
                (0..5)
                    .map(|j| ((i * 7 + j * 3) % 11) as f64 * 0.3)
                    .collect()
            })
            .collect();
        let d = distance_matrix(&x).unwrap();
        for i in 0..7 {
            assert_eq!(d[i][i], 0.0);
            for j in 0..7 {
                assert_eq!(d[i][j], d[j][i]);
                assert!((d[i][j] - dist(&x[i], &x[j])).abs() < 1e-15);
            }
        }
        assert!(distance_matrix(&[vec![1.0], vec![1.0, 2.0]]).is_err());
        assert!(classical_mds(&[vec![0.0, 1.0], vec![2.0, 0.0]], 2).is_err());
    }

    #[test]
    fn weyl_normalised_sphere_spectrum_is_near_one() {
        // Unit sphere: lambda = l(l+1) with multiplicity 2l+1, area 4 pi: the normalised
        // values oscillate around 1 (Weyl's law).
        let shape = Shape::new(generate::icosphere(3));
        let dna = dual_shape_dna_of_shape(&shape, 15).unwrap();
        assert!((dna.regular[0] - 2.0).abs() < 0.05, "{:?}", dna.regular);
        let w = weyl_normalise(&dna.regular, dna.area_regular);
        assert!(w.iter().all(|&x| x > 0.5 && x < 2.5), "{w:?}");
    }

    #[test]
    fn descriptor_is_scale_invariant_and_rotation_invariant() {
        let base =
            crate::evaluation::synthetic::figure(2, &crate::evaluation::synthetic::default_limbs())
                .unwrap();
        let big = base
            .map_positions(|p| [p[0] * 100.0, p[1] * 100.0, p[2] * 100.0])
            .unwrap();
        let rot = base.map_positions(|p| [p[1], -p[0], p[2]]).unwrap();
        let d0 = dual_shape_dna(&base, 8).unwrap();
        let db = dual_shape_dna(&big, 8).unwrap();
        let dr = dual_shape_dna(&rot, 8).unwrap();
        for which in [Descriptor::Lbo, Descriptor::Si, Descriptor::Dual] {
            let (a, b, c) = (
                d0.descriptor(which).unwrap(),
                db.descriptor(which).unwrap(),
                dr.descriptor(which).unwrap(),
            );
            assert!(dist(&a, &b) < 1e-6, "{which:?} scale: {}", dist(&a, &b));
            assert!(dist(&a, &c) < 1e-6, "{which:?} rotation: {}", dist(&a, &c));
        }
        assert_eq!(d0.descriptor(Descriptor::Dual).unwrap().len(), 16);
    }
}

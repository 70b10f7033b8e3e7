//! Outside references for the numerical core of `dualspectra`, for its tests
//! (`tests/`): CGAL 5.5 (areas, cotangent weights, barycentric and mixed Voronoi cells, corner
//! angles) and Eigen 3 (dense generalized symmetric eigenvalues), called through autocxx over
//! the thin wrapper `cpp/reference.h`.
//!
//! The C++ part is built only where its headers and libclang are found (`build.rs`); elsewhere
//! [`AVAILABLE`] is false, every reference function returns [`Unavailable`] and the tests
//! that need them are skipped with a message. libigl is not here: its C++ headers are in no
//! package this project's machines install (the Python tests compare with the libigl wheel).

use dualspectra::TriMesh;

/// The C++ reference was built (`cfg(has_cpp_reference)`).
pub const AVAILABLE: bool = cfg!(has_cpp_reference);

/// Why a reference could not be computed.
#[derive(Debug, Clone, PartialEq)]
pub enum Unavailable {
    /// The crate was built without the C++ reference (headers or libclang missing).
    NotBuilt,
    /// CGAL rejected the mesh (not a valid `Surface_mesh`), or Eigen failed.
    Rejected(&'static str),
}

impl std::fmt::Display for Unavailable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unavailable::NotBuilt => write!(f, "the C++ reference (CGAL, Eigen) was not built: run scripts/setup.sh"),
            Unavailable::Rejected(what) => write!(f, "{what} failed on this input"),
        }
    }
}

impl std::error::Error for Unavailable {}

/// A sparse matrix as `(row, col, value)` triplets (duplicates to be summed).
pub type Triplets = Vec<(usize, usize, f64)>;

/// The generated bindings (their long argument lists are the C++ signatures).
#[cfg(has_cpp_reference)]
#[allow(clippy::too_many_arguments)]
mod bindings {
    autocxx::include_cpp! {
        #include "reference.h"
        safety!(unsafe_ffi)
        generate!("dsref::cgal_face_areas")
        generate!("dsref::cgal_total_area")
        generate!("dsref::cgal_cotangent_triplets")
        generate!("dsref::cgal_edge_cotangent_weights")
        generate!("dsref::cgal_barycentric_vertex_areas")
        generate!("dsref::cgal_mixed_voronoi_vertex_areas")
        generate!("dsref::cgal_angle_defect")
        generate!("dsref::eigen_smallest_generalized")
    }
    pub(crate) use ffi::dsref;
}

/// A mesh as the flat arrays the C++ side takes.
#[cfg_attr(not(has_cpp_reference), allow(dead_code))]
struct Flat {
    v: Vec<f64>,
    f: Vec<i32>,
    nv: i32,
    nf: i32,
}

#[cfg_attr(not(has_cpp_reference), allow(dead_code))]
fn flat(mesh: &TriMesh) -> Flat {
    let size = |n: usize| i32::try_from(n).expect("mesh too large for the C++ reference");
    Flat {
        v: mesh.vertices().iter().flatten().copied().collect(),
        f: mesh.faces().iter().flatten().map(|&i| size(i as usize)).collect(),
        nv: size(mesh.n_vertices()),
        nf: size(mesh.n_faces()),
    }
}

/// Runs a C++ function writing into caller-sized arrays; `Rejected(what)` on its -1.
#[cfg(has_cpp_reference)]
fn check(status: autocxx::c_int, what: &'static str) -> Result<(), Unavailable> {
    if status.0 == 0 {
        Ok(())
    } else {
        Err(Unavailable::Rejected(what))
    }
}

/// CGAL references on a mesh. Each function is the CGAL call its name says; the contracts are
/// in `cpp/reference.h`.
pub mod cgal {
    #[cfg(has_cpp_reference)]
    use super::{bindings::dsref, check, flat};
    use super::{Triplets, Unavailable};
    use dualspectra::TriMesh;

    macro_rules! per_element {
        ($(#[$doc:meta])* $name:ident, $cpp:ident, $len:ident) => {
            $(#[$doc])*
            pub fn $name(mesh: &TriMesh) -> Result<Vec<f64>, Unavailable> {
                #[cfg(has_cpp_reference)]
                {
                    let m = flat(mesh);
                    let mut out = vec![0.0; mesh.$len()];
                    // SAFETY: the arrays have the sizes reference.h states for these counts.
                    let status = unsafe { dsref::$cpp(m.v.as_ptr(), m.nv.into(), m.f.as_ptr().cast(), m.nf.into(), out.as_mut_ptr()) };
                    check(status, stringify!($cpp)).map(|()| out)
                }
                #[cfg(not(has_cpp_reference))]
                {
                    let _ = mesh;
                    Err(Unavailable::NotBuilt)
                }
            }
        };
    }

    per_element!(
        /// Face areas, `CGAL::Polygon_mesh_processing::face_area`.
        face_areas, cgal_face_areas, n_faces
    );
    per_element!(
        /// Barycentric vertex areas (one third of the incident faces), summed
        /// `CGAL::Weights::barycentric_area` cells.
        barycentric_vertex_areas, cgal_barycentric_vertex_areas, n_vertices
    );
    per_element!(
        /// Mixed Voronoi vertex areas (Meyer et al. 2003), summed `CGAL::Weights::mixed_voronoi_area` cells.
        mixed_voronoi_vertex_areas, cgal_mixed_voronoi_vertex_areas, n_vertices
    );
    per_element!(
        /// Angle defect per vertex from `CGAL::approximate_angle`: $2\pi - \sum\theta$ inside,
        /// $\pi - \sum\theta$ on the border.
        angle_defect, cgal_angle_defect, n_vertices
    );

    /// Total surface area, `CGAL::Polygon_mesh_processing::area`.
    pub fn total_area(mesh: &TriMesh) -> Result<f64, Unavailable> {
        #[cfg(has_cpp_reference)]
        {
            let m = flat(mesh);
            let mut out = [0.0];
            // SAFETY: one output double, as reference.h states.
            let status = unsafe { dsref::cgal_total_area(m.v.as_ptr(), m.nv.into(), m.f.as_ptr().cast(), m.nf.into(), out.as_mut_ptr()) };
            check(status, "cgal_total_area").map(|()| out[0])
        }
        #[cfg(not(has_cpp_reference))]
        {
            let _ = mesh;
            Err(Unavailable::NotBuilt)
        }
    }

    /// Cotangent stiffness $W = -L$ (positive semi-definite) assembled from the corner
    /// cotangents `CGAL::Weights::cotangent`: $W_{ij} = -\tfrac12(\cot\alpha_{ij} + \cot\beta_{ij})$,
    /// $W_{ii} = -\sum_{j \ne i} W_{ij}$; `12 n_faces` triplets.
    pub fn cotangent_triplets(mesh: &TriMesh) -> Result<Triplets, Unavailable> {
        #[cfg(has_cpp_reference)]
        {
            let m = flat(mesh);
            let len = 12 * mesh.n_faces();
            let (mut rows, mut cols, mut vals) = (vec![0i32; len], vec![0i32; len], vec![0.0; len]);
            // SAFETY: 12 nf entries in each output array, as reference.h states.
            let status = unsafe {
                dsref::cgal_cotangent_triplets(
                    m.v.as_ptr(), m.nv.into(), m.f.as_ptr().cast(), m.nf.into(),
                    rows.as_mut_ptr().cast(), cols.as_mut_ptr().cast(), vals.as_mut_ptr(),
                )
            };
            check(status, "cgal_cotangent_triplets")?;
            Ok(rows.iter().zip(&cols).zip(&vals).map(|((&i, &j), &x)| (i as usize, j as usize, x)).collect())
        }
        #[cfg(not(has_cpp_reference))]
        {
            let _ = mesh;
            Err(Unavailable::NotBuilt)
        }
    }

    /// Interior edges `(i, j, w)` with CGAL's 4-point edge weight
    /// `CGAL::Weights::cotangent_weight` $= 2(\cot\alpha_{ij} + \cot\beta_{ij}) = -4 W_{ij}$.
    pub fn edge_cotangent_weights(mesh: &TriMesh) -> Result<Triplets, Unavailable> {
        #[cfg(has_cpp_reference)]
        {
            let m = flat(mesh);
            let len = 3 * mesh.n_faces();
            let (mut i, mut j, mut w, mut count) = (vec![0i32; len], vec![0i32; len], vec![0.0; len], [0i32]);
            // SAFETY: room for 3 nf edges and one count, as reference.h states.
            let status = unsafe {
                dsref::cgal_edge_cotangent_weights(
                    m.v.as_ptr(), m.nv.into(), m.f.as_ptr().cast(), m.nf.into(),
                    i.as_mut_ptr().cast(), j.as_mut_ptr().cast(), w.as_mut_ptr(), count.as_mut_ptr().cast(),
                )
            };
            check(status, "cgal_edge_cotangent_weights")?;
            let n = count[0] as usize;
            Ok((0..n).map(|e| (i[e] as usize, j[e] as usize, w[e])).collect())
        }
        #[cfg(not(has_cpp_reference))]
        {
            let _ = mesh;
            Err(Unavailable::NotBuilt)
        }
    }
}

/// Eigen 3 references.
pub mod eigen {
    #[cfg(has_cpp_reference)]
    use super::{bindings::dsref, check};
    use super::Unavailable;

    /// The `k` smallest eigenvalues (ascending) of $W x = \lambda\,\mathrm{diag}(m)\,x$ for an
    /// `n x n` symmetric $W$ given as triplets, by Eigen's dense
    /// `GeneralizedSelfAdjointEigenSolver` ($O(n^3)$: small meshes only).
    pub fn smallest_generalized(w: &[(usize, usize, f64)], mass: &[f64], k: usize) -> Result<Vec<f64>, Unavailable> {
        #[cfg(has_cpp_reference)]
        {
            let int = |x: usize| i32::try_from(x).expect("too large for the C++ reference");
            let rows: Vec<i32> = w.iter().map(|t| int(t.0)).collect();
            let cols: Vec<i32> = w.iter().map(|t| int(t.1)).collect();
            let vals: Vec<f64> = w.iter().map(|t| t.2).collect();
            let mut out = vec![0.0; k];
            // SAFETY: nnz entries in rows/cols/vals, n in mass, k in out.
            let status = unsafe {
                dsref::eigen_smallest_generalized(
                    rows.as_ptr().cast(), cols.as_ptr().cast(), vals.as_ptr(), int(w.len()).into(),
                    mass.as_ptr(), int(mass.len()).into(), int(k).into(), out.as_mut_ptr(),
                )
            };
            check(status, "eigen_smallest_generalized").map(|()| out)
        }
        #[cfg(not(has_cpp_reference))]
        {
            let _ = (w, mass, k);
            Err(Unavailable::NotBuilt)
        }
    }
}

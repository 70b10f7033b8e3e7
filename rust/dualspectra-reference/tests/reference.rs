//! The core's stiffness, mass, curvature and eigenvalues against CGAL 5.5 and Eigen 3, called
//! through autocxx (`dualspectra_reference`). Skipped, with the reason, where the C++
//! reference was not built. Each test prints the largest error it saw per mesh.
//! Tolerances are multiples of machine epsilon where both sides evaluate the same formula in
//! floating point, and the eigensolver's stated tolerance for the eigenvalues.

mod common;

use common::*;
use dualspectra::geometry::{face_areas, gaussian_curvature};
use dualspectra::operators::{cotangent_stiffness, lumped_mass, Dirichlet};
use dualspectra_reference::{cgal, eigen};

const EPS: f64 = f64::EPSILON;
const SKIP: &str = "C++ reference (CGAL, Eigen, libclang) not built: run scripts/setup.sh";

/// W against the matrix assembled from `CGAL::Weights::cotangent` per corner: same pattern,
/// entries within 16 eps of the largest entry; on interior edges, W_ij = -cotangent_weight / 4
/// (CGAL's 4-point halfedge weight, 2 (cot a + cot b)).
#[test]
#[cfg_attr(not(has_cpp_reference), ignore = "C++ reference (CGAL, Eigen, libclang) not built: run scripts/setup.sh")]
fn stiffness_matches_cgal_cotangent_weights() {
    for (name, mesh) in all_meshes() {
        let ours = entries(&cotangent_stiffness(&mesh));
        let theirs = summed(&cgal::cotangent_triplets(&mesh).expect(SKIP));
        assert_eq!(ours.len(), theirs.len(), "{name}: sparsity pattern");
        let scale = theirs.values().fold(0.0f64, |m, x| m.max(x.abs()));
        let err = theirs.iter().map(|(k, x)| (ours[k] - x).abs()).fold(0.0, f64::max) / scale;
        let edges = cgal::edge_cotangent_weights(&mesh).unwrap();
        let err4 = edges.iter().map(|&(i, j, w)| (ours[&(i, j)] + w / 4.0).abs()).fold(0.0, f64::max) / scale;
        println!("{name:>20}: max|W - W_cgal|/max|W| = {:.1} eps, interior edges ({}) vs cotangent_weight: {:.1} eps", err / EPS, edges.len(), err4 / EPS);
        assert!(err <= 16.0 * EPS, "{name}: W vs CGAL corner cotangents, {err:e}");
        assert!(err4 <= 16.0 * EPS, "{name}: W vs CGAL edge weights, {err4:e}");
    }
}

/// The lumped mass is the barycentric one: equal to the summed `CGAL::Weights::barycentric_area`
/// cells within 16 eps of the largest, summing to `CGAL::Polygon_mesh_processing::area`, and
/// the face areas equal `face_area`. CGAL's mixed Voronoi cells (`mixed_voronoi_area`) differ
/// pointwise (the convention check: the core is not the Voronoi mass; their total is printed,
/// CGAL 5.5's cells do not partition obtuse faces exactly).
#[test]
#[cfg_attr(not(has_cpp_reference), ignore = "C++ reference (CGAL, Eigen, libclang) not built: run scripts/setup.sh")]
fn mass_matches_cgal_barycentric_cells_and_area() {
    for (name, mesh) in all_meshes() {
        let m = lumped_mass(&mesh);
        let bary = cgal::barycentric_vertex_areas(&mesh).expect(SKIP);
        let voronoi = cgal::mixed_voronoi_vertex_areas(&mesh).unwrap();
        let total = cgal::total_area(&mesh).unwrap();
        let e_mass = max_rel(&m, &bary, max_abs(&bary));
        let e_face = max_rel(&face_areas(&mesh), &cgal::face_areas(&mesh).unwrap(), max_abs(&bary));
        let e_total = (m.iter().sum::<f64>() - total).abs() / total;
        let e_voronoi_total = (voronoi.iter().sum::<f64>() - total).abs() / total;
        let d_voronoi = max_rel(&m, &voronoi, max_abs(&bary));
        println!(
            "{name:>20}: mass vs barycentric cells {:.1} eps, face areas {:.1} eps, total {:.1} eps; \
             mixed Voronoi: total {:.1} eps, pointwise difference {d_voronoi:.3e}",
            e_mass / EPS, e_face / EPS, e_total / EPS, e_voronoi_total / EPS
        );
        assert!(e_mass <= 16.0 * EPS, "{name}: mass {e_mass:e}");
        assert!(e_face <= 16.0 * EPS, "{name}: face areas {e_face:e}");
        let n = mesh.n_vertices() as f64;
        assert!(e_total <= n * EPS, "{name}: total area {e_total:e}");
    }
    // The regular closed meshes have no obtuse triangles and differing cells; the bumpy one shows it.
    let mesh = bumpy_sphere(3);
    let d = max_rel(&lumped_mass(&mesh), &cgal::mixed_voronoi_vertex_areas(&mesh).unwrap(), max_abs(&lumped_mass(&mesh)));
    assert!(d > 1e-3, "barycentric and mixed Voronoi cells should differ on an uneven mesh ({d:e})");
}

/// Gaussian curvature (angle defect / barycentric area) against the defect of the corner angles
/// `CGAL::approximate_angle` (border vertices: pi - sum) over the CGAL barycentric cells. The
/// angles are computed by different formulas (acos in CGAL, atan2 in the core): within
/// 1e3 eps of the largest |K|.
#[test]
#[cfg_attr(not(has_cpp_reference), ignore = "C++ reference (CGAL, Eigen, libclang) not built: run scripts/setup.sh")]
fn gaussian_curvature_matches_cgal_angle_defect() {
    for (name, mesh) in all_meshes() {
        let k = gaussian_curvature(&mesh);
        let defect = cgal::angle_defect(&mesh).expect(SKIP);
        let area = cgal::barycentric_vertex_areas(&mesh).unwrap();
        let reference: Vec<f64> = defect.iter().zip(&area).map(|(d, a)| d / a).collect();
        let scale = max_abs(&reference).max(1.0);
        let err = max_rel(&k, &reference, scale);
        println!("{name:>20}: max|K - K_cgal| / max(1, max|K|) = {:.1} eps", err / EPS);
        assert!(err <= 1e3 * EPS, "{name}: {err:e}");
    }
}

/// The core's sparse generalized eigensolver against Eigen's dense
/// `GeneralizedSelfAdjointEigenSolver` on CGAL's W and barycentric mass: the 20 smallest
/// eigenvalues within 1e-11 of the largest of them (the solver's residual tolerance is 1e-10), on closed
/// meshes and on the Dirichlet disk and patch (boundary rows and columns removed).
#[test]
#[cfg_attr(not(has_cpp_reference), ignore = "C++ reference (CGAL, Eigen, libclang) not built: run scripts/setup.sh")]
fn eigenvalues_match_eigen_dense() {
    let k = 20;
    let cases = [
        ("icosphere(2)", icosphere(2), false),
        ("bumpy_sphere(3)", bumpy_sphere(3), false),
        ("disk(10), Dirichlet", disk(10), true),
        ("jittered_patch(16), Dirichlet", jittered_patch(16), true),
    ];
    for (name, mesh, dirichlet) in cases {
        let mask = if dirichlet { boundary_mask(&mesh) } else { vec![false; mesh.n_vertices()] };
        let d = Dirichlet::new(&mask);
        let ours = core_eigenvalues(&d.restrict_matrix(&cotangent_stiffness(&mesh)), &d.restrict(&lumped_mass(&mesh)), k);
        // The reference problem from CGAL alone, restricted by renumbering the free vertices.
        let mut index = vec![usize::MAX; mesh.n_vertices()];
        let mut next = 0;
        for (i, &c) in mask.iter().enumerate() {
            if !c {
                index[i] = next;
                next += 1;
            }
        }
        let w: Vec<(usize, usize, f64)> = cgal::cotangent_triplets(&mesh)
            .expect(SKIP)
            .into_iter()
            .filter(|&(i, j, _)| !mask[i] && !mask[j])
            .map(|(i, j, x)| (index[i], index[j], x))
            .collect();
        let bary = cgal::barycentric_vertex_areas(&mesh).unwrap();
        let mass: Vec<f64> = bary.iter().zip(&mask).filter(|(_, &c)| !c).map(|(a, _)| *a).collect();
        let theirs = eigen::smallest_generalized(&w, &mass, k).unwrap();
        let err = max_rel(&ours, &theirs, theirs[k - 1].abs());
        println!("{name:>30}: n = {}, max|lambda - lambda_eigen| / lambda_{k} = {err:.3e}", mass.len());
        assert!(err <= 1e-11, "{name}: {err:e}\n ours {ours:?}\n eigen {theirs:?}");
    }
}

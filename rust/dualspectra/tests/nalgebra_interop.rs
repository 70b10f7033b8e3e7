//! The `nalgebra` feature: the operators as nalgebra-sparse matrices hold the same entries as
//! the faer ones, and a mesh built from nalgebra points is the same mesh.
#![cfg(feature = "nalgebra")]

use dualspectra::mesh::generate::icosphere;
use dualspectra::operators::{self, nalgebra as na_ops};
use dualspectra::TriMesh;

#[test]
fn stiffness_and_mass_match_the_faer_operators() {
    let mesh = icosphere(2);
    let w = operators::cotangent_stiffness(&mesh);
    let w_na = na_ops::cotangent_stiffness(&mesh);
    assert_eq!((w_na.nrows(), w_na.ncols()), (w.nrows(), w.ncols()));
    let dense = w.to_dense();
    let mut seen = 0;
    for (i, j, v) in w_na.triplet_iter() {
        assert!((*v - dense[(i, j)]).abs() <= 4.0 * f64::EPSILON * dense[(i, j)].abs().max(1.0));
        seen += 1;
    }
    // every non-zero of W is in the CSC matrix
    let nonzero = (0..w.nrows()).flat_map(|i| (0..w.ncols()).map(move |j| (i, j))).filter(|&(i, j)| dense[(i, j)] != 0.0).count();
    assert!(seen >= nonzero);
    // rows of W sum to zero: the law survives the conversion
    let mut row_sum = vec![0.0; w_na.nrows()];
    for (i, _, v) in w_na.triplet_iter() {
        row_sum[i] += *v;
    }
    assert!(row_sum.iter().all(|s| s.abs() < 1e-12));

    let a = operators::lumped_mass(&mesh);
    let a_na = na_ops::lumped_mass(&mesh);
    assert_eq!(a_na.nnz(), a.len());
    for (i, j, v) in a_na.triplet_iter() {
        assert_eq!(i, j);
        assert_eq!(*v, a[i]);
    }
}

#[test]
fn mesh_from_nalgebra_points() {
    let mesh = icosphere(1);
    let points: Vec<nalgebra::Point3<f64>> = mesh.vertices().iter().map(|p| nalgebra::Point3::new(p[0], p[1], p[2])).collect();
    let again = TriMesh::from_points(&points, mesh.faces().to_vec()).unwrap();
    assert_eq!(again.vertices(), mesh.vertices());
    assert_eq!(again.faces(), mesh.faces());
    // bad input is an error, not a panic
    assert!(TriMesh::from_points(&points, vec![[0, 1, points.len() as u32]]).is_err());
}

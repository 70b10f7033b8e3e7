// Thin C++ reference for the Rust tests of dualspectra (bound by autocxx, see src/lib.rs).
//
// A mesh is passed flat: `v` holds 3 nv doubles (x, y, z per vertex), `f` holds 3 nf vertex
// indices (counter-clockwise triangles). Results are written into caller-owned arrays whose
// sizes each function states. Every function returns 0 on success and -1 when the mesh is not
// a valid CGAL::Surface_mesh (non-manifold, bad index). Implemented in reference.cpp with CGAL
// 5.5 and Eigen 3 only: this header includes nothing, so the binding generator parses no CGAL.
#pragma once

namespace dsref {

// Face areas by CGAL::Polygon_mesh_processing::face_area, `out`: nf doubles.
int cgal_face_areas(const double* v, int nv, const int* f, int nf, double* out);

// Total area by CGAL::Polygon_mesh_processing::area, written to `out[0]`.
int cgal_total_area(const double* v, int nv, const int* f, int nf, double* out);

// Cotangent stiffness W = -L (positive semi-definite) assembled from the corner cotangents
// CGAL::Weights::cotangent: for the angle at corner q of a face (p, q, r),
// W_pr = W_rp -= cot/2, W_pp = W_rr += cot/2. Triplets (rows, cols, vals), 12 nf of each,
// duplicates to be summed.
int cgal_cotangent_triplets(const double* v, int nv, const int* f, int nf, int* rows, int* cols, double* vals);

// Interior edges (i, j) with CGAL's 4-point edge weight CGAL::Weights::cotangent_weight
// = 2 (cot a + cot b), walked on the halfedge structure. `i`, `j`, `w`: room for 3 nf each;
// the number written is returned in `count[0]`.
int cgal_edge_cotangent_weights(const double* v, int nv, const int* f, int nf, int* i, int* j, double* w, int* count);

// Barycentric vertex areas: sum over incident faces of CGAL::Weights::barycentric_area
// (the barycentric cell of the corner). `out`: nv doubles.
int cgal_barycentric_vertex_areas(const double* v, int nv, const int* f, int nf, double* out);

// Mixed Voronoi vertex areas: sum over incident faces of CGAL::Weights::mixed_voronoi_area.
// `out`: nv doubles.
int cgal_mixed_voronoi_vertex_areas(const double* v, int nv, const int* f, int nf, double* out);

// Angle defect per vertex from CGAL::approximate_angle: 2 pi - sum of corner angles at an
// interior vertex, pi - sum on a border vertex (CGAL::Surface_mesh::is_border). `out`: nv doubles.
int cgal_angle_defect(const double* v, int nv, const int* f, int nf, double* out);

// The k smallest eigenvalues of the pencil W x = lambda diag(mass) x by Eigen's dense
// GeneralizedSelfAdjointEigenSolver; W given by nnz triplets (duplicates summed), n x n.
// `out`: k doubles, ascending. Returns -1 when Eigen reports a failure.
int eigen_smallest_generalized(const int* rows, const int* cols, const double* vals, int nnz, const double* mass, int n,
                               int k, double* out);

}  // namespace dsref

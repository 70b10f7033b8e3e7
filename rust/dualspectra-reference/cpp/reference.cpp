// CGAL 5.5 and Eigen 3 implementations of reference.h (see there for the contracts).
#include "reference.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <vector>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Weights/barycentric_region_weights.h>
#include <CGAL/Weights/cotangent_weights.h>
#include <CGAL/Weights/mixed_voronoi_region_weights.h>
#include <CGAL/Weights/utils.h>
#include <Eigen/Dense>

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SM = CGAL::Surface_mesh<Point>;
using VI = SM::Vertex_index;
namespace PMP = CGAL::Polygon_mesh_processing;
constexpr double kPi = 3.14159265358979323846;

// The flat arrays as a Surface_mesh with the same vertex and face numbering; false when a
// face is rejected (index out of range, non-manifold, inconsistent orientation).
bool build(const double* v, int nv, const int* f, int nf, SM& sm) {
  if (nv < 0 || nf < 0) return false;
  for (int i = 0; i < nv; ++i) sm.add_vertex(Point(v[3 * i], v[3 * i + 1], v[3 * i + 2]));
  for (int t = 0; t < nf; ++t) {
    const int a = f[3 * t], b = f[3 * t + 1], c = f[3 * t + 2];
    if (a < 0 || b < 0 || c < 0 || a >= nv || b >= nv || c >= nv) return false;
    if (sm.add_face(VI(a), VI(b), VI(c)) == SM::null_face()) return false;
  }
  return true;
}

// The three vertices of face `fd` in the order they were given.
void corners(const SM& sm, SM::Face_index fd, VI out[3]) {
  int k = 0;
  for (VI x : CGAL::vertices_around_face(sm.halfedge(fd), sm)) out[k++] = x;
}

// Runs `body` on a built mesh; -1 for a bad mesh or a C++ exception (none crosses into Rust).
template <class Body>
int with_mesh(const double* v, int nv, const int* f, int nf, Body body) {
  try {
    SM sm;
    if (!build(v, nv, f, nf, sm)) return -1;
    body(sm);
    return 0;
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace

namespace dsref {

int cgal_face_areas(const double* v, int nv, const int* f, int nf, double* out) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) {
    for (auto fd : sm.faces()) out[fd.idx()] = PMP::face_area(fd, sm);
  });
}

int cgal_total_area(const double* v, int nv, const int* f, int nf, double* out) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) { out[0] = PMP::area(sm); });
}

int cgal_cotangent_triplets(const double* v, int nv, const int* f, int nf, int* rows, int* cols, double* vals) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) {
    int e = 0;
    auto put = [&](VI i, VI j, double x) {
      rows[e] = static_cast<int>(i.idx());
      cols[e] = static_cast<int>(j.idx());
      vals[e] = x;
      ++e;
    };
    for (auto fd : sm.faces()) {
      VI c[3];
      corners(sm, fd, c);
      for (int k = 0; k < 3; ++k) {
        const VI q = c[k], p = c[(k + 1) % 3], r = c[(k + 2) % 3];
        const double cot = CGAL::Weights::cotangent(sm.point(p), sm.point(q), sm.point(r));  // angle at q
        put(p, r, -cot / 2);
        put(r, p, -cot / 2);
        put(p, p, cot / 2);
        put(r, r, cot / 2);
      }
    }
  });
}

int cgal_edge_cotangent_weights(const double* v, int nv, const int* f, int nf, int* i, int* j, double* w, int* count) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) {
    int e = 0;
    for (auto ed : sm.edges()) {
      if (sm.is_border(ed)) continue;
      const auto h = sm.halfedge(ed);
      const VI s = sm.source(h), t = sm.target(h);
      const VI a = sm.target(sm.next(h)), b = sm.target(sm.next(sm.opposite(h)));
      // cotangent_weight(p0, p1, p2, q): edge q-p1, opposite vertices p0 and p2.
      w[e] = CGAL::Weights::cotangent_weight(sm.point(a), sm.point(t), sm.point(b), sm.point(s));
      i[e] = static_cast<int>(s.idx());
      j[e] = static_cast<int>(t.idx());
      ++e;
    }
    count[0] = e;
  });
}

int cgal_barycentric_vertex_areas(const double* v, int nv, const int* f, int nf, double* out) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) {
    std::fill(out, out + nv, 0.0);
    for (auto fd : sm.faces()) {
      VI c[3];
      corners(sm, fd, c);
      for (int k = 0; k < 3; ++k)
        out[c[k].idx()] +=
            CGAL::Weights::barycentric_area(sm.point(c[(k + 2) % 3]), sm.point(c[k]), sm.point(c[(k + 1) % 3]));
    }
  });
}

int cgal_mixed_voronoi_vertex_areas(const double* v, int nv, const int* f, int nf, double* out) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) {
    std::fill(out, out + nv, 0.0);
    for (auto fd : sm.faces()) {
      VI c[3];
      corners(sm, fd, c);
      for (int k = 0; k < 3; ++k)
        out[c[k].idx()] +=
            CGAL::Weights::mixed_voronoi_area(sm.point(c[(k + 2) % 3]), sm.point(c[k]), sm.point(c[(k + 1) % 3]));
    }
  });
}

int cgal_angle_defect(const double* v, int nv, const int* f, int nf, double* out) {
  return with_mesh(v, nv, f, nf, [&](const SM& sm) {
    std::vector<double> sum(nv, 0.0);
    for (auto fd : sm.faces()) {
      VI c[3];
      corners(sm, fd, c);
      for (int k = 0; k < 3; ++k)  // degrees -> radians
        sum[c[k].idx()] +=
            CGAL::approximate_angle(sm.point(c[(k + 2) % 3]), sm.point(c[k]), sm.point(c[(k + 1) % 3])) * kPi / 180.0;
    }
    for (VI x : sm.vertices()) out[x.idx()] = (sm.is_border(x) ? kPi : 2 * kPi) - sum[x.idx()];
  });
}

int eigen_smallest_generalized(const int* rows, const int* cols, const double* vals, int nnz, const double* mass, int n,
                               int k, double* out) {
  try {
    if (n <= 0 || k <= 0 || k > n) return -1;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int e = 0; e < nnz; ++e) {
      if (rows[e] < 0 || cols[e] < 0 || rows[e] >= n || cols[e] >= n) return -1;
      a(rows[e], cols[e]) += vals[e];
    }
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < n; ++i) b(i, i) = mass[i];
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(a, b, Eigen::EigenvaluesOnly | Eigen::Ax_lBx);
    if (solver.info() != Eigen::Success) return -1;
    for (int i = 0; i < k; ++i) out[i] = solver.eigenvalues()(i);  // Eigen sorts them ascending
    return 0;
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace dsref

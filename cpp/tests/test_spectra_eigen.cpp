// dualspectra::spectrum against an independent dense generalized eigensolve (Eigen 3).
//
// The reference rebuilds every operator here, from the formulas (not from dualspectra):
//   W_ij = -(cot a_ij + cot b_ij) / 2, W_ii = -sum_j W_ij     (cotangent stiffness)
//   a_i  = (area of the faces at i) / 3                        (lumped mass)
//   K_i  = (2pi or pi on the boundary - sum of angles at i) / a_i, then the one-ring mean Ks_i
//   s_i  = (1e-8 + Ks_i^2)^(alpha/2), scale-invariant mass s_i a_i  (alpha = 0.33)
// and solves W phi = lambda M phi restricted to the interior vertices (homogeneous Dirichlet
// conditions on the boundary; none on a closed mesh) with
// Eigen::GeneralizedSelfAdjointEigenSolver on dense matrices (LAPACK-style, all eigenvalues,
// backward stable: error ~ 1e-16 * lambda_max, i.e. ~1e-11 relative on the 20 smallest here).
// dualspectra uses a sparse shift-invert iterative solver, so agreement is to the solvers'
// tolerances: the bound is 1e-8 relative (the zero eigenvalue of a closed mesh: 1e-8 relative
// to lambda_k). The mass diagonals are compared too (1e-12).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include <dualspectra/dualspectra.hpp>

#include "test_meshes.hpp"

static dstest::Checker T;
static const double kPi = 3.14159265358979323846;

struct Reference {
  Eigen::MatrixXd W;
  std::vector<double> mass, si_mass;
  std::vector<bool> boundary;
};

static Reference build_reference(const dstest::SimpleMesh& m, double alpha) {
  const std::size_t n = m.V.size();
  Reference r;
  r.W = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  r.mass.assign(n, 0.0);
  std::vector<double> angle(n, 0.0);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_faces;
  std::vector<std::vector<std::uint32_t>> nb(n);
  for (const auto& f : m.F) {
    const double area = 0.5 * dstest::norm(dstest::cross(dstest::sub(m.V[f[1]], m.V[f[0]]), dstest::sub(m.V[f[2]], m.V[f[0]])));
    for (int c = 0; c < 3; ++c) {
      const auto q = f[c], p = f[(c + 1) % 3], s = f[(c + 2) % 3];
      const auto u = dstest::sub(m.V[p], m.V[q]), v = dstest::sub(m.V[s], m.V[q]);
      const double cot = dstest::dot(u, v) / dstest::norm(dstest::cross(u, v));
      angle[q] += std::atan2(dstest::norm(dstest::cross(u, v)), dstest::dot(u, v));
      r.W(p, s) -= cot / 2;
      r.W(s, p) -= cot / 2;
      r.W(p, p) += cot / 2;
      r.W(s, s) += cot / 2;
      r.mass[q] += area / 3;
      edge_faces[std::minmax(p, s)] += 1;
      nb[q].push_back(p);
      nb[q].push_back(s);
    }
  }
  r.boundary.assign(n, false);
  for (const auto& [e, count] : edge_faces)
    if (count == 1) r.boundary[e.first] = r.boundary[e.second] = true;
  std::vector<double> K(n);
  for (std::size_t i = 0; i < n; ++i) K[i] = ((r.boundary[i] ? kPi : 2 * kPi) - angle[i]) / r.mass[i];
  r.si_mass.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::sort(nb[i].begin(), nb[i].end());
    nb[i].erase(std::unique(nb[i].begin(), nb[i].end()), nb[i].end());
    double ks = 0;
    for (auto j : nb[i]) ks += K[j];
    ks /= static_cast<double>(nb[i].size());
    r.si_mass[i] = std::pow(1e-8 + ks * ks, alpha / 2) * r.mass[i];
  }
  return r;
}

static std::vector<double> dense_spectrum(const Reference& r, const std::vector<double>& mass, std::size_t k) {
  std::vector<Eigen::Index> free;
  for (std::size_t i = 0; i < r.boundary.size(); ++i)
    if (!r.boundary[i]) free.push_back(static_cast<Eigen::Index>(i));
  const auto nf = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd A(nf, nf), B = Eigen::MatrixXd::Zero(nf, nf);
  for (Eigen::Index a = 0; a < nf; ++a) {
    for (Eigen::Index b = 0; b < nf; ++b) A(a, b) = r.W(free[a], free[b]);
    B(a, a) = mass[static_cast<std::size_t>(free[a])];
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(A, B, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) throw std::runtime_error("Eigen generalized eigensolve failed");
  std::vector<double> out(k);
  for (std::size_t i = 0; i < k; ++i) out[i] = es.eigenvalues()(static_cast<Eigen::Index>(i));  // ascending
  return out;
}

static void compare(const std::string& name, const dstest::SimpleMesh& m, std::size_t k) {
  const double alpha = 0.33;
  const auto t0 = std::chrono::steady_clock::now();
  const dualspectra::Mesh mesh(m.V, m.F);
  const Reference ref = build_reference(m, alpha);
  std::size_t n_free = 0;
  for (bool b : ref.boundary) n_free += !b;
  std::printf("\n%s: %zu vertices, %zu interior\n", name.c_str(), m.V.size(), n_free);
  for (auto metric : {dualspectra::Metric::Regular, dualspectra::Metric::ScaleInvariant}) {
    const bool si = metric == dualspectra::Metric::ScaleInvariant;
    const char* mname = si ? "scale-invariant" : "regular";
    const auto& rmass = si ? ref.si_mass : ref.mass;
    const auto mass = dualspectra::mass(mesh, metric, alpha);
    double merr = 0;
    for (std::size_t i = 0; i < mass.size(); ++i) merr = std::max(merr, std::abs(mass[i] - rmass[i]) / rmass[i]);
    T.check(merr < 1e-12, name + ", " + mname + " mass vs the formula: max relative error " + std::to_string(merr) + " < 1e-12");

    const auto ours = dualspectra::spectrum(mesh, k, metric, alpha);
    const auto dense = dense_spectrum(ref, rmass, k);
    const double scale = std::abs(dense.back());
    double max_rel = 0, max_abs = 0;
    for (std::size_t i = 0; i < k; ++i) {
      const double e = std::abs(ours[i] - dense[i]);
      max_abs = std::max(max_abs, e);
      max_rel = std::max(max_rel, std::abs(dense[i]) > 1e-8 * scale ? e / std::abs(dense[i]) : e / scale);
    }
    std::printf("  %-16s lambda_1..%zu: ours [%.10g, %.10g, %.10g, ..., %.10g]\n"
                "  %-16s                dense[%.10g, %.10g, %.10g, ..., %.10g]\n"
                "  %-16s max abs error %.3e, max relative error %.3e\n",
                mname, k, ours[0], ours[1], ours[2], ours[k - 1], "", dense[0], dense[1], dense[2], dense[k - 1], "", max_abs, max_rel);
    char buf[160];
    std::snprintf(buf, sizeof buf, ", %s Dirichlet spectrum (k=%zu) vs Eigen dense generalized eigensolve: relative error %.3e < 1e-8",
                  mname, k, max_rel);
    T.check(ours.size() == k && max_rel < 1e-8, name + buf);
  }
  std::printf("  (%.2f s)\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

int main() {
  try {
    compare("bumpy sphere level 3 (closed, no boundary condition)", dstest::bumpy_sphere(3), 20);
    compare("bumpy patch 36x36 (Dirichlet boundary)", dstest::bumpy_patch(36), 20);
  } catch (const std::exception& e) {
    T.check(false, std::string("unexpected exception: ") + e.what());
  }
  std::printf("\n%d failure(s)\n", T.failures);
  return T.failures == 0 ? 0 : 1;
}

// dualspectra C++ API: partial shape localization by multi-metric Hamiltonian spectra matching.
//
// A thin layer over the Rust core through a cxx bridge (rust/dualspectra-ffi/src/cxx_bridge.rs);
// every computation happens in Rust. Errors are thrown as dualspectra::Error (a
// std::runtime_error with a Status). Meshes are immutable and may be shared between threads.
//
//   #include <dualspectra/dualspectra.hpp>
//   dualspectra::Mesh full(V, F), part(Vp, Fp);          // std::vector<std::array<...,3>>
//   dualspectra::Localization r = dualspectra::localize(full, part);
//   for (std::size_t i = 0; i < r.region.size(); ++i) if (r.region[i]) ...;
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "rust/cxx.h"
#include "dualspectra-ffi/src/cxx_bridge.rs.h"  // generated: Options, Timings, Mode, Selection, StartShape, Metric, Status

namespace dualspectra {

// Thrown by every function of this header on failure.
class Error : public std::runtime_error {
 public:
  Error(Status status, const std::string& what) : std::runtime_error(what), status_(status) {}
  // InvalidArgument, InvalidMesh, Numerical, Cancelled, Panic (a bug) or Io.
  Status status() const noexcept { return status_; }

 private:
  Status status_;
};

// A validated triangle mesh: vertex positions and 0-based triangles. Construction checks
// indices in range, finite coordinates, no degenerate or repeated-vertex faces,
// edge/vertex-manifoldness and no isolated vertices; it throws Error(Status::InvalidMesh)
// otherwise. The arrays are copied. Operators (stiffness, mass, curvature) are computed once
// on first use and cached.
class Mesh {
 public:
  // Flat arrays: positions[3*i + d], triangles[3*f + c].
  Mesh(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles, std::size_t n_faces);
  Mesh(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles);
  Mesh(const std::vector<std::array<double, 3>>& vertices, const std::vector<std::array<std::uint32_t, 3>>& faces);

  std::size_t n_vertices() const noexcept { return data_->n_vertices(); }
  std::size_t n_faces() const noexcept { return data_->n_faces(); }
  std::vector<std::array<double, 3>> vertices() const;
  std::vector<std::array<std::uint32_t, 3>> faces() const;

  const detail::MeshData& data() const noexcept { return *data_; }

 private:
  rust::Box<detail::MeshData> data_;
};

// The result of localize(); per-vertex arrays are indexed by the full mesh's vertices.
struct Localization {
  std::vector<bool> region;            // true: vertex in the matched region
  std::vector<double> score;           // soft membership in [0, 1]
  std::vector<double> potential;       // optimised potential v >= 0
  std::vector<double> eigenvalues_regular;  // Hamiltonian eigenvalues at the optimum (empty in Si mode)
  std::vector<double> eigenvalues_si;       // (empty in Lbo mode)
  std::vector<double> target_regular;       // the partial shape's Dirichlet eigenvalues
  std::vector<double> target_si;
  double cost = 0.0;                   // final alignment cost of the selected start
  std::size_t selected_start = 0;
  std::size_t n_starts = 0;
  Timings timings{};                   // wall-clock seconds per stage
  std::vector<std::string> warnings;   // repairs made to the input (e.g. partial reduced to its largest component)

  // Indices of the vertices in the region, ascending.
  std::vector<std::uint32_t> region_vertices() const;
};

// fraction in [0, 1] of the whole computation, stage a short name; return false to cancel
// (localize then throws Error(Status::Cancelled)). An exception thrown by the callback cancels
// the computation and is rethrown by localize. Calls are serialized but may come from a
// worker thread.
using ProgressCallback = std::function<bool(double fraction, std::string_view stage)>;

// The library's defaults (Mode::Dual, k = 20, alpha = 0.33, seed 0, optimisation on a 1000-vertex
// decimation, 4 centres x 3 starts, 25 trust-region iterations, all cores, gated selection).
Options default_options();

// Find the region of `full` that `partial` corresponds to.
Localization localize(const Mesh& full, const Mesh& partial, const Options& options = default_options(),
                      const ProgressCallback& progress = {});

// Pointwise Gaussian curvature per vertex: angle defect over barycentric area; with
// smoothed = true, then the one-ring mean (what the scale-invariant metric uses).
std::vector<double> gaussian_curvature(const Mesh& mesh, bool smoothed = false);

// A sparse n x n matrix as coordinate triplets (entry rows[i], cols[i] has value values[i];
// no duplicates).
struct SparseMatrix {
  std::size_t n = 0;
  std::vector<std::uint32_t> rows, cols;
  std::vector<double> values;
};

// The cotangent stiffness matrix W (symmetric positive semi-definite, rows sum to 0):
// W_ij = -(cot a_ij + cot b_ij) / 2 for an edge ij, W_ii = -sum_j W_ij; W = -L for libigl's
// cotmatrix L.
SparseMatrix cotangent_stiffness(const Mesh& mesh);

// The lumped mass diagonal of `metric`: a_i = (area of the faces at i) / 3 (Regular), or
// s_i a_i with s = (1e-8 + K_smoothed^2)^(alpha/2) (ScaleInvariant).
std::vector<double> mass(const Mesh& mesh, Metric metric = Metric::Regular);
std::vector<double> mass(const Mesh& mesh, Metric metric, double alpha);

// The k smallest eigenvalues (ascending) of the Dirichlet Laplacian in `metric` (no boundary
// condition on a closed mesh, where the first eigenvalue is 0). For Metric::ScaleInvariant the
// metric is s g with s = (1e-8 + K^2)^(alpha/2), K the smoothed Gaussian curvature.
std::vector<double> spectrum(const Mesh& mesh, std::size_t k, Metric metric = Metric::Regular);
std::vector<double> spectrum(const Mesh& mesh, std::size_t k, Metric metric, double alpha);

// The library version, e.g. "0.1.0".
std::string version();

}  // namespace dualspectra

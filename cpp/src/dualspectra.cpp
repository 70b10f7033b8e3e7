// Implementation of the C++ API (dualspectra/dualspectra.hpp): conversion between std
// containers and the cxx bridge, and rust::Error -> dualspectra::Error. No computation here.
// Compiled into the Rust static library by rust/dualspectra-ffi/build.rs (cxx_build).
#include "dualspectra/dualspectra.hpp"

#include "dualspectra/dualspectra.h"
#include "dualspectra/detail/progress_sink.hpp"

#include <limits>
#include <type_traits>

namespace dualspectra {

// The C++ enums mirror the C API's codes.
static_assert(static_cast<std::int32_t>(Status::Ok) == DS_OK, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::InvalidArgument) == DS_INVALID_ARGUMENT, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::InvalidMesh) == DS_INVALID_MESH, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Numerical) == DS_NUMERICAL, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Cancelled) == DS_CANCELLED, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Panic) == DS_PANIC, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Io) == DS_IO, "Status mirrors ds_status");
static_assert(static_cast<std::uint32_t>(Mode::Dual) == DS_MODE_DUAL, "Mode mirrors ds_mode");
static_assert(static_cast<std::uint32_t>(Mode::Lbo) == DS_MODE_LBO, "Mode mirrors ds_mode");
static_assert(static_cast<std::uint32_t>(Mode::Si) == DS_MODE_SI, "Mode mirrors ds_mode");
static_assert(static_cast<std::uint32_t>(Selection::Descriptors) == DS_SELECTION_DESCRIPTORS, "Selection mirrors ds_selection");
static_assert(static_cast<std::uint32_t>(Selection::Cost) == DS_SELECTION_COST, "Selection mirrors ds_selection");
static_assert(static_cast<std::uint32_t>(StartShape::BallsAndWideBumps) == DS_STARTS_BALLS_AND_WIDE_BUMPS, "StartShape mirrors ds_start_shape");
static_assert(static_cast<std::uint32_t>(StartShape::BallsAndWideGaussians) == DS_STARTS_BALLS_AND_WIDE_GAUSSIANS, "StartShape mirrors ds_start_shape");
static_assert(static_cast<std::uint32_t>(StartShape::Gaussian) == DS_STARTS_GAUSSIAN, "StartShape mirrors ds_start_shape");
static_assert(static_cast<std::uint32_t>(StartShape::AreaBall) == DS_STARTS_AREA_BALL, "StartShape mirrors ds_start_shape");
static_assert(static_cast<std::uint32_t>(Metric::Regular) == DS_METRIC_REGULAR, "Metric mirrors ds_metric");
static_assert(static_cast<std::uint32_t>(Metric::ScaleInvariant) == DS_METRIC_SCALE_INVARIANT, "Metric mirrors ds_metric");
static_assert(sizeof(Timings) == sizeof(ds_timings) && std::is_standard_layout<Timings>::value, "Timings mirrors ds_timings");
static_assert(sizeof(std::array<double, 3>) == 3 * sizeof(double), "std::array<double, 3> is packed");
static_assert(sizeof(std::array<std::uint32_t, 3>) == 3 * sizeof(std::uint32_t), "std::array<uint32_t, 3> is packed");

namespace {

// Runs a bridge call, turning its rust::Error into a dualspectra::Error with the status the
// Rust side recorded for this thread.
template <class F>
auto translated(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const rust::Error& e) {
    throw Error(detail::last_error_status(), e.what());
  }
}

std::vector<double> to_std(const rust::Vec<double>& v) { return std::vector<double>(v.begin(), v.end()); }

rust::Box<detail::MeshData> make_mesh(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles,
                                      std::size_t n_faces) {
  constexpr std::size_t max = std::numeric_limits<std::size_t>::max() / 3;
  if (n_vertices > max || n_faces > max) throw Error(Status::InvalidArgument, "mesh size overflows");
  if ((positions == nullptr && n_vertices != 0) || (triangles == nullptr && n_faces != 0))
    throw Error(Status::InvalidArgument, "null array with a non-zero length");
  // rust::Slice requires a non-null pointer even when empty.
  static const double no_positions = 0.0;
  static const std::uint32_t no_triangles = 0;
  rust::Slice<const double> p(n_vertices ? positions : &no_positions, 3 * n_vertices);
  rust::Slice<const std::uint32_t> t(n_faces ? triangles : &no_triangles, 3 * n_faces);
  return translated([&] { return detail::mesh_from_arrays(p, t); });
}

}  // namespace

namespace detail {

bool ProgressSink::report(double fraction, rust::Str stage) const noexcept {
  if (!callback_ || error_) return !error_;
  try {
    return callback_(fraction, std::string_view(stage.data(), stage.size()));
  } catch (...) {
    error_ = std::current_exception();
    return false;
  }
}

void ProgressSink::rethrow_if_failed() const {
  if (error_) std::rethrow_exception(error_);
}

}  // namespace detail

Mesh::Mesh(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles, std::size_t n_faces)
    : data_(make_mesh(positions, n_vertices, triangles, n_faces)) {}

Mesh::Mesh(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles)
    : data_(positions.size() % 3 != 0 || triangles.size() % 3 != 0
                ? throw Error(Status::InvalidArgument, "positions and triangles must have a multiple of 3 entries")
                : make_mesh(positions.data(), positions.size() / 3, triangles.data(), triangles.size() / 3)) {}

Mesh::Mesh(const std::vector<std::array<double, 3>>& vertices,
           const std::vector<std::array<std::uint32_t, 3>>& faces)
    : data_(make_mesh(vertices.empty() ? nullptr : vertices.front().data(), vertices.size(),
                      faces.empty() ? nullptr : faces.front().data(), faces.size())) {}

std::vector<std::array<double, 3>> Mesh::vertices() const {
  rust::Slice<const double> p = data_->positions();
  std::vector<std::array<double, 3>> out(p.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  return out;
}

std::vector<std::array<std::uint32_t, 3>> Mesh::faces() const {
  rust::Slice<const std::uint32_t> t = data_->triangles();
  std::vector<std::array<std::uint32_t, 3>> out(t.size() / 3);
  for (std::size_t f = 0; f < out.size(); ++f) out[f] = {t[3 * f], t[3 * f + 1], t[3 * f + 2]};
  return out;
}

std::vector<std::uint32_t> Localization::region_vertices() const {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i]) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

Options default_options() { return detail::default_options(); }

Localization localize(const Mesh& full, const Mesh& partial, const Options& options, const ProgressCallback& progress) {
  detail::ProgressSink sink(progress);
  detail::LocalizationData d;
  try {
    d = translated([&] { return detail::localize(full.data(), partial.data(), options, sink); });
  } catch (const Error&) {
    sink.rethrow_if_failed();  // the callback's own exception wins over "cancelled"
    throw;
  }
  Localization r;
  r.region.assign(d.region.begin(), d.region.end());
  r.score = to_std(d.score);
  r.potential = to_std(d.potential);
  r.eigenvalues_regular = to_std(d.eigenvalues_regular);
  r.eigenvalues_si = to_std(d.eigenvalues_si);
  r.target_regular = to_std(d.target_regular);
  r.target_si = to_std(d.target_si);
  r.cost = d.cost;
  r.selected_start = d.selected_start;
  r.n_starts = d.n_starts;
  r.timings = d.timings;
  for (const rust::String& w : d.warnings) r.warnings.emplace_back(std::string(w));
  return r;
}

std::vector<double> gaussian_curvature(const Mesh& mesh, bool smoothed) {
  return to_std(translated([&] { return detail::gaussian_curvature(mesh.data(), smoothed); }));
}

SparseMatrix cotangent_stiffness(const Mesh& mesh) {
  detail::TripletData t = translated([&] { return detail::cotangent_stiffness(mesh.data()); });
  SparseMatrix m;
  m.n = t.n;
  m.rows.assign(t.rows.begin(), t.rows.end());
  m.cols.assign(t.cols.begin(), t.cols.end());
  m.values = to_std(t.values);
  return m;
}

std::vector<double> mass(const Mesh& mesh, Metric metric) { return mass(mesh, metric, default_options().alpha); }

std::vector<double> mass(const Mesh& mesh, Metric metric, double alpha) {
  return to_std(translated([&] { return detail::mass(mesh.data(), metric, alpha); }));
}

std::vector<double> spectrum(const Mesh& mesh, std::size_t k, Metric metric) {
  return spectrum(mesh, k, metric, default_options().alpha);
}

std::vector<double> spectrum(const Mesh& mesh, std::size_t k, Metric metric, double alpha) {
  return to_std(translated([&] { return detail::spectrum(mesh.data(), k, metric, alpha); }));
}

std::string version() { return std::string(detail::version()); }

}  // namespace dualspectra

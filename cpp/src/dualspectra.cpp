// Implementation of the C++ API (dualspectra/dualspectra.hpp): conversion between std
// containers and the cxx bridge, and rust::Error -> dualspectra::Error. No computation here.
// Compiled into the Rust static library by rust/dualspectra-ffi/build.rs (cxx_build).
#include "dualspectra/dualspectra.hpp"

#include "dualspectra/dualspectra.h"
#include "dualspectra/detail/progress_sink.hpp"

#include <limits>
#include <type_traits>

namespace dualspectra {

// The C++ enums and structs mirror the C API's.
static_assert(static_cast<std::int32_t>(Status::Ok) == DS_OK, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::InvalidArgument) == DS_INVALID_ARGUMENT, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::InvalidMesh) == DS_INVALID_MESH, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Numerical) == DS_NUMERICAL, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Cancelled) == DS_CANCELLED, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Panic) == DS_PANIC, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::Io) == DS_IO, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::OutOfMemory) == DS_OUT_OF_MEMORY, "Status mirrors ds_status");
static_assert(static_cast<std::int32_t>(Status::InvalidPreparedShape) == DS_INVALID_PREPARED_SHAPE,
              "Status mirrors ds_status");
static_assert(static_cast<std::uint32_t>(Metric::Regular) == DS_METRIC_REGULAR, "Metric mirrors ds_metric");
static_assert(static_cast<std::uint32_t>(Metric::ScaleInvariant) == DS_METRIC_SCALE_INVARIANT, "Metric mirrors ds_metric");
static_assert(sizeof(Timings) == sizeof(ds_timings) && std::is_standard_layout<Timings>::value, "Timings mirrors ds_timings");
static_assert(offsetof(Timings, preparation) == offsetof(ds_timings, preparation) &&
                  offsetof(Timings, selection) == offsetof(ds_timings, selection) &&
                  offsetof(Timings, total) == offsetof(ds_timings, total),
              "Timings mirrors ds_timings field by field");
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

// A bridge call that reports progress to `sink`: the callback's own exception wins over the
// "cancelled" it caused.
template <class F>
auto with_progress(const detail::ProgressSink& sink, F&& f) -> decltype(f()) {
  try {
    return translated(std::forward<F>(f));
  } catch (const Error&) {
    sink.rethrow_if_failed();
    throw;
  }
}

std::vector<double> to_std(const rust::Vec<double>& v) { return std::vector<double>(v.begin(), v.end()); }

rust::Str str_of(std::string_view s) { return rust::Str(s.data(), s.size()); }

// The bytes of a file name (any bytes: the Rust side takes them as the OS does).
rust::Slice<const std::uint8_t> bytes_of(const std::string& s) {
  return rust::Slice<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
}

// The flat arrays as bridge slices, checked for sizes (rust::Slice needs a non-null pointer
// even when empty).
struct Arrays {
  rust::Slice<const double> positions;
  rust::Slice<const std::uint32_t> triangles;
};

Arrays arrays(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles, std::size_t n_faces) {
  constexpr std::size_t max = std::numeric_limits<std::size_t>::max() / 3;
  if (n_vertices > max || n_faces > max) throw Error(Status::InvalidArgument, "mesh size overflows");
  if ((positions == nullptr && n_vertices != 0) || (triangles == nullptr && n_faces != 0))
    throw Error(Status::InvalidArgument, "null array with a non-zero length");
  static const double no_positions = 0.0;
  static const std::uint32_t no_triangles = 0;
  return {rust::Slice<const double>(n_vertices ? positions : &no_positions, 3 * n_vertices),
          rust::Slice<const std::uint32_t>(n_faces ? triangles : &no_triangles, 3 * n_faces)};
}

rust::Box<detail::MeshData> strict_mesh(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles,
                                        std::size_t n_faces) {
  const Arrays a = arrays(positions, n_vertices, triangles, n_faces);
  return translated([&] { return detail::mesh_from_arrays(a.positions, a.triangles); });
}

void check_flat(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles) {
  if (positions.size() % 3 != 0 || triangles.size() % 3 != 0)
    throw Error(Status::InvalidArgument, "positions and triangles must have a multiple of 3 entries");
}

Localization to_localization(const detail::LocalizationData& d) {
  Localization r;
  r.region.assign(d.region.begin(), d.region.end());
  r.score = to_std(d.score);
  r.potential = to_std(d.potential);
  r.eigenvalues_regular = to_std(d.eigenvalues_regular);
  r.eigenvalues_si = to_std(d.eigenvalues_si);
  r.target_regular = to_std(d.target_regular);
  r.target_si = to_std(d.target_si);
  r.cost = d.cost;
  r.confidence = d.confidence;
  r.scale = d.scale;
  r.similarity_score = d.similarity_score;
  r.optimisation_vertices = d.optimisation_vertices;
  r.selected_start = d.selected_start;
  r.n_starts = d.n_starts;
  r.timings = d.timings;
  for (const rust::String& w : d.warnings) r.warnings.emplace_back(std::string(w));
  return r;
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

// ---------------------------------------------------------------------------------------------
// Mesh

Mesh::Mesh(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles, std::size_t n_faces)
    : data_(strict_mesh(positions, n_vertices, triangles, n_faces)) {}

Mesh::Mesh(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles)
    : data_((check_flat(positions, triangles),
             strict_mesh(positions.data(), positions.size() / 3, triangles.data(), triangles.size() / 3))) {}

Mesh::Mesh(const std::vector<std::array<double, 3>>& vertices,
           const std::vector<std::array<std::uint32_t, 3>>& faces)
    : data_(strict_mesh(vertices.empty() ? nullptr : vertices.front().data(), vertices.size(),
                        faces.empty() ? nullptr : faces.front().data(), faces.size())) {}

Mesh Mesh::from_host(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles,
                     std::size_t n_faces) {
  const Arrays a = arrays(positions, n_vertices, triangles, n_faces);
  return Mesh(translated([&] { return detail::mesh_from_host(a.positions, a.triangles); }));
}

Mesh Mesh::from_host(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles) {
  check_flat(positions, triangles);
  return from_host(positions.data(), positions.size() / 3, triangles.data(), triangles.size() / 3);
}

Mesh Mesh::from_host(const std::vector<std::array<double, 3>>& vertices,
                     const std::vector<std::array<std::uint32_t, 3>>& faces) {
  return from_host(vertices.empty() ? nullptr : vertices.front().data(), vertices.size(),
                   faces.empty() ? nullptr : faces.front().data(), faces.size());
}

Mesh Mesh::read(const std::string& path) {
  return Mesh(translated([&] { return detail::mesh_read(bytes_of(path)); }));
}

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

std::vector<std::uint32_t> Mesh::used_vertices() const {
  const rust::Vec<std::uint32_t> used = data_->used_vertices();
  return std::vector<std::uint32_t>(used.begin(), used.end());
}

std::string Mesh::warning() const { return std::string(data_->warning()); }

// ---------------------------------------------------------------------------------------------
// Options

Options::Options() : data_(detail::options_new()) {}

Options::Options(const Options& other) : data_(detail::options_clone(*other.data_)) {}

Options& Options::operator=(const Options& other) {
  if (this != &other) data_ = detail::options_clone(*other.data_);
  return *this;
}

Options Options::from_json(std::string_view json_object) {
  Options o;
  o.set_json(json_object);
  return o;
}

Options& Options::set(std::string_view name, std::string_view value) {
  translated([&] { detail::options_set_text(*data_, str_of(name), str_of(value)); });
  return *this;
}

Options& Options::set(std::string_view name, double value) {
  translated([&] { detail::options_set_f64(*data_, str_of(name), value); });
  return *this;
}

Options& Options::set_integer(std::string_view name, long long value) {
  translated([&] { detail::options_set_i64(*data_, str_of(name), static_cast<std::int64_t>(value)); });
  return *this;
}

Options& Options::set_unsigned(std::string_view name, unsigned long long value) {
  translated([&] { detail::options_set_u64(*data_, str_of(name), static_cast<std::uint64_t>(value)); });
  return *this;
}

Options& Options::set_json(std::string_view json_object) {
  translated([&] { detail::options_set_json(*data_, str_of(json_object)); });
  return *this;
}

std::string Options::json() const { return std::string(detail::options_json(*data_)); }

std::string Options::schema() { return std::string(detail::options_schema()); }

// ---------------------------------------------------------------------------------------------
// Localization

std::vector<std::uint32_t> Localization::region_vertices() const {
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < region.size(); ++i)
    if (region[i]) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

namespace {
rust::Box<detail::LocalizerData> prepare(const Mesh& full, const Options& options, const ProgressCallback& progress) {
  const detail::ProgressSink sink(progress);
  return with_progress(sink, [&] { return detail::localizer_new(full.data(), options.data(), sink); });
}
}  // namespace

Localizer::Localizer(const Mesh& full, const Options& options, const ProgressCallback& progress)
    : data_(prepare(full, options, progress)) {}

Localization Localizer::locate(const Mesh& partial, const ProgressCallback& progress) const {
  const detail::ProgressSink sink(progress);
  return to_localization(with_progress(sink, [&] { return detail::localizer_locate(*data_, partial.data(), sink); }));
}

std::vector<std::string> Localizer::warnings() const {
  std::vector<std::string> out;
  for (const rust::String& w : data_->warnings()) out.emplace_back(std::string(w));
  return out;
}

Options Localizer::options() const { return Options(data_->options()); }

Localizer Localizer::load(const std::string& path) {
  return Localizer(translated([&] { return detail::localizer_load(bytes_of(path)); }));
}

void Localizer::save(const std::string& path) const {
  translated([&] { detail::localizer_save(*data_, bytes_of(path)); });
}

std::vector<Match> search(const Mesh& partial, const std::vector<const Localizer*>& localizers, std::size_t top,
                          const ProgressCallback& progress, std::size_t shortlist) {
  rust::Box<detail::LocalizerList> list = detail::localizer_list_new();
  for (std::size_t i = 0; i < localizers.size(); ++i) {
    if (localizers[i] == nullptr)
      throw Error(Status::InvalidArgument, "localizers[" + std::to_string(i) + "] is null");
    list->push(localizers[i]->data());
  }
  const detail::ProgressSink sink(progress);
  const rust::Vec<detail::MatchData> found =
      with_progress(sink, [&] { return detail::search(partial.data(), *list, top, shortlist, sink); });
  std::vector<Match> out;
  out.reserve(found.size());
  for (const detail::MatchData& d : found) {
    Match m;
    m.index = d.index;
    m.score = d.score;
    m.located = d.located;
    if (d.located) m.localization = to_localization(d.localization);
    m.error = std::string(d.error);
    m.screen_score = d.screen_score;
    m.quick = d.quick;
    m.confidence = d.confidence;
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<Match> search(const Mesh& partial, const std::vector<Localizer>& localizers, std::size_t top,
                          const ProgressCallback& progress, std::size_t shortlist) {
  std::vector<const Localizer*> pointers;
  pointers.reserve(localizers.size());
  for (const Localizer& l : localizers) pointers.push_back(&l);
  return search(partial, pointers, top, progress, shortlist);
}

Localization localize(const Mesh& full, const Mesh& partial, const Options& options, const ProgressCallback& progress) {
  const detail::ProgressSink sink(progress);
  return to_localization(
      with_progress(sink, [&] { return detail::localize(full.data(), partial.data(), options.data(), sink); }));
}

// ---------------------------------------------------------------------------------------------
// Per-mesh quantities

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

std::vector<double> mass(const Mesh& mesh, Metric metric) { return mass(mesh, metric, detail::default_alpha()); }

std::vector<double> mass(const Mesh& mesh, Metric metric, double alpha) {
  return to_std(translated([&] { return detail::mass(mesh.data(), metric, alpha); }));
}

std::vector<double> spectrum(const Mesh& mesh, std::size_t k, Metric metric) {
  return spectrum(mesh, k, metric, detail::default_alpha());
}

std::vector<double> spectrum(const Mesh& mesh, std::size_t k, Metric metric, double alpha) {
  return to_std(translated([&] { return detail::spectrum(mesh.data(), k, metric, alpha); }));
}

std::string version() { return std::string(detail::version()); }

}  // namespace dualspectra

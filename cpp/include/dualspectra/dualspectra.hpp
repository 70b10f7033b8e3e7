// dualspectra C++ API: partial shape localization by multi-metric Hamiltonian spectra matching.
//
// A thin layer over the Rust core through a cxx bridge (rust/dualspectra-ffi/src/cxx_bridge.rs);
// every computation happens in Rust. Errors are thrown as dualspectra::Error (a
// std::runtime_error with a Status). Meshes and localizers are immutable and may be shared
// between threads.
//
//   #include <dualspectra/dualspectra.hpp>
//   dualspectra::Mesh full(V, F), part(Vp, Fp);          // std::vector<std::array<...,3>>
//   dualspectra::Mesh scan = dualspectra::Mesh::read("scan.ply");  // or a file: OFF, OBJ, PLY
//   dualspectra::Options opts;
//   opts.set("k", 10).set("mode", "dual");                // names and ranges: Options::schema()
//   dualspectra::Localization r = dualspectra::localize(full, part, opts);
//   for (std::size_t i = 0; i < r.region.size(); ++i) if (r.region[i]) ...;
//
//   dualspectra::Localizer prepared(full, opts);          // several partials on one full mesh:
//   auto a = prepared.locate(part_a), b = prepared.locate(part_b);  // prepared once
//   prepared.save("full.dsprep");                          // later: Localizer::load("full.dsprep")
//
//   std::vector<dualspectra::Localizer> library = ...;     // which model is the part from?
//   std::vector<dualspectra::Match> ranked = dualspectra::search(part, library);  // best first
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "rust/cxx.h"
#include "dualspectra-ffi/src/cxx_bridge.rs.h"  // generated: Timings, Metric, Status, detail::*

namespace dualspectra {

// Thrown by every function of this header on failure.
class Error : public std::runtime_error {
 public:
  Error(Status status, const std::string& what) : std::runtime_error(what), status_(status) {}
  // InvalidArgument, InvalidMesh, Numerical, Cancelled, Panic (a bug), Io or
  // InvalidPreparedShape (Localizer::load: a foreign, stale, truncated or corrupted file).
  Status status() const noexcept { return status_; }

 private:
  Status status_;
};

// A validated triangle mesh. The arrays are copied; operators (stiffness, mass, curvature) are
// computed once on first use and cached.
//
// Two ways in:
//  - the constructors check strictly: indices in range, finite coordinates, no degenerate or
//    repeated-vertex face, edge/vertex-manifold, no vertex in no face; otherwise they throw
//    Error(Status::InvalidMesh) with the reason;
//  - Mesh::from_host takes a host's arrays (an editor's mesh, a scan, a file) through the
//    core's intake: faces that repeat a vertex or have zero area are left out; non-manifold
//    edges (in more than two faces) and vertices (faces in several fans) are split, each
//    extra fan of a vertex getting a copy of it (no face removed); then vertices in no face
//    are left out. warning() says what was left out or split. Every per-vertex array in or
//    out (curvature, mass, the Localization) stays in the host's numbering: 0 / false at the
//    left-out vertices; a split vertex is in a region if any copy is, its curvature and
//    score are its first copy's, its mass the sum over its copies. What cannot be used still
//    throws Error(Status::InvalidMesh), with vertex and face numbers as the host's: an index
//    out of range, a non-finite coordinate, no faces, every face degenerate;
//  - Mesh::read reads a file as the command line and Python's read_mesh do (below).
class Mesh {
 public:
  // Flat arrays: positions[3*i + d], triangles[3*f + c].
  Mesh(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles, std::size_t n_faces);
  Mesh(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles);
  Mesh(const std::vector<std::array<double, 3>>& vertices, const std::vector<std::array<std::uint32_t, 3>>& faces);

  static Mesh from_host(const double* positions, std::size_t n_vertices, const std::uint32_t* triangles,
                        std::size_t n_faces);
  static Mesh from_host(const std::vector<double>& positions, const std::vector<std::uint32_t>& triangles);
  static Mesh from_host(const std::vector<std::array<double, 3>>& vertices,
                        const std::vector<std::array<std::uint32_t, 3>>& faces);

  // Read an OFF, OBJ or PLY file (ASCII or binary; the format from the extension). Polygons
  // are fan-triangulated; a triangle listed twice in opposite orientations (a two-sided flap)
  // is removed with the vertices only it used; non-manifold edges and vertices are split, the
  // copies appended after the file's vertices. warning() then says so, naming the file: the
  // mesh's numbering (vertices(), every per-vertex array) is its own, not the file's. Throws
  // Error(Status::Io) when the file cannot be read or is not a mesh of its format, and
  // Error(Status::InvalidMesh) for an index out of range, a non-finite coordinate, no faces,
  // a zero-area face or a vertex in no face; the message names the file.
  static Mesh read(const std::string& path);

  // Vertices in the host's numbering: the length of every per-vertex array.
  std::size_t n_vertices() const noexcept { return data_->n_vertices(); }
  // Faces used (for from_host: less those left out).
  std::size_t n_faces() const noexcept { return data_->n_faces(); }
  // The mesh the core works on: the used vertices (in host order), then the copies of split
  // non-manifold vertices, and faces into them. For a strictly checked mesh, the given arrays.
  std::vector<std::array<double, 3>> vertices() const;
  std::vector<std::array<std::uint32_t, 3>> faces() const;
  // Host index of each vertex of vertices(): the used host vertices (increasing), then each
  // copy of a split non-manifold vertex as its host vertex's index (so not increasing, and
  // repeated, when something was split); 0, 1, 2, ... for a strictly checked mesh.
  std::vector<std::uint32_t> used_vertices() const;
  // What the intake left out or split, or reading the file repaired, as a sentence ("" if
  // nothing).
  std::string warning() const;

  const detail::MeshData& data() const noexcept { return *data_; }

 private:
  explicit Mesh(rust::Box<detail::MeshData> data) : data_(std::move(data)) {}
  rust::Box<detail::MeshData> data_;
};

// Options of the localizer, by name. The names, labels, types, ranges, defaults and docs are
// the core's (Options::schema()), so a new core option needs no change here. A value out of
// range, of the wrong type or an unknown name throws Error(Status::InvalidArgument) naming the
// option and its range, and leaves the options unchanged.
//
//   dualspectra::Options o;                       // the defaults
//   o.set("k", 10).set("alpha", 0.5).set("mode", "lbo").set("plane_cuts", "14");
class Options {
 public:
  Options();
  Options(const Options& other);
  Options& operator=(const Options& other);
  Options(Options&&) noexcept = default;
  Options& operator=(Options&&) noexcept = default;

  // The defaults with the options of a JSON object set ({"k": 10, "mode": "lbo"}).
  static Options from_json(std::string_view json_object);

  // Set from text ("20", "0.5", "dual"), as a command line or a GUI gives it.
  Options& set(std::string_view name, std::string_view value);
  Options& set(std::string_view name, const char* value) { return set(name, std::string_view(value)); }
  Options& set(std::string_view name, const std::string& value) { return set(name, std::string_view(value)); }
  // Set a number (an integer option refuses a fractional or negative value).
  template <class T, std::enable_if_t<std::is_integral<T>::value && !std::is_same<T, bool>::value, int> = 0>
  Options& set(std::string_view name, T value) {
    if (std::is_signed<T>::value) return set_integer(name, static_cast<long long>(value));
    return set_unsigned(name, static_cast<unsigned long long>(value));
  }
  Options& set(std::string_view name, double value);
  // Set the options of a JSON object on top of these (all or none).
  Options& set_json(std::string_view json_object);

  // Every option's value as a JSON object ({"mode":"dual","k":20,...}).
  std::string json() const;
  // Every option as a JSON array of {"name", "label", "type" ("int", "float", "choice"),
  // "min", "max" | "choices", "default", "doc"}, in the order front ends list them.
  static std::string schema();

  const detail::OptionsData& data() const noexcept { return *data_; }

 private:
  explicit Options(rust::Box<detail::OptionsData> data) : data_(std::move(data)) {}
  Options& set_integer(std::string_view name, long long value);
  Options& set_unsigned(std::string_view name, unsigned long long value);
  rust::Box<detail::OptionsData> data_;
  friend class Localizer;
};

// The result of a localization; per-vertex arrays are indexed by the full mesh's vertices (in
// its host's numbering, see Mesh::from_host).
struct Localization {
  std::vector<bool> region;            // true: vertex in the matched region
  std::vector<double> score;           // soft membership in [0, 1]
  std::vector<double> potential;       // optimised potential v >= 0
  std::vector<double> eigenvalues_regular;  // Hamiltonian eigenvalues at the optimum (empty in si mode)
  std::vector<double> eigenvalues_si;       // (empty in lbo mode)
  std::vector<double> target_regular;       // the partial shape's Dirichlet eigenvalues
  std::vector<double> target_si;
  double cost = 0.0;                   // final alignment cost of the selected start
  // How much to trust the region, in [0, 1]: the estimated probability that the partial is
  // part of this full shape and the region overlaps the true one with IoU >= 0.5. Reject
  // matches below a threshold of your choice.
  double confidence = 0.0;
  // How similar the partial is to the full shape (lower is more similar), comparable between
  // full shapes of different size and meshing: what search() ranks by. The core's
  // Localization::similarity_score (the best partial fit among the candidate regions:
  // docs/algorithm.md, "Searching several full shapes"); +inf when unknown.
  double similarity_score = 0.0;
  // The factor the partial's coordinates were multiplied by: 1 with the option scale "same",
  // the given factor, or the estimate with "auto".
  double scale = 1.0;
  // Vertices of the optimisation mesh used: about the resolution option, or twice that for a
  // partial with holes.
  std::size_t optimisation_vertices = 0;
  std::size_t selected_start = 0;
  std::size_t n_starts = 0;
  Timings timings{};                   // wall-clock seconds per stage
  // What was repaired or left out: the intake's notes on the full and partial meshes, a
  // disconnected partial reduced to its largest component, ...
  std::vector<std::string> warnings;

  // Indices of the vertices in the region, ascending.
  std::vector<std::uint32_t> region_vertices() const;
};

// fraction in [0, 1] of the whole computation, stage a short name; return false to cancel
// (the call then throws Error(Status::Cancelled)). An exception thrown by the callback cancels
// the computation and is rethrown by the call. The calls of one computation are serialized
// but may come from a worker thread.
using ProgressCallback = std::function<bool(double fraction, std::string_view stage)>;

// A full mesh prepared for locating partials on it: what depends on the full shape alone
// (scale, optimisation mesh, descriptors, start positions) is computed once, by the
// constructor (or read back by load()). locate() may be called from several threads at once.
class Localizer {
 public:
  explicit Localizer(const Mesh& full, const Options& options = Options(), const ProgressCallback& progress = {});

  // Read a prepared shape written by save() (or `dualspectra prepare`): it locates as the one
  // saved does, with its options, in the numbering of the mesh it was prepared from. Throws
  // Error(Status::Io) for a file that cannot be read, Error(Status::InvalidPreparedShape) for
  // one that is not a prepared shape, of another format version (stale: prepare it again),
  // truncated or corrupted; the message names the file and which.
  static Localizer load(const std::string& path);
  // Write the prepared shape to `path` (".dsprep" by convention; versioned format): the
  // options, the host's vertex numbering and all the preparation computed. Throws
  // Error(Status::Io) when the file cannot be written.
  void save(const std::string& path) const;

  // Find the region of the full mesh that `partial` is.
  Localization locate(const Mesh& partial, const ProgressCallback& progress = {}) const;

  // Vertices of the full mesh (host numbering): the length of every result's arrays.
  std::size_t n_vertices() const noexcept { return data_->n_vertices(); }
  // Vertices of the optimisation mesh (the full mesh decimated to about "resolution").
  std::size_t optimisation_vertices() const noexcept { return data_->optimisation_vertices(); }
  // Seconds the constructor took.
  double preparation_seconds() const noexcept { return data_->preparation_seconds(); }
  // Notes on the preparation (repeated in every result).
  std::vector<std::string> warnings() const;
  // The options it was prepared with.
  Options options() const;

  const detail::LocalizerData& data() const noexcept { return *data_; }

 private:
  explicit Localizer(rust::Box<detail::LocalizerData> data) : data_(std::move(data)) {}
  rust::Box<detail::LocalizerData> data_;
};

// One full shape's answer of search().
struct Match {
  std::size_t index = 0;          // the shape's position in the localizers searched
  // Localization::similarity_score (lower is more similar); +inf when not located.
  double score = std::numeric_limits<double>::infinity();
  bool located = false;           // false: the partial cannot be on this shape (see error)
  Localization localization;      // in the numbering of this shape's full mesh; empty if not located
  std::string error;              // why it was not located ("" if it was)
  // The screen's score (lower is more similar) when search() screened the shapes (a shortlist
  // below their number); NaN otherwise. A shape screened out is not located, with no error.
  double screen_score = std::numeric_limits<double>::quiet_NaN();
  // Whether `localization` is the screened search's quick one (fewer starts, iterations and eigenvalues, on the regular optimisation mesh even for a partial with holes,
  // ranking the shortlist) rather than a full one; the best few of the shortlist are
  // localized again in full.
  bool quick = false;
  // How much to trust that the partial is a part of this shape rather than of another one
  // searched, in [0, 1]: how far its score is behind (relative to the spread of the search's
  // scores), or ahead of, the best other shape's, and the localization's own confidence; 0
  // when not located. What to threshold to reject a match.
  double confidence = 0.0;
};

// Which of the prepared full shapes is `partial` a part of, and where: the partial is located
// on each, and the `top` best (lowest score) are returned, best first (ties: the lower index
// first). A shape the partial cannot be on (e.g. smaller than it) ranks last, not located;
// when no shape can take it, the first shape's error is thrown. top == 0 throws
// Error(Status::InvalidArgument); a null pointer among the localizers too. Progress runs over
// the shapes. With `shortlist` below the number of shapes, a screen (a few SHOT descriptors
// per shape, with the first localizer's scale option) ranks them first and the partial is
// located on the `shortlist` best only, quickly (Match::quick), and again in full on the best
// few of those; the others follow in screen order, not located (Match::screen_score).
// shortlist == 0 throws Error(Status::InvalidArgument).
std::vector<Match> search(const Mesh& partial, const std::vector<const Localizer*>& localizers,
                          std::size_t top = std::numeric_limits<std::size_t>::max(),
                          const ProgressCallback& progress = {},
                          std::size_t shortlist = std::numeric_limits<std::size_t>::max());
std::vector<Match> search(const Mesh& partial, const std::vector<Localizer>& localizers,
                          std::size_t top = std::numeric_limits<std::size_t>::max(),
                          const ProgressCallback& progress = {},
                          std::size_t shortlist = std::numeric_limits<std::size_t>::max());

// Find the region of `full` that `partial` corresponds to, in one call (a Localizer used once).
Localization localize(const Mesh& full, const Mesh& partial, const Options& options = Options(),
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
// cotmatrix L. n = mesh.n_vertices() (host numbering; no entries at left-out vertices).
SparseMatrix cotangent_stiffness(const Mesh& mesh);

// The lumped mass diagonal of `metric`: a_i = (area of the faces at i) / 3 (Regular), or
// s_i a_i with s = (1e-8 + K_smoothed^2)^(alpha/2) (ScaleInvariant; alpha defaults to the
// "alpha" option's default).
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

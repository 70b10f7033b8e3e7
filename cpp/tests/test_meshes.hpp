// Test meshes generated in C++ (no files, no dependencies): subdivided icospheres, a bumpy
// sphere, a height-field patch with boundary, cuts of a mesh, plain OFF I/O, and the
// statistics the tests report. Header-only, shared by the CTest programs of cpp/tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dstest {

using Vec3 = std::array<double, 3>;
using Tri = std::array<std::uint32_t, 3>;

struct SimpleMesh {
  std::vector<Vec3> V;
  std::vector<Tri> F;
};

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// Icosahedron subdivided `level` times (each triangle into 4, new vertices projected on the
// unit sphere): 10 * 4^level + 2 vertices.
inline SimpleMesh icosphere(int level) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  SimpleMesh m;
  m.V = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  m.F = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
         {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
         {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& v : m.V) {
    const double n = norm(v);
    for (auto& c : v) c /= n;
  }
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      Vec3 p{(m.V[a][0] + m.V[b][0]) / 2, (m.V[a][1] + m.V[b][1]) / 2, (m.V[a][2] + m.V[b][2]) / 2};
      const double n = norm(p);
      for (auto& c : p) c /= n;
      m.V.push_back(p);
      const auto i = static_cast<std::uint32_t>(m.V.size() - 1);
      mid.emplace(key, i);
      return i;
    };
    std::vector<Tri> F;
    F.reserve(4 * m.F.size());
    for (const auto& f : m.F) {
      const auto a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      F.push_back({f[0], a, c});
      F.push_back({f[1], b, a});
      F.push_back({f[2], c, b});
      F.push_back({a, b, c});
    }
    m.F = std::move(F);
  }
  return m;
}

// The icosphere with radius r(p) = 1 + amplitude * sin(3x) sin(2y + 1) sin(2.5z + 0.5): a smooth
// star-shaped surface with curvature of both signs.
inline SimpleMesh bumpy_sphere(int level, double amplitude = 0.2) {
  SimpleMesh m = icosphere(level);
  for (auto& v : m.V) {
    const double r = 1.0 + amplitude * std::sin(3 * v[0]) * std::sin(2 * v[1] + 1) * std::sin(2.5 * v[2] + 0.5);
    for (auto& c : v) c *= r;
  }
  return m;
}

// A height field z = 0.3 sin(2x) cos(1.5y) over an n x n grid on [-1, 1]^2 (a disk with boundary),
// each cell split along alternating diagonals.
inline SimpleMesh bumpy_patch(int n) {
  SimpleMesh m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -1.0 + 2.0 * i / (n - 1), y = -1.0 + 2.0 * j / (n - 1);
      m.V.push_back({x, y, 0.3 * std::sin(2 * x) * std::cos(1.5 * y)});
    }
  auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      if ((i + j) % 2 == 0) {
        m.F.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.F.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        m.F.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        m.F.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return m;
}

// The faces whose three vertices all satisfy `keep`, re-indexed; `origin[i]` is the vertex of
// `m` that vertex i of the cut came from.
template <class Pred>
SimpleMesh cut(const SimpleMesh& m, Pred keep, std::vector<std::uint32_t>* origin = nullptr) {
  std::vector<std::int64_t> index(m.V.size(), -1);
  SimpleMesh c;
  std::vector<std::uint32_t> from;
  for (const auto& f : m.F) {
    if (!(keep(m.V[f[0]]) && keep(m.V[f[1]]) && keep(m.V[f[2]]))) continue;
    Tri g;
    for (int k = 0; k < 3; ++k) {
      if (index[f[k]] < 0) {
        index[f[k]] = static_cast<std::int64_t>(c.V.size());
        c.V.push_back(m.V[f[k]]);
        from.push_back(f[k]);
      }
      g[k] = static_cast<std::uint32_t>(index[f[k]]);
    }
    c.F.push_back(g);
  }
  if (origin) *origin = std::move(from);
  return c;
}

// Remove two-sided flaps (a triangle listed in both orientations) and the vertices only they
// used, renumbering the rest: the same repair the Rust reader applies to SHREC'16
// null/cat.off (twelve flaps that make their base edges non-manifold). Returns the number of
// faces removed.
inline std::size_t remove_flaps(SimpleMesh& m) {
  std::map<std::array<std::uint32_t, 3>, std::vector<std::size_t>> by_set;
  for (std::size_t f = 0; f < m.F.size(); ++f) {
    auto key = m.F[f];
    std::sort(key.begin(), key.end());
    by_set[key].push_back(f);
  }
  std::vector<char> drop(m.F.size(), 0);
  std::size_t removed = 0;
  for (const auto& [key, faces] : by_set)
    if (faces.size() == 2) {
      drop[faces[0]] = drop[faces[1]] = 1;
      removed += 2;
    }
  if (removed == 0) return 0;
  std::vector<Tri> F;
  for (std::size_t f = 0; f < m.F.size(); ++f)
    if (!drop[f]) F.push_back(m.F[f]);
  std::vector<std::int64_t> index(m.V.size(), -1);
  std::vector<Vec3> V;
  for (auto& f : F)
    for (auto& v : f) {
      if (index[v] < 0) index[v] = 0;
    }
  for (std::size_t i = 0; i < m.V.size(); ++i)
    if (index[i] == 0) {
      index[i] = static_cast<std::int64_t>(V.size());
      V.push_back(m.V[i]);
    }
  for (auto& f : F)
    for (auto& v : f) v = static_cast<std::uint32_t>(index[v]);
  m.V = std::move(V);
  m.F = std::move(F);
  return removed;
}

// Flip faces so that neighbouring faces traverse their shared edge in opposite directions
// (breadth-first per component). Some SHREC'16 shapes have a few flipped triangles, which a
// halfedge structure (CGAL::Surface_mesh) refuses; angles, areas and cotangents do not depend
// on the orientation. Returns the number of flipped faces, or -1 if a component is not orientable.
inline long orient_consistently(SimpleMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> edge_faces;
  for (std::size_t f = 0; f < m.F.size(); ++f)
    for (int c = 0; c < 3; ++c) edge_faces[std::minmax(m.F[f][c], m.F[f][(c + 1) % 3])].push_back(f);
  auto has_directed = [&](std::size_t f, std::uint32_t a, std::uint32_t b) {
    for (int c = 0; c < 3; ++c)
      if (m.F[f][c] == a && m.F[f][(c + 1) % 3] == b) return true;
    return false;
  };
  std::vector<char> seen(m.F.size(), 0);
  long flipped = 0;
  for (std::size_t root = 0; root < m.F.size(); ++root) {
    if (seen[root]) continue;
    seen[root] = 1;
    std::vector<std::size_t> queue{root};
    while (!queue.empty()) {
      const std::size_t f = queue.back();
      queue.pop_back();
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = m.F[f][c], b = m.F[f][(c + 1) % 3];
        for (std::size_t g : edge_faces[std::minmax(a, b)]) {
          if (g == f) continue;
          const bool same = has_directed(g, a, b);
          if (seen[g]) {
            if (same) return -1;
            continue;
          }
          if (same) {
            std::swap(m.F[g][1], m.F[g][2]);
            ++flipped;
          }
          seen[g] = 1;
          queue.push_back(g);
        }
      }
    }
  }
  return flipped;
}

inline void write_off(const std::string& path, const SimpleMesh& m) {
  std::ofstream os(path);
  os.precision(17);
  os << "OFF\n" << m.V.size() << ' ' << m.F.size() << " 0\n";
  for (const auto& v : m.V) os << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
  for (const auto& f : m.F) os << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  if (!os) throw std::runtime_error("cannot write " + path);
}

// Triangle-only OFF reader (enough for SHREC'16 and our own files).
inline SimpleMesh read_off(const std::string& path) {
  std::ifstream is(path);
  std::string head;
  std::size_t nv = 0, nf = 0, ne = 0;
  if (!(is >> head) || head != "OFF" || !(is >> nv >> nf >> ne)) throw std::runtime_error("not an OFF file: " + path);
  SimpleMesh m;
  m.V.resize(nv);
  for (auto& v : m.V) is >> v[0] >> v[1] >> v[2];
  m.F.resize(nf);
  for (auto& f : m.F) {
    int k = 0;
    is >> k >> f[0] >> f[1] >> f[2];
    if (k != 3) throw std::runtime_error("non-triangle face in " + path);
  }
  if (!is) throw std::runtime_error("truncated OFF file: " + path);
  return m;
}

// The datasets folder: $DUALSPECTRA_DATA, else the one CMake found beside the repository
// (DUALSPECTRA_TEST_DATA_DIR: ../shared/datasets).
inline std::string data_dir() {
  const char* env = std::getenv("DUALSPECTRA_DATA");
  return env && *env ? std::string(env) : std::string(DUALSPECTRA_TEST_DATA_DIR);
}

// SHREC'16 directory: data_dir()/shrec16; empty if absent.
inline std::string shrec16_dir() {
  const std::string dir = data_dir() + "/shrec16";
  std::ifstream probe(dir + "/null/cat.off");
  return probe ? dir : std::string();
}

// Spearman rank correlation (average ranks for ties).
inline double spearman(const std::vector<double>& a, const std::vector<double>& b) {
  auto ranks = [](const std::vector<double>& x) {
    std::vector<std::size_t> order(x.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return x[i] < x[j]; });
    std::vector<double> r(x.size());
    for (std::size_t i = 0; i < order.size();) {
      std::size_t j = i;
      while (j + 1 < order.size() && x[order[j + 1]] == x[order[i]]) ++j;
      for (std::size_t k = i; k <= j; ++k) r[order[k]] = 0.5 * static_cast<double>(i + j);
      i = j + 1;
    }
    return r;
  };
  const auto ra = ranks(a), rb = ranks(b);
  const double n = static_cast<double>(a.size());
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / n, mb = std::accumulate(rb.begin(), rb.end(), 0.0) / n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// Minimal check/report helpers: a failed check prints and marks the run failed.
struct Checker {
  int failures = 0;
  void check(bool ok, const std::string& what) {
    std::printf("%s %s\n", ok ? "[ ok ]" : "[FAIL]", what.c_str());
    std::fflush(stdout);
    if (!ok) ++failures;
  }
};

}  // namespace dstest

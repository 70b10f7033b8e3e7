// An outside project using the installed package (find_package(dualspectra) +
// dualspectra::dualspectra): the C and the C++ API, typed exceptions, options by name, and one
// Localizer locating two partials exactly as two one-call localizations do. Built with
// DS_CONSUMER_CGAL (component `cgal`, dualspectra::cgal): the same full mesh as a
// CGAL::Surface_mesh through dualspectra/cgal.hpp gives the same region.
#include <dualspectra/dualspectra.hpp>
#include <dualspectra/dualspectra.h>
#ifdef DS_CONSUMER_CGAL
#include <CGAL/Simple_cartesian.h>
#include <dualspectra/cgal.hpp>
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

using V3 = std::array<double, 3>;
using T3 = std::array<std::uint32_t, 3>;

static int failures = 0;
static void check(bool ok, const std::string& what) {
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  failures += !ok;
}

// Unit icosphere subdivided `level` times.
static void icosphere(int level, std::vector<V3>& V, std::vector<T3>& F) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  V = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  F = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
       {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  auto unit = [](V3 p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return V3{p[0] / n, p[1] / n, p[2] / n};
  };
  for (auto& v : V) v = unit(v);
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      V.push_back(unit({(V[a][0] + V[b][0]) / 2, (V[a][1] + V[b][1]) / 2, (V[a][2] + V[b][2]) / 2}));
      return mid[key] = static_cast<std::uint32_t>(V.size() - 1);
    };
    std::vector<T3> next;
    for (const auto& f : F) {
      const auto a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      next.insert(next.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
    }
    F.swap(next);
  }
}

// The faces of (V, F) whose vertices all satisfy `keep`, compacted.
template <class Pred>
static dualspectra::Mesh cut(const std::vector<V3>& V, const std::vector<T3>& F, Pred keep) {
  std::vector<std::uint32_t> index(V.size(), UINT32_MAX);
  std::vector<V3> Vc;
  std::vector<T3> Fc;
  for (const auto& f : F) {
    if (!keep(V[f[0]]) || !keep(V[f[1]]) || !keep(V[f[2]])) continue;
    T3 g;
    for (int c = 0; c < 3; ++c) {
      if (index[f[c]] == UINT32_MAX) {
        index[f[c]] = static_cast<std::uint32_t>(Vc.size());
        Vc.push_back(V[f[c]]);
      }
      g[c] = index[f[c]];
    }
    Fc.push_back(g);
  }
  return dualspectra::Mesh(Vc, Fc);
}

int main() {
  try {
    // Gauss-Bonnet on a tetrahedron through the C++ API, the version through both APIs.
    std::vector<V3> V{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<T3> F{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    dualspectra::Mesh m(V, F);
    const auto K = dualspectra::gaussian_curvature(m);
    const auto a = dualspectra::mass(m);
    double s = 0;
    for (std::size_t i = 0; i < K.size(); ++i) s += K[i] * a[i];
    check(std::abs(s - 4 * 3.14159265358979323846) < 1e-12 && dualspectra::version() == ds_version(),
          "version " + dualspectra::version() + ", Gauss-Bonnet sum K a = 4 pi");
    try {
      dualspectra::Mesh bad(std::vector<double>{0, 0, 0}, std::vector<std::uint32_t>{0, 1, 2});
      check(false, "an index out of range throws");
    } catch (const dualspectra::Error& e) {
      check(e.status() == dualspectra::Status::InvalidMesh, std::string("InvalidMesh: ") + e.what());
    }

    // Options by name (C++ and C), errors naming the option.
    dualspectra::Options opts;
    opts.set("k", 6).set("max_iterations", 5).set("resolution", "0").set("plane_cuts", 2);
    try {
      opts.set("k", 0);
      check(false, "k = 0 throws");
    } catch (const dualspectra::Error& e) {
      check(e.status() == dualspectra::Status::InvalidArgument && std::string(e.what()).find("k = 0") != std::string::npos,
            std::string("k = 0 throws InvalidArgument: ") + e.what());
    }
    check(dualspectra::Options::schema() == ds_options_schema_json(), "one schema for C and C++");
    ds_options* copts = nullptr;
    ds_options_create(&copts);
    check(ds_options_set_json(copts, opts.json().c_str()) == DS_OK && opts.json() == ds_options_json(copts),
          "C options from the C++ options' JSON: " + opts.json());
    const ds_status refused = ds_options_set(copts, "starts", "gaussian");
    const std::string why = ds_last_error_message();
    check(refused == DS_INVALID_ARGUMENT && why.find("unknown option 'starts'") != std::string::npos,
          "C: a removed option is refused: " + why);

    // One Localizer, two partials = two one-call localizations.
    icosphere(3, V, F);
    for (auto& p : V) p[2] *= 1.0 + 0.3 * p[0];  // no symmetry between the two caps
    const dualspectra::Mesh full(V, F);
    const auto top = cut(V, F, [](const V3& p) { return p[2] > 0.4; });
    const auto side = cut(V, F, [](const V3& p) { return p[0] > 0.5; });
    const dualspectra::Localizer prepared(full, opts);
    for (const auto* partial : {&top, &side}) {
      const auto got = prepared.locate(*partial);
      const auto want = dualspectra::localize(full, *partial, opts);
      check(got.region == want.region && got.score == want.score && got.cost == want.cost &&
                got.timings.preparation == 0.0 && want.timings.preparation > 0.0,
            "Localizer::locate = localize (" + std::to_string(got.region_vertices().size()) + " of " +
                std::to_string(got.region.size()) + " vertices)");
    }

    // The C API's localizer on the same meshes gives the C++ result.
    std::vector<double> xyz;
    std::vector<std::uint32_t> tri;
    for (const auto& p : V) xyz.insert(xyz.end(), p.begin(), p.end());
    for (const auto& f : F) tri.insert(tri.end(), f.begin(), f.end());
    const auto tv = top.vertices();
    const auto tf = top.faces();
    ds_mesh *cfull = nullptr, *cpart = nullptr;
    ds_localizer* cloc = nullptr;
    ds_result* cres = nullptr;
    ds_mesh_create(xyz.data(), V.size(), tri.data(), F.size(), &cfull);
    ds_mesh_create(tv.front().data(), tv.size(), tf.front().data(), tf.size(), &cpart);
    const ds_status st = ds_localizer_create(cfull, copts, nullptr, nullptr, &cloc) == DS_OK
                             ? ds_localizer_locate(cloc, cpart, nullptr, nullptr, &cres)
                             : DS_PANIC;
    std::vector<std::uint8_t> cregion(ds_result_n_vertices(cres));
    ds_result_region(cres, cregion.data(), cregion.size());
    double cconfidence = -1.0;
    ds_result_confidence(cres, &cconfidence);
    std::size_t coptimised_on = 0;
    ds_result_optimisation_vertices(cres, &coptimised_on);
    const auto cpp = prepared.locate(top);
    check(st == DS_OK && std::vector<bool>(cregion.begin(), cregion.end()) == cpp.region &&
              cconfidence == cpp.confidence && coptimised_on > 0 && coptimised_on == cpp.optimisation_vertices,
          "C ds_localizer_locate = C++ Localizer::locate, region, confidence and optimisation mesh (status " +
              std::string(ds_status_name(st)) + ")");
    ds_result_destroy(cres);
    ds_localizer_destroy(cloc);
    ds_mesh_destroy(cpart);
    ds_mesh_destroy(cfull);
    ds_options_destroy(copts);

#ifdef DS_CONSUMER_CGAL
    // The full mesh as a CGAL::Surface_mesh: same vertices, same region, written back to a map.
    using Point = CGAL::Simple_cartesian<double>::Point_3;
    CGAL::Surface_mesh<Point> sm;
    std::vector<CGAL::Surface_mesh<Point>::Vertex_index> vi;
    for (const auto& p : V) vi.push_back(sm.add_vertex(Point(p[0], p[1], p[2])));
    for (const auto& f : F) sm.add_face(vi[f[0]], vi[f[1]], vi[f[2]]);
    const auto conv = dualspectra::cgal::to_mesh(sm);
    const auto via_cgal = dualspectra::localize(conv.mesh, top, opts);
    const auto map = dualspectra::cgal::write_region(sm, conv, via_cgal);
    std::size_t marked = 0;
    for (auto v : sm.vertices()) marked += map[v] ? 1 : 0;
    check(conv.mesh.n_vertices() == V.size() && conv.mesh.n_faces() == F.size() && via_cgal.region == cpp.region &&
              marked == cpp.region_vertices().size(),
          "CGAL Surface_mesh (dualspectra::cgal): same region, " + std::to_string(marked) + " vertices in the map");
#endif
  } catch (const std::exception& e) {
    check(false, std::string("unexpected exception: ") + e.what());
  }
  std::printf("%d failure(s)\n", failures);
  return failures == 0 ? 0 : 1;
}

// The OpenMesh adapter (dualspectra/openmesh.hpp): float and double TriMesh round trips,
// deleted elements (before garbage_collection), isolated vertices left out by the core's intake
// (with its warning), polygon faces rejected in a PolyMesh, region write-back as a property
// and as the `selected` status flag, and a localization through the adapter (one Localizer,
// two partials) whose results, in the host's numbering, are those of the strict mesh.
#include <cstdio>
#include <string>
#include <vector>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <dualspectra/openmesh.hpp>

#include "test_meshes.hpp"

static dstest::Checker T;

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using TriMeshF = OpenMesh::TriMesh_ArrayKernelT<>;
using TriMeshD = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<>;

template <class OM>
static OM to_openmesh(const dstest::SimpleMesh& m, std::vector<OpenMesh::VertexHandle>* handles = nullptr) {
  OM om;
  std::vector<OpenMesh::VertexHandle> vh;
  for (const auto& v : m.V) vh.push_back(om.add_vertex(typename OM::Point(v[0], v[1], v[2])));
  for (const auto& f : m.F) om.add_face(vh[f[0]], vh[f[1]], vh[f[2]]);
  if (handles) *handles = vh;
  return om;
}

int main() {
  try {
    const auto src = dstest::bumpy_sphere(3);
    const dualspectra::Mesh ref(src.V, src.F);
    const auto K_ref = dualspectra::gaussian_curvature(ref);
    {
      const auto om = to_openmesh<TriMeshD>(src);
      const auto conv = dualspectra::openmesh::to_mesh(om);
      T.check(conv.mesh.vertices() == src.V && conv.mesh.faces() == src.F, "double TriMesh: exact round trip");
    }
    {
      const auto om = to_openmesh<TriMeshF>(src);
      const auto conv = dualspectra::openmesh::to_mesh(om);
      double err = 0;
      const auto V = conv.mesh.vertices();
      for (std::size_t i = 0; i < V.size(); ++i)
        for (int d = 0; d < 3; ++d) err = std::max(err, std::abs(V[i][d] - src.V[i][d]));
      T.check(conv.mesh.faces() == src.F && err < 1e-6,
              "float TriMesh: same faces, positions rounded to float (max error " + std::to_string(err) + ")");
    }
    // Deleted elements: a dangling triangle and interleaved junk vertices deleted without
    // garbage collection, plus one isolated live vertex.
    TriMeshD om;
    om.request_vertex_status();
    om.request_edge_status();
    om.request_halfedge_status();
    om.request_face_status();
    std::vector<OpenMesh::VertexHandle> real, junk;
    for (std::size_t i = 0; i < src.V.size(); ++i) {
      if (i % 5 == 2) junk.push_back(om.add_vertex(TriMeshD::Point(9, 9, 9)));
      real.push_back(om.add_vertex(TriMeshD::Point(src.V[i][0], src.V[i][1], src.V[i][2])));
    }
    for (const auto& f : src.F) om.add_face(real[f[0]], real[f[1]], real[f[2]]);
    const auto a = om.add_vertex(TriMeshD::Point(5, 0, 0)), b = om.add_vertex(TriMeshD::Point(5, 1, 0)),
               c = om.add_vertex(TriMeshD::Point(5, 0, 1));
    om.add_face(a, b, c);
    const auto isolated = om.add_vertex(TriMeshD::Point(7, 7, 7));
    om.delete_vertex(a, true);  // deletes the dangling face and its now-isolated vertices
    for (auto v : junk) om.delete_vertex(v, true);
    const auto conv = dualspectra::openmesh::to_mesh(om);
    T.check(conv.mesh.vertices() == src.V && conv.mesh.faces() == src.F && conv.mesh.n_vertices() == src.V.size() + 1,
            "deleted elements skipped, isolated vertex left out by the intake: same mesh as the source, results for the " +
                std::to_string(conv.mesh.n_vertices()) + " non-deleted of " + std::to_string(om.n_vertices()) + " handles");
    bool map_ok = conv.index(isolated) == src.V.size() && conv.index(b) == conv.none;
    for (auto v : junk) map_ok = map_ok && conv.index(v) == conv.none;
    for (std::size_t i = 0; i < real.size(); ++i) map_ok = map_ok && conv.vertex_of[i] == real[i] && conv.index(real[i]) == i;
    T.check(map_ok, "vertex_of / index_of correspondence over non-deleted vertices");
    T.check(conv.mesh.warning().find("0 degenerate face(s) and 1 vertex(es)") != std::string::npos,
            "the intake's warning: " + conv.mesh.warning());
    auto K = dualspectra::gaussian_curvature(conv.mesh);
    T.check(K.size() == src.V.size() + 1 && K.back() == 0.0 && std::equal(K_ref.begin(), K_ref.end(), K.begin()),
            "curvature through the adapter identical to direct construction, 0 at the isolated vertex");

    // A localization through the adapter: one Localizer, two partials; each result, in the
    // host's numbering, is the strict mesh's at the same vertices and false at the isolated one.
    {
      dualspectra::Options fast;
      fast.set_json(R"({"k": 6, "max_iterations": 5, "resolution": 0, "plane_cuts": 2})");
      const dualspectra::Localizer prepared(conv.mesh, fast);
      T.check(prepared.n_vertices() == conv.mesh.n_vertices() && prepared.warnings().size() == 1,
              "Localizer on the adapter's mesh: host vertex count, the intake's note among its warnings");
      for (const auto& part : {dstest::cut(src, [](const dstest::Vec3& p) { return p[0] > 0.3; }),
                               dstest::cut(src, [](const dstest::Vec3& p) { return p[2] < -0.2; })}) {
        const dualspectra::Mesh partial(part.V, part.F);
        const auto got = prepared.locate(partial);
        const auto want = dualspectra::localize(ref, partial, fast);
        bool same = got.region.size() == conv.mesh.n_vertices() && !got.region.back() && got.score.back() == 0.0 &&
                    got.cost == want.cost;
        for (std::size_t i = 0; same && i < src.V.size(); ++i)
          same = got.region[i] == want.region[i] && got.score[i] == want.score[i];
        std::size_t n_region = 0;
        for (bool in : got.region) n_region += in;
        T.check(same && !got.warnings.empty() && got.warnings[0].rfind("full mesh: left out", 0) == 0,
                "located through the adapter = strict one-call result in host numbering (" + std::to_string(n_region) +
                    " vertices in the region); warnings[0]: " + (got.warnings.empty() ? "(none)" : got.warnings[0]));
        T.check(got.confidence == want.confidence && got.confidence >= 0.0 && got.confidence <= 1.0,
                "confidence through the adapter = strict one-call result, in [0, 1]: " + std::to_string(got.confidence));
      }
    }

    // Write-back (a Localization filled by hand: this checks the index mapping only).
    TriMeshD plain = to_openmesh<TriMeshD>(src);  // no status: write_region requests it
    const auto conv_plain = dualspectra::openmesh::to_mesh(plain);
    dualspectra::Localization r;
    r.region.resize(conv_plain.mesh.n_vertices());
    r.score.resize(conv_plain.mesh.n_vertices());
    for (std::size_t i = 0; i < r.region.size(); ++i) {
      r.region[i] = i % 4 == 1;
      r.score[i] = 1.0 / static_cast<double>(i + 1);
    }
    auto h = dualspectra::openmesh::write_region(plain, conv_plain, r);
    auto hs = dualspectra::openmesh::write_score(plain, conv_plain, r);
    bool wb = plain.has_vertex_status();
    for (std::size_t i = 0; i < r.region.size(); ++i) {
      const OpenMesh::VertexHandle vh(static_cast<int>(i));
      wb = wb && plain.property(h, vh) == r.region[i] && plain.status(vh).selected() == r.region[i] &&
           plain.property(hs, vh) == r.score[i];
    }
    OpenMesh::VPropHandleT<bool> found;
    T.check(wb && plain.get_property_handle(found, "v:dualspectra_region"),
            "region as property \"v:dualspectra_region\" and selected flags, score as \"v:dualspectra_score\"");
    dualspectra::Localization rh;  // one value per non-deleted vertex of om
    rh.region.assign(conv.mesh.n_vertices(), false);
    for (std::size_t i = 0; i < rh.region.size(); ++i) rh.region[i] = i % 4 == 1;
    rh.region.back() = false;  // the isolated vertex, as the intake leaves it
    auto h2 = dualspectra::openmesh::write_region(om, conv, rh, "v:dualspectra_region", true);
    bool wb2 = !om.property(h2, isolated) && !om.status(isolated).selected() && !om.property(h2, b);
    for (std::size_t i = 0; i < real.size(); ++i) wb2 = wb2 && om.status(real[i]).selected() == rh.region[i];
    T.check(wb2, "write-back through index holes; deleted and isolated vertices unselected");
    rh.region.pop_back();
    try {
      dualspectra::openmesh::write_region(om, conv, rh);
      T.check(false, "size mismatch throws");
    } catch (const dualspectra::Error& e) {
      T.check(e.status() == dualspectra::Status::InvalidArgument, std::string("size mismatch throws InvalidArgument: ") + e.what());
    }
    PolyMesh quad;
    std::vector<PolyMesh::VertexHandle> q{quad.add_vertex(PolyMesh::Point(0, 0, 0)), quad.add_vertex(PolyMesh::Point(1, 0, 0)),
                                          quad.add_vertex(PolyMesh::Point(1, 1, 0)), quad.add_vertex(PolyMesh::Point(0, 1, 0))};
    quad.add_face(q);
    try {
      dualspectra::openmesh::to_mesh(quad);
      T.check(false, "quad face throws");
    } catch (const dualspectra::Error& e) {
      T.check(e.status() == dualspectra::Status::InvalidMesh, std::string("PolyMesh quad face throws InvalidMesh: ") + e.what());
    }
  } catch (const std::exception& e) {
    T.check(false, std::string("unexpected exception: ") + e.what());
  }
  std::printf("\n%d failure(s)\n", T.failures);
  return T.failures == 0 ? 0 : 1;
}

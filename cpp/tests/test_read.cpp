// dualspectra::Mesh::read and the C API's ds_mesh_read on files: the generated bumpy sphere
// (make_test_meshes DIR) reads back to the arrays it was written from, bit for bit, and to the
// mesh those arrays make (same spectrum); a file needing repairs (a quad, a non-manifold edge)
// reads with a warning naming it; a missing, garbage or invalid file throws Status::Io or
// Status::InvalidMesh (DS_IO, DS_INVALID_MESH in C) with the file in the message.
#include <dualspectra/dualspectra.h>
#include <dualspectra/dualspectra.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "test_meshes.hpp"

namespace {

// Status of the dualspectra::Error `f` throws (Status::Ok if it throws none), its message in `what`.
template <class F>
dualspectra::Status status_of(F&& f, std::string& what) {
  try {
    f();
  } catch (const dualspectra::Error& e) {
    what = e.what();
    return e.status();
  }
  what.clear();
  return dualspectra::Status::Ok;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void write_text(const std::string& path, const std::string& text) {
  std::ofstream os(path, std::ios::binary);
  os << text;
  if (!os) throw std::runtime_error("cannot write " + path);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR (holding make_test_meshes' full.off)\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  dstest::Checker t;
  try {
    // The generated file, read by the library and by the test's own OFF reader.
    const std::string full_path = dir + "/full.off";
    const dstest::SimpleMesh written = dstest::read_off(full_path);
    const dualspectra::Mesh full = dualspectra::Mesh::read(full_path);
    t.check(full.n_vertices() == written.V.size() && full.n_faces() == written.F.size(),
            "Mesh::read: " + std::to_string(full.n_vertices()) + " vertices, " + std::to_string(full.n_faces()) +
                " faces, as the file");
    t.check(full.vertices() == written.V && full.faces() == written.F, "Mesh::read: the file's arrays, bit for bit");
    t.check(full.warning().empty(), "Mesh::read: no warning for a valid file");
    const auto from_file = dualspectra::spectrum(full, 6);
    const auto from_arrays = dualspectra::spectrum(dualspectra::Mesh(written.V, written.F), 6);
    t.check(from_file == from_arrays, "Mesh::read: the spectrum of the mesh its arrays make");

    // The C API reads the same mesh.
    ds_mesh* c_mesh = nullptr;
    const ds_status s = ds_mesh_read(full_path.c_str(), &c_mesh);
    std::vector<double> xyz(3 * ds_mesh_n_used_vertices(c_mesh));
    std::vector<std::uint32_t> tri(3 * ds_mesh_n_faces(c_mesh));
    const bool copied = ds_mesh_vertices(c_mesh, xyz.data(), xyz.size()) == DS_OK &&
                        ds_mesh_faces(c_mesh, tri.data(), tri.size()) == DS_OK;
    bool same = copied && xyz.size() == 3 * written.V.size() && tri.size() == 3 * written.F.size();
    for (std::size_t i = 0; same && i < xyz.size(); ++i) same = xyz[i] == written.V[i / 3][i % 3];
    for (std::size_t i = 0; same && i < tri.size(); ++i) same = tri[i] == written.F[i / 3][i % 3];
    t.check(s == DS_OK && same && ds_mesh_warning(c_mesh) == nullptr, "ds_mesh_read: the file's arrays, no warning");
    ds_mesh_destroy(c_mesh);

    // A quad and a third face on one of its edges: triangulated and split, with a warning.
    const std::string repaired = dir + "/read_repaired.obj";
    write_text(repaired, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 -1 0.5\nf 1 2 3 4\nf 2 1 5\n");
    const dualspectra::Mesh r = dualspectra::Mesh::read(repaired);
    t.check(r.n_faces() == 3 && r.n_vertices() == 5, "Mesh::read: a quad fan-triangulated (" + std::to_string(r.n_faces()) +
                                                         " faces)");
    write_text(repaired, "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
    const dualspectra::Mesh split = dualspectra::Mesh::read(repaired);
    t.check(split.n_vertices() > 5 && contains(split.warning(), repaired) && contains(split.warning(), "non-manifold"),
            "Mesh::read: a non-manifold edge split, said by warning(): " + split.warning());

    // Files that cannot be used.
    std::string what;
    const std::string missing = dir + "/no such mesh.off";
    dualspectra::Status st = status_of([&] { dualspectra::Mesh::read(missing); }, what);
    t.check(st == dualspectra::Status::Io && contains(what, "no such mesh.off"),
            "missing file: Status::Io naming it: " + what);
    const std::string garbage = dir + "/read_garbage.ply";
    write_text(garbage, std::string("\x7f\x45LF\x02\x01\x01\0\0\0", 10));
    st = status_of([&] { dualspectra::Mesh::read(garbage); }, what);
    t.check(st == dualspectra::Status::Io && contains(what, "read_garbage.ply"),
            "garbage file: Status::Io naming it: " + what);
    const std::string invalid = dir + "/read_invalid.off";
    write_text(invalid, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    st = status_of([&] { dualspectra::Mesh::read(invalid); }, what);
    t.check(st == dualspectra::Status::InvalidMesh && contains(what, "read_invalid.off") && contains(what, "vertex 7"),
            "index out of range: Status::InvalidMesh naming the file and the index: " + what);
    ds_mesh* none = nullptr;
    const ds_status c_status = ds_mesh_read(invalid.c_str(), &none);
    const std::string message = ds_last_error_message();
    t.check(c_status == DS_INVALID_MESH && none == nullptr && contains(message, "read_invalid.off"),
            "ds_mesh_read: DS_INVALID_MESH naming the file: " + message);
  } catch (const std::exception& e) {
    t.check(false, std::string("unexpected exception: ") + e.what());
  }
  std::printf("%s\n", t.failures ? "FAILED" : "all passed");
  return t.failures ? 1 : 0;
}

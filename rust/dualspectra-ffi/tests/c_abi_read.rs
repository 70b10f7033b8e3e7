//! `ds_mesh_read`, `ds_mesh_vertices` and `ds_mesh_faces`, called as C calls them: a file reads
//! to the core reader's mesh bit for bit, with its repairs said by `ds_mesh_warning`; a missing,
//! garbage or invalid file is a status and a message naming the file, never a panic; any bytes
//! name a file on Unix; the arrays given back make the same mesh through `ds_mesh_create`.

use dualspectra::mesh::generate::icosphere;
use dualspectra::mesh::io::{read_mesh, write_off};
use dualspectra_ffi::c_abi::*;
use std::ffi::{c_char, CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr;

fn last_error() -> String {
    unsafe { CStr::from_ptr(ds_last_error_message()) }.to_string_lossy().into_owned()
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data").join(name)
}

/// A folder of this test's own under the target directory, emptied.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ds_c_abi_read_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn c_path(path: &Path) -> CString {
    use std::os::unix::ffi::OsStrExt;
    CString::new(path.as_os_str().as_bytes()).unwrap()
}

/// A live mesh handle, destroyed on drop.
struct Mesh(*mut ds_mesh);
impl Drop for Mesh {
    fn drop(&mut self) {
        unsafe { ds_mesh_destroy(self.0) }
    }
}

/// `ds_mesh_read` of `path`: the mesh, or the status and message.
fn read(path: *const c_char) -> Result<Mesh, (ds_status, String)> {
    let mut out = ptr::null_mut();
    match unsafe { ds_mesh_read(path, &mut out) } {
        DS_OK => {
            assert!(!out.is_null());
            Ok(Mesh(out))
        }
        s => {
            assert!(out.is_null(), "out is written only on success");
            Err((s, last_error()))
        }
    }
}

/// The arrays of a mesh handle, through `ds_mesh_vertices` and `ds_mesh_faces`.
fn arrays(m: &Mesh) -> (Vec<f64>, Vec<u32>) {
    unsafe {
        let mut xyz = vec![f64::NAN; 3 * ds_mesh_n_used_vertices(m.0)];
        let mut tri = vec![u32::MAX; 3 * ds_mesh_n_faces(m.0)];
        assert_eq!(ds_mesh_vertices(m.0, xyz.as_mut_ptr(), xyz.len()), DS_OK, "{}", last_error());
        assert_eq!(ds_mesh_faces(m.0, tri.as_mut_ptr(), tri.len()), DS_OK, "{}", last_error());
        (xyz, tri)
    }
}

fn warning(m: &Mesh) -> Option<String> {
    let w = unsafe { ds_mesh_warning(m.0) };
    (!w.is_null()).then(|| unsafe { CStr::from_ptr(w) }.to_string_lossy().into_owned())
}

#[test]
fn a_good_file_reads_as_the_core_reads_it() {
    for name in ["tetrahedron.off", "square_pyramid.off", "square_pyramid.ply", "cube_quads.obj"] {
        let path = data(name);
        let m = read(c_path(&path).as_ptr()).unwrap_or_else(|e| panic!("{name}: {e:?}"));
        let core = read_mesh(&path).unwrap();
        let (xyz, tri) = arrays(&m);
        assert_eq!(xyz, core.vertices().as_flattened(), "{name}");
        assert_eq!(tri, core.faces().as_flattened(), "{name}");
        assert_eq!(unsafe { ds_mesh_n_vertices(m.0) }, core.n_vertices());
        assert_eq!(warning(&m), None, "{name}: nothing was repaired");
        // The arrays given back make the same mesh through the strict constructor.
        let mut again = ptr::null_mut();
        let s = unsafe { ds_mesh_create(xyz.as_ptr(), xyz.len() / 3, tri.as_ptr(), tri.len() / 3, &mut again) };
        assert_eq!(s, DS_OK, "{name}: {}", last_error());
        let again = Mesh(again);
        assert_eq!(arrays(&again), (xyz, tri));
    }
}

#[test]
fn a_read_mesh_is_a_mesh_handle_like_any_other() {
    let dir = scratch("sphere");
    let path = dir.join("sphere.off");
    let sphere = icosphere(2);
    write_off(&path, &sphere).unwrap();
    let m = read(c_path(&path).as_ptr()).unwrap();
    let mut from_file = [0.0; 5];
    let mut from_arrays = [0.0; 5];
    let (xyz, tri) = (sphere.vertices().as_flattened(), sphere.faces().as_flattened());
    let mut h = ptr::null_mut();
    unsafe {
        assert_eq!(ds_mesh_create(xyz.as_ptr(), sphere.n_vertices(), tri.as_ptr(), sphere.n_faces(), &mut h), DS_OK);
        let h = Mesh(h);
        assert_eq!(ds_spectrum(m.0, 5, DS_METRIC_REGULAR, 0.0, from_file.as_mut_ptr(), 5), DS_OK, "{}", last_error());
        assert_eq!(ds_spectrum(h.0, 5, DS_METRIC_REGULAR, 0.0, from_arrays.as_mut_ptr(), 5), DS_OK);
    }
    // OFF round-trips coordinates bit for bit, so the spectra are the same bit for bit.
    assert_eq!(from_file.map(f64::to_bits), from_arrays.map(f64::to_bits));
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn repairs_are_said_by_the_mesh_warning_naming_the_file() {
    let path = data("nonmanifold_edge.off");
    let m = read(c_path(&path).as_ptr()).unwrap();
    let w = warning(&m).expect("a split says so");
    assert!(w.starts_with(&path.display().to_string()), "{w}");
    assert!(w.contains("non-manifold"), "{w}");
    let core = read_mesh(&path).unwrap();
    assert!(core.n_vertices() > 5, "the split added copies");
    assert_eq!(unsafe { ds_mesh_n_vertices(m.0) }, core.n_vertices(), "numbered as the mesh, copies included");

    let path = data("flap.off");
    let m = read(c_path(&path).as_ptr()).unwrap();
    let w = warning(&m).expect("a removed flap says so");
    assert!(w.contains("removed 2 repeated triangle(s) and the 1 vertex(es)"), "{w}");
    assert_eq!(arrays(&m).1, read_mesh(&path).unwrap().faces().as_flattened());
}

#[test]
fn a_missing_file_is_an_io_error_naming_it() {
    let path = scratch("missing").join("no such mesh.off");
    let (status, message) = read(c_path(&path).as_ptr()).err().unwrap();
    assert_eq!(status, DS_IO, "{message}");
    assert!(message.contains("no such mesh.off"), "{message}");
    // A folder is not a mesh file either.
    let dir = scratch("folder.off");
    let (status, message) = read(c_path(&dir).as_ptr()).err().unwrap();
    assert_eq!(status, DS_IO, "{message}");
}

#[test]
fn garbage_and_invalid_files_are_errors_naming_the_file() {
    let dir = scratch("garbage");
    let cases: [(&str, &[u8]); 4] = [
        ("noise.off", &[0xff, 0x00, 0x13, 0x37, b'\n', 0x80, 0x81]),
        ("noise.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 99999999999\n"),
        ("text.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"),
        ("mesh.stl", b"solid nothing\nendsolid\n"),
    ];
    for (name, bytes) in cases {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let (status, message) = read(c_path(&path).as_ptr()).err().unwrap_or_else(|| panic!("{name} read"));
        assert_eq!(status, DS_IO, "{name}: {message}");
        assert!(message.contains(name), "{name}: {message}");
    }
    for name in ["bad.off", "nan.off", "degenerate.off", "isolated.off", "no_faces.off"] {
        let path = data(name);
        let (status, message) = read(c_path(&path).as_ptr()).err().unwrap_or_else(|| panic!("{name} read"));
        assert_eq!(status, DS_INVALID_MESH, "{name}: {message}");
        assert!(message.contains(name), "{name}: {message}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_non_utf8_path_names_its_file() {
    use std::os::unix::ffi::OsStrExt;
    let dir = scratch("bytes");
    let name = std::ffi::OsStr::from_bytes(b"t\xe9tra\xff.off");
    let path = dir.join(name);
    std::fs::copy(data("tetrahedron.off"), &path).unwrap();
    let m = read(c_path(&path).as_ptr()).expect("any bytes name a file on Unix");
    assert_eq!(arrays(&m), arrays(&read(c_path(&data("tetrahedron.off")).as_ptr()).unwrap()));
    // Missing, it is an error whose message shows the name (lossily).
    std::fs::remove_file(&path).unwrap();
    let (status, message) = read(c_path(&path).as_ptr()).err().unwrap();
    assert_eq!(status, DS_IO, "{message}");
    assert!(message.contains("tra"), "{message}");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_arguments_are_errors() {
    let path = c_path(&data("tetrahedron.off"));
    unsafe {
        assert_eq!(read(ptr::null()).err().unwrap().0, DS_INVALID_ARGUMENT);
        assert!(last_error().contains("path is NULL"), "{}", last_error());
        assert_eq!(read(c"".as_ptr()).err().unwrap().0, DS_INVALID_ARGUMENT);
        assert!(last_error().contains("path is empty"), "{}", last_error());
        assert_eq!(ds_mesh_read(path.as_ptr(), ptr::null_mut()), DS_INVALID_ARGUMENT);

        let m = read(path.as_ptr()).unwrap();
        let n = ds_mesh_n_vertices(m.0);
        let mut xyz = vec![0.0; 3 * n + 1];
        assert_eq!(ds_mesh_vertices(m.0, xyz.as_mut_ptr(), 3 * n + 1), DS_INVALID_ARGUMENT);
        assert!(last_error().contains(&format!("xyz_len is {}, expected 3 * ds_mesh_n_used_vertices = {}", 3 * n + 1, 3 * n)));
        assert_eq!(ds_mesh_vertices(m.0, ptr::null_mut(), 3 * n), DS_INVALID_ARGUMENT);
        let mut tri = vec![0u32; 2];
        assert_eq!(ds_mesh_faces(m.0, tri.as_mut_ptr(), 2), DS_INVALID_ARGUMENT);
        // Not a mesh handle: refused without being read.
        let mut options = ptr::null_mut();
        assert_eq!(ds_options_create(&mut options), DS_OK);
        assert_eq!(ds_mesh_vertices(options as *const ds_mesh, xyz.as_mut_ptr(), 3 * n), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("is a ds_options handle, not a ds_mesh"), "{}", last_error());
        ds_options_destroy(options);
        let stale = m.0;
        drop(m);
        assert_eq!(ds_mesh_faces(stale, tri.as_mut_ptr(), 2), DS_INVALID_ARGUMENT);
    }
}

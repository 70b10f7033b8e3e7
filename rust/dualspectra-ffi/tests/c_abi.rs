//! Laws of the C ABI, called from Rust exactly as C would call it: bad input gives a status
//! code and a message (never UB or a panic across the boundary), good input gives the core's
//! own results bit for bit, progress is reported and cancel works.

use dualspectra::mesh::generate::{disk, icosphere};
use dualspectra::shape::{Metric, Shape};
use dualspectra::TriMesh;
use dualspectra_ffi::c_abi::*;
use std::ffi::{c_char, c_int, c_void, CStr};
use std::ptr;

fn flat(mesh: &TriMesh) -> (Vec<f64>, Vec<u32>) {
    (mesh.vertices().as_flattened().to_vec(), mesh.faces().as_flattened().to_vec())
}

fn last_error() -> String {
    unsafe { CStr::from_ptr(ds_last_error_message()) }.to_string_lossy().into_owned()
}

/// A live mesh handle, destroyed on drop.
struct Handle(*mut ds_mesh);
impl Drop for Handle {
    fn drop(&mut self) {
        unsafe { ds_mesh_destroy(self.0) }
    }
}

fn create(mesh: &TriMesh) -> Handle {
    let (v, f) = flat(mesh);
    let mut h = ptr::null_mut();
    let s = unsafe { ds_mesh_create(v.as_ptr(), mesh.n_vertices(), f.as_ptr(), mesh.n_faces(), &mut h) };
    assert_eq!(s, DS_OK, "{}", last_error());
    assert!(!h.is_null());
    Handle(h)
}

#[test]
fn version_is_the_crate_version() {
    let v = unsafe { CStr::from_ptr(ds_version()) }.to_str().unwrap();
    assert_eq!(v, env!("CARGO_PKG_VERSION"));
    let parts: Vec<u32> = v.split('.').map(|p| p.parse().unwrap()).collect();
    assert_eq!(ds_version_number(), parts[0] * 10000 + parts[1] * 100 + parts[2]);
}

#[test]
fn status_names_are_distinct() {
    let names: Vec<String> = (0..=7)
        .map(|s| unsafe { CStr::from_ptr(ds_status_name(s)) }.to_string_lossy().into_owned())
        .collect();
    assert_eq!(names[0], "DS_OK");
    assert_eq!(names[2], "DS_INVALID_MESH");
    assert_eq!(names[7], "DS_UNKNOWN_STATUS");
    let mut unique = names.clone();
    unique.dedup();
    assert_eq!(unique.len(), names.len());
}

#[test]
fn null_pointers_are_errors() {
    let m = icosphere(1);
    let (v, f) = flat(&m);
    let mut h = ptr::null_mut();
    unsafe {
        assert_eq!(ds_mesh_create(ptr::null(), m.n_vertices(), f.as_ptr(), m.n_faces(), &mut h), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("xyz is NULL"), "{}", last_error());
        assert_eq!(ds_mesh_create(v.as_ptr(), m.n_vertices(), ptr::null(), m.n_faces(), &mut h), DS_INVALID_ARGUMENT);
        assert_eq!(ds_mesh_create(v.as_ptr(), m.n_vertices(), f.as_ptr(), m.n_faces(), ptr::null_mut()), DS_INVALID_ARGUMENT);
        assert!(h.is_null(), "out is written only on success");
        let mut out = [0.0; 4];
        assert_eq!(ds_gaussian_curvature(ptr::null(), 0, out.as_mut_ptr(), 4), DS_INVALID_ARGUMENT);
        assert_eq!(ds_spectrum(ptr::null(), 4, DS_METRIC_REGULAR, 0.33, out.as_mut_ptr(), 4), DS_INVALID_ARGUMENT);
        let mut r = ptr::null_mut();
        assert_eq!(ds_localize(ptr::null(), ptr::null(), ptr::null(), None, ptr::null_mut(), &mut r), DS_INVALID_ARGUMENT);
        assert!(r.is_null());
        assert_eq!(ds_result_region(ptr::null(), ptr::null_mut(), 0), DS_INVALID_ARGUMENT);
        let mut c = 0.0;
        assert_eq!(ds_result_cost(ptr::null(), &mut c), DS_INVALID_ARGUMENT);
        assert_eq!(ds_mesh_n_vertices(ptr::null()), 0);
        assert_eq!(ds_result_n_vertices(ptr::null()), 0);
        assert!(ds_result_warning(ptr::null(), 0).is_null());
        ds_mesh_destroy(ptr::null_mut());
        ds_result_destroy(ptr::null_mut());
    }
}

#[test]
fn empty_and_overflowing_sizes_are_errors() {
    let mut h = ptr::null_mut();
    unsafe {
        assert_eq!(ds_mesh_create(ptr::null(), 0, ptr::null(), 0, &mut h), DS_INVALID_MESH);
        let x = [0.0f64; 3];
        let t = [0u32; 3];
        assert_eq!(ds_mesh_create(x.as_ptr(), usize::MAX, t.as_ptr(), 1, &mut h), DS_INVALID_ARGUMENT);
        assert_eq!(ds_mesh_create(x.as_ptr(), usize::MAX / 4, t.as_ptr(), 1, &mut h), DS_INVALID_ARGUMENT);
    }
    assert!(h.is_null());
}

#[test]
fn misaligned_pointers_are_errors() {
    let m = icosphere(0);
    let (v, f) = flat(&m);
    // Copy the positions one byte into a buffer: a valid address, wrong alignment for f64.
    let mut bytes = vec![0u8; v.len() * 8 + 1];
    for (i, x) in v.iter().enumerate() {
        bytes[1 + 8 * i..1 + 8 * i + 8].copy_from_slice(&x.to_ne_bytes());
    }
    let mut h = ptr::null_mut();
    let s = unsafe { ds_mesh_create(bytes.as_ptr().add(1) as *const f64, m.n_vertices(), f.as_ptr(), m.n_faces(), &mut h) };
    assert_eq!(s, DS_INVALID_ARGUMENT);
    assert!(last_error().contains("aligned"), "{}", last_error());
}

#[test]
fn out_of_range_index_is_an_invalid_mesh_naming_the_face() {
    let m = icosphere(1);
    let (v, mut f) = flat(&m);
    f[3 * 7 + 1] = m.n_vertices() as u32; // face 7
    let mut h = ptr::null_mut();
    let s = unsafe { ds_mesh_create(v.as_ptr(), m.n_vertices(), f.as_ptr(), m.n_faces(), &mut h) };
    assert_eq!(s, DS_INVALID_MESH);
    let msg = last_error();
    assert!(msg.contains("face 7") && msg.contains(&m.n_vertices().to_string()), "{msg}");
    assert!(h.is_null());
    // A success clears the message.
    let _ok = create(&m);
    assert_eq!(last_error(), "");
}

#[test]
fn non_finite_and_isolated_vertices() {
    let m = icosphere(1);
    let (mut v, f) = flat(&m);
    v[5] = f64::NAN;
    let mut h = ptr::null_mut();
    assert_eq!(unsafe { ds_mesh_create(v.as_ptr(), m.n_vertices(), f.as_ptr(), m.n_faces(), &mut h) }, DS_INVALID_MESH);
    // An extra unreferenced vertex: rejected by ds_mesh_create, dropped by the repairing variant.
    let (mut v, f) = flat(&m);
    v.splice(0..0, [9.0, 9.0, 9.0]);
    let f: Vec<u32> = f.iter().map(|i| i + 1).collect();
    let n = m.n_vertices() + 1;
    assert_eq!(unsafe { ds_mesh_create(v.as_ptr(), n, f.as_ptr(), m.n_faces(), &mut h) }, DS_INVALID_MESH);
    let mut kept = vec![u32::MAX; n];
    let mut n_kept = 0usize;
    let s = unsafe {
        ds_mesh_create_dropping_isolated(v.as_ptr(), n, f.as_ptr(), m.n_faces(), kept.as_mut_ptr(), n, &mut n_kept, &mut h)
    };
    assert_eq!(s, DS_OK, "{}", last_error());
    let h = Handle(h);
    assert_eq!(n_kept, m.n_vertices());
    assert_eq!(unsafe { ds_mesh_n_vertices(h.0) }, m.n_vertices());
    assert_eq!(&kept[..n_kept], &(1..n as u32).collect::<Vec<_>>()[..]);
    // Too small a `kept` buffer is an error, not an overflow.
    let mut h2 = ptr::null_mut();
    let s = unsafe {
        ds_mesh_create_dropping_isolated(v.as_ptr(), n, f.as_ptr(), m.n_faces(), kept.as_mut_ptr(), n - 1, ptr::null_mut(), &mut h2)
    };
    assert_eq!(s, DS_INVALID_ARGUMENT);
}

#[test]
fn curvature_is_the_cores_and_lengths_are_checked() {
    let m = icosphere(2);
    let h = create(&m);
    let n = m.n_vertices();
    assert_eq!(unsafe { ds_mesh_n_faces(h.0) }, m.n_faces());
    let mut k = vec![0.0; n];
    unsafe {
        assert_eq!(ds_gaussian_curvature(h.0, 0, k.as_mut_ptr(), n - 1), DS_INVALID_ARGUMENT);
        assert_eq!(ds_gaussian_curvature(h.0, 0, k.as_mut_ptr(), n + 1), DS_INVALID_ARGUMENT);
        assert_eq!(ds_gaussian_curvature(h.0, 0, ptr::null_mut(), n), DS_INVALID_ARGUMENT);
        assert_eq!(ds_gaussian_curvature(h.0, 0, k.as_mut_ptr(), n), DS_OK);
    }
    assert_eq!(k, dualspectra::geometry::gaussian_curvature(&m));
    unsafe { assert_eq!(ds_gaussian_curvature(h.0, 1, k.as_mut_ptr(), n), DS_OK) };
    assert_eq!(k, dualspectra::geometry::smoothed_gaussian_curvature(&m));
}

#[test]
fn spectrum_is_the_cores_and_arguments_are_checked() {
    let m = disk(1.0, 8);
    let h = create(&m);
    let mut out = vec![0.0; 6];
    unsafe {
        assert_eq!(ds_spectrum(h.0, 6, 7, 0.33, out.as_mut_ptr(), 6), DS_INVALID_ARGUMENT, "unknown metric");
        assert_eq!(ds_spectrum(h.0, 6, DS_METRIC_REGULAR, 0.33, out.as_mut_ptr(), 5), DS_INVALID_ARGUMENT);
        assert_eq!(ds_spectrum(h.0, 0, DS_METRIC_REGULAR, 0.33, out.as_mut_ptr(), 0), DS_INVALID_ARGUMENT);
        assert_eq!(ds_spectrum(h.0, 6, DS_METRIC_SCALE_INVARIANT, f64::NAN, out.as_mut_ptr(), 6), DS_INVALID_ARGUMENT);
        assert_eq!(ds_spectrum(h.0, 6, DS_METRIC_REGULAR, 0.33, out.as_mut_ptr(), 6), DS_OK, "{}", last_error());
    }
    let core = Shape::new(m.clone()).dirichlet_spectrum(Metric::Regular, 6).unwrap().values;
    assert_eq!(out, core);
    // Unit disk, Dirichlet: lambda_1 = j_{0,1}^2 = 5.7832 (discretisation error a few percent).
    assert!((out[0] - 5.7832).abs() < 0.05 * 5.7832, "{out:?}");
    for alpha in [0.33, 0.5] {
        unsafe { assert_eq!(ds_spectrum(h.0, 6, DS_METRIC_SCALE_INVARIANT, alpha, out.as_mut_ptr(), 6), DS_OK, "{}", last_error()) };
        let eps = dualspectra::geometry::metric::DEFAULT_EPS;
        let core = Shape::with_metric_params(m.clone(), alpha, eps).dirichlet_spectrum(Metric::ScaleInvariant, 6).unwrap().values;
        assert_eq!(out, core);
    }
}

#[test]
fn options_round_trip_and_are_checked() {
    let o = ds_options_default();
    let d = dualspectra::Options::default();
    assert_eq!((o.mode, o.k, o.alpha, o.seed), (DS_MODE_DUAL, d.k, d.alpha, d.seed));
    assert_eq!((o.resolution, o.centers, o.max_iterations, o.threads), (d.resolution, d.centers, d.max_iterations, d.threads));
    assert_eq!(o.selection, DS_SELECTION_GATED);
    assert_eq!((o.start_shape, o.spectral_cuts), (DS_STARTS_BALLS_AND_WIDE_BUMPS, d.spectral_cuts));
    assert_eq!(o.plane_cuts, d.plane_cuts);
    let full = create(&icosphere(2));
    let part = create(&disk(0.5, 4));
    let mut r = ptr::null_mut();
    for bad in [
        ds_options { mode: 9, ..o },
        ds_options { selection: 9, ..o },
        ds_options { start_shape: 9, ..o },
        ds_options { k: 0, ..o },
        ds_options { alpha: f64::INFINITY, ..o },
        ds_options { max_iterations: 0, ..o },
        ds_options { plane_cuts: 27, ..o },
    ] {
        let s = unsafe { ds_localize(full.0, part.0, &bad, None, ptr::null_mut(), &mut r) };
        assert_eq!(s, DS_INVALID_ARGUMENT, "{bad:?}: {}", last_error());
        assert!(r.is_null());
    }
}

struct Calls {
    fractions: Vec<f64>,
    stages: Vec<String>,
    cancel_after: usize,
}

unsafe extern "C" fn record(fraction: f64, stage: *const c_char, user: *mut c_void) -> c_int {
    let calls = unsafe { &mut *(user as *mut Calls) };
    calls.fractions.push(fraction);
    calls.stages.push(unsafe { CStr::from_ptr(stage) }.to_string_lossy().into_owned());
    (calls.fractions.len() < calls.cancel_after) as c_int
}

/// A small pair: a sphere and a cap of it, with few starts and iterations (fast).
fn small_pair() -> (TriMesh, TriMesh) {
    let full = icosphere(3);
    let keep: Vec<[u32; 3]> = full
        .faces()
        .iter()
        .filter(|f| f.iter().all(|&i| full.vertices()[i as usize][2] > 0.4))
        .copied()
        .collect();
    let (cap, _) = TriMesh::new_dropping_isolated(full.vertices().to_vec(), keep).unwrap();
    (full, cap)
}

fn fast_options() -> ds_options {
    ds_options { k: 6, centers: 2, max_iterations: 10, resolution: 0, ..ds_options_default() }
}

#[test]
fn cancel_from_the_callback() {
    let (full, cap) = small_pair();
    let (hf, hp) = (create(&full), create(&cap));
    let mut calls = Calls { fractions: vec![], stages: vec![], cancel_after: 1 };
    let mut r = ptr::null_mut();
    let o = fast_options();
    let s = unsafe { ds_localize(hf.0, hp.0, &o, Some(record), &mut calls as *mut Calls as *mut c_void, &mut r) };
    assert_eq!(s, DS_CANCELLED, "{}", last_error());
    assert!(r.is_null());
    assert_eq!(calls.fractions.len(), 1, "no call after the one that returned 0");
}

#[test]
fn start_options_reach_the_core() {
    // Each start shape gives its number of starts per centre, plus two per spectral cut.
    let (full, cap) = small_pair();
    let (hf, hp) = (create(&full), create(&cap));
    for (shape, per_centre) in [
        (DS_STARTS_BALLS_AND_WIDE_BUMPS, 3),
        (DS_STARTS_BALLS_AND_WIDE_GAUSSIANS, 4),
        (DS_STARTS_GAUSSIAN, 4),
        (DS_STARTS_AREA_BALL, 2),
    ] {
        let o = ds_options { start_shape: shape, spectral_cuts: 1, plane_cuts: 3, max_iterations: 2, ..fast_options() };
        let mut r = ptr::null_mut();
        let s = unsafe { ds_localize(hf.0, hp.0, &o, None, ptr::null_mut(), &mut r) };
        assert_eq!(s, DS_OK, "{}", last_error());
        let (mut sel, mut ns) = (usize::MAX, 0usize);
        unsafe {
            assert_eq!(ds_result_starts(r, &mut sel, &mut ns), DS_OK);
            ds_result_destroy(r);
        }
        assert_eq!(ns, per_centre * o.centers + 2 + 3, "start shape {shape}");
    }
}

#[test]
fn localize_reports_progress_and_fills_every_accessor() {
    let (full, cap) = small_pair();
    let (hf, hp) = (create(&full), create(&cap));
    let mut calls = Calls { fractions: vec![], stages: vec![], cancel_after: usize::MAX };
    let mut r = ptr::null_mut();
    let o = fast_options();
    let s = unsafe { ds_localize(hf.0, hp.0, &o, Some(record), &mut calls as *mut Calls as *mut c_void, &mut r) };
    assert_eq!(s, DS_OK, "{}", last_error());
    assert!(!r.is_null());
    assert!(!calls.fractions.is_empty());
    assert!(calls.fractions.iter().all(|f| (0.0..=1.0).contains(f)), "{:?}", calls.fractions);
    assert!(calls.stages.iter().all(|s| !s.is_empty()));

    // The same computation through the core, for the accessors' values.
    let opts = dualspectra::Options { k: 6, centers: 2, max_iterations: 10, resolution: 0, ..Default::default() };
    let core = dualspectra::localize(&full, &cap, &opts, &dualspectra::Progress::none()).unwrap();
    let n = full.n_vertices();
    unsafe {
        assert_eq!(ds_result_n_vertices(r), n);
        let mut region = vec![7u8; n];
        assert_eq!(ds_result_region(r, region.as_mut_ptr(), n - 1), DS_INVALID_ARGUMENT);
        assert_eq!(ds_result_region(r, region.as_mut_ptr(), n), DS_OK);
        assert_eq!(region, core.region.iter().map(|&b| b as u8).collect::<Vec<_>>());
        let mut x = vec![0.0; n];
        assert_eq!(ds_result_score(r, x.as_mut_ptr(), n), DS_OK);
        assert_eq!(x, core.score);
        assert_eq!(ds_result_potential(r, x.as_mut_ptr(), n), DS_OK);
        assert_eq!(x, core.potential);
        for (metric, ev, target) in [
            (DS_METRIC_REGULAR, &core.eigenvalues_regular, &core.target_regular),
            (DS_METRIC_SCALE_INVARIANT, &core.eigenvalues_si, &core.target_si),
        ] {
            let m = ds_result_n_eigenvalues(r, metric);
            assert_eq!(m, ev.len());
            let mut e = vec![0.0; m];
            assert_eq!(ds_result_eigenvalues(r, metric, e.as_mut_ptr(), m), DS_OK);
            assert_eq!(&e, ev);
            assert_eq!(ds_result_target_eigenvalues(r, metric, e.as_mut_ptr(), m), DS_OK);
            assert_eq!(&e, target);
        }
        assert_eq!(ds_result_n_eigenvalues(r, 5), 0);
        assert_eq!(ds_result_eigenvalues(r, 5, x.as_mut_ptr(), 0), DS_INVALID_ARGUMENT);
        let mut cost = f64::NAN;
        assert_eq!(ds_result_cost(r, &mut cost), DS_OK);
        assert_eq!(cost, core.cost);
        let mut t = ds_timings::default();
        assert_eq!(ds_result_timings(r, &mut t), DS_OK);
        let mut secs = 0.0;
        assert_eq!(ds_result_seconds(r, &mut secs), DS_OK);
        assert_eq!(secs, t.total);
        assert!(t.total > 0.0);
        let (mut sel, mut ns) = (usize::MAX, 0usize);
        assert_eq!(ds_result_starts(r, &mut sel, &mut ns), DS_OK);
        assert_eq!((sel, ns), (core.selected_start, core.n_starts));
        assert_eq!(ds_result_n_warnings(r), core.warnings.len());
        assert!(ds_result_warning(r, core.warnings.len()).is_null());
        ds_result_destroy(r);
    }
}

#[test]
fn last_error_is_per_thread() {
    let mut h = ptr::null_mut();
    unsafe { ds_mesh_create(ptr::null(), 3, ptr::null(), 1, &mut h) };
    let here = last_error();
    assert!(!here.is_empty());
    let there = std::thread::spawn(last_error).join().unwrap();
    assert_eq!(there, "");
    assert_eq!(last_error(), here);
}

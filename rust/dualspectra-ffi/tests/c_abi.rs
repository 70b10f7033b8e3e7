//! Laws of the C ABI, called from Rust exactly as C would call it: bad input gives a status
//! code and a message (never UB or a panic across the boundary), good input gives the core's
//! own results bit for bit, progress is reported and cancel works; options by name report the
//! core's ranges; a prepared localizer gives what the one-call form gives, also from several
//! threads; a host's mesh goes through the core intake and results come back in its numbering.

use dualspectra::mesh::generate::{disk, icosphere};
use dualspectra::shape::{Metric, Shape};
use dualspectra::TriMesh;
use dualspectra_ffi::c_abi::*;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
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
    let names: Vec<String> = (0..=9)
        .map(|s| unsafe { CStr::from_ptr(ds_status_name(s)) }.to_string_lossy().into_owned())
        .collect();
    assert_eq!(names[0], "DS_OK");
    assert_eq!(names[2], "DS_INVALID_MESH");
    assert_eq!(names[7], "DS_OUT_OF_MEMORY");
    assert_eq!(names[8], "DS_INVALID_PREPARED_SHAPE");
    assert_eq!(names[9], "DS_UNKNOWN_STATUS");
    let mut unique = names.clone();
    unique.sort();
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
        assert_eq!(ds_result_confidence(ptr::null(), &mut c), DS_INVALID_ARGUMENT);
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
    // An extra unreferenced vertex: rejected by the strict ds_mesh_create.
    let (mut v, f) = flat(&m);
    v.splice(0..0, [9.0, 9.0, 9.0]);
    let f: Vec<u32> = f.iter().map(|i| i + 1).collect();
    let n = m.n_vertices() + 1;
    assert_eq!(unsafe { ds_mesh_create(v.as_ptr(), n, f.as_ptr(), m.n_faces(), &mut h) }, DS_INVALID_MESH);
    assert!(last_error().contains("isolated"), "{}", last_error());
    // ... and by the intake, a non-finite coordinate still is.
    let (mut v, f) = flat(&m);
    v[5] = f64::INFINITY;
    assert_eq!(unsafe { ds_mesh_create_from_host(v.as_ptr(), m.n_vertices(), f.as_ptr(), m.n_faces(), &mut h) }, DS_INVALID_MESH);
    assert!(h.is_null());
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

/// The faces of `full` whose three vertices satisfy `inside`, as a mesh.
fn cut(full: &TriMesh, inside: impl Fn([f64; 3]) -> bool) -> TriMesh {
    let keep: Vec<[u32; 3]> =
        full.faces().iter().filter(|f| f.iter().all(|&i| inside(full.vertices()[i as usize]))).copied().collect();
    TriMesh::new_dropping_isolated(full.vertices().to_vec(), keep).unwrap().0
}

/// A small pair: a sphere and a cap of it (run with [`fast_options`]: few starts and
/// iterations).
fn small_pair() -> (TriMesh, TriMesh) {
    let full = icosphere(3);
    let cap = cut(&full, |p| p[2] > 0.4);
    (full, cap)
}

/// Options handle, destroyed on drop.
struct OptionsHandle(*mut ds_options);
impl Drop for OptionsHandle {
    fn drop(&mut self) {
        unsafe { ds_options_destroy(self.0) }
    }
}

fn options_handle() -> OptionsHandle {
    let mut o = ptr::null_mut();
    assert_eq!(unsafe { ds_options_create(&mut o) }, DS_OK, "{}", last_error());
    OptionsHandle(o)
}

fn set(o: &OptionsHandle, name: &str, value: &str) -> ds_status {
    let (n, v) = (CString::new(name).unwrap(), CString::new(value).unwrap());
    unsafe { ds_options_set(o.0, n.as_ptr(), v.as_ptr()) }
}

fn options_json(o: &OptionsHandle) -> serde_json::Value {
    serde_json::from_str(unsafe { CStr::from_ptr(ds_options_json(o.0)) }.to_str().unwrap()).unwrap()
}

/// Few starts and iterations, no decimation: a fast localization.
fn fast_options() -> OptionsHandle {
    let o = options_handle();
    let json = CString::new(r#"{"k": 6, "max_iterations": 10, "resolution": 0}"#).unwrap();
    assert_eq!(unsafe { ds_options_set_json(o.0, json.as_ptr()) }, DS_OK, "{}", last_error());
    o
}

/// [`fast_options`] in the core.
fn fast_core_options() -> dualspectra::Options {
    dualspectra::Options { k: 6, max_iterations: 10, resolution: 0, ..Default::default() }
}

#[test]
fn cancel_from_the_callback() {
    let (full, cap) = small_pair();
    let (hf, hp) = (create(&full), create(&cap));
    let mut calls = Calls { fractions: vec![], stages: vec![], cancel_after: 1 };
    let mut r = ptr::null_mut();
    let o = fast_options();
    let s = unsafe { ds_localize(hf.0, hp.0, o.0, Some(record), &mut calls as *mut Calls as *mut c_void, &mut r) };
    assert_eq!(s, DS_CANCELLED, "{}", last_error());
    assert!(r.is_null());
    assert_eq!(calls.fractions.len(), 1, "no call after the one that returned 0");
}

#[test]
fn localize_reports_progress_and_fills_every_accessor() {
    let (full, cap) = small_pair();
    let (hf, hp) = (create(&full), create(&cap));
    let mut calls = Calls { fractions: vec![], stages: vec![], cancel_after: usize::MAX };
    let mut r = ptr::null_mut();
    let o = fast_options();
    let s = unsafe { ds_localize(hf.0, hp.0, o.0, Some(record), &mut calls as *mut Calls as *mut c_void, &mut r) };
    assert_eq!(s, DS_OK, "{}", last_error());
    assert!(!r.is_null());
    assert!(!calls.fractions.is_empty());
    assert!(calls.fractions.iter().all(|f| (0.0..=1.0).contains(f)), "{:?}", calls.fractions);
    assert!(calls.stages.iter().all(|s| !s.is_empty()));

    // The same computation through the core, for the accessors' values.
    let core = dualspectra::localize(&full, &cap, &fast_core_options(), &dualspectra::Progress::none()).unwrap();
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
        let mut confidence = f64::NAN;
        assert_eq!(ds_result_confidence(r, &mut confidence), DS_OK);
        assert!((0.0..=1.0).contains(&confidence), "{confidence}");
        assert_eq!(confidence, core.confidence);
        assert_eq!(ds_result_confidence(r, ptr::null_mut()), DS_INVALID_ARGUMENT);
        let mut optimised_on = 0usize;
        assert_eq!(ds_result_optimisation_vertices(r, &mut optimised_on), DS_OK);
        assert!(optimised_on > 0);
        assert_eq!(optimised_on, core.optimisation_vertices);
        assert_eq!(ds_result_optimisation_vertices(ptr::null(), &mut optimised_on), DS_INVALID_ARGUMENT);
        let mut t = ds_timings::default();
        assert_eq!(ds_result_timings(r, &mut t), DS_OK);
        let mut secs = 0.0;
        assert_eq!(ds_result_seconds(r, &mut secs), DS_OK);
        assert_eq!(secs, t.total);
        assert!(t.preparation > 0.0 && t.optimisation > 0.0, "{t:?}");
        assert!(t.total >= t.preparation + t.optimisation, "{t:?}");
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

#[test]
fn options_by_name_are_the_cores_and_errors_name_the_option() {
    let o = options_handle();
    let defaults = serde_json::to_value(dualspectra::Options::default()).unwrap();
    assert_eq!(options_json(&o), defaults);
    assert_eq!(set(&o, "k", "12"), DS_OK, "{}", last_error());
    assert_eq!(set(&o, "mode", "LBO"), DS_OK, "{}", last_error());
    assert_eq!(set(&o, "alpha", " 0.5 "), DS_OK, "{}", last_error());
    let json = options_json(&o);
    assert_eq!((json["k"].as_u64(), json["mode"].as_str(), json["alpha"].as_f64()), (Some(12), Some("lbo"), Some(0.5)));
    for (name, value, says) in [
        ("k", "0", "k = 0 must be an integer in 1..=500"),
        ("k", "2.5", "k = 2.5"),
        ("k", "ten", "k = ten"),
        ("plane_cuts", "27", "0..=26"),
        ("alpha", "nan", "alpha"),
        ("mode", "both", "one of dual, lbo, si"),
        ("resolution", "50", "too coarse"),
        ("threads", "-1", "threads = -1"),
        ("seed", "0", "option 'seed' was removed in 0.3.0"),
        ("centers", "2", "option 'centers' was removed in 0.3.0"),
        ("selection", "gated", "unknown option 'selection'"),
    ] {
        assert_eq!(set(&o, name, value), DS_INVALID_ARGUMENT, "{name} = {value}");
        assert!(last_error().contains(says), "{name} = {value}: {}", last_error());
    }
    assert_eq!(options_json(&o), json, "a refused value leaves the options unchanged");
    // JSON: all or none.
    let good = CString::new(r#"{"plane_cuts": 14, "max_iterations": "7"}"#).unwrap();
    let bad = CString::new(r#"{"resolution": 300, "max_iterations": 0}"#).unwrap();
    let not_object = CString::new("[1, 2]").unwrap();
    let not_json = CString::new("{k: 1").unwrap();
    unsafe {
        assert_eq!(ds_options_set_json(o.0, good.as_ptr()), DS_OK, "{}", last_error());
        let json = options_json(&o);
        assert_eq!((json["plane_cuts"].as_u64(), json["max_iterations"].as_u64(), json["k"].as_u64()), (Some(14), Some(7), Some(12)));
        assert_eq!(ds_options_set_json(o.0, bad.as_ptr()), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("max_iterations = 0"), "{}", last_error());
        assert_eq!(options_json(&o)["resolution"], json["resolution"], "all or none");
        let removed = CString::new(r#"{"k": 8, "centers": 2}"#).unwrap();
        assert_eq!(ds_options_set_json(o.0, removed.as_ptr()), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("option 'centers' was removed"), "{}", last_error());
        assert_eq!(options_json(&o), json, "all or none");
        assert_eq!(ds_options_set_json(o.0, not_object.as_ptr()), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("JSON object"), "{}", last_error());
        assert_eq!(ds_options_set_json(o.0, not_json.as_ptr()), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("not valid JSON"), "{}", last_error());
        // NULL handles and strings.
        assert_eq!(ds_options_set(ptr::null_mut(), c"k".as_ptr(), c"1".as_ptr()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_options_set(o.0, ptr::null(), c"1".as_ptr()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_options_set(o.0, c"k".as_ptr(), ptr::null()), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("value is NULL"), "{}", last_error());
        assert_eq!(ds_options_set_json(o.0, ptr::null()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_options_create(ptr::null_mut()), DS_INVALID_ARGUMENT);
        assert!(ds_options_json(ptr::null()).is_null());
        ds_options_destroy(ptr::null_mut());
    }
}

#[test]
fn the_schema_is_the_cores_table() {
    let text = unsafe { CStr::from_ptr(ds_options_schema_json()) }.to_str().unwrap();
    assert_eq!(text, dualspectra::localizer::options_schema_json());
    assert_eq!(ds_options_schema_json(), ds_options_schema_json(), "a static string");
    let schema: serde_json::Value = serde_json::from_str(text).unwrap();
    let names: Vec<&str> = schema.as_array().unwrap().iter().map(|o| o["name"].as_str().unwrap()).collect();
    let table: Vec<&str> = dualspectra::localizer::OPTIONS.iter().map(|s| s.name).collect();
    assert_eq!(names, table);
    // Every default of the schema is accepted back by name.
    let o = options_handle();
    for entry in schema.as_array().unwrap() {
        let value = match &entry["default"] {
            serde_json::Value::String(t) => t.clone(),
            v => v.to_string(),
        };
        assert_eq!(set(&o, entry["name"].as_str().unwrap(), &value), DS_OK, "{entry}: {}", last_error());
    }
    assert_eq!(options_json(&o), serde_json::to_value(dualspectra::Options::default()).unwrap());
}

#[test]
fn options_out_of_range_are_refused_where_they_enter() {
    let (full, cap) = small_pair();
    let (hf, hp) = (create(&full), create(&cap));
    let o = fast_options();
    assert_eq!(set(&o, "plane_cuts", "27"), DS_INVALID_ARGUMENT);
    assert!(last_error().contains("plane_cuts = 27"), "{}", last_error());
    let mut r = ptr::null_mut();
    let mut l = ptr::null_mut();
    unsafe {
        assert_eq!(ds_localizer_create(hf.0, ptr::null(), None, ptr::null_mut(), ptr::null_mut()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_localizer_create(ptr::null(), o.0, None, ptr::null_mut(), &mut l), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("full is NULL"), "{}", last_error());
        assert_eq!(ds_localizer_locate(ptr::null(), hp.0, None, ptr::null_mut(), &mut r), DS_INVALID_ARGUMENT);
        assert!(l.is_null() && r.is_null());
        assert_eq!(ds_localizer_n_vertices(ptr::null()), 0);
        assert!(ds_localizer_warning(ptr::null(), 0).is_null());
        ds_localizer_destroy(ptr::null_mut());
    }
}

/// A localizer handle, destroyed on drop.
struct LocalizerHandle(*mut ds_localizer);
impl Drop for LocalizerHandle {
    fn drop(&mut self) {
        unsafe { ds_localizer_destroy(self.0) }
    }
}
// SAFETY: a ds_localizer may be used from several threads (the C ABI's promise under test).
unsafe impl Send for LocalizerHandle {}
unsafe impl Sync for LocalizerHandle {}

/// A mesh handle shared with threads (read only).
struct SharedMesh(*mut ds_mesh);
unsafe impl Send for SharedMesh {}
unsafe impl Sync for SharedMesh {}

/// Region, score and cost of a result; the result is destroyed.
fn take(r: *mut ds_result) -> (Vec<u8>, Vec<f64>, f64) {
    unsafe {
        let n = ds_result_n_vertices(r);
        let mut region = vec![9u8; n];
        let mut score = vec![f64::NAN; n];
        let mut cost = f64::NAN;
        assert_eq!(ds_result_region(r, region.as_mut_ptr(), n), DS_OK);
        assert_eq!(ds_result_score(r, score.as_mut_ptr(), n), DS_OK);
        assert_eq!(ds_result_cost(r, &mut cost), DS_OK);
        ds_result_destroy(r);
        (region, score, cost)
    }
}

fn one_call(full: *const ds_mesh, partial: *const ds_mesh, o: &OptionsHandle) -> (Vec<u8>, Vec<f64>, f64) {
    let mut r = ptr::null_mut();
    assert_eq!(unsafe { ds_localize(full, partial, o.0, None, ptr::null_mut(), &mut r) }, DS_OK, "{}", last_error());
    take(r)
}

#[test]
fn one_localizer_locates_several_partials_as_the_one_call_form_does() {
    let (full, cap) = small_pair();
    let side = cut(&full, |p| p[0] > 0.5);
    let (hf, hcap, hside) = (create(&full), create(&cap), create(&side));
    let o = fast_options();
    let mut l = ptr::null_mut();
    let mut calls = Calls { fractions: vec![], stages: vec![], cancel_after: usize::MAX };
    let s = unsafe { ds_localizer_create(hf.0, o.0, Some(record), &mut calls as *mut Calls as *mut c_void, &mut l) };
    assert_eq!(s, DS_OK, "{}", last_error());
    let l = LocalizerHandle(l);
    assert!(!calls.fractions.is_empty(), "preparation reports progress");
    drop(hf); // the localizer owns what it needs of the full mesh
    unsafe {
        assert_eq!(ds_localizer_n_vertices(l.0), full.n_vertices());
        assert_eq!(ds_localizer_optimisation_vertices(l.0), full.n_vertices(), "resolution 0: no decimation");
        let mut secs = -1.0;
        assert_eq!(ds_localizer_preparation_seconds(l.0, &mut secs), DS_OK);
        assert!(secs > 0.0);
        let json: serde_json::Value = serde_json::from_str(CStr::from_ptr(ds_localizer_options_json(l.0)).to_str().unwrap()).unwrap();
        assert_eq!(json, options_json(&o));
        assert_eq!(ds_localizer_n_warnings(l.0), 0);
    }
    let hf = create(&full);
    for partial in [&hcap, &hside, &hcap] {
        let mut r = ptr::null_mut();
        let s = unsafe { ds_localizer_locate(l.0, partial.0, None, ptr::null_mut(), &mut r) };
        assert_eq!(s, DS_OK, "{}", last_error());
        let mut t = ds_timings::default();
        assert_eq!(unsafe { ds_result_timings(r, &mut t) }, DS_OK);
        assert_eq!(t.preparation, 0.0, "a prepared localizer is not prepared again");
        let (region, score, cost) = take(r);
        assert!(region.contains(&1) && region.contains(&0));
        assert_eq!((region, score, cost), one_call(hf.0, partial.0, &o));
    }

    // From two threads at once: the same results as one after the other.
    let expected = [one_call(hf.0, hcap.0, &o), one_call(hf.0, hside.0, &o)];
    let shared = [SharedMesh(hcap.0), SharedMesh(hside.0)];
    let (l, shared) = (&l, &shared);
    let got: Vec<_> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..2)
            .map(|i| {
                scope.spawn(move || {
                    let mut r = ptr::null_mut();
                    let s = unsafe { ds_localizer_locate(l.0, shared[i].0, None, ptr::null_mut(), &mut r) };
                    assert_eq!(s, DS_OK, "{}", last_error());
                    take(r)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(got, expected);
}

#[test]
fn cancel_while_preparing() {
    let (full, _) = small_pair();
    let hf = create(&full);
    let o = fast_options();
    let mut calls = Calls { fractions: vec![], stages: vec![], cancel_after: 1 };
    let mut l = ptr::null_mut();
    let s = unsafe { ds_localizer_create(hf.0, o.0, Some(record), &mut calls as *mut Calls as *mut c_void, &mut l) };
    assert_eq!(s, DS_CANCELLED, "{}", last_error());
    assert!(l.is_null());
}

/// `mesh` as a host's arrays: a loose vertex first (host index 0), then the mesh's vertices,
/// then three collinear vertices with a zero-area face on them; and a face repeating a vertex.
fn with_host_debris(mesh: &TriMesh) -> (Vec<f64>, Vec<u32>) {
    let (mut v, f) = flat(mesh);
    v.splice(0..0, [5.0, 5.0, 5.0]);
    let n = mesh.n_vertices() as u32 + 1;
    v.extend_from_slice(&[3.0, 0.0, 0.0, 3.5, 0.0, 0.0, 4.0, 0.0, 0.0]);
    let mut f: Vec<u32> = f.iter().map(|i| i + 1).collect();
    f.extend_from_slice(&[n, n + 1, n + 2, 1, 1, 2]);
    (v, f)
}

fn host_mesh(v: &[f64], f: &[u32]) -> Handle {
    let mut h = ptr::null_mut();
    let s = unsafe { ds_mesh_create_from_host(v.as_ptr(), v.len() / 3, f.as_ptr(), f.len() / 3, &mut h) };
    assert_eq!(s, DS_OK, "{}", last_error());
    Handle(h)
}

#[test]
fn a_host_mesh_goes_through_the_intake_and_results_come_back_in_its_numbering() {
    let (full, cap) = small_pair();
    let (v, f) = with_host_debris(&full);
    let n_host = v.len() / 3;
    let host = host_mesh(&v, &f);
    // The strict constructor refuses the same arrays.
    let mut h = ptr::null_mut();
    assert_eq!(unsafe { ds_mesh_create(v.as_ptr(), n_host, f.as_ptr(), f.len() / 3, &mut h) }, DS_INVALID_MESH);
    // The map: host vertex 1 + i is mesh vertex i.
    let used: Vec<u32> = (1..=full.n_vertices() as u32).collect();
    unsafe {
        assert_eq!(ds_mesh_n_vertices(host.0), n_host);
        assert_eq!(ds_mesh_n_used_vertices(host.0), full.n_vertices());
        assert_eq!(ds_mesh_n_faces(host.0), full.n_faces());
        let mut got = vec![0u32; full.n_vertices()];
        assert_eq!(ds_mesh_used_vertices(host.0, got.as_mut_ptr(), got.len() - 1), DS_INVALID_ARGUMENT);
        assert_eq!(ds_mesh_used_vertices(host.0, got.as_mut_ptr(), got.len()), DS_OK);
        assert_eq!(got, used);
        let warning = CStr::from_ptr(ds_mesh_warning(host.0)).to_str().unwrap().to_owned();
        assert!(warning.contains("2 degenerate face(s) and 4 vertex(es)"), "{warning}");
        let strict = create(&full);
        assert!(ds_mesh_warning(strict.0).is_null());
        // Per-vertex quantities are in the host's numbering, 0 at left-out vertices.
        let mut k = vec![f64::NAN; n_host];
        assert_eq!(ds_gaussian_curvature(host.0, 0, k.as_mut_ptr(), full.n_vertices()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_gaussian_curvature(host.0, 0, k.as_mut_ptr(), n_host), DS_OK);
        let core = dualspectra::geometry::gaussian_curvature(&full);
        assert_eq!(&k[1..=full.n_vertices()], &core[..]);
        assert_eq!([k[0], k[n_host - 3], k[n_host - 2], k[n_host - 1]], [0.0; 4]);
    }

    // Results: the strict mesh's, scattered to the host's numbering, with the intake's notes.
    let partial = create(&cap);
    let o = fast_options();
    let strict = create(&full);
    let (region, score, cost) = one_call(strict.0, partial.0, &o);
    let mut r = ptr::null_mut();
    assert_eq!(unsafe { ds_localize(host.0, partial.0, o.0, None, ptr::null_mut(), &mut r) }, DS_OK, "{}", last_error());
    let warnings: Vec<String> = (0..unsafe { ds_result_n_warnings(r) })
        .map(|i| unsafe { CStr::from_ptr(ds_result_warning(r, i)) }.to_string_lossy().into_owned())
        .collect();
    assert!(warnings[0].starts_with("full mesh: left out 2 degenerate face(s) and 4 vertex(es)"), "{warnings:?}");
    assert_eq!(unsafe { ds_result_n_vertices(r) }, n_host);
    let (host_region, host_score, host_cost) = take(r);
    assert_eq!(host_cost, cost);
    assert_eq!(&host_region[1..=full.n_vertices()], &region[..]);
    assert_eq!(&host_score[1..=full.n_vertices()], &score[..]);
    assert_eq!((host_region[0], host_region[n_host - 1], host_score[0]), (0, 0, 0.0));

    // The same through a localizer, with a host partial too: its note is in the result.
    let (pv, pf) = with_host_debris(&cap);
    let host_partial = host_mesh(&pv, &pf);
    let mut l = ptr::null_mut();
    assert_eq!(unsafe { ds_localizer_create(host.0, o.0, None, ptr::null_mut(), &mut l) }, DS_OK, "{}", last_error());
    let l = LocalizerHandle(l);
    unsafe {
        assert_eq!(ds_localizer_n_vertices(l.0), n_host);
        assert_eq!(ds_localizer_n_warnings(l.0), 1);
        let w = CStr::from_ptr(ds_localizer_warning(l.0, 0)).to_string_lossy();
        assert!(w.starts_with("full mesh: left out"), "{w}");
        assert!(ds_localizer_warning(l.0, 1).is_null());
        let mut r = ptr::null_mut();
        assert_eq!(ds_localizer_locate(l.0, host_partial.0, None, ptr::null_mut(), &mut r), DS_OK, "{}", last_error());
        let notes: Vec<String> =
            (0..ds_result_n_warnings(r)).map(|i| CStr::from_ptr(ds_result_warning(r, i)).to_string_lossy().into_owned()).collect();
        assert!(notes[0].starts_with("full mesh: left out") && notes[1].starts_with("partial mesh: left out"), "{notes:?}");
        let (lr, ls, lc) = take(r);
        assert_eq!((lr, ls, lc), (host_region, host_score, host_cost), "a host partial is the same partial");
    }
}

#[test]
fn host_meshes_the_intake_cannot_repair_are_refused_in_the_hosts_numbering() {
    let mut h = ptr::null_mut();
    // Only a zero-area face.
    let v = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0];
    let f = [0u32, 1, 2];
    assert_eq!(unsafe { ds_mesh_create_from_host(v.as_ptr(), 3, f.as_ptr(), 1, &mut h) }, DS_INVALID_MESH);
    assert!(last_error().contains("degenerate"), "{}", last_error());
    // A face naming a vertex the host does not have, as the host numbers it.
    let f = [0u32, 1, 2, 0, 2, 7];
    assert_eq!(unsafe { ds_mesh_create_from_host(v.as_ptr(), 3, f.as_ptr(), 2, &mut h) }, DS_INVALID_MESH);
    assert!(last_error().contains("face 1 refers to vertex 7"), "{}", last_error());
    // A NaN coordinate behind a loose vertex: named as the host numbers it (3), not as the
    // intake would after leaving the loose vertex out (2).
    let v = [9.0, 9.0, 9.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, f64::NAN, 1.0, 0.0, 1.0, 1.0, 0.0];
    let f = [1u32, 2, 3, 2, 4, 3];
    assert_eq!(unsafe { ds_mesh_create_from_host(v.as_ptr(), 5, f.as_ptr(), 2, &mut h) }, DS_INVALID_MESH);
    assert!(last_error().contains("vertex 3 has a non-finite coordinate"), "{}", last_error());
    assert!(h.is_null());
}

#[test]
fn host_meshes_with_non_manifold_edges_are_split_and_said_so() {
    // A loose vertex 0, then three triangles on the edge (1, 2): strictly refused; through
    // the intake the third gets copies of 1 and 2, listed after the used host vertices.
    let v = [9.0, 9.0, 9.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.5, -1.0, 0.0, 0.5, 0.0, 1.0];
    let f = [1u32, 2, 3, 2, 1, 4, 1, 2, 5];
    let mut h = ptr::null_mut();
    assert_eq!(unsafe { ds_mesh_create(v.as_ptr(), 6, f.as_ptr(), 3, &mut h) }, DS_INVALID_MESH);
    assert!(last_error().contains("edge (1, 2) is shared by 3 faces"), "{}", last_error());
    let host = host_mesh(&v, &f);
    unsafe {
        assert_eq!((ds_mesh_n_vertices(host.0), ds_mesh_n_used_vertices(host.0)), (6, 7));
        let mut used = vec![0u32; 7];
        assert_eq!(ds_mesh_used_vertices(host.0, used.as_mut_ptr(), used.len()), DS_OK);
        assert_eq!(used, [1, 2, 3, 4, 5, 1, 2]);
        let warning = CStr::from_ptr(ds_mesh_warning(host.0)).to_str().unwrap().to_owned();
        assert!(warning.contains("split 1 non-manifold edge(s) and 2 non-manifold vertex(es)"), "{warning}");
        // Per-vertex arrays stay in the host's numbering; a split vertex reads its first copy.
        let mut k = vec![f64::NAN; 6];
        assert_eq!(ds_gaussian_curvature(host.0, 0, k.as_mut_ptr(), k.len()), DS_OK);
        let intake = dualspectra::mesh::intake::MeshIntake::from_flat(&v, &f).unwrap();
        let core = dualspectra::geometry::gaussian_curvature(&intake.mesh);
        assert_eq!(k, [0.0, core[0], core[1], core[2], core[3], core[4]]);
        assert_ne!(core[0], core[5], "the copy of host vertex 1 is another fan");
    }
}

//! Laws of the C ABI's search and prepared-shape files, called as C would call them: a
//! partial ranked against a small generated library finds the model it was cut from first,
//! with the core's scores and each shape's result readable (borrowed) from the ranking; a
//! shape the partial cannot be on ranks last with its reason; a saved localizer loads back
//! with the same answers in the host's numbering; foreign, stale and missing files and bad
//! arguments are clear statuses; the callback cancels.

use dualspectra::evaluation::synthetic::{default_limbs, figure, horned_limbs, synthetic_pair, Limb, SyntheticPair, SyntheticParams};
use dualspectra::TriMesh;
use dualspectra_ffi::c_abi::*;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::path::PathBuf;
use std::ptr;
use std::sync::OnceLock;

fn last_error() -> String {
    unsafe { CStr::from_ptr(ds_last_error_message()) }.to_string_lossy().into_owned()
}

/// Handles made once and shared by the tests (read only: meshes and localizers may be used
/// from several threads at once).
struct Library {
    partial: *mut ds_mesh,
    /// A figure without a head, the figure the partial was cut from, a horned figure, and the
    /// figure at a tenth of its size (smaller than the partial: it cannot take it).
    localizers: Vec<*mut ds_localizer>,
    pair: SyntheticPair,
}
unsafe impl Send for Library {}
unsafe impl Sync for Library {}

const RIGHT: usize = 1;
const TOO_SMALL: usize = 3;

fn mesh(m: &TriMesh) -> *mut ds_mesh {
    let (v, f) = (m.vertices().as_flattened(), m.faces().as_flattened());
    let mut h = ptr::null_mut();
    assert_eq!(unsafe { ds_mesh_create(v.as_ptr(), m.n_vertices(), f.as_ptr(), m.n_faces(), &mut h) }, DS_OK, "{}", last_error());
    h
}

/// Few starts (2 plane cuts, 2 descriptor starts) and iterations, two threads.
fn light_options() -> *mut ds_options {
    let mut o = ptr::null_mut();
    let json = CString::new(r#"{"k": 6, "max_iterations": 8, "plane_cuts": 2, "threads": 2}"#).unwrap();
    unsafe {
        assert_eq!(ds_options_create(&mut o), DS_OK);
        assert_eq!(ds_options_set_json(o, json.as_ptr()), DS_OK, "{}", last_error());
    }
    o
}

fn prepare(full: *const ds_mesh) -> *mut ds_localizer {
    let o = light_options();
    let mut l = ptr::null_mut();
    let s = unsafe { ds_localizer_create(full, o, None, ptr::null_mut(), &mut l) };
    unsafe { ds_options_destroy(o) };
    assert_eq!(s, DS_OK, "{}", last_error());
    l
}

fn library() -> &'static Library {
    static LIBRARY: OnceLock<Library> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let pair = synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() }).unwrap();
        let headless: Vec<Limb> = default_limbs().into_iter().skip(1).collect();
        let small = pair.full.map_positions(|p| p.map(|c| 0.1 * c)).unwrap();
        let fulls = [figure(3, &headless).unwrap(), pair.full.clone(), figure(3, &horned_limbs()).unwrap(), small];
        let localizers = fulls
            .iter()
            .map(|m| {
                let h = mesh(m);
                let l = prepare(h);
                unsafe { ds_mesh_destroy(h) };
                l
            })
            .collect();
        Library { partial: mesh(&pair.partial), localizers, pair }
    })
}

struct Calls {
    fractions: Vec<f64>,
    cancel_after: usize,
}

unsafe extern "C" fn record(fraction: f64, _stage: *const c_char, user: *mut c_void) -> c_int {
    let calls = unsafe { &mut *(user as *mut Calls) };
    calls.fractions.push(fraction);
    (calls.fractions.len() < calls.cancel_after) as c_int
}

/// Run `ds_search` over `localizers`; the status and the ranking (NULL on failure).
fn search(localizers: &[*mut ds_localizer], top: usize, calls: Option<&mut Calls>) -> (ds_status, *mut ds_search_result) {
    let pointers: Vec<*const ds_localizer> = localizers.iter().map(|&l| l as *const _).collect();
    let (progress, user): (ds_progress_fn, *mut c_void) = match calls {
        Some(c) => (Some(record), c as *mut Calls as *mut c_void),
        None => (None, ptr::null_mut()),
    };
    let mut out = ptr::null_mut();
    let s = unsafe { ds_search(pointers.as_ptr(), pointers.len(), library().partial, top, progress, user, &mut out) };
    (s, out)
}

/// (index, score) of each rank.
fn ranking(s: *const ds_search_result) -> Vec<(usize, f64)> {
    (0..unsafe { ds_search_result_count(s) })
        .map(|rank| {
            let (mut index, mut score) = (usize::MAX, f64::NAN);
            unsafe {
                assert_eq!(ds_search_result_index(s, rank, &mut index), DS_OK, "{}", last_error());
                assert_eq!(ds_search_result_score(s, rank, &mut score), DS_OK, "{}", last_error());
            }
            (index, score)
        })
        .collect()
}

fn region(r: *const ds_result) -> Vec<u8> {
    let n = unsafe { ds_result_n_vertices(r) };
    let mut out = vec![9u8; n];
    assert_eq!(unsafe { ds_result_region(r, out.as_mut_ptr(), n) }, DS_OK, "{}", last_error());
    out
}

fn locate(l: *const ds_localizer, partial: *const ds_mesh) -> *mut ds_result {
    let mut r = ptr::null_mut();
    assert_eq!(unsafe { ds_localizer_locate(l, partial, None, ptr::null_mut(), &mut r) }, DS_OK, "{}", last_error());
    r
}

#[test]
fn the_model_the_partial_was_cut_from_ranks_first() {
    let lib = library();
    let mut calls = Calls { fractions: vec![], cancel_after: usize::MAX };
    let (s, found) = search(&lib.localizers, 10, Some(&mut calls));
    assert_eq!(s, DS_OK, "{}", last_error());
    let order = ranking(found);
    println!("ranking (index, score): {order:?}");
    assert_eq!(order.len(), lib.localizers.len(), "top above the count keeps every shape");
    assert_eq!(order[0].0, RIGHT, "ranking {order:?}");
    assert!(order.windows(2).all(|w| w[0].1 <= w[1].1), "best (lowest) first: {order:?}");
    // Progress over the shapes, from 0 to 1.
    assert!(calls.fractions.windows(2).all(|w| w[0] <= w[1] + 1e-12), "{:?}", calls.fractions);
    assert_eq!(calls.fractions.last(), Some(&1.0));

    // The shape too small for the partial ranks last, with its reason and no result.
    let last = order.len() - 1;
    assert_eq!(order[last], (TOO_SMALL, f64::INFINITY));
    unsafe {
        assert!(ds_search_result_result(found, last).is_null());
        let why = CStr::from_ptr(ds_search_result_error(found, last)).to_string_lossy();
        assert!(why.contains("cannot be a part of it"), "{why}");
        assert!(ds_search_result_error(found, 0).is_null(), "no error where the partial was located");
    }

    // Each located shape's result is borrowed from the ranking and read like any result: its
    // score is the similarity score ranked by, its arrays are that shape's.
    for (rank, &(index, score)) in order.iter().enumerate().take(last) {
        let r = unsafe { ds_search_result_result(found, rank) };
        assert!(!r.is_null(), "rank {rank}: {}", last_error());
        let mut similarity = f64::NAN;
        assert_eq!(unsafe { ds_result_similarity_score(r, &mut similarity) }, DS_OK);
        assert_eq!(similarity.to_bits(), score.to_bits());
        assert!(score.is_finite() && score >= 0.0, "{score}");
        assert_eq!(unsafe { ds_result_n_vertices(r) }, unsafe { ds_localizer_n_vertices(lib.localizers[index]) });
    }
    // The best is what ds_localizer_locate finds on that shape, and its region is the cut.
    let best = unsafe { ds_search_result_result(found, 0) };
    let direct = locate(lib.localizers[RIGHT], lib.partial);
    assert_eq!(region(best), region(direct));
    let (mut a, mut b) = (f64::NAN, f64::NAN);
    unsafe {
        assert_eq!(ds_result_similarity_score(direct, &mut a), DS_OK);
        assert_eq!(ds_result_confidence(best, &mut b), DS_OK);
        assert!((0.0..=1.0).contains(&b));
        ds_result_destroy(direct);
    }
    assert_eq!(a.to_bits(), order[0].1.to_bits());
    let truth = &lib.pair.gt;
    let found_region = region(best);
    let both = truth.iter().zip(&found_region).filter(|(&t, &f)| t && f == 1).count();
    let either = truth.iter().zip(&found_region).filter(|(&t, &f)| t || f == 1).count();
    assert!(both as f64 >= 0.5 * either as f64, "IoU {both}/{either}");
    unsafe { ds_search_result_destroy(found) };

    // top keeps the best only (here the shape that cannot take the partial goes).
    let (s, best_only) = search(&[lib.localizers[TOO_SMALL], lib.localizers[RIGHT]], 1, None);
    assert_eq!(s, DS_OK, "{}", last_error());
    assert_eq!(ranking(best_only), [(1, order[0].1)]);
    unsafe { ds_search_result_destroy(best_only) };
}

#[test]
fn search_arguments_are_checked() {
    let lib = library();
    let l = lib.localizers[RIGHT] as *const ds_localizer;
    let mut out = ptr::null_mut();
    unsafe {
        let one = [l];
        assert_eq!(ds_search(ptr::null(), 2, lib.partial, 1, None, ptr::null_mut(), &mut out), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("localizers is NULL but its length is 2"), "{}", last_error());
        let with_null = [l, ptr::null()];
        assert_eq!(ds_search(with_null.as_ptr(), 2, lib.partial, 1, None, ptr::null_mut(), &mut out), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("localizers[1] is NULL"), "{}", last_error());
        let a_mesh = [lib.partial as *const ds_localizer];
        assert_eq!(ds_search(a_mesh.as_ptr(), 1, lib.partial, 1, None, ptr::null_mut(), &mut out), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("localizers[0] is a ds_mesh handle, not a ds_localizer"), "{}", last_error());
        assert_eq!(ds_search(one.as_ptr(), 1, ptr::null(), 1, None, ptr::null_mut(), &mut out), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("partial is NULL"), "{}", last_error());
        assert_eq!(ds_search(one.as_ptr(), 1, lib.partial, 0, None, ptr::null_mut(), &mut out), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("top is 0"), "{}", last_error());
        assert_eq!(ds_search(one.as_ptr(), 1, lib.partial, 1, None, ptr::null_mut(), ptr::null_mut()), DS_INVALID_ARGUMENT);
        assert!(out.is_null(), "out is written only on success");

        // No shapes: an empty ranking.
        assert_eq!(ds_search(ptr::null(), 0, lib.partial, 3, None, ptr::null_mut(), &mut out), DS_OK, "{}", last_error());
        assert_eq!(ds_search_result_count(out), 0);
        let (mut index, mut score) = (0usize, 0.0);
        assert_eq!(ds_search_result_index(out, 0, &mut index), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("rank 0 is out of range (0 shapes ranked)"), "{}", last_error());
        assert_eq!(ds_search_result_score(out, 0, &mut score), DS_INVALID_ARGUMENT);
        assert!(ds_search_result_result(out, 0).is_null() && ds_search_result_error(out, 0).is_null());
        ds_search_result_destroy(out);

        // NULL and wrong-kind rankings.
        assert_eq!(ds_search_result_count(ptr::null()), 0);
        assert_eq!(ds_search_result_index(ptr::null(), 0, &mut index), DS_INVALID_ARGUMENT);
        assert_eq!(ds_search_result_count(l as *const ds_search_result), 0);
        assert!(last_error().contains("search is a ds_localizer handle, not a ds_search_result"), "{}", last_error());
        assert!(ds_search_result_result(ptr::null(), 0).is_null());
        ds_search_result_destroy(ptr::null_mut());
        assert_eq!(ds_result_similarity_score(ptr::null(), &mut score), DS_INVALID_ARGUMENT);
    }
}

#[test]
fn cancel_stops_the_search() {
    let lib = library();
    let mut calls = Calls { fractions: vec![], cancel_after: 2 };
    let (s, out) = search(&lib.localizers[..2], 2, Some(&mut calls));
    assert_eq!(s, DS_CANCELLED, "{}", last_error());
    assert!(out.is_null());
    assert_eq!(calls.fractions.len(), 2, "no call after the one that returned 0");
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dualspectra_ffi_search_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn c_path(p: &std::path::Path) -> CString {
    CString::new(p.to_str().unwrap()).unwrap()
}

fn load(path: &std::path::Path) -> (ds_status, *mut ds_localizer) {
    let mut l = ptr::null_mut();
    let s = unsafe { ds_localizer_load(c_path(path).as_ptr(), &mut l) };
    (s, l)
}

#[test]
fn a_saved_localizer_loads_back_with_the_same_answers_in_the_hosts_numbering() {
    let lib = library();
    // The full mesh as a host's arrays: a loose vertex first, so that host vertex 1 + i is
    // mesh vertex i.
    let full = &lib.pair.full;
    let mut xyz = vec![7.0, 7.0, 7.0];
    xyz.extend_from_slice(full.vertices().as_flattened());
    let tri: Vec<u32> = full.faces().as_flattened().iter().map(|i| i + 1).collect();
    let mut host = ptr::null_mut();
    let s = unsafe { ds_mesh_create_from_host(xyz.as_ptr(), xyz.len() / 3, tri.as_ptr(), tri.len() / 3, &mut host) };
    assert_eq!(s, DS_OK, "{}", last_error());
    let fresh = prepare(host);
    unsafe { ds_mesh_destroy(host) };

    let path = tmp("full.dsprep");
    assert_eq!(unsafe { ds_localizer_save(fresh, c_path(&path).as_ptr()) }, DS_OK, "{}", last_error());
    let (s, loaded) = load(&path);
    assert_eq!(s, DS_OK, "{}", last_error());
    unsafe {
        assert_eq!(ds_localizer_n_vertices(loaded), full.n_vertices() + 1, "the host's numbering is kept");
        assert_eq!(ds_localizer_optimisation_vertices(loaded), ds_localizer_optimisation_vertices(fresh));
        let json = |l| CStr::from_ptr(ds_localizer_options_json(l)).to_string_lossy().into_owned();
        assert_eq!(json(loaded), json(fresh));
    }
    let (a, b) = (locate(fresh, lib.partial), locate(loaded, lib.partial));
    let n = full.n_vertices() + 1;
    let (mut sa, mut sb) = (vec![0.0; n], vec![0.0; n]);
    let (mut ca, mut cb) = (f64::NAN, f64::NAN);
    unsafe {
        assert_eq!(ds_result_score(a, sa.as_mut_ptr(), n), DS_OK);
        assert_eq!(ds_result_score(b, sb.as_mut_ptr(), n), DS_OK);
        assert_eq!(ds_result_similarity_score(a, &mut ca), DS_OK);
        assert_eq!(ds_result_similarity_score(b, &mut cb), DS_OK);
    }
    let (ra, rb) = (region(a), region(b));
    assert_eq!(ra, rb);
    assert_eq!(ra[0], 0, "the loose host vertex is in no region");
    assert_eq!(sa.iter().map(|x| x.to_bits()).collect::<Vec<_>>(), sb.iter().map(|x| x.to_bits()).collect::<Vec<_>>());
    assert_eq!(ca.to_bits(), cb.to_bits());
    unsafe {
        ds_result_destroy(a);
        ds_result_destroy(b);
        ds_localizer_destroy(loaded);
        ds_localizer_destroy(fresh);
    }
}

#[test]
fn foreign_stale_and_missing_files_are_clear_errors() {
    let lib = library();
    let good = tmp("good.dsprep");
    assert_eq!(unsafe { ds_localizer_save(lib.localizers[RIGHT], c_path(&good).as_ptr()) }, DS_OK, "{}", last_error());
    let bytes = std::fs::read(&good).unwrap();

    let foreign = tmp("mesh.off");
    std::fs::write(&foreign, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    let mut stale_bytes = bytes.clone();
    stale_bytes[8..12].copy_from_slice(&999u32.to_le_bytes()); // the format version, after the magic
    let stale = tmp("stale.dsprep");
    std::fs::write(&stale, &stale_bytes).unwrap();
    let truncated = tmp("truncated.dsprep");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    for (path, says) in [
        (&foreign, "not a dualspectra prepared shape"),
        (&stale, "stale prepared shape: format version 999"),
        (&truncated, "truncated"),
    ] {
        let (s, l) = load(path);
        assert_eq!(s, DS_INVALID_PREPARED_SHAPE, "{}: {}", path.display(), last_error());
        let msg = last_error();
        assert!(msg.contains(says) && msg.contains(path.to_str().unwrap()), "{msg}");
        assert!(l.is_null());
    }
    assert_eq!(unsafe { CStr::from_ptr(ds_status_name(DS_INVALID_PREPARED_SHAPE)) }.to_str().unwrap(), "DS_INVALID_PREPARED_SHAPE");

    let missing = tmp("missing.dsprep");
    assert_eq!(load(&missing).0, DS_IO);
    assert!(last_error().contains("missing.dsprep"), "{}", last_error());
    let nowhere = tmp("no_such_folder").join("x.dsprep");
    assert_eq!(unsafe { ds_localizer_save(lib.localizers[RIGHT], c_path(&nowhere).as_ptr()) }, DS_IO);
    let mut l = ptr::null_mut();
    unsafe {
        assert_eq!(ds_localizer_load(ptr::null(), &mut l), DS_INVALID_ARGUMENT);
        assert_eq!(ds_localizer_load(c"".as_ptr(), &mut l), DS_INVALID_ARGUMENT);
        assert!(last_error().contains("path is empty"), "{}", last_error());
        assert_eq!(ds_localizer_load(c_path(&good).as_ptr(), ptr::null_mut()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_localizer_save(ptr::null(), c_path(&good).as_ptr()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_localizer_save(lib.localizers[RIGHT], ptr::null()), DS_INVALID_ARGUMENT);
        assert_eq!(ds_localizer_save(lib.partial as *const ds_localizer, c_path(&good).as_ptr()), DS_INVALID_ARGUMENT);
    }
    assert!(l.is_null());
}

/// `ds_search_screened` with a shortlist of 1 locates the partial on the shape the screen
/// ranks best (the one it was cut from, with the same region as a direct localization); the
/// others follow not located, without an error, with a screen score no better than the first;
/// `ds_search` reports NaN screen scores; a shortlist of 0 is refused.
#[test]
fn a_screened_search_locates_the_shortlist_only() {
    let lib = library();
    let shapes = &lib.localizers[..3];
    let pointers: Vec<*const ds_localizer> = shapes.iter().map(|&l| l as *const _).collect();
    let mut out = ptr::null_mut();
    let s = unsafe { ds_search_screened(pointers.as_ptr(), pointers.len(), lib.partial, 1, usize::MAX, None, ptr::null_mut(), &mut out) };
    assert_eq!(s, DS_OK, "{}", last_error());
    let ranked = ranking(out);
    assert_eq!(ranked.len(), 3);
    assert_eq!(ranked[0].0, RIGHT);
    let screen = |rank: usize| {
        let mut x = f64::NAN;
        assert_eq!(unsafe { ds_search_result_screen_score(out, rank, &mut x) }, DS_OK, "{}", last_error());
        x
    };
    assert!(screen(0).is_finite());
    for (rank, &(_, score)) in ranked.iter().enumerate().skip(1) {
        assert!(score.is_infinite());
        assert!(unsafe { ds_search_result_result(out, rank) }.is_null());
        assert!(unsafe { ds_search_result_error(out, rank) }.is_null());
        assert!(screen(rank) >= screen(0));
    }
    let direct = locate(lib.localizers[RIGHT], lib.partial);
    assert_eq!(region(unsafe { ds_search_result_result(out, 0) }), region(direct));
    let quick = |search: *const ds_search_result, rank: usize| {
        let mut q = true;
        assert_eq!(unsafe { ds_search_result_quick(search, rank, &mut q) }, DS_OK, "{}", last_error());
        q
    };
    assert!(!quick(out, 0), "a shortlist of one is localized in full");
    unsafe { ds_search_result_destroy(out) };
    // A shortlist of 3 of the 4 shapes: localized quickly, the best two again in full, first.
    let all: Vec<*const ds_localizer> = lib.localizers.iter().map(|&l| l as *const _).collect();
    let s = unsafe { ds_search_screened(all.as_ptr(), all.len(), lib.partial, 3, usize::MAX, None, ptr::null_mut(), &mut out) };
    assert_eq!(s, DS_OK, "{}", last_error());
    let located: Vec<usize> = (0..all.len()).filter(|&r| !unsafe { ds_search_result_result(out, r) }.is_null()).collect();
    let kinds: Vec<bool> = located.iter().map(|&r| quick(out, r)).collect();
    assert_eq!(ranking(out)[0].0, RIGHT);
    assert_eq!(region(unsafe { ds_search_result_result(out, 0) }), region(direct));
    assert!(kinds.iter().filter(|&&q| !q).count() <= 2 && kinds.windows(2).all(|w| w[0] <= w[1]), "{kinds:?}");
    let mut q = false;
    assert_eq!(unsafe { ds_search_result_quick(out, all.len(), &mut q) }, DS_INVALID_ARGUMENT, "a rank past the end");
    // The search's confidence: in [0, 1] for a located shape, the best's at least any other's
    // full one behind it, 0 for a shape screened out; a rank past the end is an error.
    let confidence = |rank: usize| {
        let mut c = f64::NAN;
        assert_eq!(unsafe { ds_search_result_confidence(out, rank, &mut c) }, DS_OK, "{}", last_error());
        c
    };
    for r in 0..all.len() {
        let c = confidence(r);
        if located.contains(&r) {
            assert!((0.0..=1.0).contains(&c), "rank {r}: {c}");
        } else {
            assert_eq!(c, 0.0, "rank {r} not located");
        }
    }
    let mut c = 0.0;
    assert_eq!(unsafe { ds_search_result_confidence(out, all.len(), &mut c) }, DS_INVALID_ARGUMENT, "a rank past the end");
    assert_eq!(unsafe { ds_search_result_confidence(ptr::null(), 0, &mut c) }, DS_INVALID_ARGUMENT, "a NULL search");
    assert_eq!(unsafe { ds_search_result_confidence(out, 0, ptr::null_mut()) }, DS_INVALID_ARGUMENT, "a NULL out");
    unsafe {
        ds_result_destroy(direct);
        ds_search_result_destroy(out);
    }
    let (s, plain) = search(shapes, usize::MAX, None);
    assert_eq!(s, DS_OK, "{}", last_error());
    let mut x = 0.0;
    assert_eq!(unsafe { ds_search_result_screen_score(plain, 0, &mut x) }, DS_OK);
    assert!(x.is_nan());
    unsafe { ds_search_result_destroy(plain) };
    let mut none = ptr::null_mut();
    let s = unsafe { ds_search_screened(pointers.as_ptr(), pointers.len(), lib.partial, 0, usize::MAX, None, ptr::null_mut(), &mut none) };
    assert_eq!(s, DS_INVALID_ARGUMENT);
    assert!(last_error().contains("shortlist"), "{}", last_error());
}

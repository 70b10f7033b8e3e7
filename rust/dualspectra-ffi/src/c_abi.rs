//! The C ABI of dualspectra (header: `cpp/include/dualspectra/dualspectra.h`).
//!
//! Conventions, the same at every entry point:
//! - Opaque handles (`ds_mesh`, `ds_result`) created by `*_create`/`ds_localize` and released by
//!   `*_destroy` (which accept NULL).
//! - Arrays are passed as a pointer plus an explicit element count; a pointer may be NULL only
//!   when its count is 0. Indices are 0-based `uint32_t`.
//! - Every fallible function returns a `ds_status`; on failure `ds_last_error_message()` (per
//!   thread) says why. Out-parameters are written only on success.
//! - No Rust panic crosses the boundary: every body runs under `std::panic::catch_unwind`, a
//!   panic becomes `DS_PANIC`. NULL pointers, misaligned pointers, wrong lengths and
//!   out-of-range indices are reported as `DS_INVALID_ARGUMENT` / `DS_INVALID_MESH`.
//!
//! This file is conversion only: every computation is a call into the `dualspectra` crate.

#![allow(non_camel_case_types)]

use crate::{metric_from_code, status_of, ShapeCache};
use dualspectra::{Error, Localization, Options, Progress, TriMesh};
use std::cell::RefCell;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

/// Status code returned by every fallible entry point (`DS_OK` = 0 on success).
pub type ds_status = i32;
/// Success.
pub const DS_OK: ds_status = 0;
/// A NULL/misaligned pointer, a wrong array length, an unknown enum value or an option out of range.
pub const DS_INVALID_ARGUMENT: ds_status = 1;
/// The mesh arrays do not describe a valid triangle mesh (index out of range, degenerate or
/// non-manifold face, isolated vertex, non-finite coordinate, ...).
pub const DS_INVALID_MESH: ds_status = 2;
/// A numerical method failed (eigensolver, factorization, optimiser).
pub const DS_NUMERICAL: ds_status = 3;
/// The progress callback returned 0.
pub const DS_CANCELLED: ds_status = 4;
/// An internal error (a bug): a Rust panic was caught at the boundary.
pub const DS_PANIC: ds_status = 5;
/// A file could not be read or parsed.
pub const DS_IO: ds_status = 6;

/// Which spectra `ds_localize` matches (`ds_options.mode`).
pub type ds_mode = u32;
/// k regular + k scale-invariant eigenvalues (the paper's method; the default).
pub const DS_MODE_DUAL: ds_mode = 0;
/// 2k regular (Laplace-Beltrami) eigenvalues only.
pub const DS_MODE_LBO: ds_mode = 1;
/// 2k scale-invariant eigenvalues only.
pub const DS_MODE_SI: ds_mode = 2;

/// How `ds_localize` chooses among its optimised starts (`ds_options.selection`).
pub type ds_selection = u32;
/// SHOT descriptors projected on the first eigenfunctions (the paper's rule).
pub const DS_SELECTION_DESCRIPTORS: ds_selection = 0;
/// The lowest final alignment cost.
pub const DS_SELECTION_COST: ds_selection = 1;
/// The lowest alignment cost of the candidate's extracted region as a step potential.
pub const DS_SELECTION_REGION: ds_selection = 2;
/// The lowest descriptor score among the candidates whose region cost is at most 3x the
/// lowest (the default).
pub const DS_SELECTION_GATED: ds_selection = 3;

/// The starting potentials around each farthest-point centre (`ds_options.start_shape`).
pub type ds_start_shape = u32;
/// A well on the ball with the partial's area, one on everything but a ball with the rest of
/// the area, and a wide Gaussian bump: 3 starts per centre (the default).
pub const DS_STARTS_BALLS_AND_WIDE_BUMPS: ds_start_shape = 0;
/// The two balls, and the wide Gaussian well and bump: 4 starts per centre.
pub const DS_STARTS_BALLS_AND_WIDE_GAUSSIANS: ds_start_shape = 1;
/// The reference's Gaussians, two widths, both signs: 4 starts per centre.
pub const DS_STARTS_GAUSSIAN: ds_start_shape = 2;
/// The two balls only: 2 starts per centre.
pub const DS_STARTS_AREA_BALL: ds_start_shape = 3;

/// Which metric a spectrum is computed in.
pub type ds_metric = u32;
/// The surface's own metric (Laplace-Beltrami spectrum).
pub const DS_METRIC_REGULAR: ds_metric = 0;
/// The scale-invariant metric `s g` with `s = (eps + K^2)^(alpha/2)`.
pub const DS_METRIC_SCALE_INVARIANT: ds_metric = 1;

/// A validated triangle mesh (immutable; may be shared between threads for reading).
pub struct ds_mesh {
    pub(crate) shape: ShapeCache,
}

/// The result of `ds_localize` (immutable).
pub struct ds_result {
    pub(crate) loc: Localization,
    /// `loc.warnings` as C strings, owned by the result.
    pub(crate) warnings: Vec<CString>,
}

/// Parameters of `ds_localize`. Start from `ds_options_default()` and change fields.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct ds_options {
    /// One of `DS_MODE_DUAL`, `DS_MODE_LBO`, `DS_MODE_SI`.
    pub mode: ds_mode,
    /// Eigenvalues per spectrum (`dual` uses k + k, `lbo`/`si` use 2k); at least 1.
    pub k: usize,
    /// Exponent of the scale-invariant factor (paper default 0.33).
    pub alpha: f64,
    /// Seed of every random choice: results are deterministic for a given seed.
    pub seed: u64,
    /// Vertices of the decimated full shape the potential is optimised on (0: no decimation).
    pub resolution: usize,
    /// Farthest-point centres of the starts (each gives 3 starts; the plane cuts come on top).
    pub centers: usize,
    /// Trust-region iterations per start (at least 1).
    pub max_iterations: usize,
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// One of `DS_SELECTION_DESCRIPTORS`, `DS_SELECTION_COST`, `DS_SELECTION_REGION`, `DS_SELECTION_GATED`.
    pub selection: ds_selection,
    /// One of `DS_STARTS_BALLS_AND_WIDE_BUMPS`, `DS_STARTS_BALLS_AND_WIDE_GAUSSIANS`,
    /// `DS_STARTS_GAUSSIAN`, `DS_STARTS_AREA_BALL`.
    pub start_shape: ds_start_shape,
    /// Further starts from the full shape's first `spectral_cuts` eigenfunctions, two each (the
    /// region on either side of a level set, with the partial's area); 0: none (the default).
    pub spectral_cuts: usize,
    /// Further starts, one per direction: the side of a plane with the partial's area, normal to
    /// the first `plane_cuts` of 26 directions (6, the default: both ways along the full shape's
    /// principal axes; 14: and the diagonals; 26: and the face diagonals); at most 26.
    pub plane_cuts: usize,
}

/// Wall-clock seconds per stage of `ds_localize`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct ds_timings {
    pub preprocessing: f64,
    pub starts: f64,
    pub optimisation: f64,
    pub selection: f64,
    pub region: f64,
    pub total: f64,
}

/// Progress callback: `fraction` in [0, 1] of the whole computation, `stage` a short
/// NUL-terminated name valid only during the call, `user` the pointer given to `ds_localize`.
/// Return non-zero to continue, 0 to cancel (`ds_localize` then returns `DS_CANCELLED`).
/// Calls are serialized (never concurrent) but may come from a worker thread. The callback
/// must not unwind (no C++ exception, no longjmp) out of itself.
pub type ds_progress_fn =
    Option<unsafe extern "C" fn(fraction: f64, stage: *const c_char, user: *mut c_void) -> c_int>;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    let c = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_owned()
    }
}

/// Run an entry point body: clear the thread's error, catch panics, map errors to codes.
fn guard(body: impl FnOnce() -> Result<(), Error>) -> ds_status {
    set_last_error("");
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => DS_OK,
        Ok(Err(e)) => {
            set_last_error(&e.to_string());
            status_of(&e)
        }
        Err(payload) => {
            set_last_error(&format!("internal error (panic caught at the C boundary): {}", panic_message(&*payload)));
            DS_PANIC
        }
    }
}

/// Like [`guard`] for infallible getters: a panic yields `fallback`.
fn guard_value<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(v) => v,
        Err(payload) => {
            set_last_error(&format!("internal error (panic caught at the C boundary): {}", panic_message(&*payload)));
            fallback
        }
    }
}

fn invalid(msg: impl Into<String>) -> Error {
    Error::InvalidArgument(msg.into())
}

/// Borrow `len` elements at `ptr`, checking NULL, alignment and size overflow.
///
/// # Safety
/// If the checks pass, `ptr` must point to `len` initialised `T`s valid for the returned lifetime.
unsafe fn slice_in<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], Error> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL but its length is {len}")));
    }
    if (ptr as usize) % std::mem::align_of::<T>() != 0 {
        return Err(invalid(format!("{what} is not aligned to {} bytes", std::mem::align_of::<T>())));
    }
    if len > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(invalid(format!("{what}: length {len} is too large")));
    }
    // SAFETY: non-null, aligned, size fits isize; validity of the memory is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// Mutable version of [`slice_in`].
///
/// # Safety
/// As [`slice_in`], and the memory must not be aliased during the call.
unsafe fn slice_out<'a, T>(ptr: *mut T, len: usize, what: &str) -> Result<&'a mut [T], Error> {
    // SAFETY: same checks; exclusivity is the caller's contract.
    unsafe { slice_in(ptr as *const T, len, what)? };
    if len == 0 {
        return Ok(&mut []);
    }
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, len) })
}

/// Dereference a handle, checking NULL and alignment.
///
/// # Safety
/// A non-NULL `ptr` must come from this library and not have been destroyed.
unsafe fn handle<'a, T>(ptr: *const T, what: &str) -> Result<&'a T, Error> {
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL")));
    }
    if (ptr as usize) % std::mem::align_of::<T>() != 0 {
        return Err(invalid(format!("{what} is not a valid handle (misaligned)")));
    }
    // SAFETY: caller's contract.
    Ok(unsafe { &*ptr })
}

/// Write `value` to an out-pointer, checking NULL and alignment.
///
/// # Safety
/// A non-NULL `ptr` must be valid for writes of one `T`.
unsafe fn write_out<T>(ptr: *mut T, value: T, what: &str) -> Result<(), Error> {
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL")));
    }
    if (ptr as usize) % std::mem::align_of::<T>() != 0 {
        return Err(invalid(format!("{what} is not aligned to {} bytes", std::mem::align_of::<T>())));
    }
    // SAFETY: caller's contract; `write` does not drop the (possibly uninitialised) old value.
    unsafe { ptr.write(value) };
    Ok(())
}

fn checked_mul3(n: usize, what: &str) -> Result<usize, Error> {
    n.checked_mul(3).ok_or_else(|| invalid(format!("{what} = {n} overflows")))
}

// ---------------------------------------------------------------------------------------------
// Version and errors

/// The library version, e.g. `"0.1.0"` (static string, never NULL).
#[no_mangle]
pub extern "C" fn ds_version() -> *const c_char {
    static VERSION: &CStr = match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
        Ok(s) => s,
        Err(_) => c"unknown",
    };
    VERSION.as_ptr()
}

/// The library version as `major * 10000 + minor * 100 + patch`.
#[no_mangle]
pub extern "C" fn ds_version_number() -> u32 {
    guard_value(0, crate::version_number)
}

/// The message of the last failed call on this thread (`""` if the last call succeeded).
/// Never NULL; valid until the next dualspectra call on this thread.
#[no_mangle]
pub extern "C" fn ds_last_error_message() -> *const c_char {
    guard_value(c"".as_ptr(), || LAST_ERROR.with(|e| e.borrow().as_ptr()))
}

/// A constant name for a status code, e.g. `"DS_INVALID_MESH"` (never NULL).
#[no_mangle]
pub extern "C" fn ds_status_name(status: ds_status) -> *const c_char {
    match status {
        DS_OK => c"DS_OK",
        DS_INVALID_ARGUMENT => c"DS_INVALID_ARGUMENT",
        DS_INVALID_MESH => c"DS_INVALID_MESH",
        DS_NUMERICAL => c"DS_NUMERICAL",
        DS_CANCELLED => c"DS_CANCELLED",
        DS_PANIC => c"DS_PANIC",
        DS_IO => c"DS_IO",
        _ => c"DS_UNKNOWN_STATUS",
    }
    .as_ptr()
}

// ---------------------------------------------------------------------------------------------
// Meshes

/// Create a mesh from `n_vertices` positions `xyz[3*i .. 3*i+3]` and `n_faces` triangles
/// `tri[3*f .. 3*f+3]` (0-based vertex indices). The arrays are copied. On success `*out`
/// receives a handle to release with `ds_mesh_destroy`.
///
/// Errors: `DS_INVALID_ARGUMENT` (NULL/misaligned pointers, overflowing counts),
/// `DS_INVALID_MESH` (index out of range, repeated/degenerate face, non-manifold edge or
/// vertex, vertex in no face, non-finite coordinate, no faces).
///
/// # Safety
/// `xyz` must point to `3 * n_vertices` doubles and `tri` to `3 * n_faces` uint32 (or be NULL
/// with a zero count); `out` must be valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_create(
    xyz: *const f64,
    n_vertices: usize,
    tri: *const u32,
    n_faces: usize,
    out: *mut *mut ds_mesh,
) -> ds_status {
    guard(|| {
        if out.is_null() {
            return Err(invalid("out is NULL"));
        }
        let v = unsafe { slice_in(xyz, checked_mul3(n_vertices, "n_vertices")?, "xyz")? };
        let f = unsafe { slice_in(tri, checked_mul3(n_faces, "n_faces")?, "tri")? };
        let mesh = TriMesh::from_flat(v, f)?;
        let h = Box::into_raw(Box::new(ds_mesh { shape: ShapeCache::new(mesh) }));
        unsafe { write_out(out, h, "out") }
    })
}

/// As `ds_mesh_create`, but vertices referenced by no face are dropped instead of rejected
/// (e.g. unreferenced or deleted vertices of an editor's mesh). If `kept` is not NULL it
/// receives, for each vertex of the new mesh, its index in the input
/// (`kept[new] = old`); it must have room for `kept_capacity >= n_vertices` entries.
/// `*n_kept` (if not NULL) receives the number of vertices of the new mesh.
///
/// # Safety
/// As `ds_mesh_create`; `kept` valid for `kept_capacity` writes, `n_kept` for one.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_create_dropping_isolated(
    xyz: *const f64,
    n_vertices: usize,
    tri: *const u32,
    n_faces: usize,
    kept: *mut u32,
    kept_capacity: usize,
    n_kept: *mut usize,
    out: *mut *mut ds_mesh,
) -> ds_status {
    guard(|| {
        if out.is_null() {
            return Err(invalid("out is NULL"));
        }
        if !kept.is_null() && kept_capacity < n_vertices {
            return Err(invalid(format!("kept_capacity {kept_capacity} < n_vertices {n_vertices}")));
        }
        let v = unsafe { slice_in(xyz, checked_mul3(n_vertices, "n_vertices")?, "xyz")? };
        let f = unsafe { slice_in(tri, checked_mul3(n_faces, "n_faces")?, "tri")? };
        let verts = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let faces = f.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let (mesh, kept_idx) = TriMesh::new_dropping_isolated(verts, faces)?;
        if !kept.is_null() {
            let dst = unsafe { slice_out(kept, kept_idx.len(), "kept")? };
            dst.copy_from_slice(&kept_idx);
        }
        if !n_kept.is_null() {
            unsafe { write_out(n_kept, kept_idx.len(), "n_kept")? };
        }
        let h = Box::into_raw(Box::new(ds_mesh { shape: ShapeCache::new(mesh) }));
        unsafe { write_out(out, h, "out") }
    })
}

/// Release a mesh (NULL is ignored).
///
/// # Safety
/// `mesh` must be NULL or a handle from `ds_mesh_create*` not yet destroyed.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_destroy(mesh: *mut ds_mesh) {
    if !mesh.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(mesh) })));
    }
}

/// Number of vertices (0 for NULL).
///
/// # Safety
/// `mesh` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_n_vertices(mesh: *const ds_mesh) -> usize {
    guard_value(0, || unsafe { handle(mesh, "mesh") }.map(|m| m.shape.mesh().n_vertices()).unwrap_or(0))
}

/// Number of faces (0 for NULL).
///
/// # Safety
/// `mesh` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_n_faces(mesh: *const ds_mesh) -> usize {
    guard_value(0, || unsafe { handle(mesh, "mesh") }.map(|m| m.shape.mesh().n_faces()).unwrap_or(0))
}

// ---------------------------------------------------------------------------------------------
// Per-mesh quantities

/// Pointwise Gaussian curvature per vertex (angle defect over barycentric area; with
/// `smoothed != 0`, then averaged over each vertex's one-ring, as the scale-invariant metric
/// uses). `out` must hold `out_len == ds_mesh_n_vertices(mesh)` doubles.
///
/// # Safety
/// `mesh` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_gaussian_curvature(mesh: *const ds_mesh, smoothed: c_int, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| {
        let m = unsafe { handle(mesh, "mesh")? };
        let n = m.shape.mesh().n_vertices();
        if out_len != n {
            return Err(invalid(format!("out_len is {out_len}, the mesh has {n} vertices")));
        }
        let dst = unsafe { slice_out(out, out_len, "out")? };
        let k = crate::gaussian_curvature(&m.shape, smoothed != 0);
        dst.copy_from_slice(&k);
        Ok(())
    })
}

/// The `k` smallest eigenvalues (ascending) of the Dirichlet Laplacian of `mesh` in `metric`
/// (`DS_METRIC_REGULAR` or `DS_METRIC_SCALE_INVARIANT` with exponent `alpha`; `alpha` is
/// ignored for the regular metric). On a closed mesh there is no boundary and the first
/// eigenvalue is 0. `out` must hold `out_len == k` doubles.
///
/// # Safety
/// `mesh` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_spectrum(
    mesh: *const ds_mesh,
    k: usize,
    metric: ds_metric,
    alpha: f64,
    out: *mut f64,
    out_len: usize,
) -> ds_status {
    guard(|| {
        let m = unsafe { handle(mesh, "mesh")? };
        let metric = metric_from_code(metric)?;
        if out_len != k {
            return Err(invalid(format!("out_len is {out_len}, expected k = {k}")));
        }
        let dst = unsafe { slice_out(out, out_len, "out")? };
        let values = crate::spectrum(&m.shape, k, metric, alpha)?;
        if values.len() != k {
            return Err(Error::Numerical(format!("eigensolver returned {} eigenvalues, expected {k}", values.len())));
        }
        dst.copy_from_slice(&values);
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Localization

/// The paper's default parameters.
#[no_mangle]
pub extern "C" fn ds_options_default() -> ds_options {
    // `Options::default()` cannot panic; the fallback only satisfies the panic guard.
    guard_value(
        ds_options {
            mode: DS_MODE_DUAL,
            k: 20,
            alpha: 0.33,
            seed: 0,
            resolution: 0,
            centers: 1,
            max_iterations: 1,
            threads: 0,
            selection: DS_SELECTION_DESCRIPTORS,
            start_shape: DS_STARTS_BALLS_AND_WIDE_BUMPS,
            spectral_cuts: 0,
            plane_cuts: 0,
        },
        || crate::options_to_c(&Options::default()),
    )
}

struct CallbackData {
    f: unsafe extern "C" fn(f64, *const c_char, *mut c_void) -> c_int,
    user: *mut c_void,
}
// SAFETY: the C caller hands us `user` for use during `ds_localize`, which does not return
// before the computation ends; the Mutex below serializes the calls.
unsafe impl Send for CallbackData {}

/// Find the region of `full` that `partial` corresponds to. `options` may be NULL (defaults);
/// `progress` may be NULL. On success `*out` receives a result to release with
/// `ds_result_destroy`.
///
/// Errors: `DS_INVALID_ARGUMENT` (NULL meshes/out, unknown mode, k = 0, non-finite alpha),
/// `DS_NUMERICAL`, `DS_CANCELLED` (the callback returned 0).
///
/// # Safety
/// `full`, `partial` live handles; `options` NULL or valid; `out` valid for one write;
/// `progress` NULL or a function callable as described for `ds_progress_fn`.
#[no_mangle]
pub unsafe extern "C" fn ds_localize(
    full: *const ds_mesh,
    partial: *const ds_mesh,
    options: *const ds_options,
    progress: ds_progress_fn,
    user: *mut c_void,
    out: *mut *mut ds_result,
) -> ds_status {
    guard(|| {
        if out.is_null() {
            return Err(invalid("out is NULL"));
        }
        let full = unsafe { handle(full, "full")? };
        let partial = unsafe { handle(partial, "partial")? };
        let opts = if options.is_null() { Options::default() } else { crate::options_from_c(unsafe { handle(options, "options")? })? };
        let prog = match progress {
            None => Progress::none(),
            Some(f) => {
                let data = Mutex::new(CallbackData { f, user });
                Progress::new(move |fraction, stage| {
                    let stage = CString::new(stage.replace('\0', " ")).unwrap_or_default();
                    let guard = data.lock().unwrap_or_else(|p| p.into_inner());
                    // SAFETY: the caller promised `f` is callable with its own `user`.
                    unsafe { (guard.f)(fraction, stage.as_ptr(), guard.user) != 0 }
                })
            }
        };
        let loc = crate::localize(&full.shape, &partial.shape, &opts, &prog)?;
        let warnings = loc.warnings.iter().map(|w| CString::new(w.replace('\0', " ")).unwrap_or_default()).collect();
        let h = Box::into_raw(Box::new(ds_result { loc, warnings }));
        unsafe { write_out(out, h, "out") }
    })
}

/// Release a result (NULL is ignored).
///
/// # Safety
/// `result` must be NULL or a handle from `ds_localize` not yet destroyed.
#[no_mangle]
pub unsafe extern "C" fn ds_result_destroy(result: *mut ds_result) {
    if !result.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(result) })));
    }
}

/// Number of vertices of the full mesh, the length of the per-vertex arrays (0 for NULL).
///
/// # Safety
/// `result` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn ds_result_n_vertices(result: *const ds_result) -> usize {
    guard_value(0, || unsafe { handle(result, "result") }.map(|r| r.loc.region.len()).unwrap_or(0))
}

fn copy_f64(src: &[f64], out: *mut f64, out_len: usize, what: &str) -> Result<(), Error> {
    if out_len != src.len() {
        return Err(invalid(format!("out_len is {out_len}, {what} has {} values", src.len())));
    }
    let dst = unsafe { slice_out(out, out_len, "out")? };
    dst.copy_from_slice(src);
    Ok(())
}

/// The region: `out[i] = 1` if vertex `i` of the full mesh is in the matched region, else 0.
/// `out_len` must equal `ds_result_n_vertices(result)`.
///
/// # Safety
/// `result` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_region(result: *const ds_result, out: *mut u8, out_len: usize) -> ds_status {
    guard(|| {
        let r = unsafe { handle(result, "result")? };
        let n = r.loc.region.len();
        if out_len != n {
            return Err(invalid(format!("out_len is {out_len}, the region has {n} vertices")));
        }
        let dst = unsafe { slice_out(out, out_len, "out")? };
        for (d, &b) in dst.iter_mut().zip(&r.loc.region) {
            *d = b as u8;
        }
        Ok(())
    })
}

/// Soft membership score in [0, 1] per full-mesh vertex (`out_len == ds_result_n_vertices`).
///
/// # Safety
/// `result` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_score(result: *const ds_result, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| copy_f64(&unsafe { handle(result, "result")? }.loc.score, out, out_len, "the score"))
}

/// Optimised potential `v >= 0` per full-mesh vertex (`out_len == ds_result_n_vertices`).
///
/// # Safety
/// `result` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_potential(result: *const ds_result, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| copy_f64(&unsafe { handle(result, "result")? }.loc.potential, out, out_len, "the potential"))
}

/// Number of Hamiltonian eigenvalues at the optimum in `metric` (0 for NULL or an unknown
/// metric; 0 for the metric the mode does not use).
///
/// # Safety
/// `result` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn ds_result_n_eigenvalues(result: *const ds_result, metric: ds_metric) -> usize {
    guard_value(0, || match (unsafe { handle(result, "result") }, metric_from_code(metric)) {
        (Ok(r), Ok(m)) => crate::eigenvalues(&r.loc, m, false).len(),
        _ => 0,
    })
}

/// Hamiltonian eigenvalues at the optimum in `metric` (`out_len == ds_result_n_eigenvalues`).
///
/// # Safety
/// `result` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_eigenvalues(result: *const ds_result, metric: ds_metric, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| {
        let r = unsafe { handle(result, "result")? };
        copy_f64(crate::eigenvalues(&r.loc, metric_from_code(metric)?, false), out, out_len, "the spectrum")
    })
}

/// The partial shape's Dirichlet eigenvalues (the target) in `metric`; same length as
/// `ds_result_n_eigenvalues(result, metric)`.
///
/// # Safety
/// `result` a live handle; `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_target_eigenvalues(result: *const ds_result, metric: ds_metric, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| {
        let r = unsafe { handle(result, "result")? };
        copy_f64(crate::eigenvalues(&r.loc, metric_from_code(metric)?, true), out, out_len, "the target spectrum")
    })
}

/// Final alignment cost of the selected start.
///
/// # Safety
/// `result` a live handle; `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_cost(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.cost, "out") })
}

/// Total wall-clock seconds of `ds_localize`.
///
/// # Safety
/// `result` a live handle; `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_seconds(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.timings.total, "out") })
}

/// Wall-clock seconds per stage.
///
/// # Safety
/// `result` a live handle; `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_timings(result: *const ds_result, out: *mut ds_timings) -> ds_status {
    guard(|| {
        let t = &unsafe { handle(result, "result")? }.loc.timings;
        let c = ds_timings {
            preprocessing: t.preprocessing,
            starts: t.starts,
            optimisation: t.optimisation,
            selection: t.selection,
            region: t.region,
            total: t.total,
        };
        unsafe { write_out(out, c, "out") }
    })
}

/// Index of the selected start and the number of starts run (either pointer may be NULL).
///
/// # Safety
/// `result` a live handle; non-NULL pointers valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_starts(result: *const ds_result, selected: *mut usize, n_starts: *mut usize) -> ds_status {
    guard(|| {
        let r = unsafe { handle(result, "result")? };
        if !selected.is_null() {
            unsafe { write_out(selected, r.loc.selected_start, "selected")? };
        }
        if !n_starts.is_null() {
            unsafe { write_out(n_starts, r.loc.n_starts, "n_starts")? };
        }
        Ok(())
    })
}

/// Number of warnings about repairs made to the input (e.g. a disconnected partial reduced to
/// its largest component); 0 for NULL.
///
/// # Safety
/// `result` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn ds_result_n_warnings(result: *const ds_result) -> usize {
    guard_value(0, || unsafe { handle(result, "result") }.map(|r| r.warnings.len()).unwrap_or(0))
}

/// Warning `index` (< `ds_result_n_warnings`), NUL-terminated and owned by the result (valid
/// until `ds_result_destroy`); NULL for a NULL result or an index out of range.
///
/// # Safety
/// `result` must be NULL or a live handle.
#[no_mangle]
pub unsafe extern "C" fn ds_result_warning(result: *const ds_result, index: usize) -> *const c_char {
    guard_value(std::ptr::null(), || match unsafe { handle(result, "result") } {
        Ok(r) => r.warnings.get(index).map_or(std::ptr::null(), |w| w.as_ptr()),
        Err(_) => std::ptr::null(),
    })
}

//! The C ABI of dualspectra (header: `cpp/include/dualspectra/dualspectra.h`).
//!
//! Conventions, the same at every entry point:
//! - Opaque handles (`ds_mesh`, `ds_options`, `ds_localizer`, `ds_result`, `ds_search_result`)
//!   created by `*_create`/`ds_localize`/`ds_localizer_load`/`ds_search` and released by
//!   `*_destroy`. A *handle argument* may be any
//!   pointer: it is looked up in a registry of live handles before it is read (below); NULL, a
//!   destroyed or foreign pointer, or a handle of another type is `DS_INVALID_ARGUMENT`
//!   (getters: 0 or NULL, with the message; `*_destroy`: nothing happens). A handle must not be
//!   destroyed while another thread is in a call on it.
//! - Arrays are passed as a pointer plus an explicit element count; a pointer may be NULL only
//!   when its count is 0. Indices are 0-based `uint32_t`. Strings are NUL-terminated UTF-8.
//! - Every fallible function returns a `ds_status`; on failure `ds_last_error_message()` (per
//!   thread) says why. Out-parameters are written only on success.
//! - No Rust panic crosses the boundary: every body runs under `std::panic::catch_unwind`, a
//!   panic becomes `DS_PANIC`. NULL pointers, misaligned pointers, wrong lengths and
//!   out-of-range indices are reported as `DS_INVALID_ARGUMENT` / `DS_INVALID_MESH`; sizes
//!   that cannot be allocated as `DS_OUT_OF_MEMORY` (below).
//! - Options are a key/value handle whose names, ranges and docs are the core's table
//!   (`ds_options_schema_json()`), so a new core option needs no change here.
//! - A mesh made from a host's arrays (`ds_mesh_create_from_host`) goes through the core's
//!   intake (degenerate faces and loose vertices left out, non-manifold edges and vertices
//!   split): every per-vertex array in or out is in the host's numbering.
//!
//! This file is conversion only: every computation is a call into the `dualspectra` crate.
//!
//! ## Handles: a registry of live ones
//!
//! Every handle made here is recorded (address -> type) in one process-wide registry
//! (`LIVE`); every entry point looks a handle argument up there before dereferencing it, and
//! `*_destroy` takes it out before releasing it. So a destroyed handle (use after destroy,
//! double destroy), a pointer this library did not make, or a handle of another type (a
//! `ds_mesh*` given as a `ds_result*`) is `DS_INVALID_ARGUMENT` (for `*_destroy`: nothing
//! happens) with a message naming it, and is never read. A check word in each handle (magic +
//! generation) was the other design; it would have to read the pointed-to memory to check it,
//! which for a freed or foreign pointer is itself the undefined behaviour (a fault, or whatever
//! was allocated there since); the registry needs only the address. The lock is held for the
//! lookup only (a tree lookup, cheap next to any call's work), so one handle used from several
//! threads at once keeps working. Limits: the address of a destroyed handle may be reused by a
//! new handle of the same type, and the stale pointer then is that new handle
//! (indistinguishable; of another type it is refused); destroying a handle while another thread
//! is inside a call on it is still the caller's bug.
//!
//! A `ds_search_result` owns the `ds_result` of each shape it ranks; they are registered as
//! *borrowed* results while it lives: every `ds_result_*` getter takes them, `ds_result_destroy`
//! refuses them (nothing happens, the message says who owns them), and
//! `ds_search_result_destroy` takes them out of the registry with their owner.
//!
//! ## Memory
//!
//! Rust aborts the process when an allocation fails, and `catch_unwind` cannot catch that. So
//! before the core reads host arrays or allocates anything in proportion to host-given sizes,
//! the sizes are checked for overflow and a lower bound of what the call will hold is reserved
//! and released at once (`reserve`): a mesh's own arrays for `ds_mesh_create*`, eigenvectors
//! and operators (`n (min(k, n) + c)` doubles) for `ds_spectrum`, `ds_localize`,
//! `ds_localizer_create`/`_locate` and `ds_search` (per shape), the file's bytes for
//! `ds_localizer_load`. A reservation that fails is `DS_OUT_OF_MEMORY` with the size in the
//! message. Best effort: it turns impossible requests (a mesh of 2^40 vertices) into an
//! error, but cannot guard every allocation in the core, and an overcommitting kernel may grant
//! a reservation the computation later cannot fill.

#![allow(non_camel_case_types)]

pub(crate) mod read;
pub use read::{ds_mesh_faces, ds_mesh_read, ds_mesh_vertices};

use crate::{metric_from_code, status_of, HostLocalizer, HostMesh};
use dualspectra::{Error, Localization, Options, Progress};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError};

/// Status code returned by every fallible entry point (`DS_OK` = 0 on success).
pub type ds_status = i32;
/// Success.
pub const DS_OK: ds_status = 0;
/// A NULL/misaligned pointer, a pointer that is not a live handle of the expected type
/// (destroyed, not from this library, or a handle of another type), a wrong array length, an
/// unknown metric, an unknown option or a value out of its range (the message names the
/// option and its range).
pub const DS_INVALID_ARGUMENT: ds_status = 1;
/// The mesh arrays do not describe a valid triangle mesh (index out of range, non-finite
/// coordinate, no usable face; for `ds_mesh_create` also a degenerate face, a vertex in no face,
/// or a non-manifold edge or vertex, which `ds_mesh_create_from_host` repairs).
pub const DS_INVALID_MESH: ds_status = 2;
/// A numerical method failed (eigensolver, factorization, optimiser).
pub const DS_NUMERICAL: ds_status = 3;
/// The progress callback returned 0.
pub const DS_CANCELLED: ds_status = 4;
/// An internal error (a bug): a Rust panic was caught at the boundary.
pub const DS_PANIC: ds_status = 5;
/// A file could not be read or parsed.
pub const DS_IO: ds_status = 6;
/// The memory the call needs at least could not be reserved; the message names the size.
/// Checked up front from the sizes given (best effort: a lower bound of what the call holds,
/// not every allocation of the core), before anything is read or computed.
pub const DS_OUT_OF_MEMORY: ds_status = 7;
/// A file given to `ds_localizer_load` is not a usable prepared shape: foreign (not one),
/// stale (written by another format version: prepare the shape again), truncated or
/// corrupted. The message names the file and which of these it is.
pub const DS_INVALID_PREPARED_SHAPE: ds_status = 8;

/// Which metric a spectrum is computed in.
pub type ds_metric = u32;
/// The surface's own metric (Laplace-Beltrami spectrum).
pub const DS_METRIC_REGULAR: ds_metric = 0;
/// The scale-invariant metric `s g` with `s = (eps + K^2)^(alpha/2)`.
pub const DS_METRIC_SCALE_INVARIANT: ds_metric = 1;

/// A validated triangle mesh (immutable; may be shared between threads for reading). Made by
/// `ds_mesh_create` (strict) or `ds_mesh_create_from_host` (through the core's intake, with
/// the map back to the host's vertex numbering).
pub struct ds_mesh {
    pub(crate) mesh: HostMesh,
    /// What the intake left out, as a sentence (`None`: nothing).
    pub(crate) warning: Option<CString>,
}

/// Options of the localizer, by name (`ds_options_set`); `ds_options_schema_json()` lists the
/// names, types, ranges, defaults and docs.
pub struct ds_options {
    pub(crate) options: Options,
    /// `options` as a JSON object (`ds_options_json`), kept up to date by every setter.
    pub(crate) json: CString,
}

/// A full mesh prepared for locating partials on it (immutable; `ds_localizer_locate` may be
/// called from several threads at once on one localizer).
pub struct ds_localizer {
    pub(crate) inner: HostLocalizer,
    pub(crate) warnings: Vec<CString>,
    pub(crate) options_json: CString,
}

/// The result of `ds_localize` or `ds_localizer_locate` (immutable), or one shape's result in
/// a `ds_search_result` (borrowed from it).
pub struct ds_result {
    pub(crate) loc: Localization,
    /// `loc.warnings` as C strings, owned by the result.
    pub(crate) warnings: Vec<CString>,
}

/// The ranking of `ds_search` (immutable): the best matches, best first.
pub struct ds_search_result {
    pub(crate) matches: Vec<SearchMatch>,
}

/// One full shape's answer in a `ds_search_result`.
pub(crate) struct SearchMatch {
    /// Index of the localizer in the array given to `ds_search`.
    index: usize,
    /// The similarity score (lower is more similar; infinite when the partial could not be
    /// located on the shape).
    score: f64,
    /// The localization, a borrowed handle while the search result lives (`None`: not located).
    result: Option<Box<ds_result>>,
    /// Why the partial could not be located on the shape.
    error: Option<CString>,
    /// The screen's score (NaN when the search was not screened).
    screen_score: f64,
    /// Whether the localization is the screened search's quick one rather than a full one.
    quick: bool,
    /// The search's confidence in this shape (0 when not located).
    confidence: f64,
}

/// Wall-clock seconds per stage.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct ds_timings {
    /// Preparing the full mesh (0 for a result of `ds_localizer_locate`: see
    /// `ds_localizer_preparation_seconds`).
    pub preparation: f64,
    /// The partial's spectra and descriptors.
    pub preprocessing: f64,
    pub starts: f64,
    pub optimisation: f64,
    /// Each candidate's region on the full mesh.
    pub region: f64,
    /// Scoring the candidates and choosing one.
    pub selection: f64,
    pub total: f64,
}

/// Progress callback: `fraction` in [0, 1] of the whole computation, `stage` a short
/// NUL-terminated name valid only during the call, `user` the pointer given with it.
/// Return non-zero to continue, 0 to cancel (the call then returns `DS_CANCELLED`).
/// The calls of one computation are serialized (never concurrent) but may come from a worker
/// thread. The callback must not unwind (no C++ exception, no longjmp) out of itself.
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

/// Why an entry point failed: an error of the core or of the checks here, or memory that
/// could not be reserved ([`reserve`]; the core's [`Error`] has no such case).
enum Failure {
    Core(Error),
    OutOfMemory(String),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Core(e)
    }
}

impl Failure {
    fn status(&self) -> ds_status {
        match self {
            Failure::Core(e) => status_of(e),
            Failure::OutOfMemory(_) => DS_OUT_OF_MEMORY,
        }
    }

    fn message(&self) -> String {
        match self {
            Failure::Core(e) => e.to_string(),
            Failure::OutOfMemory(m) => format!("out of memory: {m}"),
        }
    }
}

/// Run an entry point body: clear the thread's error, catch panics, map errors to codes.
fn guard(body: impl FnOnce() -> Result<(), Failure>) -> ds_status {
    set_last_error("");
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => DS_OK,
        Ok(Err(e)) => {
            set_last_error(&e.message());
            e.status()
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

fn invalid(msg: impl Into<String>) -> Failure {
    Failure::Core(Error::InvalidArgument(msg.into()))
}

/// Check an array argument of `len` elements without reading it: NULL (with `len > 0`),
/// alignment, and a size in bytes that fits `isize`.
fn check_array<T>(ptr: *const T, len: usize, what: &str) -> Result<(), Failure> {
    if len == 0 {
        return Ok(());
    }
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL but its length is {len}")));
    }
    if !(ptr as usize).is_multiple_of(std::mem::align_of::<T>()) {
        return Err(invalid(format!("{what} is not aligned to {} bytes", std::mem::align_of::<T>())));
    }
    if len > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(invalid(format!("{what}: length {len} is too large")));
    }
    Ok(())
}

/// Borrow `len` elements at `ptr`, checking NULL, alignment and size overflow ([`check_array`]).
///
/// # Safety
/// If the checks pass, `ptr` must point to `len` initialised `T`s valid for the returned lifetime.
unsafe fn slice_in<'a, T>(ptr: *const T, len: usize, what: &str) -> Result<&'a [T], Failure> {
    check_array(ptr, len, what)?;
    if len == 0 {
        return Ok(&[]);
    }
    // SAFETY: non-null, aligned, size fits isize; validity of the memory is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// Mutable version of [`slice_in`].
///
/// # Safety
/// As [`slice_in`], and the memory must not be aliased during the call.
unsafe fn slice_out<'a, T>(ptr: *mut T, len: usize, what: &str) -> Result<&'a mut [T], Failure> {
    // SAFETY: same checks; exclusivity is the caller's contract.
    unsafe { slice_in(ptr as *const T, len, what)? };
    if len == 0 {
        return Ok(&mut []);
    }
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, len) })
}

/// Write `value` to an out-pointer, checking NULL and alignment.
///
/// # Safety
/// A non-NULL `ptr` must be valid for writes of one `T`.
unsafe fn write_out<T>(ptr: *mut T, value: T, what: &str) -> Result<(), Failure> {
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL")));
    }
    if !(ptr as usize).is_multiple_of(std::mem::align_of::<T>()) {
        return Err(invalid(format!("{what} is not aligned to {} bytes", std::mem::align_of::<T>())));
    }
    // SAFETY: caller's contract; `write` does not drop the (possibly uninitialised) old value.
    unsafe { ptr.write(value) };
    Ok(())
}

fn checked_mul3(n: usize, what: &str) -> Result<usize, Failure> {
    n.checked_mul(3).ok_or_else(|| invalid(format!("{what} = {n} overflows")))
}

// ---------------------------------------------------------------------------------------------
// Memory: what cannot be reserved is refused before the core allocates it (module doc)

/// Doubles per vertex that operators take at least (stiffness in CSR, mass, curvature, the
/// factorization's share), beside a computation's eigenvectors.
const OPERATOR_DOUBLES: usize = 16;

/// Bytes that building a mesh of `n_vertices` and `n_faces` holds at least: the core's copy
/// of the arrays (24 bytes per vertex, 12 per face) and the edge buckets of its validation
/// (8 per vertex, 12 per face). `None` on overflow.
fn mesh_bytes(n_vertices: usize, n_faces: usize) -> Option<usize> {
    n_vertices.checked_mul(32)?.checked_add(n_faces.checked_mul(24)?)
}

/// Bytes that a computation of `k` eigenpairs on a mesh of `n` vertices holds at least: the
/// eigenvectors (`min(k, n)` of `n` doubles; the core refuses `k >= n` before computing) and
/// [`OPERATOR_DOUBLES`] per vertex. `k = 0`: the operators alone. `None` on overflow.
fn eigen_bytes(n: usize, k: usize) -> Option<usize> {
    n.checked_mul(k.min(n).checked_add(OPERATOR_DOUBLES)?)?.checked_mul(8)
}

/// The sum of estimates, `None` if one is or the sum overflows.
fn sum_bytes(parts: &[Option<usize>]) -> Option<usize> {
    parts.iter().try_fold(0usize, |total, &part| total.checked_add(part?))
}

fn human_bytes(bytes: usize) -> String {
    let units = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    let (mut x, mut unit) = (bytes as f64, 0);
    while x >= 1024.0 && unit + 1 < units.len() {
        x /= 1024.0;
        unit += 1;
    }
    format!("{x:.1} {}", units[unit])
}

/// Reserve `bytes` and release them at once, to learn whether the call can have them before
/// the core allocates (where a failure aborts the process): `DS_OUT_OF_MEMORY` naming the size
/// and `what` needs it if not, or if the estimate overflowed (`None`). Cheap: the pages are
/// never touched.
fn reserve(bytes: Option<usize>, what: impl FnOnce() -> String) -> Result<(), Failure> {
    let Some(bytes) = bytes else {
        return Err(Failure::OutOfMemory(format!("{} needs more bytes than the address space has", what())));
    };
    let mut probe = Vec::<u8>::new();
    probe
        .try_reserve_exact(bytes)
        .map_err(|_| Failure::OutOfMemory(format!("cannot reserve {bytes} bytes ({}) for {}", human_bytes(bytes), what())))
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
        DS_OUT_OF_MEMORY => c"DS_OUT_OF_MEMORY",
        DS_INVALID_PREPARED_SHAPE => c"DS_INVALID_PREPARED_SHAPE",
        _ => c"DS_UNKNOWN_STATUS",
    }
    .as_ptr()
}

/// Borrow a NUL-terminated UTF-8 string, checking NULL.
///
/// # Safety
/// A non-NULL `ptr` must point to a NUL-terminated string valid for the returned lifetime.
unsafe fn str_in<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL")));
    }
    // SAFETY: caller's contract.
    unsafe { CStr::from_ptr(ptr) }.to_str().map_err(|_| invalid(format!("{what} is not valid UTF-8")))
}

fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

// ---------------------------------------------------------------------------------------------
// Handles: the registry of live ones (module doc)

/// The types handed to C as opaque handles, as the registry records them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Mesh,
    Options,
    Localizer,
    Result,
    SearchResult,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Mesh => "ds_mesh",
            Kind::Options => "ds_options",
            Kind::Localizer => "ds_localizer",
            Kind::Result => "ds_result",
            Kind::SearchResult => "ds_search_result",
        }
    }
}

/// A type handed to C as an opaque handle.
trait Handle {
    const KIND: Kind;

    /// Addresses of the handles this one owns and lends out (registered and released with
    /// it): the results of a `ds_search_result`.
    fn lent(&self) -> Vec<usize> {
        Vec::new()
    }
}

impl Handle for ds_mesh {
    const KIND: Kind = Kind::Mesh;
}
impl Handle for ds_options {
    const KIND: Kind = Kind::Options;
}
impl Handle for ds_localizer {
    const KIND: Kind = Kind::Localizer;
}
impl Handle for ds_result {
    const KIND: Kind = Kind::Result;
}
impl Handle for ds_search_result {
    const KIND: Kind = Kind::SearchResult;

    fn lent(&self) -> Vec<usize> {
        self.matches.iter().filter_map(|m| m.result.as_deref()).map(|r| r as *const ds_result as usize).collect()
    }
}

/// A live handle's registry entry: its type, and whether another handle owns it (lent by
/// [`Handle::lent`]; `*_destroy` refuses it).
#[derive(Debug, Clone, Copy)]
struct Entry {
    kind: Kind,
    lent: bool,
}

/// The live handles: address -> entry. An address is inserted by [`write_handle`] when its
/// handle is made (with the handles it lends) and removed by [`destroy`] before it is
/// released, so a registered address always points to a live handle of the recorded type.
static LIVE: Mutex<BTreeMap<usize, Entry>> = Mutex::new(BTreeMap::new());

fn live() -> MutexGuard<'static, BTreeMap<usize, Entry>> {
    // Poisoning: a panic cannot leave the map half-updated (each insert/remove is whole).
    LIVE.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The entry of `ptr` if it is registered as a `T`; `what` names the argument in the message.
fn check_live<T: Handle>(live: &BTreeMap<usize, Entry>, ptr: *const T, what: &str) -> Result<Entry, Failure> {
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL")));
    }
    match live.get(&(ptr as usize)) {
        Some(&entry) if entry.kind == T::KIND => Ok(entry),
        Some(&entry) => Err(invalid(format!("{what} is a {} handle, not a {}", entry.kind.name(), T::KIND.name()))),
        None => Err(invalid(format!(
            "{what} ({ptr:p}) is not a live {} handle (destroyed already, or not made by this library)",
            T::KIND.name()
        ))),
    }
}

/// Dereference a handle after looking it up in the registry (NULL, destroyed, foreign and
/// other-type pointers are refused without being read).
///
/// # Safety
/// No other thread may destroy the handle (or its owner) while the returned reference is in use.
unsafe fn handle<'a, T: Handle>(ptr: *const T, what: &str) -> Result<&'a T, Failure> {
    check_live(&live(), ptr, what)?;
    // SAFETY: registered, so made by `write_handle` from a `Box<T>` (or lent by a handle made
    // so) and not yet destroyed.
    Ok(unsafe { &*ptr })
}

/// A getter's body on a handle: `f` of it, or `fallback` for a pointer [`handle`] refuses (the
/// reason then is the thread's last error) or a panic.
///
/// # Safety
/// As [`handle`].
unsafe fn get<T: Handle, R: Copy>(ptr: *const T, what: &str, fallback: R, f: impl FnOnce(&T) -> R) -> R {
    guard_value(fallback, || match unsafe { handle(ptr, what) } {
        Ok(h) => f(h),
        Err(e) => {
            set_last_error(&e.message());
            fallback
        }
    })
}

/// Make a handle of `value`, register it (and the handles it lends) and write it to `out`;
/// drop it if `out` cannot take it.
///
/// # Safety
/// As [`write_out`].
unsafe fn write_handle<T: Handle>(out: *mut *mut T, value: T) -> Result<(), Failure> {
    let lent = value.lent();
    let h = Box::into_raw(Box::new(value));
    {
        let mut live = live();
        live.insert(h as usize, Entry { kind: T::KIND, lent: false });
        for &address in &lent {
            live.insert(address, Entry { kind: Kind::Result, lent: true });
        }
    }
    // SAFETY: caller's contract.
    let written = unsafe { write_out(out, h, "out") };
    if written.is_err() {
        {
            let mut live = live();
            live.remove(&(h as usize));
            for address in &lent {
                live.remove(address);
            }
        }
        // SAFETY: `h` was just made by `Box::into_raw` and given to no one.
        drop(unsafe { Box::from_raw(h) });
    }
    written
}

/// The body of an entry point that makes a handle: `out` is checked first (NULL: nothing is
/// computed), `body` makes the value, which becomes a handle written to `out`.
///
/// # Safety
/// As [`write_out`] for `out`; `body` as its own unsafe calls require.
unsafe fn make<T: Handle>(out: *mut *mut T, body: impl FnOnce() -> Result<T, Failure>) -> ds_status {
    guard(|| {
        if out.is_null() {
            return Err(invalid("out is NULL"));
        }
        let value = body()?;
        unsafe { write_handle(out, value) }
    })
}

/// Release a handle made by [`write_handle`]. NULL is ignored; a pointer that is not a live
/// `T` (destroyed already, foreign, another type) or that another handle lends is left alone,
/// and `function` names it in the thread's last error.
///
/// # Safety
/// No other thread may be using the handle (or one it lends).
unsafe fn destroy<T: Handle>(ptr: *mut T, function: &str) {
    if ptr.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        let registered = {
            let mut live = live();
            check_live(&live, ptr, "the handle").and_then(|entry| {
                if entry.lent {
                    return Err(invalid(format!(
                        "the handle ({ptr:p}) belongs to a ds_search_result (released with it by ds_search_result_destroy)"
                    )));
                }
                live.remove(&(ptr as usize));
                // SAFETY: registered just now, so live; the lock is held.
                for address in unsafe { &*ptr }.lent() {
                    live.remove(&address);
                }
                Ok(())
            })
        };
        match registered {
            // SAFETY: it was registered, so made by `write_handle` from a `Box<T>`; it left the
            // registry under the lock just now, so it is released once.
            Ok(()) => drop(unsafe { Box::from_raw(ptr) }),
            Err(e) => set_last_error(&format!("{function}: {}; nothing was released", e.message())),
        }
    }));
}

// ---------------------------------------------------------------------------------------------
// Meshes

/// Borrow the flat arrays of a mesh, after checking their sizes for overflow and reserving
/// what the core's copy of them takes ([`mesh_bytes`]): nothing is read before both pass.
///
/// # Safety
/// As `ds_mesh_create`.
unsafe fn mesh_arrays<'a>(xyz: *const f64, n_vertices: usize, tri: *const u32, n_faces: usize) -> Result<(&'a [f64], &'a [u32]), Failure> {
    let (n_xyz, n_tri) = (checked_mul3(n_vertices, "n_vertices")?, checked_mul3(n_faces, "n_faces")?);
    check_array(xyz, n_xyz, "xyz")?;
    check_array(tri, n_tri, "tri")?;
    reserve(mesh_bytes(n_vertices, n_faces), || format!("a mesh of {n_vertices} vertices and {n_faces} faces"))?;
    Ok((unsafe { slice_in(xyz, n_xyz, "xyz")? }, unsafe { slice_in(tri, n_tri, "tri")? }))
}

/// Create a mesh from `n_vertices` positions `xyz[3*i .. 3*i+3]` and `n_faces` triangles
/// `tri[3*f .. 3*f+3]` (0-based vertex indices), checked strictly. The arrays are copied. On
/// success `*out` receives a handle to release with `ds_mesh_destroy`.
///
/// Errors: `DS_INVALID_ARGUMENT` (NULL/misaligned pointers, overflowing counts),
/// `DS_OUT_OF_MEMORY` (counts too large to hold the mesh: checked before the arrays are read),
/// `DS_INVALID_MESH` (index out of range, a face repeating a vertex or of zero area, a
/// triangle given twice, non-manifold edge (in more than two faces) or vertex (its faces in
/// several fans), vertex in no face, non-finite coordinate, no faces).
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
    unsafe {
        make(out, || {
            let (v, f) = mesh_arrays(xyz, n_vertices, tri, n_faces)?;
            Ok(ds_mesh { mesh: HostMesh::strict(v, f)?, warning: None })
        })
    }
}

/// Create a mesh from a host's arrays (an editor's mesh, a scan, a file) through the core's
/// intake: faces that repeat a vertex or have zero area, and repeated copies of a triangle,
/// are left out; non-manifold edges (in
/// more than two faces) and vertices (faces in several fans) are split, each extra fan of a
/// vertex getting a copy of it (no face removed; the rule of the core's `mesh::repair`); then
/// vertices in no face are left out. The mesh remembers the map back to the host's vertices.
/// Every per-vertex array in or out (`ds_gaussian_curvature`, `ds_result_region`, ...) is then
/// in the host's numbering, of length `ds_mesh_n_vertices` = `n_vertices`; left-out vertices
/// get 0; a split vertex is in a region if any copy is, its curvature and score are its first
/// copy's, its mass the sum over its copies. What was changed is said by `ds_mesh_warning` and
/// among the warnings of every result computed with the mesh.
///
/// Errors: as `ds_mesh_create`, without the degenerate-face, vertex-in-no-face and
/// non-manifold cases (`DS_INVALID_MESH` when every face is degenerate). Vertex and face
/// numbers in the messages are the host's.
///
/// # Safety
/// As `ds_mesh_create`.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_create_from_host(
    xyz: *const f64,
    n_vertices: usize,
    tri: *const u32,
    n_faces: usize,
    out: *mut *mut ds_mesh,
) -> ds_status {
    unsafe {
        make(out, || {
            let (v, f) = mesh_arrays(xyz, n_vertices, tri, n_faces)?;
            let mesh = HostMesh::from_host(v, f)?;
            let warning = mesh.host_map().warning("mesh").map(|w| c_string(&w));
            Ok(ds_mesh { mesh, warning })
        })
    }
}

/// Release a mesh. NULL is ignored; a pointer that is not a live `ds_mesh` (destroyed
/// already, not from this library, another handle type) is left alone and named in
/// `ds_last_error_message` (a second destroy does nothing).
///
/// # Safety
/// `mesh` any pointer: only a live `ds_mesh` is released. No other thread may be in a
/// call on it.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_destroy(mesh: *mut ds_mesh) {
    unsafe { destroy(mesh, "ds_mesh_destroy") }
}

/// Number of vertices in the host's numbering: the length of every per-vertex array of the
/// mesh (the given `n_vertices`; 0 for NULL).
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_n_vertices(mesh: *const ds_mesh) -> usize {
    unsafe { get(mesh, "mesh", 0, |m| m.mesh.n_vertices()) }
}

/// Number of faces used (the given ones, less those the intake left out; 0 for NULL).
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_n_faces(mesh: *const ds_mesh) -> usize {
    unsafe { get(mesh, "mesh", 0, |m| m.mesh.mesh().n_faces()) }
}

/// Number of vertices of the mesh the core works on: those of some used face, then the copies
/// of split non-manifold vertices (0 for NULL).
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_n_used_vertices(mesh: *const ds_mesh) -> usize {
    unsafe { get(mesh, "mesh", 0, |m| m.mesh.mesh().n_vertices()) }
}

/// The host index of each vertex of the mesh the core works on (`out_len ==
/// ds_mesh_n_used_vertices`): the used host vertices, increasing, then the copies of split
/// non-manifold vertices, each its host vertex's index.
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_used_vertices(mesh: *const ds_mesh, out: *mut u32, out_len: usize) -> ds_status {
    guard(|| {
        let m = unsafe { handle(mesh, "mesh")? };
        let used = m.mesh.used_vertices();
        if out_len != used.len() {
            return Err(invalid(format!("out_len is {out_len}, the mesh uses {} vertices", used.len())));
        }
        unsafe { slice_out(out, out_len, "out")? }.copy_from_slice(&used);
        Ok(())
    })
}

/// What the intake left out or split in a mesh from `ds_mesh_create_from_host`, as a sentence
/// owned by the mesh (valid until `ds_mesh_destroy`); NULL if nothing (always for
/// `ds_mesh_create`) or for a NULL mesh.
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_mesh_warning(mesh: *const ds_mesh) -> *const c_char {
    unsafe { get(mesh, "mesh", std::ptr::null(), |m| m.warning.as_ref().map_or(std::ptr::null(), |w| w.as_ptr())) }
}

// ---------------------------------------------------------------------------------------------
// Per-mesh quantities

/// Pointwise Gaussian curvature per vertex (angle defect over barycentric area; with
/// `smoothed != 0`, then averaged over each vertex's one-ring, as the scale-invariant metric
/// uses). `out` must hold `out_len == ds_mesh_n_vertices(mesh)` doubles (host numbering; 0 at
/// vertices the intake left out).
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_gaussian_curvature(mesh: *const ds_mesh, smoothed: c_int, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| {
        let m = unsafe { handle(mesh, "mesh")? };
        let n = m.mesh.n_vertices();
        if out_len != n {
            return Err(invalid(format!("out_len is {out_len}, the mesh has {n} vertices")));
        }
        let dst = unsafe { slice_out(out, out_len, "out")? };
        let used = m.mesh.mesh().n_vertices();
        // The curvature, the areas it divides by, and the copy in the host's numbering.
        reserve(sum_bytes(&[used.checked_mul(16), n.checked_mul(8)]), || format!("the curvature of {n} vertices"))?;
        dst.copy_from_slice(&crate::gaussian_curvature(&m.mesh, smoothed != 0));
        Ok(())
    })
}

/// The `k` smallest eigenvalues (ascending) of the Dirichlet Laplacian of `mesh` in `metric`
/// (`DS_METRIC_REGULAR` or `DS_METRIC_SCALE_INVARIANT` with exponent `alpha`; `alpha` is
/// ignored for the regular metric). On a closed mesh there is no boundary and the first
/// eigenvalue is 0. `out` must hold `out_len == k` doubles.
///
/// Errors: `DS_INVALID_ARGUMENT` (unknown metric, `out_len != k`, `k` not in `1..` interior
/// vertices), `DS_OUT_OF_MEMORY` (the eigenvectors cannot be held), `DS_NUMERICAL`.
///
/// # Safety
/// `mesh` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
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
        let n = m.mesh.mesh().n_vertices();
        reserve(eigen_bytes(n, k), || format!("{k} eigenpairs of a mesh of {n} vertices"))?;
        let values = crate::spectrum(&m.mesh, k, metric, alpha)?;
        if values.len() != k {
            return Err(Error::Numerical(format!("eigensolver returned {} eigenvalues, expected {k}", values.len())).into());
        }
        dst.copy_from_slice(&values);
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Options

/// Every option as a JSON array, in the order front ends list them:
/// `[{"name", "label", "type": "int"|"float"|"choice", "min", "max" | "choices", "default",
/// "doc"}, ...]`. A static string (never NULL), for building parameter lists (GUI, flags).
#[no_mangle]
pub extern "C" fn ds_options_schema_json() -> *const c_char {
    static SCHEMA: OnceLock<CString> = OnceLock::new();
    guard_value(c"[]".as_ptr(), || SCHEMA.get_or_init(|| c_string(&dualspectra::localizer::options_schema_json())).as_ptr())
}

/// Create options holding the defaults. On success `*out` receives a handle to release with
/// `ds_options_destroy`.
///
/// # Safety
/// `out` must be valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn ds_options_create(out: *mut *mut ds_options) -> ds_status {
    guard(|| {
        let options = Options::default();
        let json = c_string(&options.to_json());
        unsafe { write_handle(out, ds_options { options, json }) }
    })
}

/// Release options. NULL is ignored; a pointer that is not a live `ds_options` (destroyed
/// already, not from this library, another handle type) is left alone and named in
/// `ds_last_error_message` (a second destroy does nothing).
///
/// # Safety
/// `options` any pointer: only a live `ds_options` is released. No other thread may be in a
/// call on it.
#[no_mangle]
pub unsafe extern "C" fn ds_options_destroy(options: *mut ds_options) {
    unsafe { destroy(options, "ds_options_destroy") }
}

/// Borrow a handle mutably, after looking it up in the registry as [`handle`] does.
///
/// # Safety
/// A non-NULL `ptr` must come from this library, not be destroyed and not be in use elsewhere.
unsafe fn handle_mut<'a, T: Handle>(ptr: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    check_live(&live(), ptr as *const T, what)?;
    // SAFETY: registered (see `handle`); exclusivity is the caller's contract.
    Ok(unsafe { &mut *ptr })
}

/// Set the option `name` from text: `"20"`, `"0.5"`, `"lbo"` (names and ranges:
/// `ds_options_schema_json`). A value out of range, of the wrong type, or an unknown name is
/// `DS_INVALID_ARGUMENT` with a message naming the option and its range; the options are then
/// unchanged.
///
/// # Safety
/// `options` any pointer (a handle argument, checked), not used by another thread during the
/// call; `name` and `value` NUL-terminated strings.
#[no_mangle]
pub unsafe extern "C" fn ds_options_set(options: *mut ds_options, name: *const c_char, value: *const c_char) -> ds_status {
    guard(|| {
        let o = unsafe { handle_mut(options, "options")? };
        let name = unsafe { str_in(name, "name")? };
        let value = unsafe { str_in(value, "value")? };
        crate::set_option(&mut o.options, name, serde_json::Value::String(value.to_owned()))?;
        o.json = c_string(&o.options.to_json());
        Ok(())
    })
}

/// Set the options of a JSON object, e.g. `{"k": 10, "mode": "lbo"}` (numbers as numbers or
/// text), on top of the current ones: all or none (on error the options are unchanged and the
/// message names the offending option).
///
/// # Safety
/// As `ds_options_set`; `json_object` a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn ds_options_set_json(options: *mut ds_options, json_object: *const c_char) -> ds_status {
    guard(|| {
        let o = unsafe { handle_mut(options, "options")? };
        crate::set_json(&mut o.options, unsafe { str_in(json_object, "json_object")? })?;
        o.json = c_string(&o.options.to_json());
        Ok(())
    })
}

/// Every option's value as a JSON object (`{"mode":"dual","k":20,...}`), owned by the handle:
/// valid until the next `ds_options_set*` or `ds_options_destroy` on it. NULL for NULL.
///
/// # Safety
/// `options` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_options_json(options: *const ds_options) -> *const c_char {
    unsafe { get(options, "options", std::ptr::null(), |o| o.json.as_ptr()) }
}

// ---------------------------------------------------------------------------------------------
// Localization

struct CallbackData {
    f: unsafe extern "C" fn(f64, *const c_char, *mut c_void) -> c_int,
    user: *mut c_void,
}
// SAFETY: the C caller hands us `user` for use during the call it is given to, which does not
// return before the computation ends; the Mutex below serializes the calls.
unsafe impl Send for CallbackData {}

/// The core's progress handle calling a C callback (none for NULL).
fn progress_of(progress: ds_progress_fn, user: *mut c_void) -> Progress {
    match progress {
        None => Progress::none(),
        Some(f) => {
            let data = Mutex::new(CallbackData { f, user });
            Progress::new(move |fraction, stage| {
                let stage = c_string(stage);
                let guard = data.lock().unwrap_or_else(|p| p.into_inner());
                // SAFETY: the caller promised `f` is callable with its own `user`.
                unsafe { (guard.f)(fraction, stage.as_ptr(), guard.user) != 0 }
            })
        }
    }
}

/// The options of a possibly NULL handle (NULL: the defaults).
///
/// # Safety
/// As [`handle`].
unsafe fn options_in(options: *const ds_options) -> Result<Options, Failure> {
    if options.is_null() {
        Ok(Options::default())
    } else {
        Ok(unsafe { handle(options, "options")? }.options.clone())
    }
}

/// Vertices the potential is optimised on for a full mesh of `n` vertices: `n` decimated to
/// the `resolution` option (0: not decimated).
fn optimisation_vertices(n: usize, options: &Options) -> usize {
    if options.resolution == 0 {
        n
    } else {
        options.resolution.min(n)
    }
}

/// Bytes that preparing a full mesh of `n` vertices holds at least ([`eigen_bytes`]): its
/// operators, and `k` eigenpairs on the optimisation mesh.
fn prepare_bytes(n: usize, options: &Options) -> Option<usize> {
    sum_bytes(&[eigen_bytes(n, 0), eigen_bytes(optimisation_vertices(n, options), options.k)])
}

/// Bytes that locating a partial of `n_partial` vertices holds at least: `k` eigenpairs of the
/// partial, and of the Hamiltonian on the optimisation mesh of `n_optimisation` vertices.
fn locate_bytes(n_partial: usize, n_optimisation: usize, k: usize) -> Option<usize> {
    sum_bytes(&[eigen_bytes(n_partial, k), eigen_bytes(n_optimisation, k)])
}

fn result_handle(loc: Localization) -> ds_result {
    let warnings = loc.warnings.iter().map(|w| c_string(w)).collect();
    ds_result { loc, warnings }
}

fn localizer_handle(inner: HostLocalizer) -> ds_localizer {
    let warnings = inner.warnings().iter().map(|w| c_string(w)).collect();
    let options_json = c_string(&inner.localizer().options().to_json());
    ds_localizer { inner, warnings, options_json }
}

/// Reserve what locating `partial` on `localizer` holds at least ([`locate_bytes`]).
fn reserve_locate(localizer: &HostLocalizer, partial: &ds_mesh) -> Result<(), Failure> {
    let (n, m) = (partial.mesh.mesh().n_vertices(), localizer.localizer().optimisation_vertices());
    let k = localizer.localizer().options().k;
    reserve(locate_bytes(n, m, k), || format!("locating a partial of {n} vertices with k = {k}"))
}

/// Prepare `full` for locating partials on it: its scale, optimisation mesh, descriptors and
/// start positions, computed once. `options` may be NULL (defaults); the options are checked
/// here and copied. `progress` may be NULL. On success `*out` receives a handle to release
/// with `ds_localizer_destroy`; the mesh handle may be destroyed after this call.
///
/// Errors: `DS_INVALID_ARGUMENT` (NULL or not-live mesh/options, NULL out, options out of
/// range), `DS_OUT_OF_MEMORY` (the mesh too large for `k` and `resolution`: checked before the
/// work starts, best effort), `DS_NUMERICAL`, `DS_CANCELLED` (the callback returned 0).
///
/// # Safety
/// `full`, `options` (NULL: the defaults) any pointers (handle arguments, checked); `out`
/// valid for one write; `progress` NULL or a function callable as described for
/// `ds_progress_fn`.
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_create(
    full: *const ds_mesh,
    options: *const ds_options,
    progress: ds_progress_fn,
    user: *mut c_void,
    out: *mut *mut ds_localizer,
) -> ds_status {
    unsafe {
        make(out, || {
            let full = handle(full, "full")?;
            let options = options_in(options)?;
            let n = full.mesh.mesh().n_vertices();
            reserve(prepare_bytes(n, &options), || format!("preparing a full mesh of {n} vertices with k = {}", options.k))?;
            Ok(localizer_handle(HostLocalizer::new(&full.mesh, &options, &progress_of(progress, user))?))
        })
    }
}

/// Find the region of the prepared full mesh that `partial` is. May be called from several
/// threads at once on one localizer (each call with its own callback and result). On success
/// `*out` receives a result to release with `ds_result_destroy`; its per-vertex arrays are in
/// the host's numbering of the full mesh.
///
/// Errors: `DS_INVALID_ARGUMENT` (NULL or not-live handles, NULL out; a partial without
/// boundary or larger than the full mesh), `DS_OUT_OF_MEMORY` (as for `ds_localizer_create`),
/// `DS_NUMERICAL`, `DS_CANCELLED`.
///
/// # Safety
/// `localizer`, `partial` any pointers (handle arguments, checked); `out` valid for one
/// write; `progress` as for `ds_localizer_create`.
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_locate(
    localizer: *const ds_localizer,
    partial: *const ds_mesh,
    progress: ds_progress_fn,
    user: *mut c_void,
    out: *mut *mut ds_result,
) -> ds_status {
    unsafe {
        make(out, || {
            let localizer = handle(localizer, "localizer")?;
            let partial = handle(partial, "partial")?;
            reserve_locate(&localizer.inner, partial)?;
            Ok(result_handle(localizer.inner.locate(&partial.mesh, &progress_of(progress, user))?))
        })
    }
}

/// Release a localizer. NULL is ignored; a pointer that is not a live `ds_localizer`
/// (destroyed already, not from this library, another handle type) is left alone and named in
/// `ds_last_error_message` (a second destroy does nothing). No `ds_localizer_locate` on it may
/// be running.
///
/// # Safety
/// `localizer` any pointer: only a live `ds_localizer` is released. No other thread may be in a
/// call on it.
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_destroy(localizer: *mut ds_localizer) {
    unsafe { destroy(localizer, "ds_localizer_destroy") }
}

/// Vertices of the full mesh in the host's numbering: the length of every result's per-vertex
/// arrays (0 for NULL).
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_n_vertices(localizer: *const ds_localizer) -> usize {
    unsafe { get(localizer, "localizer", 0, |l| l.inner.n_vertices()) }
}

/// Vertices of the optimisation mesh (the full mesh decimated to about the `resolution`
/// option; 0 for NULL).
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_optimisation_vertices(localizer: *const ds_localizer) -> usize {
    unsafe { get(localizer, "localizer", 0, |l| l.inner.localizer().optimisation_vertices()) }
}

/// Seconds `ds_localizer_create` took.
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_preparation_seconds(localizer: *const ds_localizer, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(localizer, "localizer")?.inner.localizer().preparation_seconds(), "out") })
}

/// The options the localizer was prepared with, as a JSON object owned by the localizer
/// (valid until `ds_localizer_destroy`); NULL for NULL.
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_options_json(localizer: *const ds_localizer) -> *const c_char {
    unsafe { get(localizer, "localizer", std::ptr::null(), |l| l.options_json.as_ptr()) }
}

/// Number of notes on the preparation (what the intake left out of the full mesh, a
/// decimation that failed, ...); they are repeated in every result. 0 for NULL.
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_n_warnings(localizer: *const ds_localizer) -> usize {
    unsafe { get(localizer, "localizer", 0, |l| l.warnings.len()) }
}

/// Note `index` (< `ds_localizer_n_warnings`), owned by the localizer (valid until
/// `ds_localizer_destroy`); NULL for a NULL localizer or an index out of range.
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_warning(localizer: *const ds_localizer, index: usize) -> *const c_char {
    let warning = |l: &ds_localizer| l.warnings.get(index).map_or(std::ptr::null(), |w| w.as_ptr());
    unsafe { get(localizer, "localizer", std::ptr::null(), warning) }
}

/// Borrow a NUL-terminated path: any bytes on Unix (as the file system takes them), UTF-8
/// elsewhere.
///
/// # Safety
/// As [`str_in`].
unsafe fn path_in(ptr: *const c_char, what: &str) -> Result<PathBuf, Failure> {
    if ptr.is_null() {
        return Err(invalid(format!("{what} is NULL")));
    }
    // SAFETY: caller's contract.
    Ok(crate::path_of(unsafe { CStr::from_ptr(ptr) }.to_bytes(), what)?)
}

/// Save the prepared full shape to the file `path` (created or replaced; `.dsprep` by
/// convention), so that `ds_localizer_load` gives it back without preparing it again: the
/// options, the host's vertex numbering and everything the preparation computed, in a
/// versioned format (the core's `localizer::persist`; the same files as `dualspectra prepare`).
///
/// Errors: `DS_INVALID_ARGUMENT` (not a live localizer, NULL or empty path), `DS_IO` (the file
/// cannot be written; the message names it).
///
/// # Safety
/// `localizer` any pointer (a handle argument, checked); `path` a NUL-terminated string.
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_save(localizer: *const ds_localizer, path: *const c_char) -> ds_status {
    guard(|| {
        let localizer = unsafe { handle(localizer, "localizer")? };
        let path = unsafe { path_in(path, "path")? };
        Ok(localizer.inner.save(&path)?)
    })
}

/// Load a prepared full shape saved by `ds_localizer_save` (or `dualspectra prepare`): it
/// locates partials as the localizer that was saved does, with its options (threads included),
/// and its results are in the numbering of the mesh it was prepared from. The intake's note on
/// that mesh (`ds_localizer_warning`) is not kept in the file; a file of another library
/// version with the same format loads, with a note. On success `*out` receives a handle to
/// release with `ds_localizer_destroy`.
///
/// Errors: `DS_INVALID_ARGUMENT` (NULL or empty path, NULL out), `DS_IO` (the file cannot be
/// read), `DS_INVALID_PREPARED_SHAPE` (not a prepared shape, a stale format version, truncated
/// or corrupted: the message names the file and which; prepare the shape again),
/// `DS_OUT_OF_MEMORY` (the file's size cannot be reserved).
///
/// # Safety
/// `path` a NUL-terminated string; `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_localizer_load(path: *const c_char, out: *mut *mut ds_localizer) -> ds_status {
    unsafe {
        make(out, || {
            let path = path_in(path, "path")?;
            // The bytes are read whole: reserve them first (the format checks every count
            // against the bytes present before allocating).
            if let Ok(meta) = std::fs::metadata(&path) {
                let bytes = usize::try_from(meta.len()).ok();
                reserve(bytes, || format!("reading the prepared shape {}", path.display()))?;
            }
            Ok(localizer_handle(HostLocalizer::load(&path)?))
        })
    }
}

/// Find the region of `full` that `partial` corresponds to, in one call (prepare, then locate;
/// to locate several partials on one full mesh, prepare it once with `ds_localizer_create`).
/// `options` may be NULL (defaults); `progress` may be NULL. On success `*out` receives a
/// result to release with `ds_result_destroy`.
///
/// Errors: as `ds_localizer_create` and `ds_localizer_locate`.
///
/// # Safety
/// `full`, `partial`, `options` (NULL: the defaults) any pointers (handle arguments,
/// checked); `out` valid for one write; `progress` NULL or a function callable as described
/// for `ds_progress_fn`.
#[no_mangle]
pub unsafe extern "C" fn ds_localize(
    full: *const ds_mesh,
    partial: *const ds_mesh,
    options: *const ds_options,
    progress: ds_progress_fn,
    user: *mut c_void,
    out: *mut *mut ds_result,
) -> ds_status {
    unsafe {
        make(out, || {
            let full = handle(full, "full")?;
            let partial = handle(partial, "partial")?;
            let options = options_in(options)?;
            let (n, n_partial) = (full.mesh.mesh().n_vertices(), partial.mesh.mesh().n_vertices());
            let m = optimisation_vertices(n, &options);
            reserve(sum_bytes(&[prepare_bytes(n, &options), locate_bytes(n_partial, m, options.k)]), || {
                format!("localizing a partial of {n_partial} vertices on a full mesh of {n} with k = {}", options.k)
            })?;
            Ok(result_handle(crate::localize(&full.mesh, &partial.mesh, &options, &progress_of(progress, user))?))
        })
    }
}

/// Release a result. NULL is ignored; a pointer that is not a live `ds_result` (destroyed
/// already, not from this library, another handle type) or that a `ds_search_result` owns
/// (`ds_search_result_result`) is left alone and named in `ds_last_error_message` (a second
/// destroy does nothing).
///
/// # Safety
/// `result` any pointer: only a live `ds_result` is released. No other thread may be in a
/// call on it.
#[no_mangle]
pub unsafe extern "C" fn ds_result_destroy(result: *mut ds_result) {
    unsafe { destroy(result, "ds_result_destroy") }
}

/// Number of vertices of the full mesh in the host's numbering, the length of the per-vertex
/// arrays (0 for NULL).
///
/// # Safety
/// `result` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_result_n_vertices(result: *const ds_result) -> usize {
    unsafe { get(result, "result", 0, |r| r.loc.region.len()) }
}

fn copy_f64(src: &[f64], out: *mut f64, out_len: usize, what: &str) -> Result<(), Failure> {
    if out_len != src.len() {
        return Err(invalid(format!("out_len is {out_len}, {what} has {} values", src.len())));
    }
    let dst = unsafe { slice_out(out, out_len, "out")? };
    dst.copy_from_slice(src);
    Ok(())
}

/// The region: `out[i] = 1` if vertex `i` of the full mesh is in the matched region, else 0
/// (0 at vertices the intake left out). `out_len` must equal `ds_result_n_vertices(result)`.
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
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
/// `result` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_score(result: *const ds_result, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| copy_f64(&unsafe { handle(result, "result")? }.loc.score, out, out_len, "the score"))
}

/// Optimised potential `v >= 0` per full-mesh vertex (`out_len == ds_result_n_vertices`).
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
#[no_mangle]
pub unsafe extern "C" fn ds_result_potential(result: *const ds_result, out: *mut f64, out_len: usize) -> ds_status {
    guard(|| copy_f64(&unsafe { handle(result, "result")? }.loc.potential, out, out_len, "the potential"))
}

/// Number of Hamiltonian eigenvalues at the optimum in `metric` (0 for NULL or an unknown
/// metric; 0 for the metric the mode does not use).
///
/// # Safety
/// `result` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_result_n_eigenvalues(result: *const ds_result, metric: ds_metric) -> usize {
    let count = |r: &ds_result| metric_from_code(metric).map_or(0, |m| crate::eigenvalues(&r.loc, m, false).len());
    unsafe { get(result, "result", 0, count) }
}

/// Hamiltonian eigenvalues at the optimum in `metric` (`out_len == ds_result_n_eigenvalues`).
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
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
/// `result` any pointer (a handle argument, checked); `out` valid for `out_len` writes.
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
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_cost(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.cost, "out") })
}

/// How much to trust the region, in [0, 1]: the estimated probability that the partial is
/// part of this full shape and the region overlaps the true one with IoU >= 0.5 (the core's
/// `selection::confidence`, from the partial fit and the region cost). Reject matches below a
/// threshold of your choice.
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_confidence(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.confidence, "out") })
}

/// The factor the partial's coordinates were multiplied by: 1 with the option `scale` =
/// `same`, the given factor, or the estimate with `auto` (docs/algorithm.md, "The partial's
/// units").
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_scale(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.scale, "out") })
}

/// Vertices of the optimisation mesh this localization ran on: about the `resolution`
/// option, or twice that for a partial with holes (docs/algorithm.md, "A finer mesh for
/// partials with holes").
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_optimisation_vertices(result: *const ds_result, out: *mut usize) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.optimisation_vertices, "out") })
}

/// How similar the partial is to the full shape, from this localization: lower is more
/// similar, comparable between full shapes of different size and meshing (both shapes at
/// unit full-shape area), the score `ds_search` ranks by. The core's
/// `Localization::similarity_score`: the best partial fit (the mean distance from the partial's
/// SHOT descriptors to the nearest descriptor in a region) among the localization's candidate
/// regions (docs/algorithm.md, "Searching several full shapes"); `+inf` when unknown.
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_similarity_score(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.similarity_score, "out") })
}

/// Total wall-clock seconds of the call that made the result.
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_seconds(result: *const ds_result, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, handle(result, "result")?.loc.timings.total, "out") })
}

/// Wall-clock seconds per stage.
///
/// # Safety
/// `result` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_result_timings(result: *const ds_result, out: *mut ds_timings) -> ds_status {
    guard(|| {
        let t = &unsafe { handle(result, "result")? }.loc.timings;
        let c = ds_timings {
            preparation: t.preparation,
            preprocessing: t.preprocessing,
            starts: t.starts,
            optimisation: t.optimisation,
            region: t.region,
            selection: t.selection,
            total: t.total,
        };
        unsafe { write_out(out, c, "out") }
    })
}

/// Index of the selected start and the number of starts run (either pointer may be NULL).
///
/// # Safety
/// `result` any pointer (a handle argument, checked); non-NULL pointers valid for one write.
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

/// Number of warnings about what was repaired or left out (what the intake left out of the
/// full and partial meshes, a disconnected partial reduced to its largest component, ...); 0
/// for NULL.
///
/// # Safety
/// `result` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_result_n_warnings(result: *const ds_result) -> usize {
    unsafe { get(result, "result", 0, |r| r.warnings.len()) }
}

/// Warning `index` (< `ds_result_n_warnings`), NUL-terminated and owned by the result (valid
/// until `ds_result_destroy`); NULL for a NULL result or an index out of range.
///
/// # Safety
/// `result` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_result_warning(result: *const ds_result, index: usize) -> *const c_char {
    let warning = |r: &ds_result| r.warnings.get(index).map_or(std::ptr::null(), |w| w.as_ptr());
    unsafe { get(result, "result", std::ptr::null(), warning) }
}

// ---------------------------------------------------------------------------------------------
// Search: which of several full shapes is the partial a part of

/// Rank the prepared full shapes `localizers[0 .. n_localizers]` for `partial`: the partial is
/// located on each (as `ds_localizer_locate`), each localization scored by
/// `ds_result_similarity_score` (lower is more similar), and the `top` best are kept, best
/// first (ties: the lower index first). A shape the partial cannot be located on (e.g. smaller
/// than it) ranks last, with its reason (`ds_search_result_error`); if that is every shape,
/// the call fails with the first shape's error. The same localizer may appear twice.
/// Progress runs over the shapes, 0 to 1; the callback returning 0 cancels. On success `*out`
/// receives the ranking, to release with `ds_search_result_destroy`; it owns each shape's
/// `ds_result` (`ds_search_result_result`).
///
/// Errors: `DS_INVALID_ARGUMENT` (`localizers` NULL with `n_localizers > 0`, an element that
/// is not a live `ds_localizer` (named by its index), `partial` not a live mesh, `top == 0`,
/// NULL out), `DS_OUT_OF_MEMORY` (as `ds_localizer_locate`, for the largest shape), the first
/// shape's error when no shape can take the partial, `DS_CANCELLED`.
///
/// # Safety
/// `localizers` NULL with `n_localizers == 0`, or `n_localizers` pointers (each any pointer: a
/// handle argument, checked); `partial` any pointer (checked); `out` valid for one write;
/// `progress` as for `ds_localizer_create`. No localizer may be destroyed during the call.
#[no_mangle]
pub unsafe extern "C" fn ds_search(
    localizers: *const *const ds_localizer,
    n_localizers: usize,
    partial: *const ds_mesh,
    top: usize,
    progress: ds_progress_fn,
    user: *mut c_void,
    out: *mut *mut ds_search_result,
) -> ds_status {
    unsafe { ds_search_screened(localizers, n_localizers, partial, usize::MAX, top, progress, user, out) }
}

/// `ds_search` after a screen: with `shortlist` below `n_localizers`, every shape is ranked
/// by a screen of its SHOT descriptors (with the first localizer's `scale` option) and the
/// partial is located on the `shortlist` best only, quickly (`ds_search_result_quick`), and
/// again in full on the best few of those; the others follow in screen order, not
/// located and without an error (`ds_search_result_result` NULL, `ds_search_result_error`
/// NULL), each with its `ds_search_result_screen_score`. `shortlist >= n_localizers` is
/// `ds_search`. Errors as `ds_search`, and `DS_INVALID_ARGUMENT` for `shortlist == 0`.
///
/// # Safety
/// As `ds_search`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn ds_search_screened(
    localizers: *const *const ds_localizer,
    n_localizers: usize,
    partial: *const ds_mesh,
    shortlist: usize,
    top: usize,
    progress: ds_progress_fn,
    user: *mut c_void,
    out: *mut *mut ds_search_result,
) -> ds_status {
    unsafe {
        make(out, || {
            let pointers = slice_in(localizers, n_localizers, "localizers")?;
            let fulls = pointers
                .iter()
                .enumerate()
                .map(|(i, &l)| handle(l, &format!("localizers[{i}]")).map(|l| &l.inner))
                .collect::<Result<Vec<_>, _>>()?;
            let partial = handle(partial, "partial")?;
            for full in &fulls {
                reserve_locate(full, partial)?;
            }
            let found = crate::search(&partial.mesh, &fulls, top, shortlist, &progress_of(progress, user))?;
            let matches = found
                .into_iter()
                .map(|m| SearchMatch {
                    index: m.index,
                    score: m.score,
                    result: m.localization.map(|loc| Box::new(result_handle(loc))),
                    error: m.error.as_deref().map(c_string),
                    screen_score: m.screen_score.unwrap_or(f64::NAN),
                    quick: m.quick,
                    confidence: m.confidence,
                })
                .collect();
            Ok(ds_search_result { matches })
        })
    }
}

/// Release a ranking and the results it owns (their pointers are then no longer live). NULL
/// is ignored; a pointer that is not a live `ds_search_result` is left alone and named in
/// `ds_last_error_message` (a second destroy does nothing).
///
/// # Safety
/// `search` any pointer: only a live `ds_search_result` is released. No other thread may be in
/// a call on it or on one of its results.
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_destroy(search: *mut ds_search_result) {
    unsafe { destroy(search, "ds_search_result_destroy") }
}

/// Number of ranked shapes: `min(top, n_localizers)` (0 for NULL).
///
/// # Safety
/// `search` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_count(search: *const ds_search_result) -> usize {
    unsafe { get(search, "search", 0, |s| s.matches.len()) }
}

/// The match at `rank` (0 = the best), or an error naming the rank.
fn ranked(search: &ds_search_result, rank: usize) -> Result<&SearchMatch, Failure> {
    search
        .matches
        .get(rank)
        .ok_or_else(|| invalid(format!("rank {rank} is out of range ({} shapes ranked)", search.matches.len())))
}

/// Which shape is ranked at `rank` (0 = the best, `< ds_search_result_count`): its index in
/// the `localizers` array given to `ds_search`.
///
/// # Safety
/// `search` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_index(search: *const ds_search_result, rank: usize, out: *mut usize) -> ds_status {
    guard(|| unsafe { write_out(out, ranked(handle(search, "search")?, rank)?.index, "out") })
}

/// The similarity score of the shape at `rank` (`ds_result_similarity_score` of its result;
/// lower is more similar; `+inf` when the partial could not be located on it).
///
/// # Safety
/// `search` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_score(search: *const ds_search_result, rank: usize, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, ranked(handle(search, "search")?, rank)?.score, "out") })
}

/// The screen's score of the shape at `rank` (lower is more similar; `ds_search_screened`
/// with a shortlist below the number of shapes); NaN when the search was not screened.
///
/// # Safety
/// `search` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_screen_score(search: *const ds_search_result, rank: usize, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, ranked(handle(search, "search")?, rank)?.screen_score, "out") })
}

/// How much to trust that the partial is a part of the shape at `rank` rather than of another
/// one searched, in [0, 1]: how far its score is behind (relative to the spread of the search's
/// scores), or ahead of, the best other shape's, and the localization's own confidence
/// (`ds_result_confidence`, whether the region fits); 0 when the partial
/// could not be located on it or the shape was screened out. What to threshold to reject a
/// match.
///
/// # Safety
/// `search` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_confidence(search: *const ds_search_result, rank: usize, out: *mut f64) -> ds_status {
    guard(|| unsafe { write_out(out, ranked(handle(search, "search")?, rank)?.confidence, "out") })
}

/// Whether the localization at `rank` is the screened search's quick one (fewer starts, iterations
/// and eigenvalues, ranking the shortlist) rather than a full one: `ds_search_screened` localizes
/// its shortlist quickly and the best few of those again in full.
///
/// # Safety
/// `search` any pointer (a handle argument, checked); `out` valid for one write.
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_quick(search: *const ds_search_result, rank: usize, out: *mut bool) -> ds_status {
    guard(|| unsafe { write_out(out, ranked(handle(search, "search")?, rank)?.quick, "out") })
}

/// The localization on the shape at `rank`, *borrowed* from the ranking: read it with every
/// `ds_result_*` getter (its per-vertex arrays are in the numbering of that shape's full
/// mesh) until `ds_search_result_destroy(search)`; do not release it (`ds_result_destroy`
/// refuses it and does nothing). NULL when the partial could not be located on that shape
/// (see `ds_search_result_error`), for a rank out of range or a NULL ranking.
///
/// # Safety
/// `search` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_result(search: *const ds_search_result, rank: usize) -> *const ds_result {
    let result = |s: &ds_search_result| {
        s.matches.get(rank).and_then(|m| m.result.as_deref()).map_or(std::ptr::null(), |r| r as *const ds_result)
    };
    unsafe { get(search, "search", std::ptr::null(), result) }
}

/// Why the partial could not be located on the shape at `rank` (NUL-terminated, owned by the
/// ranking); NULL when it was located, for a rank out of range or a NULL ranking.
///
/// # Safety
/// `search` any pointer (a handle argument, checked).
#[no_mangle]
pub unsafe extern "C" fn ds_search_result_error(search: *const ds_search_result, rank: usize) -> *const c_char {
    let error = |s: &ds_search_result| s.matches.get(rank).and_then(|m| m.error.as_ref()).map_or(std::ptr::null(), |e| e.as_ptr());
    unsafe { get(search, "search", std::ptr::null(), error) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_are_exact_sums_and_overflow_to_none() {
        assert_eq!(mesh_bytes(10, 20), Some(10 * 32 + 20 * 24));
        assert_eq!(eigen_bytes(100, 20), Some(100 * (20 + OPERATOR_DOUBLES) * 8));
        // k beyond n is refused by the core before it computes anything.
        assert_eq!(eigen_bytes(100, usize::MAX), Some(100 * (100 + OPERATOR_DOUBLES) * 8));
        assert_eq!(mesh_bytes(usize::MAX / 32 + 1, 0), None);
        assert_eq!(eigen_bytes(usize::MAX / 8, 1), None);
        assert_eq!(sum_bytes(&[Some(usize::MAX), Some(1)]), None);
        assert_eq!(sum_bytes(&[Some(1), None]), None);
        assert_eq!(human_bytes(1536), "1.5 KiB");
    }

    #[test]
    fn reserve_refuses_what_no_machine_has() {
        assert!(reserve(Some(1 << 20), String::new).is_ok());
        for bytes in [None, Some(usize::MAX), eigen_bytes(1 << 40, 500)] {
            let e = reserve(bytes, || "the test".into()).unwrap_err();
            assert_eq!(e.status(), DS_OUT_OF_MEMORY);
            assert!(e.message().starts_with("out of memory: ") && e.message().contains("the test"), "{}", e.message());
        }
    }
}

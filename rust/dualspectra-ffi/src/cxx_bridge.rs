//! The `cxx` bridge behind the C++ API (`cpp/include/dualspectra/dualspectra.hpp`,
//! implemented in `cpp/src/dualspectra.cpp`, both compiled into this crate's static library by
//! `build.rs`).
//!
//! Shared plain types live in namespace `dualspectra` and are part of the public C++ API
//! (`Timings`, `Metric`, `Status`); the functions and the opaque Rust types (mesh, options,
//! localizer, a list of localizers to search) live in `dualspectra::detail` and are wrapped by
//! the public header, which turns
//! a `rust::Error` into a typed `dualspectra::Error` carrying the [`ffi::Status`] recorded here.
//!
//! Every function body runs under `catch_unwind` (a panic must not reach C++, where cxx would
//! abort): a panic becomes an error with status `Panic`. Conversion only, no formula.

use crate::{HostLocalizer, HostMesh};
use dualspectra::shape::Metric as CoreMetric;
use dualspectra::{Error, Localization, Options, Progress};
use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex, OnceLock};

#[cxx::bridge(namespace = "dualspectra")]
pub mod ffi {
    /// The metric of a spectrum.
    #[repr(u32)]
    enum Metric {
        Regular = 0,
        ScaleInvariant = 1,
    }

    /// Why a call failed (same values as the C API's `DS_*` codes).
    #[repr(i32)]
    enum Status {
        Ok = 0,
        InvalidArgument = 1,
        InvalidMesh = 2,
        Numerical = 3,
        Cancelled = 4,
        Panic = 5,
        Io = 6,
        /// C API only (`DS_OUT_OF_MEMORY`): the C++ API does not reserve memory up front.
        OutOfMemory = 7,
        /// `Localizer::load`: not a prepared shape, a stale format version, truncated or corrupted.
        InvalidPreparedShape = 8,
    }

    /// Wall-clock seconds per stage of a localization.
    #[derive(Debug, Clone, Copy, Default)]
    struct Timings {
        /// Preparing the full mesh (0 for `Localizer::locate`: see `preparation_seconds()`).
        preparation: f64,
        /// The partial's spectra and descriptors.
        preprocessing: f64,
        starts: f64,
        optimisation: f64,
        /// Each candidate's region on the full mesh.
        region: f64,
        /// Scoring the candidates and choosing one.
        selection: f64,
        total: f64,
    }

    /// Raw result of a localization (the public header converts it to std containers).
    #[namespace = "dualspectra::detail"]
    #[derive(Default)]
    struct LocalizationData {
        region: Vec<u8>,
        score: Vec<f64>,
        potential: Vec<f64>,
        eigenvalues_regular: Vec<f64>,
        eigenvalues_si: Vec<f64>,
        target_regular: Vec<f64>,
        target_si: Vec<f64>,
        cost: f64,
        confidence: f64,
        similarity_score: f64,
        /// The factor the partial was multiplied by (`Localization::scale`).
        scale: f64,
        optimisation_vertices: usize,
        selected_start: usize,
        n_starts: usize,
        timings: Timings,
        warnings: Vec<String>,
    }

    /// One full shape's answer of a search (`located`: else `error` says why and
    /// `localization` is empty).
    #[namespace = "dualspectra::detail"]
    struct MatchData {
        index: usize,
        score: f64,
        located: bool,
        localization: LocalizationData,
        error: String,
        screen_score: f64,
        quick: bool,
        confidence: f64,
    }

    /// A sparse `n x n` matrix as coordinate triplets (`rows[i], cols[i], values[i]`).
    #[namespace = "dualspectra::detail"]
    struct TripletData {
        n: usize,
        rows: Vec<u32>,
        cols: Vec<u32>,
        values: Vec<f64>,
    }

    #[namespace = "dualspectra::detail"]
    extern "Rust" {
        /// A validated triangle mesh with cached operators and, for a host's mesh, the map
        /// back to the host's vertex numbering.
        type MeshData;

        fn mesh_from_arrays(positions: &[f64], triangles: &[u32]) -> Result<Box<MeshData>>;
        fn mesh_from_host(positions: &[f64], triangles: &[u32]) -> Result<Box<MeshData>>;
        /// A mesh file (OFF, OBJ, PLY) read and repaired as the core reads it; `path`: the file
        /// name's bytes (any bytes on Unix).
        fn mesh_read(path: &[u8]) -> Result<Box<MeshData>>;
        /// Vertices in the host's numbering (the length of every per-vertex array).
        fn n_vertices(self: &MeshData) -> usize;
        /// Faces used.
        fn n_faces(self: &MeshData) -> usize;
        /// Flat positions `x0 y0 z0 x1 ...` of the used vertices.
        fn positions(self: &MeshData) -> &[f64];
        /// Flat 0-based triangles `i0 j0 k0 ...` into the used vertices.
        fn triangles(self: &MeshData) -> &[u32];
        /// Host index of each used vertex.
        fn used_vertices(self: &MeshData) -> Vec<u32>;
        /// What the intake left out, or reading the file repaired ("" if nothing).
        fn warning(self: &MeshData) -> String;

        /// The localizer's options (the core's `Options`).
        type OptionsData;

        fn options_new() -> Box<OptionsData>;
        fn options_clone(options: &OptionsData) -> Box<OptionsData>;
        fn options_set_text(options: &mut OptionsData, name: &str, value: &str) -> Result<()>;
        fn options_set_i64(options: &mut OptionsData, name: &str, value: i64) -> Result<()>;
        fn options_set_u64(options: &mut OptionsData, name: &str, value: u64) -> Result<()>;
        fn options_set_f64(options: &mut OptionsData, name: &str, value: f64) -> Result<()>;
        fn options_set_json(options: &mut OptionsData, json_object: &str) -> Result<()>;
        fn options_json(options: &OptionsData) -> String;
        fn options_schema() -> &'static str;

        /// A prepared full shape.
        type LocalizerData;

        fn localizer_new(full: &MeshData, options: &OptionsData, progress: &ProgressSink) -> Result<Box<LocalizerData>>;
        fn localizer_locate(localizer: &LocalizerData, partial: &MeshData, progress: &ProgressSink) -> Result<LocalizationData>;
        /// Vertices of the full mesh in the host's numbering.
        fn n_vertices(self: &LocalizerData) -> usize;
        fn optimisation_vertices(self: &LocalizerData) -> usize;
        fn preparation_seconds(self: &LocalizerData) -> f64;
        fn warnings(self: &LocalizerData) -> Vec<String>;
        fn options(self: &LocalizerData) -> Box<OptionsData>;
        /// `path`: the file name's bytes (any bytes on Unix).
        fn localizer_save(localizer: &LocalizerData, path: &[u8]) -> Result<()>;
        fn localizer_load(path: &[u8]) -> Result<Box<LocalizerData>>;

        /// The full shapes of a search, in order (each shared with its `LocalizerData`).
        type LocalizerList;

        fn localizer_list_new() -> Box<LocalizerList>;
        fn push(self: &mut LocalizerList, localizer: &LocalizerData);
        fn search(partial: &MeshData, localizers: &LocalizerList, top: usize, shortlist: usize, progress: &ProgressSink) -> Result<Vec<MatchData>>;

        fn gaussian_curvature(mesh: &MeshData, smoothed: bool) -> Result<Vec<f64>>;
        fn cotangent_stiffness(mesh: &MeshData) -> Result<TripletData>;
        fn mass(mesh: &MeshData, metric: Metric, alpha: f64) -> Result<Vec<f64>>;
        fn spectrum(mesh: &MeshData, k: usize, metric: Metric, alpha: f64) -> Result<Vec<f64>>;
        /// The default exponent of the scale-invariant metric (the "alpha" option's default).
        fn default_alpha() -> f64;
        fn localize(full: &MeshData, partial: &MeshData, options: &OptionsData, progress: &ProgressSink) -> Result<LocalizationData>;
        /// Status of the last error thrown on this thread.
        fn last_error_status() -> Status;
        fn version() -> &'static str;
    }

    #[namespace = "dualspectra::detail"]
    unsafe extern "C++" {
        include!("dualspectra/detail/progress_sink.hpp");
        /// The C++ side of a progress callback; `report` never throws.
        type ProgressSink;
        fn report(self: &ProgressSink, fraction: f64, stage: &str) -> bool;
        fn is_active(self: &ProgressSink) -> bool;
    }
}

// SAFETY: `ProgressSink::report` is documented thread-safe on the C++ side for serialized calls
// (we hold a Mutex around every call) and it is only used while the call it was given to runs.
unsafe impl Sync for ffi::ProgressSink {}
unsafe impl Send for ffi::ProgressSink {}

/// The payload of the C++ `detail::MeshData`: the mesh, and what reading its file repaired
/// (`None` for a mesh from arrays, or a file read as it was).
pub struct MeshData(HostMesh, Option<String>);

/// The payload of the C++ `detail::OptionsData`.
pub struct OptionsData(Options);

/// The payload of the C++ `detail::LocalizerData` (shared with the lists it is searched in).
pub struct LocalizerData(Arc<HostLocalizer>);

/// The payload of the C++ `detail::LocalizerList`.
pub struct LocalizerList(Vec<Arc<HostLocalizer>>);

thread_local! {
    static LAST_STATUS: Cell<i32> = const { Cell::new(0) };
}

/// Error returned through cxx; its `Display` is the C++ `what()`.
#[derive(Debug)]
pub struct BridgeError(String);

impl std::fmt::Display for BridgeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BridgeError {}

fn fail(status: i32, message: String) -> BridgeError {
    LAST_STATUS.with(|s| s.set(status));
    BridgeError(message)
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic payload".into())
}

/// Run a bridge body: catch panics, record the status of an error for `last_error_status`.
fn guarded<T>(body: impl FnOnce() -> Result<T, Error>) -> Result<T, BridgeError> {
    LAST_STATUS.with(|s| s.set(0));
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(fail(crate::status_of(&e), e.to_string())),
        Err(payload) => Err(fail(
            crate::c_abi::DS_PANIC,
            format!("internal error (panic caught at the C++ boundary): {}", panic_text(&*payload)),
        )),
    }
}

/// For infallible bridge functions: a panic yields `fallback` (cxx would abort on unwinding).
fn guarded_value<T>(fallback: impl FnOnce() -> T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|_| fallback())
}

fn mesh_from_arrays(positions: &[f64], triangles: &[u32]) -> Result<Box<MeshData>, BridgeError> {
    guarded(|| Ok(Box::new(MeshData(HostMesh::strict(positions, triangles)?, None))))
}

fn mesh_from_host(positions: &[f64], triangles: &[u32]) -> Result<Box<MeshData>, BridgeError> {
    guarded(|| Ok(Box::new(MeshData(HostMesh::from_host(positions, triangles)?, None))))
}

fn mesh_read(path: &[u8]) -> Result<Box<MeshData>, BridgeError> {
    guarded(|| {
        let (mesh, note) = crate::c_abi::read::read_mesh_file(&crate::path_of(path, "the path")?)?;
        Ok(Box::new(MeshData(mesh, note)))
    })
}

impl MeshData {
    fn n_vertices(&self) -> usize {
        self.0.n_vertices()
    }
    fn n_faces(&self) -> usize {
        self.0.mesh().n_faces()
    }
    fn positions(&self) -> &[f64] {
        self.0.mesh().vertices().as_flattened()
    }
    fn triangles(&self) -> &[u32] {
        self.0.mesh().faces().as_flattened()
    }
    fn used_vertices(&self) -> Vec<u32> {
        guarded_value(Vec::new, || self.0.used_vertices())
    }
    fn warning(&self) -> String {
        guarded_value(String::new, || self.1.clone().or_else(|| self.0.host_map().warning("mesh")).unwrap_or_default())
    }
}

fn options_new() -> Box<OptionsData> {
    Box::new(OptionsData(Options::default()))
}

fn options_clone(options: &OptionsData) -> Box<OptionsData> {
    Box::new(OptionsData(options.0.clone()))
}

fn options_set_text(options: &mut OptionsData, name: &str, value: &str) -> Result<(), BridgeError> {
    guarded(|| crate::set_option(&mut options.0, name, serde_json::Value::String(value.to_owned())))
}

fn options_set_i64(options: &mut OptionsData, name: &str, value: i64) -> Result<(), BridgeError> {
    guarded(|| crate::set_option(&mut options.0, name, value.into()))
}

fn options_set_u64(options: &mut OptionsData, name: &str, value: u64) -> Result<(), BridgeError> {
    guarded(|| crate::set_option(&mut options.0, name, value.into()))
}

fn options_set_f64(options: &mut OptionsData, name: &str, value: f64) -> Result<(), BridgeError> {
    guarded(|| {
        let v = serde_json::Number::from_f64(value)
            .map(serde_json::Value::Number)
            .ok_or_else(|| Error::InvalidArgument(format!("{name} = {value} is not a finite number")))?;
        crate::set_option(&mut options.0, name, v)
    })
}

fn options_set_json(options: &mut OptionsData, json_object: &str) -> Result<(), BridgeError> {
    guarded(|| crate::set_json(&mut options.0, json_object))
}

fn options_json(options: &OptionsData) -> String {
    guarded_value(String::new, || options.0.to_json())
}

fn options_schema() -> &'static str {
    static SCHEMA: OnceLock<String> = OnceLock::new();
    guarded_value(|| "[]", || SCHEMA.get_or_init(dualspectra::localizer::options_schema_json).as_str())
}

/// Address of the caller's `ProgressSink`, valid while the call it was given to runs.
struct SinkPtr(*const ffi::ProgressSink);
// SAFETY: see the `Send`/`Sync` impls of `ProgressSink`; access is serialized by a Mutex.
unsafe impl Send for SinkPtr {}

/// The core's progress handle reporting to `sink` (none if the sink has no callback).
fn progress_of(sink: &ffi::ProgressSink) -> Progress {
    if !sink.is_active() {
        return Progress::none();
    }
    let sink = Mutex::new(SinkPtr(sink as *const _));
    Progress::new(move |fraction, stage| {
        let guard = sink.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: the sink outlives the bridge call, during which alone the closure runs.
        unsafe { &*guard.0 }.report(fraction, stage)
    })
}

fn localizer_new(full: &MeshData, options: &OptionsData, progress: &ffi::ProgressSink) -> Result<Box<LocalizerData>, BridgeError> {
    guarded(|| Ok(Box::new(LocalizerData(Arc::new(HostLocalizer::new(&full.0, &options.0, &progress_of(progress))?)))))
}

fn localizer_locate(
    localizer: &LocalizerData,
    partial: &MeshData,
    progress: &ffi::ProgressSink,
) -> Result<ffi::LocalizationData, BridgeError> {
    guarded(|| Ok(localization_data(localizer.0.locate(&partial.0, &progress_of(progress))?)))
}

fn localizer_save(localizer: &LocalizerData, path: &[u8]) -> Result<(), BridgeError> {
    guarded(|| localizer.0.save(&crate::path_of(path, "the path")?))
}

fn localizer_load(path: &[u8]) -> Result<Box<LocalizerData>, BridgeError> {
    guarded(|| Ok(Box::new(LocalizerData(Arc::new(HostLocalizer::load(&crate::path_of(path, "the path")?)?)))))
}

fn localizer_list_new() -> Box<LocalizerList> {
    Box::new(LocalizerList(Vec::new()))
}

impl LocalizerList {
    fn push(&mut self, localizer: &LocalizerData) {
        guarded_value(|| (), || self.0.push(localizer.0.clone()))
    }
}

fn search(
    partial: &MeshData,
    localizers: &LocalizerList,
    top: usize,
    shortlist: usize,
    progress: &ffi::ProgressSink,
) -> Result<Vec<ffi::MatchData>, BridgeError> {
    guarded(|| {
        let fulls: Vec<&HostLocalizer> = localizers.0.iter().map(|l| l.as_ref()).collect();
        let found = crate::search(&partial.0, &fulls, top, shortlist, &progress_of(progress))?;
        Ok(found
            .into_iter()
            .map(|m| ffi::MatchData {
                index: m.index,
                score: m.score,
                located: m.localization.is_some(),
                localization: m.localization.map(localization_data).unwrap_or_default(),
                error: m.error.unwrap_or_default(),
                screen_score: m.screen_score.unwrap_or(f64::NAN),
                quick: m.quick,
                confidence: m.confidence,
            })
            .collect())
    })
}

impl LocalizerData {
    fn n_vertices(&self) -> usize {
        self.0.n_vertices()
    }
    fn optimisation_vertices(&self) -> usize {
        self.0.localizer().optimisation_vertices()
    }
    fn preparation_seconds(&self) -> f64 {
        self.0.localizer().preparation_seconds()
    }
    fn warnings(&self) -> Vec<String> {
        guarded_value(Vec::new, || self.0.warnings())
    }
    fn options(&self) -> Box<OptionsData> {
        Box::new(OptionsData(self.0.localizer().options().clone()))
    }
}

fn metric_to_core(m: ffi::Metric) -> Result<CoreMetric, Error> {
    crate::metric_from_code(m.repr)
}

fn gaussian_curvature(mesh: &MeshData, smoothed: bool) -> Result<Vec<f64>, BridgeError> {
    guarded(|| Ok(crate::gaussian_curvature(&mesh.0, smoothed)))
}

fn spectrum(mesh: &MeshData, k: usize, metric: ffi::Metric, alpha: f64) -> Result<Vec<f64>, BridgeError> {
    guarded(|| crate::spectrum(&mesh.0, k, metric_to_core(metric)?, alpha))
}

/// The cotangent stiffness in the host's numbering (rows and columns of used vertices only).
/// The copies of a split non-manifold vertex are summed into its host vertex's row and
/// column (no duplicate entries): the stiffness assembled on the host's faces.
fn cotangent_stiffness(mesh: &MeshData) -> Result<ffi::TripletData, BridgeError> {
    guarded(|| {
        let host = mesh.0.used_vertices();
        let w = mesh.0.stiffness();
        let mut entries: Vec<(u32, u32, f64)> = w.triplet_iter().map(|e| (host[e.row], host[e.col], *e.val)).collect();
        if host.windows(2).any(|p| p[0] >= p[1]) {
            entries.sort_unstable_by_key(|&(r, c, _)| (r, c));
            entries.dedup_by(|later, kept| {
                let same = (later.0, later.1) == (kept.0, kept.1);
                if same {
                    kept.2 += later.2;
                }
                same
            });
        }
        let mut t = ffi::TripletData { n: mesh.0.n_vertices(), rows: Vec::new(), cols: Vec::new(), values: Vec::new() };
        for (r, c, v) in entries {
            t.rows.push(r);
            t.cols.push(c);
            t.values.push(v);
        }
        Ok(t)
    })
}

fn mass(mesh: &MeshData, metric: ffi::Metric, alpha: f64) -> Result<Vec<f64>, BridgeError> {
    guarded(|| crate::mass(&mesh.0, metric_to_core(metric)?, alpha))
}

fn default_alpha() -> f64 {
    Options::default().alpha
}

fn localization_data(loc: Localization) -> ffi::LocalizationData {
    let similarity_score = loc.similarity_score;
    let t = &loc.timings;
    let timings = ffi::Timings {
        preparation: t.preparation,
        preprocessing: t.preprocessing,
        starts: t.starts,
        optimisation: t.optimisation,
        region: t.region,
        selection: t.selection,
        total: t.total,
    };
    ffi::LocalizationData {
        region: loc.region.iter().map(|&b| b as u8).collect(),
        score: loc.score,
        potential: loc.potential,
        eigenvalues_regular: loc.eigenvalues_regular,
        eigenvalues_si: loc.eigenvalues_si,
        target_regular: loc.target_regular,
        target_si: loc.target_si,
        cost: loc.cost,
        confidence: loc.confidence,
        scale: loc.scale,
        similarity_score,
        optimisation_vertices: loc.optimisation_vertices,
        selected_start: loc.selected_start,
        n_starts: loc.n_starts,
        timings,
        warnings: loc.warnings,
    }
}

fn localize(
    full: &MeshData,
    partial: &MeshData,
    options: &OptionsData,
    progress: &ffi::ProgressSink,
) -> Result<ffi::LocalizationData, BridgeError> {
    guarded(|| Ok(localization_data(crate::localize(&full.0, &partial.0, &options.0, &progress_of(progress))?)))
}

fn last_error_status() -> ffi::Status {
    ffi::Status { repr: LAST_STATUS.with(|s| s.get()) }
}

fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

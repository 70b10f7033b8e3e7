//! The `cxx` bridge behind the C++ API (`cpp/include/dualspectra/dualspectra.hpp`,
//! implemented in `cpp/src/dualspectra.cpp`, both compiled into this crate's static library by
//! `build.rs`).
//!
//! Shared plain types live in namespace `dualspectra` and are part of the public C++ API
//! (`Options`, `Timings`, `Mode`, `Metric`, `Status`); the functions and the opaque mesh
//! live in `dualspectra::detail` and are wrapped by the public header, which turns a
//! `rust::Error` into a typed `dualspectra::Error` carrying the [`ffi::Status`] recorded here.
//!
//! Every function body runs under `catch_unwind` (a panic must not reach C++, where cxx would
//! abort): a panic becomes an error with status `Panic`. Conversion only, no formula.

use crate::ShapeCache;
use dualspectra::shape::Metric as CoreMetric;
use dualspectra::{Error, Progress, TriMesh};
use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

#[cxx::bridge(namespace = "dualspectra")]
pub mod ffi {
    /// Which spectra `localize` matches.
    #[repr(u32)]
    enum Mode {
        /// k regular + k scale-invariant eigenvalues (the paper's method).
        Dual = 0,
        /// 2k regular (Laplace-Beltrami) eigenvalues.
        Lbo = 1,
        /// 2k scale-invariant eigenvalues.
        Si = 2,
    }

    /// How `localize` chooses among its optimised starts.
    #[repr(u32)]
    enum Selection {
        /// SHOT descriptors projected on the first eigenfunctions (the paper's rule).
        Descriptors = 0,
        /// The lowest final alignment cost.
        Cost = 1,
        /// The lowest alignment cost of the candidate's extracted region as a step potential.
        Region = 2,
        /// The lowest descriptor score among the candidates whose region cost is at most 3x
        /// the lowest (the default).
        Gated = 3,
    }

    /// The starting potentials around each farthest-point centre.
    #[repr(u32)]
    enum StartShape {
        /// The area-matched ball and coball and a wide Gaussian bump: 3 per centre (default).
        BallsAndWideBumps = 0,
        /// The two balls and the wide Gaussian well and bump: 4 per centre.
        BallsAndWideGaussians = 1,
        /// The reference's Gaussians, two widths, both signs: 4 per centre.
        Gaussian = 2,
        /// The two balls only: 2 per centre.
        AreaBall = 3,
    }

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
    }

    /// Parameters of `localize`; `default_options()` gives the paper's settings.
    #[derive(Clone, Copy)]
    struct Options {
        mode: Mode,
        /// Eigenvalues per spectrum (`Dual`: k + k, `Lbo`/`Si`: 2k).
        k: usize,
        /// Exponent of the scale-invariant factor.
        alpha: f64,
        /// Seed of every random choice.
        seed: u64,
        /// Vertices of the decimated full shape the potential is optimised on (0: none).
        resolution: usize,
        /// Farthest-point centres of the starts (each gives 3 starts).
        centers: usize,
        /// Trust-region iterations per start.
        max_iterations: usize,
        /// Worker threads (0: all cores).
        threads: usize,
        selection: Selection,
        start_shape: StartShape,
        /// Further starts from the full shape's first eigenfunctions, two each (0: none).
        spectral_cuts: usize,
        /// Plane-cut starts, one per direction (the first of 26 around the principal axes; 0: none).
        plane_cuts: usize,
    }

    /// Wall-clock seconds per stage of `localize`.
    #[derive(Debug, Clone, Copy, Default)]
    struct Timings {
        preprocessing: f64,
        starts: f64,
        optimisation: f64,
        selection: f64,
        region: f64,
        total: f64,
    }

    /// Raw result of `localize` (the public header converts it to std containers).
    #[namespace = "dualspectra::detail"]
    struct LocalizationData {
        region: Vec<u8>,
        score: Vec<f64>,
        potential: Vec<f64>,
        eigenvalues_regular: Vec<f64>,
        eigenvalues_si: Vec<f64>,
        target_regular: Vec<f64>,
        target_si: Vec<f64>,
        cost: f64,
        selected_start: usize,
        n_starts: usize,
        timings: Timings,
        warnings: Vec<String>,
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
        /// A validated triangle mesh with cached operators.
        type MeshData;

        fn mesh_from_arrays(positions: &[f64], triangles: &[u32]) -> Result<Box<MeshData>>;
        fn n_vertices(self: &MeshData) -> usize;
        fn n_faces(self: &MeshData) -> usize;
        /// Flat positions `x0 y0 z0 x1 ...` (`3 * n_vertices`).
        fn positions(self: &MeshData) -> &[f64];
        /// Flat 0-based triangles `i0 j0 k0 ...` (`3 * n_faces`).
        fn triangles(self: &MeshData) -> &[u32];

        fn default_options() -> Options;
        fn gaussian_curvature(mesh: &MeshData, smoothed: bool) -> Result<Vec<f64>>;
        fn cotangent_stiffness(mesh: &MeshData) -> Result<TripletData>;
        fn mass(mesh: &MeshData, metric: Metric, alpha: f64) -> Result<Vec<f64>>;
        fn spectrum(mesh: &MeshData, k: usize, metric: Metric, alpha: f64) -> Result<Vec<f64>>;
        fn localize(full: &MeshData, partial: &MeshData, options: &Options, progress: &ProgressSink) -> Result<LocalizationData>;
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
// (we hold a Mutex around every call) and it is only used while `localize` runs.
unsafe impl Sync for ffi::ProgressSink {}
unsafe impl Send for ffi::ProgressSink {}

/// The payload of the C++ `detail::MeshData`.
pub struct MeshData(ShapeCache);

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

/// Run a bridge body: catch panics, record the status of an error for `last_error_status`.
fn guarded<T>(body: impl FnOnce() -> Result<T, Error>) -> Result<T, BridgeError> {
    LAST_STATUS.with(|s| s.set(0));
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(fail(crate::status_of(&e), e.to_string())),
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic payload".into());
            Err(fail(crate::c_abi::DS_PANIC, format!("internal error (panic caught at the C++ boundary): {msg}")))
        }
    }
}

fn mesh_from_arrays(positions: &[f64], triangles: &[u32]) -> Result<Box<MeshData>, BridgeError> {
    guarded(|| Ok(Box::new(MeshData(ShapeCache::new(TriMesh::from_flat(positions, triangles)?)))))
}

impl MeshData {
    fn n_vertices(&self) -> usize {
        self.0.mesh().n_vertices()
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
}

fn metric_to_core(m: ffi::Metric) -> Result<CoreMetric, Error> {
    crate::metric_from_code(m.repr)
}

fn options_to_c(o: &ffi::Options) -> crate::c_abi::ds_options {
    crate::c_abi::ds_options {
        mode: o.mode.repr,
        k: o.k,
        alpha: o.alpha,
        seed: o.seed,
        resolution: o.resolution,
        centers: o.centers,
        max_iterations: o.max_iterations,
        threads: o.threads,
        selection: o.selection.repr,
        start_shape: o.start_shape.repr,
        spectral_cuts: o.spectral_cuts,
        plane_cuts: o.plane_cuts,
    }
}

fn default_options() -> ffi::Options {
    let o = crate::options_to_c(&dualspectra::Options::default());
    ffi::Options {
        mode: ffi::Mode { repr: o.mode },
        k: o.k,
        alpha: o.alpha,
        seed: o.seed,
        resolution: o.resolution,
        centers: o.centers,
        max_iterations: o.max_iterations,
        threads: o.threads,
        selection: ffi::Selection { repr: o.selection },
        start_shape: ffi::StartShape { repr: o.start_shape },
        spectral_cuts: o.spectral_cuts,
        plane_cuts: o.plane_cuts,
    }
}

fn gaussian_curvature(mesh: &MeshData, smoothed: bool) -> Result<Vec<f64>, BridgeError> {
    guarded(|| Ok(crate::gaussian_curvature(&mesh.0, smoothed)))
}

fn spectrum(mesh: &MeshData, k: usize, metric: ffi::Metric, alpha: f64) -> Result<Vec<f64>, BridgeError> {
    guarded(|| crate::spectrum(&mesh.0, k, metric_to_core(metric)?, alpha))
}

fn cotangent_stiffness(mesh: &MeshData) -> Result<ffi::TripletData, BridgeError> {
    guarded(|| {
        let w = mesh.0.stiffness();
        let mut t = ffi::TripletData { n: w.nrows(), rows: Vec::new(), cols: Vec::new(), values: Vec::new() };
        for e in w.triplet_iter() {
            t.rows.push(e.row as u32);
            t.cols.push(e.col as u32);
            t.values.push(*e.val);
        }
        Ok(t)
    })
}

fn mass(mesh: &MeshData, metric: ffi::Metric, alpha: f64) -> Result<Vec<f64>, BridgeError> {
    guarded(|| crate::mass(&mesh.0, metric_to_core(metric)?, alpha))
}

/// Address of the caller's `ProgressSink`, valid while `localize` runs.
struct SinkPtr(*const ffi::ProgressSink);
// SAFETY: see the `Send`/`Sync` impls of `ProgressSink`; access is serialized by a Mutex.
unsafe impl Send for SinkPtr {}

fn localize(
    full: &MeshData,
    partial: &MeshData,
    options: &ffi::Options,
    progress: &ffi::ProgressSink,
) -> Result<ffi::LocalizationData, BridgeError> {
    guarded(|| {
        let opts = crate::options_from_c(&options_to_c(options))?;
        let prog = if progress.is_active() {
            let sink = Mutex::new(SinkPtr(progress as *const _));
            Progress::new(move |fraction, stage| {
                let guard = sink.lock().unwrap_or_else(|p| p.into_inner());
                // SAFETY: the sink outlives this `localize` call, during which alone the closure runs.
                unsafe { &*guard.0 }.report(fraction, stage)
            })
        } else {
            Progress::none()
        };
        let loc = crate::localize(&full.0, &partial.0, &opts, &prog)?;
        let t = &loc.timings;
        Ok(ffi::LocalizationData {
            region: loc.region.iter().map(|&b| b as u8).collect(),
            score: loc.score.clone(),
            potential: loc.potential.clone(),
            eigenvalues_regular: loc.eigenvalues_regular.clone(),
            eigenvalues_si: loc.eigenvalues_si.clone(),
            target_regular: loc.target_regular.clone(),
            target_si: loc.target_si.clone(),
            cost: loc.cost,
            selected_start: loc.selected_start,
            n_starts: loc.n_starts,
            timings: ffi::Timings {
                preprocessing: t.preprocessing,
                starts: t.starts,
                optimisation: t.optimisation,
                selection: t.selection,
                region: t.region,
                total: t.total,
            },
            warnings: loc.warnings.clone(),
        })
    })
}

fn last_error_status() -> ffi::Status {
    ffi::Status { repr: LAST_STATUS.with(|s| s.get()) }
}

fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

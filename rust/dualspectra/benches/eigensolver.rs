//! Eigensolver benchmark (prints figures; not a test).
//!
//! `cargo bench -p dualspectra --bench eigensolver [-- NAME]` with `DUALSPECTRA_DATA` set:
//! a SHREC'16 null shape (`shrec16/null/NAME.off`, default `cat`) scaled to unit area,
//! - cold `k = 20` solve of $W\phi = \lambda A\phi$ against scipy's ARPACK
//!   `eigsh(W, k, M, sigma, which='LM')` on the same matrices, timed in the same run
//!   (`tests/python/bench_scipy_eigsh.py`, single-threaded BLAS);
//! - a Hamiltonian $(W + A\,\mathrm{diag}(v))$ with a step-like potential: cold solve, then
//!   warm re-solves after small changes of $v$ (one optimiser step), against cold solves.

use dualspectra::mesh::io::read_mesh;
use dualspectra::operators::{cotangent_stiffness, lumped_mass, SparseMatrix};
use dualspectra::spectra::{generalized_eigen, EigenParams, HamiltonianSolver};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn best_of<T>(reps: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..reps {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("reps >= 1"))
}

fn write_pencil(path: &Path, w: &SparseMatrix, mass: &[f64], k: usize, sigma: f64) -> std::io::Result<()> {
    let n = w.nrows();
    let mut buf: Vec<u8> = Vec::new();
    let nnz = w.compute_nnz();
    for x in [n as u64, nnz as u64, k as u64] {
        buf.extend_from_slice(&x.to_le_bytes());
    }
    buf.extend_from_slice(&sigma.to_le_bytes());
    let mut ptr = 0u64;
    buf.extend_from_slice(&ptr.to_le_bytes());
    for j in 0..n {
        ptr += w.row_idx_of_col_raw(j).len() as u64;
        buf.extend_from_slice(&ptr.to_le_bytes());
    }
    for j in 0..n {
        for &i in w.row_idx_of_col_raw(j) {
            buf.extend_from_slice(&(i as u64).to_le_bytes());
        }
    }
    for j in 0..n {
        for &v in w.val_of_col(j) {
            buf.extend_from_slice(&v.to_le_bytes());
        }
    }
    for &m in mass {
        buf.extend_from_slice(&m.to_le_bytes());
    }
    std::fs::File::create(path)?.write_all(&buf)
}

fn run_scipy(pencil: &Path) -> Option<(f64, Vec<f64>)> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/python/bench_scipy_eigsh.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(pencil)
        .arg("3")
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .env("MKL_NUM_THREADS", "1")
        .output()
        .ok()?;
    if !out.status.success() {
        eprintln!("scipy baseline failed: {}", String::from_utf8_lossy(&out.stderr));
        return None;
    }
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let mut secs = None;
    let mut vals = Vec::new();
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("seconds") => secs = it.next().and_then(|s| s.parse().ok()),
            Some("values") => vals = it.filter_map(|s| s.parse().ok()).collect(),
            _ => {}
        }
    }
    Some((secs?, vals))
}

fn main() {
    let name = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with('-'))
        .unwrap_or_else(|| "cat".into());
    let Some(data) = std::env::var_os("DUALSPECTRA_DATA") else {
        println!("SKIP eigensolver bench: DUALSPECTRA_DATA is not set");
        return;
    };
    let path = PathBuf::from(data).join("shrec16/null").join(format!("{name}.off"));
    if !path.exists() {
        println!("SKIP eigensolver bench: {} not found", path.display());
        return;
    }
    let mesh = match read_mesh(&path) {
        Ok(m) => m,
        Err(e) => {
            println!("SKIP eigensolver bench: cannot read {}: {e}", path.display());
            return;
        }
    };
    let scale = 1.0 / mesh.area().sqrt();
    let mesh = mesh
        .map_positions(|p| [p[0] * scale, p[1] * scale, p[2] * scale])
        .expect("scaling keeps a valid mesh");
    let w = cotangent_stiffness(&mesh);
    let mass = lumped_mass(&mesh);
    let n = mass.len();
    let k = 20;
    let params = EigenParams {
        k,
        ..Default::default()
    };
    println!("mesh {name}: {n} vertices, unit area, k = {k}");

    // Cold generalized problem vs scipy.
    let (t_rust, spec) = best_of(3, || generalized_eigen(&w, &mass, &params).expect("solve"));
    println!(
        "rust cold generalized_eigen: {:8.2} ms  (converged {}, max residual {:.1e}, shift {:.3e})",
        t_rust * 1e3,
        spec.info.converged,
        spec.info.max_residual,
        spec.info.shift
    );
    let tmp = std::env::temp_dir().join(format!("dualspectra_bench_pencil_{}.bin", std::process::id()));
    let scipy = write_pencil(&tmp, &w, &mass, k, spec.info.shift)
        .ok()
        .and_then(|_| run_scipy(&tmp));
    let _ = std::fs::remove_file(&tmp);
    match scipy {
        Some((t_py, vals)) => {
            let diff = spec
                .values
                .iter()
                .zip(&vals)
                .map(|(a, b)| (a - b).abs() / b.abs().max(1.0))
                .fold(0.0, f64::max);
            println!("scipy eigsh shift-invert:    {:8.2} ms", t_py * 1e3);
            println!("ratio rust / scipy:          {:8.3}   (goal <= 0.5)", t_rust / t_py);
            println!("max relative eigenvalue difference rust vs scipy: {diff:.2e}");
        }
        None => println!("scipy baseline unavailable (python3 with numpy/scipy needed)"),
    }

    // Hamiltonian: cold, then warm after small steps of the potential.
    let lam_k = spec.values[k - 1];
    let tau = 50.0 * lam_k;
    let (lo, hi) = mesh
        .vertices()
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p[1]), h.max(p[1]))
        });
    let field = |shift: f64| -> Vec<f64> {
        mesh.vertices()
            .iter()
            .map(|p| {
                let t = (p[1] - lo) / (hi - lo);
                let wv = 8.0 * (t - 0.5 - shift) + 0.5 * (7.0 * p[0]).sin();
                0.5 * tau * (wv.tanh() + 1.0)
            })
            .collect()
    };
    let v0 = field(0.0);
    let mut solver = HamiltonianSolver::new(&w, &mass, params.clone()).expect("solver");
    let (t_cold, s0) = best_of(3, || solver.solve_cold(&v0).expect("cold").clone());
    println!(
        "hamiltonian cold solve:      {:8.2} ms  (lambda_1 = {:.4}, lambda_k = {:.4}, residual {:.1e})",
        t_cold * 1e3,
        s0.values[0],
        s0.values[k - 1],
        s0.info.max_residual
    );
    let mut t_warm_total = 0.0;
    let mut t_cold_total = 0.0;
    let mut worst = 0.0f64;
    let mut iters = Vec::new();
    let steps = 5;
    for step in 1..=steps {
        let v = field(0.002 * step as f64);
        let t = Instant::now();
        let warm = solver.solve(&v).expect("warm").clone();
        t_warm_total += t.elapsed().as_secs_f64();
        iters.push((warm.info.warm, warm.info.iterations));
        let mut cold_solver = HamiltonianSolver::new(&w, &mass, params.clone()).expect("solver");
        let t = Instant::now();
        let cold = cold_solver.solve_cold(&v).expect("cold").clone();
        t_cold_total += t.elapsed().as_secs_f64();
        for (a, b) in warm.values.iter().zip(&cold.values) {
            worst = worst.max((a - b).abs() / b.abs());
        }
    }
    println!(
        "hamiltonian warm re-solve:   {:8.2} ms per step vs cold {:8.2} ms (ratio {:.3}, goal <= 0.2)",
        t_warm_total / steps as f64 * 1e3,
        t_cold_total / steps as f64 * 1e3,
        t_warm_total / t_cold_total
    );
    println!(
        "warm (was_warm, iterations) per step: {iters:?}; max relative eigenvalue difference warm vs cold: {worst:.2e}"
    );
}

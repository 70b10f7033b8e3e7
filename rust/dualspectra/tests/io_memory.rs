//! Memory of the readers (issue 23): reading a ~50 MB file, valid or not, allocates a
//! bounded multiple of its size. Before, a 200 MB PLY of zero-length faces took 1.72 GB
//! before `face 0 has 0 vertices`, and 200 MB of duplicate triangles 3.3 GB.
//!
//! A dedicated test binary: its global allocator counts the bytes allocated (capacity,
//! not only what is touched), and its one test runs the cases one after another, so the
//! peak of each read is its own.

use dualspectra::mesh::generate::grid;
use dualspectra::mesh::io::{read_mesh_with_report, write_obj, write_off, write_ply, ReadOptions};
use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(size: usize) {
    let live = LIVE.fetch_add(size, Ordering::Relaxed) + size;
    PEAK.fetch_max(live, Ordering::Relaxed);
}

// SAFETY: every call is forwarded to `System` with the caller's arguments; the counters
// only observe sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            // Counted as if old and new were live together (a copy), the worst case.
            grew(new_size);
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_memory");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Peak bytes allocated above what was live before, while reading `path`; and the result.
fn peak_of_read(path: &Path) -> (usize, dualspectra::Result<usize>) {
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let result = read_mesh_with_report(path, &ReadOptions::default()).map(|(mesh, _)| mesh.n_faces());
    (PEAK.load(Ordering::Relaxed) - before, result)
}

/// Write a file with `body` (called with a buffered writer), return its path.
fn generated(name: &str, body: impl FnOnce(&mut std::io::BufWriter<std::fs::File>)) -> PathBuf {
    let path = tmp(name);
    let mut w = std::io::BufWriter::new(std::fs::File::create(&path).unwrap());
    body(&mut w);
    w.flush().unwrap();
    path
}

/// A wavy grid with about 50 MB of text (OFF, OBJ) or binary (PLY) data.
fn big_grid(n: u32) -> dualspectra::TriMesh {
    grid(1.0, 1.0, n, n)
        .map_positions(|p| [p[0] * std::f64::consts::PI, p[1] / 3.0, (7.0 * p[0]).sin() * (5.0 * p[1]).cos()])
        .unwrap()
}

#[test]
fn issue23_memory_of_reading_50_mb_stays_bounded() {
    const MB: f64 = 1e6;
    const DUPLICATES: usize = 6_500_000; // "3 0 1 2\n": 52 MB
    const ZERO_FACES: usize = 50_000_000; // one count byte each: 50 MB
    type Case = (&'static str, PathBuf, Result<usize, &'static str>, f64);
    let mut cases: Vec<Case> = Vec::new();
    // Valid meshes in each format (the repairs and validation run in full).
    let mesh = big_grid(700);
    let path = tmp("grid.off");
    write_off(&path, &mesh).unwrap();
    cases.push(("valid grid, OFF", path, Ok(mesh.n_faces()), 3.0));
    let path = tmp("grid.obj");
    write_obj(&path, &mesh).unwrap();
    cases.push(("valid grid, OBJ", path, Ok(mesh.n_faces()), 3.0));
    let n_faces = mesh.n_faces();
    drop(mesh);
    let mesh = big_grid(1000);
    let path = tmp("grid.ply");
    write_ply(&path, &mesh, None, true).unwrap();
    cases.push(("valid grid, binary PLY", path, Ok(mesh.n_faces()), 3.0));
    drop(mesh);
    assert!(n_faces > 0);
    // One triangle repeated: read, the copies removed, one face left.
    let path = generated("duplicates.off", |w| {
        write!(w, "OFF\n3 {DUPLICATES} 0\n0 0 0\n1 0 0\n0 1 0\n").unwrap();
        let line = b"3 0 1 2\n".repeat(1 << 16);
        for _ in 0..DUPLICATES >> 16 {
            w.write_all(&line).unwrap();
        }
        w.write_all(&line[..8 * (DUPLICATES % (1 << 16))]).unwrap();
    });
    cases.push(("one triangle 6.5 million times, OFF", path, Ok(1), 5.0));
    // Zero-length faces: an error at face 0, without holding the faces.
    let path = generated("zero_faces.ply", |w| {
        write!(
            w,
            "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
             property float z\nelement face {ZERO_FACES}\nproperty list uchar int vertex_indices\nend_header\n"
        )
        .unwrap();
        w.write_all(&[0u8; 36]).unwrap();
        let zeros = vec![0u8; 1 << 20];
        for _ in 0..ZERO_FACES >> 20 {
            w.write_all(&zeros).unwrap();
        }
        w.write_all(&zeros[..ZERO_FACES % (1 << 20)]).unwrap();
    });
    cases.push(("50 million zero-length faces, binary PLY", path, Err("face 0 has 0 vertices"), 1.2));

    let mut worst: f64 = 0.0;
    for (name, path, expected, bound) in cases {
        let size = std::fs::metadata(&path).unwrap().len() as f64;
        assert!(size > 40.0 * MB, "{name}: only {:.1} MB", size / MB);
        let t = std::time::Instant::now();
        let (peak, result) = peak_of_read(&path);
        let seconds = t.elapsed().as_secs_f64();
        let ratio = peak as f64 / size;
        println!(
            "issue23 memory: {name}: file {:.1} MB, peak allocated {:.1} MB = {ratio:.2} x the file ({seconds:.1} s)",
            size / MB,
            peak as f64 / MB
        );
        match (&result, expected) {
            (Ok(faces), Ok(want)) => assert_eq!(*faces, want, "{name}"),
            (Err(e), Err(want)) => assert!(e.to_string().contains(want), "{name}: {e}"),
            (got, want) => panic!("{name}: got {got:?}, expected {want:?}"),
        }
        assert!(ratio < bound, "{name}: peak {ratio:.2} x the file size (bound {bound})");
        worst = worst.max(ratio);
        std::fs::remove_file(&path).unwrap();
    }
    assert!(worst < 6.0, "the generous bound of the issue");
}

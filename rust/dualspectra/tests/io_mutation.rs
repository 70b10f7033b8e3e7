//! Property test of the readers (issue 23): valid OFF, OBJ and PLY files (ASCII and
//! binary), mutated thousands of ways with a fixed seed (byte and bit flips, truncation,
//! duplicated, deleted and swapped lines, inserted bytes, tokens replaced by extreme
//! values), always give `Ok` or `Err` without a panic, within a time bound. An `Ok` mesh
//! must be consistent with its report, and an error must be one short line.

use dualspectra::mesh::generate::icosphere;
use dualspectra::mesh::io::{read_mesh_from_bytes, write_obj, write_off, write_ply, MeshFormat, ReadOptions};
use dualspectra::TriMesh;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

const SEED: u64 = 0x2300_D15E_A5ED_0023;
const CASES_PER_SOURCE: usize = 1000;
/// Per read; the slowest honest read of these small files takes well under a millisecond.
const READ_LIMIT: Duration = Duration::from_secs(2);
/// Longest error message accepted (quoted tokens are cut to 40 characters).
const MAX_MESSAGE: usize = 400;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data").join(name)
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("io_mutation");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        // xorshift64*
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Values that found bugs, or could: overflow edges, counts, NaN, OBJ corner forms.
const TOKENS: &[&str] = &[
    "0", "-1", "3", "255", "4294967295", "4294967296", "18446744073709551615", "18446744073709551616",
    "-9223372036854775808", "9223372036854775807", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", "1.5",
    "1/a/b", "1//", "-1/-1/-1", "#", "x", "", "element junk 18446744073709551615", "property list uint uint vertex_indices",
    "end_header", "format binary_big_endian 1.0", "f", "v", "3 0 0 0", "OFF", "ply",
];

/// Lines of `bytes` (each with its `\n`).
fn lines(bytes: &[u8]) -> Vec<&[u8]> {
    bytes.split_inclusive(|&b| b == b'\n').collect()
}

/// One random mutation of `b`, and what it was.
fn mutate(rng: &mut Rng, b: &[u8]) -> (Vec<u8>, String) {
    let mut out = b.to_vec();
    let at = rng.below(b.len());
    let kind = if b.is_empty() { 6 } else { rng.below(9) };
    match kind {
        0 => {
            let v = rng.next() as u8;
            out[at] = v;
            (out, format!("byte {at} = {v}"))
        }
        1 => {
            let bit = rng.below(8);
            out[at] ^= 1 << bit;
            (out, format!("bit {bit} of byte {at} flipped"))
        }
        2 => {
            out.truncate(at);
            (out, format!("truncated to {at} bytes"))
        }
        3 => {
            let l = lines(b);
            let k = rng.below(l.len());
            let times = 1 + rng.below(3);
            let mut v: Vec<&[u8]> = l[..=k].to_vec();
            v.extend(std::iter::repeat_n(l[k], times));
            v.extend(&l[k + 1..]);
            (v.concat(), format!("line {k} repeated {times} more times"))
        }
        4 => {
            let mut l = lines(b);
            let k = rng.below(l.len());
            l.remove(k);
            (l.concat(), format!("line {k} deleted"))
        }
        5 => {
            let mut l = lines(b);
            let (i, j) = (rng.below(l.len()), rng.below(l.len()));
            l.swap(i, j);
            (l.concat(), format!("lines {i} and {j} swapped"))
        }
        6 => {
            let n = 1 + rng.below(8);
            let ins: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
            out.splice(at..at, ins.iter().copied());
            (out, format!("{n} bytes inserted at {at}"))
        }
        _ => {
            // Replace the whitespace-separated token around `at` by an extreme one.
            let is_space = |c: &u8| c.is_ascii_whitespace();
            let start = out[..at].iter().rposition(is_space).map_or(0, |p| p + 1);
            let end = out[at..].iter().position(is_space).map_or(out.len(), |p| at + p);
            let tok = TOKENS[rng.below(TOKENS.len())];
            out.splice(start..end, tok.bytes());
            (out, format!("token at {start}..{end} replaced by '{tok}'"))
        }
    }
}

/// The valid sources: files of `tests/data` and files written here.
fn sources() -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<(String, Vec<u8>)> = ["tetrahedron.off", "square_pyramid.off", "flap.off", "cube_quads.obj", "square_pyramid.ply"]
        .iter()
        .map(|n| (n.to_string(), std::fs::read(data(n)).unwrap()))
        .collect();
    let ico = icosphere(1);
    type Writer = fn(&Path, &TriMesh) -> dualspectra::Result<()>;
    let writers: [(&str, Writer); 4] = [
        ("ico.off", write_off),
        ("ico.obj", write_obj),
        ("ico_ascii.ply", |p, m| write_ply(p, m, None, false)),
        ("ico_binary.ply", |p, m| write_ply(p, m, Some(&vec![[1, 2, 3]; m.n_vertices()]), true)),
    ];
    for (name, write) in writers {
        let path = tmp(name);
        write(&path, &ico).unwrap();
        out.push((name.to_string(), std::fs::read(&path).unwrap()));
    }
    out
}

/// Reads whose mesh had non-manifold vertices split (mutations make some).
static SPLIT_READS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// What one read gave: `Ok` (checked consistent) or the error's message; `Err` for a broken property.
fn check_read(bytes: &[u8], format: MeshFormat) -> Result<Option<String>, String> {
    let path = Path::new("<mutated>");
    let read = std::panic::catch_unwind(|| read_mesh_from_bytes(bytes, format, path, &ReadOptions::default()));
    match read {
        Err(_) => Err("panicked".into()),
        Ok(Ok((mesh, report))) => {
            // kept_vertices: the file's vertices kept, strictly increasing, then the copies of
            // the split non-manifold vertices, each a kept vertex, as many distinct as counted.
            let (kept, copies) = report.kept_vertices.split_at(report.kept_vertices.len() - report.n_copies());
            let mut copied: Vec<u32> = copies.to_vec();
            copied.sort_unstable();
            copied.dedup();
            let consistent = report.kept_vertices.len() == mesh.n_vertices()
                && report.face_origin.len() == mesh.n_faces()
                && kept.windows(2).all(|w| w[0] < w[1])
                && copies.iter().all(|v| kept.binary_search(v).is_ok())
                && copied.len() == report.non_manifold_vertices_split
                && (report.non_manifold_edges_split == 0 || !copies.is_empty())
                && report.kept_vertices.iter().all(|&v| (v as usize) < report.file_vertices)
                && report.face_origin.iter().all(|&r| (r as usize) < report.file_faces)
                && TriMesh::new(mesh.vertices().to_vec(), mesh.faces().to_vec()).is_ok();
            if consistent {
                if !copies.is_empty() {
                    SPLIT_READS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                }
                Ok(None)
            } else {
                Err(format!("an inconsistent mesh and report: {report:?}"))
            }
        }
        Ok(Err(e)) => {
            let m = e.to_string();
            if m.contains('\n') || m.len() > MAX_MESSAGE {
                Err(format!("an error message of {} bytes or several lines: {}", m.len(), &m[..m.len().min(300)]))
            } else {
                Ok(Some(m))
            }
        }
    }
}

#[test]
fn issue23_mutated_files_read_or_fail_cleanly_in_bounded_time() {
    let start = Instant::now();
    let mut rng = Rng(SEED);
    let mut cases: Vec<(String, MeshFormat, Vec<u8>)> = Vec::new();
    for (name, bytes) in sources() {
        let format = MeshFormat::from_path(Path::new(&name)).unwrap();
        cases.push((format!("{name} unchanged"), format, bytes.clone()));
        for _ in 0..CASES_PER_SOURCE {
            // One to three mutations on top of each other.
            let (mut b, mut what) = mutate(&mut rng, &bytes);
            for _ in 0..rng.below(3) {
                let (b2, w2) = mutate(&mut rng, &b);
                b = b2;
                what = format!("{what}; {w2}");
            }
            cases.push((format!("{name}: {what}"), format, b));
        }
    }
    let n = cases.len();
    // The reads run on a worker; the test fails on the first one that does not answer in time.
    let (tx, rx) = mpsc::channel();
    let worker_cases: Vec<(MeshFormat, Vec<u8>)> = cases.iter().map(|(_, f, b)| (*f, b.clone())).collect();
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {})); // panics are reported below, per case
    std::thread::spawn(move || {
        for (format, bytes) in worker_cases {
            if tx.send(check_read(&bytes, format)).is_err() {
                return;
            }
        }
    });
    let (mut ok, mut errors, mut broken) = (0, 0, Vec::new());
    for (k, (what, _, bytes)) in cases.iter().enumerate() {
        match rx.recv_timeout(READ_LIMIT) {
            Ok(Ok(None)) => ok += 1,
            Ok(Ok(Some(_))) => errors += 1,
            Ok(Err(problem)) => {
                let file = tmp(&format!("failing_case_{k}.bin"));
                std::fs::write(&file, bytes).unwrap();
                broken.push(format!("case {k} ({what}, saved as {}): {problem}", file.display()));
            }
            Err(_) => {
                std::panic::set_hook(hook);
                let file = tmp(&format!("hanging_case_{k}.bin"));
                std::fs::write(&file, bytes).unwrap();
                panic!("case {k} ({what}, saved as {}): no answer within {READ_LIMIT:?}", file.display());
            }
        }
    }
    std::panic::set_hook(hook);
    let seconds = start.elapsed().as_secs_f64();
    let split = SPLIT_READS.load(std::sync::atomic::Ordering::Relaxed);
    println!("issue23 mutation: {n} cases ({ok} read, {split} of them split, {errors} errors) in {seconds:.2} s");
    assert!(broken.is_empty(), "{} of {n} cases broke a property:\n{}", broken.len(), broken.join("\n"));
    // Both outcomes occur (the mutations are neither all harmless nor all fatal).
    assert!(ok > n / 20 && errors > n / 2, "{ok} read, {errors} errors");
    assert!(split > 0, "no read split a non-manifold vertex");
    assert!(seconds < 30.0, "{seconds:.1} s");
}

/// Peak resident memory of this process so far (`VmHWM`, kB; 0 where unknown).
fn peak_rss_kb() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse().ok()))
        .unwrap_or(0)
}

/// A time-bounded fuzz run per reader: mutated files (one to three mutations of a valid
/// source) read until the time is up, with the properties of the test above. 5 s per
/// reader by default; `DUALSPECTRA_FUZZ_SECONDS=600` for the long runs of
/// a study (prints executions, outcomes, slowest case, peak memory).
#[test]
fn issue23_fuzz_each_reader_for_a_bounded_time() {
    let seconds: f64 = std::env::var("DUALSPECTRA_FUZZ_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(5.0);
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let all = sources();
    for format in [MeshFormat::Off, MeshFormat::Obj, MeshFormat::Ply] {
        let mine: Vec<Vec<u8>> = all
            .iter()
            .filter(|(n, _)| MeshFormat::from_path(Path::new(n)).ok() == Some(format))
            .map(|(_, b)| b.clone())
            .collect();
        let (tx, rx) = mpsc::channel::<(String, Vec<u8>, Result<Option<String>, String>, Duration)>();
        let until = Instant::now() + Duration::from_secs_f64(seconds);
        let worker = std::thread::spawn(move || {
            let mut rng = Rng(SEED ^ format as u64);
            let mut k = 0usize;
            while Instant::now() < until {
                let source = &mine[k % mine.len()];
                k += 1;
                let (mut b, mut what) = mutate(&mut rng, source);
                for _ in 0..rng.below(3) {
                    let (b2, w2) = mutate(&mut rng, &b);
                    b = b2;
                    what = format!("{what}; {w2}");
                }
                let t = Instant::now();
                let outcome = check_read(&b, format);
                if tx.send((what, b, outcome, t.elapsed())).is_err() {
                    return;
                }
            }
        });
        let (mut runs, mut ok, mut errors) = (0usize, 0usize, 0usize);
        let mut slowest = (Duration::ZERO, String::new());
        loop {
            match rx.recv_timeout(READ_LIMIT) {
                Ok((what, bytes, outcome, took)) => {
                    runs += 1;
                    if took > slowest.0 {
                        slowest = (took, what.clone());
                    }
                    match outcome {
                        Ok(None) => ok += 1,
                        Ok(Some(_)) => errors += 1,
                        Err(problem) => {
                            std::panic::set_hook(hook);
                            let file = tmp(&format!("fuzz_failing_{runs}.bin"));
                            std::fs::write(&file, bytes).unwrap();
                            panic!("{format:?} fuzz case {runs} ({what}, saved as {}): {problem}", file.display());
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    std::panic::set_hook(hook);
                    panic!("{format:?} fuzz: a read gave no answer within {READ_LIMIT:?} after {runs} cases");
                }
            }
        }
        worker.join().unwrap();
        println!(
            "issue23 fuzz {format:?}: {runs} executions in {seconds} s ({ok} read, {errors} errors, 0 panics, 0 hangs); slowest {:.2} ms ({}); peak RSS {} MB",
            slowest.0.as_secs_f64() * 1e3,
            slowest.1,
            peak_rss_kb() / 1024
        );
        assert!(runs > 0 && ok > 0 && errors > 0, "{format:?}: {runs} runs, {ok} read, {errors} errors");
    }
    std::panic::set_hook(hook);
}

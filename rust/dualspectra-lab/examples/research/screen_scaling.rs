//! The library screen at thousands of models: its file, load time, memory and time per query
//! on a screen made `COPIES` times larger by repeating its models (copies are fine for
//! timing; the ranking itself is not looked at).
//!
//! `cargo run -p dualspectra-lab --release --example research_screen_scaling -- LIB.dsscreen PARTIAL COPIES...`
//!
//! One line per size: models, file bytes (and per model), seconds to load, resident memory
//! after loading (VmRSS) and its peak so far (VmHWM), and the median seconds of three ranks of
//! PARTIAL with `scale = same` and with `scale = auto`.

use dualspectra::lab::persist::crc32;
use dualspectra::mesh::io::read_mesh;
use dualspectra::{Progress, Scale, Screen};
use std::path::Path;
use std::time::Instant;

/// `VmRSS` and `VmHWM` of this process, in MB (Linux; NaN elsewhere).
fn memory_mb() -> (f64, f64) {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|kb| kb.parse::<f64>().ok())
            .map_or(f64::NAN, |kb| kb / 1024.0)
    };
    (field("VmRSS:"), field("VmHWM:"))
}

/// The screen file's bytes with its models repeated `copies` times (same layout: header,
/// payload of dimensions, basis, model count, model records; the checksum redone).
fn repeated(bytes: &[u8], copies: usize) -> Result<Vec<u8>, String> {
    let u64_at = |at: usize| -> Result<u64, String> {
        bytes.get(at..at + 8).map(|b| u64::from_le_bytes(b.try_into().unwrap())).ok_or_else(|| "truncated".to_string())
    };
    let header = 8 + 4 + 8 + 4;
    let dims = u64_at(header)? as usize;
    let count_at = header + 8 + 352 * dims * 8;
    let models = u64_at(count_at)?;
    let records = bytes.get(count_at + 8..).ok_or("truncated")?;
    let mut payload = bytes[header..count_at].to_vec();
    payload.extend_from_slice(&(models * copies as u64).to_le_bytes());
    for _ in 0..copies {
        payload.extend_from_slice(records);
    }
    let mut out = bytes[..12].to_vec();
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Ok(out)
}

fn median3(mut f: impl FnMut() -> Result<(), Box<dyn std::error::Error>>) -> Result<f64, Box<dyn std::error::Error>> {
    let mut t = Vec::new();
    for _ in 0..3 {
        let t0 = Instant::now();
        f()?;
        t.push(t0.elapsed().as_secs_f64());
    }
    t.sort_by(f64::total_cmp);
    Ok(t[1])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: research_screen_scaling LIB.dsscreen PARTIAL COPIES...";
    let bytes = std::fs::read(args.first().ok_or(usage)?)?;
    let partial = read_mesh(Path::new(args.get(1).ok_or(usage)?))?;
    println!("models file_MB KB_per_model load_s rss_MB peak_MB same_s auto_s");
    for c in &args[2..] {
        let copies: usize = c.parse()?;
        let big = repeated(&bytes, copies)?;
        let t0 = Instant::now();
        let screen = Screen::from_bytes(&big, None)?;
        let load = t0.elapsed().as_secs_f64();
        let file_mb = big.len() as f64 / 1e6;
        drop(big);
        let (rss, _) = memory_mb();
        let same = median3(|| Ok(screen.rank(&partial, Scale::Same, &Progress::none()).map(|_| ())?))?;
        let auto = median3(|| Ok(screen.rank(&partial, Scale::Auto, &Progress::none()).map(|_| ())?))?;
        let (_, peak) = memory_mb();
        println!(
            "{} {file_mb:.1} {:.1} {load:.2} {rss:.0} {peak:.0} {same:.3} {auto:.3}",
            screen.len(),
            file_mb * 1e3 / screen.len() as f64
        );
    }
    Ok(())
}

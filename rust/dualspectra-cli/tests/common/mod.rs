//! Helpers shared by the end-to-end tests that run the `dualspectra` binary.

use std::path::PathBuf;
use std::process::{Command, Output};

/// The binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_dualspectra"))
}

/// A fresh, empty scratch folder `dualspectra_<suite>_<pid>_<name>` in the temp dir.
pub fn scratch(suite: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dualspectra_{suite}_{}_{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Run `cmd` and assert that it succeeded, showing its stderr and stdout if not.
pub fn run(cmd: &mut Command) -> Output {
    let out = cmd.output().expect("run dualspectra");
    assert!(
        out.status.success(),
        "{:?} failed: {}\n{}",
        cmd,
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
    out
}

/// A PNG file decoded with the `png` crate: (width, height, 8-bit RGB rows), after checking
/// that it is 8-bit RGB.
#[allow(dead_code)]
pub fn decode_png(path: &std::path::Path) -> (usize, usize, Vec<u8>) {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())));
    let mut reader = png::Decoder::new(file).read_info().expect("a valid PNG header");
    let mut buf = vec![0; reader.output_buffer_size().expect("a PNG of sane size")];
    let info = reader.next_frame(&mut buf).expect("valid PNG data");
    assert_eq!((info.color_type, info.bit_depth), (png::ColorType::Rgb, png::BitDepth::Eight));
    buf.truncate(info.buffer_size());
    (info.width as usize, info.height as usize, buf)
}

/// Pixels of the region colour (red well above green; the shape is grey, the rest white),
/// in columns `x0..x1` of a decoded RGB image `width` wide.
#[allow(dead_code)]
pub fn red_pixels(rgb: &[u8], width: usize, x0: usize, x1: usize) -> usize {
    rgb.chunks_exact(3)
        .enumerate()
        .filter(|(i, p)| (x0..x1).contains(&(i % width)) && p[0] as i32 > p[1] as i32 + 20)
        .count()
}

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

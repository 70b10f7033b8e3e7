//! Writing results.

use crate::error::CliError;
use serde::Serialize;
use std::path::Path;

/// `value` as compact JSON followed by a newline.
pub fn to_json_line<T: Serialize>(value: &T) -> Result<String, CliError> {
    serde_json::to_string(value)
        .map(|s| s + "\n")
        .map_err(|e| CliError::Internal(format!("cannot encode JSON: {e}")))
}

/// Write `text` to `path`.
pub fn write_text(path: &Path, text: &str) -> Result<(), CliError> {
    std::fs::write(path, text).map_err(|source| CliError::Output {
        path: path.to_path_buf(),
        source,
    })
}

/// Print `text` on standard output. A closed pipe (`dualspectra ... | head`) ends the
/// output quietly instead of panicking as `print!` does.
pub fn print_stdout(text: &str) -> Result<(), CliError> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(CliError::Output {
            path: "<standard output>".into(),
            source: e,
        }),
        _ => Ok(()),
    }
}

/// Check, before any work, that `path` can take an output: not a directory or another
/// non-regular file (a device such as /dev/full), not one of the `inputs` (which it would
/// overwrite), in an existing folder where a file can be created or is writable. A file the
/// check creates is removed again.
pub fn check_output_path(path: &Path, inputs: &[&Path]) -> Result<(), CliError> {
    let refuse = |why: &str| CliError::Output {
        path: path.to_path_buf(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidInput, why.to_string()),
    };
    if let Ok(meta) = std::fs::metadata(path) {
        if meta.is_dir() {
            return Err(refuse("is a directory"));
        }
        if !meta.is_file() {
            return Err(refuse("is not a regular file"));
        }
        let target = std::fs::canonicalize(path).ok();
        if inputs.iter().any(|i| std::fs::canonicalize(i).ok() == target && target.is_some()) {
            return Err(refuse("is an input of this command (it would be overwritten)"));
        }
        std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map(drop)
            .map_err(|source| CliError::Output { path: path.to_path_buf(), source })
    } else {
        std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(path)
            .map_err(|source| CliError::Output { path: path.to_path_buf(), source })?;
        let _ = std::fs::remove_file(path);
        Ok(())
    }
}

/// One line of a command's report on standard output (the `outln!` macro, `println!`'s
/// form). A closed pipe (`dualspectra bench | head`) ends the program quietly with success,
/// as [`print_stdout`] treats it, where `println!` panics; any other write error is reported
/// as one line and exits with the output error's code.
pub fn print_line(args: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    if let Err(source) = writeln!(out, "{args}") {
        if source.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        let e = CliError::Output { path: "<standard output>".into(), source };
        crate::error::report(&e);
        std::process::exit(i32::from(e.code()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_are_checked_before_the_work() {
        let dir = std::env::temp_dir().join(format!("dualspectra_output_check_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("in.off");
        std::fs::write(&input, "OFF\n").unwrap();
        let fresh = dir.join("new.json");
        check_output_path(&fresh, &[&input]).unwrap();
        assert!(!fresh.exists(), "the check leaves no file behind");
        let err = |p: &Path| check_output_path(p, &[&input]).unwrap_err().to_string();
        assert!(err(&input).contains("is an input"));
        assert!(err(&dir).contains("is a directory"));
        assert!(err(&dir.join("missing").join("x.json")).contains("cannot write"));
        if Path::new("/dev/full").exists() {
            assert!(err(Path::new("/dev/full")).contains("not a regular file"));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

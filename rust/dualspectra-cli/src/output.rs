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

//! The CLI's error type, its exit codes, and the one-line printer.
//!
//! Exit codes: 0 success; 1 other failure; 2 usage (clap's own errors too, and invalid
//! argument values); 3 input file unreadable or invalid; 4 numerical failure; 5 output
//! file not writable; 130 cancelled.

use dualspectra::{Error, MeshError};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug)]
pub enum CliError {
    /// An error of the core library (names the file for input errors).
    Core(Error),
    /// An argument value that clap's parser accepts but the command does not.
    Usage(String),
    /// The output file could not be written.
    Output { path: PathBuf, source: std::io::Error },
    /// A failure of the CLI itself (e.g. encoding the output).
    Internal(String),
}

impl From<Error> for CliError {
    fn from(e: Error) -> Self {
        CliError::Core(e)
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CliError::Core(e) => write!(f, "{e}"),
            CliError::Usage(m) | CliError::Internal(m) => write!(f, "{m}"),
            CliError::Output { path, source } => write!(f, "{}: cannot write: {source}", path.display()),
        }
    }
}

impl std::error::Error for CliError {}

impl CliError {
    pub fn exit_code(&self) -> ExitCode {
        ExitCode::from(self.code())
    }

    /// The exit status [`CliError::exit_code`] gives.
    pub fn code(&self) -> u8 {
        match self {
            CliError::Usage(_) | CliError::Core(Error::InvalidArgument(_)) => 2,
            CliError::Core(Error::Io { .. } | Error::Parse { .. } | Error::InvalidMeshFile { .. } | Error::PreparedShape { .. }) => 3,
            CliError::Core(Error::Numerical(_)) => 4,
            CliError::Output { .. } => 5,
            CliError::Core(Error::Cancelled) => 130,
            CliError::Core(_) | CliError::Internal(_) => 1,
        }
    }

    /// The message without the `error: ` prefix, on one line, with a hint where one helps.
    pub fn message(&self) -> String {
        let mut m = self.to_string();
        if let CliError::Core(Error::InvalidMeshFile {
            source: MeshError::IsolatedVertex { .. },
            ..
        }) = self
        {
            m.push_str(" (run with --drop-isolated to remove them)");
        }
        m.split_whitespace().collect::<Vec<_>>().join(" ")
    }
}

/// Print `error: <message>` on one line of standard error.
pub fn report(e: &CliError) {
    eprintln!("error: {}", e.message());
}

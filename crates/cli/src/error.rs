//! Errors of the command line and how they are reported: one line on stderr
//! and exit status 2 for bad input, 1 for other failures.

use std::io::Write;
use std::process::ExitCode;

/// A failure of a command.
#[derive(Debug)]
pub enum CliError {
    /// The user's input is invalid: exit status 2.
    Usage(String),
    /// Something else failed (e.g. writing a file): exit status 1.
    Failure(String),
}

impl CliError {
    /// Prints the error as one line and returns the exit status.
    pub fn report(&self) -> ExitCode {
        let (message, status) = match self {
            CliError::Usage(message) => (message, 2),
            CliError::Failure(message) => (message, 1),
        };
        let _ = writeln!(std::io::stderr(), "lqmc: {}", one_line(message));
        ExitCode::from(status)
    }
}

impl From<qmc::PointSetError> for CliError {
    fn from(error: qmc::PointSetError) -> Self {
        CliError::Usage(error.to_string())
    }
}

/// A shortcut for bad-input errors.
pub fn usage(message: impl Into<String>) -> CliError {
    CliError::Usage(message.into())
}

/// Joins a multi-line message into one line.
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|line| !line.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Reports a command-line parsing error. Help and version requests print
/// normally and succeed; errors become one line with exit status 2.
pub fn report_clap_error(error: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match error.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = error.print();
            ExitCode::SUCCESS
        }
        _ => {
            let rendered = error.render().to_string();
            let message: Vec<&str> = rendered
                .lines()
                .map(str::trim)
                .filter(|line| {
                    !line.is_empty()
                        && !line.starts_with("Usage:")
                        && !line.starts_with("For more information")
                })
                .collect();
            let message = message.join(" ");
            let message = message.strip_prefix("error: ").unwrap_or(&message);
            let _ = writeln!(std::io::stderr(), "lqmc: {message}");
            ExitCode::from(2)
        }
    }
}

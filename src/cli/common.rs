//! Helpers every subcommand shares: the bad-flag error and the `--json` printer.

use super::output::outln;
use scm::error::{Error, Result};
use std::path::Path;

/// A bad command-line value: exit 2, naming the flag.
pub fn bad_flag(flag: &str, message: String) -> Error {
    Error::input(Path::new("command line"), flag.to_string(), message)
}

/// `value` as a JSON value; a value that cannot be serialised is a failure, not empty output.
pub fn to_json<T: serde::Serialize>(value: &T) -> Result<serde_json::Value> {
    serde_json::to_value(value).map_err(json_failed)
}

/// Prints `value` as pretty JSON on stdout (`--json`).
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(json_failed)?;
    outln!("{text}");
    Ok(())
}

/// The typed error of a report that serde_json cannot write.
fn json_failed(e: serde_json::Error) -> Error {
    Error::Failed {
        context: "--json".into(),
        message: format!("cannot write the report as JSON: {e}"),
    }
}

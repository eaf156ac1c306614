//! Helpers every subcommand shares: the bad-flag error and the `--json` printer.

use super::output::outln;
use scm::error::Error;
use std::path::Path;

/// A bad command-line value: exit 2, naming the flag.
pub fn bad_flag(flag: &str, message: String) -> Error {
    Error::input(Path::new("command line"), flag.to_string(), message)
}

/// Prints `value` as pretty JSON on stdout (`--json`).
pub fn print_json<T: serde::Serialize>(value: &T) {
    outln!(
        "{}",
        serde_json::to_string_pretty(value).unwrap_or_default()
    );
}

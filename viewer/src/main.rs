//! scm-viewer: the interactive viewer (its own issue). For now it loads a URDD and prints what it holds,
//! so `scm view` has a binary to launch and the workspace layout is fixed.

use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(dir) = std::env::args_os().nth(1) else {
        eprintln!("usage: scm-viewer URDD_DIR");
        return ExitCode::from(2);
    };
    match scm::urdd::Urdd::open(std::path::Path::new(&dir)) {
        Ok(urdd) => {
            println!("{}", urdd.summary_line());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("scm-viewer: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

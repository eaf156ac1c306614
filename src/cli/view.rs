//! `scm view`: find the viewer binary and run it on the URDD.

use super::args::ViewArgs;
use scm::error::{Error, Result};
use std::path::PathBuf;

/// `scm view`: launch the viewer binary found next to this executable or on PATH.
pub fn run_view(args: &ViewArgs) -> Result<()> {
    scm::urdd::Urdd::open(&args.urdd)?;
    let viewer = find_viewer().ok_or_else(|| Error::Failed {
        context: "scm view".into(),
        message:
            "the viewer binary `scm-viewer` was not found next to scm or on PATH; build it in the \
             scm source tree with `cargo build --release -p scm-viewer` (it needs Bevy) and put \
             target/release/scm-viewer beside scm or on PATH"
                .into(),
    })?;
    let status = std::process::Command::new(&viewer)
        .arg(&args.urdd)
        .status()
        .map_err(|e| Error::io(&viewer, e))?;
    if status.success() {
        Ok(())
    } else {
        Err(Error::Failed {
            context: "scm view".into(),
            message: format!("the viewer exited with {status}"),
        })
    }
}

/// `scm-viewer` beside the running executable, else the first on PATH.
fn find_viewer() -> Option<PathBuf> {
    let name = format!("scm-viewer{}", std::env::consts::EXE_SUFFIX);
    let beside = std::env::current_exe().ok()?.parent()?.join(&name);
    if beside.is_file() {
        return Some(beside);
    }
    std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|p| p.join(&name))
            .find(|p| p.is_file())
    })
}

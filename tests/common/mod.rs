//! Shared helpers of the integration tests: the third-party robots folder and scratch directories.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The shared robots folder (`SCM_ROBOTS`, default `../shared/robots`). Without it the test is skipped,
/// except under `CI=true`, where missing data fails the test.
pub fn robots_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("SCM_ROBOTS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/robots"));
    if dir.is_dir() {
        return Some(dir);
    }
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!(
            "robot data not found at {} (set SCM_ROBOTS); CI=true requires it",
            dir.display()
        );
    }
    eprintln!(
        "skipping: robot data not found at {} (set SCM_ROBOTS)",
        dir.display()
    );
    None
}

/// The shared robots: (folder, URDF file name).
pub const ROBOTS: [(&str, &str); 7] = [
    ("fanuc", "fanuc.urdf"),
    ("ur5e", "ur5e.urdf"),
    ("panda", "panda.urdf"),
    ("xarm7", "xarm7.urdf"),
    ("xarm7_gripper", "xarm7_with_gripper.urdf"),
    ("b1", "b1.urdf"),
    ("orca_hand", "orcahand_right.urdf"),
];

/// The project's own demo robot.
pub fn demo_urdf() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("robots/demo_arm/demo_arm.urdf")
}

/// A fresh, empty scratch directory under the system temp dir.
pub fn scratch(name: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "scm-test-{}-{}-{}",
        name,
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// Runs the `scm` binary with `args`.
pub fn scm(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scm"))
        .args(args)
        .output()
        .expect("run scm")
}

/// Convenience: `scm` with string arguments.
pub fn scm_str(args: &[&str]) -> Output {
    let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| std::ffi::OsStr::new(*a)).collect();
    scm(&args)
}

/// Preprocesses `urdf` with default parameters into a fresh scratch URDD named after `name`.
pub fn preprocessed(urdf: &Path, name: &str) -> PathBuf {
    let out = scratch(name);
    let opts = scm::preprocess::PreprocessOptions {
        urdf: urdf.to_path_buf(),
        out: out.clone(),
        packages: scm::robot::PackagePaths::new(),
        params: scm::shapes::ShapeParams::default(),
        force: false,
    };
    scm::preprocess::preprocess(&opts, &scm::progress::NoProgress)
        .unwrap_or_else(|e| panic!("{}: {e}", urdf.display()));
    out
}

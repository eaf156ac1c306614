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
        visual_fallback: false,
        params: scm::shapes::ShapeParams::default(),
        force: false,
    };
    scm::preprocess::preprocess(&opts, &scm::progress::NoProgress)
        .unwrap_or_else(|e| panic!("{}: {e}", urdf.display()));
    out
}

/// Preprocesses and samples `urdf` (`samples` configurations, all six types) into a scratch URDD.
pub fn sampled(urdf: &Path, name: &str, samples: u64) -> PathBuf {
    let out = preprocessed(urdf, name);
    let mut opts = scm::sample::SampleOptions::new(&out);
    opts.samples = samples;
    scm::sample::sample(&opts, &scm::progress::NoProgress)
        .unwrap_or_else(|e| panic!("{}: {e}", urdf.display()));
    out
}

/// `python3` if it can import every module in `modules`. Without them the test is skipped, except under
/// `CI=true`, where `.ci/run` installs them and their absence fails the test.
pub fn python_with(modules: &[&str]) -> Option<&'static str> {
    let probe = format!("import {}", modules.join(", "));
    let ok = Command::new("python3")
        .args(["-c", &probe])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        return Some("python3");
    }
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("python3 with {modules:?} is required under CI=true (pip install pin mujoco drake)");
    }
    eprintln!("skipping: python3 with {modules:?} not available (pip install pin mujoco drake)");
    None
}

/// Runs a checker script of `tests/consumers/` and parses its one JSON line.
pub fn run_consumer(python: &str, script: &str, args: &[&Path]) -> serde_json::Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/consumers")
        .join(script);
    let out = Command::new(python)
        .arg(&path)
        .args(args)
        .output()
        .expect("run python3");
    assert!(
        out.status.success(),
        "{script} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{script}: bad output ({e}): {}",
            String::from_utf8_lossy(&out.stdout)
        )
    })
}

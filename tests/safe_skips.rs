//! Safe skips: the SRDF scm exports hides no collision that the real Pinocchio + Coal find on the
//! URDF's exact collision geometry.
//!
//! For every shared robot: `scm run` (20,000 samples) writes `DIR/export/<robot>.srdf`, and
//! `tests/consumers/srdf_pinocchio.py`, an independent checker, loads the same URDF with Pinocchio,
//! reads the SRDF's `<disable_collisions>` with their reasons and decides with `coal.collide` on the
//! collision geometry (meshes, boxes, cylinders, spheres as the URDF gives them, not scm's shapes),
//! at the home configuration and 2,000 random ones (seed 7, drawn independently of scm's sampling):
//!
//! - every `Default` pair collides at home, and every `Always` pair in every configuration: these
//!   reasons claim contact, so scm must decide them on geometry inside what Coal checks (a shape that
//!   touches the other link's shape only if the exact geometries touch);
//! - no `Never` pair collides in any configuration: this reason claims clearance, so scm must decide it
//!   on geometry around what Coal checks (a link hull that contains the exact geometry), where a miss
//!   of the hulls proves a miss of the meshes.
//!
//! `Adjacent` and `User` pairs are not claims about geometry and are not checked. A violation is a pair
//! MoveIt (which loads the same geometry into FCL, Coal's ancestor) would stop checking although the
//! robot can really collide there, or a pair whose reason the geometry contradicts.

mod common;

use common::{python_with, robots_dir, run_consumer, scm_str, scratch};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// scm's samples per pair (`scm run --samples`).
const SAMPLES: &str = "20000";
/// The checker's random configurations, besides home, and their seed.
const CONFIGURATIONS: &str = "2000";
const SEED: &str = "7";

/// The one SRDF `scm run` exported into `dir/export`.
fn exported_srdf(dir: &Path) -> PathBuf {
    let export = dir.join("export");
    let srdfs: Vec<PathBuf> = std::fs::read_dir(&export)
        .unwrap_or_else(|e| panic!("{}: {e}", export.display()))
        .map(|e| e.expect("read export dir").path())
        .filter(|p| p.extension().is_some_and(|x| x == "srdf"))
        .collect();
    assert_eq!(
        srdfs.len(),
        1,
        "{}: expected one .srdf, found {srdfs:?}",
        export.display()
    );
    srdfs.into_iter().next().unwrap()
}

/// Runs scm on the shared robot in `folder` and checks its SRDF with the Pinocchio + Coal checker.
fn assert_safe_skips(folder: &str) {
    let Some(python) = python_with(&["pinocchio", "coal"]) else {
        return;
    };
    let Some(robots) = robots_dir() else { return };
    let (_, file) = common::ROBOTS
        .iter()
        .find(|(f, _)| *f == folder)
        .unwrap_or_else(|| panic!("{folder} is not a shared robot"));
    let urdf = robots.join(folder).join(file);
    let packages = robots.join(folder);
    let dir = scratch(&format!("safe-skips-{folder}"));

    let start = Instant::now();
    let out = scm_str(&[
        "run",
        urdf.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
        "--samples",
        SAMPLES,
    ]);
    assert!(
        out.status.success(),
        "{folder}: scm run: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let scm_time = start.elapsed();
    let srdf = exported_srdf(&dir);

    let start = Instant::now();
    let report = run_consumer(
        python,
        "srdf_pinocchio.py",
        &[
            &urdf,
            &packages,
            &srdf,
            Path::new(CONFIGURATIONS),
            Path::new(SEED),
        ],
    );
    let check_time = start.elapsed();

    assert_eq!(
        report["configs"].as_u64(),
        CONFIGURATIONS.parse().ok(),
        "{folder}: the checker's configurations"
    );
    let pairs = &report["pairs"];
    let checked: u64 = ["Default", "Always", "Never"]
        .iter()
        .map(|r| pairs[r].as_u64().expect("a count"))
        .sum();
    assert!(
        checked > 0,
        "{folder}: no Default, Always or Never pair checked"
    );
    let violations = report["violations"].as_array().expect("violations");
    eprintln!(
        "{folder}: {checked} pairs checked (Default {}, Always {}, Never {}) at home + {CONFIGURATIONS} \
         configurations: {} violations; scm run {:.1} s, checker {:.1} s",
        pairs["Default"],
        pairs["Always"],
        pairs["Never"],
        violations.len(),
        scm_time.as_secs_f64(),
        check_time.as_secs_f64()
    );
    let lines: Vec<String> = violations.iter().map(describe).collect();
    assert!(
        violations.is_empty(),
        "{folder}: {} of the SRDF's skips are contradicted by Pinocchio + Coal ({}):\n{}",
        violations.len(),
        srdf.display(),
        lines.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// One violation on one line: the pair, its reason, what is wrong and where.
fn describe(v: &Value) -> String {
    let q = v["q"]
        .as_object()
        .map(|q| {
            q.iter()
                .map(|(j, x)| format!("{j}={:.4}", x.as_f64().unwrap_or(f64::NAN)))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_default();
    format!(
        "  {} / {} ({}): {} at configuration {} [{q}]",
        v["link1"].as_str().unwrap_or("?"),
        v["link2"].as_str().unwrap_or("?"),
        v["reason"].as_str().unwrap_or("?"),
        v["kind"].as_str().unwrap_or("?"),
        v["config"]
    )
}

#[test]
fn panda_skips_are_safe() {
    assert_safe_skips("panda");
}

#[test]
fn ur5e_skips_are_safe() {
    assert_safe_skips("ur5e");
}

#[test]
fn xarm7_skips_are_safe() {
    assert_safe_skips("xarm7");
}

#[test]
fn xarm7_gripper_skips_are_safe() {
    assert_safe_skips("xarm7_gripper");
}

#[test]
fn b1_skips_are_safe() {
    assert_safe_skips("b1");
}

#[test]
fn orca_hand_skips_are_safe() {
    assert_safe_skips("orca_hand");
}

#[test]
fn fanuc_skips_are_safe() {
    assert_safe_skips("fanuc");
}

//! The synthetic robot of scripts/make_synthetic_robot.py and `scm bench --scale` on it.

mod common;

use common::{python_with, scm, scratch};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Writes the synthetic robot with `args` into `out` and returns its URDF.
fn synthetic(python: &str, out: &Path, args: &[&str]) -> PathBuf {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/make_synthetic_robot.py");
    let o = Command::new(python)
        .arg(&script)
        .args(args)
        .arg("-o")
        .arg(out)
        .output()
        .expect("run python3");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    PathBuf::from(String::from_utf8_lossy(&o.stdout).trim())
}

/// Preprocesses `urdf` with at most `max_pieces` decomposition pieces a link.
fn preprocess(urdf: &Path, out: &Path, max_pieces: u32) -> scm::preprocess::PreprocessReport {
    let mut params = scm::shapes::ShapeParams::default();
    params.decomposition.max_pieces = max_pieces;
    let opts = scm::preprocess::PreprocessOptions {
        urdf: urdf.to_path_buf(),
        out: out.to_path_buf(),
        packages: scm::robot::PackagePaths::new(),
        visual_fallback: false,
        params,
        force: false,
    };
    scm::preprocess::preprocess(&opts, &scm::progress::NoProgress).expect("preprocess")
}

#[test]
fn the_synthetic_robot_has_the_asked_links_and_pieces() {
    let Some(python) = python_with(&["argparse"]) else {
        return;
    };
    let dir = scratch("synthetic");
    for (links, pieces, branches) in [(3, 2, 1), (10, 3, 1), (7, 2, 2)] {
        let args = [links, pieces, branches].map(|n: usize| n.to_string());
        let urdf = synthetic(
            python,
            &dir,
            &[
                "--links",
                &args[0],
                "--pieces",
                &args[1],
                "--branches",
                &args[2],
            ],
        );
        let again = std::fs::read(&urdf).unwrap();
        let out = dir.join(urdf.file_stem().unwrap());
        let r = preprocess(&urdf, &out, pieces as u32);
        assert_eq!((r.links, r.links_with_geometry), (links, links), "{r:?}");
        assert_eq!(r.dofs, links - 1);
        let urdd = scm::urdd::Urdd::open(&out).unwrap();
        let shapes = urdd.shapes(scm::shapes::ShapeType::DecompHull).unwrap();
        for link in 0..links {
            let n = shapes
                .shapes
                .iter()
                .filter(|s| s.link_index == link)
                .count();
            assert_eq!(n, pieces, "link {link} of {}", urdf.display());
        }
        // Deterministic: the same arguments write the same bytes.
        synthetic(
            python,
            &dir,
            &[
                "--links",
                &args[0],
                "--pieces",
                &args[1],
                "--branches",
                &args[2],
            ],
        );
        assert_eq!(std::fs::read(&urdf).unwrap(), again);
    }
}

#[test]
fn the_scale_table_measures_a_urdf_and_a_urdd() {
    let Some(python) = python_with(&["argparse"]) else {
        return;
    };
    let dir = scratch("scale");
    let urdf = synthetic(python, &dir, &["--links", "3", "--pieces", "2"]);
    let urdd = dir.join("preprocessed");
    preprocess(&urdf, &urdd, 2);
    let work = dir.join("work");
    let args: Vec<&OsStr> = vec![
        OsStr::new("--json"),
        OsStr::new("bench"),
        OsStr::new("--scale"),
        urdf.as_os_str(),
        urdd.as_os_str(),
        OsStr::new("-n"),
        OsStr::new("300"),
        OsStr::new("--runs"),
        OsStr::new("2"),
        OsStr::new("-o"),
        work.as_os_str(),
    ];
    let o = scm(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = report["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for row in rows {
        assert_eq!(row["robot"], "synthetic_n3_m2");
        assert_eq!(row["links"], 3);
        assert_eq!(row["dofs"], 2);
        assert_eq!(row["link_pairs"], 3);
        assert_eq!(row["runs"].as_array().unwrap().len(), 2);
        assert!(row["seconds"].as_f64().unwrap() > 0.0);
        if cfg!(target_os = "linux") {
            assert!(row["peak_bytes"].as_u64().unwrap() > 1_000_000, "{row}");
        }
    }
    // The URDD kept its two pieces a link; the URDF got the default decomposition, whatever it finds.
    assert_eq!(rows[1]["pieces"], 6);
    assert_eq!(rows[1]["piece_pairs"], 12);
    assert_eq!(
        rows[0]["urdd"].as_str().map(Path::new),
        Some(&*work.join("00"))
    );
    // Both were sampled with the asked count.
    for dir in [work.join("00"), urdd.clone()] {
        let u = scm::urdd::Urdd::open(&dir).unwrap();
        let f: scm::sample::SampleFile = u.sample_output("hull.json").unwrap().unwrap();
        assert_eq!(f.samples, 300);
    }

    // The markdown table: the command, one row per robot.
    let o = scm(&[
        OsStr::new("bench"),
        OsStr::new("--scale"),
        urdd.as_os_str(),
        OsStr::new("-n"),
        OsStr::new("100"),
        OsStr::new("-q"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("-n 100 --runs 1`"), "{text}");
    let row = text
        .lines()
        .find(|l| l.starts_with("| preprocessed | synthetic_n3_m2 |"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        row.starts_with("| preprocessed | synthetic_n3_m2 | 3 | 2 | 6 | 3 | 12 |"),
        "{row}"
    );
}

#[test]
fn bench_without_scale_takes_one_urdd() {
    let o = common::scm_str(&["bench", "a", "b"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--scale"));
    let o = common::scm_str(&["bench", "a", "--runs", "3"]);
    assert_eq!(o.status.code(), Some(2));
}

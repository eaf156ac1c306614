//! `scm import-moveit` and `scm diff` on the real robots' MoveIt SRDFs, and the SRDF round trip.

mod common;

use common::{preprocessed, robots_dir, sampled, scm_str, scratch};
use scm::export::{EXPORT, ExportOptions, Format, export};
use scm::matrix::{Layer, SkipMatrix};
use scm::progress::NoProgress;
use scm::shapes::ShapeType;
use scm::urdd::Urdd;
use std::collections::BTreeMap;
use std::path::Path;

/// The robots that ship a MoveIt SRDF: (folder, URDF, SRDF).
const WITH_SRDF: [(&str, &str, &str); 5] = [
    ("panda", "panda.urdf", "panda.srdf"),
    ("ur5e", "ur5e.urdf", "ur5e.srdf"),
    ("xarm7", "xarm7.urdf", "xarm7.srdf"),
    (
        "xarm7_gripper",
        "xarm7_with_gripper.urdf",
        "xarm7_with_gripper.srdf",
    ),
    ("fanuc", "fanuc.urdf", "fanuc.srdf"),
];

/// `reason="..."` counts of the `<disable_collisions>` lines, counted from the text itself.
fn reasons_in_text(srdf: &Path) -> BTreeMap<String, u64> {
    let text = std::fs::read_to_string(srdf).unwrap();
    let mut out = BTreeMap::new();
    for line in text.lines().filter(|l| l.contains("<disable_collisions")) {
        let reason = line
            .split("reason=\"")
            .nth(1)
            .and_then(|r| r.split('"').next())
            .unwrap_or("");
        *out.entry(reason.to_string()).or_insert(0) += 1;
    }
    out
}

fn import_json(srdf: &Path, dir: &Path) -> serde_json::Value {
    let out = scm_str(&[
        "import-moveit",
        srdf.to_str().unwrap(),
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap()["import"].clone()
}

#[test]
fn import_counts_per_reason_match_the_srdfs_with_warnings() {
    let Some(robots) = robots_dir() else { return };
    for (folder, urdf, srdf) in WITH_SRDF {
        let srdf = robots.join(folder).join(srdf);
        let dir = preprocessed(&robots.join(folder).join(urdf), &format!("import-{folder}"));
        let report = import_json(&srdf, &dir);
        let reasons: BTreeMap<String, u64> =
            serde_json::from_value(report["reasons"].clone()).unwrap();
        assert_eq!(reasons, reasons_in_text(&srdf), "{folder}");
        let warnings: Vec<String> = serde_json::from_value(report["warnings"].clone()).unwrap();
        match folder {
            "xarm7" => {
                let eef: Vec<&String> = warnings
                    .iter()
                    .filter(|w| w.contains("\"link_eef\" has no geometry"))
                    .collect();
                assert_eq!(eef.len(), 3, "{warnings:?}");
            }
            "xarm7_gripper" => {
                assert!(
                    warnings
                        .iter()
                        .any(|w| w.contains("\"link6\"") && w.contains("\"link7\"")),
                    "{warnings:?}"
                );
                // 71 distinct pairs in the file; the ones naming geometry-less links are not stored.
                let stored = report["stored"].as_u64().unwrap();
                assert!((50..71).contains(&stored), "{stored}");
            }
            _ => assert!(warnings.is_empty(), "{folder}: {warnings:?}"),
        }
    }
}

#[test]
fn imported_pairs_apply_to_every_shape_pair_of_the_two_links() {
    let Some(robots) = robots_dir() else { return };
    let dir = sampled(&robots.join("panda/panda.urdf"), "import-layer", 500);
    import_json(&robots.join("panda/panda.srdf"), &dir);
    let urdd = Urdd::open(&dir).unwrap();
    let m = SkipMatrix::load(&urdd, ShapeType::DecompHull).unwrap();
    let between = |a: &str, b: &str| {
        m.stats
            .iter()
            .zip(&m.entries)
            .filter(|(p, _)| {
                let (la, lb) = (&m.shapes[p.a].link, &m.shapes[p.b].link);
                (la == a && lb == b) || (la == b && lb == a)
            })
            .map(|(_, e)| e.clone())
            .collect::<Vec<_>>()
    };
    // The Panda SRDF disables panda_link0 - panda_link4 as Never.
    let entries = between("panda_link0", "panda_link4");
    assert!(!entries.is_empty());
    for e in entries {
        assert!(e.skip);
        assert_eq!((e.reason.as_str(), e.layer), ("Never", Layer::Imported));
    }
}

#[test]
fn srdf_round_trip_gives_identical_link_matrices() {
    let Some(robots) = robots_dir() else { return };
    let urdf = robots.join("ur5e/ur5e.urdf");
    let first = sampled(&urdf, "roundtrip-a", 1000);
    let mut opts = ExportOptions::new(&first);
    opts.formats = vec![Format::Srdf, Format::Matrices];
    let report = export(&opts, &NoProgress).unwrap();
    let name = report
        .files
        .iter()
        .find(|f| f.ends_with(".srdf"))
        .unwrap()
        .clone();
    let srdf = first.join(EXPORT).join(&name);

    let second = sampled(&urdf, "roundtrip-b", 1000);
    import_json(&srdf, &second);
    let mut opts2 = ExportOptions::new(&second);
    opts2.formats = vec![Format::Srdf, Format::Matrices];
    export(&opts2, &NoProgress).unwrap();

    let skip = |dir: &Path| {
        let v: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(EXPORT).join("matrices/hull.json")).unwrap(),
        )
        .unwrap();
        v["skip"].clone()
    };
    assert_eq!(skip(&first), skip(&second));
    // The same elements; only the comments saying what decided each pair differ (`mesh, certified`
    // in the first, `imported` in the second).
    let elements = |path: &Path| -> Vec<String> {
        std::fs::read_to_string(path)
            .unwrap()
            .lines()
            .map(|l| {
                l.split("<!--")
                    .next()
                    .unwrap_or_default()
                    .trim_end()
                    .to_string()
            })
            .collect()
    };
    assert_eq!(elements(&srdf), elements(&second.join(EXPORT).join(&name)));
    let again = std::fs::read_to_string(second.join(EXPORT).join(&name)).unwrap();
    assert!(
        again.contains("reason=\"Never\"/> <!-- imported -->"),
        "{again}"
    );
    // The second URDD's link pairs now come from the imported layer.
    let m = SkipMatrix::load(&Urdd::open(&second).unwrap(), ShapeType::Hull).unwrap();
    assert!(
        m.link_pairs()
            .iter()
            .any(|p| p.entry.layer == Layer::Imported)
    );
}

#[test]
fn diff_lists_disagreements_with_evidence() {
    let Some(robots) = robots_dir() else { return };
    let dir = sampled(&robots.join("panda/panda.urdf"), "diff-panda", 2000);
    let srdf = robots.join("panda/panda.srdf");
    let out = scm_str(&[
        "diff",
        dir.to_str().unwrap(),
        "--srdf",
        srdf.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // scm's verdicts are the exported files': the exact geometry's.
    let urdd = Urdd::open(&dir).unwrap();
    let m = SkipMatrix::load(&urdd, ShapeType::Hull).unwrap();
    let mesh = scm::sample::load_mesh_file(&urdd).unwrap().unwrap();
    let scm_verdict: BTreeMap<(String, String), bool> =
        scm::matrix::consumer_link_pairs(m.link_pairs(), &mesh, false)
            .into_iter()
            .map(|p| ((p.link1, p.link2), p.entry.skip))
            .collect();
    let text = std::fs::read_to_string(&srdf).unwrap();
    let moveit = scm::formats::srdf::parse_srdf(&text, &srdf).unwrap();
    let moveit_skips = |a: &str, b: &str| {
        moveit
            .disabled
            .iter()
            .any(|p| (p.link1 == a && p.link2 == b) || (p.link1 == b && p.link2 == a))
    };
    let mut expected = (0, 0);
    for ((a, b), skip) in &scm_verdict {
        match (moveit_skips(a, b), skip) {
            (true, false) => expected.0 += 1,
            (false, true) => expected.1 += 1,
            _ => {}
        }
    }
    let listed_a = v["moveit_skips_scm_checks"].as_array().unwrap();
    let listed_b = v["scm_skips_moveit_checks"].as_array().unwrap();
    assert_eq!((listed_a.len(), listed_b.len()), expected);
    let dofs = urdd.robot().unwrap().dofs.len();
    for d in listed_a {
        assert_eq!(d["scm"], "checked");
        assert_eq!(d["geometry"], "mesh");
        // Evidence: the configuration behind scm's verdict, with a value for every DOF.
        assert_eq!(d["witness"].as_array().unwrap().len(), dofs);
    }
    // MoveIt's shipped panda SRDF disables a pair whose exact geometry collides: scm shows where.
    assert!(
        listed_a
            .iter()
            .any(|d| d["witness_kind"] == "exact geometry overlaps"),
        "{listed_a:?}"
    );
    for d in listed_b {
        if d["scm"] == "never" {
            assert!(
                d["evidence"] == "certified" || d["evidence"] == "sampled",
                "{d}"
            );
        }
    }
    // Text mode names both sections.
    let text = scm_str(&[
        "diff",
        dir.to_str().unwrap(),
        "--srdf",
        srdf.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("MoveIt skips, scm checks:") && text.contains("scm skips, MoveIt checks:")
    );
}

#[test]
fn bad_srdf_input_is_one_line_and_exit_2() {
    let dir = preprocessed(&common::demo_urdf(), "import-bad");
    let bad = scratch("bad-srdf").join("bad.srdf");
    std::fs::write(
        &bad,
        "<robot name=\"demo_arm\">\n  <disable_collisions link1=\"a\"\n",
    )
    .unwrap();
    let out = scm_str(&[
        "import-moveit",
        bad.to_str().unwrap(),
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.srdf: line 3"), "{err}");

    std::fs::write(
        &bad,
        "<robot name=\"demo_arm\">\n  <disable_collisions link1=\"link1\"/>\n</robot>\n",
    )
    .unwrap();
    let out = scm_str(&[
        "import-moveit",
        bad.to_str().unwrap(),
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("line 2") && err.contains("link2"), "{err}");
    assert!(!dir.join("layers").exists(), "nothing written on bad input");
}

#[test]
fn an_import_is_a_manifest_record_with_the_srdf_hash_and_a_stamped_layer() {
    let Some(robots) = robots_dir() else { return };
    let dir = preprocessed(&robots.join("panda/panda.urdf"), "import-record");
    let srdf = robots.join("panda/panda.srdf");
    import_json(&srdf, &dir);
    let urdd = Urdd::open(&dir).unwrap();
    let record = urdd
        .fresh_stage(scm::urdd::IMPORT)
        .expect("a current import record");
    let hash = scm::urdd::sha256_hex(&std::fs::read(&srdf).unwrap());
    assert_eq!(record.inputs.len(), 1);
    assert_eq!(
        (record.inputs[0].role.as_str(), &record.inputs[0].sha256),
        ("srdf", &hash)
    );
    assert_eq!(record.outputs, vec!["imported.json".to_string()]);
    assert_eq!(record.summary["stored"], 34);
    let preprocess = urdd.stage(scm::urdd::PREPROCESS).unwrap().key.clone();
    assert_eq!(record.depends_on.get("preprocess"), Some(&preprocess));
    // A hand-edited layer no longer matches its stamp.
    std::fs::write(dir.join("layers/imported.json"), b"{}").unwrap();
    let changes = Urdd::open(&dir).unwrap().output_changes(scm::urdd::IMPORT);
    assert!(
        changes.iter().any(|c| c.contains("imported.json")),
        "{changes:?}"
    );
}

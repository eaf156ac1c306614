//! `scm export`: the six matrix files (snapshots), the consumer files loaded by the real consumers
//! (Pinocchio, MuJoCo), SRDF merging, layers, staleness and bad input.

mod common;

use common::{demo_urdf, robots_dir, run_consumer, sampled, scm_str, scratch};
use scm::export::{EXPORT, ExportOptions, ExportReport, export};
use scm::formats::matrices::MatrixFile;
use scm::matrix::{Layer, ShapeKey, SkipMatrix, UserLayer};
use scm::progress::NoProgress;
use scm::shapes::ShapeType;
use scm::urdd::Urdd;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn exported(dir: &Path) -> ExportReport {
    export(&ExportOptions::new(dir), &NoProgress).unwrap_or_else(|e| panic!("export: {e}"))
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The demo arm sampled once per test binary (2,000 samples), exported with every format.
fn demo() -> &'static PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let dir = sampled(&demo_urdf(), "export-demo", 2000);
        exported(&dir);
        dir
    })
}

#[test]
fn demo_exports_snapshot() {
    let out = demo().join(EXPORT);
    insta::assert_snapshot!("demo_hull_json", read(&out.join("matrices/hull.json")));
    insta::assert_snapshot!("demo_hull_yaml", read(&out.join("matrices/hull.yaml")));
    insta::assert_snapshot!("demo_srdf", read(&out.join("demo_arm.srdf")));
    insta::assert_snapshot!("demo_mjcf", read(&out.join("demo_arm.mjcf-excludes.xml")));
    insta::assert_snapshot!("demo_curobo", read(&out.join("demo_arm.curobo.yml")));
    insta::assert_snapshot!("demo_drake", read(&out.join("demo_arm.drake-filters.xml")));
    insta::assert_snapshot!(
        "demo_heatmap_links_svg",
        read(&out.join("heatmaps/links.svg"))
    );
    insta::assert_snapshot!(
        "demo_heatmap_decomp_hull_svg",
        read(&out.join("heatmaps/decomp-hull.svg"))
    );
}

/// The pairs an SVG heat map draws as skipped, from the cells' hover text (`a - b: skip: ...`),
/// sorted by name within each pair, and how many cells it draws.
fn svg_skipped_pairs(text: &str) -> (BTreeSet<(String, String)>, usize) {
    let mut skipped = BTreeSet::new();
    let mut cells = 0;
    for title in text.split("<title>").skip(1) {
        let title = title.split("</title>").next().unwrap_or_default();
        let (pair, verdict) = title.split_once(": ").expect("pair: verdict");
        let (a, b) = pair.split_once(" - ").expect("a - b");
        cells += 1;
        if verdict.starts_with("skip") {
            let (a, b) = (a.to_string(), b.to_string());
            skipped.insert(if a <= b { (a, b) } else { (b, a) });
        }
    }
    (skipped, cells)
}

#[test]
fn svg_heat_maps_draw_the_exported_verdicts_for_every_type() {
    let dir = demo();
    let out = dir.join(EXPORT);
    // The link-level map shows exactly the SRDF's disabled pairs as skips, each pair on both sides
    // of the diagonal.
    let srdf = srdf_pairs(&read(&out.join("demo_arm.srdf")));
    let (skipped, cells) = svg_skipped_pairs(&read(&out.join("heatmaps/links.svg")));
    assert_eq!(skipped, srdf);
    let urdd = Urdd::open(dir).unwrap();
    let hull = SkipMatrix::load(&urdd, ShapeType::Hull).unwrap();
    assert_eq!(cells, 2 * hull.link_pairs().len());
    assert!(read(&out.join("heatmaps/links.svg")).contains("never, certified"));
    // One map per sampled type, its skips the type's link-level skips.
    for t in ShapeType::ALL {
        let m = SkipMatrix::load(&urdd, t).unwrap();
        let (skipped, _) = svg_skipped_pairs(&read(&out.join(format!("heatmaps/{t}.svg"))));
        let expected: BTreeSet<(String, String)> = m
            .link_pairs()
            .into_iter()
            .filter(|p| p.entry.skip)
            .map(|p| {
                let (a, b) = (p.link1, p.link2);
                if a <= b { (a, b) } else { (b, a) }
            })
            .collect();
        assert_eq!(skipped, expected, "{t}");
    }
}

#[test]
fn matrix_files_are_consistent_in_both_encodings() {
    let out = demo().join(EXPORT);
    let urdd = Urdd::open(demo()).unwrap();
    for t in ShapeType::ALL {
        let json: MatrixFile = serde_json::from_str(&read(&out.join(format!("matrices/{t}.json"))))
            .unwrap_or_else(|e| panic!("{t} json: {e}"));
        let yaml: MatrixFile =
            serde_saphyr::from_str(&read(&out.join(format!("matrices/{t}.yaml"))))
                .unwrap_or_else(|e| panic!("{t} yaml: {e}"));
        assert_eq!(json, yaml, "{t}: JSON and YAML differ");
        let n = urdd.shapes(t).unwrap().shapes.len();
        assert_eq!(json.shapes.len(), n, "{t}");
        assert_eq!(json.skip.len(), n, "{t}");
        assert_eq!(json.pairs.len(), n * (n - 1) / 2, "{t}");
        for p in &json.pairs {
            assert_eq!(json.skip[p.0.a].0[p.0.b], p.0.skip, "{t}: matrix vs pair");
            assert_eq!(json.skip[p.0.b].0[p.0.a], p.0.skip, "{t}: not symmetric");
            // d_min and d_max carry the sampling tolerance; d_mean is exact.
            let tol = scm::sample::DEFAULT_TOLERANCE + 1e-9;
            assert!(
                p.0.d_min <= p.0.d_mean + tol && p.0.d_mean <= p.0.d_max + tol,
                "{t}"
            );
        }
        assert!((0..n).all(|i| json.skip[i].0[i]), "{t}: diagonal");
    }
    for module in [
        "link_shapes_skips_module",
        "link_shapes_distance_statistics_module",
    ] {
        for file in ["VERSION", "module.json", "module.yaml"] {
            assert!(out.join(module).join(file).is_file(), "{module}/{file}");
        }
    }
    let skips: serde_json::Value =
        serde_json::from_str(&read(&out.join("link_shapes_skips_module/module.json"))).unwrap();
    let hull = urdd.shapes(ShapeType::Hull).unwrap().shapes.len();
    assert_eq!(
        skips["full_convex_hulls_skips"].as_array().unwrap().len(),
        hull
    );
}

#[test]
fn rerun_is_a_no_op_and_user_edits_rerun_the_export() {
    let dir = sampled(&demo_urdf(), "export-layers", 1000);
    exported(&dir);
    let index = dir.join(EXPORT).join("export.json");
    let before = std::fs::metadata(&index).unwrap().modified().unwrap();
    assert!(exported(&dir).up_to_date);
    assert_eq!(
        std::fs::metadata(&index).unwrap().modified().unwrap(),
        before
    );

    // Mark one inferred `never` hull pair as checked: the export reruns and shows the user layer.
    let urdd = Urdd::open(&dir).unwrap();
    let m = SkipMatrix::load(&urdd, ShapeType::Hull).unwrap();
    let k = m.entries.iter().position(|e| e.reason == "never").unwrap();
    let (a, b) = (m.stats[k].a, m.stats[k].b);
    let mut user = UserLayer::load(&urdd).unwrap();
    user.set(ShapeType::Hull, m.key(b), m.key(a), false);
    user.save(&urdd).unwrap();
    let report = exported(&dir);
    assert!(!report.up_to_date);
    let file: MatrixFile =
        serde_json::from_str(&read(&dir.join(EXPORT).join("matrices/hull.json"))).unwrap();
    let pair = &file.pairs[k].0;
    assert_eq!((pair.a, pair.b, pair.skip), (a, b, false));
    assert_eq!((pair.reason.as_str(), pair.layer), ("user", Layer::User));
    assert!(!file.skip[a].0[b]);
    // The edit names shapes by link and piece, in either order.
    assert_eq!(
        user.get(
            ShapeType::Hull,
            &ShapeKey {
                link: m.shapes[a].link.clone(),
                piece: 0
            },
            &m.key(b)
        ),
        Some(false)
    );
}

#[test]
fn export_refuses_stale_or_missing_sampling_and_writes_nothing() {
    // Preprocessed only: no sampling.
    let dir = common::preprocessed(&demo_urdf(), "export-nosample");
    let out = scm_str(&["export", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("stage \"sample\"") && err.contains("scm sample"),
        "{err}"
    );
    assert!(!dir.join(EXPORT).exists());

    // Sampled, exported, then preprocessed again with other parameters: sampling is stale.
    let dir = sampled(&demo_urdf(), "export-stale", 500);
    exported(&dir);
    let before = read(&dir.join(EXPORT).join("demo_arm.srdf"));
    let pre = scm_str(&[
        "preprocess",
        demo_urdf().to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
        "--max-hull-vertices",
        "64",
        "-q",
    ]);
    assert!(pre.status.success());
    let out = scm_str(&["export", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("stale") && err.contains("scm sample"), "{err}");
    assert_eq!(read(&dir.join(EXPORT).join("demo_arm.srdf")), before);

    // A folder that exists, is not empty and is not an export is not replaced.
    let foreign = scratch("export-foreign");
    std::fs::write(foreign.join("notes.txt"), "mine").unwrap();
    let dir = demo();
    let out = scm_str(&[
        "export",
        dir.to_str().unwrap(),
        "-o",
        foreign.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(read(&foreign.join("notes.txt")), "mine");
}

#[test]
fn merge_into_keeps_everything_but_disable_collisions() {
    let Some(robots) = robots_dir() else { return };
    let urdf = robots.join("panda/panda.urdf");
    let srdf = robots.join("panda/panda.srdf");
    let dir = sampled(&urdf, "export-merge", 1000);
    let mut opts = ExportOptions::new(&dir);
    opts.formats = vec![scm::export::Format::Srdf];
    opts.merge_into = Some(srdf.clone());
    export(&opts, &NoProgress).unwrap();
    let merged = read(&dir.join(EXPORT).join("panda.srdf"));
    let without = |text: &str| -> Vec<String> {
        text.lines()
            .filter(|l| !l.contains("<disable_collisions"))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(without(&merged), without(&read(&srdf)));
    let ours = read(&dir.join(EXPORT).join("panda.srdf"));
    let disabled = ours.matches("<disable_collisions").count();
    let m = SkipMatrix::load(&Urdd::open(&dir).unwrap(), ShapeType::Hull).unwrap();
    let skipped = m.link_pairs().iter().filter(|p| p.entry.skip).count();
    assert_eq!(disabled, skipped);
}

/// Exported link pairs `(link1, link2)` of an SRDF, sorted by name within each pair.
fn srdf_pairs(text: &str) -> BTreeSet<(String, String)> {
    let srdf = scm::formats::srdf::parse_srdf(text, Path::new("x.srdf")).unwrap();
    srdf.disabled
        .iter()
        .map(|p| {
            let (a, b) = (p.link1.clone(), p.link2.clone());
            if a <= b { (a, b) } else { (b, a) }
        })
        .collect()
}

fn json_pairs(v: &serde_json::Value) -> BTreeSet<(String, String)> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p[0].as_str().unwrap().to_string(),
                p[1].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

#[test]
fn panda_srdf_loads_in_pinocchio_and_removes_exactly_the_exported_pairs() {
    let Some(robots) = robots_dir() else { return };
    let Some(python) = common::python_with(&["pinocchio"]) else {
        return;
    };
    let urdf = robots.join("panda/panda.urdf");
    let dir = sampled(&urdf, "export-pinocchio", 2000);
    exported(&dir);
    let srdf = dir.join(EXPORT).join("panda.srdf");
    let exported_pairs = srdf_pairs(&read(&srdf));
    assert!(!exported_pairs.is_empty());
    let v = run_consumer(
        python,
        "check_pinocchio.py",
        &[&urdf, &robots.join("panda"), &srdf],
    );
    let (before, after) = (json_pairs(&v["before"]), json_pairs(&v["after"]));
    let removed: BTreeSet<_> = before.difference(&after).cloned().collect();
    let expected: BTreeSet<_> = exported_pairs.intersection(&before).cloned().collect();
    assert_eq!(removed, expected);
    assert!(after.is_disjoint(&exported_pairs));
    assert!(removed.len() >= 30, "only {} pairs removed", removed.len());
}

#[test]
fn mjcf_excludes_compile_in_mujoco() {
    let Some(robots) = robots_dir() else { return };
    let Some(python) = common::python_with(&["mujoco"]) else {
        return;
    };
    // The demo arm has a link fused into its parent by MuJoCo (shoulder_stop, fixed to link1).
    for (folder, urdf) in [
        ("demo", demo_urdf()),
        ("panda", robots.join("panda/panda.urdf")),
        ("ur5e", robots.join("ur5e/ur5e.urdf")),
        ("xarm7", robots.join("xarm7/xarm7.urdf")),
    ] {
        let dir = sampled(&urdf, &format!("export-mjcf-{folder}"), 1000);
        let report = exported(&dir);
        let name = report
            .files
            .iter()
            .find(|f| f.ends_with(".mjcf-excludes.xml"))
            .unwrap();
        let v = run_consumer(
            python,
            "check_mujoco.py",
            &[&urdf, &dir.join(EXPORT).join(name)],
        );
        let wanted = json_pairs(&v["wanted"]);
        assert!(!wanted.is_empty(), "{folder}: no excludes");
        assert_eq!(json_pairs(&v["got"]), wanted, "{folder}");
        assert_eq!(
            v["nexclude"].as_u64(),
            Some(wanted.len() as u64),
            "{folder}"
        );
    }
}

#[test]
fn drake_filter_groups_load_in_drake_and_filter_exactly_the_exported_pairs() {
    let Some(robots) = robots_dir() else { return };
    let Some(python) = common::python_with(&["pydrake"]) else {
        return;
    };
    for (name, urdf) in [
        ("demo", demo_urdf()),
        ("panda", robots.join("panda/panda.urdf")),
    ] {
        let dir = sampled(&urdf, &format!("export-drake-{name}"), 1000);
        let report = exported(&dir);
        let file = |suffix: &str| {
            dir.join(EXPORT)
                .join(report.files.iter().find(|f| f.ends_with(suffix)).unwrap())
        };
        let exported_pairs = srdf_pairs(&read(&file(".srdf")));
        let v = run_consumer(
            python,
            "check_drake.py",
            &[&urdf, &file(".drake-filters.xml")],
        );
        // Drake filters joined and welded bodies itself; the groups add exactly the exported pairs.
        let expected: BTreeSet<_> = exported_pairs
            .union(&json_pairs(&v["without"]))
            .cloned()
            .collect();
        assert_eq!(json_pairs(&v["with"]), expected, "{name}");
    }
}

/// With a certificate budget too small to prove anything, every `never` is only sampled: the files say
/// so per pair, and `--require-certified` keeps those pairs checked.
#[test]
fn require_certified_keeps_sampled_nevers_checked() {
    let dir = common::preprocessed(&demo_urdf(), "export-uncertified");
    let o = scm_str(&[
        "sample",
        dir.to_str().unwrap(),
        "-n",
        "500",
        "--types",
        "hull",
        "--certify-boxes",
        "1",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let export_with = |extra: &[&str], out: &str| -> (serde_json::Value, String) {
        let out = scratch(out);
        let mut args = vec![
            "export",
            dir.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--format",
            "srdf",
            "--json",
        ];
        args.extend_from_slice(extra);
        let o = scm_str(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let srdf = read(&out.join("demo_arm.srdf"));
        (serde_json::from_slice(&o.stdout).unwrap(), srdf)
    };
    let (plain, srdf) = export_with(&[], "uncertified-plain");
    let sampled_nevers = plain["link_reasons"]["never-sampled"].as_u64().unwrap();
    assert!(sampled_nevers > 0, "{plain}");
    assert_eq!(
        srdf.matches("<!-- mesh, sampled -->").count() as u64,
        sampled_nevers
    );
    let (strict, srdf) = export_with(&["--require-certified"], "uncertified-strict");
    assert_eq!(
        strict["link_reasons"]["never-kept-checked"].as_u64(),
        Some(sampled_nevers)
    );
    assert_eq!(
        strict["link_pairs"][0].as_u64().unwrap() + sampled_nevers,
        plain["link_pairs"][0].as_u64().unwrap()
    );
    assert!(!srdf.contains("sampled -->"), "{srdf}");
}

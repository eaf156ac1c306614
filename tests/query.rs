//! The query API against brute force over every pair, a known colliding configuration, and `scm bench`
//! (its files and its errors), on UR5e sampled briefly.

mod common;

use scm::bench::{BenchOptions, bench};
use scm::collision::signed_distance;
use scm::progress::NoProgress;
use scm::query::{SelfChecker, SkipMode};
use scm::robot::Kinematics;
use scm::sample::{Reason, SampleFile, SampleOptions, sample};
use scm::shapes::ShapeType;
use scm::urdd::Urdd;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const TYPES: [ShapeType; 3] = [ShapeType::Hull, ShapeType::Obb, ShapeType::DecompSphere];

/// UR5e preprocessed and sampled (2,000 samples) for [`TYPES`], shared by the tests of this file.
fn ur5e() -> Option<&'static Path> {
    static DIR: OnceLock<Option<PathBuf>> = OnceLock::new();
    DIR.get_or_init(|| {
        let robots = common::robots_dir()?;
        let out = common::preprocessed(&robots.join("ur5e/ur5e.urdf"), "query-ur5e");
        let mut opts = SampleOptions::new(&out);
        opts.samples = 2000;
        opts.types = TYPES.to_vec();
        sample(&opts, &NoProgress).unwrap();
        Some(out)
    })
    .as_deref()
}

/// Deterministic joint values within the limits.
fn configurations(checker: &SelfChecker, n: usize) -> Vec<Vec<f64>> {
    let mut s = 0x1234_5678u64;
    let mut unit = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            checker
                .dofs()
                .iter()
                .map(|d| d.lower + (d.upper - d.lower) * unit())
                .collect()
        })
        .collect()
}

/// Exact signed distance of every pair `a < b` (row-major), no culling, straight from the shapes.
fn brute_force(urdd: &Urdd, t: ShapeType, q: &[f64]) -> Vec<((usize, usize), f64)> {
    let robot = urdd.robot().unwrap().robot;
    let set = urdd.collision_shapes(t, robot.links.len()).unwrap();
    let poses = Kinematics::new(&robot).link_poses(q);
    let n = set.shapes.len();
    let mut out = Vec::new();
    for a in 0..n {
        for b in a + 1..n {
            let (sa, sb) = (&set.shapes[a], &set.shapes[b]);
            let d = signed_distance(
                sa,
                &sa.pose(&poses[set.links[a]]),
                sb,
                &sb.pose(&poses[set.links[b]]),
            );
            out.push(((a, b), d));
        }
    }
    out
}

fn sample_file(dir: &Path, t: ShapeType) -> SampleFile {
    scm::urdd::read_json_file(&dir.join("sample").join(format!("{}.json", t.id()))).unwrap()
}

#[test]
fn queries_match_brute_force_with_and_without_skips() {
    let Some(dir) = ur5e() else { return };
    let urdd = Urdd::open(dir).unwrap();
    for t in TYPES {
        let reasons = sample_file(dir, t).pairs;
        for mode in [SkipMode::NoSkips, SkipMode::Skips] {
            let checker = SelfChecker::load(&urdd, t, mode).unwrap();
            let mut scratch = checker.scratch();
            let mut seen_collision = false;
            for q in configurations(&checker, 150) {
                let reference: Vec<((usize, usize), f64)> = brute_force(&urdd, t, &q)
                    .into_iter()
                    .zip(&reasons)
                    .filter(|(_, r)| mode == SkipMode::NoSkips || r.reason == Reason::Checked)
                    .map(|(p, _)| p)
                    .collect();
                let colliding: Vec<(usize, usize)> = reference
                    .iter()
                    .filter(|(_, d)| *d <= 0.0)
                    .map(|(p, _)| *p)
                    .collect();
                let report = checker.collisions(&q, &mut scratch).unwrap();
                let got: Vec<(usize, usize)> = report.pairs.iter().map(|p| (p.a, p.b)).collect();
                assert_eq!(got, colliding, "{t} {mode:?} at {q:?}");
                assert_eq!(
                    checker.in_collision(&q, &mut scratch).unwrap(),
                    !colliding.is_empty()
                );
                seen_collision |= !colliding.is_empty();
                let min = reference
                    .iter()
                    .map(|(_, d)| *d)
                    .fold(f64::INFINITY, f64::min);
                let near = checker.min_distance(&q, &mut scratch).unwrap().unwrap();
                assert_eq!(near.distance, min, "{t} {mode:?} at {q:?}");
                let of_pair = reference
                    .iter()
                    .find(|(p, _)| *p == (near.pair.a, near.pair.b))
                    .unwrap()
                    .1;
                assert_eq!(of_pair, min);
                if near.distance > 1e-6 {
                    // Witness points lie `distance` apart.
                    let gap = near.points[0].distance(near.points[1]);
                    assert!(
                        (gap - near.distance).abs() < 1e-6,
                        "{gap} vs {}",
                        near.distance
                    );
                }
            }
            if mode == SkipMode::NoSkips {
                // Adjacent shapes touch at their joints: without skips collisions must occur.
                assert!(seen_collision, "{t}: no collision without skips");
            }
        }
    }
}

#[test]
fn pair_distance_of_any_pair_matches_brute_force_even_when_skipped() {
    let Some(dir) = ur5e() else { return };
    let urdd = Urdd::open(dir).unwrap();
    let checker = SelfChecker::load(&urdd, ShapeType::Hull, SkipMode::Skips).unwrap();
    let mut scratch = checker.scratch();
    for q in configurations(&checker, 20) {
        for ((a, b), d) in brute_force(&urdd, ShapeType::Hull, &q) {
            let (got, points) = checker.pair_distance(&q, b, a, &mut scratch).unwrap();
            assert_eq!(got, d, "pair {a}-{b} at {q:?}");
            if d > 1e-6 {
                assert!((points[0].distance(points[1]) - d).abs() < 1e-6);
            }
        }
    }
    assert!(
        checker
            .pair_distance(&checker.home(), 0, 0, &mut scratch)
            .is_err()
    );
}

#[test]
fn a_sampled_collision_is_reported_with_its_pair() {
    let Some(dir) = ur5e() else { return };
    let urdd = Urdd::open(dir).unwrap();
    let t = ShapeType::Hull;
    let file = sample_file(dir, t);
    let checker = SelfChecker::load(&urdd, t, SkipMode::Skips).unwrap();
    let mut scratch = checker.scratch();
    let witnessed: Vec<_> = file
        .pairs
        .iter()
        .filter(|p| p.reason == Reason::Checked && p.d_min < -1e-3)
        .collect();
    assert!(
        !witnessed.is_empty(),
        "UR5e hulls have checked pairs that collide"
    );
    for p in witnessed {
        let report = checker.collisions(&p.witness.q, &mut scratch).unwrap();
        let found = report.pairs.iter().find(|r| (r.a, r.b) == (p.a, p.b));
        let found = found.unwrap_or_else(|| panic!("pair {} {} not reported", p.a, p.b));
        assert_eq!(found.link_a, checker.shapes()[p.a].link);
        assert!(checker.in_collision(&p.witness.q, &mut scratch).unwrap());
        let near = checker
            .min_distance(&p.witness.q, &mut scratch)
            .unwrap()
            .unwrap();
        assert!(
            near.distance <= p.d_min + 1e-4,
            "{} > {}",
            near.distance,
            p.d_min
        );
    }
}

#[test]
fn a_configuration_of_the_wrong_length_is_an_error() {
    let Some(dir) = ur5e() else { return };
    let urdd = Urdd::open(dir).unwrap();
    let checker = SelfChecker::load(&urdd, ShapeType::Hull, SkipMode::Skips).unwrap();
    let mut scratch = checker.scratch();
    let err = checker.in_collision(&[0.0; 3], &mut scratch).unwrap_err();
    assert_eq!(err.exit_code(), 2);
    assert!(err.to_string().contains("expected 6"), "{err}");
    let mut q = checker.home();
    q[2] = f64::NAN;
    assert!(checker.min_distance(&q, &mut scratch).is_err());
}

#[test]
fn bench_writes_the_tables() {
    let Some(dir) = ur5e() else { return };
    let mut opts = BenchOptions::new(dir);
    opts.configs = 100;
    opts.repeats = 2;
    opts.truth_configs = 100;
    let report = bench(&opts, &NoProgress).unwrap();
    let types: Vec<ShapeType> = report.types.iter().map(|t| t.shape_type).collect();
    let mut sampled = TYPES.to_vec();
    sampled.sort();
    assert_eq!(types, sampled, "default: every sampled type, in order");
    let json: serde_json::Value = scm::urdd::read_json_file(&dir.join("bench/bench.json")).unwrap();
    assert_eq!(json["types"].as_array().unwrap().len(), 3);
    for t in &report.types {
        assert!(t.collisions.ratio_mean > 0.0 && t.proximity.skips_us > 0.0);
        assert!(
            t.checked < t.pairs,
            "{}: skips leave pairs out",
            t.shape_type
        );
        assert_eq!(t.accuracy.configs, 100);
        // Hulls contain the link meshes: with nothing skipped they would report every mesh
        // collision, so all their misses come from skips.
        if t.shape_type == ShapeType::Hull {
            assert_eq!(t.accuracy.missed_by_shapes, 0);
        }
    }
    let md = std::fs::read_to_string(dir.join("bench/bench.md")).unwrap();
    for t in &report.types {
        // One row in the timing table and one in the accuracy table.
        let rows = md
            .lines()
            .filter(|l| l.starts_with(&format!("| {} |", t.shape_type)))
            .count();
        assert_eq!(rows, 2, "{}:\n{md}", t.shape_type);
    }
    let manifest = Urdd::open(dir).unwrap();
    assert!(manifest.stage("bench").is_ok());
}

/// Runs `scm bench` and returns (exit code, stderr).
fn bench_cli(args: &[&str]) -> (i32, String) {
    let out = common::scm_str(&[&["bench", "--quiet"], args].concat());
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn bad_bench_input_is_one_line_and_exit_2() {
    let unsampled = common::preprocessed(&common::demo_urdf(), "bench-unsampled");
    let (code, err) = bench_cli(&[unsampled.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("sample"), "{err}");

    let Some(dir) = ur5e() else { return };
    let dir = dir.to_str().unwrap();
    let (code, err) = bench_cli(&[dir, "--types", "hull,cylinder"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("cylinder"), "{err}");

    // A type that was not sampled.
    let (code, err) = bench_cli(&[dir, "--types", "decomp-hull"]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("not sampled"), "{err}");
}

#[test]
fn table_3_attributes_hidden_collisions_to_their_skip_reason() {
    // The demo arm's designed pairs: link2 / shoulder_stop collide except near joint2 = 0 (`always`);
    // link1 / link3 and the closed fingers are in contact at home (`default`, design contacts).
    let dir = common::preprocessed(&common::demo_urdf(), "bench-demo");
    let mut opts = SampleOptions::new(&dir);
    opts.samples = 2000;
    opts.types = vec![ShapeType::Hull];
    sample(&opts, &NoProgress).unwrap();
    let mut opts = BenchOptions::new(&dir);
    opts.configs = 20;
    opts.repeats = 1;
    opts.truth_configs = 200;
    let report = bench(&opts, &NoProgress).unwrap();
    let left_out = |a: &str, b: &str| {
        report
            .truth_at_home
            .iter()
            .any(|[x, y]| (x == a && y == b) || (x == b && y == a))
    };
    assert!(left_out("link1", "link3"), "{:?}", report.truth_at_home);
    assert!(left_out("finger_left", "finger_right"));
    assert!(!left_out("link2", "shoulder_stop"), "clear at home");
    let a = &report.types[0].accuracy;
    let always = a.hidden["always"];
    assert!(
        always >= 150,
        "link2 / shoulder_stop meshes collide in most configurations: {a:?}"
    );
    assert!(a.mesh_collisions >= always && a.false_negatives <= always);
    assert_eq!(a.missed_by_shapes, 0, "hulls contain the meshes");
}

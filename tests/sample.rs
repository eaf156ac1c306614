//! `scm sample`: reasons on hand-checkable robots, MoveIt's adjacency on Panda, determinism across
//! threads and shards, the targeted search, and clear errors on broken URDDs.

mod common;

use scm::progress::NoProgress;
use scm::sample::{Reason, SampleFile, SampleOptions, sample};
use scm::shapes::ShapeType;
use scm::urdd::Urdd;
use std::collections::BTreeSet;
use std::path::Path;
use std::process::Output;

fn read_sample(dir: &Path, t: ShapeType) -> SampleFile {
    scm::urdd::read_json_file(&dir.join("sample").join(format!("{}.json", t.id()))).unwrap()
}

/// `(link a, link b) -> reason` for a whole-link type.
fn reasons_by_link(dir: &Path, t: ShapeType) -> Vec<((String, String), Reason, f64)> {
    let urdd = Urdd::open(dir).unwrap();
    let shapes = urdd.shapes(t).unwrap().shapes;
    read_sample(dir, t)
        .pairs
        .into_iter()
        .map(|p| {
            (
                (shapes[p.a].link.clone(), shapes[p.b].link.clone()),
                p.reason,
                p.collision_fraction,
            )
        })
        .collect()
}

#[test]
fn panda_adjacent_pairs_match_moveit() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    let dir = robots.join("panda");
    let out = common::preprocessed(&dir.join("panda.urdf"), "panda-adj");
    let record = Urdd::open(&out).unwrap().robot().unwrap();
    let ours: BTreeSet<(String, String)> = record
        .adjacent
        .iter()
        .map(|[a, b]| (a.clone().min(b.clone()), a.clone().max(b.clone())))
        .collect();
    let srdf = std::fs::read_to_string(dir.join("panda.srdf")).unwrap();
    let doc = roxmltree::Document::parse(&srdf).unwrap();
    let moveit: BTreeSet<(String, String)> = doc
        .descendants()
        .filter(|n| {
            n.has_tag_name("disable_collisions") && n.attribute("reason") == Some("Adjacent")
        })
        .map(|n| {
            let (a, b) = (
                n.attribute("link1").unwrap().to_string(),
                n.attribute("link2").unwrap().to_string(),
            );
            (a.clone().min(b.clone()), a.max(b))
        })
        .collect();
    assert_eq!(ours, moveit);
}

#[test]
fn demo_arm_reasons_are_the_designed_ones() {
    let out = common::preprocessed(&common::demo_urdf(), "demo-reasons");
    let mut opts = SampleOptions::new(&out);
    opts.samples = 20_000;
    opts.types = vec![ShapeType::Hull];
    sample(&opts, &NoProgress).unwrap();
    let pairs = reasons_by_link(&out, ShapeType::Hull);
    let reason = |a: &str, b: &str| {
        pairs
            .iter()
            .find(|((x, y), _, _)| (x == a && y == b) || (x == b && y == a))
            .map(|(_, r, _)| *r)
            .unwrap_or_else(|| panic!("no pair {a} {b}"))
    };
    assert_eq!(
        reason("link7", "hand"),
        Reason::Adjacent,
        "bridged by the geometry-less flange"
    );
    assert_eq!(reason("link3", "link4"), Reason::Adjacent);
    assert_eq!(
        reason("finger_left", "finger_right"),
        Reason::Default,
        "the closed fingers touch at home"
    );
    assert_eq!(reason("base_link", "link2"), Reason::Never);
    assert_eq!(reason("link5", "link7"), Reason::Checked);
    let count = |r: Reason| pairs.iter().filter(|(_, x, _)| *x == r).count();
    assert_eq!(count(Reason::Adjacent), 12);
    assert_eq!(
        reason("link2", "shoulder_stop"),
        Reason::Always,
        "collides except near joint2 = 0"
    );
    assert_eq!(
        reason("link1", "link3"),
        Reason::Default,
        "always in contact, home included: default wins"
    );
    // Every never verdict carries zero collisions; every always pair collides in >= 95% of samples.
    for (_, r, f) in &pairs {
        match r {
            Reason::Never => assert_eq!(*f, 0.0),
            Reason::Always => assert!(*f >= 0.95),
            _ => {}
        }
    }
}

/// Sample bytes of every type written by one run, and of the exact geometry's verdicts.
fn sample_bytes(dir: &Path) -> Vec<Vec<u8>> {
    ShapeType::ALL
        .iter()
        .map(|t| format!("{}.json", t.id()))
        .chain([scm::sample::MESH_FILE.to_string()])
        .filter_map(|name| std::fs::read(dir.join("sample").join(name)).ok())
        .collect()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &to.join(e.file_name()));
        } else {
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    }
}

#[test]
fn same_seed_same_bytes_at_any_thread_count_and_sharding() {
    let base = common::preprocessed(&common::demo_urdf(), "determinism");
    // `scm sample DIR` with the same samples, seed and types every time, plus `extra`.
    let sample_in = |dir: &Path, extra: &[&str]| {
        let mut args = vec!["sample", dir.to_str().unwrap(), "-n", "3000", "--seed", "7"];
        args.extend(["--types", "sphere,obb,hull,decomp-hull", "-q"]);
        args.extend_from_slice(extra);
        let o = common::scm_str(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        o
    };
    let fresh = |name: &str| {
        let dir = common::scratch(name);
        copy_dir(&base, &dir);
        dir
    };
    let (one, two) = (fresh("t1"), fresh("t2"));
    let report = |o: Output| -> serde_json::Value { serde_json::from_slice(&o.stdout).unwrap() };
    let report_one = report(sample_in(&one, &["--threads", "1", "--json"]));
    let work_one = report_one["work"].clone();
    let work_two = report(sample_in(&two, &["--threads", "2", "--json"]))["work"].clone();
    // Where the time went: every phase timed, and the run's seconds are the phases after loading.
    let phase = |r: &serde_json::Value, k: &str| r["phases"][k].as_f64().unwrap();
    let phases = ["load", "sampling", "search", "verdicts"];
    assert!(phases.iter().all(|k| phase(&report_one, k) >= 0.0));
    assert!(phase(&report_one, "sampling") > 0.0, "{report_one}");
    let after_load: f64 = phases[1..].iter().map(|k| phase(&report_one, k)).sum();
    let seconds = report_one["seconds"].as_f64().unwrap();
    assert!((seconds - after_load).abs() < 1e-9, "{report_one}");
    let reference = sample_bytes(&one);
    assert_eq!(reference.len(), 5, "four types and mesh.json");
    assert_eq!(
        sample_bytes(&two),
        reference,
        "thread count changed the output"
    );
    // The work counts explain a run's time; they too are fixed by the seed, and every pair-sample of
    // a moving pair is settled exactly one way.
    assert_eq!(work_one, work_two, "thread count changed the work");
    for t in ["sphere", "obb", "hull", "decomp-hull"] {
        let w = &work_one[t];
        let settled: u64 = ["cheap", "bounds", "windows", "exact"]
            .iter()
            .map(|k| w[k].as_u64().unwrap())
            .sum();
        assert!(w["pair_samples"].as_u64().unwrap() > 0, "{t}: {w}");
        assert_eq!(settled, w["pair_samples"].as_u64().unwrap(), "{t}: {w}");
    }

    // Three shards, merged, equal the single run byte for byte.
    let sharded = fresh("shards");
    for k in ["0/3", "1/3", "2/3"] {
        sample_in(&sharded, &["--shard", k]);
    }
    assert!(
        !sharded.join("sample").exists(),
        "a shard alone writes no sample output"
    );
    sample_in(&sharded, &["--merge-shards", "3"]);
    assert_eq!(
        sample_bytes(&sharded),
        reference,
        "merged shards differ from the single run"
    );

    // Same inputs and parameters: a no-op.
    let rerun = sample_in(&one, &["--json"]);
    let json: serde_json::Value = serde_json::from_slice(&rerun.stdout).unwrap();
    assert_eq!(json["up_to_date"], true);
    assert!(phases.iter().all(|k| phase(&json, k) == 0.0), "{json}");
}

/// Writes the authored URDF `text` as `NAME.urdf` in a scratch folder and preprocesses it into the
/// scratch URDD `NAME`.
fn preprocessed_text(name: &str, text: &str) -> std::path::PathBuf {
    let urdf = common::scratch(&format!("{name}-src")).join(format!("{name}.urdf"));
    std::fs::write(&urdf, text).unwrap();
    common::preprocessed(&urdf, name)
}

/// An arm whose thin blade passes a thin post only within ~0.7 mrad of its 6 rad range.
const NARROW: &str = r#"<robot name="narrow">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="post"><collision><origin xyz="0.1621 0.2524 0.2"/><geometry><box size="0.0001 0.0001 0.1"/></geometry></collision></link>
  <link name="arm"><collision><origin xyz="0.3 0 0.2"/><geometry><box size="0.2 0.0001 0.02"/></geometry></collision></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="post"/></joint>
  <joint name="swing" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/><limit lower="-3" upper="3"/></joint>
</robot>"#;

#[test]
fn targeted_search_finds_a_collision_random_sampling_misses() {
    let out = preprocessed_text("narrow", NARROW);
    let mut opts = SampleOptions::new(&out);
    opts.samples = 500;
    opts.types = vec![ShapeType::Obb];
    sample(&opts, &NoProgress).unwrap();
    let file = read_sample(&out, ShapeType::Obb);
    let urdd = Urdd::open(&out).unwrap();
    let shapes = urdd.shapes(ShapeType::Obb).unwrap().shapes;
    let pair = file
        .pairs
        .iter()
        .find(|p| {
            let names = [shapes[p.a].link.as_str(), shapes[p.b].link.as_str()];
            names.contains(&"post") && names.contains(&"arm")
        })
        .unwrap();
    assert_eq!(
        pair.collisions, 0,
        "random sampling should miss the 0.7 mrad window"
    );
    let search = pair.search.as_ref().expect("the close pair was searched");
    assert!(search.collision, "{search:?}");
    assert_eq!(pair.reason, Reason::Checked);
    // The witness really collides: the blade passes the post near atan2(0.2524, 0.1621) = 1.0 rad.
    assert!((search.q[0] - 1.0).abs() < 0.01, "{:?}", search.q);
    assert_eq!(file.summary.overturned, 1);

    // On the exact geometry, the `never` certificate's branch and bound finds the same window.
    let mesh = scm::sample::load_mesh_file(&urdd).unwrap().unwrap();
    let exact = mesh.pair("post", "arm").unwrap();
    assert_eq!(
        (exact.overlaps, exact.reason),
        (0, Reason::Checked),
        "{exact:?}"
    );
    let c = exact.certificate.as_ref().unwrap();
    assert_eq!(c.status, scm::sample::Status::Collides, "{c:?}");
    assert!((c.q[0] - 1.0).abs() < 0.01, "{:?}", c.q);
    assert_eq!(exact.witness.as_ref().unwrap().q, c.q);
    assert_eq!(mesh.summary.overturned, 1);
}

/// On the shared arms, every `never` of the exact geometry is certified, none hides a collision the
/// certificate search found, and the certificates stay within their budget.
#[test]
fn never_pairs_are_certified_on_arms() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    for robot in ["ur5e", "panda"] {
        let urdf = robots.join(robot).join(format!("{robot}.urdf"));
        let dir = common::sampled(&urdf, &format!("certified-{robot}"), 5000);
        let urdd = Urdd::open(&dir).unwrap();
        let mesh = scm::sample::load_mesh_file(&urdd).unwrap().unwrap();
        let never = mesh
            .summary
            .reasons
            .get(&Reason::Never)
            .copied()
            .unwrap_or(0);
        assert!(never > 0, "{robot}: {:?}", mesh.summary);
        assert_eq!(mesh.summary.certified, never, "{robot}: {:?}", mesh.summary);
        for p in &mesh.pairs {
            if let Some(c) = &p.certificate {
                assert!(c.boxes <= mesh.certify.max_boxes_per_pair, "{p:?}");
                assert!(c.lower_bound > mesh.certify.margin, "{p:?}");
                assert!(c.closest >= c.lower_bound, "{p:?}");
                assert_eq!(c.cleared, 1.0, "{p:?}");
            }
        }
    }
}

#[test]
fn broken_urdds_are_bad_input() {
    let base = common::preprocessed(&common::demo_urdf(), "broken");
    let case = |name: &str, edit: &dyn Fn(&Path), expect: &str| {
        let dir = common::scratch(name);
        copy_dir(&base, &dir);
        edit(&dir);
        let o = common::scm_str(&["sample", dir.to_str().unwrap(), "-n", "100"]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{name}: {stderr}");
        assert!(
            stderr.contains(expect),
            "{name}: expected `{expect}` in {stderr}"
        );
        assert!(!stderr.contains("panicked"));
    };
    case(
        "no-manifest",
        &|d| std::fs::remove_file(d.join("manifest.json")).unwrap(),
        "run `scm preprocess",
    );
    case(
        "truncated",
        &|d| {
            let p = d.join("preprocess/shapes/hull.json");
            let bytes = std::fs::read(&p).unwrap();
            std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
        },
        "hull.json",
    );
    case(
        "future",
        &|d| {
            let p = d.join("manifest.json");
            let text = std::fs::read_to_string(&p)
                .unwrap()
                .replace("\"format_version\": 1,", "\"format_version\": 99,");
            std::fs::write(&p, text).unwrap();
        },
        "newer scm",
    );
    case(
        "no-stage",
        &|d| {
            let p = d.join("manifest.json");
            let mut m: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
            m["stages"].as_object_mut().unwrap().remove("preprocess");
            std::fs::write(&p, serde_json::to_string(&m).unwrap()).unwrap();
        },
        "stage \"preprocess\"",
    );
}

/// The default run's shortcuts against an exact run of the same samples on UR5e: collision counts and
/// verdicts identical, `d_min` / `d_max` within the tolerance, `d_mean` within 1% (the control-variate
/// estimate from each pair's leading samples against the mean over all of them).
#[test]
fn estimates_stay_within_their_documented_error_on_ur5e() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    let base = common::preprocessed(&robots.join("ur5e/ur5e.urdf"), "ur5e-exact");
    let run = |name: &str, exact: bool| {
        let dir = common::scratch(name);
        copy_dir(&base, &dir);
        let mut opts = SampleOptions::new(&dir);
        opts.samples = 30_000;
        if exact {
            opts.tolerance = 0.0;
            opts.mean_samples = scm::sample::EXACT_MEAN;
        }
        sample(&opts, &NoProgress).unwrap();
        dir
    };
    let (fast, exact) = (run("ur5e-fast", false), run("ur5e-all", true));
    let tol = SampleOptions::new(&fast).tolerance;
    let mut estimated = 0;
    for t in ShapeType::ALL {
        let (f, e) = (read_sample(&fast, t), read_sample(&exact, t));
        for (p, q) in f.pairs.iter().zip(&e.pairs) {
            let at = format!("{} pair {}-{}", t.id(), p.a, p.b);
            assert_eq!((p.collisions, p.reason), (q.collisions, q.reason), "{at}");
            assert!(
                (p.d_min - q.d_min).abs() <= tol,
                "{at}: d_min {} vs {}",
                p.d_min,
                q.d_min
            );
            assert!(
                (p.d_max - q.d_max).abs() <= tol,
                "{at}: d_max {} vs {}",
                p.d_max,
                q.d_max
            );
            let err = (p.d_mean - q.d_mean).abs();
            assert!(
                err <= 0.01 * q.d_mean.abs().max(1e-3),
                "{at}: d_mean {} vs {}",
                p.d_mean,
                q.d_mean
            );
            estimated += usize::from(p.mean_samples < q.mean_samples);
        }
    }
    assert!(
        estimated > 0,
        "no mean was estimated: the test compares nothing"
    );
}

/// Checks that `table` (of pair `p` of set `s`) brackets the exact distance at `n` random
/// configurations, and returns the widths of its brackets there.
fn bracket_widths(
    engine: &scm::sample::Engine,
    (s, p): (usize, usize),
    table: &scm::sample::Table,
    rng: &mut scm::rng::Rng,
    n: usize,
) -> Vec<f64> {
    let set = &engine.sets[s];
    (0..n)
        .map(|_| {
            let mut q = Vec::new();
            scm::robot::random_configuration(engine.kinematics.dofs(), rng, &mut q);
            let d = engine.pair_distance(s, p, &q);
            let (lower, upper) = table.bounds(&q);
            // The exact query's own error is below 1e-6 m (tests/exactness.rs).
            assert!(
                lower <= d + 1e-6 && d <= upper + 1e-6,
                "{} pair {:?} (rank {}): {d} outside [{lower}, {upper}]",
                set.shape_type.id(),
                set.pairs[p],
                table.rank()
            );
            upper - lower
        })
        .collect()
}

/// b1's hips of one side turn about one line (parallel to the trunk's x axis through both hip joints),
/// so a pair of them (or of the thigh rotors fixed to them) depends only on the hips' relative turn:
/// its table spans that one coordinate, as fine as a one-DOF table, and still bounds the exact distance
/// at random configurations. No other pair of b1 is coaxial (the front hips, say, turn about parallel
/// but distinct lines). (It fails with the relative turn's sign flipped.)
#[test]
fn coaxial_tables_bracket_the_exact_distance() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    let dir = common::preprocessed(&robots.join("b1/b1.urdf"), "b1-coaxial");
    let urdd = Urdd::open(&dir).unwrap();
    let types = [ShapeType::Hull, ShapeType::DecompHull];
    let engine = scm::sample::Engine::load(&urdd, &types)
        .unwrap()
        .with_tables();
    let names: Vec<&str> = engine.robot.links.iter().map(|l| l.name.as_str()).collect();
    let mut rng = scm::rng::Rng::new(12, 0);
    let mut pairs = std::collections::BTreeSet::new();
    let (mut checked, mut within) = (0usize, 0usize);
    for (s, (set, tables)) in engine.sets.iter().zip(&engine.tables).enumerate() {
        for (p, table) in tables.iter().enumerate() {
            let Some(table) = table.as_ref().filter(|t| t.is_coaxial()) else {
                continue;
            };
            assert_eq!(table.rank(), 1);
            let (i, j) = set.pairs[p];
            let link = |k: u32| names[set.links[k as usize]];
            pairs.insert((link(i), link(j)));
            for width in bracket_widths(&engine, (s, p), table, &mut rng, 40) {
                checked += 1;
                within += usize::from(width < 1e-3);
            }
        }
    }
    // Each side's hips, and the thigh rotors fixed to them.
    let expected = [
        ("FL_hip", "RL_hip"),
        ("FL_hip", "RL_thigh_rotor"),
        ("FL_thigh_rotor", "RL_hip"),
        ("FL_thigh_rotor", "RL_thigh_rotor"),
        ("FR_hip", "RR_hip"),
        ("FR_hip", "RR_thigh_rotor"),
        ("FR_thigh_rotor", "RR_hip"),
        ("FR_thigh_rotor", "RR_thigh_rotor"),
    ];
    assert_eq!(pairs, expected.into_iter().collect(), "coaxial link pairs");
    assert!(checked >= 2000, "only {checked} checks");
    assert!(
        within * 10 >= checked * 9,
        "{within} of {checked} coaxial bounds within 1 mm"
    );
}

/// Two cranks on one axle whose joint axes point opposite ways (so the pair depends on `q_a + q_b`),
/// and a third crank on a parallel axle beside them.
const AXLE: &str = r#"<robot name="axle">
  <link name="base"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <link name="left"><collision><origin xyz="0.1 0.03 0"/><geometry><box size="0.2 0.02 0.03"/></geometry></collision></link>
  <link name="right"><collision><origin xyz="0.1 -0.03 0.02"/><geometry><box size="0.2 0.02 0.03"/></geometry></collision></link>
  <link name="beside"><collision><origin xyz="0.1 0 0"/><geometry><box size="0.2 0.02 0.03"/></geometry></collision></link>
  <joint name="l" type="revolute"><parent link="base"/><child link="left"/><origin xyz="0 0.1 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2.5"/></joint>
  <joint name="r" type="continuous"><parent link="base"/><child link="right"/><origin xyz="0 -0.1 0"/><axis xyz="0 -1 0"/></joint>
  <joint name="b" type="revolute"><parent link="base"/><child link="beside"/><origin xyz="0.3 0.1 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1"/></joint>
</robot>"#;

/// On an authored axle, the cranks on one line (axes opposite) get a coaxial table and no other pair
/// does; the table brackets the exact distance within millimetres, where the cranks' distance
/// changes by centimetres as they turn.
/// (It fails with the relative turn taken as `q_b - q_a`.)
#[test]
fn opposite_coaxial_axes_turn_by_the_sum() {
    let out = preprocessed_text("axle", AXLE);
    let engine = scm::sample::Engine::load(&Urdd::open(&out).unwrap(), &[ShapeType::Obb])
        .unwrap()
        .with_tables();
    let names: Vec<&str> = engine.robot.links.iter().map(|l| l.name.as_str()).collect();
    let mut rng = scm::rng::Rng::new(13, 0);
    let set = &engine.sets[0];
    let mut coaxial = Vec::new();
    for (p, table) in engine.tables[0].iter().enumerate() {
        let Some(table) = table.as_ref().filter(|t| t.is_coaxial()) else {
            continue;
        };
        let (i, j) = set.pairs[p];
        coaxial.push((names[set.links[i as usize]], names[set.links[j as usize]]));
        let widths = bracket_widths(&engine, (0, p), table, &mut rng, 2000);
        // One coordinate of 9.6 rad over 1,024 points, a crank of 0.2 m: about 2 mm at most.
        assert!(
            widths.iter().all(|&w| w < 5e-3),
            "a bracket wider than 5 mm"
        );
    }
    assert_eq!(coaxial, [("left", "right")]);
}

/// Every table (pairs that depend on one or two DOFs: adjacent links, Panda's mimic fingers, links two
/// joints apart) bounds the exact signed distance at random configurations: the Lipschitz constants it
/// is built with cover how fast either shape can move, so no sample it settles could have been decided
/// otherwise. (It fails with the one-DOF constants scaled by 0.7, the two-DOF ones by 0.4.)
#[test]
fn tables_bracket_the_exact_distance() {
    let Some(robots) = common::robots_dir() else {
        return;
    };
    let dir = common::preprocessed(&robots.join("panda/panda.urdf"), "panda-tables");
    let engine = scm::sample::Engine::load(&Urdd::open(&dir).unwrap(), &ShapeType::ALL)
        .unwrap()
        .with_tables();
    let mut rng = scm::rng::Rng::new(11, 0);
    // Per rank: checks, and bounds within 1 mm and 5 cm.
    let mut checked = [0usize; 2];
    let mut within = [[0usize; 2]; 2];
    for (s, tables) in engine.tables.iter().enumerate() {
        for (p, table) in tables.iter().enumerate() {
            let Some(table) = table else { continue };
            let rank = table.rank();
            for width in bracket_widths(&engine, (s, p), table, &mut rng, 24) {
                checked[rank - 1] += 1;
                within[rank - 1][0] += usize::from(width < 1e-3);
                within[rank - 1][1] += usize::from(width < 5e-2);
            }
        }
    }
    assert!(
        checked.iter().all(|&c| c >= 500),
        "only {checked:?} table checks"
    );
    // Bounds that hold because they are loose would be no use: most one-DOF bounds are within a
    // millimetre; two-DOF ones, over a coarser grid, within 5 cm.
    assert!(
        within[0][0] * 10 >= checked[0] * 9,
        "{} of {} one-DOF bounds within 1 mm",
        within[0][0],
        checked[0]
    );
    assert!(
        within[1][1] * 10 >= checked[1] * 9,
        "{} of {} two-DOF bounds within 5 cm ({} within 1 mm)",
        within[1][1],
        checked[1],
        within[1][0]
    );
}

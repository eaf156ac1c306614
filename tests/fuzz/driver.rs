//! A mutation fuzzer for scm's readers on stable Rust (cargo-fuzz needs a nightly toolchain, which
//! cannot be installed here). Each reader starts from authored seed files; every run applies one to
//! four mutations (bit flips, bytes set to XML, number and OBJ/STL tokens, ranges deleted or doubled,
//! truncation, splices of two seeds) and feeds the result to the reader. A panic is a crash: its input
//! is kept. An error return is the expected answer to bad input. Runs are seeded and deterministic.
//!
//! Used by `benches/fuzz_readers.rs` (millions of runs, `cargo bench --bench fuzz_readers`) and by
//! `tests/fuzz_readers.rs` (a few thousand, in CI).
#![allow(dead_code)]

use scm::rng::Rng;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// One reader under test: its seeds and how to call it.
pub struct Target {
    /// The reader's name (`urdf`, `srdf`, `stl`, `obj`, `dae`, `urdd-json`).
    pub name: &'static str,
    /// Seed inputs.
    pub seeds: Vec<Vec<u8>>,
    /// Feeds one input to the reader; its result is dropped.
    pub run: fn(&[u8]),
}

/// What a fuzz run of one target found.
#[derive(Debug, Default)]
pub struct Outcome {
    /// Inputs run.
    pub execs: u64,
    /// Inputs that made the reader panic, with the panic message.
    pub crashes: Vec<(Vec<u8>, String)>,
    /// The slowest single input.
    pub slowest: Duration,
    /// Wall time of the run.
    pub seconds: f64,
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn read(relative: &str) -> Vec<u8> {
    std::fs::read(root().join(relative)).unwrap_or_else(|e| panic!("seed {relative}: {e}"))
}

fn text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(bytes)
}

/// The URDD JSON seeds: a preprocessed and sampled mesh-variants robot, made once in `scratch`.
fn urdd_seeds(scratch: &Path) -> Vec<Vec<u8>> {
    let dir = scratch.join("seed.urdd");
    let opts = scm::preprocess::PreprocessOptions {
        urdf: root().join("tests/data/mesh_variants/mesh_variants.urdf"),
        out: dir.clone(),
        packages: scm::robot::PackagePaths::new(),
        visual_fallback: false,
        params: scm::shapes::ShapeParams::default(),
        force: false,
    };
    scm::preprocess::preprocess(&opts, &scm::progress::NoProgress).expect("seed preprocess");
    let mut sample = scm::sample::SampleOptions::new(&dir);
    sample.samples = 200;
    sample.types = vec![scm::shapes::ShapeType::Hull];
    scm::sample::sample(&sample, &scm::progress::NoProgress).expect("seed sample");
    [
        "manifest.json",
        "preprocess/robot.json",
        "preprocess/links.json",
        "preprocess/shapes/hull.json",
        "sample/hull.json",
    ]
    .iter()
    .map(|f| std::fs::read(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}")))
    .collect()
}

/// Every reader, with its seeds (`scratch` holds the URDD the JSON seeds come from).
pub fn targets(scratch: &Path) -> Vec<Target> {
    let v = "tests/data/mesh_variants";
    vec![
        Target {
            name: "urdf",
            seeds: vec![
                read(&format!("{v}/mesh_variants.urdf")),
                read("robots/demo_arm/demo_arm.urdf"),
            ],
            run: |b| {
                let _ = scm::robot::parse_urdf(
                    &text(b),
                    Path::new("/nonexistent/fuzz.urdf"),
                    &Default::default(),
                );
            },
        },
        Target {
            name: "srdf",
            seeds: vec![SRDF.as_bytes().to_vec()],
            run: |b| {
                let _ = scm::formats::srdf::parse_srdf(&text(b), Path::new("fuzz.srdf"));
            },
        },
        Target {
            name: "stl",
            seeds: vec![
                read(&format!("{v}/meshes/solid_header.stl")),
                read(&format!("{v}/meshes/wrong_count.stl")),
                read(&format!("{v}/meshes/irregular.stl")),
            ],
            run: |b| {
                let _ = scm::mesh::read_mesh(b, "stl");
            },
        },
        Target {
            name: "obj",
            seeds: vec![
                read(&format!("{v}/meshes/polygons.obj")),
                read(&format!("{v}/meshes/wedge.obj")),
            ],
            run: |b| {
                let _ = scm::mesh::read_mesh(b, "obj");
            },
        },
        Target {
            name: "dae",
            seeds: vec![
                read(&format!("{v}/meshes/polylist_yup_inch.dae")),
                read(&format!("{v}/meshes/nested_nodes.dae")),
                read(&format!("{v}/meshes/instances.dae")),
            ],
            run: |b| {
                let _ = scm::mesh::read_mesh(b, "dae");
            },
        },
        Target {
            name: "urdd-json",
            seeds: urdd_seeds(scratch),
            run: |b| {
                let _ = serde_json::from_slice::<scm::urdd::Manifest>(b);
                let _ = serde_json::from_slice::<scm::urdd::RobotRecord>(b);
                let _ = serde_json::from_slice::<Vec<scm::urdd::LinkRecord>>(b);
                let _ = serde_json::from_slice::<scm::urdd::ShapeFile>(b);
                let _ = serde_json::from_slice::<scm::sample::SampleFile>(b);
                if let Ok(robot) = serde_json::from_slice::<scm::urdd::RobotRecord>(b)
                    && robot.robot.check_tree().is_ok()
                {
                    // A record that passes the reader's checks (as `Urdd::robot` applies them) has
                    // to be safe to use: kinematics on its tree.
                    let k = scm::robot::Kinematics::new(&robot.robot);
                    let _ = k.link_poses(&k.home());
                }
            },
        },
    ]
}

const SRDF: &str = r#"<?xml version="1.0"?>
<robot name="demo_arm">
  <group name="arm"><chain base_link="base_link" tip_link="link8"/></group>
  <group_state name="home" group="arm"><joint name="joint1" value="0"/></group_state>
  <disable_default_collisions link="camera_link"/>
  <disable_collisions link1="base_link" link2="link1" reason="Adjacent"/>
  <disable_collisions link1="link2" link2="shoulder_stop" reason="Default"/>
  <enable_collisions link1="link3" link2="link5" reason="Never"/>
</robot>
"#;

/// Tokens a mutation may insert: numbers scm must refuse or survive, markup, format keywords.
const TOKENS: &[&[u8]] = &[
    b"1e308",
    b"-1e308",
    b"nan",
    b"inf",
    b"-0",
    b"4294967295",
    b"-2147483649",
    b"99999999999999999999",
    b"0",
    b"-1",
    b"1e-320",
    b"<",
    b">",
    b"</",
    b"/>",
    b"\"",
    b"'",
    b"&amp;",
    b"&#0;",
    b"<![CDATA[",
    b"<node>",
    b"<instance_node url=\"#",
    b"<p>",
    b"<vcount>",
    b"#",
    b"=\"",
    b"f 1 2 3\n",
    b"f -1 -2 -3\n",
    b"v 1 2 3\n",
    b"\\\n",
    b"facet normal",
    b"vertex",
    b"endsolid",
    b"solid",
    b"\0",
    b"\xff\xfe",
];

fn mutate(rng: &mut Rng, seeds: &[Vec<u8>], input: &mut Vec<u8>) {
    let pick = |rng: &mut Rng, n: usize| (rng.next_u64() % n.max(1) as u64) as usize;
    for _ in 0..1 + pick(rng, 4) {
        let len = input.len();
        match pick(rng, 8) {
            0 if len > 0 => {
                let at = pick(rng, len);
                input[at] ^= 1 << pick(rng, 8);
            }
            1 if len > 0 => {
                let at = pick(rng, len);
                input[at] = b"<>/\"=#-.e9 \n\0"[pick(rng, 13)];
            }
            2 if len > 0 => {
                let at = pick(rng, len);
                let n = 1 + pick(rng, 32).min(len - at - 1);
                input.drain(at..(at + n).min(len));
            }
            3 if len > 0 => {
                let at = pick(rng, len);
                let n = (1 + pick(rng, 64)).min(len - at);
                let copy = input[at..at + n].to_vec();
                let to = pick(rng, len);
                input.splice(to..to, copy);
            }
            4 => {
                let token = TOKENS[pick(rng, TOKENS.len())];
                let at = pick(rng, len + 1);
                input.splice(at..at, token.iter().copied());
            }
            5 if len > 0 => input.truncate(pick(rng, len)),
            6 => {
                let other = &seeds[pick(rng, seeds.len())];
                let cut = pick(rng, len + 1);
                let from = pick(rng, other.len() + 1);
                input.truncate(cut);
                input.extend_from_slice(&other[from..]);
            }
            _ if len > 0 => {
                // Replace a run of digits with an extreme number.
                let at = pick(rng, len);
                if let Some(start) = (at..len).find(|&i| input[i].is_ascii_digit()) {
                    let end = (start..len)
                        .find(|&i| !input[i].is_ascii_digit())
                        .unwrap_or(len);
                    let token = TOKENS[pick(rng, 8)];
                    input.splice(start..end, token.iter().copied());
                }
            }
            _ => {}
        }
    }
}

/// Runs `execs` mutated inputs through `target` from `seed`; the seeds themselves run first.
pub fn fuzz(target: &Target, execs: u64, seed: u64) -> Outcome {
    let started = Instant::now();
    let mut rng = Rng::new(seed, 0x5eed);
    let mut out = Outcome::default();
    let mut input = Vec::new();
    for k in 0..execs {
        input.clear();
        let base = &target.seeds[(k as usize) % target.seeds.len()];
        input.extend_from_slice(base);
        if k as usize >= target.seeds.len() {
            mutate(&mut rng, &target.seeds, &mut input);
        }
        let t = Instant::now();
        let result = catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
        out.slowest = out.slowest.max(t.elapsed());
        out.execs += 1;
        if let Err(panic) = result {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            out.crashes.push((input.clone(), message));
        }
    }
    out.seconds = started.elapsed().as_secs_f64();
    out
}

/// Silences the default panic message (crashes are counted and kept instead).
pub fn quiet_panics() {
    std::panic::set_hook(Box::new(|_| {}));
}

//! Sampling past one machine (docs/cluster.md): four shards of the `scm` binary run side by side through
//! `xargs -P 4`, exactly the commands a Slurm array task or a Kubernetes Indexed Job pod runs, and merge
//! into the bytes of one run; a shard computed in a copy of the URDD at another path merges; a missing,
//! foreign or truncated shard is bad input (exit 2, one line naming it) and the merge writes nothing.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Samples per run: four chunks, one per shard.
const SAMPLES: &str = "4000";
/// The types the checks of shipping and checking shards sample (the byte-for-byte test samples all six).
const TYPES: &str = "sphere,hull";

/// Copies the directory tree `from` into `to`.
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

/// Every file under `dir` (path relative to it -> bytes).
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                let bytes = std::fs::read(&path).unwrap();
                out.insert(path.strip_prefix(root).unwrap().to_path_buf(), bytes);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// `scm -q sample DIR -n SAMPLES --types TYPES` plus `extra`, which must succeed.
fn sample(dir: &Path, extra: &[&str]) {
    sample_n(dir, SAMPLES, extra);
}

/// `scm -q sample DIR -n N --types TYPES` plus `extra`, which must succeed.
fn sample_n(dir: &Path, n: &str, extra: &[&str]) {
    let mut args = vec!["-q", "sample", dir.to_str().unwrap(), "-n", n];
    args.extend(["--types", TYPES]);
    args.extend_from_slice(extra);
    let o = common::scm_str(&args);
    assert!(
        o.status.success(),
        "scm {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// `scm sample DIR -n SAMPLES --types TYPES --merge-shards 4`, which must fail as bad input (exit 2) with one line
/// on stderr, returned; the URDD and its shards are unchanged.
fn bad_merge(dir: &Path) -> String {
    let before = files(dir);
    let o = common::scm_str(&[
        "sample",
        dir.to_str().unwrap(),
        "-n",
        SAMPLES,
        "--types",
        TYPES,
        "--merge-shards",
        "4",
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "merge: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "one line: {stderr}");
    assert!(
        files(dir) == before,
        "a failed merge changed the URDD: {stderr}"
    );
    assert!(!dir.join("sample").exists(), "a failed merge wrote sample/");
    stderr.trim_end().to_string()
}

/// The shard file `k` of 4 in `dir`.
fn shard_file(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("sample-shards/shard-{k}-of-4.json"))
}

/// The demo arm preprocessed by the binary from its own copy of the robot folder: (URDD, robot folder).
fn preprocessed_from_copy(name: &str) -> (PathBuf, PathBuf) {
    let robot = common::scratch(&format!("{name}-robot"));
    copy_dir(common::demo_urdf().parent().unwrap(), &robot);
    let dir = common::scratch(name).join("robot.urdd");
    let urdf = robot.join("demo_arm.urdf");
    let o = common::scm_str(&[
        "-q",
        "preprocess",
        urdf.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (dir, robot)
}

/// Runs `sh -c SCRIPT` with `SCM` (the binary) and `DIR` in its environment.
fn sh(script: &str, dir: &Path) -> Output {
    Command::new("sh")
        .args(["-c", script])
        .env("SCM", env!("CARGO_BIN_EXE_scm"))
        .env("DIR", dir)
        .output()
        .expect("run sh")
}

#[test]
fn four_shards_through_xargs_merge_into_the_bytes_of_one_run() {
    let base = common::preprocessed(&common::demo_urdf(), "shards-base");
    let (single, sharded) = (
        common::scratch("shards-one"),
        common::scratch("shards-four"),
    );
    copy_dir(&base, &single);
    copy_dir(&base, &sharded);
    let o = sh("\"$SCM\" -q sample \"$DIR\" -n 4000", &single);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    // The four array tasks / pods, side by side on one machine.
    let o = sh(
        "printf '0\\n1\\n2\\n3\\n' | xargs -P 4 -I{} \"$SCM\" -q sample \"$DIR\" -n 4000 --shard {}/4",
        &sharded,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!sharded.join("sample").exists(), "shards write no sample/");

    // A shard file is self-contained: what the merge checks, and no path of this machine.
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(sharded.join("manifest.json")).unwrap()).unwrap();
    for k in 0..4 {
        let bytes = std::fs::read(shard_file(&sharded, k)).unwrap();
        let text = String::from_utf8(bytes).unwrap();
        for path in [sharded.to_str().unwrap(), env!("CARGO_MANIFEST_DIR")] {
            assert!(!text.contains(path), "shard {k} names the path {path}");
        }
        let shard: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(shard["format"], "scm-sample-shard");
        assert_eq!(shard["format_version"], 4);
        assert_eq!(shard["tool_version"], env!("CARGO_PKG_VERSION"));
        assert_eq!(shard["robot"], "demo_arm");
        assert_eq!(shard["preprocess"], manifest["stages"]["preprocess"]["key"]);
        assert_eq!(
            shard["shard"],
            serde_json::json!({ "index": k, "count": 4 })
        );
        assert_eq!(shard["options"]["samples"], 4000);
        assert_eq!(shard["options"]["seed"], 0);
        assert_eq!(shard["options"]["types"].as_array().unwrap().len(), 6);
        assert!(shard["options"]["search"]["margin"].is_number());
        assert_eq!(shard["key"].as_str().unwrap().len(), 64);
    }

    let o = sh(
        "\"$SCM\" -q sample \"$DIR\" -n 4000 --merge-shards 4",
        &sharded,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (one, four) = (
        files(&single.join("sample")),
        files(&sharded.join("sample")),
    );
    assert_eq!(one.len(), 7, "six types and mesh.json: {:?}", one.keys());
    assert_eq!(
        one.keys().collect::<Vec<_>>(),
        four.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &one {
        assert!(four[name] == *bytes, "{} differs", name.display());
    }

    // The recipe's last step: the export of the merged URDD is the single run's (export.json names
    // the URDD's path, so it differs).
    for dir in [&single, &sharded] {
        let o = common::scm_str(&["-q", "export", dir.to_str().unwrap()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let (mut one, mut four) = (
        files(&single.join("export")),
        files(&sharded.join("export")),
    );
    one.remove(Path::new("export.json"));
    four.remove(Path::new("export.json"));
    assert!(one.len() > 10 && one == four, "the exports differ");
}

#[test]
fn a_shard_computed_in_a_copy_at_another_path_merges() {
    let (dir, robot) = preprocessed_from_copy("shards-home");
    // Ship the preprocessed URDD to a "node": another path, and no robot files (moved away meanwhile).
    // What a scheduler ships to a shard: the manifest and the preprocess output, nothing else.
    let node = common::scratch("shards-node").join("copy.urdd");
    copy_dir(&dir.join("preprocess"), &node.join("preprocess"));
    std::fs::copy(dir.join("manifest.json"), node.join("manifest.json")).unwrap();
    let away = robot.with_extension("away");
    std::fs::rename(&robot, &away).unwrap();
    sample(&node, &["--shard", "2/4"]);
    std::fs::rename(&away, &robot).unwrap();
    for k in [0, 1, 2, 3] {
        sample(&dir, &["--shard", &format!("{k}/4")]);
    }
    let here = std::fs::read(shard_file(&dir, 2)).unwrap();
    let there = std::fs::read(shard_file(&node, 2)).unwrap();
    assert!(here == there, "the shard depends on where the URDD lies");

    // Copy it back over the local one and merge (the merge reads the robot's meshes for the
    // certificates, so it runs where the preprocess did).
    std::fs::remove_file(shard_file(&dir, 2)).unwrap();
    std::fs::copy(shard_file(&node, 2), shard_file(&dir, 2)).unwrap();
    sample(&dir, &["--merge-shards", "4"]);
    assert!(dir.join("sample/mesh.json").is_file());
}

#[test]
fn a_missing_foreign_or_truncated_shard_is_bad_input_naming_it() {
    let dir = common::preprocessed(&common::demo_urdf(), "shards-bad");
    let shown = dir.display();
    for k in [0, 1] {
        sample(&dir, &["--shard", &format!("{k}/4")]);
    }
    assert_eq!(
        bad_merge(&dir),
        format!(
            "scm: error: {shown}/sample-shards/shard-2-of-4.json: shard 2 of 4: missing \
             (missing shards: 2, 3); run `scm sample {shown} --shard 2/4` with the merge's sampling flags"
        )
    );
    sample(&dir, &["--shard", "2/4"]);
    assert_eq!(
        bad_merge(&dir),
        format!(
            "scm: error: {shown}/sample-shards/shard-3-of-4.json: shard 3 of 4: missing; \
             run `scm sample {shown} --shard 3/4` with the merge's sampling flags"
        )
    );

    // Shard 3 with another seed, another sample count, from another preprocess output.
    let shard3 = shard_file(&dir, 3);
    sample(&dir, &["--shard", "3/4", "--seed", "7"]);
    assert_eq!(
        bad_merge(&dir),
        format!(
            "scm: error: {}: seed: this shard has 7, the merge expects 0; \
             give the shards and the merge the same sampling flags, or rerun this shard",
            shard3.display()
        )
    );
    sample_n(&dir, "8000", &["--shard", "3/4"]);
    assert_eq!(
        bad_merge(&dir),
        format!(
            "scm: error: {}: samples: this shard has 8000, the merge expects 4000; \
             give the shards and the merge the same sampling flags, or rerun this shard",
            shard3.display()
        )
    );
    let other = common::scratch("shards-other").join("other.urdd");
    let o = common::scm_str(&[
        "-q",
        "preprocess",
        common::demo_urdf().to_str().unwrap(),
        "-o",
        other.to_str().unwrap(),
        "--max-pieces",
        "4",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    sample(&other, &["--shard", "3/4"]);
    std::fs::copy(shard_file(&other, 3), &shard3).unwrap();
    let line = bad_merge(&dir);
    assert!(
        line.starts_with(&format!(
            "scm: error: {}: preprocess: this shard has ",
            shard3.display()
        )) && line.ends_with("; rerun this shard on a copy of this URDD"),
        "{line}"
    );

    // A shard file under another shard's name, cut short, empty.
    std::fs::copy(shard_file(&dir, 2), &shard3).unwrap();
    assert_eq!(
        bad_merge(&dir),
        format!(
            "scm: error: {}: shard: this shard has \"2/4\", the merge expects \"3/4\"; rerun this shard",
            shard3.display()
        )
    );
    sample(&dir, &["--shard", "3/4"]);
    let whole = std::fs::read(&shard3).unwrap();
    std::fs::write(&shard3, &whole[..whole.len() / 2]).unwrap();
    let line = bad_merge(&dir);
    assert!(
        line.starts_with(&format!(
            "scm: error: {}: line 1, column ",
            shard3.display()
        )) && line.ends_with(&format!(
            ": truncated after {} bytes; copy it again or rerun this shard",
            whole.len() / 2
        )),
        "{line}"
    );
    std::fs::write(&shard3, b"").unwrap();
    assert!(bad_merge(&dir).ends_with(": empty; copy it again or rerun this shard"));

    // The shard put right, the merge goes through.
    std::fs::write(&shard3, &whole).unwrap();
    sample(&dir, &["--merge-shards", "4"]);
    assert!(dir.join("sample/mesh.json").is_file());
}

/// The recipes of docs/cluster.md, in `scripts/cluster/`.
fn recipe(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scripts/cluster")
        .join(name)
}

/// A `Command` whose `scm` on the PATH is the binary under test, as in the recipes' container image.
fn with_scm_on_path(program: &str) -> Command {
    let bin = Path::new(env!("CARGO_BIN_EXE_scm")).parent().unwrap();
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut paths = vec![bin.to_path_buf()];
    paths.extend(std::env::split_paths(&path));
    let mut c = Command::new(program);
    c.env("PATH", std::env::join_paths(paths).unwrap());
    c.env_remove("SCM");
    c
}

/// The flags the recipe tests sample with (the recipes pass any flags through).
const RECIPE_FLAGS: [&str; 4] = ["-n", SAMPLES, "--types", TYPES];

/// A single run's sample/ and export/ (without export.json, which names the URDD) on a copy of `base`.
fn single_run(base: &Path, name: &str) -> BTreeMap<PathBuf, Vec<u8>> {
    let single = common::scratch(name);
    copy_dir(base, &single);
    sample(&single, &[]);
    let o = common::scm_str(&["-q", "export", single.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    outputs(&single)
}

/// `dir`'s sample/ and export/ files, export.json left out.
fn outputs(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut all = BTreeMap::new();
    for folder in ["sample", "export"] {
        for (name, bytes) in files(&dir.join(folder)) {
            all.insert(Path::new(folder).join(name), bytes);
        }
    }
    all.remove(Path::new("export/export.json"));
    all
}

/// Waits for every child, asserting each succeeded.
fn wait_all(children: Vec<std::process::Child>) {
    for child in children {
        let o = child.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
}

#[test]
fn the_slurm_job_array_recipe_merges_into_the_bytes_of_one_run() {
    let base = common::preprocessed(&common::demo_urdf(), "slurm-base");
    let one = single_run(&base, "slurm-one");
    let dir = common::scratch("slurm-array");
    copy_dir(&base, &dir);
    // `sbatch --array=1-4`: four tasks at once with the variables Slurm sets (ids from 1, to check
    // the offset), then the merge job.
    let tasks = (1..=4)
        .map(|id| {
            with_scm_on_path("bash")
                .arg(recipe("slurm-shards.sbatch"))
                .arg(&dir)
                .args(RECIPE_FLAGS)
                .env("SLURM_ARRAY_TASK_ID", id.to_string())
                .env("SLURM_ARRAY_TASK_MIN", "1")
                .env("SLURM_ARRAY_TASK_COUNT", "4")
                .env("SLURM_CPUS_PER_TASK", "1")
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    wait_all(tasks);
    for k in 0..4 {
        assert!(shard_file(&dir, k).is_file(), "no shard {k}");
    }
    let merge = with_scm_on_path("bash")
        .arg(recipe("slurm-merge.sbatch"))
        .arg(&dir)
        .arg("4")
        .args(RECIPE_FLAGS)
        .output()
        .unwrap();
    assert!(
        merge.status.success(),
        "{}",
        String::from_utf8_lossy(&merge.stderr)
    );
    let four = outputs(&dir);
    assert!(one.len() > 10, "{:?}", one.keys());
    assert_eq!(
        one.keys().collect::<Vec<_>>(),
        four.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &one {
        assert!(four[name] == *bytes, "{} differs", name.display());
    }
}

/// A Job manifest of `scripts/cluster/`: (completions, completion mode, the container's command, its
/// environment).
fn job(name: &str) -> (u64, String, Vec<String>, BTreeMap<String, String>) {
    let text = std::fs::read_to_string(recipe(name)).unwrap();
    let v: serde_json::Value = serde_saphyr::from_str(&text).unwrap();
    assert_eq!(v["kind"], "Job", "{name}");
    let spec = &v["spec"];
    let container = &spec["template"]["spec"]["containers"][0];
    let command = container["command"].as_array().unwrap();
    let env = container["env"].as_array().unwrap();
    (
        spec["completions"].as_u64().unwrap(),
        spec["completionMode"]
            .as_str()
            .unwrap_or("NonIndexed")
            .into(),
        command.iter().map(|c| c.as_str().unwrap().into()).collect(),
        env.iter()
            .map(|e| {
                (
                    e["name"].as_str().unwrap().into(),
                    e["value"].as_str().unwrap().into(),
                )
            })
            .collect(),
    )
}

#[test]
fn the_kubernetes_indexed_job_recipe_merges_into_the_bytes_of_one_run() {
    let (completions, mode, command, env) = job("k8s-shards.yaml");
    assert_eq!(mode, "Indexed");
    assert_eq!(
        env["SHARDS"],
        completions.to_string(),
        "SHARDS is the completion count"
    );
    let (merge_completions, _, merge_command, merge_env) = job("k8s-merge.yaml");
    assert_eq!(merge_completions, 1);
    for name in ["URDD", "SHARDS", "SAMPLE_FLAGS"] {
        assert_eq!(
            env[name], merge_env[name],
            "the merge Job's {name} is the shard Job's"
        );
    }

    let base = common::preprocessed(&common::demo_urdf(), "k8s-base");
    let one = single_run(&base, "k8s-one");
    // The volume: the URDD lies where the manifests' URDD says, under a scratch folder for /data.
    let volume = common::scratch("k8s-volume");
    let urdd = Path::new(&env["URDD"]);
    let dir = volume.join(urdd.strip_prefix("/data").unwrap());
    copy_dir(&base, &dir);
    // Each pod runs the container's command with the Job's environment and its completion index.
    let run = |command: &[String], env: &BTreeMap<String, String>, index: Option<u64>| {
        let mut c = with_scm_on_path(&command[0]);
        c.args(&command[1..]).envs(env).env("URDD", &dir);
        c.env("SAMPLE_FLAGS", RECIPE_FLAGS.join(" "));
        if let Some(i) = index {
            c.env("JOB_COMPLETION_INDEX", i.to_string());
        }
        c.stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped());
        c.spawn().unwrap()
    };
    wait_all(
        (0..completions)
            .map(|i| run(&command, &env, Some(i)))
            .collect(),
    );
    wait_all(vec![run(&merge_command, &merge_env, None)]);
    let four = outputs(&dir);
    assert_eq!(
        one.keys().collect::<Vec<_>>(),
        four.keys().collect::<Vec<_>>()
    );
    for (name, bytes) in &one {
        assert!(four[name] == *bytes, "{} differs", name.display());
    }
}

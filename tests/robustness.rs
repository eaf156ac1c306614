//! Nothing lost, nothing silently wrong: closed pipes, output paths that are files, killed commits,
//! concurrent writers, corrupt outputs, numbers scm cannot represent, unbounded arguments.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

/// The demo arm preprocessed, sampled (500 samples) and exported once for the whole file; tests copy it.
fn demo() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = common::sampled(&common::demo_urdf(), "robust-demo", 500);
        let o = common::scm_str(&["export", dir.to_str().unwrap(), "-q"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        dir
    })
}

/// A fresh copy of the demo URDD.
fn demo_copy(name: &str) -> PathBuf {
    let to = common::scratch(name).join("demo.urdd");
    let status = Command::new("cp")
        .arg("-a")
        .arg(demo())
        .arg(&to)
        .status()
        .unwrap();
    assert!(status.success());
    to
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_closed_stdout_ends_quietly() {
    let dir = demo_copy("pipe");
    let srdf = dir.join("export/demo_arm.srdf");
    let cases: Vec<Vec<&str>> = vec![
        vec!["diff", s(&dir), "--srdf", s(&srdf)],
        vec!["diff", s(&dir), "--srdf", s(&srdf), "--json"],
        vec!["export", s(&dir), "--force"],
        vec!["export", s(&dir), "--force", "--json"],
        vec!["import-moveit", s(&srdf), s(&dir), "--compare"],
        vec!["inspect", s(&dir), "--random", "50", "--json"],
    ];
    for args in cases {
        // The read end is closed before scm starts, so its first write meets a closed pipe.
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let out = Command::new(env!("CARGO_BIN_EXE_scm"))
            .args(&args)
            .stdout(writer)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

#[test]
fn an_output_path_that_is_a_file_is_bad_input_and_the_file_stays() {
    let dir = demo_copy("out-file");
    let file = dir.parent().unwrap().join("notes.txt");
    std::fs::write(&file, "my notes").unwrap();
    let demo_urdf = common::demo_urdf();
    let runs: Vec<Vec<&str>> = vec![
        vec!["export", s(&dir), "-o", s(&file)],
        vec!["run", s(&demo_urdf), "-o", s(&file), "-n", "10"],
        vec!["preprocess", s(&demo_urdf), "-o", s(&file)],
    ];
    for args in runs {
        let o = common::scm_str(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains("notes.txt") && err.contains("is an existing file"),
            "{err}"
        );
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "my notes");
    }
    let hidden: Vec<_> = std::fs::read_dir(file.parent().unwrap())
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(hidden.is_empty(), "{hidden:?}");
}

/// A PID above Linux's largest (2^22), so no process has it.
const DEAD: u32 = 99_999_999;

#[test]
fn a_commit_killed_between_its_renames_is_recovered_on_the_next_read() {
    let dir = demo_copy("killed");
    let export = dir.join("export");
    // The state a kill between "export -> .export.old-PID" and ".export.tmp-PID -> export" leaves.
    let old = dir.join(format!(".export.old-{DEAD}"));
    std::fs::rename(&export, &old).unwrap();
    let tmp = dir.join(format!(".export.tmp-{DEAD}"));
    std::fs::create_dir_all(&tmp).unwrap();
    std::fs::write(tmp.join("half.json"), "{").unwrap();
    // Any read repairs it: the old folder, which the manifest describes, comes back.
    let o = common::scm_str(&["export", s(&dir)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("up to date"));
    assert!(export.join("export.json").is_file());
    assert!(!old.exists() && !tmp.exists());
    // And later rewrites work (the fixed `.old` name once made every one fail).
    let o = common::scm_str(&["export", s(&dir), "--force"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-") || n.contains(".old-"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_second_writer_waits_for_the_first_and_says_so() {
    use std::io::BufRead;
    let dir = demo_copy("lock");
    let lock = scm::urdd::WriterLock::take(&dir, || panic!("nobody else holds it")).unwrap();
    let stamp = || {
        std::fs::metadata(dir.join("export/export.json"))
            .unwrap()
            .modified()
            .unwrap()
    };
    let before = stamp();
    let mut child = Command::new(env!("CARGO_BIN_EXE_scm"))
        .args(["export", s(&dir), "--force"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read the child's stderr until it says it waits (a minute at most on a loaded machine).
    let (tx, rx) = std::sync::mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            let _ = tx.send(line);
        }
    });
    let said = rx
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("the second writer said nothing");
    assert!(said.contains("waiting: another scm is writing"), "{said}");
    // While it waits, nothing is rewritten.
    std::thread::sleep(std::time::Duration::from_millis(300));
    assert_eq!(stamp(), before);
    drop(lock);
    assert!(child.wait().unwrap().success());
    reader.join().unwrap();
    assert!(
        stamp() > before,
        "the export ran after the lock was released"
    );
}

#[test]
fn corrupt_or_missing_outputs_are_not_up_to_date() {
    let dir = demo_copy("corrupt");
    let demo_urdf = common::demo_urdf();
    /// (output file, its stage, what it becomes: new bytes, or deleted).
    type Case<'a> = (&'a str, &'a str, Option<&'a [u8]>);
    let cases: [Case; 4] = [
        ("export/demo_arm.srdf", "export", Some(b"")),
        ("export/matrices/hull.json", "export", Some(b"{}")),
        ("preprocess/links.json", "preprocess", None),
        ("sample/hull.json", "sample", Some(b"[1,")),
    ];
    for (file, stage, content) in cases {
        let path = dir.join(file);
        let before = std::fs::read(&path).unwrap();
        match content {
            Some(bytes) => std::fs::write(&path, bytes).unwrap(),
            None => std::fs::remove_file(&path).unwrap(),
        }
        let mut cmd: Vec<&str> = vec![stage];
        if stage == "preprocess" {
            cmd.push(s(&demo_urdf));
            cmd.extend(["-o", s(&dir)]);
        } else {
            cmd.push(s(&dir));
        }
        if stage == "sample" {
            cmd.extend(["-n", "500"]);
        }
        let o = common::scm_str(&cmd);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{file}: {stderr}");
        assert!(
            stderr.contains(&format!("rerunning {stage}: {file}")),
            "{file}: {stderr}"
        );
        assert_eq!(
            std::fs::read(&path).unwrap(),
            before,
            "{file} was not rewritten"
        );
    }
}

#[test]
fn numbers_scm_cannot_represent_are_rejected_at_the_element() {
    let dir = common::scratch("huge");
    for (attr, text) in [
        ("origin", r#"<origin xyz="1e308 0 0"/>"#),
        ("limit", r#"<limit lower="-1e308" upper="1e308"/>"#),
    ] {
        let (origin, limit) = if attr == "origin" {
            (text, r#"<limit lower="-1" upper="1"/>"#)
        } else {
            ("", text)
        };
        let urdf = dir.join(format!("{attr}.urdf"));
        std::fs::write(
            &urdf,
            format!(
                r#"<robot name="r"><link name="a"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
<link name="b"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/>{origin}<axis xyz="0 0 1"/>{limit}</joint></robot>"#
            ),
        )
        .unwrap();
        let o = common::scm_str(&["preprocess", s(&urdf), "-o", s(&dir.join("out"))]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains(&format!("<{attr}>")) && err.contains("beyond ±1e6"),
            "{err}"
        );
    }
}

#[test]
fn absurd_sample_and_thread_counts_are_bad_input_with_the_range() {
    let dir = demo_copy("absurd");
    for (flag, value, range) in [
        ("--samples", "1000000000000", "1..=1000000000"),
        ("--threads", "100000", "1..=1024"),
        ("--threads", "0", "1..=1024"),
        ("--certify-boxes", "0", "1..=1000000000"),
        ("--certify-total", "0", "1..=100000000000"),
        ("--certify-exact", "many", "invalid value"),
    ] {
        let o = common::scm_str(&["sample", s(&dir), flag, value]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(err.contains(flag) && err.contains(range), "{err}");
    }
    // An unknown link level names the valid ones, for export and diff.
    for (command, flag) in [("export", "--link-type"), ("diff", "--type")] {
        let o = common::scm_str(&[command, s(&dir), flag, "cylinder"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{command}: {err}");
        assert!(
            err.contains("unknown link level \"cylinder\" (mesh, or a shape type: sphere"),
            "{err}"
        );
    }
}

#[test]
fn import_counts_agree() {
    let dir = demo_copy("import-counts");
    let srdf = dir.parent().unwrap().join("twice.srdf");
    std::fs::write(
        &srdf,
        r#"<robot name="demo_arm">
  <disable_collisions link1="base_link" link2="link1" reason="Adjacent"/>
  <disable_collisions link1="link1" link2="base_link" reason="Adjacent"/>
  <disable_collisions link1="base_link" link2="no_such_link" reason="Never"/>
</robot>"#,
    )
    .unwrap();
    let o = common::scm_str(&["import-moveit", s(&srdf), s(&dir)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(
        line.contains("read 3 <disable_collisions>")
            && line.contains("Adjacent 2, Never 1")
            && line.contains("stored 1 distinct link pairs")
            && line.contains("2 warnings"),
        "{line}"
    );
}

#[test]
fn a_robot_record_whose_joints_form_a_cycle_is_an_error_naming_the_file() {
    let dir = demo_copy("cycle");
    let path = dir.join("preprocess/robot.json");
    let mut record: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    // Make the first joint's parent its own child's child: a loop that never reaches the root.
    let joints = record["robot"]["joints"].as_array().unwrap().clone();
    let (j0, j1) = (&joints[0], &joints[1]);
    record["robot"]["joints"][0]["parent"] = j1["child"].clone();
    assert_ne!(j0["child"], j1["child"]);
    std::fs::write(&path, serde_json::to_vec(&record).unwrap()).unwrap();
    let o = common::scm_str(&["inspect", s(&dir)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("robot.json") && err.contains("cycle"), "{err}");
}

#[test]
fn a_hand_broken_stage_summary_is_an_error_not_empty_counts() {
    let dir = demo_copy("summary");
    let path = dir.join("manifest.json");
    let mut manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
    manifest["stages"]["sample"]["summary"] = serde_json::json!("garbage");
    std::fs::write(&path, serde_json::to_vec(&manifest).unwrap()).unwrap();
    let o = common::scm_str(&["sample", s(&dir), "-n", "500"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("manifest.json") && err.contains("stages.sample.summary"),
        "{err}"
    );
}

#[test]
fn a_truncated_urdd_file_is_an_error_naming_it_never_empty_data() {
    // (file, the command that reads it): each truncated to half its bytes.
    let cases: [(&str, &[&str]); 6] = [
        ("manifest.json", &["export"]),
        ("layers/user.json", &["export"]),
        ("preprocess/robot.json", &["inspect"]),
        ("preprocess/shapes/hull.json", &["export", "--force"]),
        ("sample/mesh.json", &["diff", "--srdf", "SRDF"]),
        ("sample/hull.json", &["export", "--force"]),
    ];
    for (k, (file, command)) in cases.iter().enumerate() {
        let dir = demo_copy(&format!("truncated-{k}"));
        if *file == "layers/user.json" {
            let edit = r#"{"edits":[{"shape_type":"hull","a":{"link":"link1","piece":0},"b":{"link":"link3","piece":0},"skip":true}]}"#;
            std::fs::create_dir_all(dir.join("layers")).unwrap();
            std::fs::write(dir.join(file), edit).unwrap();
        }
        let path = dir.join(file);
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        let srdf = dir.join("export/demo_arm.srdf");
        let mut args: Vec<&str> = vec![command[0], s(&dir)];
        for a in &command[1..] {
            args.push(if *a == "SRDF" { s(&srdf) } else { a });
        }
        let o = common::scm_str(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{file}: {err}");
        assert_eq!(err.lines().count(), 1, "{file}: {err}");
        let name = Path::new(file).file_name().unwrap().to_str().unwrap();
        assert!(err.contains(name), "{file}: {err}");
    }
}

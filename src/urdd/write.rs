//! Atomic writes: single files by temp + rename, whole stage folders by building aside and swapping in.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, bytes).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::io(path, e)
    })
}

/// A path a stage makes a folder of must not be an existing file: that is bad input (exit 2), and the
/// file is left as it is.
pub fn ensure_not_file(path: &Path) -> Result<()> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_dir() => Err(Error::input(
            path,
            "output",
            "is an existing file, not a folder; give a folder path (the file is left untouched)",
        )),
        _ => Ok(()),
    }
}

/// Serialises `value` as pretty JSON with a final newline. A value JSON cannot hold is an error naming
/// `file` (the file it was for), never empty data.
pub fn json_bytes<T: serde::Serialize>(file: &str, value: &T) -> Result<Vec<u8>> {
    let mut bytes = serde_json::to_vec_pretty(value).map_err(|e| Error::Failed {
        context: file.to_string(),
        message: format!("cannot be written as JSON: {e}"),
    })?;
    bytes.push(b'\n');
    Ok(bytes)
}

/// A stage's output folder under construction. Files go to a hidden sibling folder; [`StageDir::commit`]
/// swaps it in place of the old one, so a failed or interrupted run leaves the old output untouched.
#[derive(Debug)]
pub struct StageDir {
    tmp: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl StageDir {
    /// Starts a new output for the folder `target`, first clearing what killed runs left beside it.
    pub fn create(target: &Path) -> Result<StageDir> {
        ensure_not_file(target)?;
        recover(target)?;
        let tmp = sibling(target, "tmp", std::process::id());
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp).map_err(|e| Error::io(&tmp, e))?;
        }
        std::fs::create_dir_all(&tmp).map_err(|e| Error::io(&tmp, e))?;
        Ok(StageDir {
            tmp,
            target: target.to_path_buf(),
            committed: false,
        })
    }

    /// Writes `bytes` at `relative` inside the stage folder.
    pub fn write(&self, relative: &str, bytes: &[u8]) -> Result<()> {
        let path = self.file(relative)?;
        std::fs::write(&path, bytes).map_err(|e| Error::io(&path, e))
    }

    /// The path of `relative` inside the stage folder, its folder created.
    fn file(&self, relative: &str) -> Result<PathBuf> {
        let path = self.tmp.join(relative);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        }
        Ok(path)
    }

    /// Writes `value` as compact JSON with a final newline at `relative` inside the stage folder,
    /// serialised straight into the file (a decomposition type's pair list is tens of MB). A value
    /// JSON cannot hold is an error naming `relative`; the stage is then not committed, so no file
    /// of it is ever read half written.
    pub fn write_json<T: serde::Serialize>(&self, relative: &str, value: &T) -> Result<()> {
        use std::io::Write;
        let path = self.file(relative)?;
        let file = std::fs::File::create(&path).map_err(|e| Error::io(&path, e))?;
        let mut out = std::io::BufWriter::with_capacity(1 << 16, file);
        serde_json::to_writer(&mut out, value).map_err(|e| match e.io_error_kind() {
            Some(_) => Error::io(&path, e.into()),
            None => super::layout::json_error(relative, e),
        })?;
        out.write_all(b"\n")
            .and_then(|()| out.flush())
            .map_err(|e| Error::io(&path, e))
    }

    /// Replaces the old folder with the new one: the old one is renamed aside (a name of this process's
    /// own), the new one renamed in, the old one removed. A kill between the two renames leaves the
    /// target missing and the old folder beside it; [`recover`] puts it back on the next run or read.
    pub fn commit(mut self) -> Result<()> {
        let old = sibling(&self.target, "old", std::process::id());
        if self.target.exists() {
            std::fs::rename(&self.target, &old).map_err(|e| Error::io(&self.target, e))?;
        }
        if let Err(e) = std::fs::rename(&self.tmp, &self.target) {
            let _ = std::fs::rename(&old, &self.target);
            return Err(Error::io(&self.target, e));
        }
        self.committed = true;
        if old.exists() {
            std::fs::remove_dir_all(&old).map_err(|e| Error::io(&old, e))?;
        }
        Ok(())
    }
}

/// `.NAME.KIND-PID` beside `target`: a stage folder under construction (`tmp`) or set aside (`old`).
fn sibling(target: &Path, kind: &str, pid: u32) -> PathBuf {
    let parent = target.parent().unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    parent.join(format!(".{name}.{kind}-{pid}"))
}

/// Whether process `pid` still runs (on Linux, by /proc; elsewhere every process is taken to run, so
/// nothing of another process is ever removed).
fn alive(pid: u32) -> bool {
    pid == std::process::id()
        || !Path::new("/proc/self").exists()
        || Path::new("/proc").join(pid.to_string()).exists()
}

/// Repairs what killed runs left beside the stage folder `target`: a folder set aside by a commit that
/// never finished comes back when the target is missing (it is the output the manifest describes: the
/// manifest is written after the commit) and is removed otherwise; half-built folders are removed.
/// Folders of processes that still run are left alone.
pub fn recover(target: &Path) -> Result<()> {
    let parent = target.parent().unwrap_or(Path::new("."));
    let Some(name) = target.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return Ok(());
    };
    let Ok(entries) = std::fs::read_dir(parent) else {
        return Ok(());
    };
    let mut leftovers: Vec<(String, u32, PathBuf)> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let file = e.file_name().to_string_lossy().into_owned();
            let rest = file.strip_prefix(&format!(".{name}."))?;
            let (kind, pid) = rest.split_once('-')?;
            let pid: u32 = pid.parse().ok()?;
            (matches!(kind, "tmp" | "old") && !alive(pid))
                .then(|| (kind.to_string(), pid, e.path()))
        })
        .collect();
    leftovers.sort();
    for (kind, _, path) in leftovers {
        if kind == "old" && !target.exists() {
            std::fs::rename(&path, target).map_err(|e| Error::io(target, e))?;
        } else {
            std::fs::remove_dir_all(&path).map_err(|e| Error::io(&path, e))?;
        }
    }
    Ok(())
}

/// The URDD's writer lock (`DIR/.lock`), held until dropped: two processes writing one URDD take
/// turns, so neither overwrites the other's manifest or folder.
#[derive(Debug)]
pub struct WriterLock {
    _file: std::fs::File,
}

impl WriterLock {
    /// Takes the lock of the URDD folder `dir`, which must exist; `waiting` is called once if another
    /// process holds it, before this one blocks until it is free.
    pub fn take(dir: &Path, waiting: impl FnOnce()) -> Result<WriterLock> {
        let path = dir.join(".lock");
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| Error::io(&path, e))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                waiting();
                file.lock().map_err(|e| Error::io(&path, e))?;
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(Error::io(&path, e)),
        }
        Ok(WriterLock { _file: file })
    }
}

impl Drop for StageDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.tmp);
        }
    }
}

#[cfg(test)]
mod json_tests {
    use super::{StageDir, json_bytes};
    use crate::urdd::{compact_json, sha256_file, sha256_hex};
    use std::collections::BTreeMap;

    #[test]
    fn stage_json_is_streamed_as_the_compact_bytes_and_hashed_as_they_are() {
        let root = std::env::temp_dir().join(format!("scm-write-json-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let target = root.join("sample");
        // Larger than the hash's read buffer, so the file is hashed in several pieces.
        let value: Vec<f64> = (0..40_000).map(|i| f64::from(i) / 7.0).collect();
        let stage = StageDir::create(&target).unwrap();
        stage.write_json("big.json", &value).unwrap();
        stage.commit().unwrap();
        let mut expected = compact_json("big.json", &value).unwrap();
        expected.push(b'\n');
        let written = std::fs::read(target.join("big.json")).unwrap();
        assert!(written.len() > 1 << 17, "{} bytes", written.len());
        assert_eq!(written, expected);
        let (len, hash) = sha256_file(&target.join("big.json")).unwrap();
        assert_eq!((len, hash), (expected.len() as u64, sha256_hex(&expected)));

        // A value JSON cannot hold names its file, and the output already there stays as it was.
        let stage = StageDir::create(&target).unwrap();
        let bad: BTreeMap<(u8, u8), u8> = [((1, 2), 3)].into();
        let err = stage.write_json("bad.json", &bad).unwrap_err().to_string();
        assert!(
            err.starts_with("bad.json: cannot be written as JSON"),
            "{err}"
        );
        drop(stage);
        assert_eq!(std::fs::read(target.join("big.json")).unwrap(), expected);
        assert!(!target.join("bad.json").exists());
        std::fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn a_value_json_cannot_hold_names_its_file() {
        let bad: BTreeMap<(u8, u8), u8> = [((1, 2), 3)].into();
        let err = json_bytes("manifest.json", &bad).unwrap_err().to_string();
        assert!(
            err.starts_with("manifest.json: cannot be written as JSON"),
            "{err}"
        );
        assert_eq!(json_bytes("x.json", &[1]).unwrap(), b"[\n  1\n]\n");
    }

    #[test]
    fn the_stage_key_text_is_the_pretty_serialisation() {
        let v = serde_json::json!({"b": [1, {"c": 2.5}], "a": "x"});
        let pretty = json_bytes("k", &v).unwrap();
        assert_eq!(format!("{v:#}\n").into_bytes(), pretty);
    }
}

//! Running a child process and measuring it: its wall time and its peak resident memory.
//!
//! The peak is the kernel's high-water mark of the child's resident set (`VmHWM` in
//! `/proc/<pid>/status`), read every [`POLL`] while the child runs: the mark only grows, so the last
//! reading is the peak up to that moment, and only an increase in the child's final [`POLL`] can be
//! missed. Where `/proc` does not exist (not Linux) the peak is unknown.

use crate::error::{Error, Result};
use serde::Serialize;
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How often the child's high-water mark is read.
pub const POLL: Duration = Duration::from_millis(5);

/// A child process that ran to success.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ChildRun {
    /// Wall time from spawn to exit (s).
    pub seconds: f64,
    /// Peak resident memory (bytes); `None` where it cannot be read.
    pub peak_bytes: Option<u64>,
}

/// Runs `command` (stdin and stdout closed, stderr captured) to its end and measures it. A child that
/// cannot start or exits unsuccessfully is a failure quoting the end of its stderr.
pub fn run_measured(command: &mut Command) -> Result<ChildRun> {
    let what = format!("{command:?}");
    let failed = |message: String| Error::Failed {
        context: what.clone(),
        message,
    };
    let start = Instant::now();
    let mut child = command
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| failed(format!("cannot start: {e}")))?;
    // Drained on its own thread, so a chatty child never blocks on a full pipe.
    let mut stderr = child.stderr.take().expect("stderr is piped");
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let status_file = Path::new("/proc")
        .join(child.id().to_string())
        .join("status");
    let mut peak = None;
    let status = loop {
        if let Some(kib) = high_water_kib(&status_file) {
            peak = peak.max(Some(kib * 1024));
        }
        match child.try_wait() {
            Ok(Some(status)) => break status,
            Ok(None) => std::thread::sleep(POLL),
            Err(e) => return Err(failed(format!("cannot wait: {e}"))),
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    let stderr = reader.join().unwrap_or_default();
    if !status.success() {
        let tail: Vec<&str> = stderr.lines().rev().take(5).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(failed(format!("{status}: {}", tail.join("\n"))));
    }
    Ok(ChildRun {
        seconds,
        peak_bytes: peak,
    })
}

/// The `VmHWM` line of a `/proc/<pid>/status` file (KiB), or `None` when the file or line is missing
/// (the child has exited, or this is not Linux).
fn high_water_kib(status_file: &Path) -> Option<u64> {
    let text = std::fs::read_to_string(status_file).ok()?;
    parse_high_water(&text)
}

/// The value of the `VmHWM:` line of a status text, in KiB.
fn parse_high_water(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line["VmHWM:".len()..]
        .trim()
        .strip_suffix("kB")?
        .trim()
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_high_water_mark() {
        let status = "Name:\tscm\nVmPeak:\t  300 kB\nVmHWM:\t   12345 kB\nVmRSS:\t 100 kB\n";
        assert_eq!(parse_high_water(status), Some(12345));
        assert_eq!(parse_high_water("Name:\tzombie\n"), None);
    }

    #[test]
    fn a_failing_child_is_an_error_with_its_stderr() {
        let mut c = Command::new("sh");
        c.args(["-c", "echo broken >&2; exit 3"]);
        let e = run_measured(&mut c).unwrap_err().to_string();
        assert!(e.contains("broken"), "{e}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn measures_a_child_that_runs() {
        let mut c = Command::new("sh");
        c.args(["-c", "sleep 0.05"]);
        let run = run_measured(&mut c).unwrap();
        assert!(run.seconds >= 0.05);
        assert!(run.peak_bytes.is_some_and(|b| b > 0));
    }
}

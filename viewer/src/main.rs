//! scm-viewer: `scm-viewer URDD_DIR [--script ACTIONS.txt] [--size WxH]`, the binary `scm view` launches.

use scm_viewer::{ViewerOptions, run};
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: scm-viewer URDD_DIR [--script ACTIONS.txt] [--size WIDTHxHEIGHT]";

/// The parsed command line.
fn parse(args: &[String]) -> Result<(PathBuf, ViewerOptions), String> {
    let mut dir = None;
    let mut options = ViewerOptions::default();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--script" => {
                let v = it.next().ok_or("--script needs a file")?;
                options.script = Some(PathBuf::from(v));
            }
            "--size" => {
                let v = it.next().ok_or("--size needs WIDTHxHEIGHT")?;
                let (w, h) = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
                    .filter(|&(w, h): &(u32, u32)| w >= 320 && h >= 240)
                    .ok_or_else(|| {
                        format!("--size: \"{v}\" is not WIDTHxHEIGHT (at least 320x240)")
                    })?;
                options.window = (w, h);
            }
            "-h" | "--help" => return Err(String::new()),
            flag if flag.starts_with('-') => return Err(format!("unknown flag {flag}")),
            path if dir.is_none() => dir = Some(PathBuf::from(path)),
            extra => return Err(format!("unexpected argument \"{extra}\"")),
        }
    }
    Ok((dir.ok_or("missing URDD_DIR")?, options))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (dir, options) = match parse(&args) {
        Ok(p) => p,
        Err(e) if e.is_empty() => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("scm-viewer: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    match run(&dir, options) {
        Ok(bevy::app::AppExit::Success) => ExitCode::SUCCESS,
        Ok(bevy::app::AppExit::Error(code)) => ExitCode::from(code.get()),
        Err(e) => {
            eprintln!("scm-viewer: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

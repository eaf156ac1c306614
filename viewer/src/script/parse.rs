//! Reading action scripts: one action per line (`#` after whitespace or at the start begins a comment;
//! `link#2` names a piece), every line checked against the loaded URDD before the window opens. Plain
//! Rust; the script plugin ([`super::ScriptPlugin`]) plays them frame by frame.
//!
//! ```text
//! home | random SEED | joint NAME VALUE | config V1 .. Vn | witness
//! type ID | originals on|off | sort current|ratio|dmin | filter [WORDS..] | compact on|off
//! select SHAPE SHAPE | select-closest | deselect          (SHAPE: link or link#piece)
//! matrix on|off|type|exported | pieces LINK LINK | frame | look X Y Z DISTANCE
//! skip | check | unmark | skip-below METRES | skip-below-selected | skip-ratio-below R
//! undo | redo | save | screenshot FILE.png
//! ```

use crate::model::Model;
use crate::pairs::list::{SortKey, find_pair};
use scm::error::{Error, Result};
use scm::shapes::ShapeType;
use std::path::{Path, PathBuf};

/// One scripted action (what a person could do with the panels).
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Every joint to its home value.
    Home,
    /// A random configuration from this seed.
    Random(u64),
    /// One joint (by name) to a value (clamped to its limits).
    Joint(String, f64),
    /// The whole configuration, one value per DOF.
    Config(Vec<f64>),
    /// The selected pair's witness configuration.
    Witness,
    /// Select a shape type.
    Type(ShapeType),
    /// Show or hide the original meshes.
    Originals(bool),
    /// Sort the pair list.
    Sort(SortKey),
    /// Filter the pair list.
    Filter(String),
    /// Write pair names compactly (shared prefix and suffix once) or in full.
    Compact(bool),
    /// Close the matrix window (`None`) or open it on the type's verdicts (`Some(false)`) or the
    /// exported files' (`Some(true)`).
    Matrix(Option<bool>),
    /// Open the piece grid of two links in the matrix window.
    Pieces(String, String),
    /// Point the camera at the selected pair.
    Frame,
    /// Point the camera at a point of the robot's root frame (x, y, z in m) from a distance (m).
    Look([f64; 3], f64),
    /// Select the pair of two shapes (`link` or `link#piece`).
    Select(String, String),
    /// Select the pair with the smallest current distance among the checked pairs.
    SelectClosest,
    /// Clear the selection.
    Deselect,
    /// Mark the selected pair skipped.
    Skip,
    /// Mark the selected pair checked.
    Check,
    /// Remove the selected pair's mark.
    Unmark,
    /// Skip every pair closer than this many metres.
    SkipBelow(f64),
    /// Skip every pair at most as far apart as the selected pair.
    SkipBelowSelected,
    /// Skip every pair whose `d / d_mean` is below this.
    SkipRatioBelow(f64),
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Save the user layer and re-run the export.
    Save,
    /// Write a PNG screenshot of the window.
    Screenshot(PathBuf),
}

/// A parsed script: actions with their line numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Script {
    /// The script file (for messages).
    pub path: PathBuf,
    /// `(line, action)` in order.
    pub actions: Vec<(usize, Action)>,
}

impl Script {
    /// Reads and parses `path`; a bad line is bad input naming the line.
    pub fn load(path: &Path) -> Result<Script> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        Script::parse(path, &text)
    }

    /// Parses `text` (read from `path`).
    pub fn parse(path: &Path, text: &str) -> Result<Script> {
        let mut actions = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = strip_comment(raw).trim();
            if line.is_empty() {
                continue;
            }
            let action = parse_line(line).map_err(|m| Error::input(path, line_label(i + 1), m))?;
            actions.push((i + 1, action));
        }
        Ok(Script {
            path: path.to_path_buf(),
            actions,
        })
    }

    /// Checks every action against `model`: joint and shape names exist, the type was sampled, and an
    /// action on the selected pair has one selected. Returns the first problem, naming its line.
    pub fn check(&self, model: &Model) -> Result<()> {
        let mut t = model.types[0].shape_type;
        let mut selected = false;
        for (line, action) in &self.actions {
            let fail = |m: String| Err(Error::input(&self.path, line_label(*line), m));
            let data = model.sampled(t);
            match action {
                Action::Joint(name, _) if !model.dofs().iter().any(|d| &d.name == name) => {
                    return fail(format!("no joint \"{name}\" among the robot's DOFs"));
                }
                Action::Config(q) if q.len() != model.dofs().len() => {
                    return fail(format!(
                        "{} values, the robot has {} DOFs",
                        q.len(),
                        model.dofs().len()
                    ));
                }
                Action::Type(new) => {
                    if model.sampled(*new).is_none() {
                        return fail(format!("type {new} was not sampled in this URDD"));
                    }
                    t = *new;
                    selected = false;
                }
                Action::Select(a, b) => {
                    let found = data.and_then(|d| find_pair(&d.matrix, a, b));
                    if found.is_none() {
                        return fail(format!("no {t} pair of shapes \"{a}\" and \"{b}\""));
                    }
                    selected = true;
                }
                Action::SelectClosest => selected = true,
                Action::Deselect => selected = false,
                Action::Pieces(a, b) => {
                    let pieces =
                        data.is_some_and(|d| d.shape_type.scope() == scm::shapes::Scope::Pieces);
                    let found = data.and_then(|d| scm::matrix::HeatMap::pieces(&d.matrix, a, b));
                    if !pieces || found.is_none() {
                        return fail(format!("no {t} piece grid of links \"{a}\" and \"{b}\""));
                    }
                }
                Action::Witness
                | Action::Frame
                | Action::Skip
                | Action::Check
                | Action::Unmark
                | Action::SkipBelowSelected
                    if !selected =>
                {
                    return fail("needs a selected pair (use `select` first)".into());
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// The line without its comment: from a `#` at the start or after whitespace (`link#2` is a name).
fn strip_comment(line: &str) -> &str {
    let mut prev_space = true;
    for (i, c) in line.char_indices() {
        if c == '#' && prev_space {
            return &line[..i];
        }
        prev_space = c.is_whitespace();
    }
    line
}

/// `line N`, the element of a script error.
fn line_label(n: usize) -> String {
    format!("line {n}")
}

/// `on` or `off` for `verb`.
fn on_off(verb: &str, arg: &str) -> std::result::Result<bool, String> {
    match arg {
        "on" => Ok(true),
        "off" => Ok(false),
        other => Err(format!("`{verb}` takes on or off, got \"{other}\"")),
    }
}

/// One action from a non-empty line.
fn parse_line(line: &str) -> std::result::Result<Action, String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let (verb, args) = (words[0], &words[1..]);
    let arity = |n: usize| {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!(
                "`{verb}` takes {n} argument(s), got {}",
                args.len()
            ))
        }
    };
    let number = |s: &str| {
        s.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("`{verb}`: \"{s}\" is not a finite number"))
    };
    Ok(match verb {
        "home" => arity(0).map(|_| Action::Home)?,
        "random" => {
            arity(1)?;
            let seed = args[0]
                .parse()
                .map_err(|_| format!("`random`: \"{}\" is not a seed (an integer)", args[0]))?;
            Action::Random(seed)
        }
        "joint" => {
            arity(2)?;
            Action::Joint(args[0].to_string(), number(args[1])?)
        }
        "config" => Action::Config(args.iter().map(|s| number(s)).collect::<Result<_, _>>()?),
        "witness" => arity(0).map(|_| Action::Witness)?,
        "type" => {
            arity(1)?;
            let ids: Vec<&str> = ShapeType::ALL.iter().map(|t| t.id()).collect();
            Action::Type(ShapeType::from_id(args[0]).ok_or_else(|| {
                format!("unknown type \"{}\" (one of {})", args[0], ids.join(", "))
            })?)
        }
        "originals" => {
            arity(1)?;
            Action::Originals(on_off(verb, args[0])?)
        }
        "sort" => {
            arity(1)?;
            Action::Sort(SortKey::from_id(args[0]).ok_or_else(|| {
                format!("unknown sort key \"{}\" (current, ratio, dmin)", args[0])
            })?)
        }
        "filter" => Action::Filter(args.join(" ")),
        "compact" => {
            arity(1)?;
            Action::Compact(on_off(verb, args[0])?)
        }
        "matrix" => {
            arity(1)?;
            Action::Matrix(match args[0] {
                "off" => None,
                "on" | "type" => Some(false),
                "exported" => Some(true),
                other => {
                    return Err(format!(
                        "`matrix` takes on, off, type or exported, got \"{other}\""
                    ));
                }
            })
        }
        "pieces" => {
            arity(2)?;
            Action::Pieces(args[0].to_string(), args[1].to_string())
        }
        "frame" => arity(0).map(|_| Action::Frame)?,
        "look" => {
            arity(4)?;
            let distance = number(args[3])?;
            if distance <= 0.0 {
                return Err(format!(
                    "`look`: the distance must be positive, got {distance}"
                ));
            }
            Action::Look(
                [number(args[0])?, number(args[1])?, number(args[2])?],
                distance,
            )
        }
        "select" => {
            arity(2)?;
            Action::Select(args[0].to_string(), args[1].to_string())
        }
        "select-closest" => arity(0).map(|_| Action::SelectClosest)?,
        "deselect" => arity(0).map(|_| Action::Deselect)?,
        "skip" => arity(0).map(|_| Action::Skip)?,
        "check" => arity(0).map(|_| Action::Check)?,
        "unmark" => arity(0).map(|_| Action::Unmark)?,
        "skip-below" => {
            arity(1)?;
            Action::SkipBelow(number(args[0])?)
        }
        "skip-below-selected" => arity(0).map(|_| Action::SkipBelowSelected)?,
        "skip-ratio-below" => {
            arity(1)?;
            Action::SkipRatioBelow(number(args[0])?)
        }
        "undo" => arity(0).map(|_| Action::Undo)?,
        "redo" => arity(0).map(|_| Action::Redo)?,
        "save" => arity(0).map(|_| Action::Save)?,
        "screenshot" => {
            arity(1)?;
            if !args[0].to_ascii_lowercase().ends_with(".png") {
                return Err(format!("`screenshot`: \"{}\" must end in .png", args[0]));
            }
            Action::Screenshot(PathBuf::from(args[0]))
        }
        other => return Err(format!("unknown action \"{other}\"")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Script> {
        Script::parse(Path::new("s.txt"), text)
    }

    #[test]
    fn parses_every_action_with_line_numbers() {
        let s = parse(
            "# demo\nhome\njoint j1 0.5\nconfig 0 1.5 -2\ntype decomp-hull\n\nselect a b#2 # pair\n\
             skip\nskip-below 0.01\nskip-ratio-below 0.3\nsort dmin\nfilter link 3\nscreenshot x.png\nsave\n\
             matrix exported\nmatrix off\nframe\nlook 0 0 0.5 1.2\ncompact on\npieces a b\n",
        )
        .unwrap();
        let lines: Vec<usize> = s.actions.iter().map(|(l, _)| *l).collect();
        assert_eq!(
            lines,
            vec![
                2, 3, 4, 5, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20
            ]
        );
        assert_eq!(s.actions[12].1, Action::Matrix(Some(true)));
        assert_eq!(s.actions[13].1, Action::Matrix(None));
        assert_eq!(s.actions[15].1, Action::Look([0.0, 0.0, 0.5], 1.2));
        assert_eq!(s.actions[16].1, Action::Compact(true));
        assert_eq!(s.actions[1].1, Action::Joint("j1".into(), 0.5));
        assert_eq!(s.actions[2].1, Action::Config(vec![0.0, 1.5, -2.0]));
        assert_eq!(s.actions[3].1, Action::Type(ShapeType::DecompHull));
        assert_eq!(s.actions[4].1, Action::Select("a".into(), "b#2".into()));
        assert_eq!(s.actions[9].1, Action::Filter("link 3".into()));
    }

    #[test]
    fn a_bad_line_is_bad_input_naming_file_and_line() {
        for (text, needle) in [
            ("home\nfly away\n", "line 2: unknown action \"fly\""),
            ("type cube\n", "line 1: unknown type \"cube\""),
            (
                "joint j1 x\n",
                "line 1: `joint`: \"x\" is not a finite number",
            ),
            ("skip now\n", "line 1: `skip` takes 0 argument(s), got 1"),
            ("screenshot a.jpg\n", "must end in .png"),
            ("joint j1 NaN\n", "not a finite number"),
            ("matrix big\n", "`matrix` takes on, off, type or exported"),
            ("look 0 0 0 -1\n", "distance must be positive"),
            ("compact yes\n", "`compact` takes on or off"),
        ] {
            let e = parse(text).unwrap_err();
            assert_eq!(e.exit_code(), 2);
            let msg = e.to_string();
            assert!(msg.starts_with("s.txt: "), "{msg}");
            assert!(msg.contains(needle), "{msg}");
        }
    }
}

//! The script player: a small state machine that runs a script's actions one at a time, a few frames
//! apart so the app can follow, waits for each screenshot to be written, and says when to exit. Plain
//! Rust over the [`Controls`] it drives: the app in the script plugin ([`super::ScriptPlugin`]), a
//! recording in the tests.

use super::parse::{Action, Script};
use std::path::{Path, PathBuf};

/// Frames before the first action (window, meshes and egui's layout settle).
pub const WARM_UP: u32 = 10;
/// Frames after each action, so derived state, materials and panels follow.
pub const SETTLE: u32 = 3;
/// Frames before a screenshot is taken.
pub const BEFORE_SHOT: u32 = 6;
/// Frames to wait for a screenshot to be written before giving up.
pub const SHOT_TIMEOUT: u32 = 600;

/// What the player drives.
pub trait Controls {
    /// Applies `action` (any but a screenshot); a message if it cannot apply now.
    fn perform(&mut self, action: Action) -> Result<(), String>;
    /// Starts capturing the window into `path`.
    fn shoot(&mut self, path: &Path);
    /// The capture into `path` once it is written (or failed); `None` while it is in flight.
    fn shot(&mut self, path: &Path) -> Option<Result<(), String>>;
}

/// Where the player stands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Phase {
    /// Frames (at least one) to wait before the next action: the warm-up, or letting the last action
    /// settle (longer before a screenshot).
    Settling(u32),
    /// The next action runs this frame.
    Ready,
    /// A screenshot into `path` is in flight, for `frames` frames so far.
    Shooting {
        /// The PNG file.
        path: PathBuf,
        /// Frames waited.
        frames: u32,
    },
    /// Every action ran: exit 0.
    Done,
    /// Stopped with this exit code (the reason is on stderr).
    Failed(u8),
}

impl Phase {
    /// Waiting `frames` frames, or ready now.
    fn settling(frames: u32) -> Phase {
        match frames {
            0 => Phase::Ready,
            n => Phase::Settling(n),
        }
    }
}

/// A script being played.
#[derive(Debug)]
pub struct Player {
    script: Script,
    next: usize,
    phase: Phase,
}

impl Player {
    /// Starts `script`: its first action runs after the warm-up.
    pub fn new(script: Script) -> Player {
        Player {
            script,
            next: 0,
            phase: Phase::settling(WARM_UP),
        }
    }

    /// Where the player stands.
    pub fn phase(&self) -> &Phase {
        &self.phase
    }

    /// Plays one frame on `controls`. Returns the exit code once, in the frame the script ends (0
    /// when every action succeeded, 2 for an action that cannot apply, 1 for a failed screenshot).
    pub fn frame(&mut self, controls: &mut impl Controls) -> Option<u8> {
        self.phase = match std::mem::replace(&mut self.phase, Phase::Ready) {
            Phase::Settling(n) => Phase::settling(n - 1),
            Phase::Ready => self.run_next(controls),
            Phase::Shooting { path, frames } => self.await_shot(path, frames, controls),
            // Already ended: the exit code was returned in the frame it did.
            over @ (Phase::Done | Phase::Failed(_)) => {
                self.phase = over;
                return None;
            }
        };
        self.exit_code()
    }

    /// Stops the script because the app failed (a save, say; the caller reports why). Returns the
    /// exit code (1), unless the script already ended.
    pub fn abort(&mut self) -> Option<u8> {
        match self.phase {
            Phase::Done | Phase::Failed(_) => None,
            _ => {
                self.phase = Phase::Failed(1);
                self.exit_code()
            }
        }
    }

    /// The exit code if the script has ended.
    fn exit_code(&self) -> Option<u8> {
        match self.phase {
            Phase::Done => Some(0),
            Phase::Failed(code) => Some(code),
            _ => None,
        }
    }

    /// Runs the next action (a screenshot starts capturing), or ends the script after the last.
    fn run_next(&mut self, controls: &mut impl Controls) -> Phase {
        let Some((line, action)) = self.script.actions.get(self.next).cloned() else {
            return Phase::Done;
        };
        self.next += 1;
        if let Action::Screenshot(path) = action {
            controls.shoot(&path);
            return Phase::Shooting { path, frames: 0 };
        }
        if let Err(message) = controls.perform(action) {
            let file = self.script.path.display();
            eprintln!("scm-viewer: {file}: line {line}: {message}");
            return Phase::Failed(2);
        }
        match self.script.actions.get(self.next) {
            Some((_, Action::Screenshot(_))) => Phase::settling(BEFORE_SHOT),
            _ => Phase::settling(SETTLE),
        }
    }

    /// Waits for the screenshot into `path`; once written, the next action runs in the same frame.
    fn await_shot(&mut self, path: PathBuf, frames: u32, controls: &mut impl Controls) -> Phase {
        match controls.shot(&path) {
            Some(Ok(())) => {
                eprintln!("scm-viewer: wrote {}", path.display());
                self.run_next(controls)
            }
            Some(Err(e)) => {
                eprintln!("scm-viewer: screenshot {}: {e}", path.display());
                Phase::Failed(1)
            }
            None if frames < SHOT_TIMEOUT => Phase::Shooting {
                path,
                frames: frames + 1,
            },
            None => {
                let path = path.display();
                eprintln!(
                    "scm-viewer: screenshot {path}: not captured after {SHOT_TIMEOUT} frames"
                );
                Phase::Failed(1)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Controls that record what happens in which frame.
    #[derive(Default)]
    struct Recorder {
        /// The current frame (1 is the first).
        frame: u32,
        /// `(frame, event)`.
        log: Vec<(u32, String)>,
        /// Frames a screenshot takes to be written (`None`: it never is).
        shot_takes: Option<u32>,
        /// The frame of the last `shoot`.
        shot_at: u32,
    }

    impl Controls for Recorder {
        fn perform(&mut self, action: Action) -> Result<(), String> {
            self.log.push((self.frame, format!("{action:?}")));
            match action {
                Action::Undo => Err("cannot".into()),
                _ => Ok(()),
            }
        }

        fn shoot(&mut self, path: &Path) {
            self.shot_at = self.frame;
            self.log
                .push((self.frame, format!("shoot {}", path.display())));
        }

        fn shot(&mut self, _: &Path) -> Option<Result<(), String>> {
            let takes = self.shot_takes?;
            (self.frame >= self.shot_at + takes).then_some(Ok(()))
        }
    }

    /// Plays `text` for at most `frames` frames; the frame and code of the exit, if any, and the log.
    fn play(text: &str, shot_takes: Option<u32>, frames: u32) -> (Option<(u32, u8)>, Recorder) {
        let script = Script::parse(Path::new("s.txt"), text).expect("a valid script");
        let mut player = Player::new(script);
        let mut rec = Recorder {
            shot_takes,
            ..Recorder::default()
        };
        let mut exit = None;
        for _ in 0..frames {
            rec.frame += 1;
            if let Some(code) = player.frame(&mut rec) {
                assert!(exit.is_none(), "a second exit in frame {}", rec.frame);
                exit = Some((rec.frame, code));
            }
        }
        (exit, rec)
    }

    #[test]
    fn actions_run_after_the_warm_up_and_settle_longer_before_a_screenshot() {
        let (exit, rec) = play("home\nframe\nscreenshot a.png\ndeselect\n", Some(2), 100);
        let home = WARM_UP + 1;
        let frame = home + SETTLE + 1;
        let shoot = frame + BEFORE_SHOT + 1;
        // Written two frames after the shot; the next action runs in that frame.
        let deselect = shoot + 2;
        let events: Vec<(u32, &str)> = rec.log.iter().map(|(f, e)| (*f, e.as_str())).collect();
        assert_eq!(
            events,
            vec![
                (home, "Home"),
                (frame, "Frame"),
                (shoot, "shoot a.png"),
                (deselect, "Deselect")
            ]
        );
        assert_eq!(exit, Some((deselect + SETTLE + 1, 0)));
    }

    #[test]
    fn an_action_that_cannot_apply_exits_2_and_stops_the_script() {
        let (exit, rec) = play("home\nundo\nhome\n", None, 100);
        assert_eq!(exit, Some((WARM_UP + SETTLE + 2, 2)));
        assert_eq!(rec.log.len(), 2);
    }

    #[test]
    fn a_screenshot_never_written_fails_after_the_timeout() {
        let (exit, _) = play("screenshot a.png\n", None, 2 * SHOT_TIMEOUT);
        assert_eq!(exit, Some((WARM_UP + 1 + SHOT_TIMEOUT + 1, 1)));
    }

    #[test]
    fn an_abort_ends_the_script_once() {
        let script = Script::parse(Path::new("s.txt"), "home\n").expect("a valid script");
        let mut player = Player::new(script);
        assert_eq!(player.abort(), Some(1));
        assert_eq!(player.abort(), None);
        assert_eq!(player.frame(&mut Recorder::default()), None);
        assert_eq!(player.phase(), &Phase::Failed(1));
    }
}

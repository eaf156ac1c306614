//! Script plugin: plays an action script frame by frame through the same resources and edit requests
//! as the panels, writes screenshots, and exits (0 when every action succeeded).

pub mod parse;

use crate::camera::{FrameRequest, Orbit};
use crate::edit::editor::Edit;
use crate::edit::{EditRequest, Editing};
use crate::joint_panel::random_configuration;
use crate::matrix_view::MatrixView;
use crate::pairs::PairView;
use crate::pairs::list::find_pair;
use crate::state::{Distances, Joints, Selection, Settings, Viewer};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::winit::WinitSettings;
use parse::{Action, Script};
use std::path::PathBuf;

/// Plays a script, then exits. Runs the app continuously (the script needs frames without input).
pub struct ScriptPlugin(pub Script);

impl Plugin for ScriptPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(WinitSettings::continuous())
            .insert_resource(Player {
                script: self.0.clone(),
                next: 0,
                wait: WARM_UP,
                shot: Shot::None,
            })
            .add_systems(Update, play_script);
    }
}

/// Frames before the first action (window, meshes and egui's layout settle).
const WARM_UP: u32 = 10;
/// Frames after each action, so derived state, materials and panels follow.
const SETTLE: u32 = 3;
/// Frames before a screenshot is taken.
const BEFORE_SHOT: u32 = 6;
/// Frames to wait for a screenshot to be written before giving up.
const SHOT_TIMEOUT: u32 = 600;

/// Where the player stands.
#[derive(Resource)]
struct Player {
    script: Script,
    next: usize,
    wait: u32,
    shot: Shot,
}

/// A screenshot in flight.
enum Shot {
    None,
    Waiting { path: PathBuf, frames: u32 },
}

/// Set by the screenshot observer once the file is written (or failed).
#[derive(Resource)]
struct ShotDone(Result<PathBuf, String>);

#[allow(clippy::too_many_arguments)]
fn play_script(
    mut commands: Commands,
    mut player: ResMut<Player>,
    done: Option<Res<ShotDone>>,
    viewer: Res<Viewer>,
    mut joints: ResMut<Joints>,
    mut settings: ResMut<Settings>,
    mut view: ResMut<PairView>,
    mut selection: ResMut<Selection>,
    distances: Res<Distances>,
    editing: Res<Editing>,
    (mut matrix, mut frame, mut orbits): (
        ResMut<MatrixView>,
        ResMut<FrameRequest>,
        Query<&mut Orbit>,
    ),
    mut requests: MessageWriter<EditRequest>,
    mut exit: MessageWriter<AppExit>,
) {
    if let Some(e) = &editing.error {
        eprintln!("scm-viewer: {e}");
        exit.write(AppExit::error());
        return;
    }
    if let Shot::Waiting { path, frames } = &mut player.shot {
        match done.as_deref() {
            Some(ShotDone(Ok(p))) if p == path => {
                eprintln!("scm-viewer: wrote {}", p.display());
                commands.remove_resource::<ShotDone>();
                player.shot = Shot::None;
            }
            Some(ShotDone(Err(e))) => {
                eprintln!("scm-viewer: screenshot {}: {e}", path.display());
                exit.write(AppExit::error());
                return;
            }
            _ => {
                *frames += 1;
                if *frames > SHOT_TIMEOUT {
                    eprintln!(
                        "scm-viewer: screenshot {}: not captured after {SHOT_TIMEOUT} frames",
                        path.display()
                    );
                    exit.write(AppExit::error());
                }
                return;
            }
        }
    }
    if player.wait > 0 {
        player.wait -= 1;
        return;
    }
    let Some((line, action)) = player.script.actions.get(player.next).cloned() else {
        exit.write(AppExit::Success);
        return;
    };
    if let Action::Screenshot(path) = &action {
        player.next += 1;
        let target = path.clone();
        commands.spawn(Screenshot::primary_window()).observe(
            move |captured: On<ScreenshotCaptured>, mut commands: Commands| {
                commands.insert_resource(ShotDone(save_png(&captured.image, &target)));
            },
        );
        player.shot = Shot::Waiting {
            path: path.clone(),
            frames: 0,
        };
        return;
    }
    player.next += 1;
    player.wait = match player.script.actions.get(player.next) {
        Some((_, Action::Screenshot(_))) => BEFORE_SHOT,
        _ => SETTLE,
    };
    let model = &viewer.0;
    let data = model.sampled(settings.shape_type);
    let fail = |exit: &mut MessageWriter<AppExit>, message: &str| {
        eprintln!(
            "scm-viewer: {}: line {line}: {message}",
            player.script.path.display()
        );
        exit.write(AppExit::from_code(2));
    };
    match action {
        Action::Home => joints.q = model.kinematics.home(),
        Action::Random(seed) => joints.q = random_configuration(model.dofs(), seed),
        Action::Joint(name, value) => {
            if let Some(i) = model.dofs().iter().position(|d| d.name == name) {
                let d = &model.dofs()[i];
                joints.q[i] = value.clamp(d.lower, d.upper);
            }
        }
        Action::Config(mut q) => {
            crate::model::clamp(model.dofs(), &mut q);
            joints.q = q;
        }
        Action::Witness => {
            if let (Some(p), Some(d)) = (selection.0, data) {
                let w = &d.matrix.stats[p].witness.q;
                if w.len() == model.dofs().len() {
                    joints.q = w.clone();
                    frame.0 = true;
                } else {
                    fail(&mut exit, "the selected pair has no witness configuration");
                }
            }
        }
        Action::Type(t) => settings.shape_type = t,
        Action::Originals(on) => settings.originals = on,
        Action::Sort(k) => view.sort = k,
        Action::Filter(f) => view.filter = f,
        Action::Compact(on) => view.compact = on,
        Action::Matrix(exported) => {
            matrix.open = exported.is_some();
            matrix.exported = exported.unwrap_or(false);
        }
        Action::Pieces(a, b) => {
            matrix.open = true;
            matrix.pieces = Some((a, b));
        }
        Action::Frame => frame.0 = true,
        Action::Look(p, distance) => {
            let focus = crate::scene::to_world(scm::math::Vec3::new(p[0], p[1], p[2]));
            for mut orbit in &mut orbits {
                orbit.focus = focus;
                orbit.distance = distance as f32;
            }
        }
        Action::Select(a, b) => match data.and_then(|d| find_pair(&d.matrix, &a, &b)) {
            Some(p) => selection.0 = Some(p),
            None => fail(&mut exit, &format!("no pair of \"{a}\" and \"{b}\"")),
        },
        Action::SelectClosest => {
            let best = data.and_then(|d| {
                (0..d.pair_count())
                    .filter(|&p| !d.matrix.entries[p].skip)
                    .filter_map(|p| distances.0.get(p).map(|&x| (x, p)))
                    .min_by(|x, y| x.0.total_cmp(&y.0))
            });
            match best {
                Some((_, p)) => selection.0 = Some(p),
                None => fail(&mut exit, "the selected type has no checked pair"),
            }
        }
        Action::Deselect => selection.0 = None,
        Action::Skip | Action::Check | Action::Unmark | Action::SkipBelowSelected => {
            let Some(pair) = selection.0 else {
                fail(&mut exit, "needs a selected pair");
                return;
            };
            let edit = match action {
                Action::Skip => Edit::Mark { pair, skip: true },
                Action::Check => Edit::Mark { pair, skip: false },
                Action::Unmark => Edit::Unmark { pair },
                _ => Edit::SkipCloser {
                    below: distances.0.get(pair).copied().unwrap_or(f64::NEG_INFINITY),
                    inclusive: true,
                },
            };
            requests.write(EditRequest::Apply(edit));
        }
        Action::SkipBelow(below) => {
            requests.write(EditRequest::Apply(Edit::SkipCloser {
                below,
                inclusive: false,
            }));
        }
        Action::SkipRatioBelow(below) => {
            requests.write(EditRequest::Apply(Edit::SkipRatio { below }));
        }
        Action::Undo => {
            requests.write(EditRequest::Undo);
        }
        Action::Redo => {
            requests.write(EditRequest::Redo);
        }
        Action::Save => {
            requests.write(EditRequest::Save);
        }
        Action::Screenshot(_) => {}
    }
}

/// Writes a captured window image as PNG (through a temporary file, so a reader never sees half a
/// file).
fn save_png(image: &Image, path: &std::path::Path) -> Result<PathBuf, String> {
    let rgb = image
        .clone()
        .try_into_dynamic()
        .map_err(|e| e.to_string())?
        .to_rgb8();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    }
    let tmp = path.with_extension("tmp.png");
    rgb.save(&tmp).map_err(|e| e.to_string())?;
    std::fs::rename(&tmp, path).map_err(|e| e.to_string())?;
    Ok(path.to_path_buf())
}

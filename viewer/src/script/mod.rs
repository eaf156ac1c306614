//! Script plugin: plays an action script frame by frame through the same resources and edit requests
//! as the panels, writes screenshots, and exits (0 when every action succeeded). [`parse`] reads the
//! script, [`player`] is the state machine that paces it; this module applies its actions to the app.

pub mod parse;
pub mod player;

use crate::camera::{FrameRequest, Orbit};
use crate::edit::editor::Edit;
use crate::edit::{EditRequest, Editing};
use crate::joint_panel::random_configuration;
use crate::matrix_view::MatrixView;
use crate::pairs::PairView;
use crate::pairs::list::find_pair;
use crate::state::{Distances, Joints, Selection, Settings, Viewer};
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::winit::WinitSettings;
use parse::{Action, Script};
use player::{Controls, Player};
use std::path::{Path, PathBuf};

/// Plays a script, then exits. Runs the app continuously (the script needs frames without input).
pub struct ScriptPlugin(pub Script);

impl Plugin for ScriptPlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(WinitSettings::continuous())
            .insert_resource(Playing(Player::new(self.0.clone())))
            .add_systems(Update, play_script);
    }
}

/// The script being played.
#[derive(Resource)]
struct Playing(Player);

/// Plays one frame of the script; a failed save ends it. Exits when it ends.
fn play_script(
    mut playing: ResMut<Playing>,
    editing: Res<Editing>,
    mut controls: AppControls,
    mut exit: MessageWriter<AppExit>,
) {
    let player = &mut playing.0;
    let code = match &editing.error {
        Some(e) => player.abort().inspect(|_| eprintln!("scm-viewer: {e}")),
        None => player.frame(&mut controls),
    };
    if let Some(code) = code {
        exit.write(AppExit::from_code(code));
    }
}

/// The app as the player drives it: the resources an action sets, the camera, edit requests and
/// screenshots.
#[derive(SystemParam)]
struct AppControls<'w, 's> {
    viewer: Res<'w, Viewer>,
    distances: Res<'w, Distances>,
    joints: ResMut<'w, Joints>,
    settings: ResMut<'w, Settings>,
    selection: ResMut<'w, Selection>,
    view: ResMut<'w, PairView>,
    matrix: ResMut<'w, MatrixView>,
    camera: CameraControls<'w, 's>,
    requests: MessageWriter<'w, EditRequest>,
    screenshots: Screenshots<'w, 's>,
}

impl Controls for AppControls<'_, '_> {
    fn perform(&mut self, action: Action) -> Result<(), String> {
        let model = &self.viewer.0;
        match action {
            Action::Home => self.joints.q = model.kinematics.home(),
            Action::Random(seed) => self.joints.q = random_configuration(model.dofs(), seed),
            Action::Joint(name, value) => {
                if let Some(i) = model.dofs().iter().position(|d| d.name == name) {
                    let d = &model.dofs()[i];
                    self.joints.q[i] = value.clamp(d.lower, d.upper);
                }
            }
            Action::Config(mut q) => {
                crate::model::clamp(model.dofs(), &mut q);
                self.joints.q = q;
            }
            Action::Witness => return self.go_to_witness(),
            Action::Type(t) => self.settings.shape_type = t,
            Action::Originals(on) => self.settings.originals = on,
            Action::Sort(k) => self.view.sort = k,
            Action::Filter(f) => self.view.filter = f,
            Action::Compact(on) => self.view.compact = on,
            Action::Matrix(exported) => {
                self.matrix.open = exported.is_some();
                self.matrix.exported = exported.unwrap_or(false);
            }
            Action::Pieces(a, b) => {
                self.matrix.open = true;
                self.matrix.pieces = Some((a, b));
            }
            Action::Frame => self.camera.frame.0 = true,
            Action::Look(p, distance) => self.camera.look(p, distance),
            Action::Select(a, b) => return self.select(&a, &b),
            Action::SelectClosest => return self.select_closest(),
            Action::Deselect => self.selection.0 = None,
            Action::Skip | Action::Check | Action::Unmark | Action::SkipBelowSelected => {
                return self.edit_selected(&action);
            }
            Action::SkipBelow(below) => self.request(Edit::SkipCloser {
                below,
                inclusive: false,
            }),
            Action::SkipRatioBelow(below) => self.request(Edit::SkipRatio { below }),
            Action::Undo => self.send(EditRequest::Undo),
            Action::Redo => self.send(EditRequest::Redo),
            Action::Save => self.send(EditRequest::Save),
            // The player takes screenshots with `shoot`.
            Action::Screenshot(_) => {}
        }
        Ok(())
    }

    fn shoot(&mut self, path: &Path) {
        self.screenshots.take(path);
    }

    fn shot(&mut self, path: &Path) -> Option<Result<(), String>> {
        self.screenshots.written(path)
    }
}

impl AppControls<'_, '_> {
    /// The selected type as sampled.
    fn sampled(&self) -> Option<&crate::model::SampledType> {
        self.viewer.0.sampled(self.settings.shape_type)
    }

    /// Jumps to the selected pair's witness configuration and frames the pair.
    fn go_to_witness(&mut self) -> Result<(), String> {
        let (Some(p), Some(sampled)) = (self.selection.0, self.sampled()) else {
            return Ok(());
        };
        let witness = &sampled.matrix.stats[p].witness.q;
        if witness.len() != self.viewer.0.dofs().len() {
            return Err("the selected pair has no witness configuration".into());
        }
        self.joints.q = witness.clone();
        self.camera.frame.0 = true;
        Ok(())
    }

    /// Selects the pair of shapes `a` and `b`.
    fn select(&mut self, a: &str, b: &str) -> Result<(), String> {
        let pair = self.sampled().and_then(|d| find_pair(&d.matrix, a, b));
        let p = pair.ok_or_else(|| format!("no pair of \"{a}\" and \"{b}\""))?;
        self.selection.0 = Some(p);
        Ok(())
    }

    /// Selects the checked pair closest now.
    fn select_closest(&mut self) -> Result<(), String> {
        let distances = &self.distances.0;
        let closest = self.sampled().and_then(|d| {
            (0..d.pair_count())
                .filter(|&p| !d.matrix.entries[p].skip)
                .filter_map(|p| distances.get(p).map(|&x| (x, p)))
                .min_by(|x, y| x.0.total_cmp(&y.0))
        });
        let (_, p) = closest.ok_or("the selected type has no checked pair")?;
        self.selection.0 = Some(p);
        Ok(())
    }

    /// Asks for a mark on the selected pair, or the bulk rule at its distance.
    fn edit_selected(&mut self, action: &Action) -> Result<(), String> {
        let pair = self.selection.0.ok_or("needs a selected pair")?;
        self.request(match action {
            Action::Skip => Edit::Mark { pair, skip: true },
            Action::Check => Edit::Mark { pair, skip: false },
            Action::Unmark => Edit::Unmark { pair },
            _ => Edit::SkipCloser {
                below: self
                    .distances
                    .0
                    .get(pair)
                    .copied()
                    .unwrap_or(f64::NEG_INFINITY),
                inclusive: true,
            },
        });
        Ok(())
    }

    /// Asks the editing plugin to apply `edit`.
    fn request(&mut self, edit: Edit) {
        self.send(EditRequest::Apply(edit));
    }

    /// Sends `request` to the editing plugin.
    fn send(&mut self, request: EditRequest) {
        self.requests.write(request);
    }
}

/// The camera as the script moves it.
#[derive(SystemParam)]
struct CameraControls<'w, 's> {
    frame: ResMut<'w, FrameRequest>,
    orbits: Query<'w, 's, &'static mut Orbit>,
}

impl CameraControls<'_, '_> {
    /// Looks at point `p` of the robot's root frame from `distance`.
    fn look(&mut self, p: [f64; 3], distance: f64) {
        let focus = crate::scene::to_world(scm::math::Vec3::new(p[0], p[1], p[2]));
        for mut orbit in &mut self.orbits {
            orbit.focus = focus;
            orbit.distance = distance as f32;
        }
    }
}

/// Set by the screenshot observer once the file is written (or failed).
#[derive(Resource)]
struct ShotDone(Result<PathBuf, String>);

/// Window captures written to PNG files.
#[derive(SystemParam)]
struct Screenshots<'w, 's> {
    commands: Commands<'w, 's>,
    done: Option<Res<'w, ShotDone>>,
}

impl Screenshots<'_, '_> {
    /// Captures the window into `path` (written by an observer when the capture arrives).
    fn take(&mut self, path: &Path) {
        let target = path.to_path_buf();
        self.commands.spawn(Screenshot::primary_window()).observe(
            move |captured: On<ScreenshotCaptured>, mut commands: Commands| {
                commands.insert_resource(ShotDone(save_png(&captured.image, &target)));
            },
        );
    }

    /// The capture into `path` once it is written (or failed).
    fn written(&mut self, path: &Path) -> Option<Result<(), String>> {
        match self.done.as_deref()? {
            ShotDone(Ok(p)) if p == path => {
                self.commands.remove_resource::<ShotDone>();
                Some(Ok(()))
            }
            ShotDone(Ok(_)) => None,
            ShotDone(Err(e)) => Some(Err(e.clone())),
        }
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

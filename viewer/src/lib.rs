//! scm-viewer: the interactive viewer for exploring and refining a URDD's self-collision matrices.
//!
//! One plugin per concern, all on the `scm` library's types. A concern with plain logic of its own is
//! a folder: its `mod.rs` is the plugin, the files beside it are plain Rust, tested without a window.
//!
//! - [`scene`]: robot shapes and meshes, posed by the joints; [`scene::geometry`] prepares what it
//!   draws (triangles, outlines, the robot's bounds).
//! - [`camera`]: the orbit camera, framing the selected pair.
//! - [`joint_panel`]: the left panel (shape type, original meshes, joint sliders).
//! - [`pairs`]: the right panel; [`pairs::list`] sorts and filters the pairs and names them.
//! - [`matrix_view`]: the matrix as a picture.
//! - [`selection`]: current distances, the selected pair's highlight and closest points.
//! - [`edit`]: the edit panel and edit requests; [`edit::editor`] holds the marks, bulk rules and
//!   undo history.
//! - [`script`]: scripted mode, applying an action script's actions to the app; [`script::parse`]
//!   reads and checks the script, [`script::player`] paces it (a state machine over frames).
//! - [`layout`]: how the panels share the window (their order, the part left to the 3D view).
//!
//! Each plugin inserts the resources it owns (its doc names them), building them from the model where
//! they depend on the robot; [`run`] inserts only the model ([`state::Viewer`]) and the scene data,
//! then adds the plugins. The state several plugins share is declared in [`state`]; [`model`] is the
//! URDD as loaded ([`model::Model`], one [`model::SampledType`] per sampled shape type).

pub mod camera;
pub mod edit;
#[cfg(test)]
mod fixtures;
pub mod joint_panel;
pub mod layout;
pub mod matrix_view;
pub mod model;
pub mod pairs;
pub mod scene;
pub mod script;
pub mod selection;
pub mod state;

use bevy::prelude::*;
use bevy::window::{PresentMode, WindowResolution};
use bevy::winit::WinitSettings;
use std::path::{Path, PathBuf};

/// How to run the viewer.
#[derive(Debug, Clone)]
pub struct ViewerOptions {
    /// Play this action script, write its screenshots, then exit.
    pub script: Option<PathBuf>,
    /// Window size in logical pixels.
    pub window: (u32, u32),
}

impl Default for ViewerOptions {
    fn default() -> Self {
        ViewerOptions {
            script: None,
            window: (1600, 960),
        }
    }
}

/// Opens the viewer on the URDD `dir` and runs until the window closes (or the script ends).
/// A missing, unpreprocessed or unsampled URDD, or a bad script line, is an error before any window
/// opens; the app's own exit status is returned otherwise.
pub fn run(dir: &Path, options: ViewerOptions) -> scm::Result<AppExit> {
    let model = model::Model::load(dir)?;
    let script = match &options.script {
        Some(path) => {
            let s = script::parse::Script::load(path)?;
            s.check(&model)?;
            Some(s)
        }
        None => None,
    };
    let geometry = scene::geometry::SceneGeometry::load(&model)?;
    let title = format!("scm view: {} ({})", model.name(), dir.display());

    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title,
                    resolution: WindowResolution::new(options.window.0, options.window.1)
                        .with_scale_factor_override(1.0),
                    present_mode: PresentMode::AutoVsync,
                    ..default()
                }),
                ..default()
            })
            .set(bevy::log::LogPlugin {
                filter: "warn,wgpu=error,naga=error".into(),
                ..default()
            }),
    )
    .add_plugins(bevy_egui::EguiPlugin::default())
    // The model and the scene data first: the plugins build their own resources from them.
    .insert_resource(state::Viewer(model))
    .insert_resource(scene::SceneGeometryRes(geometry))
    .add_plugins((
        layout::LayoutPlugin,
        scene::ScenePlugin,
        camera::CameraPlugin,
        joint_panel::JointPanelPlugin,
        pairs::PairPanelPlugin,
        matrix_view::MatrixViewPlugin,
        selection::SelectionPlugin,
        edit::EditingPlugin,
    ));
    match script {
        Some(s) => app.add_plugins(script::ScriptPlugin(s)),
        // Without a script, redraw only on input.
        None => app.insert_resource(WinitSettings::desktop_app()),
    };
    Ok(app.run())
}

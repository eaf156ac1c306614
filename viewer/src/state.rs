//! The state the plugins share, as explicit resources and messages. UI systems write them; scene
//! systems react to their changes.

use crate::edit::editor::{Edit, Editor};
use crate::model::Model;
use crate::pairs::list::SortKey;
use bevy::prelude::*;
use bevy_egui::egui;
use scm::shapes::ShapeType;

/// The loaded URDD (its matrices are re-resolved after every edit).
#[derive(Resource)]
pub struct Viewer(pub Model);

/// The current joint configuration, one value per DOF.
#[derive(Resource, Debug, Clone)]
pub struct Joints {
    /// Joint values.
    pub q: Vec<f64>,
    /// Seed of the next random configuration.
    pub next_seed: u64,
}

/// What is drawn: the selected shape type and whether the original meshes show.
#[derive(Resource, Debug, Clone, Copy)]
pub struct Settings {
    /// The selected type; the pair list and the highlight apply to it.
    pub shape_type: ShapeType,
    /// Draw the original link meshes too.
    pub originals: bool,
}

/// The pair list's sort key, filter and name style.
#[derive(Resource, Debug, Clone, Default, PartialEq)]
pub struct PairView {
    /// Sort key.
    pub sort: SortKey,
    /// Filter text.
    pub filter: String,
    /// Write the two names' shared prefix and suffix once (`leg_{left,right}_4_link`).
    pub compact: bool,
}

/// The pairs the list shows, in order (derived from [`PairView`], [`Distances`] and the matrix of
/// the type they were computed for).
#[derive(Resource, Debug, Clone, Default)]
pub struct PairRows {
    /// The type the rows index into.
    pub shape_type: Option<ShapeType>,
    /// Pair indices, in order.
    pub rows: Vec<usize>,
    /// Characters of the longest pair name among the rows (the name column's width).
    pub name_width: usize,
}

/// Signed distances of every pair of the selected type in the current configuration (row-major).
#[derive(Resource, Debug, Clone, Default)]
pub struct Distances(pub Vec<f64>);

impl Selection {
    /// The selected pair if it is one of `pairs` pairs (a selection never outlives its type).
    pub fn within(&self, pairs: usize) -> Option<usize> {
        self.0.filter(|&p| p < pairs)
    }
}

/// The selected pair (row-major index into the selected type's pairs).
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Selection(pub Option<usize>);

/// The selected pair's closest points (robot root frame) and signed distance, when one is selected.
#[derive(Resource, Debug, Clone, Default)]
pub struct Closest(pub Option<(f64, [scm::math::Vec3; 2])>);

/// The user layer being edited, the bulk rules' thresholds and the last outcome shown to the user.
#[derive(Resource, Debug)]
pub struct Editing {
    /// Marks with undo and redo.
    pub editor: Editor,
    /// Threshold of the distance rule (m).
    pub below_distance: f64,
    /// Threshold of the `d / d_mean` rule.
    pub below_ratio: f64,
    /// What the last edit or save did.
    pub status: String,
    /// The last save's error, if it failed.
    pub error: Option<String>,
}

/// An edit request from the panels or the action script, applied by the editing plugin.
#[derive(Message, Debug, Clone, PartialEq)]
pub enum EditRequest {
    /// Apply an edit to the selected type.
    Apply(Edit),
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Save the user layer and re-run the export.
    Save,
}

/// The part of the window the panels leave to the 3D view (egui points), rebuilt every frame as the
/// panels are laid out in [`UiOrder`].
#[derive(Resource, Debug, Clone, Copy)]
pub struct UiLayout {
    /// Free rectangle.
    pub free: egui::Rect,
}

impl Default for UiLayout {
    fn default() -> Self {
        UiLayout {
            free: egui::Rect::EVERYTHING,
        }
    }
}

/// The order in which the panels take their space in the egui pass.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UiOrder {
    /// Start of the pass: the whole window is free.
    Reset,
    /// The joint panel (left).
    Left,
    /// The pair panel (right).
    Right,
    /// The editing panel (bottom of the 3D view).
    Bottom,
    /// Overlays inside the 3D view.
    Overlay,
}

/// The highlight colour of the selected pair's first shape (blue, sRGB).
pub const BLUE: [f32; 3] = [0.1, 0.3, 1.0];
/// The highlight colour of the selected pair's second shape (yellow, sRGB).
pub const YELLOW: [f32; 3] = [1.0, 0.85, 0.05];

impl UiLayout {
    /// A root `Ui` over the free rectangle, for one panel to take its side of.
    pub fn root(&self, ctx: &egui::Context, id: &str) -> egui::Ui {
        egui::Ui::new(
            ctx.clone(),
            egui::Id::new(id),
            egui::UiBuilder::new()
                .layer_id(egui::LayerId::background())
                .max_rect(self.free),
        )
    }
}

/// Registers the shared resources and messages, and orders the panels.
pub struct StatePlugin;

impl Plugin for StatePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PairView>()
            .init_resource::<PairRows>()
            .init_resource::<Distances>()
            .init_resource::<Selection>()
            .init_resource::<Closest>()
            .init_resource::<UiLayout>()
            .add_message::<EditRequest>()
            .configure_sets(
                bevy_egui::EguiPrimaryContextPass,
                (
                    UiOrder::Reset,
                    UiOrder::Left,
                    UiOrder::Right,
                    UiOrder::Bottom,
                    UiOrder::Overlay,
                )
                    .chain(),
            )
            .add_systems(
                bevy_egui::EguiPrimaryContextPass,
                reset_layout.in_set(UiOrder::Reset),
            );
    }
}

/// Frees the whole window at the start of the egui pass.
fn reset_layout(mut contexts: bevy_egui::EguiContexts, mut layout: ResMut<UiLayout>) -> Result {
    let free = contexts.ctx_mut()?.viewport_rect();
    layout.bypass_change_detection().free = free;
    Ok(())
}

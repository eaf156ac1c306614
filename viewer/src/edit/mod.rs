//! Editing plugin: the edit panel (marks on the selected pair, the two bulk rules, undo, redo, save)
//! and the system that applies edit requests to the user layer, re-resolves the matrices and, on
//! save, writes the layer atomically and re-runs the export. The marks, rules and undo history are
//! [`editor::Editor`]'s.

pub mod editor;

use crate::layout::{UiLayout, UiOrder};
use crate::state::{Distances, Selection, Settings, Viewer};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use editor::{Edit, Editor};
use scm::export::{ExportOptions, export};
use scm::progress::NoProgress;

/// Skip marks, bulk rules, undo / redo and save. Owns [`Editing`] (an editor of the [`Viewer`]
/// model's user layer, which must be inserted first) and the [`EditRequest`] message.
pub struct EditingPlugin;

impl Plugin for EditingPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Editing>()
            .add_message::<EditRequest>()
            .add_systems(Update, (edit_shortcuts, apply_edit_requests).chain())
            .add_systems(EguiPrimaryContextPass, edit_panel.in_set(UiOrder::Bottom));
    }
}

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

impl FromWorld for Editing {
    /// Edits the user layer as loaded, with the rules' default thresholds (0 m and 0.2).
    fn from_world(world: &mut World) -> Self {
        Editing {
            editor: Editor::new(world.resource::<Viewer>().0.user.clone()),
            below_distance: 0.0,
            below_ratio: 0.2,
            status: String::new(),
            error: None,
        }
    }
}

/// An edit request from the panels or the action script, applied by [`EditingPlugin`].
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

/// Saves the user layer of `viewer` into its URDD and re-runs the export; returns what it did.
pub fn save_and_export(viewer: &Viewer, editing: &mut Editing) -> scm::Result<String> {
    let model = &viewer.0;
    editing.editor.layer().save(&model.urdd)?;
    editing.editor.mark_saved();
    let report = export(&ExportOptions::new(model.urdd.dir()), &NoProgress)?;
    Ok(format!(
        "saved {} marks to layers/user.json; export {}",
        editing.editor.layer().edits.len(),
        if report.up_to_date {
            "was up to date"
        } else {
            "rewritten"
        }
    ))
}

/// Applies the requests of this frame.
fn apply_edit_requests(
    mut requests: MessageReader<EditRequest>,
    mut viewer: ResMut<Viewer>,
    mut editing: ResMut<Editing>,
    settings: Res<Settings>,
    distances: Res<Distances>,
) {
    for request in requests.read() {
        let changed = match request {
            EditRequest::Apply(edit) => {
                let Some(data) = viewer.0.sampled(settings.shape_type) else {
                    continue;
                };
                let (n, label) = editing.editor.apply(edit, &data.matrix, &distances.0);
                editing.status = if n == 0 {
                    format!("{label}: nothing changed")
                } else {
                    label
                };
                n > 0
            }
            EditRequest::Undo => {
                let label = editing.editor.undo();
                editing.status = label.map_or("nothing to undo".into(), |l| format!("undid: {l}"));
                true
            }
            EditRequest::Redo => {
                let label = editing.editor.redo();
                editing.status = label.map_or("nothing to redo".into(), |l| format!("redid: {l}"));
                true
            }
            EditRequest::Save => {
                match save_and_export(&viewer, &mut editing) {
                    Ok(s) => {
                        editing.status = s;
                        editing.error = None;
                    }
                    Err(e) => {
                        editing.status = format!("save failed: {e}");
                        editing.error = Some(e.to_string());
                    }
                }
                false
            }
        };
        if changed {
            let layer = editing.editor.layer().clone();
            if let Err(e) = viewer.0.resolve_all(&layer) {
                editing.status = format!("cannot apply the user layer: {e}");
                editing.error = Some(e.to_string());
            }
        }
    }
}

/// Ctrl+Z undoes, Ctrl+Y or Ctrl+Shift+Z redoes, Ctrl+S saves (unless a text field has the keyboard).
fn edit_shortcuts(
    keys: Res<ButtonInput<KeyCode>>,
    mut contexts: EguiContexts,
    mut requests: MessageWriter<EditRequest>,
) {
    let typing = contexts
        .ctx_mut()
        .is_ok_and(|ctx| ctx.egui_wants_keyboard_input());
    // A key pressed and released within one frame still counts (fast typists, synthetic input).
    let ctrls = [KeyCode::ControlLeft, KeyCode::ControlRight];
    let ctrl = keys.any_pressed(ctrls) || keys.any_just_released(ctrls);
    if typing || !ctrl {
        return;
    }
    let shifts = [KeyCode::ShiftLeft, KeyCode::ShiftRight];
    let shift = keys.any_pressed(shifts) || keys.any_just_released(shifts);
    if keys.just_pressed(KeyCode::KeyZ) {
        requests.write(if shift {
            EditRequest::Redo
        } else {
            EditRequest::Undo
        });
    } else if keys.just_pressed(KeyCode::KeyY) {
        requests.write(EditRequest::Redo);
    } else if keys.just_pressed(KeyCode::KeyS) {
        requests.write(EditRequest::Save);
    }
}

fn edit_panel(
    mut contexts: EguiContexts,
    mut layout: ResMut<UiLayout>,
    selection: Res<Selection>,
    distances: Res<Distances>,
    mut editing: ResMut<Editing>,
    mut requests: MessageWriter<EditRequest>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let selected = selection.0;
    let selected_d = selected.and_then(|p| distances.0.get(p).copied());
    let (mut below, mut ratio) = (editing.below_distance, editing.below_ratio);
    let mut out = Vec::new();
    let mut root = layout.root(ctx, "edit-root");
    let response = egui::Panel::bottom("edit").show(&mut root, |ui| {
        ui.horizontal(|ui| {
            ui.strong("Selected pair");
            ui.add_enabled_ui(selected.is_some(), |ui| {
                if let Some(pair) = selected {
                    if ui.button("Mark skip").clicked() {
                        out.push(EditRequest::Apply(Edit::Mark { pair, skip: true }));
                    }
                    if ui.button("Mark check").clicked() {
                        out.push(EditRequest::Apply(Edit::Mark { pair, skip: false }));
                    }
                    if ui.button("Unmark").clicked() {
                        out.push(EditRequest::Apply(Edit::Unmark { pair }));
                    }
                } else {
                    ui.label("(none)");
                }
            });
            ui.separator();
            let e = &editing.editor;
            if ui
                .add_enabled(e.undo_label().is_some(), egui::Button::new("Undo"))
                .on_hover_text(e.undo_label().unwrap_or(""))
                .clicked()
            {
                out.push(EditRequest::Undo);
            }
            if ui
                .add_enabled(e.redo_label().is_some(), egui::Button::new("Redo"))
                .on_hover_text(e.redo_label().unwrap_or(""))
                .clicked()
            {
                out.push(EditRequest::Redo);
            }
            let save = if e.is_dirty() { "Save *" } else { "Save" };
            if ui.button(save).clicked() {
                out.push(EditRequest::Save);
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("Skip pairs with d <");
            ui.add(
                egui::Slider::new(&mut below, -0.05..=0.1)
                    .suffix(" m")
                    .fixed_decimals(3),
            );
            if ui.button("Apply").clicked() {
                out.push(EditRequest::Apply(Edit::SkipCloser {
                    below,
                    inclusive: false,
                }));
            }
            if let Some(d) = selected_d
                && ui
                    .button(format!("Skip d <= selected ({:.1} mm)", d * 1000.0))
                    .clicked()
            {
                out.push(EditRequest::Apply(Edit::SkipCloser {
                    below: d,
                    inclusive: true,
                }));
            }
        });
        ui.horizontal(|ui| {
            ui.label("Skip pairs with d / d_mean <");
            ui.add(egui::Slider::new(&mut ratio, 0.0..=1.0).fixed_decimals(2));
            if ui.button("Apply").clicked() {
                out.push(EditRequest::Apply(Edit::SkipRatio { below: ratio }));
            }
        });
        ui.label(egui::RichText::new(&editing.status).weak());
    });
    layout.bypass_change_detection().free.max.y = response.response.rect.min.y;
    if below != editing.below_distance || ratio != editing.below_ratio {
        editing.below_distance = below;
        editing.below_ratio = ratio;
    }
    for r in out {
        requests.write(r);
    }
    Ok(())
}

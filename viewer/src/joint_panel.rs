//! Joint panel plugin (left): the shape type, the original-mesh toggle, one slider per degree of
//! freedom with its name and limits (filtered by name, for robots with tens of joints), home and a
//! random configuration.

use crate::layout::{UiLayout, UiOrder};
use crate::state::{Joints, Settings, Viewer};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use scm::rng::Rng;
use scm::shapes::ShapeType;

/// The left panel. Owns [`Joints`] (starting at home) and [`Settings`] (starting on the link hulls),
/// both built from the [`Viewer`] model, which must be inserted first.
pub struct JointPanelPlugin;

impl Plugin for JointPanelPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Joints>()
            .init_resource::<Settings>()
            .add_systems(EguiPrimaryContextPass, joint_panel.in_set(UiOrder::Left));
    }
}

/// A configuration drawn uniformly within the limits from `seed`.
pub fn random_configuration(dofs: &[scm::robot::Dof], seed: u64) -> Vec<f64> {
    let mut q = Vec::new();
    scm::robot::random_configuration(dofs, &mut Rng::new(seed, 0x7669_6577), &mut q);
    q
}

/// The DOFs whose name contains every word of `filter` (case-insensitive), in configuration order.
pub fn matching_joints(dofs: &[scm::robot::Dof], filter: &str) -> Vec<usize> {
    let words: Vec<String> = filter.split_whitespace().map(str::to_lowercase).collect();
    (0..dofs.len())
        .filter(|&i| {
            let name = dofs[i].name.to_lowercase();
            words.iter().all(|w| name.contains(w.as_str()))
        })
        .collect()
}

fn joint_panel(
    mut filter: Local<String>,
    mut contexts: EguiContexts,
    mut layout: ResMut<UiLayout>,
    viewer: Res<Viewer>,
    mut joints: ResMut<Joints>,
    mut settings: ResMut<Settings>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let model = &viewer.0;
    let mut q = joints.q.clone();
    let mut s = *settings;
    let mut root = layout.root(ctx, "joint-root");
    let response = egui::Panel::left("joints")
        .resizable(true)
        .default_size(270.0)
        .show(&mut root, |ui| {
            ui.heading(model.name());
            ui.label(
                egui::RichText::new(model.urdd.dir().display().to_string())
                    .small()
                    .weak(),
            );
            ui.separator();
            ui.horizontal(|ui| {
                ui.label("Shape type");
                egui::ComboBox::from_id_salt("shape-type")
                    .selected_text(s.shape_type.id())
                    .show_ui(ui, |ui| {
                        for t in ShapeType::ALL {
                            let sampled = model.sampled(t).is_some();
                            let label = if sampled {
                                t.id().to_string()
                            } else {
                                format!("{} (not sampled)", t.id())
                            };
                            ui.add_enabled_ui(sampled, |ui| {
                                ui.selectable_value(&mut s.shape_type, t, label);
                            });
                        }
                    });
            });
            ui.checkbox(&mut s.originals, "original meshes");
            ui.separator();
            ui.horizontal(|ui| {
                ui.strong("Joints");
                if ui.button("Home").clicked() {
                    q = model.kinematics.home();
                }
                if ui.button("Random").clicked() {
                    q = random_configuration(model.dofs(), joints.next_seed);
                    joints.bypass_change_detection().next_seed += 1;
                }
            });
            let shown = matching_joints(model.dofs(), &filter);
            ui.horizontal(|ui| {
                ui.label("Filter");
                ui.add(
                    egui::TextEdit::singleline(&mut *filter)
                        .hint_text("joint name words")
                        .desired_width(120.0),
                );
                ui.label(format!("{} of {}", shown.len(), model.dofs().len()));
            });
            egui::ScrollArea::vertical().show(ui, |ui| {
                for i in shown {
                    let d = &model.dofs()[i];
                    ui.label(format!("{}  [{:.3}, {:.3}]", d.name, d.lower, d.upper));
                    ui.add(egui::Slider::new(&mut q[i], d.lower..=d.upper).fixed_decimals(3));
                }
            });
        });
    layout.bypass_change_detection().free.min.x = response.response.rect.max.x;
    if q != joints.q {
        joints.q = q;
    }
    if s.shape_type != settings.shape_type || s.originals != settings.originals {
        *settings = s;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filter_keeps_joints_whose_name_has_every_word() {
        let dofs: Vec<scm::robot::Dof> = ["leg_left_knee", "leg_right_knee", "arm_left_elbow"]
            .iter()
            .enumerate()
            .map(|(joint, name)| scm::robot::Dof {
                joint,
                name: name.to_string(),
                lower: -1.0,
                upper: 1.0,
            })
            .collect();
        assert_eq!(matching_joints(&dofs, ""), vec![0, 1, 2]);
        assert_eq!(matching_joints(&dofs, "KNEE"), vec![0, 1]);
        assert_eq!(matching_joints(&dofs, "left knee"), vec![0]);
        assert!(matching_joints(&dofs, "wrist").is_empty());
    }
}

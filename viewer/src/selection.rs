//! Selection and highlight plugin: current distances of the selected type, the selected pair's closest
//! points, its two shapes in blue and yellow with every other shape faded and outlined, and the segment
//! between the closest points with its length.

use crate::layout::UiOrder;
use crate::scene::{OriginalMesh, ShapeEntity, to_world};
use crate::state::{Distances, Joints, Selection, Settings, Viewer};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use scm::query::Scratch;

/// Selection, highlight and the closest-point segment. Owns [`Selection`], [`Distances`] and
/// [`Closest`].
pub struct SelectionPlugin;

impl Plugin for SelectionPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<Selection>()
            .init_resource::<Distances>()
            .init_resource::<Closest>()
            .add_systems(
                Update,
                (
                    clear_selection_on_type_change.run_if(resource_changed::<Settings>),
                    update_distances
                        .run_if(resource_changed::<Joints>.or_eager(resource_changed::<Settings>)),
                    update_closest
                        .run_if(resource_changed::<Joints>.or_eager(resource_changed::<Selection>)),
                    highlight_selected_pair.run_if(
                        resource_changed::<Selection>.or_eager(resource_changed::<Settings>),
                    ),
                    draw_outlines_and_segment,
                )
                    .chain(),
            )
            .add_systems(
                EguiPrimaryContextPass,
                distance_label.in_set(UiOrder::Overlay),
            );
    }
}

/// The selected pair's closest points (robot root frame) and signed distance, when one is selected.
#[derive(Resource, Debug, Clone, Default)]
pub struct Closest(pub Option<(f64, [scm::math::Vec3; 2])>);

/// The highlight colour of the selected pair's first shape (blue, sRGB).
pub const BLUE: [f32; 3] = [0.1, 0.3, 1.0];
/// The highlight colour of the selected pair's second shape (yellow, sRGB).
pub const YELLOW: [f32; 3] = [1.0, 0.85, 0.05];

/// Opacity of the shapes that are not selected while a pair is.
const FADED: f32 = 0.12;
/// Opacity of the shapes while the original meshes show.
const WITH_ORIGINALS: f32 = 0.35;

/// Pair indices belong to one type: a new type starts without a selection.
fn clear_selection_on_type_change(
    settings: Res<Settings>,
    mut last: Local<Option<scm::shapes::ShapeType>>,
    mut selection: ResMut<Selection>,
) {
    if last.is_some_and(|t| t != settings.shape_type) && selection.0.is_some() {
        selection.0 = None;
    }
    *last = Some(settings.shape_type);
}

/// Signed distance of every pair of the selected type in the current configuration.
fn update_distances(
    viewer: Res<Viewer>,
    joints: Res<Joints>,
    settings: Res<Settings>,
    mut scratch: Local<Scratch>,
    mut distances: ResMut<Distances>,
) {
    if let Some(data) = viewer.0.sampled(settings.shape_type) {
        match data.distances(&joints.q, &mut scratch) {
            Ok(d) => distances.0 = d,
            Err(e) => error!("distances: {e}"),
        }
    }
}

/// The selected pair's closest points.
fn update_closest(
    viewer: Res<Viewer>,
    joints: Res<Joints>,
    settings: Res<Settings>,
    selection: Res<Selection>,
    mut scratch: Local<Scratch>,
    mut closest: ResMut<Closest>,
) {
    closest.0 = viewer.0.sampled(settings.shape_type).and_then(|data| {
        let p = selection.within(data.pair_count())?;
        data.closest_points(&joints.q, p, &mut scratch).ok()
    });
}

/// Colours the selected pair blue and yellow and fades the other shapes, or restores every shape.
fn highlight_selected_pair(
    viewer: Res<Viewer>,
    settings: Res<Settings>,
    selection: Res<Selection>,
    shapes: Query<(&ShapeEntity, &MeshMaterial3d<StandardMaterial>)>,
    originals: Query<&MeshMaterial3d<StandardMaterial>, With<OriginalMesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let pair = viewer.0.sampled(settings.shape_type).and_then(|data| {
        let p = selection.within(data.pair_count())?;
        Some(data.pair(p))
    });
    // The original meshes share one material: see-through while a pair is selected.
    if let Some(handle) = originals.iter().next()
        && let Some(mut mat) = materials.get_mut(&handle.0)
    {
        let alpha = if pair.is_some() { WITH_ORIGINALS } else { 1.0 };
        mat.base_color.set_alpha(alpha);
        mat.alpha_mode = if alpha < 1.0 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        };
    }
    for (shape, handle) in &shapes {
        if shape.shape_type != settings.shape_type {
            continue;
        }
        let Some(mut mat) = materials.get_mut(&handle.0) else {
            continue;
        };
        let role = pair.map(|(a, b)| {
            if shape.index == a {
                Some(BLUE)
            } else if shape.index == b {
                Some(YELLOW)
            } else {
                None
            }
        });
        let (rgb, alpha, glow) = match role {
            Some(Some(c)) => (c, 1.0, 0.35),
            Some(None) => (shape.color, FADED, 0.0),
            None if settings.originals => (shape.color, WITH_ORIGINALS, 0.0),
            None => (shape.color, 1.0, 0.0),
        };
        mat.base_color = Color::srgba(rgb[0], rgb[1], rgb[2], alpha);
        mat.emissive = Color::srgb(rgb[0], rgb[1], rgb[2]).to_linear() * glow;
        mat.alpha_mode = if alpha < 1.0 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        };
    }
}

/// Outlines the faded shapes and draws the segment between the selected pair's closest points.
fn draw_outlines_and_segment(
    mut gizmos: Gizmos,
    settings: Res<Settings>,
    selection: Res<Selection>,
    closest: Res<Closest>,
    shapes: Query<(&ShapeEntity, &GlobalTransform)>,
) {
    if selection.0.is_none() {
        return;
    }
    let outline = Color::srgba(0.85, 0.85, 0.85, 0.45);
    let pair = closest.0.as_ref();
    for (shape, transform) in &shapes {
        if shape.shape_type != settings.shape_type {
            continue;
        }
        for [a, b] in &shape.outline {
            gizmos.line(
                transform.transform_point(*a),
                transform.transform_point(*b),
                outline,
            );
        }
    }
    if let Some((_, [a, b])) = pair {
        let (a, b) = (to_world(*a), to_world(*b));
        let red = Color::srgb(1.0, 0.15, 0.1);
        gizmos.line(a, b, red);
        for end in [a, b] {
            gizmos.sphere(Isometry3d::from_translation(end), 0.004, red);
        }
    }
}

/// The segment's length, written beside its midpoint in the 3D view.
fn distance_label(
    mut contexts: EguiContexts,
    closest: Res<Closest>,
    cameras: Query<(&Camera, &GlobalTransform), With<crate::camera::Orbit>>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let Some((d, [a, b])) = closest.0.as_ref() else {
        return Ok(());
    };
    let Ok((camera, at)) = cameras.single() else {
        return Ok(());
    };
    let mid = (to_world(*a) + to_world(*b)) * 0.5;
    let Ok(pos) = camera.world_to_viewport(at, mid) else {
        return Ok(());
    };
    let text = if *d > 0.0 {
        format!("{:.1} mm", d * 1000.0)
    } else {
        format!("{:.1} mm (penetration)", d * 1000.0)
    };
    egui::Area::new(egui::Id::new("distance-label"))
        .fixed_pos(egui::pos2(pos.x + 8.0, pos.y - 8.0))
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::NONE
                .fill(egui::Color32::from_black_alpha(170))
                .inner_margin(4.0)
                .show(ui, |ui| {
                    let text = egui::RichText::new(text)
                        .color(egui::Color32::WHITE)
                        .strong();
                    ui.add(egui::Label::new(text).wrap_mode(egui::TextWrapMode::Extend));
                });
        });
    Ok(())
}

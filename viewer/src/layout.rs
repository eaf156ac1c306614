//! Layout plugin: how the panels share the window. Every egui pass starts with the whole window free;
//! each panel, in [`UiOrder`], takes its side of what is left, and the 3D view gets the rest
//! ([`UiLayout`]).

use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};

/// Orders the panels in the egui pass and keeps the free part of the window.
pub struct LayoutPlugin;

impl Plugin for LayoutPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<UiLayout>()
            .configure_sets(
                EguiPrimaryContextPass,
                (
                    UiOrder::Reset,
                    UiOrder::Left,
                    UiOrder::Right,
                    UiOrder::Bottom,
                    UiOrder::Overlay,
                )
                    .chain(),
            )
            .add_systems(EguiPrimaryContextPass, reset_layout.in_set(UiOrder::Reset));
    }
}

/// The part of the window the panels leave to the 3D view (egui points), rebuilt every frame as the
/// panels are laid out in [`UiOrder`]. Owned by [`LayoutPlugin`].
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

/// Frees the whole window at the start of the egui pass.
fn reset_layout(mut contexts: EguiContexts, mut layout: ResMut<UiLayout>) -> Result {
    let free = contexts.ctx_mut()?.viewport_rect();
    layout.bypass_change_detection().free = free;
    Ok(())
}

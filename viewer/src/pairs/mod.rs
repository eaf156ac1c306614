//! Pair panel plugin (right): the selected type's pairs with their verdict, reason and statistics,
//! sortable and filtered; the selected pair's details and a button to its witness configuration.
//! Which pairs the list shows, in which order and under which names is decided by [`list`].

pub mod list;

use crate::camera::FrameRequest;
use crate::layout::{UiLayout, UiOrder};
use crate::state::{Distances, Joints, Selection, Settings, Viewer};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use list::{SortKey, pair_label, ratio, ratio_text, visible_pairs};
use scm::shapes::ShapeType;

/// The right panel and the list it shows. Owns [`PairView`] and [`PairRows`].
pub struct PairPanelPlugin;

impl Plugin for PairPanelPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PairView>()
            .init_resource::<PairRows>()
            .add_systems(
                Update,
                refresh_pair_rows.run_if(
                    resource_changed::<Distances>
                        .or_eager(resource_changed::<Settings>)
                        .or_eager(resource_changed::<PairView>)
                        .or_eager(resource_changed::<Viewer>),
                ),
            )
            .add_systems(EguiPrimaryContextPass, pair_panel.in_set(UiOrder::Right));
    }
}

/// The pair list's sort key, filter and name style (set in the panel or by the script).
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

/// Recomputes the visible rows after a change of distances, sort, filter or matrix.
fn refresh_pair_rows(
    viewer: Res<Viewer>,
    settings: Res<Settings>,
    view: Res<PairView>,
    distances: Res<Distances>,
    mut rows: ResMut<PairRows>,
) {
    if let Some(data) = viewer.0.sampled(settings.shape_type)
        && distances.0.len() == data.pair_count()
    {
        rows.rows = visible_pairs(
            &data.matrix,
            &data.exact,
            &distances.0,
            view.sort,
            &view.filter,
        );
        rows.shape_type = Some(settings.shape_type);
        rows.name_width = rows
            .rows
            .iter()
            .map(|&p| pair_label(&data.matrix, p, view.compact).chars().count())
            .max()
            .unwrap_or(0)
            .clamp(4, MAX_NAME_WIDTH);
    }
}

/// The widest the name column pads to (characters); longer names still show whole, unaligned.
const MAX_NAME_WIDTH: usize = 64;

/// A distance in millimetres, for the list.
fn mm(d: f64) -> String {
    if d.is_finite() {
        format!("{:+8.1}", d * 1000.0)
    } else {
        "       -".into()
    }
}

#[allow(clippy::too_many_arguments)]
fn pair_panel(
    mut contexts: EguiContexts,
    mut layout: ResMut<UiLayout>,
    viewer: Res<Viewer>,
    settings: Res<Settings>,
    distances: Res<Distances>,
    rows: Res<PairRows>,
    mut view: ResMut<PairView>,
    mut selection: ResMut<Selection>,
    mut joints: ResMut<Joints>,
    mut frame: ResMut<FrameRequest>,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let Some(data) = viewer.0.sampled(settings.shape_type) else {
        return Ok(());
    };
    let m = &data.matrix;
    let d = &distances.0;
    let mut v = view.clone();
    let mut selected = selection.within(m.entries.len());
    let listed: &[usize] = if rows.shape_type == Some(settings.shape_type) {
        &rows.rows
    } else {
        &[]
    };
    let mut go_to: Option<Vec<f64>> = None;
    let mut root = layout.root(ctx, "pair-root");
    let response = egui::Panel::right("pairs")
        .resizable(true)
        .default_size((0.42 * ctx.content_rect().width()).clamp(500.0, 760.0))
        .show(&mut root, |ui| {
            let skipped = data.skipped();
            let user = m.entries.iter().filter(|e| e.reason == "user").count();
            ui.heading(format!("Pairs of {}", settings.shape_type));
            ui.label(format!(
                "{} pairs: {skipped} skipped, {} checked, {user} by user marks ({} samples)",
                m.entries.len(),
                m.entries.len() - skipped,
                m.samples
            ));
            ui.horizontal(|ui| {
                ui.label("Sort by");
                for k in SortKey::ALL {
                    ui.radio_value(&mut v.sort, k, k.label());
                }
            });
            ui.horizontal(|ui| {
                ui.label("Filter");
                ui.add(
                    egui::TextEdit::singleline(&mut v.filter)
                        .hint_text("link, reason, skip, certified, sampled..."),
                );
                ui.checkbox(&mut v.compact, "compact names")
                    .on_hover_text("write the two names' shared prefix and suffix once");
            });
            let width = rows.name_width;
            ui.label(
                egui::RichText::new(format!(
                    "{:<width$} {:>8} {:>6} {:>8}  {:<14} exact geometry",
                    format!("pair (shown: {})", listed.len()),
                    "d mm",
                    "d/mean",
                    "d_min mm",
                    "verdict",
                ))
                .monospace()
                .size(11.0),
            )
            .on_hover_text(
                "d: distance now; d/mean: over the sampled mean; verdict: this type's; \
                 exact geometry: the link pair's verdict in the exported files, and whether a never \
                 is certified or only sampled",
            );
            let row_height = ui.text_style_height(&egui::TextStyle::Monospace) + 4.0;
            // Whole names: the rows scroll sideways rather than cut a name off.
            egui::ScrollArea::both()
                .max_height((ui.available_height() - 260.0).max(120.0))
                .auto_shrink([false, false])
                .show_rows(ui, row_height, listed.len(), |ui, range| {
                    for &p in &listed[range] {
                        let e = &m.entries[p];
                        let s = &m.stats[p];
                        let cur = d.get(p).copied().unwrap_or(f64::NAN);
                        let verdict = format!("{} {}", if e.skip { "skip " } else { "check" }, e.reason);
                        let text = format!(
                            "{:<width$} {} {:>6} {}  {verdict:<14} {}",
                            pair_label(m, p, v.compact),
                            mm(cur),
                            ratio_text(ratio(cur, s)),
                            mm(s.d_min),
                            data.exact[p],
                        );
                        let rich = egui::RichText::new(text).monospace().size(11.0);
                        let rich = if e.skip { rich.weak() } else { rich };
                        let row = ui
                            .add(egui::Button::selectable(selected == Some(p), rich).wrap_mode(egui::TextWrapMode::Extend))
                            .on_hover_text(format!(
                                "{}\n{verdict} ({} layer); exact geometry: {}\nd_min {:.2} mm, d_mean {:.2} mm, in collision {:.2}% of samples",
                                pair_label(m, p, false),
                                e.layer.id(),
                                if data.exact[p].is_empty() { "\u{2014}" } else { &data.exact[p] },
                                s.d_min * 1000.0,
                                s.d_mean * 1000.0,
                                100.0 * s.collision_fraction
                            ));
                        if row.clicked() {
                            selected = if selected == Some(p) { None } else { Some(p) };
                        }
                    }
                });
            ui.separator();
            match selected {
                None => {
                    ui.label("Select a pair to highlight it and edit its verdict.");
                }
                Some(p) => {
                    let e = &m.entries[p];
                    let s = &m.stats[p];
                    let cur = d.get(p).copied().unwrap_or(f64::NAN);
                    ui.strong(pair_label(m, p, false));
                    ui.label(format!(
                        "{}  (reason {}, layer {}; inferred by sampling: {})",
                        if e.skip { "skipped" } else { "checked" },
                        e.reason,
                        e.layer.id(),
                        s.reason.id()
                    ));
                    egui::Grid::new("stats").num_columns(4).show(ui, |ui| {
                        ui.label("d now");
                        ui.label(format!("{:.2} mm", cur * 1000.0));
                        ui.label("d / d_mean");
                        ui.label(ratio_text(ratio(cur, s)));
                        ui.end_row();
                        ui.label("d_min");
                        ui.label(format!("{:.2} mm", s.d_min * 1000.0));
                        ui.label("d_mean");
                        ui.label(format!("{:.2} mm", s.d_mean * 1000.0));
                        ui.end_row();
                        ui.label("d_max");
                        ui.label(format!("{:.2} mm", s.d_max * 1000.0));
                        ui.label("at home");
                        ui.label(format!("{:.2} mm", s.home_distance * 1000.0));
                        ui.end_row();
                        ui.label("in collision");
                        ui.label(format!("{:.2}% of samples", s.collision_fraction * 100.0));
                        ui.end_row();
                    });
                    let witness = &s.witness.q;
                    let usable = witness.len() == viewer.0.dofs().len();
                    let label = match s.witness.sample {
                        Some(k) => format!("Go to witness (sample {k}, closest)"),
                        None => "Go to witness (closest found)".into(),
                    };
                    ui.horizontal(|ui| {
                        if ui.add_enabled(usable, egui::Button::new(label)).clicked() {
                            go_to = Some(witness.clone());
                        }
                        if ui
                            .button("Frame (F)")
                            .on_hover_text("point the camera at the selected pair")
                            .clicked()
                        {
                            frame.0 = true;
                        }
                    });
                    let (la, lb) = (&m.shapes[s.a].link, &m.shapes[s.b].link);
                    if let Some(r) = viewer.0.mesh.as_ref().and_then(|f| f.pair(la, lb)) {
                        ui.separator();
                        if let Some(q) = exact_geometry(ui, r, usable) {
                            go_to = Some(q);
                        }
                    }
                }
            }
        });
    layout.bypass_change_detection().free.max.x = response.response.rect.min.x;
    if v != *view {
        *view = v;
    }
    if selected != selection.within(m.entries.len()) {
        selection.0 = selected;
    }
    if let Some(q) = go_to {
        joints.q = q;
        frame.0 = true;
    }
    Ok(())
}

/// The link pair's verdict on the exact geometry (what the SRDF, MJCF, cuRobo and Drake files carry)
/// and its evidence; the configuration to jump to when its button is clicked.
fn exact_geometry(
    ui: &mut egui::Ui,
    r: &scm::sample::LinkPairRecord,
    usable: bool,
) -> Option<Vec<f64>> {
    let evidence = r
        .evidence
        .map_or(String::new(), |e| format!(", {}", e.id()));
    ui.label(format!(
        "Links on the exact geometry (exported files): {}{evidence}",
        r.reason.id()
    ));
    let millimetres = |d: f64| format!("{:.2} mm", d * 1000.0);
    // A bound at or below zero proves no gap: not written as "proved".
    let mut go_to = None;
    if let Some(c) = &r.certificate {
        // The bound is the exact geometry's where the second search ran, else the hulls'; at or
        // below zero it proves no gap and is not written as "proved".
        let on = if c.exact_queries > 0 {
            "the exact geometry"
        } else {
            "the hulls"
        };
        let bound = if c.lower_bound > 0.0 {
            format!("{on} proved >= {}", millimetres(c.lower_bound))
        } else {
            format!("lower bound on {on} {}", millimetres(c.lower_bound))
        };
        ui.label(format!(
            "certificate: {} after {} boxes; {bound} over {:.1}% of the joint box; closest hull distance found {}",
            match c.status {
                scm::sample::Status::Certified => "proved",
                scm::sample::Status::Budget => "budget spent",
                scm::sample::Status::HullsTouch => "the hulls touch",
                scm::sample::Status::Collides => "collision found",
            },
            c.boxes,
            100.0 * c.cleared,
            millimetres(c.closest)
        ));
        if ui
            .add_enabled(usable, egui::Button::new("Go to the certificate's closest"))
            .clicked()
        {
            go_to = Some(c.q.clone());
        }
    }
    if let Some(w) = &r.witness {
        let label = match w.sample {
            Some(k) => format!("Go to the exact geometry's collision (sample {k})"),
            None => "Go to the exact geometry's collision".into(),
        };
        if ui.add_enabled(usable, egui::Button::new(label)).clicked() {
            go_to = Some(w.q.clone());
        }
    }
    go_to
}

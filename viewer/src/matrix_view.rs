//! Matrix view plugin: the selected type's matrix as a picture (the same [`HeatMap`] that
//! `scm export --format svg` draws): links against links in kinematic order, each cell coloured by
//! verdict and shaded by `d_min`. Hovering a cell shows the pair and its statistics; clicking selects
//! it (the list's selection, so highlight, witness and edits work from either). A decomposition
//! type's map is its link level: clicking a cell opens that link pair's piece grid.

use crate::layout::{UiLayout, UiOrder};
use crate::model::Model;
use crate::state::{Selection, Settings, Viewer};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use scm::matrix::{HeatMap, Verdict, consumer_link_pairs};
use scm::shapes::{Scope, ShapeType};

/// The matrix window. Owns [`MatrixView`] and the picture it draws.
pub struct MatrixViewPlugin;

impl Plugin for MatrixViewPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<MatrixView>()
            .init_resource::<Picture>()
            .add_systems(
                Update,
                (
                    close_pieces_on_type_change.run_if(resource_changed::<Settings>),
                    rebuild_picture.run_if(
                        resource_changed::<MatrixView>
                            .or_eager(resource_changed::<Settings>)
                            .or_eager(resource_changed::<Viewer>),
                    ),
                )
                    .chain(),
            )
            .add_systems(
                EguiPrimaryContextPass,
                matrix_window.in_set(UiOrder::Overlay),
            );
    }
}

/// What the matrix window shows.
#[derive(Resource, Debug, Clone, Default, PartialEq)]
pub struct MatrixView {
    /// The window is open.
    pub open: bool,
    /// Colour by the link pairs' verdicts in the exported files (decided on the exact geometry, with
    /// a `never`'s evidence) instead of the selected type's own verdicts.
    pub exported: bool,
    /// The link pair whose piece grid is open (decomposition types).
    pub pieces: Option<(String, String)>,
}

/// The picture the window draws, rebuilt when the view, the type or the matrices change.
#[derive(Resource, Debug, Default)]
struct Picture(Option<HeatMap>);

/// The colour of the one-pixel frame around the grid (a colour no verdict and no panel uses, so a
/// screenshot can find the grid).
pub const FRAME_RGB: [u8; 3] = [255, 0, 255];

/// The picture for `view` of type `t`: the piece grid of the open link pair, the exported link
/// pairs, or the type's own matrix; `None` if the type was not sampled.
pub fn picture(model: &Model, t: ShapeType, view: &MatrixView) -> Option<HeatMap> {
    let data = model.sampled(t)?;
    let order = model.robot.kinematic_link_names();
    if let Some((a, b)) = &view.pieces
        && let Some(map) = HeatMap::pieces(&data.matrix, a, b)
    {
        return Some(map);
    }
    if !view.exported {
        return Some(HeatMap::of_type(&data.matrix, &order));
    }
    // The layers come from the link hull's link level, as the export reads them.
    let layer = model.sampled(ShapeType::Hull).unwrap_or(data);
    let (pairs, title) = match &model.mesh {
        Some(mesh) => (
            consumer_link_pairs(layer.matrix.link_pairs(), mesh, false),
            "link pairs as exported (decided on mesh)".to_string(),
        ),
        None => (
            layer.matrix.link_pairs(),
            format!("link pairs as exported (decided on {})", layer.shape_type),
        ),
    };
    Some(HeatMap::of_link_pairs(title, &pairs, &data.matrix, &order))
}

/// What a click on cell `(row, col)` does.
#[derive(Debug, Clone, PartialEq)]
pub enum Click {
    /// Select this pair of the type.
    Select(usize),
    /// Open the piece grid of these two links.
    Pieces(String, String),
    /// Nothing (the diagonal, or a cell without a pair).
    Nothing,
}

/// The effect of clicking `(row, col)` of `map` drawn for a type of `scope`.
pub fn click(map: &HeatMap, scope: Scope, row: usize, col: usize) -> Click {
    let Some(cell) = map.cell(row, col) else {
        return Click::Nothing;
    };
    match cell.pair {
        Some(p) => Click::Select(p),
        None if scope == Scope::Pieces && map.symmetric => {
            Click::Pieces(map.rows[cell.row].clone(), map.cols[cell.col].clone())
        }
        None => Click::Nothing,
    }
}

/// The cell under `pos` in a grid at `origin` with square cells of side `size`.
pub fn cell_at(
    pos: egui::Pos2,
    origin: egui::Pos2,
    size: f32,
    rows: usize,
    cols: usize,
) -> Option<(usize, usize)> {
    let (x, y) = ((pos.x - origin.x) / size, (pos.y - origin.y) / size);
    (x >= 0.0 && y >= 0.0 && (y as usize) < rows && (x as usize) < cols)
        .then_some((y as usize, x as usize))
}

fn close_pieces_on_type_change(
    settings: Res<Settings>,
    mut last: Local<Option<ShapeType>>,
    mut view: ResMut<MatrixView>,
) {
    if last.is_some_and(|t| t != settings.shape_type) && view.pieces.is_some() {
        view.pieces = None;
    }
    *last = Some(settings.shape_type);
}

fn rebuild_picture(
    viewer: Res<Viewer>,
    settings: Res<Settings>,
    view: Res<MatrixView>,
    mut picture_res: ResMut<Picture>,
) {
    picture_res.0 = if view.open {
        picture(&viewer.0, settings.shape_type, &view)
    } else {
        None
    };
}

fn color(rgb: [u8; 3]) -> egui::Color32 {
    egui::Color32::from_rgb(rgb[0], rgb[1], rgb[2])
}

fn matrix_window(
    mut contexts: EguiContexts,
    layout: Res<UiLayout>,
    viewer: Res<Viewer>,
    settings: Res<Settings>,
    picture_res: Res<Picture>,
    mut view: ResMut<MatrixView>,
    mut selection: ResMut<Selection>,
) -> Result {
    let (Some(map), true) = (&picture_res.0, view.open) else {
        return Ok(());
    };
    let ctx = contexts.ctx_mut()?;
    let Some(data) = viewer.0.sampled(settings.shape_type) else {
        return Ok(());
    };
    let scope = settings.shape_type.scope();
    let selected = selection.within(data.pair_count());
    let mut v = view.clone();
    let mut select = None;
    let free = layout.free;
    let side = (free.width().min(free.height()) - 140.0).clamp(160.0, 900.0);
    egui::Window::new("Matrix")
        .id(egui::Id::new("matrix-view"))
        .default_pos(free.min + egui::vec2(8.0, 8.0))
        .open(&mut v.open)
        .resizable(false)
        .show(ctx, |ui| {
            ui.horizontal(|ui| {
                ui.radio_value(&mut v.exported, false, format!("{} verdicts", settings.shape_type));
                ui.radio_value(&mut v.exported, true, "exported files (mesh)")
                    .on_hover_text("the link pairs' verdicts the SRDF, MJCF, cuRobo and Drake files carry, with each never's evidence");
            });
            ui.horizontal(|ui| {
                ui.strong(&map.title);
                if v.pieces.is_some() && ui.button("back to links").clicked() {
                    v.pieces = None;
                }
            });
            let counts = map.counts();
            ui.horizontal_wrapped(|ui| {
                for verdict in Verdict::ALL {
                    if let Some(n) = counts.get(&verdict) {
                        let (r, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
                        ui.painter().rect_filled(r, 0.0, color(verdict.rgb()));
                        ui.label(egui::RichText::new(format!("{} {n}", verdict.label())).small());
                    }
                }
            });
            let n = map.rows.len().max(map.cols.len()).max(1);
            // Names on both axes when the cells are tall enough to read them by.
            let longest = map.rows.iter().chain(&map.cols).map(|l| l.chars().count()).max().unwrap_or(0);
            let font = egui::FontId::monospace(10.0);
            let labels = side / n as f32 >= 9.0;
            let margin = if labels { (longest as f32 * 6.1 + 6.0).min(220.0) } else { 0.0 };
            let size = ((side - margin) / n as f32).floor().clamp(3.0, 24.0);
            let grid = egui::vec2(size * map.cols.len() as f32, size * map.rows.len() as f32);
            let (whole, response) = ui.allocate_exact_size(
                grid + egui::vec2(margin + 2.0, margin + 2.0),
                egui::Sense::click(),
            );
            let rect = egui::Rect::from_min_size(whole.min + egui::vec2(margin, margin), grid + egui::vec2(2.0, 2.0));
            let origin = rect.min + egui::vec2(1.0, 1.0);
            let painter = ui.painter_at(whole);
            if labels {
                let ink = ui.visuals().text_color();
                for (i, label) in map.rows.iter().enumerate() {
                    painter.text(
                        egui::pos2(origin.x - 4.0, origin.y + (i as f32 + 0.5) * size),
                        egui::Align2::RIGHT_CENTER,
                        label,
                        font.clone(),
                        ink,
                    );
                }
                for (j, label) in map.cols.iter().enumerate() {
                    let galley = painter.layout_no_wrap(label.clone(), font.clone(), ink);
                    let at = egui::pos2(
                        origin.x + (j as f32 + 0.5) * size - galley.size().y / 2.0,
                        origin.y - 4.0,
                    );
                    painter.add(
                        egui::epaint::TextShape::new(at, galley, ink)
                            .with_angle(-std::f32::consts::FRAC_PI_2),
                    );
                }
            }
            painter.rect_stroke(
                rect.shrink(0.5),
                0.0,
                egui::Stroke::new(1.0, color(FRAME_RGB)),
                egui::StrokeKind::Inside,
            );
            painter.rect_filled(egui::Rect::from_min_size(origin, grid), 0.0, egui::Color32::from_gray(235));
            let at = |r: usize, c: usize| {
                egui::Rect::from_min_size(
                    origin + egui::vec2(c as f32 * size, r as f32 * size),
                    egui::vec2(size, size),
                )
            };
            if map.symmetric {
                for i in 0..map.rows.len() {
                    painter.rect_filled(at(i, i), 0.0, color(Verdict::SameLink.rgb()));
                }
            }
            let mut outline = Vec::new();
            for cell in &map.cells {
                let fill = color(cell.verdict.shaded(cell.d_min));
                let mut places = vec![(cell.row, cell.col)];
                if map.symmetric {
                    places.push((cell.col, cell.row));
                }
                let chosen = selected.is_some_and(|p| {
                    cell.pair == Some(p) || (cell.pair.is_none() && holds(map, cell, data, p))
                });
                for (r, c) in places {
                    painter.rect_filled(at(r, c), 0.0, fill);
                    if chosen {
                        outline.push(at(r, c));
                    }
                }
            }
            for r in outline {
                painter.rect_stroke(r, 0.0, egui::Stroke::new(2.0, egui::Color32::WHITE), egui::StrokeKind::Inside);
            }
            let hovered = response
                .hover_pos()
                .and_then(|p| cell_at(p, origin, size, map.rows.len(), map.cols.len()));
            if let Some((r, c)) = hovered {
                let text = hover_text(map, data, r, c);
                response.clone().on_hover_text_at_pointer(text);
            }
            if response.clicked()
                && let Some((r, c)) = response
                    .interact_pointer_pos()
                    .and_then(|p| cell_at(p, origin, size, map.rows.len(), map.cols.len()))
            {
                match click(map, scope, r, c) {
                    Click::Select(p) => select = Some(p),
                    Click::Pieces(a, b) => v.pieces = Some((a, b)),
                    Click::Nothing => {}
                }
            }
            ui.label(
                egui::RichText::new(
                    "lighter: farther apart at the closest sampled; click a cell to select its pair",
                )
                .small()
                .weak(),
            );
        });
    if let Some(p) = select {
        selection.0 = Some(p);
    }
    if v != *view {
        *view = v;
    }
    Ok(())
}

/// Whether link-level `cell` holds pair `p` of the type (one of its piece pairs).
fn holds(
    map: &HeatMap,
    cell: &scm::matrix::Cell,
    data: &crate::model::SampledType,
    p: usize,
) -> bool {
    if !map.symmetric {
        return false;
    }
    let (a, b) = data.pair(p);
    let (la, lb) = (&data.matrix.shapes[a].link, &data.matrix.shapes[b].link);
    let (r, c) = (&map.rows[cell.row], &map.cols[cell.col]);
    (la == r && lb == c) || (la == c && lb == r)
}

/// The hover text of cell `(r, c)`: the pair, its verdict and statistics.
fn hover_text(map: &HeatMap, data: &crate::model::SampledType, r: usize, c: usize) -> String {
    if map.symmetric && r == c {
        return format!("{}: same link", map.rows[r]);
    }
    let Some(cell) = map.cell(r, c) else {
        return format!("{} - {}: no pair", map.rows[r], map.cols[c]);
    };
    let mut text = format!(
        "{} - {}\n{}",
        map.rows[cell.row],
        map.cols[cell.col],
        cell.verdict.label()
    );
    if let Some(p) = cell.pair {
        let s = &data.matrix.stats[p];
        text += &format!(
            "\nd_min {:.2} mm, d_mean {:.2} mm, d_max {:.2} mm\nin collision {:.2}% of samples",
            s.d_min * 1000.0,
            s.d_mean * 1000.0,
            s.d_max * 1000.0,
            100.0 * s.collision_fraction
        );
        if !data.exact[p].is_empty() {
            text += &format!("\nexact geometry: {}", data.exact[p]);
        }
    } else {
        if let Some(d) = cell.d_min {
            text += &format!("\nd_min {:.2} mm", d * 1000.0);
        }
        if cell.pairs > 1 {
            text += &format!("\n{} piece pairs: click to open them", cell.pairs);
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::matrix;

    #[test]
    fn a_click_selects_the_cell_pair_on_either_side_of_the_diagonal() {
        let m = matrix(4); // links l0..l3, pairs (0,1) (0,2) (0,3) (1,2) (1,3) (2,3)
        let order: Vec<String> = (0..4).map(|i| format!("l{i}")).collect();
        let map = HeatMap::of_type(&m, &order);
        assert_eq!(click(&map, Scope::Link, 1, 3), Click::Select(4));
        assert_eq!(click(&map, Scope::Link, 3, 1), Click::Select(4));
        assert_eq!(click(&map, Scope::Link, 2, 2), Click::Nothing);
        // The adjacent pair (0,1) and a checked one keep their verdicts.
        assert_eq!(map.cell(0, 1).map(|c| c.verdict), Some(Verdict::Adjacent));
        assert_eq!(map.cell(2, 3).map(|c| c.verdict), Some(Verdict::Checked));
    }

    #[test]
    fn a_decomposition_cell_opens_its_piece_grid_whose_cells_select_piece_pairs() {
        // Two links with two pieces each: l0#0 l0#1 l1#0 l1#1.
        let (mut shapes, mut file) = crate::fixtures::sample(4);
        for (i, s) in shapes.iter_mut().enumerate() {
            s.link = format!("l{}", i / 2);
            s.link_index = i / 2;
            s.piece = i % 2;
        }
        file.shape_type = ShapeType::DecompSphere;
        let m = scm::matrix::SkipMatrix::resolve(
            shapes,
            file,
            None,
            &scm::matrix::UserLayer::default(),
        )
        .expect("sizes agree");
        let order = vec!["l0".to_string(), "l1".to_string()];
        let links = HeatMap::of_type(&m, &order);
        let cell = links.cell(1, 0).expect("the link pair");
        assert_eq!((cell.pairs, cell.pair), (4, None));
        assert_eq!(
            click(&links, Scope::Pieces, 1, 0),
            Click::Pieces("l0".into(), "l1".into())
        );
        let pieces = HeatMap::pieces(&m, "l0", "l1").expect("piece grid");
        assert_eq!((pieces.rows.len(), pieces.cols.len()), (2, 2));
        // Row l0#1, column l1#0: shapes 1 and 2.
        assert_eq!(
            click(&pieces, Scope::Pieces, 1, 0),
            Click::Select(m.pair_index(1, 2))
        );
    }

    #[test]
    fn the_pointer_maps_to_cells_inside_the_grid_only() {
        let o = egui::pos2(10.0, 20.0);
        assert_eq!(cell_at(egui::pos2(10.5, 20.5), o, 8.0, 4, 4), Some((0, 0)));
        assert_eq!(cell_at(egui::pos2(35.0, 29.0), o, 8.0, 4, 4), Some((1, 3)));
        assert_eq!(cell_at(egui::pos2(43.0, 29.0), o, 8.0, 4, 4), None);
        assert_eq!(cell_at(egui::pos2(9.0, 29.0), o, 8.0, 4, 4), None);
    }
}

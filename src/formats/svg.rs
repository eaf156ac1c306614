//! SVG heat maps of the matrices (`scm export --format svg`): the same picture as the viewer's matrix
//! view, for READMEs, reviews and CI reports. Link names on both axes, one square per pair coloured
//! by verdict and shaded by `d_min` (hover shows the pair), and a legend with counts.

use super::xml_escape;
use crate::matrix::{HeatMap, SHADE_RANGE, Verdict};
use std::fmt::Write;

/// Label font size (px) and the width one character takes at it, roughly.
const FONT: f64 = 11.0;
const CHAR: f64 = 6.6;
const MARGIN: f64 = 12.0;

/// The side of one cell (px): large for small robots, never below 6 px.
fn cell_size(n: usize) -> f64 {
    (720.0 / n.max(1) as f64).clamp(6.0, 18.0).floor()
}

fn hex(rgb: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2])
}

/// What the shade means.
fn legend_note() -> String {
    format!(
        "lighter: farther apart at the closest sampled (d_min 0 to {:.0} mm and beyond)",
        SHADE_RANGE * 1000.0
    )
}

/// The heat map as a standalone SVG document.
pub fn write_svg(map: &HeatMap) -> String {
    let c = cell_size(map.rows.len().max(map.cols.len()));
    let longest = |labels: &[String]| labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let left = MARGIN + longest(&map.rows) as f64 * CHAR + 6.0;
    let top = MARGIN + 22.0 + longest(&map.cols) as f64 * CHAR + 6.0;
    let (w, h) = (map.cols.len() as f64 * c, map.rows.len() as f64 * c);
    let counts = map.counts();
    let legend: Vec<(Verdict, usize)> = Verdict::ALL
        .into_iter()
        .filter_map(|v| counts.get(&v).map(|&n| (v, n)))
        .collect();
    let legend_top = top + h + 16.0;
    let note = legend_note();
    let text_width =
        (map.title.chars().count() as f64 * 8.6).max(note.chars().count() as f64 * CHAR);
    let width = (left + w).max(MARGIN + text_width) + MARGIN;
    let height = legend_top + 18.0 * (legend.len() as f64 + 1.0) + MARGIN;

    let mut s = String::new();
    // Writing to a String cannot fail: the `let _ =` below drop an always-Ok result.
    let _ = writeln!(
        s,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="monospace" font-size="{FONT}">"##
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN}" y="{:.0}" font-size="14" font-weight="bold">{}</text>"##,
        MARGIN + 12.0,
        xml_escape(&map.title)
    );
    for (i, label) in map.rows.iter().enumerate() {
        let _ = writeln!(
            s,
            r##"<text x="{:.1}" y="{:.1}" text-anchor="end" dominant-baseline="middle">{}</text>"##,
            left - 4.0,
            top + (i as f64 + 0.5) * c,
            xml_escape(label)
        );
    }
    for (j, label) in map.cols.iter().enumerate() {
        let (x, y) = (left + (j as f64 + 0.5) * c, top - 4.0);
        let _ = writeln!(
            s,
            r##"<text transform="translate({x:.1},{y:.1}) rotate(-90)" dominant-baseline="middle">{}</text>"##,
            xml_escape(label)
        );
    }
    let _ = writeln!(
        s,
        r##"<rect x="{left:.1}" y="{top:.1}" width="{w:.1}" height="{h:.1}" fill="#f4f4f4" stroke="#999999"/>"##
    );
    if map.symmetric {
        for i in 0..map.rows.len() {
            let _ = writeln!(
                s,
                r##"<rect x="{:.1}" y="{:.1}" width="{c}" height="{c}" fill="{}"/>"##,
                left + i as f64 * c,
                top + i as f64 * c,
                hex(Verdict::SameLink.rgb())
            );
        }
    }
    for cell in &map.cells {
        let d = cell.d_min.map_or("no distance".to_string(), |d| {
            format!("d_min {:.1} mm", d * 1000.0)
        });
        let what = if cell.pairs > 1 {
            format!(", {} shape pairs", cell.pairs)
        } else {
            String::new()
        };
        let tip = format!(
            "{} - {}: {}; {d}{what}",
            map.rows[cell.row],
            map.cols[cell.col],
            cell.verdict.label()
        );
        let fill = hex(cell.verdict.shaded(cell.d_min));
        let mut places = vec![(cell.row, cell.col)];
        if map.symmetric {
            places.push((cell.col, cell.row));
        }
        for (r, col) in places {
            let _ = writeln!(
                s,
                r##"<rect x="{:.1}" y="{:.1}" width="{c}" height="{c}" fill="{fill}" stroke="#ffffff" stroke-width="0.5"><title>{}</title></rect>"##,
                left + col as f64 * c,
                top + r as f64 * c,
                xml_escape(&tip)
            );
        }
    }
    for (k, (v, n)) in legend.iter().enumerate() {
        let y = legend_top + 18.0 * k as f64;
        let _ = writeln!(
            s,
            r##"<rect x="{MARGIN}" y="{y:.1}" width="12" height="12" fill="{}"/><text x="{:.1}" y="{:.1}">{} ({n})</text>"##,
            hex(v.rgb()),
            MARGIN + 18.0,
            y + 10.0,
            xml_escape(v.label())
        );
    }
    let _ = writeln!(
        s,
        r##"<text x="{MARGIN}" y="{:.1}" fill="#555555">{note}</text>"##,
        legend_top + 18.0 * legend.len() as f64 + 10.0,
    );
    s.push_str("</svg>\n");
    s
}

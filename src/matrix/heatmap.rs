//! The matrix as a picture: links on both axes in kinematic order, each cell coloured by its verdict
//! (adjacent, default, always, never certified, never sampled, checked, a person's mark) and shaded by
//! how close the pair came (`d_min`). One model for the viewer's matrix view and for
//! `scm export --format svg`, so both show the same colours for the same verdicts.

use super::{Entry, Layer, LinkPair, SkipMatrix};
use crate::sample::NeverEvidence;
use crate::shapes::Scope;
use std::collections::{BTreeMap, HashMap};

/// What a cell shows: the verdict and, for a skip, why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Verdict {
    /// Shapes of one link (the diagonal).
    SameLink,
    /// Joined by a joint: skipped.
    Adjacent,
    /// In collision at the home configuration: skipped.
    Default,
    /// In collision in every sample: skipped.
    Always,
    /// Never in collision, proved by a certificate: skipped.
    NeverCertified,
    /// Never in collision in the samples, not proved: skipped.
    NeverSampled,
    /// Skipped by the imported MoveIt SRDF.
    Imported,
    /// Skipped by a person's mark.
    UserSkip,
    /// Checked by a person's mark.
    UserCheck,
    /// Checked.
    Checked,
}

impl Verdict {
    /// Every verdict, in legend order.
    pub const ALL: [Verdict; 10] = [
        Verdict::Checked,
        Verdict::Adjacent,
        Verdict::Default,
        Verdict::Always,
        Verdict::NeverCertified,
        Verdict::NeverSampled,
        Verdict::Imported,
        Verdict::UserSkip,
        Verdict::UserCheck,
        Verdict::SameLink,
    ];

    /// The verdict of a matrix entry; `evidence` says whether a `never` was certified (a `never`
    /// without evidence was decided by sampling).
    pub fn of(entry: &Entry, evidence: Option<NeverEvidence>) -> Verdict {
        match entry.layer {
            Layer::User if entry.skip => Verdict::UserSkip,
            Layer::User => Verdict::UserCheck,
            Layer::Imported if entry.skip => Verdict::Imported,
            Layer::Imported => Verdict::Checked,
            Layer::Inferred => match entry.reason.as_str() {
                "same-link" => Verdict::SameLink,
                "adjacent" => Verdict::Adjacent,
                "default" => Verdict::Default,
                "always" => Verdict::Always,
                "never" if evidence == Some(NeverEvidence::Certified) => Verdict::NeverCertified,
                "never" => Verdict::NeverSampled,
                _ => Verdict::Checked,
            },
        }
    }

    /// The legend's text.
    pub fn label(self) -> &'static str {
        match self {
            Verdict::SameLink => "same link",
            Verdict::Adjacent => "skip: adjacent",
            Verdict::Default => "skip: default (collides at home)",
            Verdict::Always => "skip: always colliding",
            Verdict::NeverCertified => "skip: never, certified",
            Verdict::NeverSampled => "skip: never, sampled only",
            Verdict::Imported => "skip: imported from MoveIt",
            Verdict::UserSkip => "skip: user mark",
            Verdict::UserCheck => "check: user mark",
            Verdict::Checked => "check",
        }
    }

    /// Whether a collision check skips the pair.
    pub fn skips(self) -> bool {
        !matches!(self, Verdict::Checked | Verdict::UserCheck)
    }

    /// The cell's colour at `d_min <= 0` (sRGB). The hues are far apart so that a picture (and the
    /// render test) can tell the verdicts apart at any shade.
    pub fn rgb(self) -> [u8; 3] {
        match self {
            Verdict::SameLink => [64, 64, 64],
            Verdict::Adjacent => [140, 140, 140],
            Verdict::Default => [150, 70, 210],
            Verdict::Always => [210, 30, 30],
            Verdict::NeverCertified => [20, 150, 60],
            Verdict::NeverSampled => [40, 170, 190],
            Verdict::Imported => [150, 100, 40],
            Verdict::UserSkip => [230, 40, 170],
            Verdict::UserCheck => [110, 20, 90],
            Verdict::Checked => [240, 120, 0],
        }
    }

    /// The cell's colour for a pair that came `d_min` close: the verdict's colour mixed towards
    /// white the farther apart the pair stayed, reaching 60% white at [`SHADE_RANGE`] and beyond.
    /// Pairs without a distance, and the diagonal, are not shaded.
    pub fn shaded(self, d_min: Option<f64>) -> [u8; 3] {
        let t = match d_min {
            Some(d) if d.is_finite() && self != Verdict::SameLink => {
                0.6 * (d / SHADE_RANGE).clamp(0.0, 1.0)
            }
            _ => 0.0,
        };
        self.rgb()
            .map(|c| (c as f64 + (255.0 - c as f64) * t).round() as u8)
    }
}

/// The `d_min` (m) at and above which a cell has its lightest shade.
pub const SHADE_RANGE: f64 = 0.25;

/// One cell of a heat map.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// Row (index into [`HeatMap::rows`]).
    pub row: usize,
    /// Column (index into [`HeatMap::cols`]).
    pub col: usize,
    /// The verdict.
    pub verdict: Verdict,
    /// The smallest signed distance sampled over the shape pairs behind the cell (m).
    pub d_min: Option<f64>,
    /// The matrix pair the cell stands for, when it stands for exactly one.
    pub pair: Option<usize>,
    /// Shape pairs behind the cell.
    pub pairs: usize,
}

/// A matrix picture: row and column labels and the cells that have a verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatMap {
    /// What the picture shows.
    pub title: String,
    /// Row labels.
    pub rows: Vec<String>,
    /// Column labels.
    pub cols: Vec<String>,
    /// Symmetric (links against the same links): each cell is stored once with `row < col` and
    /// drawn on both sides of the diagonal, which shows [`Verdict::SameLink`].
    pub symmetric: bool,
    /// The cells, by row then column.
    pub cells: Vec<Cell>,
}

/// Per link pair `(row, col)` with `row < col` in the axis order: the smallest `d_min`, the number
/// of shape pairs, and the one pair index when there is one.
type LinkStats = BTreeMap<(usize, usize), (f64, usize, usize)>;

impl HeatMap {
    /// A type's matrix, links against links in `order` (link names in kinematic order; links of the
    /// matrix missing from it go last). A whole-link type has one pair per cell; for a decomposition
    /// type a cell is the link pair's verdict (skipped only when every piece pair is) and its smallest
    /// piece `d_min`, and [`HeatMap::pieces`] opens it.
    pub fn of_type(m: &SkipMatrix, order: &[String]) -> HeatMap {
        let links = axis(&m.links(), order);
        let stats = link_stats(m, &links);
        let pieces = m.shape_type.scope() == Scope::Pieces;
        let cells = m
            .link_pairs()
            .iter()
            .filter_map(|lp| {
                let (row, col) = position(&links, &lp.link1, &lp.link2)?;
                let (d_min, pairs, pair) = stats.get(&(row, col)).copied()?;
                Some(Cell {
                    row,
                    col,
                    verdict: Verdict::of(&lp.entry, None),
                    d_min: Some(d_min),
                    pair: (!pieces).then_some(pair),
                    pairs,
                })
            })
            .collect();
        HeatMap::symmetric(format!("{} pairs", m.shape_type), links, cells)
    }

    /// The link pairs the exported files carry (`pairs`, decided on the exact geometry), shaded by
    /// the smallest `d_min` of `stats`'s shape pairs between the two links; a cell selects its pair
    /// of `stats` when that type has one shape per link.
    pub fn of_link_pairs(
        title: String,
        pairs: &[LinkPair],
        stats: &SkipMatrix,
        order: &[String],
    ) -> HeatMap {
        let names: Vec<String> = {
            let mut seen = stats.links();
            for p in pairs {
                for l in [&p.link1, &p.link2] {
                    if !seen.contains(l) {
                        seen.push(l.clone());
                    }
                }
            }
            seen
        };
        let links = axis(&names, order);
        let link_stats = link_stats(stats, &links);
        let whole = stats.shape_type.scope() == Scope::Link;
        let cells = pairs
            .iter()
            .filter_map(|lp| {
                let (row, col) = position(&links, &lp.link1, &lp.link2)?;
                let found = link_stats.get(&(row, col)).copied();
                Some(Cell {
                    row,
                    col,
                    verdict: Verdict::of(&lp.entry, lp.evidence),
                    d_min: found.map(|s| s.0),
                    pair: found.filter(|_| whole).map(|s| s.2),
                    pairs: 1,
                })
            })
            .collect();
        HeatMap::symmetric(title, links, cells)
    }

    /// The piece pairs of links `a` (rows) and `b` (columns) of a decomposition type, each cell one
    /// pair; `None` when either link has no pieces or they are the same link.
    pub fn pieces(m: &SkipMatrix, a: &str, b: &str) -> Option<HeatMap> {
        let of = |link: &str| -> Vec<usize> {
            (0..m.shapes.len())
                .filter(|&i| m.shapes[i].link == link)
                .collect()
        };
        let (ra, rb) = (of(a), of(b));
        if ra.is_empty() || rb.is_empty() || a == b {
            return None;
        }
        let label = |i: usize| format!("{}#{}", m.shapes[i].link, m.shapes[i].piece);
        let mut cells = Vec::new();
        for (row, &i) in ra.iter().enumerate() {
            for (col, &j) in rb.iter().enumerate() {
                let p = m.pair_index(i, j);
                cells.push(Cell {
                    row,
                    col,
                    verdict: Verdict::of(&m.entries[p], None),
                    d_min: Some(m.stats[p].d_min),
                    pair: Some(p),
                    pairs: 1,
                });
            }
        }
        Some(HeatMap {
            title: format!("{} pieces of {a} - {b}", m.shape_type),
            rows: ra.into_iter().map(label).collect(),
            cols: rb.into_iter().map(label).collect(),
            symmetric: false,
            cells,
        })
    }

    fn symmetric(title: String, links: Vec<String>, mut cells: Vec<Cell>) -> HeatMap {
        cells.sort_by_key(|c| (c.row, c.col));
        HeatMap {
            title,
            cols: links.clone(),
            rows: links,
            symmetric: true,
            cells,
        }
    }

    /// The cell at `(row, col)` (either side of the diagonal of a symmetric map).
    pub fn cell(&self, row: usize, col: usize) -> Option<&Cell> {
        let (r, c) = if self.symmetric && row > col {
            (col, row)
        } else {
            (row, col)
        };
        self.cells
            .binary_search_by_key(&(r, c), |x| (x.row, x.col))
            .ok()
            .map(|i| &self.cells[i])
    }

    /// How many cells have each verdict (each pair once).
    pub fn counts(&self) -> BTreeMap<Verdict, usize> {
        let mut out = BTreeMap::new();
        for c in &self.cells {
            *out.entry(c.verdict).or_insert(0) += 1;
        }
        out
    }
}

/// `names` ordered as they appear in `order`, the rest after them in their own order.
fn axis(names: &[String], order: &[String]) -> Vec<String> {
    let rank: HashMap<&str, usize> = order
        .iter()
        .enumerate()
        .map(|(i, n)| (n.as_str(), i))
        .collect();
    let mut out: Vec<(usize, usize, &String)> = names
        .iter()
        .enumerate()
        .map(|(i, n)| (rank.get(n.as_str()).copied().unwrap_or(usize::MAX), i, n))
        .collect();
    out.sort();
    out.into_iter().map(|(_, _, n)| n.clone()).collect()
}

/// The cell of links `a` and `b` with `row < col`; `None` for a link off the axis or the diagonal.
fn position(links: &[String], a: &str, b: &str) -> Option<(usize, usize)> {
    let i = links.iter().position(|l| l == a)?;
    let j = links.iter().position(|l| l == b)?;
    (i != j).then(|| (i.min(j), i.max(j)))
}

fn link_stats(m: &SkipMatrix, links: &[String]) -> LinkStats {
    let mut out = LinkStats::new();
    for (p, s) in m.stats.iter().enumerate() {
        let Some(key) = position(links, &m.shapes[s.a].link, &m.shapes[s.b].link) else {
            continue;
        };
        let e = out.entry(key).or_insert((f64::INFINITY, 0, p));
        if s.d_min < e.0 {
            e.0 = s.d_min;
        }
        e.1 += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(reason: &str, skip: bool, layer: Layer) -> Entry {
        Entry {
            skip,
            reason: reason.into(),
            layer,
        }
    }

    #[test]
    fn verdicts_follow_the_layer_reason_and_evidence() {
        let never = entry("never", true, Layer::Inferred);
        assert_eq!(
            Verdict::of(&never, Some(NeverEvidence::Certified)),
            Verdict::NeverCertified
        );
        assert_eq!(
            Verdict::of(&never, Some(NeverEvidence::Sampled)),
            Verdict::NeverSampled
        );
        assert_eq!(Verdict::of(&never, None), Verdict::NeverSampled);
        let user = entry("user", false, Layer::User);
        assert_eq!(Verdict::of(&user, None), Verdict::UserCheck);
        let enabled = entry("enabled", false, Layer::Imported);
        assert_eq!(Verdict::of(&enabled, None), Verdict::Checked);
        assert!(!Verdict::Checked.skips() && Verdict::Imported.skips());
    }

    #[test]
    fn shading_lightens_with_distance_and_keeps_the_hue() {
        let v = Verdict::Checked;
        assert_eq!(v.shaded(Some(-0.01)), v.rgb());
        assert_eq!(v.shaded(None), v.rgb());
        let far = v.shaded(Some(10.0));
        assert_eq!(far, v.shaded(Some(SHADE_RANGE)));
        let mid = v.shaded(Some(SHADE_RANGE / 2.0));
        for k in 0..3 {
            assert!(v.rgb()[k] <= mid[k] && mid[k] <= far[k]);
        }
        // Red stays the largest channel: the hue survives the shade.
        assert!(far[0] > far[1] && far[1] > far[2]);
    }

    #[test]
    fn axis_follows_the_kinematic_order() {
        let names: Vec<String> = ["c", "a", "x", "b"].map(String::from).to_vec();
        let order: Vec<String> = ["a", "b", "c"].map(String::from).to_vec();
        assert_eq!(axis(&names, &order), vec!["a", "b", "c", "x"]);
    }
}

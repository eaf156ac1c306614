//! The pair list: which pairs of a type to show and in which order (by current distance, by current
//! distance over mean distance, by minimum sampled distance), filtered by text (names, reason, layer,
//! and the link pair's verdict and evidence on the exact geometry). Plain Rust, no Bevy.

use scm::matrix::SkipMatrix;
use scm::sample::PairRecord;
use scm::urdd::ShapeRecord;

/// What the list is sorted by (ascending: the closest or most suspicious pairs first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SortKey {
    /// Signed distance in the current configuration.
    #[default]
    Current,
    /// Current distance over the sampled mean distance ([`ratio`]).
    Ratio,
    /// Minimum distance over the samples.
    DMin,
}

impl SortKey {
    /// Every key, in the order the panel offers them.
    pub const ALL: [SortKey; 3] = [SortKey::Current, SortKey::Ratio, SortKey::DMin];

    /// The id used in action scripts.
    pub fn id(self) -> &'static str {
        match self {
            SortKey::Current => "current",
            SortKey::Ratio => "ratio",
            SortKey::DMin => "dmin",
        }
    }

    /// The key named `id`.
    pub fn from_id(id: &str) -> Option<SortKey> {
        SortKey::ALL.into_iter().find(|k| k.id() == id)
    }

    /// The label shown in the panel.
    pub fn label(self) -> &'static str {
        match self {
            SortKey::Current => "d (current)",
            SortKey::Ratio => "d / d_mean",
            SortKey::DMin => "d_min",
        }
    }
}

/// Current distance `d` over the pair's mean sampled distance: near 0 (or below) when the pair is
/// unusually close now. A pair whose mean is not positive (it collides most of the time) gets minus
/// infinity, so it counts as the closest.
pub fn ratio(d: f64, stats: &PairRecord) -> f64 {
    if stats.d_mean > 0.0 {
        d / stats.d_mean
    } else {
        f64::NEG_INFINITY
    }
}

/// `d / d_mean` for the list: an em dash where the ratio is undefined (the mean is not positive).
pub fn ratio_text(r: f64) -> String {
    if r.is_finite() {
        format!("{r:.2}")
    } else {
        "\u{2014}".into()
    }
}

/// The link pair's verdict on the exact geometry as the list shows and filters it: the reason, and
/// for `never` its evidence (`never certified`, `never sampled`).
pub fn exact_text(r: &scm::sample::LinkPairRecord) -> String {
    match r.evidence {
        Some(e) => format!("{} {}", r.reason.id(), e.id()),
        None => r.reason.id().to_string(),
    }
}

/// Two names with their shared prefix and suffix (whole words, cut at `_`, `-`, ...) written once:
/// `leg_{left,right}_4_link`. Names that share too little (under four characters) stay `a - b`.
pub fn compact_pair(a: &str, b: &str) -> String {
    let (ca, cb): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let separator = |c: &char| !c.is_alphanumeric();
    // The shared parts end and start at a separator, so a word is never split: `leg_{left,right}`,
    // not `leg_{lef,righ}t`.
    let mut prefix = ca.iter().zip(&cb).take_while(|(x, y)| x == y).count();
    while prefix > 0 && !separator(&ca[prefix - 1]) {
        prefix -= 1;
    }
    let rest = ca.len().min(cb.len()) - prefix;
    let mut suffix = ca
        .iter()
        .rev()
        .zip(cb.iter().rev())
        .take(rest)
        .take_while(|(x, y)| x == y)
        .count();
    while suffix > 0 && !separator(&ca[ca.len() - suffix]) {
        suffix -= 1;
    }
    let (ma, mb) = (
        &ca[prefix..ca.len() - suffix],
        &cb[prefix..cb.len() - suffix],
    );
    if prefix + suffix < 4 || ma.is_empty() || mb.is_empty() {
        return format!("{a} - {b}");
    }
    let text = |c: &[char]| c.iter().collect::<String>();
    format!(
        "{}{{{},{}}}{}",
        text(&ca[..prefix]),
        text(ma),
        text(mb),
        text(&ca[ca.len() - suffix..])
    )
}

/// `link#piece`, or just `link` for whole-link types.
pub fn shape_label(shape: &ShapeRecord, pieces: bool) -> String {
    if pieces {
        format!("{}#{}", shape.link, shape.piece)
    } else {
        shape.link.clone()
    }
}

/// The two shapes of pair `p` (`a - b`, or with `compact` their shared prefix and suffix once).
pub fn pair_label(m: &SkipMatrix, p: usize, compact: bool) -> String {
    let s = &m.stats[p];
    let pieces = m.shape_type.scope() == scm::shapes::Scope::Pieces;
    let (a, b) = (
        shape_label(&m.shapes[s.a], pieces),
        shape_label(&m.shapes[s.b], pieces),
    );
    if compact {
        compact_pair(&a, &b)
    } else {
        format!("{a} - {b}")
    }
}

/// The value of `key` for pair `p` given the current distances.
pub fn sort_value(m: &SkipMatrix, distances: &[f64], p: usize, key: SortKey) -> f64 {
    let d = distances.get(p).copied().unwrap_or(f64::NAN);
    match key {
        SortKey::Current => d,
        SortKey::Ratio => ratio(d, &m.stats[p]),
        SortKey::DMin => m.stats[p].d_min,
    }
}

/// The pairs to list: those whose names, reason, layer, skip or check, or verdict on the exact
/// geometry (`exact[p]`, e.g. `never certified`) contain `filter` (case-insensitive; every
/// whitespace-separated word must match), sorted ascending by `key` (ties by pair index).
pub fn visible_pairs(
    m: &SkipMatrix,
    exact: &[String],
    distances: &[f64],
    key: SortKey,
    filter: &str,
) -> Vec<usize> {
    let words: Vec<String> = filter.split_whitespace().map(str::to_lowercase).collect();
    let mut rows: Vec<(f64, usize)> = (0..m.entries.len())
        .filter(|&p| {
            if words.is_empty() {
                return true;
            }
            let entry = &m.entries[p];
            let text = format!(
                "{} {} {} {} {}",
                pair_label(m, p, false),
                entry.reason,
                entry.layer.id(),
                if entry.skip { "skip" } else { "check" },
                exact.get(p).map_or("", String::as_str)
            )
            .to_lowercase();
            words.iter().all(|w| text.contains(w.as_str()))
        })
        .map(|p| (sort_value(m, distances, p, key), p))
        .collect();
    rows.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    rows.into_iter().map(|(_, p)| p).collect()
}

/// The pair of shapes named `a` and `b` (`link` or `link#piece`, any order), if the type has it.
pub fn find_pair(m: &SkipMatrix, a: &str, b: &str) -> Option<usize> {
    let find = |name: &str| {
        let (link, piece) = match name.rsplit_once('#') {
            Some((l, p)) => (l, p.parse::<usize>().ok()?),
            None => (name, 0),
        };
        m.shapes
            .iter()
            .position(|s| s.link == link && s.piece == piece)
    };
    let (a, b) = (find(a)?, find(b)?);
    (a != b).then(|| m.pair_index(a, b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::matrix;

    #[test]
    fn sorts_by_each_key_ascending() {
        let m = matrix(4); // pairs (0,1) (0,2) (0,3) (1,2) (1,3) (2,3)
        let d = [0.3, -0.02, 0.1, 0.05, 0.2, 0.0];
        assert_eq!(
            visible_pairs(&m, &[], &d, SortKey::Current, ""),
            vec![1, 5, 3, 2, 4, 0]
        );
        // d_mean is 0.1 everywhere: the ratio orders like the distance.
        assert_eq!(
            visible_pairs(&m, &[], &d, SortKey::Ratio, ""),
            vec![1, 5, 3, 2, 4, 0]
        );
        // d_min falls with the pair index.
        assert_eq!(
            visible_pairs(&m, &[], &d, SortKey::DMin, ""),
            vec![5, 4, 3, 2, 1, 0]
        );
    }

    #[test]
    fn filter_matches_every_word_in_names_and_reasons() {
        let m = matrix(4);
        let d = [0.0; 6];
        assert_eq!(
            visible_pairs(&m, &[], &d, SortKey::Current, "l1"),
            vec![0, 3, 4]
        );
        assert_eq!(
            visible_pairs(&m, &[], &d, SortKey::Current, "L1 l3"),
            vec![4]
        );
        assert_eq!(
            visible_pairs(&m, &[], &d, SortKey::Current, "adjacent"),
            vec![0]
        );
        assert!(visible_pairs(&m, &[], &d, SortKey::Current, "nothing").is_empty());
    }

    #[test]
    fn filter_selects_by_evidence_on_the_exact_geometry() {
        let m = matrix(3); // pairs (0,1) (0,2) (1,2)
        let exact: Vec<String> = ["adjacent", "never certified", "never sampled"]
            .map(String::from)
            .to_vec();
        let d = [0.0; 3];
        let f = |text| visible_pairs(&m, &exact, &d, SortKey::Current, text);
        assert_eq!(f("never"), vec![1, 2]);
        assert_eq!(f("certified"), vec![1]);
        assert_eq!(f("never sampled"), vec![2]);
    }

    #[test]
    fn compact_names_write_the_shared_parts_once() {
        assert_eq!(
            compact_pair("leg_left_4_link", "leg_right_4_link"),
            "leg_{left,right}_4_link"
        );
        assert_eq!(
            compact_pair(
                "gripper_right_inner_double_link",
                "gripper_right_outer_knuckle"
            ),
            "gripper_right_{inner_double_link,outer_knuckle}"
        );
        // Too little in common, or one name inside the other: both in full.
        assert_eq!(compact_pair("base", "hand"), "base - hand");
        assert_eq!(compact_pair("link1", "link10"), "link1 - link10");
        assert_eq!(ratio_text(f64::NEG_INFINITY), "\u{2014}");
        assert_eq!(ratio_text(0.5), "0.50");
    }

    #[test]
    fn ratio_of_a_pair_that_mostly_collides_is_minus_infinity() {
        let mut m = matrix(2);
        assert_eq!(ratio(0.05, &m.stats[0]), 0.5);
        m.stats[0].d_mean = -0.01;
        assert_eq!(ratio(0.05, &m.stats[0]), f64::NEG_INFINITY);
    }

    #[test]
    fn finds_pairs_by_link_and_piece_in_any_order() {
        let m = matrix(4);
        assert_eq!(find_pair(&m, "l3", "l1"), Some(4));
        assert_eq!(find_pair(&m, "l1#0", "l2"), Some(3));
        assert_eq!(find_pair(&m, "l1", "l1"), None);
        assert_eq!(find_pair(&m, "l1#1", "l2"), None);
        assert_eq!(pair_label(&m, 4, false), "l1 - l3");
    }
}

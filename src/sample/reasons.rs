//! Skip inference: why a collision check may skip a shape pair.

use serde::{Deserialize, Serialize};

/// The reason a pair is skipped, or `Checked` when it must be checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reason {
    /// Both shapes belong to the same link.
    SameLink,
    /// The links are joined by a joint (possibly through links without geometry).
    Adjacent,
    /// In collision at the home configuration.
    Default,
    /// In collision in at least the `always` fraction of the samples.
    Always,
    /// Never in collision in any sample (nor found by the targeted search).
    Never,
    /// Must be checked.
    Checked,
}

impl Reason {
    /// All reasons, in precedence order.
    pub const ALL: [Reason; 6] = [
        Reason::SameLink,
        Reason::Adjacent,
        Reason::Default,
        Reason::Always,
        Reason::Never,
        Reason::Checked,
    ];

    /// Whether a collision check may skip the pair.
    pub fn skips(self) -> bool {
        self != Reason::Checked
    }

    /// The id used in files.
    pub fn id(self) -> &'static str {
        match self {
            Reason::SameLink => "same-link",
            Reason::Adjacent => "adjacent",
            Reason::Default => "default",
            Reason::Always => "always",
            Reason::Never => "never",
            Reason::Checked => "checked",
        }
    }
}

/// What is known of a pair when its reason is decided.
#[derive(Debug, Clone, Copy)]
pub struct Evidence {
    /// Same link.
    pub same_link: bool,
    /// Adjacent links.
    pub adjacent: bool,
    /// In collision at home.
    pub home_collision: bool,
    /// Fraction of samples in collision.
    pub collision_fraction: f64,
    /// Whether the targeted search found a collision.
    pub search_collision: bool,
}

/// The first reason that applies, in MoveIt's precedence: same link, adjacent, default, always, never.
pub fn infer(e: &Evidence, always_fraction: f64) -> Reason {
    if e.same_link {
        Reason::SameLink
    } else if e.adjacent {
        Reason::Adjacent
    } else if e.home_collision {
        Reason::Default
    } else if e.collision_fraction >= always_fraction {
        Reason::Always
    } else if e.collision_fraction == 0.0 && !e.search_collision {
        Reason::Never
    } else {
        Reason::Checked
    }
}

/// The 95% upper confidence bound on a collision probability after `n` samples without one
/// (the "rule of three": about 3/n).
pub fn never_upper_bound(n: u64) -> f64 {
    if n == 0 {
        1.0
    } else {
        1.0 - 0.05f64.powf(1.0 / n as f64)
    }
}

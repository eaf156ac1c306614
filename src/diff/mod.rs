//! `scm diff`: scm's verdicts against MoveIt's, link pair by link pair, with the evidence.

use crate::error::{Error, Result};
use crate::export::LinkLevel;
use crate::formats::srdf::parse_srdf;
use crate::matrix::{
    ImportedLayer, Layer, LinkPair, SkipMatrix, UserLayer, consumer_link_pairs, load_sample,
};
use crate::query::{Scratch, SelfChecker, SkipMode};
use crate::robot::{Kinematics, Robot};
use crate::sample::{LinkPairRecord, PairRecord, Reason, SearchOutcome, Status, load_mesh_file};
use crate::shapes::ShapeType;
use crate::urdd::Urdd;
use serde::{Serialize, Serializer};
use std::collections::HashMap;
use std::path::PathBuf;

mod report;
pub use report::{format_comparison, format_comparison_with};

/// What to compare.
#[derive(Debug, Clone)]
pub struct DiffOptions {
    /// The URDD directory (sampled).
    pub urdd: PathBuf,
    /// The SRDF to compare with; default the URDD's imported layer.
    pub srdf: Option<PathBuf>,
    /// The geometry whose verdicts stand for scm: `mesh` (what the exported files carry) or a type.
    pub link_level: LinkLevel,
}

/// What the configuration behind scm's verdict on a pair is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum WitnessKind {
    /// Where the exact geometry overlaps: the configuration that made scm check the pair.
    ExactOverlap,
    /// The home configuration, where the geometry touches (a `default` verdict).
    Home,
    /// A collision the targeted search found where sampling found none.
    SearchCollision,
    /// The closest approach of the link hulls the certificate search found.
    CertificateClosest,
    /// Where the sampled `d_min` was reached.
    ClosestSampled,
}

impl WitnessKind {
    /// The label used in the report and the JSON.
    pub fn label(self) -> &'static str {
        match self {
            WitnessKind::ExactOverlap => "exact geometry overlaps",
            WitnessKind::Home => "touches at home",
            WitnessKind::SearchCollision => "collision found by the search",
            WitnessKind::CertificateClosest => "closest found by the certificate",
            WitnessKind::ClosestSampled => "closest sampled",
        }
    }
}

impl Serialize for WitnessKind {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.label())
    }
}

/// The two links' signed distance at the witness configuration, and the geometry it was measured on.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WitnessDistance {
    /// Signed distance (m): negative is the penetration depth of the deepest shape pair between the
    /// two links.
    pub distance: f64,
    /// The shape type measured: the compared type, or for `mesh` the convex pieces the URDD has
    /// (`decomp-hull` when sampled, else `hull`); never the mesh itself.
    pub geometry: String,
}

/// One link pair on which scm and MoveIt disagree, with scm's evidence.
#[derive(Debug, Clone, Serialize)]
pub struct Disagreement {
    /// One link.
    pub link1: String,
    /// The other link.
    pub link2: String,
    /// MoveIt's verdict: its reason, or `checked`.
    pub moveit: String,
    /// scm's reason (`checked` when it keeps checking).
    pub scm: String,
    /// Smallest signed distance scm sampled between the two links (m), on [`Comparison::statistics`].
    pub d_min: f64,
    /// Largest fraction of samples in collision over the links' shape pairs.
    pub collision_fraction: f64,
    /// The geometry scm's verdict was decided on (`mesh` or a shape type; `user` for a person's mark).
    pub geometry: String,
    /// For scm's `never` on the exact geometry: `certified` or `sampled`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub evidence: Option<String>,
    /// The certificate's proved lower bound on the hulls' distance, or the exact geometry's where its
    /// second search ran (m), where one was searched.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lower_bound: Option<f64>,
    /// What `witness` is.
    pub witness_kind: WitnessKind,
    /// The configuration that decided scm's verdict: every DOF, by joint name.
    pub witness: Vec<(String, f64)>,
    /// The DOFs on the tree path between the two links: the only ones that move them relative to
    /// each other (a mimic joint counts through its leader).
    pub path_joints: Vec<String>,
    /// Where the witness is a collision: how deep, measured on convex shapes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub witness_distance: Option<WitnessDistance>,
}

/// The two lists of `scm diff`.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// What MoveIt's verdicts came from.
    pub moveit_source: String,
    /// The geometry standing for scm (`mesh` or a shape type).
    pub link_level: String,
    /// The shape type whose sampling statistics `d_min` and `collision_fraction` come from.
    pub statistics: String,
    /// Link pairs compared.
    pub link_pairs: usize,
    /// Pairs MoveIt disables that scm keeps checking: evidence that MoveIt's skip was wrong.
    pub moveit_skips_scm_checks: Vec<Disagreement>,
    /// Pairs scm skips that MoveIt checks.
    pub scm_skips_moveit_checks: Vec<Disagreement>,
}

/// Which joints the human report prints of each witness.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WitnessJoints {
    /// Only the joints on the path between the two links.
    Path,
    /// Every DOF of the robot.
    All,
}

/// Compares scm's inferred (and user) verdicts with MoveIt's.
pub fn diff(opts: &DiffOptions) -> Result<Comparison> {
    let urdd = Urdd::open(&opts.urdd)?;
    let (moveit, source) = moveit_layer(&urdd, opts)?;
    let robot = urdd.robot()?.robot;
    // The statistics come from the link hull (or the chosen type); the verdicts from the level.
    let stats_type = match opts.link_level {
        LinkLevel::Type(t) => t,
        LinkLevel::Mesh => ShapeType::Hull,
    };
    let shapes = urdd.shapes(stats_type)?.shapes;
    let sample = load_sample(&urdd, stats_type)?;
    let scm = SkipMatrix::resolve(shapes, sample, None, &UserLayer::load(&urdd)?)?;
    let mesh = match opts.link_level {
        LinkLevel::Mesh => Some(load_mesh_file(&urdd)?.ok_or_else(|| {
            Error::input(
                &opts.urdd,
                "sample/mesh.json",
                "missing: the sample output has no verdicts on the exact geometry; rerun `scm sample`",
            )
        })?),
        LinkLevel::Type(_) => None,
    };
    let pairs = match &mesh {
        Some(m) => consumer_link_pairs(scm.link_pairs(), m, false),
        None => scm.link_pairs(),
    };
    let lookup = moveit.lookup();
    let mut judge = Judge {
        urdd: &urdd,
        kinematics: Kinematics::new(&robot),
        robot: &robot,
        evidence: link_evidence(&scm),
        stats_type,
        probe: None,
    };

    let mut out = Comparison {
        moveit_source: source,
        link_level: opts.link_level.id().into(),
        statistics: stats_type.id().into(),
        link_pairs: 0,
        moveit_skips_scm_checks: Vec::new(),
        scm_skips_moveit_checks: Vec::new(),
    };
    for pair in pairs {
        out.link_pairs += 1;
        let moveit_verdict = lookup.get(&pair.link1, &pair.link2);
        let moveit_skips = moveit_verdict.is_some_and(|(skip, _)| skip);
        if moveit_skips == pair.entry.skip {
            continue;
        }
        let moveit_reason = match moveit_verdict {
            Some((true, reason)) => reason.to_string(),
            _ => "checked".into(),
        };
        let exact = mesh.as_ref().and_then(|m| m.pair(&pair.link1, &pair.link2));
        let d = judge.disagreement(&pair, moveit_reason, exact)?;
        if moveit_skips {
            out.moveit_skips_scm_checks.push(d);
        } else {
            out.scm_skips_moveit_checks.push(d);
        }
    }
    Ok(out)
}

/// MoveIt's verdicts: the SRDF given, else the URDD's imported layer; and where they came from.
fn moveit_layer(urdd: &Urdd, opts: &DiffOptions) -> Result<(ImportedLayer, String)> {
    let Some(path) = &opts.srdf else {
        let layer = ImportedLayer::load(urdd)?.ok_or_else(|| {
            Error::input(
                &opts.urdd,
                "layers/imported.json",
                "no MoveIt SRDF imported; run `scm import-moveit ROBOT.srdf DIR` or pass --srdf",
            )
        })?;
        let source = layer.source.clone();
        return Ok((layer, source));
    };
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))?;
    let srdf = parse_srdf(&text, path)?;
    let mut layer = ImportedLayer::new(path.display().to_string(), String::new(), srdf.robot);
    for (p, skip) in srdf
        .disabled
        .iter()
        .map(|p| (p, true))
        .chain(srdf.enabled.iter().map(|p| (p, false)))
    {
        layer.pairs.push(crate::matrix::ImportedPair {
            link1: p.link1.clone(),
            link2: p.link2.clone(),
            skip,
            reason: if skip {
                p.reason.clone().unwrap_or_default()
            } else {
                "enabled".into()
            },
        });
    }
    layer.default_disabled = srdf.default_disabled.into_iter().map(|(l, _)| l).collect();
    Ok((layer, path.display().to_string()))
}

/// One link pair's sampling statistics over its shape pairs.
#[derive(Debug, Clone, Copy)]
struct LinkEvidence<'a> {
    /// The shape pair with the smallest `d_min`.
    closest: &'a PairRecord,
    /// The largest collision fraction.
    fraction: f64,
    /// The smallest signed distance at home.
    home: f64,
    /// The deepest collision the targeted search found.
    searched: Option<&'a SearchOutcome>,
}

/// Per link pair (by link names), the statistics of its shape pairs.
fn link_evidence(m: &SkipMatrix) -> HashMap<(String, String), LinkEvidence<'_>> {
    let mut out: HashMap<(String, String), LinkEvidence<'_>> = HashMap::new();
    for p in &m.stats {
        let (a, b) = (&m.shapes[p.a].link, &m.shapes[p.b].link);
        if a == b {
            continue;
        }
        let e = out.entry((a.clone(), b.clone())).or_insert(LinkEvidence {
            closest: p,
            fraction: 0.0,
            home: f64::INFINITY,
            searched: None,
        });
        if p.d_min < e.closest.d_min {
            e.closest = p;
        }
        e.fraction = e.fraction.max(p.collision_fraction);
        e.home = e.home.min(p.home_distance);
        if let Some(s) = p.search.as_ref().filter(|s| s.collision)
            && e.searched.is_none_or(|t| s.d_min < t.d_min)
        {
            e.searched = Some(s);
        }
    }
    out
}

/// Whether (and on what) the two links collide at a witness configuration.
enum Collision {
    /// Not a collision (a closest approach).
    No,
    /// A collision of the compared type, of this signed distance.
    Measured(f64),
    /// The exact geometry overlaps: measured on convex shapes by a [`Probe`].
    Exact,
}

/// What turns scm's verdict on a link pair into a [`Disagreement`].
struct Judge<'a> {
    urdd: &'a Urdd,
    robot: &'a Robot,
    kinematics: Kinematics,
    evidence: HashMap<(String, String), LinkEvidence<'a>>,
    stats_type: ShapeType,
    /// Loaded at the first exact-geometry collision.
    probe: Option<Probe>,
}

impl Judge<'_> {
    fn disagreement(
        &mut self,
        pair: &LinkPair,
        moveit: String,
        exact: Option<&LinkPairRecord>,
    ) -> Result<Disagreement> {
        let key = (pair.link1.clone(), pair.link2.clone());
        let ev = *self.evidence.get(&key).ok_or_else(|| {
            Error::input(
                self.urdd.dir(),
                format!("link pair {} - {}", pair.link1, pair.link2),
                format!("no {} statistics; rerun `scm sample`", self.stats_type),
            )
        })?;
        let certificate = exact.and_then(|r| r.certificate.as_ref());
        let (kind, q, collision) = self.witness(pair, &ev, exact);
        let witness_distance = match collision {
            Collision::No => None,
            Collision::Measured(distance) => Some(WitnessDistance {
                distance,
                geometry: self.stats_type.id().into(),
            }),
            Collision::Exact => self.probe()?.distance(&q, &pair.link1, &pair.link2)?,
        };
        let dofs = self.kinematics.dofs();
        let path = self
            .kinematics
            .path_dofs(self.link_index(&pair.link1)?, self.link_index(&pair.link2)?);
        Ok(Disagreement {
            link1: pair.link1.clone(),
            link2: pair.link2.clone(),
            moveit,
            scm: pair.entry.reason.clone(),
            d_min: ev.closest.d_min,
            collision_fraction: ev.fraction,
            geometry: pair.geometry.clone(),
            evidence: pair.evidence.map(|e| e.id().to_string()),
            lower_bound: certificate.map(|c| c.lower_bound),
            witness_kind: kind,
            witness: dofs.iter().map(|d| d.name.clone()).zip(q).collect(),
            path_joints: path.iter().map(|&i| dofs[i].name.clone()).collect(),
            witness_distance,
        })
    }

    /// The configuration behind scm's verdict and whether the links collide there. On the exact
    /// geometry: home for a `default`, else where it overlaps, else the certificate's closest approach,
    /// else the sampled minimum. On a type: home for a `default` that collides there, else the sampled
    /// minimum when it collides, else the search's collision, else the sampled minimum.
    fn witness(
        &self,
        pair: &LinkPair,
        ev: &LinkEvidence<'_>,
        exact: Option<&LinkPairRecord>,
    ) -> (WitnessKind, Vec<f64>, Collision) {
        let sampled = || {
            let d = ev.closest.d_min;
            let collision = if exact.is_none() && d < 0.0 {
                Collision::Measured(d)
            } else {
                Collision::No
            };
            (
                WitnessKind::ClosestSampled,
                ev.closest.witness.q.clone(),
                collision,
            )
        };
        match exact {
            Some(r) if r.reason == Reason::Default => {
                (WitnessKind::Home, self.kinematics.home(), Collision::Exact)
            }
            Some(r) => match (&r.witness, &r.certificate) {
                (Some(w), _) => (WitnessKind::ExactOverlap, w.q.clone(), Collision::Exact),
                (None, Some(c)) if c.status != Status::Collides => {
                    (WitnessKind::CertificateClosest, c.q.clone(), Collision::No)
                }
                _ => sampled(),
            },
            None => {
                let default = pair.entry.layer == Layer::Inferred
                    && pair.entry.reason == Reason::Default.id();
                if default && ev.home < 0.0 {
                    (
                        WitnessKind::Home,
                        self.kinematics.home(),
                        Collision::Measured(ev.home),
                    )
                } else if ev.closest.d_min >= 0.0
                    && let Some(s) = ev.searched
                {
                    (
                        WitnessKind::SearchCollision,
                        s.q.clone(),
                        Collision::Measured(s.d_min),
                    )
                } else {
                    sampled()
                }
            }
        }
    }

    fn link_index(&self, link: &str) -> Result<usize> {
        self.robot.link_index(link).ok_or_else(|| {
            Error::input(
                self.urdd.dir(),
                format!("link \"{link}\""),
                "in the sample output but not in the robot; rerun `scm sample`",
            )
        })
    }

    fn probe(&mut self) -> Result<&mut Probe> {
        let probe = match self.probe.take() {
            Some(p) => p,
            None => Probe::load(self.urdd)?,
        };
        Ok(self.probe.insert(probe))
    }
}

/// Measures two links' signed distance on the convex shapes of one type the URDD has.
struct Probe {
    checker: SelfChecker,
    scratch: Scratch,
    /// Per link name, its shapes' indices.
    pieces: HashMap<String, Vec<usize>>,
}

impl Probe {
    /// The decomposition's hulls when they were sampled (the closest convex stand-in for the mesh),
    /// else the link hulls.
    fn load(urdd: &Urdd) -> Result<Probe> {
        let t = if urdd.sampled_types()?.contains(&ShapeType::DecompHull) {
            ShapeType::DecompHull
        } else {
            ShapeType::Hull
        };
        let checker = SelfChecker::load(urdd, t, SkipMode::NoSkips)?;
        let mut pieces: HashMap<String, Vec<usize>> = HashMap::new();
        for (i, s) in checker.shapes().iter().enumerate() {
            pieces.entry(s.link.clone()).or_default().push(i);
        }
        Ok(Probe {
            scratch: checker.scratch(),
            checker,
            pieces,
        })
    }

    /// The smallest signed distance over the shape pairs between `a` and `b` at `q`; `None` when a
    /// link has no shape of this type.
    fn distance(&mut self, q: &[f64], a: &str, b: &str) -> Result<Option<WitnessDistance>> {
        let (Some(pa), Some(pb)) = (self.pieces.get(a), self.pieces.get(b)) else {
            return Ok(None);
        };
        let mut best = f64::INFINITY;
        for &i in pa {
            for &j in pb {
                let (d, _) = self.checker.pair_distance(q, i, j, &mut self.scratch)?;
                best = best.min(d);
            }
        }
        Ok(Some(WitnessDistance {
            distance: best,
            geometry: self.checker.shape_type().id().into(),
        }))
    }
}

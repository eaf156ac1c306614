//! `scm diff`: scm's verdicts against MoveIt's, link pair by link pair, with the evidence.

use crate::error::{Error, Result};
use crate::export::LinkLevel;
use crate::formats::srdf::parse_srdf;
use crate::matrix::{
    ImportedLayer, LinkPair, SkipMatrix, UserLayer, consumer_link_pairs, load_sample,
};
use crate::sample::{MeshFile, PairRecord, Status, load_mesh_file};
use crate::shapes::ShapeType;
use crate::urdd::Urdd;
use serde::Serialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// What to compare.
#[derive(Debug, Clone)]
pub struct CompareOptions {
    /// The URDD directory (sampled).
    pub urdd: PathBuf,
    /// The SRDF to compare with; default the URDD's imported layer.
    pub srdf: Option<PathBuf>,
    /// The geometry whose verdicts stand for scm: `mesh` (what the exported files carry) or a type.
    pub link_level: LinkLevel,
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
    /// Smallest signed distance scm saw between the two links (m).
    pub d_min: f64,
    /// Largest fraction of samples in collision over the links' shape pairs.
    pub collision_fraction: f64,
    /// The geometry scm's verdict was decided on (`mesh` or a shape type; `user` for a person's mark).
    pub geometry: String,
    /// For scm's `never` on the exact geometry: `certified` or `sampled`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub evidence: Option<String>,
    /// The certificate's proved lower bound on the hulls' distance (m), where one was searched.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lower_bound: Option<f64>,
    /// What `witness` is: `exact geometry overlaps` (the configuration that made scm check the pair),
    /// `closest found by the certificate`, or `closest sampled` (where `d_min` was reached).
    pub witness_kind: String,
    /// The configuration that decided scm's verdict, by joint name.
    pub witness: Vec<(String, f64)>,
}

/// The two lists of `scm diff`.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// What MoveIt's verdicts came from.
    pub moveit_source: String,
    /// The geometry standing for scm (`mesh` or a shape type).
    pub link_level: String,
    /// Link pairs compared.
    pub link_pairs: usize,
    /// Pairs MoveIt disables that scm keeps checking: evidence that MoveIt's skip was wrong.
    pub moveit_skips_scm_checks: Vec<Disagreement>,
    /// Pairs scm skips that MoveIt checks.
    pub scm_skips_moveit_checks: Vec<Disagreement>,
}

/// Compares scm's inferred (and user) verdicts with MoveIt's.
pub fn compare(opts: &CompareOptions) -> Result<Comparison> {
    let urdd = Urdd::open(&opts.urdd)?;
    let (moveit, source) = match &opts.srdf {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| Error::input(path, "file", format!("cannot read: {e}")))?;
            let srdf = parse_srdf(&text, path)?;
            let mut layer =
                ImportedLayer::new(path.display().to_string(), String::new(), srdf.robot);
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
            (layer, path.display().to_string())
        }
        None => {
            let layer = ImportedLayer::load(&urdd)?.ok_or_else(|| {
                Error::input(
                    &opts.urdd,
                    "layers/imported.json",
                    "no MoveIt SRDF imported; run `scm import-moveit ROBOT.srdf DIR` or pass --srdf",
                )
            })?;
            let source = layer.source.clone();
            (layer, source)
        }
    };
    let robot = urdd.robot()?;
    let dof_names: Vec<String> = robot.dofs.iter().map(|d| d.name.clone()).collect();
    // The statistics come from the link hull (or the chosen type); the verdicts from the level.
    let stats_type = match opts.link_level {
        LinkLevel::Type(t) => t,
        LinkLevel::Mesh => ShapeType::Hull,
    };
    let shapes = urdd.shapes(stats_type)?.shapes;
    let sample = load_sample(&urdd, stats_type)?;
    let scm = SkipMatrix::resolve(shapes, sample, None, &UserLayer::load(&urdd)?)?;
    let evidence = link_evidence(&scm);
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

    let mut out = Comparison {
        moveit_source: source,
        link_level: opts.link_level.id().into(),
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
        let d = disagreement(&pair, moveit_reason, &evidence, mesh.as_ref(), &dof_names);
        if moveit_skips {
            out.moveit_skips_scm_checks.push(d);
        } else {
            out.scm_skips_moveit_checks.push(d);
        }
    }
    Ok(out)
}

/// Per link pair (by link index), the shape pair with the smallest d_min and the largest collision
/// fraction.
fn link_evidence(m: &SkipMatrix) -> HashMap<(String, String), (&PairRecord, f64)> {
    let mut out: HashMap<(String, String), (&PairRecord, f64)> = HashMap::new();
    for p in &m.stats {
        let (a, b) = (&m.shapes[p.a].link, &m.shapes[p.b].link);
        if a == b {
            continue;
        }
        let e = out.entry((a.clone(), b.clone())).or_insert((p, 0.0));
        if p.d_min < e.0.d_min {
            e.0 = p;
        }
        e.1 = e.1.max(p.collision_fraction);
    }
    out
}

fn disagreement(
    pair: &LinkPair,
    moveit: String,
    evidence: &HashMap<(String, String), (&PairRecord, f64)>,
    mesh: Option<&MeshFile>,
    dof_names: &[String],
) -> Disagreement {
    let (record, fraction) = evidence[&(pair.link1.clone(), pair.link2.clone())];
    let exact = mesh.and_then(|m| m.pair(&pair.link1, &pair.link2));
    let certificate = exact.and_then(|r| r.certificate.as_ref());
    // The configuration behind scm's verdict: where the exact geometry overlaps, else the closest
    // approach the certificate found, else the sampled minimum.
    let (witness_kind, q) = match (exact.and_then(|r| r.witness.as_ref()), certificate) {
        (Some(w), _) => ("exact geometry overlaps", &w.q),
        (None, Some(c)) if c.status != Status::Collides => {
            ("closest found by the certificate", &c.q)
        }
        _ => ("closest sampled", &record.witness.q),
    };
    Disagreement {
        link1: pair.link1.clone(),
        link2: pair.link2.clone(),
        moveit,
        scm: pair.entry.reason.clone(),
        d_min: record.d_min,
        collision_fraction: fraction,
        geometry: pair.geometry.clone(),
        evidence: pair.evidence.map(|e| e.id().to_string()),
        lower_bound: certificate.map(|c| c.lower_bound),
        witness_kind: witness_kind.into(),
        witness: dof_names.iter().cloned().zip(q.iter().copied()).collect(),
    }
}

/// The human-readable report.
pub fn format_comparison(c: &Comparison, urdd: &Path) -> String {
    let mut s = format!(
        "{}: scm ({}) against MoveIt ({}): {} link pairs\n",
        urdd.display(),
        c.link_level,
        c.moveit_source,
        c.link_pairs
    );
    let section = |s: &mut String, title: &str, list: &[Disagreement]| {
        s.push_str(&format!("{title}: {}\n", list.len()));
        for d in list {
            let q: Vec<String> = d
                .witness
                .iter()
                .map(|(n, v)| format!("{n}={v:.4}"))
                .collect();
            let evidence = match (&d.evidence, d.lower_bound) {
                (Some(e), Some(lb)) => format!(" {e}, proved >= {lb:.4} m;"),
                (Some(e), None) => format!(" {e};"),
                _ => String::new(),
            };
            s.push_str(&format!(
                "  {} - {}: MoveIt {}, scm {} (on {});{evidence} hull d_min {:.4} m, in collision {:.2}% of samples; {}: {}\n",
                d.link1,
                d.link2,
                d.moveit,
                d.scm,
                d.geometry,
                d.d_min,
                100.0 * d.collision_fraction,
                d.witness_kind,
                q.join(" ")
            ));
        }
    };
    section(
        &mut s,
        "MoveIt skips, scm checks",
        &c.moveit_skips_scm_checks,
    );
    section(
        &mut s,
        "scm skips, MoveIt checks",
        &c.scm_skips_moveit_checks,
    );
    s
}

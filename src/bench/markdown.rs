//! The bench report as markdown: the file `bench.md` and the table `scm bench` prints.

use super::{BenchReport, Timing, TypeBench};
use std::fmt::Write;

/// Renders the three tables with a header saying what was measured.
pub fn render(r: &BenchReport) -> String {
    let o = &r.options;
    let mut s = String::new();
    // Writing into a String cannot fail.
    let _ = writeln!(s, "# scm bench: {}\n", r.robot);
    let _ = writeln!(
        s,
        "Fresh configurations uniform within the joint limits (seed {}, a stream sampling never \
         uses); scm {}; {:.0} s in all.\n",
        o.seed,
        crate::VERSION,
        r.seconds
    );
    let _ = writeln!(
        s,
        "## Query time with skips / without skips (tables 1 and 2)\n\n{} configurations, {} \
         repeats, one thread; ratio = mean +- std over the repeats; time per query in microseconds \
         (with skips / without), forward kinematics included. *all pairs*: every colliding pair is \
         reported; *first hit*: stops at the first collision; *proximity*: minimum distance over \
         the checked pairs, with its pair and witness points.\n",
        o.configs, o.repeats
    );
    s.push_str(
        "| type | shapes | pairs checked | in collision | all pairs: ratio | us | first hit: ratio | us | proximity: ratio | us |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for t in &r.types {
        let _ = writeln!(
            s,
            "| {} | {} | {} / {} | {:.1}% | {} | {} | {} |",
            t.shape_type,
            t.shapes,
            t.checked,
            t.pairs,
            100.0 * t.collision_fraction,
            timing_cells(&t.collisions),
            timing_cells(&t.first_hit),
            timing_cells(&t.proximity),
        );
    }
    let configs = r
        .types
        .first()
        .map_or(o.truth_configs, |t| t.accuracy.configs);
    let mesh = r.types.first().map_or(0, |t| t.accuracy.mesh_collisions);
    let _ = writeln!(
        s,
        "\n## Verdict with skips against the exact meshes (table 3)\n\n{configs} configurations; \
         ground truth: the original link meshes of {} link pairs (not adjacent, not in contact at \
         home{}), checked exactly (surface intersection or containment), collide in {} of them \
         ({}). Per type, the share \
         of configurations where: the meshes collide but the type reports nothing (*false neg.*); \
         a pair skipped for a reason hides a real collision (*hidden by*); the type's shapes miss \
         a mesh collision even with no skips (*missed*); the type reports a collision the meshes do \
         not have (*false pos.*, and *spurious pair*: some reported link pair is not in collision).\n",
        r.truth_pairs,
        if r.truth_at_home.is_empty() {
            String::new()
        } else {
            let pairs: Vec<String> = r
                .truth_at_home
                .iter()
                .map(|[a, b]| format!("{a}/{b}"))
                .collect();
            format!(": {} pairs left out, {}", pairs.len(), pairs.join(", "))
        },
        mesh,
        pct(mesh, configs)
    );
    let _ = write!(s, "| type | reports collision | false neg. |");
    for reason in &r.reasons {
        let _ = write!(s, " hidden by {reason} |");
    }
    s.push_str(" missed | false pos. | spurious pair |\n|---|---:|---:|");
    s.push_str(&"---:|".repeat(r.reasons.len() + 3));
    s.push('\n');
    for t in &r.types {
        s.push_str(&accuracy_row(t, &r.reasons));
    }
    s
}

fn timing_cells(t: &Timing) -> String {
    format!(
        "{:.3} +- {:.3} | {} / {}",
        t.ratio_mean,
        t.ratio_std,
        micros(t.skips_us),
        micros(t.no_skips_us)
    )
}

fn micros(us: f64) -> String {
    if us < 10.0 {
        format!("{us:.2}")
    } else if us < 100.0 {
        format!("{us:.1}")
    } else {
        format!("{us:.0}")
    }
}

fn pct(n: usize, of: usize) -> String {
    format!("{:.1}%", 100.0 * n as f64 / of.max(1) as f64)
}

fn accuracy_row(t: &TypeBench, reasons: &[String]) -> String {
    let a = &t.accuracy;
    let mut row = format!(
        "| {} | {} | {} |",
        t.shape_type,
        pct(a.reported, a.configs),
        pct(a.false_negatives, a.configs)
    );
    for reason in reasons {
        let n = a.hidden.get(reason).copied().unwrap_or(0);
        row.push_str(&format!(" {} |", pct(n, a.configs)));
    }
    row.push_str(&format!(
        " {} | {} | {} |\n",
        pct(a.missed_by_shapes, a.configs),
        pct(a.false_positives, a.configs),
        pct(a.spurious_pairs, a.configs)
    ));
    row
}

//! `scm inspect`: the configurations asked for, the loaded geometry placed at them, its listing.

use super::args::{Cli, InspectArgs};
use super::common::{bad_flag, print_json};
use super::output::out;
use scm::error::Result;
use scm::inspect::{Configurations, InspectReport, inspect};
use scm::robot::GeometryOrigin;

/// `scm inspect`: each link's loaded geometry and its world boxes at the configurations asked for.
pub fn run_inspect(cli: &Cli, args: &InspectArgs) -> Result<()> {
    let report = inspect(&args.urdd, &configurations(args)?)?;
    if cli.json {
        print_json(&report)
    } else {
        out!("{}", render(&report));
        Ok(())
    }
}

/// Lowers `--random` / `--config` into the configurations to place the links at (home by default).
fn configurations(args: &InspectArgs) -> Result<Configurations> {
    if let Some(count) = args.random {
        return Ok(Configurations::Random {
            count: count as usize,
            seed: args.seed,
        });
    }
    if args.config.is_empty() {
        return Ok(Configurations::Home);
    }
    let parse = |text: &String| -> Result<Vec<f64>> {
        text.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .map(|s| {
                s.parse::<f64>().map_err(|_| {
                    bad_flag("--config", format!("`{s}` is not a number (in \"{text}\")"))
                })
            })
            .collect()
    };
    Ok(Configurations::Given(
        args.config.iter().map(parse).collect::<Result<_>>()?,
    ))
}

/// The text listing: per configuration, each link's source, elements and world box.
fn render(report: &InspectReport) -> String {
    let mut out = String::new();
    for (i, placed) in report.configurations.iter().enumerate() {
        let q: Vec<String> = placed.q.iter().map(|v| format!("{v:.4}")).collect();
        out += &format!("configuration {i}: [{}]\n", q.join(" "));
        for link in &report.links {
            let counts: Vec<String> = link
                .elements
                .iter()
                .map(|e| match &e.uri {
                    Some(uri) => format!("{uri} ({} vertices)", e.vertices),
                    None => e.kind.to_string(),
                })
                .collect();
            let bounds = placed
                .links
                .iter()
                .find(|p| p.link == link.link)
                .map_or_else(
                    || "no collision geometry".to_string(),
                    |p| {
                        let f = |v: [f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
                        format!("box {} .. {}", f(p.bounds.min), f(p.bounds.max))
                    },
                );
            out += &format!(
                "  {}: {}, {} element(s){}{}; {bounds}\n",
                link.link,
                origin_name(link.source),
                link.elements.len(),
                if counts.is_empty() { "" } else { ": " },
                counts.join(", ")
            );
        }
    }
    out
}

/// The name of a link's geometry source, as `--json` spells it.
fn origin_name(origin: GeometryOrigin) -> &'static str {
    match origin {
        GeometryOrigin::Collision => "collision",
        GeometryOrigin::Visual => "visual",
        GeometryOrigin::None => "none",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The text names each source as the JSON report does.
    #[test]
    fn origin_names_match_json() {
        for origin in [
            GeometryOrigin::Collision,
            GeometryOrigin::Visual,
            GeometryOrigin::None,
        ] {
            let json = serde_json::to_value(origin).expect("a unit variant serialises");
            assert_eq!(json.as_str(), Some(origin_name(origin)));
        }
    }
}

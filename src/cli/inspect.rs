//! `scm inspect`: the configurations asked for, the loaded geometry placed at them, its listing.

use super::args::{Cli, InspectArgs};
use super::common::{bad_flag, print_json};
use super::output::out;
use scm::error::Result;
use scm::inspect::{Configurations, InspectReport, inspect};

/// `scm inspect`: each link's loaded geometry and its world boxes at the configurations asked for.
pub fn run_inspect(cli: &Cli, args: &InspectArgs) -> Result<()> {
    let report = inspect(&args.urdd, &configurations(args)?)?;
    if cli.json {
        print_json(&report);
    } else {
        out!("{}", render(&report));
    }
    Ok(())
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
                serde_json::to_value(link.source)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_default(),
                link.elements.len(),
                if counts.is_empty() { "" } else { ": " },
                counts.join(", ")
            );
        }
    }
    out
}

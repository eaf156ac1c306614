//! Where the checker learns which pairs to skip: the sample stage's inferred reasons, one entry per
//! shape pair in row-major order. (One function, so the effective skip matrix with its imported and
//! user layers can take its place without touching the checker.)

use crate::error::{Error, Result};
use crate::sample::{SAMPLE, SampleFile, sample_file_name};
use crate::shapes::ShapeType;
use crate::urdd::Urdd;

/// Per shape pair `a < b` in row-major order: the id of the reason it is skipped, or `None` when it
/// must be checked. `shapes` is the number of shapes of the type; a sample file of another size (stale,
/// or from different shapes) is bad input.
pub fn skip_reasons(urdd: &Urdd, t: ShapeType, shapes: usize) -> Result<Vec<Option<String>>> {
    let folder = &urdd.stage(SAMPLE)?.folder;
    let path = urdd.dir().join(folder).join(sample_file_name(t));
    if !path.is_file() {
        return Err(Error::input(
            &path,
            format!("shape type {t}"),
            format!(
                "not sampled; run `scm sample {} --types {t}` first",
                urdd.dir().display()
            ),
        ));
    }
    let file: SampleFile = urdd.read_json(SAMPLE, &sample_file_name(t))?;
    let expected = shapes * shapes.saturating_sub(1) / 2;
    let in_order = file
        .pairs
        .iter()
        .zip((0..shapes).flat_map(|a| (a + 1..shapes).map(move |b| (a, b))))
        .all(|(p, (a, b))| p.a == a && p.b == b);
    if file.pairs.len() != expected || !in_order {
        return Err(Error::input(
            &path,
            "pairs",
            format!(
                "{} pair records do not match the {shapes} {t} shapes of the preprocess stage; \
                 rerun `scm sample {}`",
                file.pairs.len(),
                urdd.dir().display()
            ),
        ));
    }
    Ok(file
        .pairs
        .iter()
        .map(|p| p.reason.skips().then(|| p.reason.id().to_string()))
        .collect())
}

//! Where the checker learns which pairs to skip: the effective skip matrix of the type (sampling's
//! inferred verdicts with the imported and user layers applied, [`crate::matrix::SkipMatrix`]).

use crate::error::Result;
use crate::matrix::{Layer, SkipMatrix};
use crate::shapes::ShapeType;
use crate::urdd::Urdd;

/// Per shape pair `a < b` in row-major order: a label of the reason it is skipped, or `None` when it
/// must be checked. Labels are scm's reason ids for inferred verdicts (`never`, `adjacent`, ...),
/// `imported:<MoveIt reason>` for the imported layer and `user` for the user layer. `shapes` is the
/// number of shapes of the type; a sample stage that is missing, stale or lacks the type is bad input.
pub fn skip_reasons(urdd: &Urdd, t: ShapeType, shapes: usize) -> Result<Vec<Option<String>>> {
    let matrix = SkipMatrix::load(urdd, t)?;
    if matrix.len() != shapes {
        return Err(crate::error::Error::Failed {
            context: format!("{t} skip matrix"),
            message: format!(
                "{} shapes in the matrix, {shapes} in the shape list; rerun `scm sample`",
                matrix.len()
            ),
        });
    }
    Ok(matrix
        .entries
        .iter()
        .map(|e| {
            e.skip.then(|| match e.layer {
                Layer::Inferred | Layer::User => e.reason.clone(),
                Layer::Imported => format!("imported:{}", e.reason),
            })
        })
        .collect())
}

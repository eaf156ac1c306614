//! The loaded URDD as the viewer needs it: the robot's kinematics and, per sampled shape type, the
//! shapes, the sample statistics, a checker for current distances and the effective skip matrix.

use scm::error::{Error, Result};
use scm::math::Vec3;
use scm::matrix::{ImportedLayer, SkipMatrix, UserLayer, load_sample};
use scm::query::{Scratch, SelfChecker, SkipMode};
use scm::robot::{Dof, Kinematics, Robot};
use scm::sample::{MeshFile, SampleFile, load_mesh_file};
use scm::shapes::ShapeType;
use scm::urdd::Urdd;
use std::path::Path;

/// One sampled shape type: its samples, effective matrix and distance checker (everything the pair
/// list, the matrix view and the highlight need).
#[derive(Debug)]
pub struct SampledType {
    /// The shape type.
    pub shape_type: ShapeType,
    /// The sample output (statistics, inferred reasons, witnesses).
    pub sample: SampleFile,
    /// The effective matrix with the current user layer applied.
    pub matrix: SkipMatrix,
    /// Per pair, its link pair's verdict on the exact geometry with a `never`'s evidence
    /// ([`crate::pairs::list::exact_text`]); empty for same-link pairs or without `sample/mesh.json`.
    pub exact: Vec<String>,
    /// A checker over all pairs (no skips), for current distances and closest points.
    checker: SelfChecker,
}

impl SampledType {
    /// Number of pairs `a < b`.
    pub fn pair_count(&self) -> usize {
        self.matrix.entries.len()
    }

    /// The shapes `(a, b)` of pair `p` (row-major index).
    pub fn pair(&self, p: usize) -> (usize, usize) {
        let s = &self.matrix.stats[p];
        (s.a, s.b)
    }

    /// The signed distance of every pair at `q`, row-major.
    pub fn distances(&self, q: &[f64], scratch: &mut Scratch) -> Result<Vec<f64>> {
        self.checker.all_distances(q, scratch)
    }

    /// The signed distance of pair `p` at `q` and its witness points (root frame).
    pub fn closest_points(
        &self,
        q: &[f64],
        p: usize,
        scratch: &mut Scratch,
    ) -> Result<(f64, [Vec3; 2])> {
        let (a, b) = self.pair(p);
        self.checker.pair_distance(q, a, b, scratch)
    }

    /// Re-resolves the effective matrix with `user` (after an edit).
    pub fn resolve(&mut self, imported: Option<&ImportedLayer>, user: &UserLayer) -> Result<()> {
        self.matrix = SkipMatrix::resolve(
            self.matrix.shapes.clone(),
            self.sample.clone(),
            imported,
            user,
        )?;
        Ok(())
    }

    /// Pairs skipped by the effective matrix.
    pub fn skipped(&self) -> usize {
        self.matrix.entries.iter().filter(|e| e.skip).count()
    }
}

/// The whole URDD as loaded by the viewer.
#[derive(Debug)]
pub struct Model {
    /// The URDD.
    pub urdd: Urdd,
    /// The robot model (links, geometry sources).
    pub robot: Robot,
    /// Forward kinematics.
    pub kinematics: Kinematics,
    /// The imported layer, if any.
    pub imported: Option<ImportedLayer>,
    /// The user layer as loaded (edits live in [`crate::edit::editor::Editor`]).
    pub user: UserLayer,
    /// The sampled types, in [`ShapeType::ALL`] order.
    pub types: Vec<SampledType>,
    /// The link-level verdicts on the exact geometry (what the exported files carry), with each
    /// `never`'s evidence; `None` for a URDD sampled without them.
    pub mesh: Option<MeshFile>,
}

impl Model {
    /// Loads `dir`: it must be preprocessed and sampled (for at least one type), or it is bad input.
    pub fn load(dir: &Path) -> Result<Model> {
        let urdd = Urdd::open(dir)?;
        let robot = urdd.robot()?.robot;
        let kinematics = Kinematics::new(&robot);
        let imported = ImportedLayer::load(&urdd)?;
        let user = UserLayer::load(&urdd)?;
        let mesh = load_mesh_file(&urdd)?;
        let mut types = Vec::new();
        let mut first_error = None;
        for t in ShapeType::ALL {
            let sample = match load_sample(&urdd, t) {
                Ok(s) => s,
                Err(e) => {
                    first_error.get_or_insert(e);
                    continue;
                }
            };
            let shapes = urdd.shapes(t)?.shapes;
            let matrix = SkipMatrix::resolve(shapes, sample.clone(), imported.as_ref(), &user)?;
            let checker = SelfChecker::load(&urdd, t, SkipMode::NoSkips)?;
            let exact = matrix
                .stats
                .iter()
                .map(|s| {
                    let (a, b) = (&matrix.shapes[s.a].link, &matrix.shapes[s.b].link);
                    mesh.as_ref()
                        .and_then(|f| f.pair(a, b))
                        .map_or(String::new(), crate::pairs::list::exact_text)
                })
                .collect();
            types.push(SampledType {
                shape_type: t,
                sample,
                matrix,
                exact,
                checker,
            });
        }
        if types.is_empty() {
            return Err(first_error.unwrap_or_else(|| {
                Error::input(dir, "sample", "no shape type was sampled; run `scm sample`")
            }));
        }
        Ok(Model {
            urdd,
            robot,
            kinematics,
            imported,
            user,
            types,
            mesh,
        })
    }

    /// The degrees of freedom, in configuration order.
    pub fn dofs(&self) -> &[Dof] {
        self.kinematics.dofs()
    }

    /// Type `t` as sampled, if it was.
    pub fn sampled(&self, t: ShapeType) -> Option<&SampledType> {
        self.types.iter().find(|d| d.shape_type == t)
    }

    /// Re-resolves every type's matrix with `user`.
    pub fn resolve_all(&mut self, user: &UserLayer) -> Result<()> {
        for d in &mut self.types {
            d.resolve(self.imported.as_ref(), user)?;
        }
        Ok(())
    }

    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.robot.name
    }
}

/// Clamps a configuration into the DOF limits.
pub fn clamp(dofs: &[Dof], q: &mut [f64]) {
    for (v, d) in q.iter_mut().zip(dofs) {
        *v = v.clamp(d.lower, d.upper);
    }
}

//! Test fixtures: small skip matrices built in memory, so the state logic is tested without a URDD.

use scm::math::Vec3;
use scm::matrix::{SkipMatrix, UserLayer};
use scm::sample::{PairRecord, Reason, SampleFile, TypeSummary, Witness};
use scm::shapes::ShapeType;
use scm::urdd::{GeometryRecord, ShapeRecord};

/// The sample output for `n` spheres on links `l0..`: pair 0 is `adjacent`, the others `checked`;
/// pair `p` has `d_mean` 0.1 and `d_min` `0.05 - 0.01 p`.
pub fn sample(n: usize) -> (Vec<ShapeRecord>, SampleFile) {
    let shapes = (0..n)
        .map(|i| ShapeRecord {
            index: i,
            link: format!("l{i}"),
            link_index: i,
            piece: 0,
            geometry: GeometryRecord::Sphere {
                center: Vec3::ZERO,
                radius: 0.1,
            },
        })
        .collect();
    let pairs = (0..n)
        .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
        .enumerate()
        .map(|(p, (a, b))| PairRecord {
            a,
            b,
            reason: if p == 0 {
                Reason::Adjacent
            } else {
                Reason::Checked
            },
            d_min: 0.05 - 0.01 * p as f64,
            d_mean: 0.1,
            mean_samples: 10,
            d_max: 0.3,
            collisions: 0,
            collision_fraction: 0.0,
            home_distance: 0.1,
            witness: Witness {
                sample: Some(p as u64),
                q: vec![p as f64],
            },
            search: None,
        })
        .collect();
    let file = SampleFile {
        format_version: 1,
        shape_type: ShapeType::Sphere,
        samples: 10,
        seed: 0,
        mean_samples: 10,
        always_fraction: 0.95,
        never_upper_bound: 0.0,
        summary: TypeSummary::default(),
        pairs,
    };
    (shapes, file)
}

/// The matrix of [`sample`] without any user mark.
pub fn matrix(n: usize) -> SkipMatrix {
    let (shapes, file) = sample(n);
    SkipMatrix::resolve(shapes, file, None, &UserLayer::default()).expect("sizes agree")
}

/// `m` re-resolved with `user`.
pub fn resolve(m: &SkipMatrix, user: &UserLayer) -> SkipMatrix {
    let (shapes, file) = sample(m.len());
    SkipMatrix::resolve(shapes, file, None, user).expect("sizes agree")
}

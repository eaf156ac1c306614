//! The state several plugins share, as explicit resources. Each is inserted by exactly one plugin (its
//! owner, named on the type), built from the [`Viewer`] model where it depends on the robot; UI systems
//! write them, scene systems react to their changes.

use crate::model::Model;
use bevy::prelude::*;
use scm::shapes::ShapeType;

/// The loaded URDD (its matrices are re-resolved after every edit). Inserted by [`crate::run`] before
/// the plugins, which build their own resources from it.
#[derive(Resource)]
pub struct Viewer(pub Model);

/// The current joint configuration, one value per DOF. Owned by
/// [`JointPanelPlugin`](crate::joint_panel::JointPanelPlugin); starts at home.
#[derive(Resource, Debug, Clone)]
pub struct Joints {
    /// Joint values.
    pub q: Vec<f64>,
    /// Seed of the next random configuration.
    pub next_seed: u64,
}

impl FromWorld for Joints {
    /// The robot's home configuration.
    fn from_world(world: &mut World) -> Self {
        Joints {
            q: world.resource::<Viewer>().0.kinematics.home(),
            next_seed: 1,
        }
    }
}

/// What is drawn: the selected shape type and whether the original meshes show. Owned by
/// [`JointPanelPlugin`](crate::joint_panel::JointPanelPlugin), whose panel sets them.
#[derive(Resource, Debug, Clone, Copy)]
pub struct Settings {
    /// The selected type; the pair list and the highlight apply to it.
    pub shape_type: ShapeType,
    /// Draw the original link meshes too.
    pub originals: bool,
}

impl FromWorld for Settings {
    /// The link hulls if they were sampled, else the first sampled type; no original meshes.
    fn from_world(world: &mut World) -> Self {
        let model = &world.resource::<Viewer>().0;
        let shape_type = model
            .sampled(ShapeType::Hull)
            .unwrap_or(&model.types[0])
            .shape_type;
        Settings {
            shape_type,
            originals: false,
        }
    }
}

/// The selected pair (row-major index into the selected type's pairs). Owned by
/// [`SelectionPlugin`](crate::selection::SelectionPlugin); the pair list, the matrix view and the
/// script select.
#[derive(Resource, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Selection(pub Option<usize>);

impl Selection {
    /// The selected pair if it is one of `pairs` pairs (a selection never outlives its type).
    pub fn within(&self, pairs: usize) -> Option<usize> {
        self.0.filter(|&p| p < pairs)
    }
}

/// Signed distances of every pair of the selected type in the current configuration (row-major).
/// Owned and kept current by [`SelectionPlugin`](crate::selection::SelectionPlugin).
#[derive(Resource, Debug, Clone, Default)]
pub struct Distances(pub Vec<f64>);

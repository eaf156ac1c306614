//! Scene plugin: the robot's shapes of every sampled type and its original meshes as entities under
//! one frame per link, posed by forward kinematics; lights and the floor grid. What it draws is
//! prepared before the window opens by [`geometry`].

pub mod geometry;

use crate::state::{Joints, Settings, Viewer};
use bevy::asset::RenderAssetUsages;
use bevy::mesh::PrimitiveTopology;
use bevy::prelude::*;
use geometry::{SceneGeometry, Triangles, hull_triangles};
use scm::shapes::{Geometry, ShapeType};

/// Draws the robot in the current configuration with the selected type's shapes. Reads the
/// [`SceneGeometryRes`] inserted with the model; sets the clear colour and ambient light, and inserts
/// [`SceneBounds`] once the robot is spawned.
pub struct ScenePlugin;

impl Plugin for ScenePlugin {
    fn build(&self, app: &mut App) {
        app.insert_resource(ClearColor(Color::srgb(0.16, 0.17, 0.19)))
            .insert_resource(GlobalAmbientLight {
                color: Color::WHITE,
                brightness: 250.0,
                ..default()
            })
            .add_systems(Startup, spawn_robot)
            .add_systems(
                Update,
                (
                    pose_links.run_if(resource_changed::<Joints>),
                    show_selected_type.run_if(resource_changed::<Settings>),
                    draw_floor_grid,
                ),
            );
    }
}

/// The root of the robot: turns the robot's z-up frame into Bevy's y-up world.
#[derive(Component)]
pub struct RobotRoot;

/// A link's frame (index into the robot's links).
#[derive(Component)]
pub struct LinkFrame(pub usize);

/// One shape of one type, with its resting colour and outline (segments in the entity's frame).
#[derive(Component)]
pub struct ShapeEntity {
    /// The shape's type.
    pub shape_type: ShapeType,
    /// Matrix index.
    pub index: usize,
    /// Resting colour (sRGB).
    pub color: [f32; 3],
    /// Outline segments in the entity's frame.
    pub outline: Vec<[Vec3; 2]>,
}

/// A link's original mesh.
#[derive(Component)]
pub struct OriginalMesh;

/// The robot at home: centre (world frame) and radius, for framing the camera.
#[derive(Resource, Debug, Clone, Copy)]
pub struct SceneBounds {
    /// Centre in the world frame.
    pub center: Vec3,
    /// Radius.
    pub radius: f32,
}

/// The rotation from the robot's z-up root frame into Bevy's y-up world.
pub fn root_rotation() -> Quat {
    Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)
}

/// A point of the robot's root frame in the world.
pub fn to_world(p: scm::math::Vec3) -> Vec3 {
    root_rotation() * vec3(p)
}

/// A library (f64) vector as a Bevy vector (the two use different glam versions).
pub fn vec3(p: scm::math::Vec3) -> Vec3 {
    Vec3::new(p.x as f32, p.y as f32, p.z as f32)
}

/// A library (f64) rotation as a Bevy quaternion.
fn quat(r: scm::math::Rotation) -> Quat {
    Quat::from_xyzw(r.x as f32, r.y as f32, r.z as f32, r.w as f32).normalize()
}

/// Two alternating resting colours, so neighbouring links stay apart (neither blue nor yellow).
const LINK_COLORS: [[f32; 3]; 2] = [[0.72, 0.72, 0.70], [0.55, 0.56, 0.58]];

fn spawn_robot(
    mut commands: Commands,
    viewer: Res<Viewer>,
    geometry: Res<SceneGeometryRes>,
    settings: Res<Settings>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let model = &viewer.0;
    let geo = &geometry.0;
    commands.spawn((
        DirectionalLight {
            illuminance: 9000.0,
            shadow_maps_enabled: false,
            ..default()
        },
        Transform::from_xyz(3.0, 6.0, 4.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 2500.0,
            shadow_maps_enabled: false,
            ..default()
        },
        Transform::from_xyz(-4.0, 2.0, -3.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    let (center, radius) = geo.bounds;
    commands.insert_resource(SceneBounds {
        center: to_world(center),
        radius: radius as f32,
    });
    let root = commands
        .spawn((
            RobotRoot,
            Transform::from_rotation(root_rotation()),
            Visibility::Visible,
        ))
        .id();
    let home = model.kinematics.link_poses(&model.kinematics.home());
    let links: Vec<Entity> = home
        .iter()
        .enumerate()
        .map(|(i, pose)| {
            commands
                .spawn((
                    LinkFrame(i),
                    pose_transform(pose),
                    Visibility::Inherited,
                    ChildOf(root),
                ))
                .id()
        })
        .collect();
    for (t, shapes) in &geo.shapes {
        let visible = *t == settings.shape_type;
        for s in shapes {
            let color = LINK_COLORS[s.link % 2];
            let (mesh, local) = shape_mesh(&s.geometry);
            let inverse = local.to_matrix().inverse();
            let outline = s
                .outline
                .iter()
                .map(|[a, b]| {
                    [
                        inverse.transform_point3(vec3(*a)),
                        inverse.transform_point3(vec3(*b)),
                    ]
                })
                .collect();
            commands.spawn((
                ShapeEntity {
                    shape_type: *t,
                    index: s.index,
                    color,
                    outline,
                },
                Mesh3d(meshes.add(mesh)),
                MeshMaterial3d(materials.add(StandardMaterial {
                    base_color: Color::srgb(color[0], color[1], color[2]),
                    perceptual_roughness: 0.7,
                    ..default()
                })),
                local,
                if visible {
                    Visibility::Inherited
                } else {
                    Visibility::Hidden
                },
                ChildOf(links[s.link]),
            ));
        }
    }
    let original = materials.add(StandardMaterial {
        base_color: Color::srgb(0.85, 0.80, 0.72),
        perceptual_roughness: 0.6,
        ..default()
    });
    for (link, tris) in geo.originals.iter().enumerate() {
        if tris.positions.is_empty() {
            continue;
        }
        commands.spawn((
            OriginalMesh,
            Mesh3d(meshes.add(render_mesh(tris))),
            MeshMaterial3d(original.clone()),
            Transform::IDENTITY,
            if settings.originals {
                Visibility::Inherited
            } else {
                Visibility::Hidden
            },
            ChildOf(links[link]),
        ));
    }
}

/// The loaded scene geometry (inserted by [`crate::run`] with the model, before startup).
#[derive(Resource)]
pub struct SceneGeometryRes(pub SceneGeometry);

/// A render mesh and its transform in the link frame for one shape.
fn shape_mesh(geometry: &Geometry) -> (Mesh, Transform) {
    match geometry {
        Geometry::Sphere(s) => (
            Sphere::new(s.radius as f32).mesh().uv(48, 24),
            Transform::from_translation(vec3(s.center)),
        ),
        Geometry::Obb(b) => {
            let h = vec3(b.half_extents) * 2.0;
            (
                Cuboid::new(h.x, h.y, h.z).mesh().build(),
                Transform::from_translation(vec3(b.center)).with_rotation(quat(b.rotation)),
            )
        }
        Geometry::Hull(h) => (
            render_mesh(&hull_triangles(&h.vertices, &h.faces)),
            Transform::IDENTITY,
        ),
    }
}

/// A render mesh of flat-shaded triangles.
fn render_mesh(t: &Triangles) -> Mesh {
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, t.positions.clone())
    .with_inserted_attribute(Mesh::ATTRIBUTE_NORMAL, t.normals.clone())
}

/// A link pose of the root frame as a Bevy transform (relative to [`RobotRoot`]).
fn pose_transform(pose: &scm::math::Pose) -> Transform {
    Transform::from_translation(vec3(pose.translation)).with_rotation(quat(pose.rotation))
}

/// Poses every link frame for the current configuration.
fn pose_links(
    viewer: Res<Viewer>,
    joints: Res<Joints>,
    mut links: Query<(&LinkFrame, &mut Transform)>,
) {
    let poses = viewer.0.kinematics.link_poses(&joints.q);
    for (link, mut transform) in &mut links {
        if let Some(p) = poses.get(link.0) {
            *transform = pose_transform(p);
        }
    }
}

/// Shows the selected type's shapes and, if asked, the original meshes.
fn show_selected_type(
    settings: Res<Settings>,
    mut shapes: Query<(&ShapeEntity, &mut Visibility), Without<OriginalMesh>>,
    mut originals: Query<&mut Visibility, With<OriginalMesh>>,
) {
    for (shape, mut v) in &mut shapes {
        v.set_if_neq(if shape.shape_type == settings.shape_type {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        });
    }
    for mut v in &mut originals {
        v.set_if_neq(if settings.originals {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        });
    }
}

/// The floor: a grid of 10 cm cells on the ground plane, sized to the robot.
fn draw_floor_grid(mut gizmos: Gizmos, bounds: Option<Res<SceneBounds>>) {
    let radius = bounds.map_or(1.0, |b| b.radius);
    let cells = ((radius * 3.0 / 0.1).ceil() as u32).clamp(10, 400);
    gizmos.grid(
        Isometry3d::from_rotation(Quat::from_rotation_x(std::f32::consts::FRAC_PI_2)),
        UVec2::splat(cells),
        Vec2::splat(0.1),
        Color::srgba(0.5, 0.5, 0.5, 0.35),
    );
}

//! Camera plugin: an orbit camera around the robot (left drag orbits, right or middle drag pans, the
//! wheel zooms) whose viewport is the part of the window the panels leave free. F (or a jump to a
//! witness) frames the selected pair: the orbit turns to look at its two shapes from where it is.

use crate::layout::UiLayout;
use crate::scene::{SceneBounds, ShapeEntity};
use crate::state::{Selection, Settings, Viewer};
use bevy::camera::primitives::Aabb;
use bevy::camera::visibility::RenderLayers;
use bevy::camera::{CameraOutputMode, Viewport};
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll, MouseScrollUnit};
use bevy::prelude::*;
use bevy::render::render_resource::BlendState;
use bevy::window::PrimaryWindow;
use bevy_egui::{EguiGlobalSettings, PrimaryEguiContext};

/// Orbit, pan and zoom around the robot. Owns [`FrameRequest`].
pub struct CameraPlugin;

impl Plugin for CameraPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<FrameRequest>()
            .add_systems(Startup, spawn_camera)
            .add_systems(
                Update,
                (
                    frame_robot.run_if(resource_added::<SceneBounds>),
                    frame_key,
                    orbit_from_mouse,
                    place_camera,
                    fit_viewport,
                )
                    .chain(),
            )
            // After transform propagation, so a witness jump in this frame is framed where it puts
            // the shapes.
            .add_systems(
                PostUpdate,
                frame_selected_pair
                    .after(bevy::transform::TransformSystems::Propagate)
                    .run_if(|r: Res<FrameRequest>| r.0),
            );
    }
}

/// A request to frame the selected pair (the F key, the witness buttons, the script's `frame` and
/// `witness`), served after the shapes are posed.
#[derive(Resource, Debug, Default)]
pub struct FrameRequest(pub bool);

/// How far from the focus the camera stands, in radii of what it frames.
const FRAME_DISTANCE: f32 = 2.8;

/// The orbit: a focus point, two angles and a distance.
#[derive(Component, Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The point looked at (world frame).
    pub focus: Vec3,
    /// Angle around the vertical axis (radians).
    pub yaw: f32,
    /// Angle above the floor (radians).
    pub pitch: f32,
    /// Distance from the focus (m).
    pub distance: f32,
}

impl Orbit {
    /// The camera transform of this orbit.
    pub fn transform(&self) -> Transform {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        Transform::from_translation(self.focus + dir * self.distance)
            .looking_at(self.focus, Vec3::Y)
    }
}

/// Spawns the 3D camera and, above it, the camera egui draws the panels with (it renders nothing else).
fn spawn_camera(mut commands: Commands, mut egui: ResMut<EguiGlobalSettings>) {
    egui.auto_create_primary_context = false;
    let orbit = Orbit {
        focus: Vec3::new(0.0, 0.4, 0.0),
        yaw: 0.7,
        pitch: 0.35,
        distance: 2.5,
    };
    commands.spawn((Camera3d::default(), orbit.transform(), orbit));
    commands.spawn((
        PrimaryEguiContext,
        Camera2d,
        RenderLayers::none(),
        Camera {
            order: 1,
            output_mode: CameraOutputMode::Write {
                blend_state: Some(BlendState::ALPHA_BLENDING),
                clear_color: ClearColorConfig::None,
            },
            clear_color: ClearColorConfig::Custom(Color::NONE),
            ..default()
        },
    ));
}

/// Frames the robot once its bounds are known.
fn frame_robot(bounds: Res<SceneBounds>, mut orbits: Query<&mut Orbit>) {
    for mut orbit in &mut orbits {
        orbit.focus = bounds.center;
        orbit.distance = bounds.radius * FRAME_DISTANCE;
    }
}

/// F over the 3D view (not while typing in a panel) asks to frame the selected pair.
fn frame_key(
    keys: Res<ButtonInput<KeyCode>>,
    egui: Res<bevy_egui::input::EguiWantsInput>,
    mut frame: ResMut<FrameRequest>,
) {
    if keys.just_pressed(KeyCode::KeyF) && !egui.wants_any_keyboard_input() {
        frame.0 = true;
    }
}

/// The world-space sphere around a set of boxes (`None` for none).
pub fn bounding_sphere(boxes: &[(Vec3, Vec3)]) -> Option<(Vec3, f32)> {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (a, b) in boxes {
        lo = lo.min(*a);
        hi = hi.max(*b);
    }
    (lo.x <= hi.x).then(|| ((lo + hi) * 0.5, ((hi - lo) * 0.5).length()))
}

/// Turns the orbit to the selected pair: the focus at the centre of its two shapes, the distance so
/// both fit, the angles kept (the orbit controls go on from there). Without a selection the request
/// is dropped.
fn frame_selected_pair(
    mut frame: ResMut<FrameRequest>,
    viewer: Res<Viewer>,
    settings: Res<Settings>,
    selection: Res<Selection>,
    shapes: Query<(&ShapeEntity, &Aabb, &GlobalTransform)>,
    mut orbits: Query<&mut Orbit>,
) {
    frame.0 = false;
    let Some((a, b)) = viewer.0.sampled(settings.shape_type).and_then(|d| {
        let p = selection.within(d.pair_count())?;
        Some(d.pair(p))
    }) else {
        return;
    };
    let boxes: Vec<(Vec3, Vec3)> = shapes
        .iter()
        .filter(|(s, _, _)| s.shape_type == settings.shape_type && (s.index == a || s.index == b))
        .flat_map(|(_, aabb, t)| {
            let (c, h) = (Vec3::from(aabb.center), Vec3::from(aabb.half_extents));
            // The eight corners in the world frame, as a degenerate box each.
            (0..8).map(move |k| {
                let s = Vec3::new(
                    if k & 1 == 0 { -1.0 } else { 1.0 },
                    if k & 2 == 0 { -1.0 } else { 1.0 },
                    if k & 4 == 0 { -1.0 } else { 1.0 },
                );
                let p = t.transform_point(c + h * s);
                (p, p)
            })
        })
        .collect();
    if let Some((center, radius)) = bounding_sphere(&boxes) {
        for mut orbit in &mut orbits {
            orbit.focus = center;
            orbit.distance = (radius * FRAME_DISTANCE).clamp(0.15, 100.0);
        }
    }
}

/// Mouse input over the 3D view (not over a panel) moves the orbit.
fn orbit_from_mouse(
    buttons: Res<ButtonInput<MouseButton>>,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    layout: Res<UiLayout>,
    window: Single<&Window, With<PrimaryWindow>>,
    mut orbits: Query<&mut Orbit>,
    mut dragging: Local<bool>,
) {
    let over_view = window
        .cursor_position()
        .is_some_and(|p| layout.free.contains(bevy_egui::egui::pos2(p.x, p.y)));
    let any = buttons.any_pressed([MouseButton::Left, MouseButton::Right, MouseButton::Middle]);
    if buttons.any_just_pressed([MouseButton::Left, MouseButton::Right, MouseButton::Middle]) {
        *dragging = over_view;
    }
    if !any {
        *dragging = false;
    }
    for mut orbit in &mut orbits {
        let d = motion.delta;
        if *dragging && d != Vec2::ZERO {
            if buttons.pressed(MouseButton::Left) {
                orbit.yaw -= d.x * 0.008;
                orbit.pitch = (orbit.pitch + d.y * 0.008).clamp(-1.5, 1.5);
            } else {
                let t = orbit.transform();
                let scale = orbit.distance * 0.0015;
                let delta = (t.right() * -d.x + t.up() * d.y) * scale;
                orbit.focus += delta;
            }
        }
        if over_view && scroll.delta.y != 0.0 {
            let lines = match scroll.unit {
                MouseScrollUnit::Line => scroll.delta.y,
                MouseScrollUnit::Pixel => scroll.delta.y / 40.0,
            };
            orbit.distance = (orbit.distance * 0.9f32.powf(lines)).clamp(0.05, 100.0);
        }
    }
}

/// Moves the camera to its orbit.
fn place_camera(mut cameras: Query<(&Orbit, &mut Transform), Changed<Orbit>>) {
    for (orbit, mut transform) in &mut cameras {
        *transform = orbit.transform();
    }
}

/// Restricts the camera to the free part of the window, so the robot is centred between the panels.
fn fit_viewport(
    layout: Res<UiLayout>,
    window: Single<&Window, With<PrimaryWindow>>,
    mut cameras: Query<&mut Camera, With<Orbit>>,
) {
    let scale = window.scale_factor();
    let (w, h) = (window.physical_width(), window.physical_height());
    let free = layout.free;
    if !free.is_finite() || w == 0 || h == 0 {
        return;
    }
    let x0 = ((free.min.x * scale).max(0.0) as u32).min(w - 1);
    let y0 = ((free.min.y * scale).max(0.0) as u32).min(h - 1);
    let x1 = ((free.max.x * scale) as u32).clamp(x0 + 1, w);
    let y1 = ((free.max.y * scale) as u32).clamp(y0 + 1, h);
    let viewport = Viewport {
        physical_position: UVec2::new(x0, y0),
        physical_size: UVec2::new(x1 - x0, y1 - y0),
        ..default()
    };
    for mut camera in &mut cameras {
        let same = camera.viewport.as_ref().is_some_and(|v| {
            v.physical_position == viewport.physical_position
                && v.physical_size == viewport.physical_size
        });
        if !same {
            camera.viewport = Some(viewport.clone());
        }
    }
}

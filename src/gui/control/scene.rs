//! The 3D scene of the viewer: a mesh per geometry of every environment body and robot
//! link, touch pads that light up when pressed, lights with shadows. Physics runs in the
//! configuration's frame (z up); one root entity turns it into Bevy's y-up frame, so every
//! visual below it uses configuration coordinates. The scene is rebuilt whenever the
//! session builds a new world (load, restart) and follows the engine's bodies every frame.

use bevy::prelude::*;

use crate::config::Simulation;
use crate::config::body::{Geom, Shape};
use crate::gui::control::session::SimSession;
use crate::gui::view3d::meshes::{
    ShowGrid, apply_show_grid, geom_material, geom_mesh, spawn_grid, spawn_lights, to_transform,
};
use crate::sim::engine::BodyId;

/// The root of the scene (configuration frame -> Bevy frame).
#[derive(Component)]
pub struct SceneRoot;

/// A visual that follows a body of the physics engine.
#[derive(Component)]
pub struct BodyVisual {
    /// The engine's body it follows.
    pub body: BodyId,
    /// Index of the robot link it shows (None: an environment body).
    pub link: Option<usize>,
    /// A left drag moves it without a modifier (robot links, dynamic objects); the static
    /// scenery moves only with Shift held.
    pub movable: bool,
}

/// A touch pad's visual.
#[derive(Component)]
pub struct PadVisual {
    /// The pad's index on robot 0.
    pub index: usize,
    /// Its material when pressed.
    pub pressed: Handle<StandardMaterial>,
    /// Its material when released.
    pub released: Handle<StandardMaterial>,
}

/// Which world the scene shows (the simulator's build count).
#[derive(Resource, Default)]
pub struct SceneBuilt(pub Option<u64>);

/// Builds the scene from the session's world: environment, robot links, pads.
pub fn build_scene(
    mut commands: Commands,
    mut built: ResMut<SceneBuilt>,
    session: NonSend<SimSession>,
    roots: Query<Entity, With<SceneRoot>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    show: Option<Res<ShowGrid>>,
) {
    let show = show.map_or_else(ShowGrid::default, |s| *s);
    if built.0 == Some(session.generation) {
        return;
    }
    built.0 = Some(session.generation);
    for e in &roots {
        commands.entity(e).despawn();
    }
    let root = commands
        .spawn((
            Name::new("scene (z-up configuration frame)"),
            SceneRoot,
            Transform::from_rotation(Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)),
            Visibility::default(),
        ))
        .id();
    let sim = &session.sim;
    // (name, what it follows, geometries) of every body shown.
    let mut bodies = Vec::new();
    for obj in session.simulator.environment_bodies() {
        if let Some(body) = sim.environment.bodies.get(obj.index) {
            let visual = BodyVisual {
                body: obj.body,
                link: None,
                movable: body.kind == crate::config::body::BodyKind::Dynamic,
            };
            bodies.push((format!("environment: {}", body.name), visual, &body.geoms));
        }
    }
    for l in session.simulator.links(0).unwrap_or_default() {
        if let Some(model) = sim.robot.links.get(l.index) {
            let visual = BodyVisual {
                body: l.body,
                link: Some(l.index),
                movable: true,
            };
            bodies.push((format!("link {}", model.name), visual, &model.geoms));
        }
    }
    let mut link_entities = vec![None; sim.robot.links.len()];
    for (name, visual, geoms) in bodies {
        let (handle, link) = (visual.body, visual.link);
        // The scenery's fixed bodies carry the metre grid.
        let grid = (link.is_none() && !visual.movable).then_some(show);
        let e = spawn_body(
            &mut commands,
            (&mut meshes, &mut materials),
            sim,
            (name, visual),
            geoms,
            grid,
        );
        commands.entity(root).add_child(e);
        if let Some(slot) = link.and_then(|i| link_entities.get_mut(i)) {
            *slot = Some((e, handle));
        }
    }
    spawn_pads(
        &mut commands,
        &mut meshes,
        &mut materials,
        &session,
        &link_entities,
    );
}

/// The pads of robot 0 as small boxes under their links.
fn spawn_pads(
    commands: &mut Commands,
    meshes: &mut Assets<Mesh>,
    materials: &mut Assets<StandardMaterial>,
    session: &SimSession,
    links: &[Option<(Entity, BodyId)>],
) {
    let pressed = materials.add(StandardMaterial {
        base_color: Color::srgb(1.0, 0.1, 0.05),
        emissive: LinearRgba::rgb(2.0, 0.1, 0.0),
        ..default()
    });
    let released = materials.add(Color::srgb(0.45, 0.1, 0.1));
    for pad in session.simulator.tactile_pads(0).unwrap_or_default() {
        let Some((link, _)) = links.iter().flatten().find(|(_, lh)| *lh == pad.link) else {
            continue;
        };
        let he = pad.area.half_extents;
        let t = to_transform(&pad.area.pose);
        let e = commands
            .spawn((
                Name::new(format!("touch pad {}", pad.index)),
                PadVisual {
                    index: pad.index,
                    pressed: pressed.clone(),
                    released: released.clone(),
                },
                Mesh3d(meshes.add(Cuboid::new(
                    2.0 * he[0] as f32 + 0.001,
                    2.0 * he[1] as f32 + 0.001,
                    2.0 * he[2] as f32 + 0.001,
                ))),
                MeshMaterial3d(released.clone()),
                t,
            ))
            .id();
        commands.entity(*link).add_child(e);
    }
}

/// A body entity with one child mesh per geometry (with `grid`, a floor's metre lines on
/// those that get them).
fn spawn_body(
    commands: &mut Commands,
    (meshes, materials): (&mut Assets<Mesh>, &mut Assets<StandardMaterial>),
    sim: &Simulation,
    (name, visual): (String, BodyVisual),
    geoms: &[Geom],
    grid: Option<ShowGrid>,
) -> Entity {
    let parent = commands
        .spawn((
            Name::new(name),
            visual,
            Transform::default(),
            Visibility::default(),
        ))
        .id();
    for (i, g) in geoms.iter().enumerate().filter(|(_, g)| g.visible) {
        let tri = match &g.shape {
            Shape::Trimesh { file, .. } => sim.mesh(file).map(|m| &**m),
            _ => None,
        };
        let Some(mesh) = geom_mesh(&g.shape, tri) else {
            continue;
        };
        let material = geom_material(g);
        let child = commands
            .spawn((
                Name::new(format!("geom {i}")),
                Mesh3d(meshes.add(mesh)),
                MeshMaterial3d(materials.add(material)),
                to_transform(&g.pose),
            ))
            .id();
        if let Some(show) = grid {
            spawn_grid(commands, meshes, materials, child, &g.shape, show);
        }
        commands.entity(parent).add_child(child);
    }
    parent
}

/// Moves every body visual to its engine body's pose.
pub fn follow_bodies(
    session: NonSend<SimSession>,
    mut visuals: Query<(&BodyVisual, &mut Transform)>,
) {
    let engine = session.simulator.engine();
    for (v, mut t) in &mut visuals {
        if let Some(b) = engine.body(v.body) {
            *t = to_transform(&b.pose);
        }
    }
}

/// Colours pads by robot 0's debounced tactile readings.
pub fn colour_pads(
    session: NonSend<SimSession>,
    mut pads: Query<(&PadVisual, &mut MeshMaterial3d<StandardMaterial>)>,
) {
    let Ok(sensors) = session.simulator.sensors(0) else {
        return;
    };
    for (pad, mut material) in &mut pads {
        let on = sensors.tactile.get(pad.index).copied().unwrap_or(false);
        let want = if on { &pad.pressed } else { &pad.released };
        if material.0 != *want {
            material.0 = want.clone();
        }
    }
}

/// The 3D scene: lights, meshes built for the session's bodies, following them, pads
/// coloured by touch.
pub struct ScenePlugin;

impl Plugin for ScenePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<SceneBuilt>()
            .init_resource::<ShowGrid>()
            .add_systems(Startup, spawn_lights)
            .add_systems(
                Update,
                (build_scene, apply_show_grid, follow_bodies, colour_pads)
                    .chain()
                    .in_set(crate::gui::control::schedule::GuiSystems::Scene),
            );
    }
}

//! The configuration window's 3D scene: the robot preview on the robot and behaviour
//! pages, the edited environment with the robot placeholder at its start pose in the
//! environment editor. Rebuilt when what it shows changes; while an object is dragged
//! only its transform follows, so the picking target stays alive. The selection is
//! outlined with its bounding box.

use std::collections::HashMap;

use bevy::prelude::*;

use crate::compose::env_edit::{EnvEditor, Selected};
use crate::config::body::{Geom, Shape};
use crate::config::environment::EnvObject;
use crate::config::kinbody::parse_kinbody_file;
use crate::config::resolve::robot::RobotModel;
use crate::config::source::{FsSource, resolve_include};
use crate::config::transform::Pose;
use crate::gui::setup::preview::{robot_file_model, robot_key, robot_model};
use crate::gui::setup::state::EditorDrag;
use crate::gui::setup::state::{SetupState, Tool};
use crate::gui::view3d::meshes::{ShowGrid, geom_material, geom_mesh, spawn_grid, to_transform};
use crate::gui::view3d::orbit::to_bevy;

/// The root of the scene (configuration frame, z up -> Bevy's y up).
#[derive(Component)]
pub struct SetupSceneRoot;

/// A pickable item of the scene: an environment object or the robot.
#[derive(Component, Debug, Clone, Copy, PartialEq, Eq)]
pub struct ItemVisual(pub Selected);

/// What the scene was built from, the robot preview, and meshes by shape.
#[derive(Resource, Default)]
pub struct SceneCache {
    key: Option<String>,
    robot_key: Option<String>,
    /// The expert composition's environment, shown read-only.
    expert_env: Option<(std::path::PathBuf, Option<EnvEditor>)>,
    /// The robot preview, or why there is none.
    pub robot: Option<Result<RobotModel, crate::gui::error::GuiError>>,
    /// Objects of the edited environment the robot would start inside (warnings).
    pub overlaps: Vec<String>,
    meshes: HashMap<String, Handle<Mesh>>,
}

/// Where a body's mesh files were parsed: the robot model's, or the edited scene's (whose
/// editor reports a file that does not load); the views parse none of their own.
#[derive(Clone, Copy)]
enum MeshFrom<'a> {
    Robot(&'a RobotModel),
    Scene(&'a EnvEditor),
    Nowhere,
}

fn shape_key(s: &Shape) -> String {
    format!("{s:?}")
}

/// The asset stores a scene is built into.
#[derive(bevy::ecs::system::SystemParam)]
pub struct SceneAssets<'w> {
    meshes: ResMut<'w, Assets<Mesh>>,
    materials: ResMut<'w, Assets<StandardMaterial>>,
}

/// Keeps the robot preview up to date and rebuilds the scene when it changed.
pub fn sync_scene(
    mut commands: Commands,
    state: Res<SetupState>,
    drag: Res<EditorDrag>,
    mut cache: ResMut<SceneCache>,
    roots: Query<Entity, With<SetupSceneRoot>>,
    mut items: Query<(&ItemVisual, &mut Transform)>,
    mut assets: SceneAssets,
) {
    let rk = refresh_models(&state, &mut cache);
    let editing = state.editing_env();
    // The wizard's pages after the terrain show the robot in it.
    let wizard_scene = state.wizard_shows_terrain();
    if drag.dragging {
        // Only the dragged item moves: keep its entity (the drag's target) alive.
        let env = state.env();
        for (item, mut t) in &mut items {
            if let Some(p) = env.pose(item.0) {
                *t = to_transform(&p);
            }
        }
        return;
    }
    let key = format!(
        "{editing}|{wizard_scene}|{:?}|{}|{rk}|{:?}",
        state.tool,
        if editing || wizard_scene {
            state.env().revision
        } else {
            0
        },
        cache.expert_env.as_ref().map(|(p, _)| p),
    );
    if cache.key.as_deref() == Some(key.as_str()) {
        return;
    }
    cache.key = Some(key);
    for e in &roots {
        commands.entity(e).despawn();
    }
    let root = commands
        .spawn((
            Name::new("setup scene (z-up configuration frame)"),
            SetupSceneRoot,
            Transform::from_rotation(Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2)),
            Visibility::default(),
        ))
        .id();
    let robot = match &cache.robot {
        Some(Ok(model)) => Some(model.clone()),
        _ => None,
    };
    let shown_env: Option<EnvEditor> = if editing || wizard_scene {
        Some(state.env().clone())
    } else {
        cache.expert_env.as_ref().and_then(|(_, e)| e.clone())
    };
    cache.overlaps = match (&shown_env, &robot) {
        (Some(env), Some(r)) if editing => env.robot_overlaps(r),
        _ => Vec::new(),
    };
    let cache = &mut *cache;
    let mut spawner = Spawner {
        commands: &mut commands,
        meshes: &mut assets.meshes,
        materials: &mut assets.materials,
        cache: &mut cache.meshes,
    };
    let robot_pose = shown_env.as_ref().map_or(Pose::IDENTITY, |e| e.robot_pose);
    let robot_entity = spawner.robot(robot.as_ref(), &robot_pose);
    spawner.commands.entity(root).add_child(robot_entity);
    if let Some(env) = &shown_env {
        spawner.environment(root, env);
    }
}

/// Rebuilds the robot preview and the expert's environment when what they show changed;
/// returns the robot's key.
fn refresh_models(state: &SetupState, cache: &mut SceneCache) -> String {
    // The expert dialog shows its composition; the wizard and editor the wizard's robot.
    let expert = state.tool == Tool::Expert;
    let composition = &state.expert.composition;
    let rk = if expert {
        format!("expert:{}", composition.robot.display())
    } else {
        robot_key(&state.wizard)
    };
    if cache.robot_key.as_deref() != Some(rk.as_str()) {
        cache.robot = Some(if expert {
            robot_file_model(&composition.robot)
        } else {
            robot_model(&state.wizard)
        });
        cache.robot_key = Some(rk.clone());
    }
    let expert_env = composition.environment.clone().filter(|_| expert);
    if cache.expert_env.as_ref().map(|(p, _)| p) != expert_env.as_ref() {
        cache.expert_env = expert_env.map(|p| {
            // The expert dialog's check names the broken file; the scene shows none.
            let e = EnvEditor::load(&p)
                .inspect_err(|e| bevy::log::warn!("scene without its environment: {e}"))
                .ok();
            (p, e)
        });
    }
    rk
}

/// A thin bar standing in for a robot that cannot be built yet.
fn placeholder() -> Geom {
    Geom {
        shape: Shape::Box {
            extents: [0.026, 0.18, 0.026],
        },
        pose: Pose::from_translation([0.0, 0.144, 0.026]),
        diffuse_color: Some([1.0, 0.8, 0.1]),
        ambient_color: None,
        transparency: Some(0.4),
        friction: None,
        visible: true,
        pos: crate::config::error::Pos::new(0, 0),
    }
}

struct Spawner<'a, 'w, 's> {
    commands: &'a mut Commands<'w, 's>,
    meshes: &'a mut Assets<Mesh>,
    materials: &'a mut Assets<StandardMaterial>,
    cache: &'a mut HashMap<String, Handle<Mesh>>,
}

impl Spawner<'_, '_, '_> {
    /// The robot (its links, or a placeholder bar) under a pickable item at `pose`.
    fn robot(&mut self, robot: Option<&RobotModel>, pose: &Pose) -> Entity {
        let robot_entity = self.item(ItemVisual(Selected::Robot), "robot", pose);
        match robot {
            Some(model) => {
                for link in &model.links {
                    let from = MeshFrom::Robot(model);
                    self.body(
                        robot_entity,
                        (&link.name, &link.pose),
                        &link.geoms,
                        from,
                        false,
                    );
                }
            }
            None => {
                // No valid robot yet: a placeholder bar where it would lie.
                let g = placeholder();
                self.body(
                    robot_entity,
                    ("robot placeholder", &Pose::IDENTITY),
                    &[g],
                    MeshFrom::Nowhere,
                    false,
                );
            }
        }
        robot_entity
    }

    /// Every object of `env` as a pickable item under `root` (included kinbody files are
    /// read to show their bodies).
    fn environment(&mut self, root: Entity, env: &EnvEditor) {
        for (i, o) in env.objects.iter().enumerate() {
            let (pose, kb, name) = match o {
                EnvObject::Inline(kb) => (kb.pose, Some(kb.clone()), kb.name.clone()),
                EnvObject::Include(inc) => {
                    let kb = resolve_include(&FsSource, &env.file, &inc.file).and_then(|p| {
                        let text = std::fs::read_to_string(&p).ok()?;
                        parse_kinbody_file(&p.display().to_string(), &text).ok()
                    });
                    let kb = kb.map(|mut k| {
                        // The file's own placement sits under the include's pose.
                        let inner = k.pose;
                        for b in &mut k.bodies {
                            b.pose = inner.mul(&b.pose);
                        }
                        k
                    });
                    (inc.pose, kb, Some(inc.file.clone()))
                }
                EnvObject::Terrain(t) => (t.pose, Some(env.terrain(t)), Some(t.label())),
            };
            let e = self.item(
                ItemVisual(Selected::Object(i)),
                &name.unwrap_or_else(|| format!("object {i}")),
                &pose,
            );
            if let Some(kb) = kb {
                for b in &kb.bodies {
                    // A fixed body's floor-sized boxes carry the metre grid.
                    let grid = b.kind == crate::config::body::BodyKind::Static;
                    self.body(e, (&b.name, &b.pose), &b.geoms, MeshFrom::Scene(env), grid);
                }
            }
            self.commands.entity(root).add_child(e);
        }
    }

    fn item(&mut self, item: ItemVisual, name: &str, pose: &Pose) -> Entity {
        self.commands
            .spawn((
                Name::new(format!("scene item: {name}")),
                item,
                to_transform(pose),
                Visibility::default(),
            ))
            .id()
    }

    /// A body under `parent` with a mesh per geometry (with `grid`, the ground's metre grid
    /// on those that get one); mesh files resolve from `env`'s file.
    fn body(
        &mut self,
        parent: Entity,
        (name, pose): (&str, &Pose),
        geoms: &[Geom],
        from: MeshFrom,
        grid: bool,
    ) {
        let body = self
            .commands
            .spawn((
                Name::new(format!("body {name}")),
                to_transform(pose),
                Visibility::default(),
            ))
            .id();
        self.commands.entity(parent).add_child(body);
        for (i, g) in geoms.iter().enumerate().filter(|(_, g)| g.visible) {
            let mut shape = g.shape.clone();
            if let (Shape::Trimesh { file, .. }, MeshFrom::Scene(env)) = (&mut shape, from)
                && let Some(p) = resolve_include(&FsSource, &env.file, file)
            {
                *file = p.display().to_string();
            }
            let key = shape_key(&shape);
            let mesh = match self.cache.get(&key) {
                Some(h) => h.clone(),
                None => {
                    let tri = match (&g.shape, from) {
                        (Shape::Trimesh { file, .. }, MeshFrom::Robot(m)) => {
                            m.meshes.get(file).cloned()
                        }
                        (Shape::Trimesh { file, .. }, MeshFrom::Scene(env)) => env.mesh(file),
                        _ => None,
                    };
                    let Some(m) = geom_mesh(&shape, tri.as_deref()) else {
                        continue;
                    };
                    let h = self.meshes.add(m);
                    self.cache.insert(key, h.clone());
                    h
                }
            };
            let child = self
                .commands
                .spawn((
                    Name::new(format!("geom {i}")),
                    Mesh3d(mesh),
                    MeshMaterial3d(self.materials.add(geom_material(g))),
                    to_transform(&g.pose),
                ))
                .id();
            if grid {
                spawn_grid(
                    self.commands,
                    self.meshes,
                    self.materials,
                    child,
                    &g.shape,
                    ShowGrid::default(),
                );
            }
            self.commands.entity(body).add_child(child);
        }
    }
}

/// Outlines the selection's bounding box and marks the robot's heading.
pub fn draw_selection(state: Res<SetupState>, mut gizmos: Gizmos) {
    if !state.editing_env() {
        if state.tool == Tool::Wizard && !state.wizard_shows_terrain() {
            // A 10 cm grid on the ground under the robot preview (the terrain, once shown,
            // has its own metre grid).
            gizmos.grid(
                Isometry3d::new(
                    Vec3::new(0.0, 0.0, -0.15),
                    Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
                ),
                UVec2::splat(16),
                Vec2::splat(0.1),
                Color::srgba(1.0, 1.0, 1.0, 0.5),
            );
        }
        return;
    }
    // The last preview's path: where the robot crawled, start to end.
    if let Some(Ok(run)) = &state.preview {
        let lift = Vec3::Y * 0.02;
        gizmos.linestrip(
            run.track.iter().map(|p| to_bevy(*p) + lift),
            Color::srgb(1.0, 0.45, 0.0),
        );
        if let Some(end) = run.track.last() {
            gizmos.sphere(
                Isometry3d::from_translation(to_bevy(*end) + lift),
                0.03,
                Color::srgb(1.0, 0.45, 0.0),
            );
        }
    }
    let robot = state.env().robot_pose;
    let start = to_bevy(robot.translation);
    let ahead = robot.rotate([0.0, 0.5, 0.0]);
    let tip = to_bevy([
        robot.translation[0] + ahead[0],
        robot.translation[1] + ahead[1],
        robot.translation[2] + ahead[2],
    ]);
    // Above the robot's modules, so it shows over them.
    gizmos.arrow(
        start + Vec3::Y * 0.08,
        tip + Vec3::Y * 0.08,
        Color::srgb(1.0, 0.8, 0.1),
    );
    let Some(sel) = state.env().selected else {
        return;
    };
    let bounds = match sel {
        Selected::Object(i) => state.env().bounds(i),
        Selected::Robot => {
            let t = robot.translation;
            crate::compose::env_edit::Aabb {
                min: [t[0] - 0.05, t[1] - 0.05, t[2]],
                max: [t[0] + 0.05, t[1] + 0.45, t[2] + 0.06],
            }
        }
    };
    let (lo, hi) = (to_bevy(bounds.min), to_bevy(bounds.max));
    let centre = (lo + hi) / 2.0;
    let size = (hi - lo).abs() + Vec3::splat(0.004);
    if size.is_finite() {
        gizmos.cube(
            Transform::from_translation(centre).with_scale(size),
            Color::srgb(1.0, 1.0, 0.0),
        );
    }
}

/// The 3D scene of the models: lights, the scene rebuilt when the models change, the
/// selection drawn.
pub struct SetupScenePlugin;

impl Plugin for SetupScenePlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<SceneCache>()
            .add_systems(Startup, crate::gui::view3d::meshes::spawn_lights)
            .add_systems(
                Update,
                (sync_scene, draw_selection)
                    .chain()
                    .in_set(crate::gui::setup::schedule::SetupSystems::Scene),
            );
    }
}

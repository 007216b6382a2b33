//! The environment editor's model (thesis 4.4.6): objects from the [`library`] dropped
//! onto the ground or onto what lies under the cursor, selected, moved, turned about the
//! vertical axis, scaled, given friction, static/dynamic, mass and colour, deleted; every
//! change can be undone and redone. The robot placeholder is always there and sets the
//! robot's start pose. Loads and saves ordinary `*.env.xml` files.
//!
//! Objects that include a kinbody file (`<KinBody file=..>`) can be moved and turned;
//! their contents are edited in their own file.
//!
//! [`library`]: crate::compose::library

mod bounds;
pub use bounds::MeshError;
mod error;
mod history;

use std::path::{Path, PathBuf};

pub use bounds::{Aabb, OVERLAP_TOLERANCE, SceneMeshes};
use bounds::{add_geom, shape_aabb};
pub use error::EditError;
use history::{History, Snapshot};

use crate::compose::library::LibraryItem;
use crate::config::body::{BodyKind, Geom, MAX_FRICTION, Mass, MeshCollision, Shape};
use crate::config::environment::{
    EnvObject, EnvironmentFile, Physics, parse_environment_file, write_environment_file,
};
use crate::config::kinbody::KinBody;
use crate::config::resolve::environment::resolve_environment;
use crate::config::resolve::robot::RobotModel;
use crate::config::source::{FileSource, FsSource, resolve_include};
use crate::config::start_clearance::Boxes;
use crate::config::terrain::{Family, TerrainSpec, Tier};
use crate::config::transform::{Pose, quat_mul};

/// Largest friction the editor offers (Coulomb coefficient, as the thesis's dialog).
pub const EDITOR_MAX_FRICTION: f64 = 1.0;

/// What is selected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Selected {
    /// The robot placeholder (its start pose).
    Robot,
    /// Object `i` of the scene.
    Object(usize),
}

/// The properties the side panel shows for the selection.
#[derive(Debug, Clone, PartialEq)]
pub struct Props {
    /// The object's name (or the included file).
    pub name: String,
    /// Position (m, z up).
    pub position: [f64; 3],
    /// Heading about z (degrees).
    pub yaw_deg: f64,
    /// Extent of its bounds (m).
    pub size: [f64; 3],
    /// None: not editable here (robot, included file) or mixed.
    pub friction: Option<f64>,
    /// Whether it is pushed around (a dynamic body).
    pub dynamic: bool,
    /// Total mass (kg), when given.
    pub mass: Option<f64>,
    /// Diffuse colour (RGB 0..1), when given.
    pub colour: Option<[f64; 3]>,
    /// Whether size, friction, mass and colour can be changed (an inline object).
    pub editable: bool,
    /// A generated terrain's family, difficulty and seed (changed here).
    pub terrain: Option<TerrainSpec>,
}

/// An environment object as a kinbody and where it is placed.
struct PlacedKinBody {
    kinbody: KinBody,
    pose: Pose,
}

/// The environment being edited.
#[derive(Debug, Clone)]
pub struct EnvEditor {
    /// Gravity, self-collision and default friction of the scene.
    pub physics: Physics,
    /// The scene's objects, inline or included.
    pub objects: Vec<EnvObject>,
    /// The robot's start pose.
    pub robot_pose: Pose,
    /// What is selected.
    pub selected: Option<Selected>,
    /// Where the file is (or will be) saved: includes and meshes resolve from here.
    pub file: PathBuf,
    history: History,
    /// Merges a drag's many moves into one undo step.
    dragging: bool,
    /// Mesh files read for bounds, parsed once.
    meshes: SceneMeshes,
    /// Bumped on every change (the 3D view rebuilds when it changes).
    pub revision: u64,
}

/// A rotation about z by `deg` degrees, as a quaternion.
fn yaw_quat(deg: f64) -> [f64; 4] {
    let h = deg.to_radians() / 2.0;
    [h.cos(), 0.0, 0.0, h.sin()]
}

/// The heading (rotation about z) of a quaternion, in degrees.
pub fn yaw_of(q: [f64; 4]) -> f64 {
    let [w, x, y, z] = q;
    (2.0 * (w * z + x * y))
        .atan2(1.0 - 2.0 * (y * y + z * z))
        .to_degrees()
}

fn object_pose(o: &EnvObject) -> Pose {
    match o {
        EnvObject::Inline(kb) => kb.pose,
        EnvObject::Include(i) => i.pose,
        EnvObject::Terrain(t) => t.pose,
    }
}

fn object_pose_mut(o: &mut EnvObject) -> &mut Pose {
    match o {
        EnvObject::Inline(kb) => &mut kb.pose,
        EnvObject::Include(i) => &mut i.pose,
        EnvObject::Terrain(t) => &mut t.pose,
    }
}

/// The name shown for an object.
pub fn object_name(o: &EnvObject, index: usize) -> String {
    match o {
        EnvObject::Inline(kb) => kb.name.clone().unwrap_or_else(|| format!("object {index}")),
        EnvObject::Include(i) => format!("{} (file)", i.file),
        EnvObject::Terrain(t) => format!("terrain {}", t.label()),
    }
}

impl EnvEditor {
    /// A new environment: gravity, self collision and an 8 m x 8 m floor, the robot at
    /// the origin. `file` is where it will be saved.
    pub fn new(file: impl Into<PathBuf>) -> Self {
        let mut floor = LibraryItem::Box.kinbody("floor");
        floor.bodies[0].geoms[0].shape = Shape::Box {
            extents: [4.0, 4.0, 0.003],
        };
        floor.bodies[0].geoms[0].diffuse_color = Some([0.3, 1.0, 0.3]);
        floor.pose = Pose::from_translation([0.0, 0.0, -0.003]);
        EnvEditor {
            physics: Physics {
                self_collision: true,
                ..Physics::default()
            },
            objects: vec![EnvObject::Inline(floor)],
            robot_pose: Pose::IDENTITY,
            selected: None,
            file: file.into(),
            history: History::default(),
            dragging: false,
            meshes: SceneMeshes::default(),
            revision: 0,
        }
    }

    /// An empty scene (only the robot placeholder).
    pub fn empty(file: impl Into<PathBuf>) -> Self {
        let mut e = EnvEditor::new(file);
        e.objects.clear();
        e
    }

    /// Opens an environment file.
    pub fn load(path: &Path) -> Result<Self, EditError> {
        let text = std::fs::read_to_string(path).map_err(|source| EditError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let file = parse_environment_file(&path.display().to_string(), &text)?;
        let mut e = EnvEditor::empty(path);
        e.physics = file.physics;
        e.objects = file.objects;
        e.robot_pose = file.robot_pose.unwrap_or(Pose::IDENTITY);
        Ok(e)
    }

    /// The environment file this scene is.
    pub fn to_file(&self) -> EnvironmentFile {
        let mut file = EnvironmentFile {
            physics: self.physics.clone(),
            objects: self.objects.clone(),
            robot_pose: Some(self.robot_pose),
        };
        file.round_for_people();
        file
    }

    /// Checks the scene the way a simulation would load it (meshes and included files
    /// found, values valid) and writes it to `path`; the editor then belongs to `path`.
    pub fn save(&mut self, path: &Path) -> Result<(), EditError> {
        let text = write_environment_file(&self.to_file());
        let reread = parse_environment_file(&path.display().to_string(), &text)?;
        resolve_environment(&FsSource, path, &reread)?;
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| EditError::Io { path, source }
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
        }
        std::fs::write(path, text).map_err(io(path))?;
        self.file = path.to_path_buf();
        Ok(())
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot {
            objects: self.objects.clone(),
            robot_pose: self.robot_pose,
        }
    }

    /// Records the state before a change.
    fn checkpoint(&mut self) {
        self.history.record(self.snapshot());
        self.revision += 1;
    }

    fn restore(&mut self, s: Snapshot) {
        self.objects = s.objects;
        self.robot_pose = s.robot_pose;
        if let Some(Selected::Object(i)) = self.selected
            && i >= self.objects.len()
        {
            self.selected = None;
        }
        self.revision += 1;
    }

    /// Whether there is an edit to undo.
    pub fn can_undo(&self) -> bool {
        self.history.can_undo()
    }

    /// Whether there is an undone edit to redo.
    pub fn can_redo(&self) -> bool {
        self.history.can_redo()
    }

    /// Undoes the last edit; false when there was none.
    pub fn undo(&mut self) -> bool {
        let Some(s) = self.history.undo(self.snapshot()) else {
            return false;
        };
        self.restore(s);
        true
    }

    /// Redoes the last undone edit; false when there was none.
    pub fn redo(&mut self) -> bool {
        let Some(s) = self.history.redo(self.snapshot()) else {
            return false;
        };
        self.restore(s);
        true
    }

    /// A mesh file as named in the scene, parsed once (the 3D views draw this one); none
    /// when it cannot be read, its error kept ([`EnvEditor::mesh_errors`]).
    pub fn mesh(&self, file: &str) -> Option<std::sync::Arc<crate::config::mesh::TriMesh>> {
        self.meshes.mesh(&self.file, file)
    }

    /// Bounds of a mesh file as named in the scene (none when it cannot be read).
    fn mesh_aabb(&self, file: &str, scale: f64) -> Option<Aabb> {
        self.meshes.aabb(&self.file, file, scale)
    }

    /// Makes every mesh geometry of `kb` whose mesh is a height map collide as a height
    /// field (cheaper terrain contacts than its triangles).
    fn height_fields_where_possible(&self, kb: &mut KinBody) {
        for g in kb.bodies.iter_mut().flat_map(|b| &mut b.geoms) {
            if let Shape::Trimesh {
                file, collision, ..
            } = &mut g.shape
                && self.mesh(file).is_some_and(|m| m.height_map().is_ok())
            {
                *collision = MeshCollision::HeightField;
            }
        }
    }

    /// Mesh files the scene names that could not be read, with the reason (file: line).
    pub fn mesh_errors(&self) -> Vec<MeshError> {
        self.meshes.errors()
    }

    /// World bounds of a kinbody placed at `pose`.
    fn kinbody_aabb(&self, kb: &KinBody, pose: &Pose) -> Aabb {
        let mut out = Aabb::EMPTY;
        for body in &kb.bodies {
            let bp = pose.mul(&body.pose);
            for g in &body.geoms {
                let local = match &g.shape {
                    Shape::Trimesh { file, scale, .. } => self.mesh_aabb(file, *scale),
                    other => shape_aabb(other),
                };
                add_geom(&mut out, g, &bp, local);
            }
        }
        out
    }

    /// Objects that reach into a robot link at the start pose by more than
    /// [`OVERLAP_TOLERANCE`] (the robot would start inside them), each as a warning naming
    /// the object: the start-clearance check of a co-design body
    /// ([`crate::config::start_clearance::Boxes`], oriented boxes; the scenery's meshes are
    /// not checked, their bounds say nothing of their surface).
    pub fn robot_overlaps(&self, robot: &RobotModel) -> Vec<String> {
        let mut links = Boxes::default();
        for l in &robot.links {
            links.add(&l.geoms, &self.robot_pose.mul(&l.pose), Some(&robot.meshes));
        }
        let mut out = Vec::new();
        for i in 0..self.objects.len() {
            let Some(placed) = self.placed_kinbody(i) else {
                continue;
            };
            let mut boxes = Boxes::default();
            for body in &placed.kinbody.bodies {
                boxes.add(&body.geoms, &placed.pose.mul(&body.pose), None);
            }
            let deepest = boxes.deepest(&links);
            if deepest > OVERLAP_TOLERANCE {
                out.push(format!(
                    "{} overlaps the robot's start pose (by {:.0} mm): move one of them",
                    object_name(&self.objects[i], i),
                    deepest * 1000.0
                ));
            }
        }
        out
    }

    /// Object `i` as a kinbody and its placement (none for an included file that cannot
    /// be read), read through the file source the loader uses.
    fn placed_kinbody(&self, i: usize) -> Option<PlacedKinBody> {
        match self.objects.get(i)? {
            EnvObject::Inline(kb) => Some(PlacedKinBody {
                kinbody: kb.clone(),
                pose: kb.pose,
            }),
            EnvObject::Include(inc) => {
                let p = resolve_include(&FsSource, &self.file, &inc.file)?;
                let text = FsSource.read(&p).ok()?;
                let kb =
                    crate::config::kinbody::parse_kinbody_file(&p.display().to_string(), &text)
                        .ok()?;
                Some(PlacedKinBody {
                    pose: inc.pose.mul(&kb.pose),
                    kinbody: kb,
                })
            }
            EnvObject::Terrain(t) => Some(PlacedKinBody {
                kinbody: self.terrain(t),
                pose: t.pose,
            }),
        }
    }

    /// A generated terrain's bodies (placed by its pose); its height field joins the
    /// scene's meshes, so it is drawn and measured as a mesh file would be.
    pub fn terrain(&self, spec: &crate::config::terrain::TerrainSpec) -> KinBody {
        let generated = crate::config::terrain::generate(spec);
        let live: Vec<String> = self
            .objects
            .iter()
            .filter_map(|o| match o {
                EnvObject::Terrain(t) => Some(t.mesh_name()),
                _ => None,
            })
            .collect();
        for (name, mesh) in generated.meshes {
            self.meshes.add_generated(name, mesh, &live);
        }
        generated.kinbody
    }

    /// World bounds of object `i` (empty for an included file that cannot be read).
    pub fn bounds(&self, i: usize) -> Aabb {
        match self.placed_kinbody(i) {
            Some(p) => self.kinbody_aabb(&p.kinbody, &p.pose),
            None => Aabb::EMPTY,
        }
    }

    /// The height objects dropped at (x, y) land on: the highest top among the objects
    /// covering that point, or the ground (0).
    pub fn surface_at(&self, x: f64, y: f64, skip: Option<usize>) -> f64 {
        let mut top: f64 = 0.0;
        for i in 0..self.objects.len() {
            if Some(i) == skip {
                continue;
            }
            let b = self.bounds(i);
            if b.covers(x, y) {
                top = top.max(b.max[2]);
            }
        }
        top
    }

    fn unique_name(&self, base: &str) -> String {
        let taken = |n: &str| {
            self.objects
                .iter()
                .any(|o| matches!(o, EnvObject::Inline(kb) if kb.name.as_deref() == Some(n)))
        };
        (1..)
            .map(|k| format!("{base}{k}"))
            .find(|n| !taken(n))
            .unwrap_or_else(|| base.to_string())
    }

    /// Drops a library item at (x, y): it lands on the ground or on the object under that
    /// point, and is selected; a mesh that is a height map becomes a height field. Returns
    /// its index.
    pub fn add(&mut self, item: &LibraryItem, x: f64, y: f64) -> usize {
        if let LibraryItem::Terrain(family) = item {
            return self.add_terrain(*family, x, y);
        }
        let name = self.unique_name(&item.label());
        let mut kb = item.kinbody(&name);
        self.height_fields_where_possible(&mut kb);
        let local = self.kinbody_aabb(&kb, &Pose::IDENTITY);
        let surface = self.surface_at(x, y, None);
        let lift = if local.is_empty() { 0.0 } else { -local.min[2] };
        kb.pose = Pose::from_translation([x, y, surface + lift]);
        self.checkpoint();
        self.objects.push(EnvObject::Inline(kb));
        let i = self.objects.len() - 1;
        self.selected = Some(Selected::Object(i));
        i
    }

    /// Drops a course of `family` (medium tier, seed 1) with its start at (x, y), facing
    /// +y as the shipped robots do, and selects it. Returns its index.
    fn add_terrain(&mut self, family: Family, x: f64, y: f64) -> usize {
        let mut spec = TerrainSpec::new(family, Tier::Medium.difficulty(), 1);
        spec.pose = Pose::from_translation([x, y, 0.0]);
        self.checkpoint();
        self.objects.push(EnvObject::Terrain(spec));
        let i = self.objects.len() - 1;
        self.selected = Some(Selected::Object(i));
        i
    }

    /// Sets the selected terrain's difficulty (0..=1) and seed: its course is generated
    /// anew.
    pub fn set_terrain(&mut self, difficulty: f64, seed: u64) -> Result<(), EditError> {
        let Selected::Object(i) = self.need_selection()? else {
            return Err(EditError::NotTerrain);
        };
        let Some(EnvObject::Terrain(t)) = self.objects.get(i) else {
            return Err(EditError::NotTerrain);
        };
        let next = TerrainSpec {
            difficulty,
            seed,
            ..t.clone()
        };
        next.check().map_err(EditError::Terrain)?;
        if next == *t {
            return Ok(());
        }
        self.checkpoint();
        self.objects[i] = EnvObject::Terrain(next);
        Ok(())
    }

    /// Selects an object or the robot (None clears the selection).
    pub fn select(&mut self, s: Option<Selected>) -> Result<(), EditError> {
        if let Some(Selected::Object(i)) = s
            && i >= self.objects.len()
        {
            return Err(EditError::NoObject {
                index: i,
                count: self.objects.len(),
            });
        }
        self.selected = s;
        Ok(())
    }

    fn need_selection(&self) -> Result<Selected, EditError> {
        self.selected.ok_or(EditError::NoSelection)
    }

    /// The selected object's pose (the robot's start pose for the robot).
    pub fn pose(&self, s: Selected) -> Option<Pose> {
        match s {
            Selected::Robot => Some(self.robot_pose),
            Selected::Object(i) => self.objects.get(i).map(object_pose),
        }
    }

    fn pose_mut(&mut self, s: Selected) -> Option<&mut Pose> {
        match s {
            Selected::Robot => Some(&mut self.robot_pose),
            Selected::Object(i) => self.objects.get_mut(i).map(object_pose_mut),
        }
    }

    /// Moves the selection to a position (metres, z up).
    pub fn move_to(&mut self, p: [f64; 3]) -> Result<(), EditError> {
        let s = self.need_selection()?;
        if p.iter().any(|v| !v.is_finite()) {
            return Err(EditError::NotFinite {
                what: "position",
                value: format!("{p:?}"),
            });
        }
        if !self.dragging {
            self.checkpoint();
        } else {
            self.revision += 1;
        }
        if let Some(pose) = self.pose_mut(s) {
            pose.translation = p;
        }
        Ok(())
    }

    /// Moves the selection by an offset.
    pub fn move_by(&mut self, d: [f64; 3]) -> Result<(), EditError> {
        let s = self.need_selection()?;
        let t = self.pose(s).map_or([0.0; 3], |p| p.translation);
        self.move_to([t[0] + d[0], t[1] + d[1], t[2] + d[2]])
    }

    /// A drag starts: its moves become one undo step until [`EnvEditor::end_drag`].
    pub fn begin_drag(&mut self) {
        if !self.dragging {
            self.checkpoint();
            self.dragging = true;
        }
    }

    /// The drag ends (its moves stay one undo step).
    pub fn end_drag(&mut self) {
        self.dragging = false;
    }

    /// Drags the selection over the ground plane to (x, y): it rests on what is there.
    pub fn drag_to(&mut self, x: f64, y: f64) -> Result<(), EditError> {
        let s = self.need_selection()?;
        let z = match s {
            Selected::Robot => self.robot_pose.translation[2],
            Selected::Object(i) => {
                let b = self.bounds(i);
                let pose = self.pose(s).unwrap_or_default();
                let bottom = pose.translation[2] - b.min[2];
                self.surface_at(x, y, Some(i)) + bottom
            }
        };
        self.move_to([x, y, z])
    }

    /// Turns the selection about the vertical axis by `deg` degrees.
    pub fn rotate_by(&mut self, deg: f64) -> Result<(), EditError> {
        let s = self.need_selection()?;
        if !deg.is_finite() {
            return Err(EditError::NotFinite {
                what: "angle",
                value: deg.to_string(),
            });
        }
        self.checkpoint();
        if let Some(pose) = self.pose_mut(s) {
            pose.rotation = quat_mul(yaw_quat(deg), pose.rotation);
        }
        Ok(())
    }

    /// Sets the selection's heading (degrees about z; tilts are kept).
    pub fn set_yaw(&mut self, deg: f64) -> Result<(), EditError> {
        let s = self.need_selection()?;
        let now = self.pose(s).map_or(0.0, |p| yaw_of(p.rotation));
        self.rotate_by(deg - now)
    }

    /// The selected inline object, or why it cannot be edited.
    fn editable(&mut self) -> Result<&mut KinBody, EditError> {
        match self.need_selection()? {
            Selected::Robot => Err(EditError::Robot(
                "the robot placeholder only moves and turns; its size and material come from the robot file",
            )),
            Selected::Object(i) => {
                let count = self.objects.len();
                match self.objects.get_mut(i) {
                    Some(EnvObject::Inline(kb)) => Ok(kb),
                    Some(EnvObject::Include(inc)) => Err(EditError::Included {
                        file: inc.file.clone(),
                    }),
                    Some(EnvObject::Terrain(t)) => Err(EditError::Generated { label: t.label() }),
                    None => Err(EditError::NoObject { index: i, count }),
                }
            }
        }
    }

    /// Scales the selection along x, y, z (each geometry along its own axes; spheres and
    /// meshes by the mean factor), keeping its bottom where it was.
    pub fn scale(&mut self, f: [f64; 3]) -> Result<(), EditError> {
        if f.iter().any(|v| !v.is_finite() || *v <= 0.0 || *v > 1000.0) {
            return Err(EditError::Scale(f));
        }
        let i = match self.need_selection()? {
            Selected::Object(i) => i,
            Selected::Robot => {
                return Err(EditError::Robot("the robot cannot be scaled"));
            }
        };
        self.editable()?;
        let before = self.bounds(i);
        self.checkpoint();
        let mean = (f[0] * f[1] * f[2]).cbrt();
        if let Ok(kb) = self.editable() {
            let mul = |t: &mut [f64; 3]| {
                for k in 0..3 {
                    t[k] *= f[k];
                }
            };
            for body in &mut kb.bodies {
                mul(&mut body.pose.translation);
                for g in &mut body.geoms {
                    mul(&mut g.pose.translation);
                    match &mut g.shape {
                        Shape::Box { extents } => mul(extents),
                        Shape::Sphere { radius } => *radius *= mean,
                        Shape::Cylinder { radius, height } => {
                            *radius *= (f[0] * f[2]).sqrt();
                            *height *= f[1];
                        }
                        Shape::Trimesh { scale, .. } => *scale *= mean,
                    }
                }
            }
        }
        let after = self.bounds(i);
        if !before.is_empty() && !after.is_empty() {
            let dz = before.min[2] - after.min[2];
            if let Some(EnvObject::Inline(kb)) = self.objects.get_mut(i) {
                kb.pose.translation[2] += dz;
            }
        }
        Ok(())
    }

    /// Changes every geometry of the editable selection, undoably.
    fn edit_geoms(&mut self, change: impl FnMut(&mut Geom)) -> Result<(), EditError> {
        self.editable()?;
        self.checkpoint();
        let kb = self.editable()?;
        kb.bodies
            .iter_mut()
            .flat_map(|b| &mut b.geoms)
            .for_each(change);
        Ok(())
    }

    /// Sets the Coulomb friction of every geometry of the selection (0..1).
    pub fn set_friction(&mut self, mu: f64) -> Result<(), EditError> {
        if !(0.0..=EDITOR_MAX_FRICTION.min(MAX_FRICTION)).contains(&mu) {
            return Err(EditError::Friction(mu));
        }
        self.edit_geoms(|g| g.friction = Some(mu))
    }

    /// Makes the selection static (fixed) or dynamic (pushed around).
    pub fn set_dynamic(&mut self, dynamic: bool) -> Result<(), EditError> {
        self.editable()?;
        self.checkpoint();
        let kb = self.editable()?;
        for b in &mut kb.bodies {
            b.kind = if dynamic {
                BodyKind::Dynamic
            } else {
                BodyKind::Static
            };
        }
        Ok(())
    }

    /// Sets the selection's total mass (kg), shared equally by its bodies.
    pub fn set_mass(&mut self, kg: f64) -> Result<(), EditError> {
        if !kg.is_finite() || kg <= 0.0 || kg > 1e6 {
            return Err(EditError::Mass(kg));
        }
        self.editable()?;
        self.checkpoint();
        let kb = self.editable()?;
        let n = kb.bodies.len().max(1) as f64;
        for b in &mut kb.bodies {
            b.mass = Some(Mass {
                total: kg / n,
                distribution: "mimicgeom".into(),
                com: None,
                inertia: None,
                pos: b.pos,
            });
        }
        Ok(())
    }

    /// Sets the colour (RGB, 0..1) of every geometry of the selection.
    pub fn set_colour(&mut self, rgb: [f64; 3]) -> Result<(), EditError> {
        if rgb.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(EditError::Colour(rgb));
        }
        self.edit_geoms(|g| g.diffuse_color = Some(rgb))
    }

    /// Renames the selected object.
    pub fn rename(&mut self, name: &str) -> Result<(), EditError> {
        crate::compose::robot_builder::check_name(name, "object name").map_err(EditError::Name)?;
        self.editable()?;
        self.checkpoint();
        self.editable()?.name = Some(name.to_string());
        Ok(())
    }

    /// Deletes the selected object (the robot placeholder stays).
    pub fn delete(&mut self) -> Result<(), EditError> {
        match self.need_selection()? {
            Selected::Robot => Err(EditError::Robot(
                "the robot placeholder is obligatory: it sets the start pose",
            )),
            Selected::Object(i) => {
                self.checkpoint();
                self.objects.remove(i);
                self.selected = None;
                Ok(())
            }
        }
    }

    /// What the side panel shows for the selection.
    pub fn props(&self, s: Selected) -> Option<Props> {
        let pose = self.pose(s)?;
        let mut p = Props {
            name: "robot (start pose)".into(),
            position: pose.translation,
            yaw_deg: yaw_of(pose.rotation),
            size: [0.0; 3],
            friction: None,
            dynamic: false,
            mass: None,
            colour: None,
            editable: false,
            terrain: None,
        };
        if let Selected::Object(i) = s {
            p.size = self.bounds(i).size();
            let o = self.objects.get(i)?;
            p.name = object_name(o, i);
            if let EnvObject::Inline(kb) = o {
                p.editable = true;
                let geoms: Vec<_> = kb.bodies.iter().flat_map(|b| &b.geoms).collect();
                p.friction = geoms.first().and_then(|g| g.friction);
                p.colour = geoms.first().and_then(|g| g.diffuse_color);
                p.dynamic = kb.bodies.iter().any(|b| b.kind == BodyKind::Dynamic);
                let masses: Vec<f64> = kb
                    .bodies
                    .iter()
                    .filter_map(|b| b.mass.as_ref().map(|m| m.total))
                    .collect();
                p.mass = (!masses.is_empty()).then(|| masses.iter().sum());
            }
            if let EnvObject::Terrain(t) = o {
                p.terrain = Some(t.clone());
            }
        }
        Some(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn editor() -> EnvEditor {
        EnvEditor::new("configs/environments/_test.env.xml")
    }

    #[test]
    fn dropped_objects_land_on_the_ground_or_on_what_is_below() {
        let mut e = editor();
        let b = e.add(&LibraryItem::Box, 1.0, 1.0);
        // On the floor, whose top is at z = 0: the 0.2 m box's centre at 0.1.
        let z = e.pose(Selected::Object(b)).unwrap().translation[2];
        assert!((z - 0.1).abs() < 1e-9, "{z}");
        let s = e.add(&LibraryItem::Sphere, 1.05, 0.95);
        let z = e.pose(Selected::Object(s)).unwrap().translation[2];
        assert!((z - 0.3).abs() < 1e-9, "the sphere lands on the box: {z}");
        // Dragged off the box it comes down to the floor.
        e.drag_to(2.0, 2.0).unwrap();
        let z = e.pose(Selected::Object(s)).unwrap().translation[2];
        assert!((z - 0.1).abs() < 1e-9, "{z}");
    }

    #[test]
    fn an_object_on_the_robots_start_pose_is_a_warning() {
        let mut e = editor();
        let sim = crate::control::load_simulation("configs/demo.simulation.xml").unwrap();
        assert!(
            e.robot_overlaps(&sim.robot).is_empty(),
            "the floor only touches it"
        );
        e.add(&LibraryItem::Box, 0.0, 0.15);
        let w = e.robot_overlaps(&sim.robot);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("overlaps the robot's start pose"), "{w:?}");
        e.drag_to(1.0, 1.0).unwrap();
        assert!(e.robot_overlaps(&sim.robot).is_empty());
    }

    #[test]
    fn the_shipped_environments_leave_their_robots_room() {
        for config in [
            "configs/demo.simulation.xml",
            "configs/experiment2_sine_only.simulation.xml",
            "configs/snake16py_stairs.simulation.xml",
            "configs/snake8py_slope.simulation.xml",
            "configs/gait_from_scratch_slope.simulation.xml",
        ] {
            let sim = crate::control::load_simulation(config).unwrap();
            let env = sim.environment.file.clone().unwrap();
            let e = EnvEditor::load(&env).unwrap();
            let w = e.robot_overlaps(&sim.robot);
            assert!(w.is_empty(), "{config}: {w:?}");
        }
    }

    #[test]
    fn edits_undo_and_redo() {
        let mut e = editor();
        let i = e.add(&LibraryItem::Box, 0.0, 1.0);
        e.rotate_by(90.0).unwrap();
        e.scale([2.0, 1.0, 0.5]).unwrap();
        e.set_friction(0.9).unwrap();
        let p = e.props(Selected::Object(i)).unwrap();
        assert!((p.yaw_deg - 90.0).abs() < 1e-9);
        assert!((p.size[0] - 0.2).abs() < 1e-9 && (p.size[1] - 0.4).abs() < 1e-9);
        assert!((p.size[2] - 0.1).abs() < 1e-9);
        // The bottom stayed on the floor.
        assert!(e.bounds(i).min[2].abs() < 1e-9);
        assert_eq!(p.friction, Some(0.9));
        assert!(e.undo());
        assert_eq!(e.props(Selected::Object(i)).unwrap().friction, Some(0.5));
        assert!(e.undo() && e.undo());
        assert_eq!(e.props(Selected::Object(i)).unwrap().yaw_deg, 0.0);
        assert!(e.redo());
        assert!((e.props(Selected::Object(i)).unwrap().yaw_deg - 90.0).abs() < 1e-9);
        // A drag is one undo step.
        e.begin_drag();
        for k in 0..10 {
            e.drag_to(0.1 * k as f64, 1.0).unwrap();
        }
        e.end_drag();
        assert!(e.undo());
        assert!((e.pose(Selected::Object(i)).unwrap().translation[0]).abs() < 1e-9);
    }

    #[test]
    fn a_mesh_that_does_not_load_is_reported_not_dropped() {
        let dir = std::env::temp_dir().join(format!("proleg_env_mesh_{}", std::process::id()));
        let _ = std::fs::create_dir_all(&dir);
        std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
        let mut e = EnvEditor::new(dir.join("scene.env.xml"));
        e.add(&LibraryItem::Mesh("broken.obj".into()), 0.0, 1.0);
        e.add(&LibraryItem::Mesh("missing.obj".into()), 1.0, 1.0);
        let errors = e.mesh_errors();
        assert_eq!(errors.len(), 2, "{errors:?}");
        assert!(
            errors.iter().any(|e| matches!(e, MeshError::Load(c)
                if c.file.to_string_lossy().contains("broken.obj") && c.pos.line == 3)),
            "{errors:?}"
        );
        assert!(
            errors
                .iter()
                .any(|e| matches!(e, MeshError::NotFound { file, .. }
                if file == "missing.obj")),
            "{errors:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn bad_edits_are_refused_with_reasons() {
        let mut e = editor();
        assert!(matches!(
            e.move_by([1.0, 0.0, 0.0]),
            Err(EditError::NoSelection)
        ));
        e.select(Some(Selected::Robot)).unwrap();
        assert!(matches!(e.scale([2.0; 3]), Err(EditError::Robot(_))));
        let obligatory = e.delete().unwrap_err();
        assert!(matches!(obligatory, EditError::Robot(_)));
        assert!(obligatory.to_string().contains("obligatory"));
        e.select(Some(Selected::Object(0))).unwrap();
        let friction = e.set_friction(1.5).unwrap_err();
        assert!(matches!(friction, EditError::Friction(f) if f == 1.5));
        assert!(friction.to_string().contains("outside 0..1"));
        assert!(matches!(
            e.set_friction(f64::NAN),
            Err(EditError::Friction(_))
        ));
        assert!(matches!(e.set_mass(-1.0), Err(EditError::Mass(_))));
        assert!(matches!(e.scale([0.0, 1.0, 1.0]), Err(EditError::Scale(_))));
        assert!(matches!(
            e.select(Some(Selected::Object(9))),
            Err(EditError::NoObject { .. })
        ));
        assert!(!e.can_undo(), "refused edits leave no undo step");
    }

    #[test]
    fn a_dropped_terrain_takes_a_new_difficulty_and_seed_and_saves_as_a_terrain_element() {
        let dir = std::env::temp_dir().join(format!("proleg_env_terrain_{}", std::process::id()));
        let path = dir.join("scene.env.xml");
        let mut e = EnvEditor::new(&path);
        let i = e.add(&LibraryItem::Terrain(Family::Pegs), 0.0, 0.5);
        assert_eq!(e.selected, Some(Selected::Object(i)));
        let props = e.props(Selected::Object(i)).unwrap();
        let t = props.terrain.expect("a terrain's properties");
        assert_eq!((t.family, t.difficulty, t.seed), (Family::Pegs, 0.5, 1));
        assert_eq!(t.pose.translation, [0.0, 0.5, 0.0]);
        let medium = e.terrain(&t).bodies.len();
        assert!(e.bounds(i).size()[1] > 30.0, "the course runs 30 m ahead");
        e.set_terrain(0.9, 7).unwrap();
        let Some(EnvObject::Terrain(t)) = e.objects.get(i) else {
            panic!("still a terrain")
        };
        assert_eq!((t.difficulty, t.seed), (0.9, 7));
        let hard = e.terrain(t).bodies.len();
        assert!(hard > medium, "denser pegs: {hard} bodies against {medium}");
        assert!(matches!(e.set_terrain(1.5, 7), Err(EditError::Terrain(_))));
        assert!(matches!(
            e.set_terrain(f64::NAN, 7),
            Err(EditError::Terrain(_))
        ));
        e.save(&path).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.contains("<Terrain family=\"pegs\" difficulty=\"0.9\" seed=\"7\""),
            "{text}"
        );
        assert!(e.undo());
        let Some(EnvObject::Terrain(t)) = e.objects.get(i) else {
            panic!("still a terrain")
        };
        assert_eq!((t.difficulty, t.seed), (0.5, 1), "undone");
        e.select(Some(Selected::Object(0))).unwrap();
        assert!(matches!(e.set_terrain(0.2, 1), Err(EditError::NotTerrain)));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_terrain_whose_difficulty_is_dragged_leaves_one_course_in_the_mesh_cache() {
        let mut e = editor();
        let i = e.add(&LibraryItem::Terrain(Family::Hills), 0.0, 0.5);
        e.select(Some(Selected::Object(i))).unwrap();
        for k in 0..=10 {
            e.set_terrain(f64::from(k) / 10.0, 3).unwrap();
            let _ = e.bounds(i);
        }
        assert_eq!(
            e.meshes.generated_count(),
            1,
            "only the scene's course is held"
        );
        let Some(EnvObject::Terrain(t)) = e.objects.get(i) else {
            panic!("still a terrain")
        };
        assert!(e.mesh(&t.mesh_name()).is_some(), "and it is the one drawn");
        e.delete().unwrap();
        let j = e.add(&LibraryItem::Terrain(Family::Rough), 0.0, 0.5);
        let _ = e.bounds(j);
        assert_eq!(
            e.meshes.generated_count(),
            1,
            "a deleted terrain's course goes"
        );
    }

    #[test]
    fn saved_scene_loads_back_equal() {
        let dir = std::env::temp_dir().join(format!("proleg_env_edit_{}", std::process::id()));
        let path = dir.join("scene.env.xml");
        let mut e = EnvEditor::new(&path);
        e.add(&LibraryItem::Stairs, 0.0, 1.5);
        e.set_dynamic(false).unwrap();
        e.select(Some(Selected::Robot)).unwrap();
        e.move_to([0.0, 0.2, 0.0]).unwrap();
        e.rotate_by(30.0).unwrap();
        e.save(&path).unwrap();
        let back = EnvEditor::load(&path).unwrap();
        // Positions are written rounded to 0.1 mm: the scene read back writes the same file.
        let text = write_environment_file(&e.to_file());
        assert_eq!(write_environment_file(&back.to_file()), text);
        let pose = |f: &EnvironmentFile| f.robot_pose.unwrap_or_default();
        let (a, b) = (pose(&e.to_file()), pose(&back.to_file()));
        for (x, y) in a.translation.iter().zip(b.translation) {
            assert!((x - y).abs() <= 0.5e-4, "{a:?} vs {b:?}");
        }
        assert!(
            text.lines()
                .all(|l| !l.contains("00000000") && !l.contains("99999999")),
            "no float noise in the file:\n{text}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}

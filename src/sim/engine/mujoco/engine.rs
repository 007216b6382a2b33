//! [`MujocoEngine`]: a MuJoCo model and its data, built in memory from the simulation's
//! MJCF mapping (a virtual file system, no temporary file), stepped by `mj_step1`, the
//! servos' targets, `mj_step2` and then `mj_kinematics`, so that the next simulation step
//! senses the bodies where they are after the step (as on rapier), and the contacts found
//! at the step's start (as on rapier, whose narrow phase runs before it integrates).
//!
//! A servo is its hinge's friction loss of at most `maxtorque`
//! ([`super::mjcf::Servos::Velocity`]): between `mj_step1` (which builds the constraint
//! rows and their reference accelerations) and `mj_step2` (which solves them) the engine
//! moves each servo row's target speed from 0 to the servo stage's command, so the solver
//! gives the torque that reaches the command within the bound: like rapier's motor, a
//! velocity constraint with bounded force, solved implicitly, and no extra dof. Joint
//! limits are MuJoCo's own. A pad reads its link's contacts grouped by geometry pair (one
//! patch per pair, as rapier's manifolds), a laser casts `mj_ray` per beam.
//!
//! A static environment body is geoms of MuJoCo's world body ([`super::parts`]).
//!
//! Where MuJoCo differs from rapier here: dragging moves a robot by its root's free joint
//! (inner links follow their root) and a static body by its geoms' positions in the
//! world's own copy of the model, whose midphase is then off (MuJoCo's bounding-volume
//! tree of the world body was made when the model was compiled and would miss the moved
//! geoms; every geom of the world body is then tried against each link); an angular
//! or linear velocity is set on free bodies only; a laser in a batch of several robots also sees the
//! other robots (`mj_ray` has no collision groups); a body's linear velocity (the data
//! log's speed and kinetic energy) is MuJoCo's from the step's start, since
//! `mj_kinematics` updates positions only.

use std::ffi::{CString, c_char, c_int};
use std::sync::Arc;

use super::ffi::{
    mjData, mjModel, mjVFS, mjtConstraint_mjCNSTR_FRICTION_DOF, mjtDisableBit_mjDSBL_MIDPHASE,
    mjtGeom_mjGEOM_BOX, mjtGeom_mjGEOM_SPHERE, mjtObj_mjOBJ_BODY, mjtObj_mjOBJ_GEOM,
    mjtObj_mjOBJ_JOINT,
};
use super::library::{Library, library, take_error};
use super::mjcf::{
    MjcfOptions, Servos, env_body_name, link_body_name, mjcf, robot_prefix, static_geom_name,
};
use super::models::{MujocoModel, shared};
use super::parts::{Part, Parts, StaticPart};
use super::{MujocoError, MujocoSettings};
use crate::config::Simulation;
use crate::config::body::BodyKind;
use crate::config::simulation::EngineKind;
use crate::config::transform::Pose;
use crate::sim::engine::{
    BodyId, BodyState, ColliderView, ContactView, JointId, JointReading, LaserId, Layout, PadArea,
    PadId, PhysicsEngine, RobotLayout, SensorPart, ShapeOutline, sensor_parts, tangential_speed,
};
use crate::sim::error::SimError;

/// The name the model's document has in the virtual file system.
const MODEL_NAME: &str = "proleg-model.xml";

/// A hinge: where its angle and speed are, and its servo: the commanded speed and the
/// constraint row of its friction loss in this step (none when its torque limit is 0).
#[derive(Debug, Clone, Copy)]
struct Hinge {
    qpos: usize,
    dof: usize,
    /// rad/s.
    command: f64,
    row: Option<usize>,
}

/// No hinge on this dof (in [`MujocoEngine::dof_hinge`]).
const NO_HINGE: u32 = u32::MAX;

/// A pad: its link's MuJoCo body and the map from the link's frame to the pad's.
#[derive(Debug, Clone, Copy)]
struct Pad {
    body: c_int,
    from_link: Pose,
    area: PadArea,
}

/// A laser: its link's body, its pose there, beam directions in its frame and range.
#[derive(Debug, Clone)]
struct Laser {
    body: c_int,
    pose: Pose,
    directions: Vec<[f64; 3]>,
    max_range: f64,
}

/// A MuJoCo world.
pub struct MujocoEngine {
    lib: &'static Library,
    /// Shared with the other worlds of the same document ([`super::models`]).
    model: Arc<MujocoModel>,
    data: *mut mjData,
    settings: MujocoSettings,
    /// Our bodies: MuJoCo's bodies and the static ones of its world body.
    parts: Parts,
    hinges: Vec<Hinge>,
    /// The hinge of each MuJoCo dof, or [`NO_HINGE`].
    dof_hinge: Vec<u32>,
    pads: Vec<Pad>,
    lasers: Vec<Laser>,
    /// Whether a MuJoCo body carries a pad (indexed by MuJoCo's body id).
    pad_bodies: Vec<bool>,
    /// This step's contact patches on pad links, indexed once per step (not per pad).
    patches: Vec<Patch>,
}

/// The contacts of one geom pair (MuJoCo lists them one after another) on a pad's link.
#[derive(Debug, Clone, Copy)]
struct Patch {
    /// The pad link's MuJoCo body.
    body: c_int,
    /// The contacts `start..end` of `mjData::contact`.
    start: usize,
    end: usize,
    /// +1 when the link's geom is `geom2` (MuJoCo's normal points into it), else -1.
    sign: f64,
}

// SAFETY: the model and data are plain memory owned by this value; MuJoCo keeps no
// thread-affine state in them, and every access goes through `&self` / `&mut self`.
unsafe impl Send for MujocoEngine {}
// SAFETY: `&self` methods only read the model and data (mj_ray, mj_objectVelocity take
// them as const).
unsafe impl Sync for MujocoEngine {}

impl Drop for MujocoEngine {
    fn drop(&mut self) {
        // SAFETY: made by MuJoCo in `build` and freed once, here (the model frees itself
        // with its last world).
        unsafe { self.lib.api.mj_deleteData(self.data) };
    }
}

/// `n` numbers at `ptr[at..]`.
///
/// # Safety
/// `ptr` must point to an array MuJoCo sized to hold `at + N` values.
unsafe fn read<const N: usize>(ptr: *const f64, at: usize) -> [f64; N] {
    // SAFETY: guaranteed by the caller.
    std::array::from_fn(|i| unsafe { *ptr.add(at + i) })
}

impl MujocoEngine {
    /// `sim`'s world with `robots` copies of the robot, integrated with `settings`.
    pub fn build(
        sim: &Simulation,
        robots: usize,
        settings: MujocoSettings,
    ) -> Result<(MujocoEngine, Layout), SimError> {
        let lib = library()?;
        // An error left on this thread by another world is not this one's.
        take_error();
        let doc = mjcf(
            sim,
            &MjcfOptions {
                robots,
                servos: Servos::Velocity,
                settings,
            },
        )?;
        let model = shared(&doc.xml, || {
            load_model(lib, &doc.xml, sim).map(|m| MujocoModel::new(lib, m))
        })?;
        // SAFETY: `model` is a valid compiled model.
        let data = unsafe { lib.api.mj_makeData(model.ptr()) };
        if data.is_null() {
            return Err(rejected(sim, "mj_makeData failed".into()).into());
        }
        let mut engine = MujocoEngine {
            lib,
            model,
            data,
            settings,
            parts: Parts::default(),
            hinges: Vec::new(),
            dof_hinge: Vec::new(),
            pads: Vec::new(),
            lasers: Vec::new(),
            pad_bodies: Vec::new(),
            patches: Vec::new(),
        };
        let layout = engine.layout(sim, robots)?;
        let m = engine.m();
        let geom_body: Vec<c_int> = (0..m.ngeom.max(0) as usize)
            // SAFETY: `g < ngeom`.
            .map(|g| unsafe { *m.geom_bodyid.add(g) })
            .collect();
        let nbody = m.nbody.max(0) as usize;
        engine.parts.index_geoms(&geom_body, nbody);
        // SAFETY: nv is the model's dof count.
        engine.dof_hinge = vec![NO_HINGE; unsafe { (*engine.mp()).nv } as usize];
        for (k, h) in engine.hinges.iter().enumerate() {
            engine.dof_hinge[h.dof] = k as u32;
        }
        // SAFETY: nbody is the model's body count.
        engine.pad_bodies = vec![false; unsafe { (*engine.mp()).nbody } as usize];
        for pad in &engine.pads {
            engine.pad_bodies[pad.body as usize] = true;
        }
        // SAFETY: valid model and data; computes the positions, contacts and centres of
        // mass of the start pose.
        unsafe { lib.api.mj_forward(engine.mp(), engine.data) };
        if let Some(e) = take_error() {
            return Err(MujocoError::Library(e).into());
        }
        engine.index_patches();
        engine.target_servos();
        Ok((engine, layout))
    }

    fn m(&self) -> &mjModel {
        // SAFETY: valid for the engine's life.
        unsafe { &*self.model.ptr() }
    }

    /// The model for MuJoCo's calls.
    fn mp(&self) -> *mut mjModel {
        self.model.ptr()
    }

    /// The model, to change: first a copy of its own when other worlds share it (or may
    /// share it later); `None` when MuJoCo could not allocate the copy.
    fn own_model(&mut self) -> Option<*mut mjModel> {
        if Arc::get_mut(&mut self.model).is_none() {
            self.model = Arc::new(self.model.copy()?);
        }
        Some(self.model.ptr())
    }

    fn d(&self) -> &mjData {
        // SAFETY: valid for the engine's life.
        unsafe { &*self.data }
    }

    fn id(&self, kind: u32, name: &str, sim: &Simulation) -> Result<c_int, SimError> {
        let c = CString::new(name).map_err(|_| rejected(sim, format!("name {name:?}")))?;
        // SAFETY: valid model, NUL-terminated name.
        let id = unsafe {
            self.lib
                .api
                .mj_name2id(self.mp(), kind as c_int, c.as_ptr())
        };
        if id < 0 {
            return Err(rejected(sim, format!("no object named {name} in the model")).into());
        }
        Ok(id)
    }

    /// Our ids of the environment and of each robot's parts, by name.
    fn layout(&mut self, sim: &Simulation, robots: usize) -> Result<Layout, SimError> {
        let mut layout = Layout::default();
        for (i, b) in sim.environment.bodies.iter().enumerate() {
            let name = env_body_name(sim, i);
            let body = if b.kind == BodyKind::Static {
                let geoms = (0..b.geoms.len())
                    .map(|k| {
                        let g = self.id(mjtObj_mjOBJ_GEOM, &static_geom_name(&name, k), sim)?;
                        Ok(g as usize)
                    })
                    .collect::<Result<Vec<_>, SimError>>()?;
                self.parts.add_static(StaticPart::new(b, geoms))
            } else {
                let id = self.id(mjtObj_mjOBJ_BODY, &name, sim)?;
                self.parts.add_body(id)
            };
            layout.environment.push(body);
        }
        let parts = sensor_parts(sim);
        for r in 0..robots {
            let prefix = robot_prefix(robots, r);
            let mut robot = RobotLayout::default();
            for l in &sim.robot.links {
                let id = self.id(mjtObj_mjOBJ_BODY, &link_body_name(&prefix, &l.name), sim)?;
                let body = self.parts.add_body(id);
                robot.links.push((body, l.mass));
            }
            for j in &sim.robot.joints {
                let name = format!("{prefix}{}", j.name);
                let id = self.id(mjtObj_mjOBJ_JOINT, &name, sim)?;
                let m = self.m();
                // SAFETY: a joint of the model, the arrays have `njnt` entries.
                let (qpos, dof) = unsafe {
                    (
                        *m.jnt_qposadr.add(id as usize) as usize,
                        *m.jnt_dofadr.add(id as usize) as usize,
                    )
                };
                self.hinges.push(Hinge {
                    qpos,
                    dof,
                    command: 0.0,
                    row: None,
                });
                robot.joints.push(JointId(self.hinges.len() as u32 - 1));
            }
            for part in &parts {
                self.add_sensor(sim, part, r, &mut robot)?;
            }
            layout.robots.push(robot);
        }
        Ok(layout)
    }

    /// The MuJoCo body of link `link` of a robot laid out in `layout`.
    fn link_body(
        &self,
        sim: &Simulation,
        layout: &RobotLayout,
        link: usize,
    ) -> Result<c_int, SimError> {
        layout
            .links
            .get(link)
            .and_then(|(b, _)| self.parts.mj_body(*b))
            .ok_or_else(|| rejected(sim, format!("no body for link {link}")).into())
    }

    fn add_sensor(
        &mut self,
        sim: &Simulation,
        part: &SensorPart,
        _robot: usize,
        layout: &mut RobotLayout,
    ) -> Result<(), SimError> {
        match part {
            SensorPart::Pad { name, link, area } => {
                let body = self.link_body(sim, layout, *link)?;
                let pad = Pad {
                    body,
                    from_link: area.pose.inverse(),
                    area: *area,
                };
                if !self.pad_on_link(&pad) {
                    return Err(SimError::PadOffLink {
                        sensor: name.clone(),
                        link: sim.robot.links[*link].name.clone(),
                    });
                }
                self.pads.push(pad);
                layout.pads.push(PadId(self.pads.len() as u32 - 1));
            }
            SensorPart::Laser {
                link,
                pose,
                angles,
                max_range,
            } => {
                let body = self.link_body(sim, layout, *link)?;
                self.lasers.push(Laser {
                    body,
                    pose: *pose,
                    directions: angles
                        .iter()
                        .map(|a| crate::sim::engine::LaserSpec::direction(*a))
                        .collect(),
                    max_range: *max_range,
                });
                layout.lasers.push(LaserId(self.lasers.len() as u32 - 1));
            }
        }
        Ok(())
    }

    /// Whether the pad's box overlaps the bounding box of one of its link's geoms.
    fn pad_on_link(&self, pad: &Pad) -> bool {
        let m = self.m();
        (0..m.ngeom as usize).any(|g| {
            // SAFETY: `g < ngeom`; geom_pos 3, geom_quat 4, geom_aabb 6 values per geom.
            let (body, pos, quat, aabb) = unsafe {
                (
                    *m.geom_bodyid.add(g),
                    read::<3>(m.geom_pos, 3 * g),
                    read::<4>(m.geom_quat, 4 * g),
                    read::<6>(m.geom_aabb, 6 * g),
                )
            };
            if body != pad.body {
                return false;
            }
            let to_pad = pad.from_link.mul(&Pose {
                translation: pos,
                rotation: quat,
            });
            let corners = (0..8).map(|c| {
                let corner = std::array::from_fn(|i| {
                    let sign = if c >> i & 1 == 1 { 1.0 } else { -1.0 };
                    aabb[i] + sign * aabb[3 + i]
                });
                to_pad.transform_point(corner)
            });
            pad.area.touched_by(corners)
        })
    }

    /// Body `id`'s frame in the world.
    fn body_pose(&self, id: c_int) -> Pose {
        let d = self.d();
        // SAFETY: `id < nbody`; xpos 3, xquat 4 values per body.
        unsafe {
            Pose {
                translation: read::<3>(d.xpos, 3 * id as usize),
                rotation: read::<4>(d.xquat, 4 * id as usize),
            }
        }
    }

    /// The address of body `id`'s free joint in `qpos` and `qvel`, if it has one.
    fn free_joint(&self, id: c_int) -> Option<(usize, usize)> {
        let m = self.m();
        // SAFETY: `id < nbody`; a body's joints are `jntnum` joints from `jntadr`.
        unsafe {
            let (n, adr) = (
                *m.body_jntnum.add(id as usize),
                *m.body_jntadr.add(id as usize),
            );
            (n == 1 && *m.jnt_type.add(adr as usize) == 0).then(|| {
                (
                    *m.jnt_qposadr.add(adr as usize) as usize,
                    *m.jnt_dofadr.add(adr as usize) as usize,
                )
            })
        }
    }

    /// Recomputes positions and contacts after a change between steps.
    fn refresh(&mut self) {
        // SAFETY: valid model and data.
        unsafe { self.lib.api.mj_forward(self.mp(), self.data) };
        self.index_patches();
    }

    /// Each servo's friction-loss row (MuJoCo's rows: equality, then friction, ...) aims
    /// at its command instead of 0: the reference acceleration `-B v` becomes
    /// `-B (v - command)`. Called after `mj_step1` made the rows; remembers them for the
    /// torque readings.
    fn target_servos(&mut self) {
        // SAFETY: valid data; rows `ne..ne + nf` exist, `efc_KBIP` holds 4 values per row.
        let d = unsafe { &*self.data };
        let friction = d.ne.max(0) as usize..(d.ne.max(0) + d.nf.max(0)) as usize;
        for h in &mut self.hinges {
            h.row = None;
        }
        for r in friction {
            // SAFETY: `r < nefc`.
            let (kind, dof) = unsafe { (*d.efc_type.add(r), *d.efc_id.add(r)) };
            if kind != mjtConstraint_mjCNSTR_FRICTION_DOF as c_int {
                continue;
            }
            let k = self
                .dof_hinge
                .get(dof as usize)
                .copied()
                .unwrap_or(NO_HINGE);
            let Some(h) = self.hinges.get_mut(k as usize) else {
                continue;
            };
            h.row = Some(r);
            // SAFETY: as above.
            unsafe { *d.efc_aref.add(r) += *d.efc_KBIP.add(4 * r + 1) * h.command };
        }
    }

    /// Finds this step's contact patches on pad links: one pass over the contacts, into a
    /// buffer kept from step to step (no allocation once it is large enough).
    fn index_patches(&mut self) {
        self.patches.clear();
        if self.pads.is_empty() {
            return;
        }
        // SAFETY: valid for the engine's life; read only here, while `patches` is written.
        let (m, d) = unsafe { (&*self.mp(), &*self.data) };
        let n = d.ncon.max(0) as usize;
        let mut i = 0;
        while i < n {
            // SAFETY: `i < ncon`; contacts of one geom pair are consecutive.
            let pair = unsafe { ((*d.contact.add(i)).geom1, (*d.contact.add(i)).geom2) };
            let mut end = i + 1;
            // SAFETY: as above.
            while end < n
                && unsafe { ((*d.contact.add(end)).geom1, (*d.contact.add(end)).geom2) } == pair
            {
                end += 1;
            }
            // SAFETY: geom ids of a contact are below ngeom.
            let bodies = unsafe {
                [
                    *m.geom_bodyid.add(pair.0 as usize),
                    *m.geom_bodyid.add(pair.1 as usize),
                ]
            };
            for (body, sign) in bodies.into_iter().zip([-1.0, 1.0]) {
                if self.pad_bodies.get(body as usize).copied().unwrap_or(false) {
                    self.patches.push(Patch {
                        body,
                        start: i,
                        end,
                        sign,
                    });
                }
            }
            i = end;
        }
    }
}

/// Compiles the MJCF document from memory.
fn load_model(lib: &Library, xml: &str, sim: &Simulation) -> Result<*mut mjModel, SimError> {
    let mut vfs = mjVFS {
        impl_: std::ptr::null_mut(),
    };
    let name = CString::new(MODEL_NAME).map_err(|_| rejected(sim, "model name".into()))?;
    let mut error = [0 as c_char; 1000];
    // SAFETY: the VFS is initialised before use and deleted after; the buffer is copied
    // by mj_addBufferVFS; `error` holds `error.len()` bytes.
    let model = unsafe {
        lib.api.mj_defaultVFS(&mut vfs);
        let added = lib.api.mj_addBufferVFS(
            &mut vfs,
            name.as_ptr(),
            xml.as_ptr().cast(),
            xml.len() as c_int,
        );
        let model = if added == 0 {
            lib.api.mj_loadXML(
                name.as_ptr(),
                &vfs,
                error.as_mut_ptr(),
                error.len() as c_int,
            )
        } else {
            std::ptr::null_mut()
        };
        lib.api.mj_deleteVFS(&mut vfs);
        model
    };
    if model.is_null() {
        // SAFETY: MuJoCo writes a NUL-terminated message into `error`.
        let text = unsafe { std::ffi::CStr::from_ptr(error.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        let cause = match take_error() {
            Some(e) => format!("{text} {e}"),
            None => text,
        };
        return Err(rejected(sim, cause.trim().to_string()).into());
    }
    Ok(model)
}

/// Loads the MJCF file `path` in MuJoCo as MuJoCo's own tools would (its meshes relative
/// to it) and frees the model: `Ok` when MuJoCo accepts it, else MuJoCo's message.
pub fn check_mjcf_file(path: &std::path::Path) -> Result<(), MujocoError> {
    let lib = super::library::library()?;
    let refused = |cause: String| MujocoError::Rejected {
        file: path.display().to_string(),
        cause: cause.split_whitespace().collect::<Vec<_>>().join(" "),
    };
    let name = CString::new(path.as_os_str().as_encoded_bytes())
        .map_err(|_| refused("the path holds a NUL byte".into()))?;
    let mut error = [0 as c_char; 1000];
    // SAFETY: `name` is NUL-terminated, no VFS is used, `error` holds `error.len()` bytes;
    // the model is freed at once.
    let model = unsafe {
        let model = lib.api.mj_loadXML(
            name.as_ptr(),
            std::ptr::null(),
            error.as_mut_ptr(),
            error.len() as c_int,
        );
        if !model.is_null() {
            lib.api.mj_deleteModel(model);
        }
        model
    };
    if model.is_null() {
        // SAFETY: MuJoCo writes a NUL-terminated message into `error`.
        let text = unsafe { std::ffi::CStr::from_ptr(error.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        return Err(refused(match take_error() {
            Some(e) => format!("{text} {e}"),
            None => text,
        }));
    }
    Ok(())
}

/// MuJoCo refused `sim`'s model; its message (which may span lines) on one line.
fn rejected(sim: &Simulation, cause: String) -> MujocoError {
    MujocoError::Rejected {
        file: sim.file.display().to_string(),
        cause: cause.split_whitespace().collect::<Vec<_>>().join(" "),
    }
}

impl PhysicsEngine for MujocoEngine {
    fn kind(&self) -> EngineKind {
        EngineKind::Mujoco
    }

    fn gravity(&self) -> [f64; 3] {
        self.m().opt.gravity
    }

    fn settings(&self) -> String {
        self.settings.to_string()
    }

    fn step(&mut self) {
        // SAFETY (all three): valid model and data; between the two halves of the step the
        // user may change the constraints' reference accelerations (MuJoCo solves them in
        // `mj_step2`).
        for _ in 0..self.settings.steps_per_step.max(1) {
            unsafe { self.lib.api.mj_step1(self.mp(), self.data) };
            self.target_servos();
            unsafe { self.lib.api.mj_step2(self.mp(), self.data) };
        }
        unsafe { self.lib.api.mj_kinematics(self.mp(), self.data) };
        self.index_patches();
    }

    fn joint(&self, j: JointId) -> JointReading {
        let Some(h) = self.hinges.get(j.0 as usize) else {
            return JointReading::default();
        };
        let d = self.d();
        // SAFETY: the addresses came from the model, the row from this step's rows. The
        // friction row's Jacobian is 1 on the hinge's dof: its force is the servo's torque.
        unsafe {
            JointReading {
                angle: (*d.qpos.add(h.qpos)).to_degrees(),
                velocity: (*d.qvel.add(h.dof)).to_degrees(),
                torque: h.row.map_or(0.0, |r| *d.efc_force.add(r)),
            }
        }
    }

    fn drive_joint(&mut self, j: JointId, velocity: f64, _now: &JointReading) {
        // The servo's row aims at the command from this step on (as rapier's motor sees
        // its target).
        if let Some(h) = self.hinges.get_mut(j.0 as usize) {
            h.command = velocity.to_radians();
        }
    }

    fn body_com(&self, b: BodyId) -> [f64; 3] {
        match self.parts.get(b) {
            // SAFETY: `id < nbody`; xipos has 3 values per body.
            Some(Part::Body(id)) => unsafe { read::<3>(self.d().xipos, 3 * id as usize) },
            Some(Part::Static(s)) => self.parts.statics[s].com,
            None => [0.0; 3],
        }
    }

    fn body(&self, b: BodyId) -> Option<BodyState> {
        let id = match self.parts.get(b)? {
            Part::Body(id) => id,
            Part::Static(s) => {
                // Geoms of the world body: no mass, no motion.
                let part = &self.parts.statics[s];
                return Some(BodyState {
                    pose: part.pose,
                    com: part.com,
                    linvel: [0.0; 3],
                    mass: 0.0,
                    inertia: [0.0; 3],
                    dynamic: false,
                });
            }
        };
        let m = self.m();
        let mut velocity = [0.0; 6];
        // SAFETY: `id < nbody`; `velocity` holds the 6 values mj_objectVelocity writes.
        let (mass, inertia, weld) = unsafe {
            self.lib.api.mj_objectVelocity(
                self.mp(),
                self.data,
                mjtObj_mjOBJ_BODY as c_int,
                id,
                velocity.as_mut_ptr(),
                0,
            );
            (
                *m.body_mass.add(id as usize),
                read::<3>(m.body_inertia, 3 * id as usize),
                *m.body_weldid.add(id as usize),
            )
        };
        Some(BodyState {
            pose: self.body_pose(id),
            com: self.body_com(b),
            linvel: [velocity[3], velocity[4], velocity[5]],
            mass,
            inertia,
            dynamic: weld != 0,
        })
    }

    fn pad_contact(&self, p: PadId) -> (bool, [f64; 3]) {
        let Some(pad) = self.pads.get(p.0 as usize) else {
            return (false, [0.0; 3]);
        };
        let d = self.d();
        let to_pad = pad.from_link.mul(&self.body_pose(pad.body).inverse());
        let (mut touching, mut normal) = (false, [0.0; 3]);
        for patch in self.patches.iter().filter(|q| q.body == pad.body) {
            // SAFETY: the patch's contacts were indexed from this step's list.
            let contact = |k: usize| unsafe { &*d.contact.add(k) };
            let points = (patch.start..patch.end).map(|k| to_pad.transform_point(contact(k).pos));
            if pad.area.touched_by(points) {
                touching = true;
                let frame = &contact(patch.start).frame;
                for (n, f) in normal.iter_mut().zip(&frame[..3]) {
                    *n += patch.sign * f;
                }
            }
        }
        let len = normal.iter().map(|v| v * v).sum::<f64>().sqrt();
        if len > 0.0 {
            normal = normal.map(|v| v / len);
        }
        (touching, normal)
    }

    fn scan(&self, l: LaserId, ranges: &mut [f64]) {
        let Some(laser) = self.lasers.get(l.0 as usize) else {
            return;
        };
        let at = self.body_pose(laser.body).mul(&laser.pose);
        let mut geom: c_int = -1;
        for (range, local) in ranges.iter_mut().zip(&laser.directions) {
            let dir = at.rotate(*local);
            // SAFETY: valid model and data; `at.translation` and `dir` hold 3 values,
            // `geom` one; no normal is asked for.
            let hit = unsafe {
                self.lib.api.mj_ray(
                    self.mp(),
                    self.data,
                    at.translation.as_ptr(),
                    dir.as_ptr(),
                    std::ptr::null(),
                    true,
                    laser.body,
                    &mut geom,
                    std::ptr::null_mut(),
                )
            };
            *range = if hit >= 0.0 && hit < laser.max_range {
                hit
            } else {
                laser.max_range
            };
        }
    }

    fn height_below(&self, x: f64, y: f64) -> Option<f64> {
        let from = crate::sim::engine::PROBE_FROM;
        let (at, down) = ([x, y, from], [0.0, 0.0, -1.0]);
        let mut geom: c_int = -1;
        // SAFETY: valid model and data; `at` and `down` hold 3 values, `geom` one; no body
        // is excluded (-1), no normal is asked for.
        let hit = unsafe {
            self.lib.api.mj_ray(
                self.mp(),
                self.data,
                at.as_ptr(),
                down.as_ptr(),
                std::ptr::null(),
                true,
                -1,
                &mut geom,
                std::ptr::null_mut(),
            )
        };
        (hit >= 0.0).then_some(from - hit)
    }

    fn translate_body(&mut self, b: BodyId, delta: [f64; 3]) {
        match self.parts.get(b) {
            Some(Part::Body(id)) => {
                let Some((qpos, _)) = self.free_joint(id) else {
                    return;
                };
                let q = self.d().qpos;
                for (k, dk) in delta.iter().enumerate() {
                    // SAFETY: a free joint's position is 3 values from `qpos`.
                    unsafe { *q.add(qpos + k) += dk };
                }
            }
            Some(Part::Static(s)) => {
                // Out of memory for a copy of the shared model: the body stays where it is.
                let Some(model) = self.own_model() else {
                    return;
                };
                let part = &mut self.parts.statics[s];
                // SAFETY: this world's own model; the part's geoms are below ngeom and
                // geom_pos holds 3 values each.
                unsafe {
                    for &g in &part.geoms {
                        for (k, dk) in delta.iter().enumerate() {
                            *(*model).geom_pos.add(3 * g + k) += dk;
                        }
                    }
                    (*model).opt.disableflags |= mjtDisableBit_mjDSBL_MIDPHASE as c_int;
                }
                part.translate(delta);
            }
            None => return,
        }
        self.refresh();
    }

    fn set_angular_velocity(&mut self, b: BodyId, angvel: [f64; 3]) {
        let Some(id) = self.parts.mj_body(b) else {
            return;
        };
        let Some((_, dof)) = self.free_joint(id) else {
            return;
        };
        // A free joint's angular velocity is in the body's frame.
        let local = self.body_pose(id).inverse().rotate(angvel);
        let v = self.d().qvel;
        for (k, w) in local.iter().enumerate() {
            // SAFETY: a free joint has 6 dofs from `dof`.
            unsafe { *v.add(dof + 3 + k) = *w };
        }
        self.refresh();
    }

    fn set_linear_velocity(&mut self, b: BodyId, linvel: [f64; 3]) {
        let Some(id) = self.parts.mj_body(b) else {
            return;
        };
        let Some((_, dof)) = self.free_joint(id) else {
            return;
        };
        // A free joint's linear velocity is in the world frame.
        let v = self.d().qvel;
        for (k, x) in linvel.iter().enumerate() {
            // SAFETY: a free joint has 6 dofs from `dof`.
            unsafe { *v.add(dof + k) = *x };
        }
        self.refresh();
    }

    fn colliders(&self) -> Vec<ColliderView> {
        let (m, d) = (self.m(), self.d());
        (0..m.ngeom as usize)
            .map(|g| {
                // SAFETY: `g < ngeom`; the arrays hold their per-geom values.
                let (kind, size, pos, mat, aabb, body) = unsafe {
                    (
                        *m.geom_type.add(g) as u32,
                        read::<3>(m.geom_size, 3 * g),
                        read::<3>(d.geom_xpos, 3 * g),
                        read::<9>(d.geom_xmat, 9 * g),
                        read::<6>(m.geom_aabb, 6 * g),
                        *m.geom_bodyid.add(g),
                    )
                };
                let mut quat = [1.0, 0.0, 0.0, 0.0];
                // SAFETY: 4 and 9 values.
                unsafe { self.lib.api.mju_mat2Quat(quat.as_mut_ptr(), mat.as_ptr()) };
                let pose = Pose {
                    translation: pos,
                    rotation: quat,
                };
                let shape = match kind {
                    k if k == mjtGeom_mjGEOM_BOX => ShapeOutline::Box(size),
                    k if k == mjtGeom_mjGEOM_SPHERE => ShapeOutline::Sphere(size[0]),
                    _ => world_bounds(&pose, &aabb),
                };
                // SAFETY: `body < nbody`.
                let dynamic = unsafe { *m.body_weldid.add(body as usize) } != 0;
                ColliderView {
                    pose,
                    shape,
                    dynamic,
                }
            })
            .collect()
    }

    fn contacts(&self) -> Vec<ContactView> {
        let (m, d) = (self.m(), self.d());
        let body_of = |geom: c_int| -> c_int {
            if geom < 0 || i64::from(geom) >= m.ngeom {
                return 0;
            }
            // SAFETY: `geom < ngeom`.
            unsafe { *m.geom_bodyid.add(geom as usize) }
        };
        (0..d.ncon.max(0) as usize)
            .map(|i| {
                // SAFETY: `i < ncon`.
                let c = unsafe { &*d.contact.add(i) };
                let normal = [c.frame[0], c.frame[1], c.frame[2]];
                let bodies = [body_of(c.geom[0]), body_of(c.geom[1])];
                let v = [
                    self.point_velocity(bodies[0], c.pos),
                    self.point_velocity(bodies[1], c.pos),
                ];
                let relative = std::array::from_fn(|k| v[0][k] - v[1][k]);
                ContactView {
                    point: c.pos,
                    normal,
                    touching: c.dist <= 0.0,
                    depth: (-c.dist).max(0.0),
                    bodies: c.geom.map(|g| self.parts.owner(g)),
                    slip: tangential_speed(relative, normal),
                }
            })
            .collect()
    }
}

impl MujocoEngine {
    /// Velocity (world, m/s) of body `body`'s material point at `point` (the world body's
    /// is zero).
    fn point_velocity(&self, body: c_int, point: [f64; 3]) -> [f64; 3] {
        if body <= 0 || i64::from(body) >= self.m().nbody {
            return [0.0; 3];
        }
        let mut v = [0.0f64; 6];
        // SAFETY: valid model and data, `body < nbody`, `v` holds 6 numbers.
        unsafe {
            self.lib.api.mj_objectVelocity(
                self.mp(),
                self.data,
                mjtObj_mjOBJ_BODY as c_int,
                body,
                v.as_mut_ptr(),
                0,
            )
        };
        // SAFETY: `body < nbody`; xpos holds 3 numbers per body.
        let origin: [f64; 3] =
            std::array::from_fn(|k| unsafe { *self.d().xpos.add(3 * body as usize + k) });
        let r = std::array::from_fn::<f64, 3, _>(|k| point[k] - origin[k]);
        let (w, lin) = ([v[0], v[1], v[2]], [v[3], v[4], v[5]]);
        [
            lin[0] + w[1] * r[2] - w[2] * r[1],
            lin[1] + w[2] * r[0] - w[0] * r[2],
            lin[2] + w[0] * r[1] - w[1] * r[0],
        ]
    }
}

/// The world-space bounding box of a geom's local box (`aabb`: centre, half sizes).
fn world_bounds(pose: &Pose, aabb: &[f64; 6]) -> ShapeOutline {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for c in 0..8 {
        let corner = std::array::from_fn(|i| {
            let sign = if c >> i & 1 == 1 { 1.0 } else { -1.0 };
            aabb[i] + sign * aabb[3 + i]
        });
        let p = pose.transform_point(corner);
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    ShapeOutline::Bounds(lo, hi)
}

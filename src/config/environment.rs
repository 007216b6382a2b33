//! Environment files (`*.env.xml`, thesis listing B.6): physics properties, static and
//! dynamic objects, procedural courses (`<Terrain>`, [`crate::config::terrain`]), and the
//! robot's start pose.
//!
//! The thesis stores the robot pose as a trailing comment `<!--Pose: ,w x y z,x y z,-->`
//! (OpenRAVE's transform order: rotation quaternion, then translation). We read it, and
//! write an explicit `<RobotPose>` element as well as the comment; when both are present
//! the element wins.

use crate::config::body::MAX_FRICTION;
use crate::config::contact::{ContactModel, read_contact, write_contact};
use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::kinbody::{Include, KinBody};
use crate::config::terrain::TerrainSpec;
use crate::config::transform::{POSE_ELEMENTS, Pose};
use crate::config::xml::dom::Element;
use crate::config::xml::read::{Reader, read_document};
use crate::config::xml::write::{XmlWriter, nums};

/// Physics engine properties.
#[derive(Debug, Clone, PartialEq)]
pub struct Physics {
    /// The engine named in the file (`ode` in the thesis); proleg simulates with rapier.
    pub engine: String,
    /// m/s², z up.
    pub gravity: [f64; 3],
    /// Whether non-neighbouring links of the robot collide with each other.
    pub self_collision: bool,
    /// Friction of geometries that name none.
    pub default_friction: Option<f64>,
    /// The contact model (`<contact>`, our extension), when the file states one; else
    /// [`ContactModel::default`].
    pub contact: Option<ContactModel>,
    /// How the robot's joints are represented (`<articulation>`, our extension).
    pub articulation: Articulation,
}

/// How an engine represents the robot's joints (`<articulation>maximal|reduced</articulation>`
/// in `<odeproperties>`, our extension).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Articulation {
    /// Every link a rigid body of its own, the hinges constraints between them (rapier's
    /// impulse joints): the default, the one rapier's production settings were measured with
    /// (docs/architecture.md, "Two engines behind one interface"). MuJoCo has no such joints: it simulates every robot as
    /// `reduced`.
    #[default]
    Maximal,
    /// The joint angles as coordinates (rapier's multibody joints, MuJoCo's only kind): what
    /// `proleg import` chooses for a robot whose light links under strong servos shake
    /// apart as maximal-coordinate joints.
    Reduced,
}

impl Articulation {
    /// The name files use.
    pub fn name(self) -> &'static str {
        match self {
            Articulation::Maximal => "maximal",
            Articulation::Reduced => "reduced",
        }
    }
}

impl Physics {
    /// The contact model in force: the file's, or the default.
    pub fn contact_model(&self) -> ContactModel {
        self.contact.unwrap_or_default()
    }
}

impl Default for Physics {
    fn default() -> Self {
        Physics {
            engine: "ode".into(),
            gravity: [0.0, 0.0, -9.81],
            self_collision: false,
            default_friction: None,
            contact: None,
            articulation: Articulation::default(),
        }
    }
}

/// An object of the environment: inline, or a kinbody file placed by a pose.
#[derive(Debug, Clone, PartialEq)]
pub enum EnvObject {
    /// A kinbody written in the environment file.
    Inline(KinBody),
    /// A kinbody file included with a pose.
    Include(Include),
    /// A procedural course (`<Terrain>`), generated when the file is resolved.
    Terrain(TerrainSpec),
}

/// An environment file as written.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvironmentFile {
    /// Gravity, self-collision, default friction.
    pub physics: Physics,
    /// The objects, in file order.
    pub objects: Vec<EnvObject>,
    /// The robot's start pose (world frame); identity when absent.
    pub robot_pose: Option<Pose>,
}

fn read_physics(r: &Reader, el: &Element) -> ConfigResult<Physics> {
    r.only_children(el, &["odeproperties", "properties"])?;
    r.only_attrs(el, &["type"])?;
    let mut p = Physics {
        engine: el
            .attr("type")
            .map(|a| a.value.clone())
            .unwrap_or_else(|| "ode".into()),
        ..Physics::default()
    };
    for props in &el.children {
        r.only_children(
            props,
            &[
                "gravity",
                "selfcollision",
                "friction",
                "contact",
                "articulation",
            ],
        )?;
        if let Some(g) = r.at_most_one(props, "gravity")? {
            p.gravity = r.array::<3>(g)?;
        }
        if let Some(s) = r.at_most_one(props, "selfcollision")? {
            p.self_collision = r.flag(s)?;
        }
        if let Some(f) = r.at_most_one(props, "friction")? {
            p.default_friction = Some(r.f64_in(f, 0.0, MAX_FRICTION)?);
        }
        if let Some(c) = r.at_most_one(props, "contact")? {
            p.contact = Some(read_contact(r, c)?);
        }
        if let Some(a) = r.at_most_one(props, "articulation")? {
            let t = r.text(a)?.trim();
            p.articulation = match t.to_ascii_lowercase().as_str() {
                "maximal" => Articulation::Maximal,
                "reduced" => Articulation::Reduced,
                _ => {
                    return Err(r.err(
                        a.pos,
                        ErrorKind::InvalidValue,
                        format!("<articulation> is maximal or reduced, not `{t}`"),
                    ));
                }
            };
        }
    }
    Ok(p)
}

/// Parses the thesis's `Pose: ,w x y z,x y z,` comment.
fn parse_pose_comment(r: &Reader, body: &str, pos: Pos) -> ConfigResult<Option<Pose>> {
    let Some(rest) = body.trim().strip_prefix("Pose:") else {
        return Ok(None);
    };
    let groups: Vec<&str> = rest
        .split(',')
        .map(str::trim)
        .filter(|g| !g.is_empty())
        .collect();
    let bad = || {
        r.err(
            pos,
            ErrorKind::InvalidValue,
            "pose comment: expected \"Pose: ,w x y z,x y z,\" (quaternion, then translation)",
        )
    };
    if groups.len() != 2 {
        return Err(bad());
    }
    let q = r.numbers(groups[0], pos, "pose comment rotation")?;
    let t = r.numbers(groups[1], pos, "pose comment translation")?;
    let (Ok(q), Ok(t)) = (<[f64; 4]>::try_from(q), <[f64; 3]>::try_from(t)) else {
        return Err(bad());
    };
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let rotation = if n == 0.0 {
        Pose::IDENTITY.rotation
    } else {
        [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
    };
    Ok(Some(Pose {
        translation: t,
        rotation,
    }))
}

/// Reads an environment file's text.
pub fn parse_environment_file(file: &str, text: &str) -> ConfigResult<EnvironmentFile> {
    let (doc, r) = read_document(file, text, "Environment", "an environment file")?;
    let root = &doc.root;
    r.only_children(root, &["physicsengine", "kinbody", "terrain", "robotpose"])?;
    r.only_attrs(root, &[])?;
    let physics = r
        .at_most_one(root, "physicsengine")?
        .map(|p| read_physics(&r, p))
        .transpose()?
        .unwrap_or_default();
    let mut objects = Vec::new();
    for el in &root.children {
        if el.is("terrain") {
            objects.push(EnvObject::Terrain(TerrainSpec::read(&r, el)?));
        } else if el.is("kinbody") {
            objects.push(if el.attr("file").is_some() {
                EnvObject::Include(Include::read(&r, el)?)
            } else {
                EnvObject::Inline(KinBody::read(&r, el)?)
            });
        }
    }
    let mut robot_pose = None;
    for (body, pos) in doc.outer_comments.iter().chain(root.comments.iter()) {
        if let Some(p) = parse_pose_comment(&r, body, *pos)? {
            robot_pose = Some(p);
        }
    }
    if let Some(p) = r.at_most_one(root, "robotpose")? {
        r.only_children(p, &POSE_ELEMENTS)?;
        robot_pose = Some(Pose::read(&r, p)?);
    }
    Ok(EnvironmentFile {
        physics,
        objects,
        robot_pose,
    })
}

impl EnvironmentFile {
    /// Rounds the poses and sizes it holds as files written for people hold them
    /// (`KinBody::round_for_people`), the robot's pose and the courses' poses too.
    pub fn round_for_people(&mut self) {
        for o in &mut self.objects {
            match o {
                EnvObject::Inline(kb) => kb.round_for_people(),
                EnvObject::Include(i) => i.pose = i.pose.for_people(),
                EnvObject::Terrain(t) => t.pose = t.pose.for_people(),
            }
        }
        if let Some(p) = &mut self.robot_pose {
            *p = p.for_people();
        }
    }
}

/// Writes an environment file, with the pose both as element and as the thesis's comment.
pub fn write_environment_file(env: &EnvironmentFile) -> String {
    let mut w = XmlWriter::new();
    w.open("Environment", &[]);
    w.open("physicsengine", &[("type", env.physics.engine.clone())]);
    w.open("odeproperties", &[]);
    w.nums("gravity", &env.physics.gravity);
    w.flag("selfcollision", env.physics.self_collision);
    if let Some(f) = env.physics.default_friction {
        w.num("friction", f);
    }
    if let Some(c) = &env.physics.contact {
        write_contact(&mut w, c);
    }
    if env.physics.articulation != Articulation::default() {
        w.leaf("articulation", env.physics.articulation.name());
    }
    w.close();
    w.close();
    for o in &env.objects {
        match o {
            EnvObject::Inline(kb) => kb.write(&mut w),
            EnvObject::Include(i) => i.write(&mut w),
            EnvObject::Terrain(t) => t.write(&mut w),
        }
    }
    if let Some(p) = &env.robot_pose {
        w.open("RobotPose", &[]);
        w.nums("translation", &p.translation);
        w.nums("quat", &p.rotation);
        w.close();
    }
    w.close();
    if let Some(p) = &env.robot_pose {
        w.comment(&format!(
            "Pose: ,{},{},",
            nums(&p.rotation),
            nums(&p.translation)
        ));
    }
    w.finish()
}

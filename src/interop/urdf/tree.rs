//! The kinematic tree of a URDF: its root link, every link's pose at zero joint angles,
//! and which proleg body each link becomes (links on fixed joints merge into their parent).

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::{Isometry3, Translation3, UnitQuaternion};

use crate::interop::InteropError;

/// A URDF `<origin>` as a rigid transform (`rpy`: roll about x, then pitch about y, then
/// yaw about z, all about fixed axes).
pub fn origin(p: &urdf_rs::Pose) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(p.xyz[0], p.xyz[1], p.xyz[2]),
        UnitQuaternion::from_euler_angles(p.rpy[0], p.rpy[1], p.rpy[2]),
    )
}

/// Whether proleg drives the joint (a hinge) rather than merging its child.
pub fn is_hinge(j: &urdf_rs::Joint) -> bool {
    matches!(
        j.joint_type,
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous
    )
}

/// The tree: per link (in URDF order), its pose in the robot frame at zero angles and the
/// link whose body it is part of; `order` lists the links root first, parents before
/// children.
pub struct Tree {
    /// Link poses in the robot (root) frame.
    pub world: Vec<Isometry3<f64>>,
    /// For each link, the link that heads its body (itself unless it hangs on a fixed or
    /// unsupported joint).
    pub body_of: Vec<usize>,
    /// The links, parents before children.
    pub order: Vec<usize>,
    /// The joint whose child each link is (none for the root).
    pub parent_joint: Vec<Option<usize>>,
}

impl Tree {
    /// Builds the tree; errors name an unknown link, a link with two parents, a cycle or
    /// several roots.
    pub fn new(file: &Path, robot: &urdf_rs::Robot) -> Result<Tree, InteropError> {
        let index: BTreeMap<&str, usize> = robot
            .links
            .iter()
            .enumerate()
            .map(|(i, l)| (l.name.as_str(), i))
            .collect();
        let find = |name: &str, joint: &str| {
            index.get(name).copied().ok_or_else(|| {
                InteropError::new(
                    file,
                    format!("joint {joint} names link \"{name}\", which does not exist"),
                )
            })
        };
        let n = robot.links.len();
        let mut parent_joint = vec![None; n];
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, j) in robot.joints.iter().enumerate() {
            let p = find(&j.parent.link, &j.name)?;
            let c = find(&j.child.link, &j.name)?;
            if parent_joint[c].replace(k).is_some() {
                return Err(InteropError::new(
                    file,
                    format!("link {} is the child of two joints", j.child.link),
                ));
            }
            children[p].push(k);
        }
        let roots: Vec<usize> = (0..n).filter(|&i| parent_joint[i].is_none()).collect();
        let [root] = roots[..] else {
            let names: Vec<&str> = roots
                .iter()
                .map(|&i| robot.links[i].name.as_str())
                .collect();
            return Err(InteropError::new(
                file,
                format!(
                    "a robot needs exactly one root link; found {}: {}",
                    names.len(),
                    names.join(", ")
                ),
            ));
        };
        let mut tree = Tree {
            world: vec![Isometry3::identity(); n],
            body_of: (0..n).collect(),
            order: vec![root],
            parent_joint,
        };
        let mut next = 0;
        while next < tree.order.len() {
            let p = tree.order[next];
            next += 1;
            for &k in &children[p] {
                let j = &robot.joints[k];
                let c = index[j.child.link.as_str()];
                tree.world[c] = tree.world[p] * origin(&j.origin);
                if !is_hinge(j) {
                    tree.body_of[c] = tree.body_of[p];
                }
                tree.order.push(c);
            }
        }
        if tree.order.len() != n {
            return Err(InteropError::new(file, "the joints form a cycle"));
        }
        Ok(tree)
    }

    /// The links that make up the body headed by `head`, in tree order.
    pub fn members(&self, head: usize) -> impl Iterator<Item = usize> + '_ {
        self.order
            .iter()
            .copied()
            .filter(move |&l| self.body_of[l] == head)
    }

    /// The pose of link `link` in the frame of its body.
    pub fn in_body(&self, link: usize) -> Isometry3<f64> {
        self.world[self.body_of[link]].inverse() * self.world[link]
    }
}

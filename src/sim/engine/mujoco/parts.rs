//! Our bodies in a MuJoCo world. A movable environment body or a robot link is a MuJoCo
//! body; a static environment body is a set of the world body's geoms ([`super::mjcf`]
//! writes it as a `<frame>`, so MuJoCo steps no body for it), whose pose and centre of
//! mass are kept here. Also which of our bodies owns each geom, for contacts.

use std::ffi::c_int;

use crate::config::resolve::environment::EnvBody;
use crate::config::resolve::robot::geom_volume;
use crate::config::transform::Pose;
use crate::sim::engine::BodyId;

/// One of our bodies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// A MuJoCo body (its id).
    Body(c_int),
    /// A static environment body: its index in [`Parts::statics`].
    Static(usize),
}

/// A static environment body: geoms of MuJoCo's world body.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticPart {
    /// The body's frame in the world.
    pub pose: Pose,
    /// Its centre of volume in the world.
    pub com: [f64; 3],
    /// Its geoms' ids in the model.
    pub geoms: Vec<usize>,
}

impl StaticPart {
    /// `body`'s part, its geoms at `geoms`.
    pub fn new(body: &EnvBody, geoms: Vec<usize>) -> StaticPart {
        let (mut sum, mut volume) = ([0.0; 3], 0.0);
        for g in &body.geoms {
            let v = geom_volume(g);
            let at = body.pose.mul(&g.pose).translation;
            for k in 0..3 {
                sum[k] += v * at[k];
            }
            volume += v;
        }
        let com = if volume > 0.0 {
            sum.map(|s| s / volume)
        } else {
            body.pose.translation
        };
        StaticPart {
            pose: body.pose,
            com,
            geoms,
        }
    }

    /// Moves the kept pose and centre by `delta` (the engine moves the geoms).
    pub fn translate(&mut self, delta: [f64; 3]) {
        for (k, dk) in delta.iter().enumerate() {
            self.pose.translation[k] += dk;
            self.com[k] += dk;
        }
    }
}

/// Our bodies, by [`BodyId`].
#[derive(Debug, Clone, Default)]
pub struct Parts {
    list: Vec<Part>,
    /// The static environment bodies.
    pub statics: Vec<StaticPart>,
    /// The owner of each geom of the model, when it is one of ours.
    geom_owner: Vec<Option<BodyId>>,
}

impl Parts {
    /// Adds MuJoCo body `id`.
    pub fn add_body(&mut self, id: c_int) -> BodyId {
        self.list.push(Part::Body(id));
        BodyId(self.list.len() as u32 - 1)
    }

    /// Adds a static body.
    pub fn add_static(&mut self, part: StaticPart) -> BodyId {
        self.list.push(Part::Static(self.statics.len()));
        self.statics.push(part);
        BodyId(self.list.len() as u32 - 1)
    }

    /// What `b` is, if it is ours.
    pub fn get(&self, b: BodyId) -> Option<Part> {
        self.list.get(b.0 as usize).copied()
    }

    /// `b`'s MuJoCo body, if it is one.
    pub fn mj_body(&self, b: BodyId) -> Option<c_int> {
        match self.get(b)? {
            Part::Body(id) => Some(id),
            Part::Static(_) => None,
        }
    }

    /// Indexes each geom's owner, given each geom's MuJoCo body (`geom_body`) and the
    /// model's body count.
    pub fn index_geoms(&mut self, geom_body: &[c_int], nbody: usize) {
        let mut body_owner = vec![None; nbody];
        for (i, part) in self.list.iter().enumerate() {
            if let Part::Body(id) = part
                && let Some(slot) = body_owner.get_mut(*id as usize)
            {
                *slot = Some(BodyId(i as u32));
            }
        }
        self.geom_owner = geom_body
            .iter()
            .map(|&b| {
                // The world body's own geoms are static bodies' (below), not the world's.
                (b > 0).then(|| body_owner.get(b as usize).copied().flatten())?
            })
            .collect();
        for (i, part) in self.list.iter().enumerate() {
            if let Part::Static(s) = part {
                for &g in &self.statics[*s].geoms {
                    if let Some(slot) = self.geom_owner.get_mut(g) {
                        *slot = Some(BodyId(i as u32));
                    }
                }
            }
        }
    }

    /// The body of ours that geom `g` belongs to.
    pub fn owner(&self, g: c_int) -> Option<BodyId> {
        usize::try_from(g)
            .ok()
            .and_then(|g| self.geom_owner.get(g).copied().flatten())
    }
}

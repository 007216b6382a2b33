//! The pose stream: an episode as the viewer plays it — the [`Scene`] once, then per frame
//! every moving body's pose (position as `f32`, rotation as four `i16`), robot 0's joint
//! angles (hundredths of a degree), its pads' contacts and its score so far. The
//! [`Recorder`] fills preallocated buffers frame by frame; [`Recorder::stream`] encodes
//! them ([`crate::playback::encode`]) into the JSON the page reads.

use serde::Serialize;

use crate::playback::encode;
use crate::playback::error::PlaybackError;
use crate::playback::scene::{Scene, SceneParts};
use crate::sim::engine::BodyId;
use crate::sim::servo::JointState;
use crate::sim::{SimError, Simulator};

/// The stream's format, first in every stream (the page refuses another).
pub const FORMAT: &str = "proleg-replay 1";

/// A recorded episode, ready for the page.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PoseStream {
    /// [`FORMAT`].
    pub format: &'static str,
    /// What was run, for the page's title (shown as text).
    pub label: String,
    /// The engine and its settings.
    pub engine: String,
    /// Simulated seconds between two frames.
    pub frame_seconds: f64,
    /// Frames recorded (the first at the start).
    pub frames: usize,
    /// What the score over time is (the episode's fitness).
    pub score_name: String,
    /// How the episode ended.
    pub end: String,
    /// What is drawn.
    pub scene: Scene,
    /// Base64 `f32`: per frame, per moving body, x, y, z (m).
    pub positions: String,
    /// Base64 `i16`: per frame, per moving body, the rotation's x, y, z, w times
    /// [`encode::QUATERNION_SCALE`].
    pub rotations: String,
    /// Base64 `i16`: per frame, per joint, its angle in hundredths of a degree.
    pub angles: String,
    /// Base64 `u8`: per frame, per pad (in [`Scene::pads`] order), 1 while pressed.
    pub contacts: String,
    /// Base64 `f32`: per frame, the episode's score so far.
    pub score: String,
}

/// What the stream says of its run besides the frames.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamInfo {
    /// What was run.
    pub label: String,
    /// The engine and its settings.
    pub engine: String,
    /// Simulated seconds between frames.
    pub frame_seconds: f64,
    /// What the score is.
    pub score_name: String,
}

/// Fills the frames of one episode; allocates only when more frames come than it was
/// made for.
pub struct Recorder {
    parts: SceneParts,
    pad_slots: Vec<usize>,
    frames: usize,
    positions: Vec<f32>,
    rotations: Vec<i16>,
    angles: Vec<i16>,
    contacts: Vec<u8>,
    score: Vec<f32>,
    joint_states: Vec<JointState>,
}

impl Recorder {
    /// A recorder of the scene's moving bodies with room for `frames` frames.
    pub fn new(parts: SceneParts, frames: usize) -> Recorder {
        let (bodies, joints) = (parts.moving.len(), parts.scene.joints.len());
        let pads = parts.scene.pads.len();
        let pad_slots = parts.scene.pads.iter().map(|p| p.index).collect();
        Recorder {
            parts,
            pad_slots,
            frames: 0,
            positions: Vec::with_capacity(frames * bodies * 3),
            rotations: Vec::with_capacity(frames * bodies * 4),
            angles: Vec::with_capacity(frames * joints),
            contacts: Vec::with_capacity(frames * pads),
            score: Vec::with_capacity(frames),
            joint_states: Vec::with_capacity(joints),
        }
    }

    /// The engine bodies whose poses each frame holds.
    pub fn moving(&self) -> &[BodyId] {
        &self.parts.moving
    }

    /// Frames recorded so far.
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Records the world as it is now as the next frame, with robot 0's `score` so far.
    pub fn sample(&mut self, sim: &Simulator, score: f64) -> Result<(), SimError> {
        for body in &self.parts.moving {
            // A body the engine no longer has (none does) stays where the scene put it.
            let pose = sim.body_state(*body).map(|s| s.pose).unwrap_or_default();
            self.positions
                .extend(pose.translation.iter().map(|c| *c as f32));
            let [w, x, y, z] = pose.rotation;
            self.rotations
                .extend_from_slice(&encode::quaternion([x, y, z, w]));
        }
        // The angles the servos measured this step (the data file's real joint positions).
        sim.joint_states_into(0, &mut self.joint_states)?;
        let joints = self.parts.scene.joints.len();
        for j in 0..joints {
            let a = self.joint_states.get(j).map_or(0.0, |s| s.angle);
            self.angles.push(encode::angle(a));
        }
        let tactile = &sim.sensors(0)?.tactile;
        for slot in &self.pad_slots {
            self.contacts
                .push(u8::from(tactile.get(*slot).copied().unwrap_or(false)));
        }
        self.score.push(score as f32);
        self.frames += 1;
        Ok(())
    }

    /// The stream of the frames recorded so far, the episode having ended (or gone on) as
    /// `end` says; the recorder can go on recording.
    pub fn stream(&self, info: StreamInfo, end: &str) -> PoseStream {
        PoseStream {
            format: FORMAT,
            label: info.label,
            engine: info.engine,
            frame_seconds: info.frame_seconds,
            frames: self.frames,
            score_name: info.score_name,
            end: end.to_string(),
            scene: self.parts.scene.clone(),
            positions: encode::f32s(&self.positions),
            rotations: encode::i16s(&self.rotations),
            angles: encode::i16s(&self.angles),
            contacts: encode::u8s(&self.contacts),
            score: encode::f32s(&self.score),
        }
    }
}

impl PoseStream {
    /// The stream as the page reads it.
    pub fn to_json(&self) -> Result<String, PlaybackError> {
        serde_json::to_string(self).map_err(PlaybackError::Encode)
    }

    /// Body `body`'s (among the moving ones) position and rotation (x, y, z, w) at frame
    /// `frame`, as the page decodes them (for tests against the simulation).
    pub fn pose_at(&self, frame: usize, body: usize) -> Option<([f64; 3], [f64; 4])> {
        let moving = self.scene.bodies.iter().filter(|b| b.moves).count();
        let p = encode::decode(&self.positions, f32::from_le_bytes)?;
        let r = encode::decode(&self.rotations, i16::from_le_bytes)?;
        let k = frame.checked_mul(moving)?.checked_add(body)?;
        if body >= moving {
            return None;
        }
        let p = p.get(3 * k..3 * k + 3)?;
        let r = r.get(4 * k..4 * k + 4)?;
        Some((
            [p[0], p[1], p[2]].map(f64::from),
            [r[0], r[1], r[2], r[3]].map(|c| f64::from(c) / encode::QUATERNION_SCALE),
        ))
    }
}

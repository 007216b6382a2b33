//! The `<Terrain>` element of environment files: a generated course named by its family,
//! difficulty, seed, length and width, read and written here (one door for the format),
//! with the limits that keep a generated course within a size the engines can hold.

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::transform::{POSE_ELEMENTS, Pose};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::{XmlWriter, num};

/// The kinds of ground a course can be made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// A fractal height field (amplitude and wavelength from the difficulty).
    Rough,
    /// Experiment 2's hump, plateau with a trough, and trough, repeated with random sizes.
    Hills,
    /// Random steps up and down.
    Steps,
    /// Flights of stairs up, then down.
    Stairs,
    /// Inclines up and down with bumps.
    Slope,
    /// A field of vertical cylinders.
    Pegs,
    /// Walls that narrow and bend.
    Channel,
    /// Random boxes lying about.
    Rubble,
}

impl Family {
    /// Every family, in the order files and tables list them.
    pub const ALL: [Family; 8] = [
        Family::Rough,
        Family::Hills,
        Family::Steps,
        Family::Stairs,
        Family::Slope,
        Family::Pegs,
        Family::Channel,
        Family::Rubble,
    ];

    /// The name files and the command line use.
    pub fn name(self) -> &'static str {
        Family::NAMES[self as usize]
    }

    /// The families' names, in [`Family::ALL`]'s order.
    pub const NAMES: [&'static str; 8] = [
        "rough", "hills", "steps", "stairs", "slope", "pegs", "channel", "rubble",
    ];

    /// Reads a family's name (case ignored).
    pub fn parse(s: &str) -> Result<Family, crate::config::error::UnknownName> {
        let t = s.trim().to_ascii_lowercase();
        Family::ALL
            .into_iter()
            .find(|f| f.name() == t)
            .ok_or_else(|| {
                crate::config::error::UnknownName::new("terrain family", s, &Family::NAMES)
            })
    }

    /// Whether the family's ground is a height field (else boxes and cylinders on a floor).
    pub fn is_field(self) -> bool {
        matches!(self, Family::Rough | Family::Hills | Family::Slope)
    }
}

impl std::fmt::Display for Family {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The documented difficulty tiers: names for three points of the [0, 1] scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Tier {
    /// Difficulty 0.2.
    Easy,
    /// Difficulty 0.5.
    Medium,
    /// Difficulty 0.8.
    Hard,
}

impl Tier {
    /// Every tier, easiest first.
    pub const ALL: [Tier; 3] = [Tier::Easy, Tier::Medium, Tier::Hard];

    /// The difficulty the tier stands for.
    pub fn difficulty(self) -> f64 {
        match self {
            Tier::Easy => 0.2,
            Tier::Medium => 0.5,
            Tier::Hard => 0.8,
        }
    }

    /// The name files and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Tier::Easy => "easy",
            Tier::Medium => "medium",
            Tier::Hard => "hard",
        }
    }

    /// The tier of a name (case ignored), if it is one.
    pub fn parse(s: &str) -> Option<Tier> {
        let t = s.trim().to_ascii_lowercase();
        Tier::ALL.into_iter().find(|tier| tier.name() == t)
    }
}

/// Flat ground behind the start (m).
pub const START_PAD: f64 = 2.0;
/// Where the family's ground begins, ahead of the start (m): a robot starts on the flat.
pub const FEATURES_FROM: f64 = 1.5;
/// Ground beyond the course's length (m).
pub const END_PAD: f64 = 2.0;
/// Spacing of the height fields' nodes (m): half the rough family's finest noise lattice at
/// difficulty 1, and hills' and slopes' features are 15 cm and more. A finer grid means more
/// triangles under each link: on rough ground a 5-cm grid cost 1.39x the flat floor's
/// instructions per step on rapier, this one 1.15x (docs/suite.md).
pub const FIELD_GRID: f64 = 0.1;

/// Peg spacing (m) at difficulty `d`: 0.9 m (0) to 0.35 m (1).
pub fn peg_spacing(d: f64) -> f64 {
    0.9 - 0.55 * d
}

/// Spacing of the samples of a channel's wall curve (m). The wall is as few straight pieces
/// between samples as follow the curve within a centimetre; the channel bends gently enough
/// (curvature below 4 /m) that every piece spans two samples or more.
pub const WALL_SAMPLE: f64 = 0.05;

/// Rubble density (boxes per m²) at difficulty `d`: 0.6 (0) to 4 (1).
pub fn rubble_density(d: f64) -> f64 {
    0.6 + 3.4 * d
}

/// Course length (m ahead of the start) when a file names none: no controller of the
/// shipped robots reaches its end in a 90-s episode.
pub const DEFAULT_LENGTH: f64 = 32.0;
/// Course width (m) when a file names none.
pub const DEFAULT_WIDTH: f64 = 3.0;
/// Longest course (m).
pub const MAX_LENGTH: f64 = 500.0;
/// Widest course (m).
pub const MAX_WIDTH: f64 = 50.0;
/// Shortest course (m): the start pad and one feature.
pub const MIN_LENGTH: f64 = 4.0;
/// Narrowest course (m).
pub const MIN_WIDTH: f64 = 0.5;

/// A generated course as a file names it.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainSpec {
    /// The kind of ground.
    pub family: Family,
    /// 0 (the gentlest ground of the family) ..= 1 (the hardest); see [`Tier`].
    pub difficulty: f64,
    /// The seed of its random sizes and places: the same seed, the same geometry.
    pub seed: u64,
    /// Metres of course ahead of the start (along +y, the way the shipped robots face).
    pub length: f64,
    /// Metres across (x), centred on the start.
    pub width: f64,
    /// Where the course lies in the world (its start at the origin, facing +y, when
    /// identity).
    pub pose: Pose,
    /// Where it was written (line, column).
    pub pos: Pos,
}

impl TerrainSpec {
    /// A course of `family` at `difficulty` with `seed`, of the default length and width.
    pub fn new(family: Family, difficulty: f64, seed: u64) -> Self {
        TerrainSpec {
            family,
            difficulty,
            seed,
            length: DEFAULT_LENGTH,
            width: DEFAULT_WIDTH,
            pose: Pose::IDENTITY,
            pos: Pos::new(0, 0),
        }
    }

    /// A short name: `pegs d0.50 seed 3`.
    pub fn label(&self) -> String {
        format!("{} d{:.2} seed {}", self.family, self.difficulty, self.seed)
    }

    /// The name a height-field family's course gives its mesh (family, seed, difficulty).
    pub fn mesh_name(&self) -> String {
        format!(
            "{}{}-seed{}-d{}",
            super::GENERATED_MESH,
            self.family,
            self.seed,
            crate::config::xml::write::num(self.difficulty)
        )
    }

    /// Reads a `<Terrain family=".." difficulty=".." seed=".." length=".." width=".."/>`
    /// (with an optional placement: `<Translation>`, `<RotationAxis>`, ...).
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<TerrainSpec> {
        TerrainSpec::read_with(r, el, &[])
    }

    /// [`TerrainSpec::read`] of an element that may carry `extra` attributes of its own (a
    /// suite's task).
    pub fn read_with(r: &Reader, el: &Element, extra: &[&str]) -> ConfigResult<TerrainSpec> {
        r.only_children(el, &POSE_ELEMENTS)?;
        let mut attrs = vec!["family", "difficulty", "seed", "length", "width"];
        attrs.extend(extra);
        r.only_attrs(el, &attrs)?;
        let fam = r.required_attr(el, "family")?;
        let family = Family::parse(&fam.value)
            .map_err(|e| r.err(fam.pos, ErrorKind::UnknownReference, e.to_string()))?;
        let d = r.required_attr(el, "difficulty")?;
        let difficulty = match Tier::parse(&d.value) {
            Some(t) => t.difficulty(),
            None => r.number(&d.value, d.pos, "difficulty (or easy, medium, hard)")?,
        };
        let seed = match el.attr("seed") {
            Some(a) => a.value.trim().parse::<u64>().map_err(|_| {
                r.err(
                    a.pos,
                    ErrorKind::InvalidValue,
                    format!("seed: expected a whole number >= 0, found \"{}\"", a.value),
                )
            })?,
            None => 1,
        };
        let length = optional(r, el, "length")?.unwrap_or(DEFAULT_LENGTH);
        let width = optional(r, el, "width")?.unwrap_or(DEFAULT_WIDTH);
        let spec = TerrainSpec {
            family,
            difficulty,
            seed,
            length,
            width,
            pose: Pose::read(r, el)?,
            pos: el.pos,
        };
        spec.check().map_err(|e| {
            let at = e
                .attribute()
                .and_then(|a| el.attr(a))
                .map_or(el.pos, |a| a.pos);
            r.err(at, ErrorKind::OutOfRange, e.to_string())
        })?;
        Ok(spec)
    }

    /// The course's attributes but its seed: family, difficulty, and length and width
    /// where they are not the defaults.
    pub fn attributes(&self) -> Vec<(&'static str, String)> {
        let mut attrs = vec![
            ("family", self.family.name().to_string()),
            ("difficulty", num(self.difficulty)),
        ];
        if self.length != DEFAULT_LENGTH {
            attrs.push(("length", num(self.length)));
        }
        if self.width != DEFAULT_WIDTH {
            attrs.push(("width", num(self.width)));
        }
        attrs
    }

    /// Writes the element.
    pub fn write(&self, w: &mut XmlWriter) {
        let mut attrs = self.attributes();
        attrs.insert(2, ("seed", self.seed.to_string()));
        if self.pose.is_identity() {
            w.empty("Terrain", &attrs);
        } else {
            w.open("Terrain", &attrs);
            self.pose.write(w);
            w.close();
        }
    }

    /// Checks the numbers: difficulty in [0, 1], length and width in range, and a size the
    /// engines can hold (worked out before generating).
    pub fn check(&self) -> Result<(), TerrainError> {
        if !(0.0..=1.0).contains(&self.difficulty) {
            return Err(TerrainError::Difficulty(self.difficulty));
        }
        if !(MIN_LENGTH..=MAX_LENGTH).contains(&self.length) {
            return Err(TerrainError::Length(self.length));
        }
        if !(MIN_WIDTH..=MAX_WIDTH).contains(&self.width) {
            return Err(TerrainError::Width(self.width));
        }
        match self.size().too_big() {
            Some(why) => Err(TerrainError::TooBig {
                family: self.family,
                why,
            }),
            None => Ok(()),
        }
    }

    /// How big the generated course will be, worked out before generating it.
    pub fn size(&self) -> TerrainSize {
        let area = (self.length + START_PAD + END_PAD) * self.width;
        let nodes = if self.family.is_field() {
            let nx = (self.width / FIELD_GRID).ceil() + 1.0;
            let ny = ((self.length + START_PAD + END_PAD) / FIELD_GRID).ceil() + 1.0;
            nx * ny
        } else {
            0.0
        };
        TerrainSize {
            nodes,
            bodies: estimated_bodies(self, area),
        }
    }
}

/// The size of a generated course.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerrainSize {
    /// Height-field nodes.
    pub nodes: f64,
    /// Static bodies (boxes, cylinders).
    pub bodies: f64,
}

/// Most height-field nodes a course may have (a 500 m x 20 m course at 10 cm).
pub const MAX_NODES: f64 = 1_100_000.0;
/// Most bodies a course may have.
pub const MAX_BODIES: f64 = 20_000.0;

impl TerrainSize {
    /// Why the course is too big for the engines, if it is.
    pub fn too_big(&self) -> Option<String> {
        if self.nodes > MAX_NODES {
            Some(format!(
                "{:.0} height-field nodes (at most {MAX_NODES:.0}; make it shorter or narrower)",
                self.nodes
            ))
        } else if self.bodies > MAX_BODIES {
            Some(format!(
                "{:.0} bodies (at most {MAX_BODIES:.0}; make it shorter, narrower or easier)",
                self.bodies
            ))
        } else {
            None
        }
    }
}

/// An optional number attribute.
fn optional(r: &Reader, el: &Element, name: &str) -> ConfigResult<Option<f64>> {
    el.attr(name)
        .map(|a| r.number(&a.value, a.pos, name))
        .transpose()
}

/// What is wrong with a terrain's numbers (the file's reader locates it at the attribute).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TerrainError {
    /// A difficulty outside [0, 1].
    #[error("difficulty is {0}; it must be between 0 and 1 (or easy, medium, hard)")]
    Difficulty(f64),
    /// A length outside its range.
    #[error("length is {0} m; it must be between {MIN_LENGTH} and {MAX_LENGTH}")]
    Length(f64),
    /// A width outside its range.
    #[error("width is {0} m; it must be between {MIN_WIDTH} and {MAX_WIDTH}")]
    Width(f64),
    /// A course too big for the engines.
    #[error("the {family} terrain would be too big: {why}")]
    TooBig {
        /// Its family.
        family: Family,
        /// Its size against the limit.
        why: String,
    },
}

impl TerrainError {
    /// The attribute the error is about, if one.
    pub fn attribute(&self) -> Option<&'static str> {
        match self {
            TerrainError::Difficulty(_) => Some("difficulty"),
            TerrainError::Length(_) => Some("length"),
            TerrainError::Width(_) => Some("width"),
            TerrainError::TooBig { .. } => None,
        }
    }
}

/// How many bodies the family will make of `area` m² at most (the size check before
/// generating).
pub fn estimated_bodies(spec: &TerrainSpec, area: f64) -> f64 {
    let d = spec.difficulty;
    match spec.family {
        Family::Rough | Family::Hills | Family::Slope => 2.0,
        Family::Steps => spec.length / 0.5 + 2.0,
        Family::Stairs => 2.0 * spec.length / (0.45 - 0.24 * d).max(0.05) + 2.0,
        Family::Pegs => area / (peg_spacing(d) * peg_spacing(d)) * 1.5 + 1.0,
        Family::Channel => 2.0 * (spec.length + START_PAD) / (2.0 * WALL_SAMPLE) + 5.0,
        Family::Rubble => rubble_density(d) * area + 1.0,
    }
}

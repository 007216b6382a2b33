//! Procedural terrains: a `<Terrain>` element of an environment file names a family, a
//! difficulty in [0, 1] (tiers easy 0.2, medium 0.5, hard 0.8), a seed, a length and a
//! width, and is generated at load time into ordinary static bodies (boxes, cylinders and
//! a height field held in memory), so every engine, window, video and export draws and
//! simulates it as any other scenery.
//!
//! | module | role |
//! |---|---|
//! | [`spec`] | the element: [`Family`], [`Tier`], [`TerrainSpec`], the course's layout, what the difficulty sets that the size check needs, the limits |
//! | [`course`] | the layout every course shares (start pad, features, end) and the builder the families draw with |
//! | [`field`] | the height-field families: rough, hills, slope |
//! | [`solids`] | the families of boxes and cylinders: steps, stairs, pegs, channel, rubble |

pub mod course;
pub mod field;
pub mod solids;
pub mod spec;

pub use course::{GENERATED_MESH, GeneratedTerrain};
pub use spec::{Family, TerrainError, TerrainSize, TerrainSpec, Tier};

/// The course `spec` names: the same spec gives the same geometry on every machine.
pub fn generate(spec: &TerrainSpec) -> GeneratedTerrain {
    let mut c = course::Course::new(spec);
    match spec.family {
        Family::Rough => field::rough(&mut c),
        Family::Hills => field::hills(&mut c),
        Family::Slope => field::slope(&mut c),
        Family::Steps => solids::steps(&mut c),
        Family::Stairs => solids::stairs(&mut c),
        Family::Pegs => solids::pegs(&mut c),
        Family::Channel => solids::channel(&mut c),
        Family::Rubble => solids::rubble(&mut c),
    }
    c.finish()
}

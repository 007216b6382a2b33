//! The environment editor's object library (thesis 4.4.6): primitive objects, stairs, a
//! ramp, the triangle meshes found in the assets folder (the irregular obstacle among
//! them) and a generated course of every terrain family. Each item but a terrain becomes
//! a static `<KinBody>` whose geometry sits about its origin; a terrain becomes a
//! `<Terrain>` element (its bodies are generated from its family, difficulty and seed).

use std::path::Path;

use crate::config::body::{Body, BodyKind, Geom, MeshCollision, Shape};
use crate::config::error::Pos;
use crate::config::kinbody::KinBody;
use crate::config::terrain::Family;
use crate::config::transform::Pose;

/// Something the editor can put into the scene.
#[derive(Debug, Clone, PartialEq)]
pub enum LibraryItem {
    /// A 0.2 m box.
    Box,
    /// A plank tilted 15 degrees.
    Ramp,
    /// An upright cylinder.
    Cylinder,
    /// A ball.
    Sphere,
    /// Five 20 mm steps.
    Stairs,
    /// A Wavefront OBJ mesh, the path as the environment file will name it.
    Mesh(String),
    /// A generated course of this terrain family (dropped at the medium tier, seed 1).
    Terrain(Family),
}

impl LibraryItem {
    /// The name shown in the library and used for new objects.
    pub fn label(&self) -> String {
        match self {
            LibraryItem::Box => "box".into(),
            LibraryItem::Ramp => "ramp".into(),
            LibraryItem::Cylinder => "cylinder".into(),
            LibraryItem::Sphere => "sphere".into(),
            LibraryItem::Stairs => "stairs".into(),
            LibraryItem::Mesh(path) => Path::new(path)
                .file_stem()
                .map_or_else(|| path.clone(), |s| s.to_string_lossy().into_owned()),
            LibraryItem::Terrain(family) => format!("terrain {family}"),
        }
    }

    /// Parses a label (`box`, `stairs`, `terrain pegs` or `terrain-pegs`, ...) or a mesh
    /// path ending in `.obj`.
    pub fn parse(s: &str) -> Option<LibraryItem> {
        let s = s.trim();
        if s.to_ascii_lowercase().ends_with(".obj") {
            return Some(LibraryItem::Mesh(s.to_string()));
        }
        if let Some(family) = s
            .strip_prefix("terrain ")
            .or_else(|| s.strip_prefix("terrain-"))
        {
            return Family::parse(family).ok().map(LibraryItem::Terrain);
        }
        [
            LibraryItem::Box,
            LibraryItem::Ramp,
            LibraryItem::Cylinder,
            LibraryItem::Sphere,
            LibraryItem::Stairs,
        ]
        .into_iter()
        .find(|i| i.label().eq_ignore_ascii_case(s))
    }

    /// The object, named `name`, at the origin (a terrain has no bodies of its own: the
    /// editor places it as a `<Terrain>` element).
    pub fn kinbody(&self, name: &str) -> KinBody {
        let geoms = self.pieces(name);
        let stairs = matches!(self, LibraryItem::Stairs);
        let bodies = geoms
            .into_iter()
            .map(|(body_name, pose, shape, colour)| {
                // Stairs: each step is a body placed by its translation; others: the
                // geometry carries the tilt.
                let (body_pose, geom_pose) = if stairs {
                    (pose, Pose::IDENTITY)
                } else {
                    (Pose::IDENTITY, pose)
                };
                Body {
                    name: body_name,
                    kind: BodyKind::Static,
                    pose: body_pose,
                    geoms: vec![Geom {
                        shape,
                        pose: geom_pose,
                        diffuse_color: Some(colour),
                        ambient_color: None,
                        transparency: None,
                        friction: Some(0.5),
                        visible: true,
                        pos: Pos::new(0, 0),
                    }],
                    mass: None,
                    pos: Pos::new(0, 0),
                }
            })
            .collect();
        KinBody {
            name: Some(name.to_string()),
            pose: Pose::IDENTITY,
            includes: Vec::new(),
            bodies,
            joints: Vec::new(),
            sensors: Vec::new(),
            pos: Pos::new(0, 0),
        }
    }

    /// The object's pieces: body name, pose, shape and colour.
    fn pieces(&self, name: &str) -> Vec<(String, Pose, Shape, [f64; 3])> {
        let grey = [0.75, 0.7, 0.65];
        match self {
            LibraryItem::Box => vec![(
                name.into(),
                Pose::IDENTITY,
                Shape::Box {
                    extents: [0.1, 0.1, 0.1],
                },
                [0.85, 0.55, 0.25],
            )],
            LibraryItem::Ramp => vec![(
                name.into(),
                // A 0.6 m plank tilted 15 degrees: rising along +y.
                rotation_x(15.0),
                Shape::Box {
                    extents: [0.25, 0.3, 0.01],
                },
                grey,
            )],
            LibraryItem::Cylinder => vec![(
                name.into(),
                Pose::IDENTITY,
                Shape::Cylinder {
                    radius: 0.1,
                    height: 0.4,
                },
                [0.5, 0.5, 0.9],
            )],
            LibraryItem::Sphere => vec![(
                name.into(),
                Pose::IDENTITY,
                Shape::Sphere { radius: 0.1 },
                [0.9, 0.4, 0.4],
            )],
            // Five 20 mm steps, 100 mm deep, the whole flight 0.5 m deep and 1 m wide,
            // centred on the origin; it rises along +y.
            LibraryItem::Stairs => (1..=5)
                .map(|k| {
                    let front = 0.1 * (k - 1) as f64;
                    let h = 0.01 * k as f64;
                    (
                        format!("{name}_step{k}"),
                        Pose::from_translation([0.0, (front + 0.5) / 2.0 - 0.25, h]),
                        Shape::Box {
                            extents: [0.5, (0.5 - front) / 2.0, h],
                        },
                        grey,
                    )
                })
                .collect(),
            LibraryItem::Mesh(path) => vec![(
                name.into(),
                Pose::IDENTITY,
                Shape::Trimesh {
                    file: path.clone(),
                    scale: 1.0,
                    collision: MeshCollision::Triangles,
                },
                [0.6, 0.45, 0.3],
            )],
            LibraryItem::Terrain(_) => Vec::new(),
        }
    }
}

/// A rotation about the x axis by `deg` degrees.
pub fn rotation_x(deg: f64) -> Pose {
    let h = deg.to_radians() / 2.0;
    Pose {
        translation: [0.0; 3],
        rotation: [h.cos(), h.sin(), 0.0, 0.0],
    }
}

/// The library: the primitives, then every `*.obj` under `assets_dir/meshes`, named as
/// `assets/meshes/NAME.obj` (found from any configuration folder by the include search),
/// then a terrain of every family.
pub fn library(assets_dir: &Path) -> Vec<LibraryItem> {
    let mut items = vec![
        LibraryItem::Box,
        LibraryItem::Ramp,
        LibraryItem::Cylinder,
        LibraryItem::Sphere,
        LibraryItem::Stairs,
    ];
    let mut meshes: Vec<String> = std::fs::read_dir(assets_dir.join("meshes"))
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.to_ascii_lowercase()
                .ends_with(".obj")
                .then(|| format!("assets/meshes/{name}"))
        })
        .collect();
    meshes.sort();
    items.extend(meshes.into_iter().map(LibraryItem::Mesh));
    items.extend(Family::ALL.into_iter().map(LibraryItem::Terrain));
    items
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn library_holds_primitives_and_the_obstacle_mesh() {
        let lib = library(Path::new("assets"));
        assert!(lib.contains(&LibraryItem::Stairs));
        assert!(lib.contains(&LibraryItem::Mesh(
            "assets/meshes/irregular_obstacle.obj".into()
        )));
        assert_eq!(LibraryItem::parse("Stairs"), Some(LibraryItem::Stairs));
        assert!(lib.contains(&LibraryItem::Terrain(Family::Pegs)));
        assert_eq!(
            LibraryItem::parse("terrain Rubble"),
            Some(LibraryItem::Terrain(Family::Rubble))
        );
        assert_eq!(
            LibraryItem::parse("terrain-pegs"),
            Some(LibraryItem::Terrain(Family::Pegs))
        );
        assert_eq!(LibraryItem::parse("terrain lava"), None);
        assert_eq!(LibraryItem::parse("teapot"), None);
        assert_eq!(LibraryItem::Stairs.kinbody("s").bodies.len(), 5);
    }
}

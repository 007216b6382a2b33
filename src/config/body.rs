//! Rigid bodies and their geometry (OpenRAVE `<Body>` and `<Geom>`), shared by robot
//! module parts (`*.kinbody.xml`) and environments (`*.env.xml`).
//!
//! Units: metres and kilograms. Box `extents` are half-extents, as in OpenRAVE;
//! cylinders stand along their local y axis (OpenRAVE's convention).

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::mesh::TriMesh;
use crate::config::transform::{POSE_ELEMENTS, Pose, round_to};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::{XmlWriter, num};

/// Largest friction coefficient accepted (Coulomb coefficient; rapier takes any value >= 0,
/// beyond this no material pair is realistic and it usually is a typo).
pub const MAX_FRICTION: f64 = 100.0;

/// Whether a body moves (`dynamic`) or is fixed in the world (`static`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyKind {
    /// Moves under forces.
    Dynamic,
    /// Fixed in place.
    Static,
}

/// The shape of one geometry.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// Half-extents along x, y, z.
    Box {
        /// Half-extents (m).
        extents: [f64; 3],
    },
    /// A ball.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// Along the local y axis.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Height along its axis (m).
        height: f64,
    },
    /// A surface from a file (Wavefront OBJ), scaled uniformly: `type="trimesh"` collides
    /// as its triangles, `type="heightfield"` as a height field (the OBJ must then be a
    /// height map, see [`crate::config::mesh::TriMesh::height_map`]), `type="convexhull"`
    /// as its convex hull.
    Trimesh {
        /// The OBJ file (resolved after loading).
        file: String,
        /// Scale applied to its vertices.
        scale: f64,
        /// How the physics represents it.
        collision: MeshCollision,
    },
}

/// How the physics represents a mesh geometry. Both are drawn from the same OBJ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshCollision {
    /// Its triangles (any mesh).
    #[default]
    Triangles,
    /// A height field over its x-y grid (a height map: cheaper terrain contacts).
    HeightField,
    /// Its convex hull (`type="convexhull"`): what robot links made of meshes collide as,
    /// as in MuJoCo (imported URDF links).
    ConvexHull,
}

impl Shape {
    /// A short description for summaries.
    pub fn describe(&self) -> String {
        match self {
            Shape::Box { extents: [x, y, z] } => {
                format!("box {}x{}x{} m", num(2.0 * x), num(2.0 * y), num(2.0 * z))
            }
            Shape::Sphere { radius } => format!("sphere r={} m", num(*radius)),
            Shape::Cylinder { radius, height } => {
                format!("cylinder r={} h={} m", num(*radius), num(*height))
            }
            Shape::Trimesh {
                file,
                scale,
                collision,
            } => {
                let kind = match collision {
                    MeshCollision::Triangles => "mesh",
                    MeshCollision::HeightField => "height field",
                    MeshCollision::ConvexHull => "convex mesh",
                };
                format!("{kind} {file} (scale {})", num(*scale))
            }
        }
    }
}

/// One geometry of a body, posed in the body's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Geom {
    /// The shape.
    pub shape: Shape,
    /// Placement in its body.
    pub pose: Pose,
    /// Diffuse colour (RGB 0..1).
    pub diffuse_color: Option<[f64; 3]>,
    /// Ambient colour (RGB 0..1).
    pub ambient_color: Option<[f64; 3]>,
    /// Transparency (0 opaque .. 1 invisible).
    pub transparency: Option<f64>,
    /// Coulomb friction coefficient; the engine default when absent.
    pub friction: Option<f64>,
    /// Whether the geometry is drawn (OpenRAVE's `render="false"` hides it).
    pub visible: bool,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// The mass of a body.
#[derive(Debug, Clone, PartialEq)]
pub struct Mass {
    /// Total mass in kg.
    pub total: f64,
    /// How it is distributed: `box`, `sphere`, `mimicgeom` (from the geometry) or `custom`.
    pub distribution: String,
    /// Centre of mass in the body frame, for `custom`.
    pub com: Option<[f64; 3]>,
    /// Inertia tensor about the centre of mass in the body frame (kg·m², row-major 3x3,
    /// OpenRAVE's `<inertia>`); when given, the physics uses it and `com` instead of
    /// spreading the mass over the geometry.
    pub inertia: Option<[f64; 9]>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// One rigid body.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The body's name.
    pub name: String,
    /// Static or dynamic.
    pub kind: BodyKind,
    /// Placement in its kinbody.
    pub pose: Pose,
    /// Its geometries.
    pub geoms: Vec<Geom>,
    /// Its mass, when given (else from the geometry).
    pub mass: Option<Mass>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

const GEOM_CHILDREN: [&str; 12] = [
    "translation",
    "rotationaxis",
    "quat",
    "rotationmat",
    "extents",
    "radius",
    "height",
    "data",
    "diffusecolor",
    "ambientcolor",
    "transparency",
    "friction",
];

impl Geom {
    /// Reads it from its element; errors name the line.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<Geom> {
        r.only_children(el, &GEOM_CHILDREN)?;
        r.only_attrs(el, &["type", "render"])?;
        let shape = read_shape(r, el)?;
        let color = |name: &str| -> ConfigResult<Option<[f64; 3]>> {
            match r.at_most_one(el, name)? {
                None => Ok(None),
                Some(c) => {
                    let v = r.array::<3>(c)?;
                    for x in v {
                        r.check_range(x, 0.0, 1.0, c.text_pos, &format!("<{}> component", c.name))?;
                    }
                    Ok(Some(v))
                }
            }
        };
        let transparency = match r.at_most_one(el, "transparency")? {
            Some(c) => Some(r.f64_in(c, 0.0, 1.0)?),
            None => None,
        };
        let friction = match r.at_most_one(el, "friction")? {
            Some(c) => Some(r.f64_in(c, 0.0, MAX_FRICTION)?),
            None => None,
        };
        let visible = match el.attr("render") {
            Some(a) => r.flag_str(&a.value, a.pos, "render=")?,
            None => true,
        };
        Ok(Geom {
            shape,
            pose: Pose::read(r, el)?,
            diffuse_color: color("diffusecolor")?,
            ambient_color: color("ambientcolor")?,
            transparency,
            friction,
            visible,
            pos: el.pos,
        })
    }

    /// Writes it as XML.
    pub fn write(&self, w: &mut XmlWriter) {
        let ty = match self.shape {
            Shape::Box { .. } => "box",
            Shape::Sphere { .. } => "sphere",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Trimesh {
                collision: MeshCollision::Triangles,
                ..
            } => "trimesh",
            Shape::Trimesh {
                collision: MeshCollision::HeightField,
                ..
            } => "heightfield",
            Shape::Trimesh {
                collision: MeshCollision::ConvexHull,
                ..
            } => "convexhull",
        };
        let mut attrs = vec![("type", ty.to_string())];
        if !self.visible {
            attrs.push(("render", "false".into()));
        }
        w.open("Geom", &attrs);
        self.pose.write(w);
        match &self.shape {
            Shape::Box { extents } => w.nums("extents", extents),
            Shape::Sphere { radius } => w.num("radius", *radius),
            Shape::Cylinder { radius, height } => {
                w.num("radius", *radius);
                w.num("height", *height);
            }
            Shape::Trimesh { file, scale, .. } => {
                w.leaf("data", &format!("{file} {}", num(*scale)))
            }
        }
        if let Some(c) = self.diffuse_color {
            w.nums("diffuseColor", &c);
        }
        if let Some(c) = self.ambient_color {
            w.nums("ambientColor", &c);
        }
        if let Some(t) = self.transparency {
            w.num("transparency", t);
        }
        if let Some(f) = self.friction {
            w.num("friction", f);
        }
        w.close();
    }
}

/// The sizes a geometry may have (m): from 1 µm (both engines refuse a zero size; MuJoCo
/// anything below 1e-15) to 10 km.
pub const SIZES: (f64, f64) = (1e-6, 1e4);

/// The masses a body may have (kg): from a milligram to a thousand tonnes.
pub const MASSES: (f64, f64) = (1e-6, 1e6);

/// A geometry's shape from its `type` and the children that type needs.
fn read_shape(r: &Reader, el: &Element) -> ConfigResult<Shape> {
    let ty = r.required_attr(el, "type")?;
    let positive = |name: &str| r.f64_in(r.required(el, name)?, SIZES.0, SIZES.1);
    Ok(match ty.value.to_ascii_lowercase().as_str() {
        "box" => {
            let c = r.required(el, "extents")?;
            let e = r.array::<3>(c)?;
            if e.iter().any(|v| !(SIZES.0..=SIZES.1).contains(v)) {
                return Err(r.err(
                    c.text_pos,
                    ErrorKind::OutOfRange,
                    format!(
                        "box <extents> must all be between {} and {} (half-extents in m)",
                        SIZES.0, SIZES.1
                    ),
                ));
            }
            Shape::Box { extents: e }
        }
        "sphere" => Shape::Sphere {
            radius: positive("radius")?,
        },
        "cylinder" => Shape::Cylinder {
            radius: positive("radius")?,
            height: positive("height")?,
        },
        kind @ ("trimesh" | "heightfield" | "convexhull") => read_mesh(r, el, kind)?,
        other => {
            return Err(r.err(
                ty.pos,
                ErrorKind::InvalidValue,
                format!("unknown geometry type \"{other}\"; expected one of: box, sphere, cylinder, trimesh, heightfield, convexhull"),
            ));
        }
    })
}

/// A mesh geometry's shape (`trimesh`, `heightfield`, `convexhull`): its `<data>` file and
/// scale.
fn read_mesh(r: &Reader, el: &Element, kind: &str) -> ConfigResult<Shape> {
    let c = r.required(el, "data")?;
    let text = r.text(c)?;
    let mut words = text.split_whitespace();
    let file = words.next().unwrap_or_default().to_string();
    let scale = match words.next() {
        Some(s) => {
            let v = r.number(s, c.text_pos, "<data> scale")?;
            if v <= 0.0 {
                return Err(r.err(
                    c.text_pos,
                    ErrorKind::OutOfRange,
                    format!("<data> scale is {v}; it must be > 0"),
                ));
            }
            v
        }
        None => 1.0,
    };
    let collision = match kind {
        "heightfield" => MeshCollision::HeightField,
        "convexhull" => MeshCollision::ConvexHull,
        _ => MeshCollision::Triangles,
    };
    Ok(Shape::Trimesh {
        file,
        scale,
        collision,
    })
}

impl Mass {
    /// Reads `<Mass type="box"><total>0.1</total></Mass>` or the short `<mass>0.1</mass>`.
    pub fn read(r: &Reader, el: &Element) -> ConfigResult<Mass> {
        r.only_children(el, &["total", "com", "extents", "radius", "inertia"])?;
        r.only_attrs(el, &["type"])?;
        let (total, pos) = match r.at_most_one(el, "total")? {
            Some(c) => (r.f64(c)?, c.text_pos),
            None => (r.f64(el)?, el.text_pos),
        };
        r.check_range(total, MASSES.0, MASSES.1, pos, "the mass (kg)")?;
        let com = r
            .at_most_one(el, "com")?
            .map(|c| r.array::<3>(c))
            .transpose()?;
        let inertia = r
            .at_most_one(el, "inertia")?
            .map(|c| read_inertia(r, c))
            .transpose()?;
        Ok(Mass {
            total,
            distribution: el
                .attr("type")
                .map(|a| a.value.to_ascii_lowercase())
                .unwrap_or_else(|| "mimicgeom".into()),
            com,
            inertia,
            pos: el.pos,
        })
    }

    /// Writes it as XML.
    pub fn write(&self, w: &mut XmlWriter) {
        w.open("Mass", &[("type", self.distribution.clone())]);
        w.num("total", self.total);
        if let Some(c) = self.com {
            w.nums("com", &c);
        }
        if let Some(i) = self.inertia {
            w.nums("inertia", &i);
        }
        w.close();
    }
}

/// An `<inertia>` tensor: 9 numbers, symmetric, with positive diagonal (whether it is
/// physical, [`inertia_fault`], is checked with the robot's other physical rules).
fn read_inertia(r: &Reader, c: &Element) -> ConfigResult<[f64; 9]> {
    let m = r.array::<9>(c)?;
    let symmetric = (0..3).all(|i| {
        (0..3).all(|j| (m[3 * i + j] - m[3 * j + i]).abs() <= 1e-9 * (1.0 + m[3 * i + j].abs()))
    });
    if !symmetric || m[0] <= 0.0 || m[4] <= 0.0 || m[8] <= 0.0 {
        return Err(r.err(
            c.text_pos,
            ErrorKind::OutOfRange,
            "<inertia> must be a symmetric 3x3 tensor (9 numbers, kg m^2) with a positive diagonal",
        ));
    }
    Ok(m)
}

/// The lowest z (m) of geometry `g` placed at `at` (its body's pose times its own), `mesh`
/// holding a trimesh's vertices (unscaled; `None`: the mesh is unknown, +infinity).
/// Exact for every shape: a box's lowest corner, a cylinder's (standing along its y) lowest
/// rim point, a mesh's lowest vertex.
pub fn lowest_z(at: &Pose, g: &Geom, mesh: Option<&TriMesh>) -> f64 {
    let z = |p: [f64; 3]| at.transform_point(p)[2];
    match &g.shape {
        Shape::Box { extents } => {
            let reach: f64 = (0..3)
                .map(|k| {
                    let mut v = [0.0; 3];
                    v[k] = extents[k];
                    at.rotate(v)[2].abs()
                })
                .sum();
            at.translation[2] - reach
        }
        Shape::Sphere { radius } => at.translation[2] - radius,
        Shape::Cylinder { radius, height } => {
            let axis_z = at.rotate([0.0, 1.0, 0.0])[2].clamp(-1.0, 1.0);
            at.translation[2]
                - height / 2.0 * axis_z.abs()
                - radius * (1.0 - axis_z * axis_z).sqrt()
        }
        Shape::Trimesh { scale, .. } => mesh
            .map(|m| {
                m.vertices
                    .iter()
                    .map(|v| z(v.map(|c| c * scale)))
                    .fold(f64::INFINITY, f64::min)
            })
            .unwrap_or(f64::INFINITY),
    }
}

/// The highest z (m) of geometry `g` placed at `at`: [`lowest_z`] of it turned upside down.
pub fn highest_z(at: &Pose, g: &Geom, mesh: Option<&TriMesh>) -> f64 {
    let upside_down = Pose {
        translation: [0.0; 3],
        rotation: [0.0, 1.0, 0.0, 0.0],
    };
    -lowest_z(&upside_down.mul(at), g, mesh)
}

/// The principal moments of a symmetric inertia tensor (row-major, kg m^2), ascending.
pub fn principal_moments(m: &[f64; 9]) -> [f64; 3] {
    let t = nalgebra::Matrix3::from_row_slice(m);
    let mut e: [f64; 3] = t.symmetric_eigenvalues().into();
    e.sort_by(f64::total_cmp);
    e
}

/// `m` with its principal moments raised just enough to satisfy the triangle inequality
/// (the two smaller by half the shortfall each, about the same axes), as MuJoCo's
/// `balanceinertia` repairs such tensors; `m` itself when it satisfies it.
pub fn balanced_inertia(m: &[f64; 9]) -> [f64; 9] {
    let e = nalgebra::Matrix3::from_row_slice(m).symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| e.eigenvalues[i].total_cmp(&e.eigenvalues[j]));
    let [a, b, c] = order.map(|i| e.eigenvalues[i]);
    let short = c - a - b;
    if short <= 0.0 {
        return *m;
    }
    let mut l = e.eigenvalues;
    l[order[0]] += short / 2.0;
    l[order[1]] += short / 2.0;
    let t = e.eigenvectors * nalgebra::Matrix3::from_diagonal(&l) * e.eigenvectors.transpose();
    std::array::from_fn(|k| t[(k / 3, k % 3)])
}

/// Why a symmetric inertia tensor is one no rigid body can have, if it is: a principal
/// moment not > 0 (not positive definite), or the largest above the sum of the other two
/// (the triangle inequality A + B >= C every mass distribution satisfies). The same rule
/// for both engines (MuJoCo refuses such bodies; rapier would simulate them).
pub fn inertia_fault(m: &[f64; 9]) -> Option<String> {
    let [a, b, c] = principal_moments(m);
    let scale = c.abs().max(1e-300);
    if !(a.is_finite() && b.is_finite() && c.is_finite()) || a <= 1e-12 * scale {
        Some(format!(
            "not positive definite (principal moments {a:.4e}, {b:.4e}, {c:.4e} kg m^2)"
        ))
    } else if a + b < c * (1.0 - 1e-6) {
        Some(format!(
            "principal moments {a:.4e} + {b:.4e} < {c:.4e} kg m^2: no mass distribution has \
             them (the triangle inequality A + B >= C)"
        ))
    } else {
        None
    }
}

impl Body {
    /// Reads a `<Body>`; `default_name` is used when it has no name (environment floors).
    pub fn read(r: &Reader, el: &Element, default_name: &str) -> ConfigResult<Body> {
        let mut allowed: Vec<&str> = vec!["geom", "mass"];
        allowed.extend(POSE_ELEMENTS);
        r.only_children(el, &allowed)?;
        r.only_attrs(el, &["name", "type", "enable"])?;
        let kind = match el.attr("type") {
            None => BodyKind::Dynamic,
            Some(a) => match a.value.to_ascii_lowercase().as_str() {
                "dynamic" => BodyKind::Dynamic,
                "static" => BodyKind::Static,
                other => {
                    return Err(r.err(
                        a.pos,
                        ErrorKind::InvalidValue,
                        format!("body type \"{other}\"; expected static or dynamic"),
                    ));
                }
            },
        };
        let geoms = el
            .children_named("geom")
            .map(|g| Geom::read(r, g))
            .collect::<ConfigResult<Vec<_>>>()?;
        let mass = r
            .at_most_one(el, "mass")?
            .map(|m| Mass::read(r, m))
            .transpose()?;
        Ok(Body {
            name: el
                .attr("name")
                .map(|a| a.value.clone())
                .unwrap_or_else(|| default_name.to_string()),
            kind,
            pose: Pose::read(r, el)?,
            geoms,
            mass,
            pos: el.pos,
        })
    }

    /// Writes it as XML.
    pub fn write(&self, w: &mut XmlWriter) {
        let kind = match self.kind {
            BodyKind::Dynamic => "dynamic",
            BodyKind::Static => "static",
        };
        w.open(
            "Body",
            &[("name", self.name.clone()), ("type", kind.into())],
        );
        self.pose.write(w);
        for g in &self.geoms {
            g.write(w);
        }
        if let Some(m) = &self.mass {
            m.write(w);
        }
        w.close();
    }

    /// Rounds its pose and its geoms' poses and sizes as files written for people hold
    /// them (`Pose::for_people`; sizes to 0.01 mm).
    pub fn round_for_people(&mut self) {
        self.pose = self.pose.for_people();
        for g in &mut self.geoms {
            g.pose = g.pose.for_people();
            let size = |v: &mut f64| *v = round_to(*v, 1e5);
            match &mut g.shape {
                Shape::Box { extents } => extents.iter_mut().for_each(size),
                Shape::Sphere { radius } => size(radius),
                Shape::Cylinder { radius, height } => {
                    size(radius);
                    size(height);
                }
                Shape::Trimesh { .. } => {}
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inertia_faults_and_their_balance() {
        let box_like = [2.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 4.0];
        assert_eq!(inertia_fault(&box_like), None);
        assert_eq!(balanced_inertia(&box_like), box_like);
        // 1 + 1 < 3: balanced to 1.5 + 1.5 = 3 about the same axes.
        let broken = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 3.0];
        assert!(inertia_fault(&broken).is_some_and(|f| f.contains("triangle")));
        let b = balanced_inertia(&broken);
        let p = principal_moments(&b);
        assert!(
            (p[0] - 1.5).abs() < 1e-12 && (p[1] - 1.5).abs() < 1e-12 && (p[2] - 3.0).abs() < 1e-12
        );
        assert_eq!(inertia_fault(&b), None);
        // A product of inertia larger than the moments: indefinite.
        let indefinite = [1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        assert!(inertia_fault(&indefinite).is_some_and(|f| f.starts_with("not positive definite")));
    }
}

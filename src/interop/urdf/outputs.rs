//! The files around an imported robot that make it runnable at once: a flat floor with the
//! robot standing on it, a gentle sine on every joint and the simulation naming them.

use std::path::Path;

use crate::config::body::{Body, Shape, lowest_z};
use crate::config::environment::{Articulation, parse_environment_file, write_environment_file};
use crate::interop::urdf::meshes::MeshWriter;
use crate::interop::{InteropError, write_text};

/// Amplitude (deg) of the sine the import writes: small enough for any joint range.
pub const SINE_AMPLITUDE_DEG: f64 = 15.0;

/// Clearance (m) between the robot's lowest point and the floor at the start.
const CLEARANCE: f64 = 0.005;

/// The lowest z (robot frame) of any geometry of `bodies`; 0 without geometry.
pub fn lowest_point(bodies: &[Body], meshes: &MeshWriter) -> f64 {
    let low = bodies
        .iter()
        .flat_map(|b| b.geoms.iter().map(move |g| (b, g)))
        .map(|(b, g)| {
            let mesh = match &g.shape {
                Shape::Trimesh { file, .. } => meshes.mesh(file),
                _ => None,
            };
            lowest_z(&b.pose.mul(&g.pose), g, mesh)
        })
        .fold(f64::INFINITY, f64::min);
    if low.is_finite() { low } else { 0.0 }
}

/// Writes `NAME.env.xml`, `NAME.actuation.xml` and `NAME.simulation.xml` into `dir`
/// beside `NAME.robot.xml`, the sine on every joint centred at `offsets` (deg, one per
/// joint); returns the simulation file.
pub fn write_run_files(
    dir: &Path,
    name: &str,
    offsets: &[f64],
    lowest: f64,
) -> Result<std::path::PathBuf, InteropError> {
    let env = env_text(name, CLEARANCE - lowest);
    let actuation = actuation_text(name, offsets);
    let simulation = simulation_text(name);
    write_text(&dir.join(format!("{name}.env.xml")), &env)?;
    write_text(&dir.join(format!("{name}.actuation.xml")), &actuation)?;
    let sim = dir.join(format!("{name}.simulation.xml"));
    write_text(&sim, &simulation)?;
    Ok(sim)
}

/// The import's floor, the robot `lift` m up so it starts [`CLEARANCE`] above it.
fn env_text(name: &str, lift: f64) -> String {
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<!-- A flat floor for the imported robot {name}; it starts {clear} mm above it. -->
<Environment>
  <physicsengine type="ode">
    <odeproperties>
      <gravity>0 0 -9.81</gravity>
      <selfcollision>0</selfcollision>
    </odeproperties>
  </physicsengine>
  <KinBody name="floor">
    <Body type="static">
      <Translation>0 0 -0.05</Translation>
      <Geom type="box">
        <extents>20 20 0.05</extents>
        <diffuseColor>0.6 0.6 0.6</diffuseColor>
        <friction>0.8</friction>
      </Geom>
    </Body>
  </KinBody>
  <RobotPose>
    <Translation>0 0 {lift:.4}</Translation>
  </RobotPose>
</Environment>
"#,
        clear = CLEARANCE * 1000.0
    )
}

/// A gentle travelling sine on every joint, centred at `offsets` (deg, one per joint).
fn actuation_text(name: &str, offsets: &[f64]) -> String {
    let joints = offsets.len();
    let offset = if offsets.iter().all(|o| *o == 0.0) {
        r#"value="0""#.to_string()
    } else {
        let v: Vec<String> = offsets.iter().map(|o| format!("{o:.4}")).collect();
        format!(r#"values="{}""#, v.join(" "))
    };
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<!-- A gentle travelling sine on every joint of the imported robot {name}. -->
<actuation>
  <validRobot robotName="{name}.robot.xml"/>
{module}</actuation>
"#,
        module = if joints == 0 {
            "  <!-- no hinge to drive -->\n".to_string()
        } else {
            format!(
                r#"  <actuationModule name="PatternGenerator_sinusoidal">
    <jointConfiguration joints="{mask}"/>
    <parameter name="Amplitude" value="{SINE_AMPLITUDE_DEG}"/>
    <parameter name="Phase_Difference" value="45"/>
    <parameter name="Frequency" value="0.5"/>
    <parameter name="Offset" {offset}/>
  </actuationModule>
"#,
                mask = "1".repeat(joints)
            )
        }
    )
}

/// The simulation of the import on its floor with its sine.
fn simulation_text(name: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<simulation>
  <description>{name}, imported from URDF, on a flat floor with a sine on every joint.</description>
  <robot>{name}.robot.xml</robot>
  <actuation>{name}.actuation.xml</actuation>
  <environment>{name}.env.xml</environment>
  <simulationProperties>
    <showViewer>1</showViewer>
    <storingData>0</storingData>
    <mode>Single Run Simulation</mode>
    <stepWidth>0.001</stepWidth>
    <duration>10</duration>
    <seed>1</seed>
  </simulationProperties>
</simulation>
"#
    )
}

/// Rewrites the environment file of an import (`NAME.env.xml` in `dir`, written by
/// [`write_run_files`]) to ask for `articulation`.
pub fn set_articulation(
    dir: &Path,
    name: &str,
    articulation: Articulation,
) -> Result<(), InteropError> {
    let path = dir.join(format!("{name}.env.xml"));
    let text = std::fs::read_to_string(&path)
        .map_err(|e| InteropError::new(&path, format!("cannot read: {e}")))?;
    let mut env = parse_environment_file(&path.display().to_string(), &text)
        .map_err(|e| InteropError::new(&path, e.to_string()))?;
    env.physics.articulation = articulation;
    write_text(&path, &write_environment_file(&env))
}

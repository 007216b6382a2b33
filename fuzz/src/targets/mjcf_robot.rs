//! Robots built from the fuzzer's bytes (structured, with `arbitrary`): 1 to 12 bodies in a
//! chain, each a box, sphere or cylinder of drawn size and pose, with a drawn mass and, at
//! times, a centre of mass and an inertia matrix; a hinge between neighbours with a drawn
//! axis, anchor, torque, speed and limits; a sine on every hinge. Numbers are mostly
//! plausible (millimetres to metres, grams to kilograms) and now and then any value at all
//! (zero, negative, NaN, huge). The robot file is written as text, loaded through the
//! resolver with the demo's floor, and when proleg accepts it, exported to MJCF and loaded
//! by MuJoCo (where its library is installed): proleg accepts only what MuJoCo loads, so an
//! accepted robot that MuJoCo refuses is a finding, as is a panic. What loads runs briefly.
//! The drawn robot file is also the `arbitrary`-driven round trip: when its reader accepts
//! it, its writing reads back equal.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use proleg::config::load_simulation_with;
use proleg::config::robot::{parse_robot_file, write_robot_file};
use proleg::interop::mjcf::export_mjcf;

/// The most bodies a drawn robot has.
const MAX_BODIES: usize = 12;

/// A number: mostly `lo..hi` in steps of a thousandth of the range, now and then any f64.
fn number(u: &mut Unstructured, lo: f64, hi: f64) -> Result<f64> {
    if u.ratio(1, 16)? {
        return Ok(f64::from_bits(u.arbitrary()?));
    }
    let k: u16 = u.int_in_range(0..=1000)?;
    Ok(lo + (hi - lo) * f64::from(k) / 1000.0)
}

/// `n` numbers, space-separated.
fn numbers(u: &mut Unstructured, n: usize, lo: f64, hi: f64) -> Result<String> {
    let v: Vec<String> = (0..n)
        .map(|_| number(u, lo, hi).map(|x| x.to_string()))
        .collect::<Result<_>>()?;
    Ok(v.join(" "))
}

/// One body `B{i}` at `y` along the chain.
fn body(u: &mut Unstructured, i: usize, y: f64, out: &mut String) -> Result<()> {
    let lift = number(u, 0.0, 0.1)?;
    out.push_str(&format!(
        "<Body name=\"B{i}\" type=\"dynamic\"><Translation>0 {y} {lift}</Translation>"
    ));
    let shape = match u.int_in_range(0..=2_u8)? {
        0 => format!(
            "<Geom type=\"box\"><Extents>{}</Extents></Geom>",
            numbers(u, 3, 0.001, 0.1)?
        ),
        1 => format!(
            "<Geom type=\"sphere\"><Radius>{}</Radius></Geom>",
            number(u, 0.001, 0.1)?
        ),
        _ => format!(
            "<Geom type=\"cylinder\"><Radius>{}</Radius><Height>{}</Height></Geom>",
            number(u, 0.001, 0.1)?,
            number(u, 0.001, 0.2)?
        ),
    };
    out.push_str(&shape);
    out.push_str(&format!(
        "<Mass type=\"mimicgeom\"><total>{}</total>",
        number(u, 0.001, 2.0)?
    ));
    if u.ratio(1, 3)? {
        out.push_str(&format!("<com>{}</com>", numbers(u, 3, -0.05, 0.05)?));
    }
    if u.ratio(1, 3)? {
        let (a, b, c) = (
            number(u, 1e-6, 1e-2)?,
            number(u, 1e-6, 1e-2)?,
            number(u, 1e-6, 1e-2)?,
        );
        let (p, q, r) = (
            number(u, -1e-3, 1e-3)?,
            number(u, -1e-3, 1e-3)?,
            number(u, -1e-3, 1e-3)?,
        );
        out.push_str(&format!(
            "<inertia>{a} {p} {q} {p} {b} {r} {q} {r} {c}</inertia>"
        ));
    }
    out.push_str("</Mass></Body>");
    Ok(())
}

/// The hinge `J{i}` between bodies `i - 1` and `i`.
fn hinge(u: &mut Unstructured, i: usize, out: &mut String) -> Result<()> {
    let axis = match u.int_in_range(0..=3_u8)? {
        0 => "1 0 0".to_string(),
        1 => "0 0 1".to_string(),
        _ => numbers(u, 3, -1.0, 1.0)?,
    };
    let lo = number(u, -180.0, 0.0)?;
    let hi = number(u, 0.0, 180.0)?;
    out.push_str(&format!(
        "<Joint type=\"hinge\" name=\"J{i}\"><Body>B{}</Body><Body>B{i}</Body>\
         <offsetfrom>B{i}</offsetfrom><anchor>{}</anchor><axis>{axis}</axis>\
         <maxtorque>{}</maxtorque><maxvel>{}</maxvel><limitsdeg>{lo} {hi}</limitsdeg></Joint>",
        i - 1,
        numbers(u, 3, -0.05, 0.05)?,
        number(u, 0.01, 5.0)?,
        number(u, 0.1, 10.0)?
    ));
    Ok(())
}

/// The robot file and its joint count.
fn robot(u: &mut Unstructured) -> Result<(String, usize)> {
    let bodies = u.int_in_range(1..=MAX_BODIES)?;
    let spacing = number(u, 0.02, 0.2)?;
    let mut out = String::from("<Robot name=\"fuzz\"><KinBody name=\"kfuzz\">");
    for i in 0..bodies {
        body(u, i, spacing * i as f64, &mut out)?;
    }
    for i in 1..bodies {
        hinge(u, i, &mut out)?;
    }
    out.push_str("</KinBody></Robot>");
    Ok((out, bodies - 1))
}

/// The simulation around a robot of `joints` hinges: a sine on each, the demo's floor.
fn simulation(joints: usize) -> (String, String) {
    let modules = if joints == 0 {
        String::new()
    } else {
        format!(
            "<actuationModule name=\"PatternGenerator_sinusoidal\">\
             <jointConfiguration joints=\"{}\"/><parameter name=\"Amplitude\" value=\"30\"/>\
             <parameter name=\"Frequency\" value=\"1\"/></actuationModule>",
            "1".repeat(joints)
        )
    };
    (
        "<simulation><robot>fuzz.robot.xml</robot><actuation>fuzz.actuation.xml</actuation>\
         <environment>environments/flat.env.xml</environment><simulationProperties>\
         <stepWidth>0.001</stepWidth><duration>1</duration><seed>1</seed>\
         </simulationProperties></simulation>"
            .to_string(),
        format!("<actuation>{modules}</actuation>"),
    )
}

/// The MJCF file this process writes.
fn mjcf_out() -> &'static Path {
    static OUT: OnceLock<PathBuf> = OnceLock::new();
    OUT.get_or_init(|| {
        std::env::temp_dir().join(format!("proleg-fuzz-mjcf-{}.xml", std::process::id()))
    })
}

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let mut u = Unstructured::new(data);
    let Ok((robot, joints)) = robot(&mut u) else {
        return;
    };
    crate::round_trip(&robot, parse_robot_file, write_robot_file);
    let (top, actuation) = simulation(joints);
    let mut src = crate::source_with("fuzz.robot.xml", &robot);
    src.insert(format!("{}/fuzz.simulation.xml", crate::ROOT), &top);
    src.insert(format!("{}/fuzz.actuation.xml", crate::ROOT), &actuation);
    let path = format!("{}/fuzz.simulation.xml", crate::ROOT);
    let Ok(sim) = load_simulation_with(&src, Path::new(&path), crate::registry()) else {
        return;
    };
    if let Err(e) = export_mjcf(&sim, mjcf_out()) {
        panic!("proleg accepted the robot but MuJoCo refuses it: {e}\n{robot}");
    }
    crate::run_briefly(&sim);
}

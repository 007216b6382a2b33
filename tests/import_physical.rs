//! Imported robots behave physically: they come to rest on the floor (`proleg settle`) on
//! both engines, massless links are no anchors, a `world` root is a fixed base, COLLADA
//! collision meshes are read, exports load in MuJoCo, and every fault of a file is named
//! with its line.

mod common;

use std::path::{Path, PathBuf};

use proleg::cli::interop::{export_mjcf, import, settle};
use proleg::config::environment::Articulation;
use proleg::config::simulation::EngineKind;
use proleg::control::{ModuleRegistry, load_simulation_in};
use proleg::sim::settle::SettleReport;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A link of 1 kg with a 10 cm box (or `geom`) colliding.
fn link(name: &str, geom: &str) -> String {
    format!(
        "<link name=\"{name}\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" \
         ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>\
         <collision><geometry>{geom}</geometry></collision></link>"
    )
}

const BOX: &str = "<box size=\"0.1 0.1 0.1\"/>";

/// A revolute joint about y, 10 cm along x from its parent.
fn hinge(name: &str, parent: &str, child: &str) -> String {
    format!(
        "<joint name=\"{name}\" type=\"revolute\"><parent link=\"{parent}\"/><child link=\"{child}\"/>\
         <origin xyz=\"0.12 0 0\"/><axis xyz=\"0 1 0\"/>\
         <limit lower=\"-1\" upper=\"1\" effort=\"5\" velocity=\"3\"/></joint>"
    )
}

/// The engines here: rapier, and MuJoCo where its library is.
fn engines(test: &str) -> Vec<EngineKind> {
    let mut e = vec![EngineKind::Rapier];
    if common::mujoco_here(test) {
        e.push(EngineKind::Mujoco);
    }
    e
}

/// Imports `text` as `name.urdf` and settles it for `seconds` on `engine`.
fn import_and_settle(
    dir: &Path,
    name: &str,
    text: &str,
    engine: EngineKind,
    seconds: f64,
) -> (proleg::cli::interop::ImportReport, SettleReport) {
    let registry = ModuleRegistry::standard();
    let out = dir.join(format!("{name}-out"));
    let report = import(&write(dir, &format!("{name}.urdf"), text), &out, &registry)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let sim = report
        .import
        .simulation_file
        .clone()
        .expect("simulation file");
    let settled = settle(&sim, seconds, Some(engine), "", &registry)
        .unwrap_or_else(|e| panic!("{name} on {engine}: {e}"));
    (report, settled)
}

#[test]
fn a_massless_link_between_two_hinges_is_no_anchor_and_the_robot_settles() {
    // human's and romeo's chains: a link with neither <inertial> nor geometry between two
    // hinges. It was given 0.001 kg and no inertia: rapier held it (and the robot) in the
    // air and the next joint barely moved.
    let dir = common::scratch("urdf-massless");
    let text = format!(
        "<robot name=\"chain\">{}<link name=\"ghost\"/>{}{}{}</robot>",
        link("base", "<box size=\"0.3 0.3 0.05\"/>"),
        link("arm", BOX),
        hinge("j1", "base", "ghost"),
        hinge("j2", "ghost", "arm").replace("0.12 0 0", "0 0 0"),
    );
    for engine in engines("a massless link on MuJoCo") {
        let (report, settled) = import_and_settle(&dir, "chain", &text, engine, 2.0);
        assert!(
            report
                .import
                .warnings
                .iter()
                .any(|w| w.contains("link ghost: no <inertial> mass and no geometry")),
            "{:#?}",
            report.import.warnings
        );
        assert!(settled.settled(), "{engine}: {settled}");
        // The import itself said so.
        let own = report.settle.as_ref().expect("settled at import");
        assert!(own.settled(), "{own}");
        assert!(
            report.to_string().contains("proleg settle: settled"),
            "{report}"
        );
    }
    // Its mass and inertia are in the robot file, where `proleg check` sees them.
    let robot = std::fs::read_to_string(dir.join("chain-out/chain.robot.xml")).unwrap();
    let ghost = &robot[robot.find("name=\"ghost\"").unwrap()..];
    let ghost = &ghost[..ghost.find("</Body>").unwrap()];
    assert!(
        ghost.contains("<total>0.01</total>") && ghost.contains("<inertia>"),
        "{ghost}"
    );
}

#[test]
fn a_world_root_is_a_fixed_base_and_its_export_loads_in_mujoco() {
    // The URDF convention of UR arms, xarm7, z1: a link named world fixes the base. It was
    // a floating robot, and its MJCF held a second body named world.
    let dir = common::scratch("urdf-world");
    let text = format!(
        "<robot name=\"arm\"><link name=\"world\"/>{}{}\
         <joint name=\"fix\" type=\"fixed\"><parent link=\"world\"/><child link=\"base\"/></joint>{}</robot>",
        link("base", "<box size=\"0.1 0.1 0.1\"/>"),
        link("upper", "<box size=\"0.2 0.05 0.05\"/>"),
        hinge("shoulder", "base", "upper").replace("0.12 0 0", "0.15 0 0.3"),
    );
    let registry = ModuleRegistry::standard();
    for engine in engines("a fixed base on MuJoCo") {
        let (report, settled) = import_and_settle(&dir, "arm", &text, engine, 1.0);
        assert!(settled.settled(), "{engine}: {settled}");
        // The base did not move: the shoulder hinge held the arm up off the floor, 30 cm.
        let sim_file = report.import.simulation_file.unwrap();
        let sim = load_simulation_in(&sim_file, &registry).unwrap();
        assert!(sim.robot.links[0].fixed && sim.robot.links[0].name == "world");
        assert!(!sim.robot.links[1].fixed);
    }
    let robot = std::fs::read_to_string(dir.join("arm-out/arm.robot.xml")).unwrap();
    assert!(
        robot.contains("<Body name=\"world\" type=\"static\">"),
        "{robot}"
    );
    let out = dir.join("arm.mjcf.xml");
    let export = export_mjcf(
        &dir.join("arm-out/arm.simulation.xml"),
        &out,
        None,
        None,
        &registry,
    )
    .unwrap();
    let mjcf = std::fs::read_to_string(&out).unwrap();
    assert!(
        !mjcf.contains("name=\"world\"") && mjcf.contains("name=\"robot_world\""),
        "{mjcf}"
    );
    // The fixed base hangs on the world without a joint; the hinge is the only joint.
    assert_eq!(mjcf.matches("<freejoint").count(), 0, "{mjcf}");
    if common::mujoco_here("an export loaded by MuJoCo") {
        assert!(export.export.loaded_by_mujoco);
    }
}

#[test]
fn an_export_mujoco_refuses_is_an_error_with_mujocos_message() {
    if !common::mujoco_here("MuJoCo refusing a file") {
        return;
    }
    let dir = common::scratch("mjcf-refused");
    let bad = write(
        &dir,
        "bad.xml",
        "<mujoco><worldbody><body name=\"world\"><geom size=\"0.1\"/></body></worldbody></mujoco>",
    );
    let e = proleg::sim::engine::mujoco::check_mjcf_file(&bad).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("bad.xml") && text.contains("repeated name 'world'"),
        "{text}"
    );
    let good = write(
        &dir,
        "good.xml",
        "<mujoco><worldbody><body name=\"b\"><freejoint/><geom size=\"0.1\"/></body></worldbody></mujoco>",
    );
    proleg::sim::engine::mujoco::check_mjcf_file(&good).unwrap();
}

/// A COLLADA cube of 10 units written in centimetres (`<unit meter="0.01"/>`), triangles
/// only, as DAE collision meshes of example-robot-data are.
fn dae_cube() -> String {
    let v = "0 0 0 10 0 0 10 10 0 0 10 0 0 0 10 10 0 10 10 10 10 0 10 10";
    let tris = "0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7";
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="0.01" name="centimeter"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="cube" name="cube"><mesh>
      <source id="cube-pos">
        <float_array id="cube-pos-array" count="24">{v}</float_array>
        <technique_common><accessor source="#cube-pos-array" count="8" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
      <triangles count="12"><input semantic="VERTEX" source="#cube-vtx" offset="0"/><p>{tris}</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="n"><instance_geometry url="#cube"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##
    )
}

#[test]
fn dae_collision_meshes_are_read_in_their_unit_and_the_robot_rests_on_them() {
    // kinova's collision meshes are DAE: they were skipped and the robot fell to z = -44 m.
    let dir = common::scratch("urdf-dae");
    write(&dir, "cube.dae", &dae_cube());
    let text = format!(
        "<robot name=\"dae\">{}{}{}</robot>",
        link("a", "<mesh filename=\"cube.dae\"/>"),
        link("b", "<mesh filename=\"cube.dae\" scale=\"2 1 1\"/>"),
        hinge("j", "a", "b"),
    );
    for engine in engines("a DAE robot on MuJoCo") {
        let (report, settled) = import_and_settle(&dir, "dae", &text, engine, 1.0);
        assert_eq!(report.import.meshes, 2, "{}", report.import);
        assert!(settled.settled(), "{engine}: {settled}");
    }
    // 10 cm, scaled by 2 along x: the written OBJ is in metres.
    let obj = std::fs::read_to_string(dir.join("dae-out/meshes/cube_2.obj")).unwrap();
    let xs: Vec<f64> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split_whitespace().next().unwrap().parse().unwrap())
        .collect();
    let max = xs.iter().copied().fold(f64::MIN, f64::max);
    assert!((max - 0.2).abs() < 1e-6, "{obj}");
}

/// `sim`'s environment with the robot's start lifted by `dz` metres, as a new simulation.
fn moved(sim: &Path, dz: f64) -> PathBuf {
    let dir = sim.parent().unwrap();
    let stem = sim
        .file_name()
        .unwrap()
        .to_str()
        .unwrap()
        .replace(".simulation.xml", "");
    let env = std::fs::read_to_string(dir.join(format!("{stem}.env.xml"))).unwrap();
    let start = env.find("<RobotPose>").unwrap();
    let t = start + env[start..].find("<Translation>0 0 ").unwrap() + "<Translation>0 0 ".len();
    let end = t + env[t..].find('<').unwrap();
    let z: f64 = env[t..end].parse().unwrap();
    let env = format!("{}{}{}", &env[..t], z + dz, &env[end..]);
    write(dir, &format!("{stem}-moved.env.xml"), &env);
    let text = std::fs::read_to_string(sim)
        .unwrap()
        .replace(&format!("{stem}.env.xml"), &format!("{stem}-moved.env.xml"));
    write(dir, &format!("{stem}-moved.simulation.xml"), &text)
}

#[test]
fn settle_tells_a_robot_through_the_floor_and_one_held_in_the_air() {
    let dir = common::scratch("urdf-settle");
    let registry = ModuleRegistry::standard();
    let text = format!(
        "<robot name=\"two\">{}{}{}</robot>",
        link("a", BOX),
        link("b", BOX),
        hinge("j", "a", "b")
    );
    let (report, settled) = import_and_settle(&dir, "two", &text, EngineKind::Rapier, 1.0);
    assert!(settled.settled(), "{settled}");
    let sim = report.import.simulation_file.unwrap();
    // Started 30 cm under the floor's top, it falls on: "sank".
    let under = settle(&moved(&sim, -0.3), 1.0, None, "", &registry).unwrap();
    assert!(
        !under.settled() && under.to_string().contains("sank through the floor"),
        "{under}"
    );
    // A fixed base half a metre up holds the robot in the air: "hangs".
    let arm = format!(
        "<robot name=\"high\"><link name=\"world\"/>{}{}\
         <joint name=\"fix\" type=\"fixed\"><parent link=\"world\"/><child link=\"a\"/></joint>{}</robot>",
        link("a", BOX),
        link("b", BOX),
        hinge("j", "a", "b")
    );
    let (report, settled) = import_and_settle(&dir, "high", &arm, EngineKind::Rapier, 0.5);
    assert!(settled.settled(), "{settled}");
    let sim = report.import.simulation_file.unwrap();
    let high = settle(&moved(&sim, 0.5), 0.5, None, "", &registry).unwrap();
    assert!(
        !high.settled() && high.to_string().contains("hangs above the floor"),
        "{high}"
    );
    // The command exits 1 with the verdict.
    let (ok, _, err) = common::proleg(&["settle", moved(&sim, 0.5).to_str().unwrap()]);
    assert!(!ok && err.contains("NOT settled"), "{err}");
}

#[test]
fn a_robot_without_any_geometry_is_refused_by_check_even_when_imported() {
    let dir = common::scratch("urdf-nogeom");
    let text = "<robot name=\"ghost\"><link name=\"a\"><inertial><mass value=\"1\"/>\
        <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>\
        <visual><geometry><box size=\"0.1 0.1 0.1\"/></geometry></visual></link></robot>";
    let urdf = write(&dir, "ghost.urdf", text);
    let out = dir.join("out");
    let (ok, stdout, err) = common::proleg(&[
        "import",
        urdf.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--allow-no-collision",
    ]);
    assert!(
        ok && stdout.contains("proleg check refuses the files written"),
        "{err}"
    );
    let sim = out.join("ghost.simulation.xml");
    let (ok, _, err) = common::proleg(&["check", sim.to_str().unwrap()]);
    assert!(
        !ok && err.contains("ghost.robot.xml") && err.contains("the robot has no geometry"),
        "{err}"
    );
}

#[test]
fn irrelevant_visual_details_never_refuse_a_robot_and_faults_name_their_line() {
    let dir = common::scratch("urdf-parser");
    let registry = ModuleRegistry::standard();
    // icub's empty <texture/> in a visual material: "missing field 'filename'" refused it.
    let text = format!(
        "<robot name=\"tex\">\n{}\n<link name=\"b\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>\n\
         <visual><geometry><box size=\"0.1 0.1 0.1\"/></geometry><material name=\"m\"><texture/></material></visual>\n\
         <visual><geometry><mesh/></geometry></visual>\n\
         <collision><geometry>{BOX}</geometry></collision></link>\n{}\n</robot>",
        link("a", BOX),
        hinge("j", "a", "b")
    );
    let report = import(&write(&dir, "tex.urdf", &text), &dir.join("tex"), &registry).unwrap();
    assert!(
        report.import.warnings.iter().any(|w| w
            .contains("link b: its <visual> at line 5 is not drawn")
            && w.contains("<mesh> has no filename")),
        "{:#?}",
        report.import.warnings
    );
    // Structural faults: every one, with its element and line.
    let broken = "<robot name=\"x\">\n<link name=\"a\"/>\n<link/>\n\
        <joint name=\"j\" type=\"hinge\">\n<parent link=\"a\"/>\n<child/>\n</joint>\n</robot>";
    let e = import(
        &write(&dir, "broken.urdf", broken),
        &dir.join("b"),
        &registry,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("broken.urdf")
            && e.contains("line 3: <link> has no name")
            && e.contains("line 4: <joint> type=\"hinge\" is not a joint type")
            && e.contains("line 6: <child> has no link"),
        "{e}"
    );
    // Elements that are not URDF's (Gazebo's, transmissions) are not checked.
    let gazebo = format!(
        "<robot name=\"g\">{}<transmission><joint name=\"j\"/></transmission>\
         <gazebo reference=\"a\"><material>Gazebo/Black</material></gazebo></robot>",
        link("a", BOX)
    );
    import(&write(&dir, "g.urdf", &gazebo), &dir.join("g"), &registry).unwrap();
}

#[test]
fn check_reports_every_physical_fault_of_a_robot_file_with_its_line() {
    let dir = common::scratch("robot-physical");
    let registry = ModuleRegistry::standard();
    let robot = "<?xml version=\"1.0\"?>\n<Robot name=\"bad\">\n<KinBody name=\"bad\">\n\
        <Body name=\"a\" type=\"dynamic\"><Geom type=\"box\"><extents>0.05 0.05 0.05</extents></Geom>\n\
        <Mass type=\"custom\"><total>1</total><inertia>1 0 0 0 1 0 0 0 3</inertia></Mass></Body>\n\
        <Body name=\"ghost\" type=\"dynamic\"/>\n\
        <Body name=\"c\" type=\"static\"><Geom type=\"box\"><extents>0.05 0.05 0.05</extents></Geom></Body>\n\
        <Joint type=\"hinge\" name=\"j1\"><Body>a</Body><Body>ghost</Body><axis>0 1 0</axis></Joint>\n\
        <Joint type=\"hinge\" name=\"j2\"><Body>ghost</Body><Body>c</Body><axis>0 1 0</axis></Joint>\n\
        </KinBody>\n</Robot>\n";
    write(&dir, "bad.robot.xml", robot);
    write(
        &dir,
        "bad.actuation.xml",
        "<actuation><validRobot robotName=\"bad.robot.xml\"/></actuation>",
    );
    let sim = write(
        &dir,
        "bad.simulation.xml",
        "<simulation><robot>bad.robot.xml</robot><actuation>bad.actuation.xml</actuation>\
         <simulationProperties><stepWidth>0.001</stepWidth><duration>1</duration></simulationProperties></simulation>",
    );
    let e = load_simulation_in(&sim, &registry).unwrap_err().to_string();
    assert!(
        e.contains("bad.robot.xml:5:")
            && e.contains("body a: <inertia>: principal moments")
            && e.contains("bad.robot.xml:6:")
            && e.contains("body ghost has no geometry and no <Mass>")
            && e.contains("bad.robot.xml:7:")
            && e.contains("body c is static (fixed to the world), yet joint j2 moves it"),
        "{e}"
    );
}

/// allegro's build: a 0.4 kg palm whose centre of mass lies 9.5 cm from its box (among the
/// fingers), four fingers of four 12-35 g links, 15 N m servos.
fn light_hand() -> String {
    let link = |name: &str, mass: f64, size: [f64; 3], com: f64| {
        let i = |a: f64, b: f64| mass * (a * a + b * b) / 12.0;
        let [x, y, z] = size;
        let (ixx, iyy, izz) = if name == "palm" {
            (1e-4, 1e-4, 1e-4)
        } else {
            (i(y, z), i(x, z), i(x, y))
        };
        let geom = if name == "palm" { -0.0475 } else { com };
        format!(
            "<link name=\"{name}\"><inertial><origin xyz=\"0 0 {com}\"/><mass value=\"{mass}\"/>\
             <inertia ixx=\"{ixx}\" ixy=\"0\" ixz=\"0\" iyy=\"{iyy}\" iyz=\"0\" izz=\"{izz}\"/>\
             </inertial><collision><origin xyz=\"0 0 {geom}\"/><geometry>\
             <box size=\"{x} {y} {z}\"/></geometry></collision></link>"
        )
    };
    let mut urdf = format!(
        "<robot name=\"hand\">{}",
        link("palm", 0.4, [0.04, 0.11, 0.095], 0.0475)
    );
    for (f, y) in [-0.045, -0.015, 0.015, 0.045].into_iter().enumerate() {
        let (mut parent, mut z) = ("palm".to_string(), 0.0);
        for (k, (mass, h)) in [
            (0.012, 0.016),
            (0.035, 0.054),
            (0.035, 0.038),
            (0.026, 0.027),
        ]
        .into_iter()
        .enumerate()
        {
            let name = format!("f{f}l{k}");
            let (at, axis) = if k == 0 { (y, "0 0 1") } else { (0.0, "0 1 0") };
            urdf += &link(&name, mass, [0.0196, 0.0275, h], h / 2.0);
            urdf += &format!(
                "<joint name=\"f{f}j{k}\" type=\"revolute\"><parent link=\"{parent}\"/>\
                 <child link=\"{name}\"/><origin xyz=\"0 {at} {z}\"/><axis xyz=\"{axis}\"/>\
                 <limit lower=\"-0.5\" upper=\"1.6\" effort=\"15\" velocity=\"7\"/></joint>"
            );
            (parent, z) = (name, h);
        }
    }
    urdf + "</robot>"
}

#[test]
fn a_hand_that_shakes_apart_as_maximal_joints_is_imported_with_reduced_ones_and_rests() {
    // allegro's hands and pybullet's quadruped: light links under strong servos. As rapier
    // impulse joints (maximal coordinates) they shook at 6-14 m/s with the joints held, and
    // the import called the hand settled when a finger touched the floor by chance.
    let dir = common::scratch("urdf-light-hand");
    let registry = ModuleRegistry::standard();
    let (report, _) = import_and_settle(&dir, "hand", &light_hand(), EngineKind::Rapier, 2.0);
    assert_eq!(report.articulation, Some(Articulation::Reduced), "{report}");
    let sim_file = report.import.simulation_file.clone().expect("simulation");
    let env = std::fs::read_to_string(dir.join("hand-out/hand.env.xml")).unwrap();
    assert!(
        env.contains("<articulation>reduced</articulation>"),
        "{env}"
    );
    // What the import chose is what every run of the files gets, on both engines.
    for engine in engines("the light hand on MuJoCo") {
        let r = settle(&sim_file, 2.0, Some(engine), "", &registry).unwrap();
        assert!(r.at_rest(), "{engine}: {r}");
    }
    // Why: the same robot with maximal-coordinate joints does not come to rest.
    let mut sim = load_simulation_in(&sim_file, &registry).unwrap();
    sim.environment.physics.articulation = Articulation::Maximal;
    let opts = proleg::sim::BuildOptions {
        record: false,
        ..Default::default()
    };
    let maximal = proleg::sim::settle::settle(&sim, 2.0, &opts, &registry).unwrap();
    assert!(!maximal.at_rest(), "{maximal}");
}

#[test]
fn reduced_articulation_drives_the_servos_as_maximal_does() {
    // `<articulation>reduced</articulation>`: the hinges as rapier's multibody joints. The
    // servos must read and drive them the same way: the demo crawls forward and its joints
    // follow their targets with either articulation.
    let registry = ModuleRegistry::standard();
    let mut sim = load_simulation_in(
        common::root().join("configs/demo.simulation.xml"),
        &registry,
    )
    .unwrap();
    for articulation in [Articulation::Maximal, Articulation::Reduced] {
        sim.environment.physics.articulation = articulation;
        let opts = proleg::sim::BuildOptions::default();
        let mut s = proleg::sim::Simulator::with_registry(&sim, &opts, &registry).unwrap();
        let start = s.com(0).unwrap();
        // The mean tracking error over the last of three seconds (the start is a transient).
        let mut late = 0.0_f64;
        for k in 0..3000 {
            s.step();
            if k >= 2000 {
                late += s.tracking_error(0).unwrap() / 1000.0;
            }
        }
        let moved = proleg::measure::ground_distance(start, s.com(0).unwrap());
        assert!(
            moved > 0.1 && late < 12.0,
            "{articulation:?}: moved {moved} m, mean tracking error {late} deg"
        );
        eprintln!("{articulation:?}: moved {moved:.3} m, tracking error {late:.2} deg");
    }
}

/// kinova's build: an arm on a base box whose links' frames turn about their joints' axes,
/// two joints starting outside their limits (46..178 deg, 29..178 deg), slow strong servos.
const TWISTED_ARM: &str = r#"<robot name="arm">
<link name="base"><inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.0004"/></inertial>
<collision><origin xyz="0 0 0.05"/><geometry><box size="0.12 0.12 0.1"/></geometry></collision></link>
<link name="l1"><inertial><origin xyz="0 0 0.1"/><mass value="0.8"/><inertia ixx="0.003" ixy="0" ixz="0" iyy="0.003" iyz="0" izz="0.0006"/></inertial>
<collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.04" length="0.2"/></geometry></collision></link>
<link name="l2"><inertial><origin xyz="0 0 0.15"/><mass value="0.7"/><inertia ixx="0.005" ixy="0" ixz="0" iyy="0.005" iyz="0" izz="0.0004"/></inertial>
<collision><origin xyz="0 0 0.15"/><geometry><cylinder radius="0.035" length="0.3"/></geometry></collision></link>
<link name="l3"><inertial><origin xyz="0 0 0.1"/><mass value="0.5"/><inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.0002"/></inertial>
<collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.03" length="0.2"/></geometry></collision></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1" rpy="0 0 1.2"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="40" velocity="0.6"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.2" rpy="1.5708 0.4 0"/><axis xyz="0 0 1"/><limit lower="0.8" upper="3.1" effort="80" velocity="0.6"/></joint>
<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0 0.3 0" rpy="-1.5708 0 0.7"/><axis xyz="0 0 1"/><limit lower="0.5" upper="3.1" effort="40" velocity="0.6"/></joint>
</robot>"#;

#[test]
fn joints_outside_their_limits_are_brought_in_by_their_servos_on_every_articulation() {
    // kinova's arm: rapier completed each body's joint frame from the axis alone, so links
    // turned about the axis started at a nonzero rapier angle: its limits sat off the
    // joint's own, and as multibody joints the arm flew apart at 250 m/s in the first step
    // and rapier then panicked on a NaN joint coordinate. A joint starting outside its
    // limits was snapped in by the limit within a step.
    let dir = common::scratch("urdf-twisted-arm");
    let registry = ModuleRegistry::standard();
    let out = dir.join("arm-out");
    import(&write(&dir, "arm.urdf", TWISTED_ARM), &out, &registry).unwrap();
    let mut sim = load_simulation_in(out.join("arm.simulation.xml"), &registry).unwrap();
    let hold: Vec<f64> = sim
        .robot
        .joints
        .iter()
        .map(|j| 0.0_f64.clamp(j.limits_deg[0], j.limits_deg[1]))
        .collect();
    let mut runs = vec![
        (EngineKind::Rapier, Articulation::Maximal),
        (EngineKind::Rapier, Articulation::Reduced),
    ];
    if common::mujoco_here("the twisted arm on MuJoCo") {
        runs.push((EngineKind::Mujoco, Articulation::Reduced));
    }
    for (engine, articulation) in runs {
        sim.environment.physics.articulation = articulation;
        let opts = proleg::sim::BuildOptions {
            engine: engine.into(),
            record: false,
            ..Default::default()
        };
        let mut s = proleg::sim::Simulator::with_registry(&sim, &opts, &registry).unwrap();
        s.set_joint_override(0, Some(hold.clone())).unwrap();
        // 46 deg at 0.6 rad/s take 1.3 s; the arm then topples and comes to rest.
        s.run_steps(5000);
        let angles: Vec<f64> = s.joint_states(0).unwrap().iter().map(|j| j.angle).collect();
        for (a, h) in angles.iter().zip(&hold) {
            assert!(
                (a - h).abs() < 2.0,
                "{engine} {articulation:?}: angles {angles:?}, held at {hold:?}"
            );
        }
        let r = proleg::sim::settle::settle(&sim, 5.0, &opts, &registry).unwrap();
        assert!(r.at_rest(), "{engine} {articulation:?}: {r}");
    }
}

#[test]
fn a_collision_mesh_placed_away_from_its_visual_copy_is_named_with_both_lines() {
    // alex_nub_hands: each nub's <collision> has xyz="0 1.57 0" where its <visual> has
    // rpy="0 1.57 0"; the humanoid leaned on phantom nubs 1.57 m beside its hands.
    let dir = common::scratch("urdf-misplaced-collision");
    let registry = ModuleRegistry::standard();
    write(
        &dir,
        "nub.obj",
        "v 0 0 0\nv 0.04 0 0\nv 0 0.04 0\nv 0 0 0.04\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    );
    let nub = |collision_origin: &str| {
        format!(
            "<robot name=\"hand\">\n{}\n<link name=\"nub\"><inertial><mass value=\"0.3\"/><inertia ixx=\"0.001\" ixy=\"0\" ixz=\"0\" iyy=\"0.001\" iyz=\"0\" izz=\"0.001\"/></inertial>\n\
             <visual><origin rpy=\"0 1.57 0\" xyz=\"0 0 0\"/><geometry><mesh filename=\"nub.obj\"/></geometry></visual>\n\
             <collision>{collision_origin}<geometry><mesh filename=\"nub.obj\"/></geometry></collision>\n\
             </link>\n{}\n</robot>",
            link("palm", BOX),
            hinge("j", "palm", "nub")
        )
    };
    let swapped = import(
        &write(
            &dir,
            "swapped.urdf",
            &nub("<origin xyz=\"0 1.57 0\" rpy=\"0 0 0\"/>"),
        ),
        &dir.join("swapped"),
        &registry,
    )
    .unwrap();
    let w = swapped
        .import
        .warnings
        .iter()
        .find(|w| w.contains("<collision> mesh nub.obj"))
        .unwrap_or_else(|| panic!("{:#?}", swapped.import.warnings));
    assert!(
        w.starts_with("line 5: link nub:")
            && w.contains("lies 1.570 m from the <visual> of the same mesh (line 4)")
            && w.contains("its xyz (0 1.57 0) is the visual's rpy"),
        "{w}"
    );
    // The copies overlapping (a 1 cm offset on a 4 cm mesh): nothing to say.
    let near = import(
        &write(&dir, "near.urdf", &nub("<origin xyz=\"0.01 0 0\"/>")),
        &dir.join("near"),
        &registry,
    )
    .unwrap();
    assert!(
        near.import
            .warnings
            .iter()
            .all(|w| !w.contains("<collision> mesh")),
        "{:#?}",
        near.import.warnings
    );
}

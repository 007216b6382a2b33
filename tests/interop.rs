//! URDF import and MJCF export against files and engines we did not write: URDFs from
//! pybullet's `pybullet_data` and MuJoCo, both from the Python registry (`scripts/test`
//! installs them and sets PROLEG_PYTHON).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use proleg::cli::interop::{export_mjcf, import};
use proleg::control::{ModuleRegistry, load_simulation_in};
use proleg::sim::{BuildOptions, Simulator};

fn python() -> String {
    std::env::var("PROLEG_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// Runs Python code or a script; panics with its output when it fails.
fn run_python(args: &[&str]) -> String {
    let out = Command::new(python()).args(args).output().expect("python");
    assert!(
        out.status.success(),
        "{} {args:?} failed (scripts/test installs pybullet and mujoco and sets PROLEG_PYTHON):\n{}",
        python(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn pybullet_data() -> PathBuf {
    let path = run_python(&[
        "-c",
        "import pybullet_data; print(pybullet_data.getDataPath())",
    ]);
    PathBuf::from(path.trim())
}

/// One real URDF: what it holds and what the import must make of it.
struct Case {
    file: &'static str,
    links: usize,
    joints: usize,
    bodies: usize,
    hinges: usize,
    meshes: usize,
    warning: &'static str,
}

const CASES: &[Case] = &[
    // Boxes, cylinders, spheres, STL gripper meshes; fixed, continuous and prismatic joints.
    Case {
        file: "r2d2.urdf",
        links: 16,
        joints: 15,
        bodies: 8,
        hinges: 7,
        meshes: 2,
        warning: "gripper_extension: a Prismatic joint",
    },
    // OBJ meshes, inertials with rotated origins, fixed toes merged into the legs.
    Case {
        file: "laikago/laikago_toes_zup.urdf",
        links: 17,
        joints: 16,
        bodies: 13,
        hinges: 12,
        meshes: 6,
        warning: "continuous, limited to +-180 deg",
    },
    // STL collision meshes, joint damping.
    Case {
        file: "kuka_iiwa/model.urdf",
        links: 8,
        joints: 7,
        bodies: 8,
        hinges: 7,
        meshes: 8,
        warning: "damping 0.5",
    },
    // package:// mesh paths, limits beyond +-180 deg.
    Case {
        file: "xarm/xarm6_robot.urdf",
        links: 8,
        joints: 7,
        bodies: 7,
        hinges: 6,
        meshes: 7,
        warning: "cut to -180..180",
    },
    // Spherical joints and capsules.
    Case {
        file: "humanoid/humanoid.urdf",
        links: 16,
        joints: 15,
        bodies: 5,
        hinges: 4,
        meshes: 0,
        warning: "a capsule",
    },
];

#[test]
fn real_urdfs_import_check_and_run_a_sine_without_blowing_up() {
    let data = pybullet_data();
    let registry = ModuleRegistry::standard();
    for c in CASES {
        let urdf = data.join(c.file);
        let out = common::scratch(&format!("urdf-{}", c.file.replace('/', "-")));
        let report = import(&urdf, &out, &registry).unwrap_or_else(|e| panic!("{}: {e}", c.file));
        let r = &report.import;
        println!(
            "{}: {} links, {} joints -> {} bodies, {} hinges, {} meshes, {} warnings",
            c.file,
            r.urdf_links,
            r.urdf_joints,
            r.bodies,
            r.hinges,
            r.meshes,
            r.warnings.len()
        );
        assert_eq!(
            (r.urdf_links, r.urdf_joints, r.bodies, r.hinges, r.meshes),
            (c.links, c.joints, c.bodies, c.hinges, c.meshes),
            "{}",
            c.file
        );
        assert!(
            r.warnings.iter().any(|w| w.contains(c.warning)),
            "{}: no warning with {:?} in {:#?}",
            c.file,
            c.warning,
            r.warnings
        );
        let sim_file = r.simulation_file.as_ref().expect("a simulation file");
        let sim = load_simulation_in(sim_file, &registry).expect("the import loads");
        assert_eq!(sim.robot.joints.len(), c.hinges);
        let mut s = Simulator::with_registry(&sim, &BuildOptions::default(), &registry).unwrap();
        let mut swing = vec![(f64::INFINITY, f64::NEG_INFINITY); c.hinges];
        for _ in 0..30 {
            s.run_for(0.1);
            for (k, j) in s.joint_states(0).unwrap().iter().enumerate() {
                swing[k] = (swing[k].0.min(j.angle), swing[k].1.max(j.angle));
            }
        }
        let com = s.com(0).unwrap();
        let start = sim.environment.robot_pose.translation;
        assert!(com.iter().all(|v| v.is_finite()), "{}: {com:?}", c.file);
        assert!(
            (com[0] - start[0]).abs() < 2.0
                && (com[1] - start[1]).abs() < 2.0
                && com[2] > -0.2
                && com[2] < 3.0,
            "{}: blew up, centre of mass at {com:?} after 3 s",
            c.file
        );
        let moved = swing.iter().filter(|(lo, hi)| hi - lo > 3.0).count();
        assert!(
            moved > 0,
            "{}: no joint swung more than 3 deg: {swing:?}",
            c.file
        );
    }
}

#[test]
fn imported_masses_and_inertias_are_the_urdfs() {
    let data = pybullet_data();
    let out = common::scratch("urdf-inertia");
    let registry = ModuleRegistry::standard();
    let report = import(&data.join("kuka_iiwa/model.urdf"), &out, &registry).unwrap();
    let text = std::fs::read_to_string(&report.import.robot_file).unwrap();
    let robot = proleg::config::robot::parse_robot_file("kuka", &text).unwrap();
    let link1 = robot
        .kinbody
        .bodies
        .iter()
        .find(|b| b.name == "lbr_iiwa_link_1")
        .unwrap();
    let mass = link1.mass.as_ref().unwrap();
    // model.urdf: mass 4, origin 0 -0.03 0.12, ixx 0.1 iyy 0.09 izz 0.02, no products.
    assert_eq!(mass.total, 4.0);
    let com = mass.com.unwrap();
    assert!(
        (com[1] + 0.03).abs() < 1e-9 && (com[2] - 0.12).abs() < 1e-9,
        "{com:?}"
    );
    let i = mass.inertia.unwrap();
    assert!(
        (i[0] - 0.1).abs() < 1e-9 && (i[4] - 0.09).abs() < 1e-9 && (i[8] - 0.02).abs() < 1e-9,
        "{i:?}"
    );
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const LINK: &str = r#"<link name="NAME"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  <collision><geometry>GEOM</geometry></collision></link>"#;

fn link(name: &str, geom: &str) -> String {
    LINK.replace("NAME", name).replace("GEOM", geom)
}

#[test]
fn bad_urdfs_get_errors_naming_the_file_and_cause() {
    let dir = common::scratch("urdf-bad");
    let registry = ModuleRegistry::standard();
    let out = dir.join("out");
    let broken = write(&dir, "broken.urdf", "<robot name=\"x\"><link name=\"a\">");
    let e = import(&broken, &out, &registry).unwrap_err().to_string();
    assert!(
        e.contains("broken.urdf") && e.contains("not a valid URDF"),
        "{e}"
    );
    let missing = import(&dir.join("nothing.urdf"), &out, &registry)
        .unwrap_err()
        .to_string();
    assert!(
        missing.contains("nothing.urdf") && missing.contains("cannot read"),
        "{missing}"
    );
    let two_roots = format!(
        "<robot name=\"two\">{}{}</robot>",
        link("a", "<box size=\"0.1 0.1 0.1\"/>"),
        link("b", "<box size=\"0.1 0.1 0.1\"/>")
    );
    let e = import(&write(&dir, "two.urdf", &two_roots), &out, &registry)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("exactly one root link") && e.contains("a, b"),
        "{e}"
    );
    let no_mesh = format!(
        "<robot name=\"m\">{}</robot>",
        link("a", "<mesh filename=\"package://nowhere/m.stl\"/>")
    );
    let e = import(&write(&dir, "nomesh.urdf", &no_mesh), &out, &registry)
        .unwrap_err()
        .to_string();
    assert!(e.contains("package \"nowhere\" not found"), "{e}");
}

#[test]
fn what_cannot_be_represented_is_listed_never_dropped_silently() {
    let dir = common::scratch("urdf-warnings");
    let registry = ModuleRegistry::standard();
    let text = format!(
        r#"<robot name="w">{}{}{}
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="2" velocity="3"/></joint>
  <joint name="slide" type="prismatic"><parent link="arm"/><child link="hand"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="0.1" effort="2" velocity="3"/></joint>
</robot>"#,
        link("base", "<box size=\"0.2 0.2 0.1\"/>"),
        link("arm", "<mesh filename=\"arm.ply\"/>"),
        link("hand", "<capsule radius=\"0.02\" length=\"0.1\"/>"),
    );
    let report = import(&write(&dir, "w.urdf", &text), &dir.join("out"), &registry).unwrap();
    let w = report.import.warnings.join("\n");
    for expected in [
        "slide: a Prismatic joint",
        "arm.ply is not OBJ, STL or DAE",
        "hand: a capsule",
    ] {
        assert!(w.contains(expected), "missing {expected:?} in\n{w}");
    }
    let sim = load_simulation_in(report.import.simulation_file.unwrap(), &registry).unwrap();
    let j = &sim.robot.joints[0];
    assert_eq!((j.max_torque, j.max_vel), (2.0, 3.0));
    assert!(
        (j.limits_deg[1] - 1f64.to_degrees()).abs() < 1e-3,
        "{:?}",
        j.limits_deg
    );
}

/// Exports `config` with its gait for `seconds`, replays it in MuJoCo; both displacements.
fn cross_engine(config: &str, seconds: f64, name: &str) -> (f64, f64) {
    let dir = common::scratch(name);
    let out = dir.join(format!("{name}.xml"));
    let report = export_mjcf(
        &common::root().join(config),
        &out,
        Some(seconds),
        None,
        &ModuleRegistry::standard(),
    )
    .unwrap();
    let gait = report.gait.expect("gait");
    let script = common::root().join("scripts/mujoco_gait.py");
    let printed = run_python(&[
        script.to_str().unwrap(),
        out.to_str().unwrap(),
        gait.file.to_str().unwrap(),
    ]);
    let mujoco: f64 = printed
        .split("displacement ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no displacement in {printed:?}"));
    println!(
        "{config}: {seconds} s, proleg {:.4} m, MuJoCo {mujoco:.4} m ({printed})",
        gait.displacement
    );
    (gait.displacement, mujoco)
}

#[test]
fn the_exported_demo_gait_goes_as_far_in_mujoco() {
    let (proleg, mujoco) = cross_engine("configs/demo.simulation.xml", 10.0, "mjcf-demo");
    assert!(proleg > 0.5, "proleg: {proleg}");
    assert!(
        (mujoco - proleg).abs() < 0.3 * proleg,
        "MuJoCo {mujoco:.3} m vs proleg {proleg:.3} m: more than 30 % apart"
    );
}

#[test]
fn a_height_field_terrain_and_an_imported_mesh_robot_load_and_run_in_mujoco() {
    let (proleg, mujoco) = cross_engine(
        "configs/experiment2_sine_only.simulation.xml",
        10.0,
        "mjcf-field",
    );
    assert!(
        proleg > 0.2 && mujoco > 0.2,
        "proleg {proleg}, MuJoCo {mujoco}"
    );
    // Meshes, given inertias and fixed-joint merges through both converters.
    let data = pybullet_data();
    let dir = common::scratch("mjcf-laikago");
    let report = import(
        &data.join("laikago/laikago_toes_zup.urdf"),
        &dir,
        &ModuleRegistry::standard(),
    )
    .unwrap();
    let sim = report.import.simulation_file.unwrap();
    let out = dir.join("laikago.xml");
    let e = export_mjcf(&sim, &out, Some(1.0), None, &ModuleRegistry::standard()).unwrap();
    assert_eq!(e.export.assets, 6);
    let script = common::root().join("scripts/mujoco_gait.py");
    let gait = e.gait.unwrap().file;
    let printed = run_python(&[
        script.to_str().unwrap(),
        out.to_str().unwrap(),
        gait.to_str().unwrap(),
    ]);
    assert!(printed.contains("1000 steps"), "{printed}");
}

/// The centre of mass the simulator reports before the first step, and after it.
fn com_before_and_after_a_step(sim: &proleg::config::Simulation) -> ([f64; 3], [f64; 3]) {
    let registry = ModuleRegistry::standard();
    let opts = BuildOptions::default();
    let mut s = Simulator::with_registry(sim, &opts, &registry).unwrap();
    let before = s.com(0).unwrap();
    s.run_steps(1);
    (before, s.com(0).unwrap())
}

#[test]
fn the_start_centre_of_mass_is_the_links_inertial_one_on_both_engines() {
    // kuka_iiwa: every link's <inertial> origin is off its frame by up to 0.12 m.
    let data = pybullet_data();
    let out = common::scratch("urdf-com");
    let registry = ModuleRegistry::standard();
    let report = import(&data.join("kuka_iiwa/model.urdf"), &out, &registry).unwrap();
    let sim_file = report.import.simulation_file.expect("a simulation file");
    let sim = load_simulation_in(&sim_file, &registry).unwrap();
    let mut engines = vec![proleg::config::simulation::EngineKind::Rapier];
    if common::mujoco_here("the start centre of mass on MuJoCo") {
        engines.push(proleg::config::simulation::EngineKind::Mujoco);
    }
    for engine in engines {
        let (before, after) = com_before_and_after_a_step(&sim.clone().with_engine(Some(engine)));
        // One millisecond moves nothing by a millimetre: the start is where the links'
        // inertial frames put it, as at every later step.
        let gap = proleg::measure::norm([
            after[0] - before[0],
            after[1] - before[1],
            after[2] - before[2],
        ]);
        assert!(
            gap < 1e-3,
            "{engine}: start {before:?}, one step later {after:?}"
        );
    }
}

#[test]
fn inertial_data_no_body_can_have_is_refused_naming_the_link() {
    let dir = common::scratch("urdf-unphysical");
    let registry = ModuleRegistry::standard();
    let out = dir.join("out");
    let with_inertial = |mass: &str, ixx: &str| {
        format!(
            "<robot name=\"u\"><link name=\"base\"><inertial><mass value=\"{mass}\"/>\
             <inertia ixx=\"{ixx}\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>\
             <collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision></link></robot>"
        )
    };
    // A negative mass was a warning and a mass from the geometry.
    let e = import(
        &write(&dir, "neg.urdf", &with_inertial("-1", "0.01")),
        &out,
        &registry,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("neg.urdf")
            && e.contains("link base")
            && e.contains("a mass must be between 0 and 1000000 kg"),
        "{e}"
    );
    // 0.03 > 0.01 + 0.01: no mass distribution has these moments. Real URDFs break the
    // rule by a little (xarm6), so the import balances the tensor and says so.
    let tri = import(
        &write(&dir, "tri.urdf", &with_inertial("1", "0.03")),
        &out,
        &registry,
    )
    .expect("balanced, with a warning");
    assert!(
        tri.import
            .warnings
            .iter()
            .any(|w| w.contains("link base") && w.contains("triangle inequality")),
        "{:#?}",
        tri.import.warnings
    );
    let text = std::fs::read_to_string(&tri.import.robot_file).unwrap();
    proleg::config::robot::parse_robot_file("tri.robot.xml", &text).expect("a physical tensor");
    // An indefinite tensor (a product of inertia larger than the moments).
    let indefinite = with_inertial("1", "0.01").replace("ixy=\"0\"", "ixy=\"0.02\"");
    let e = import(&write(&dir, "indef.urdf", &indefinite), &out, &registry)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 1: link base") && e.contains("not positive semi-definite"),
        "{e}"
    );
    // The same rule for robot files: check refuses such an <inertia> where it stands.
    let good = import(
        &write(&dir, "good.urdf", &with_inertial("1", "0.01")),
        &out,
        &registry,
    )
    .expect("a physical robot imports");
    let text = std::fs::read_to_string(&good.import.robot_file).unwrap();
    let bad = text.replace("0.01 0 0 0 0.01 0 0 0 0.01", "0.03 0 0 0 0.01 0 0 0 0.01");
    assert_ne!(bad, text, "the tensor as written: {text}");
    std::fs::write(&good.import.robot_file, &bad).unwrap();
    let e = load_simulation_in(good.import.simulation_file.unwrap(), &registry)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("good.robot.xml:8:")
            && e.contains("<inertia>")
            && e.contains("triangle inequality"),
        "{e}"
    );
}

#[test]
fn a_joint_starting_outside_its_limits_is_named_and_its_sine_centred_inside() {
    let dir = common::scratch("urdf-knee");
    let registry = ModuleRegistry::standard();
    let out = dir.join("out");
    // A knee bent 30..120 deg: its zero pose is outside the limits.
    let text = format!(
        "<robot name=\"knee\">{}{}<joint name=\"knee\" type=\"revolute\"><parent link=\"thigh\"/>\
         <child link=\"shin\"/><origin xyz=\"0.2 0 0\"/><axis xyz=\"0 1 0\"/>\
         <limit lower=\"0.5236\" upper=\"2.0944\" effort=\"10\" velocity=\"5\"/></joint></robot>",
        link("thigh", "<box size=\"0.2 0.1 0.05\"/>"),
        link("shin", "<box size=\"0.2 0.1 0.05\"/>")
    );
    let report = import(&write(&dir, "knee.urdf", &text), &out, &registry).unwrap();
    assert!(
        report
            .import
            .warnings
            .iter()
            .any(|w| w.contains("joint knee") && w.contains("outside its limits")),
        "{:#?}",
        report.import.warnings
    );
    let sim =
        load_simulation_in(report.import.simulation_file.as_ref().unwrap(), &registry).unwrap();
    let mut s = Simulator::with_registry(&sim, &BuildOptions::default(), &registry).unwrap();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for _ in 0..40 {
        s.run_for(0.1);
        let a = s.joint_states(0).unwrap()[0].angle;
        if s.clock().time() > 1.0 {
            (lo, hi) = (lo.min(a), hi.max(a));
        }
    }
    // After a second it swings inside 30..120 deg instead of pressing on 30.
    assert!(
        lo > 29.0 && hi < 121.0 && hi - lo > 10.0,
        "swing {lo:.1}..{hi:.1} deg"
    );
}

#[test]
fn a_robot_without_collision_geometry_is_refused_unless_allowed() {
    let dir = common::scratch("urdf-ghost");
    let registry = ModuleRegistry::standard();
    let out = dir.join("out");
    // Visual geometry only: it would fall through the floor (kinova ended at z = -44 m).
    let text = "<robot name=\"ghost\"><link name=\"a\"><inertial><mass value=\"1\"/>\
        <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>\
        <visual><geometry><box size=\"0.1 0.1 0.1\"/></geometry></visual></link>\
        <link name=\"b\"><inertial><mass value=\"1\"/>\
        <inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\
        <joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\
        <axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>";
    let urdf = write(&dir, "ghost.urdf", text);
    let e = import(&urdf, &out, &registry).unwrap_err().to_string();
    assert!(
        e.contains("ghost.urdf")
            && e.contains("fall through the floor")
            && e.contains("<visual> only: line 1: link a")
            && e.contains("--allow-no-collision"),
        "{e}"
    );
    let opts = proleg::interop::urdf::ImportOptions {
        allow_no_collision: true,
        ..Default::default()
    };
    let allowed = proleg::cli::interop::import_with(&urdf, &out, &opts, &registry)
        .expect("imported when allowed");
    assert!(
        allowed
            .import
            .warnings
            .iter()
            .any(|w| w.contains("fall through the floor")),
        "{:#?}",
        allowed.import.warnings
    );
}

#[test]
fn package_meshes_are_found_through_ros_package_path() {
    let dir = common::scratch("urdf-rospath");
    // The URDF in one tree, its package's mesh in another: no folder above holds it.
    let urdfs = dir.join("robots");
    let pkg = dir.join("workspace/src/mypkg/meshes");
    std::fs::create_dir_all(&urdfs).unwrap();
    std::fs::create_dir_all(&pkg).unwrap();
    std::fs::write(
        pkg.join("tet.obj"),
        "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let text = format!(
        "<robot name=\"p\">{}{}<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>\
         <child link=\"b\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>",
        link("a", "<mesh filename=\"package://mypkg/meshes/tet.obj\"/>"),
        link("b", "<box size=\"0.1 0.1 0.1\"/>")
    );
    let urdf = write(&urdfs, "p.urdf", &text);
    let out = dir.join("out");
    let run = |ros: Option<&Path>, extra: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_proleg"));
        c.args([
            "import",
            urdf.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(extra)
        .env_remove("ROS_PACKAGE_PATH");
        if let Some(p) = ros {
            c.env("ROS_PACKAGE_PATH", p);
        }
        let o = c.output().unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let (ok, err) = run(None, &[]);
    assert!(
        !ok && err.contains("p.urdf")
            && err.contains("package \"mypkg\"")
            && err.contains("ROS_PACKAGE_PATH (not set)")
            && err.contains("--package-path NAME=DIR"),
        "{err}"
    );
    let (ok, err) = run(Some(&dir.join("workspace/src")), &[]);
    assert!(ok, "{err}");
    assert!(out.join("meshes").read_dir().unwrap().count() == 1);
    // The package named on the command line, no ROS_PACKAGE_PATH.
    std::fs::remove_dir_all(&out).unwrap();
    let given = format!("mypkg={}", dir.join("workspace/src/mypkg").display());
    let (ok, err) = run(None, &["--package-path", &given]);
    assert!(ok, "{err}");
    assert!(out.join("meshes").read_dir().unwrap().count() == 1);
    // A package given where its mesh is not: the error names the path tried.
    let wrong = format!("mypkg={}", dir.display());
    let (ok, err) = run(None, &["--package-path", &wrong]);
    assert!(
        !ok && err.contains("meshes/tet.obj does not exist"),
        "{err}"
    );
    let (ok, err) = run(None, &["--package-path", "mypkg"]);
    assert!(!ok && err.contains("NAME=DIR"), "{err}");
}

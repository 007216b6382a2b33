//! Each class of bad input gives an error naming the file, the line and column, and what
//! was expected — never a panic.

use std::path::Path;

use proleg::config::{ConfigError, ErrorKind, MemSource, load_simulation_with};
use proleg::control::ModuleRegistry;

const SIM: &str = r#"<simulation>
  <robot>r.robot.xml</robot>
  <actuation>a.actuation.xml</actuation>
  <environment>e.env.xml</environment>
  <optimizer>o.gd.xml</optimizer>
  <simulationProperties>
    <mode>Great Deluge optimization</mode>
    <stepWidth>0.001</stepWidth>
  </simulationProperties>
</simulation>
"#;

const ROBOT: &str = r#"<Robot name="three">
  <KinBody name="k">
    <KinBody prefix="1" file="parts/p.kinbody.xml"/>
    <Body name="A">
      <Geom type="box"><extents>0.02 0.03 0.02</extents></Geom>
      <mass>0.1</mass>
    </Body>
    <Body name="C">
      <Translation>0 0.144 0</Translation>
      <Geom type="box"><extents>0.02 0.03 0.02</extents></Geom>
      <mass>0.1</mass>
    </Body>
    <Joint type="hinge" name="J1">
      <Body>A</Body>
      <Body>1B</Body>
      <offsetfrom>1B</offsetfrom>
      <axis>1 0 0</axis>
      <limitsdeg>-90 90</limitsdeg>
    </Joint>
    <Joint type="hinge" name="J2">
      <Body>1B</Body>
      <Body>C</Body>
      <offsetfrom>C</offsetfrom>
      <axis>0 0 1</axis>
    </Joint>
  </KinBody>
</Robot>
"#;

const PART: &str = r#"<KinBody name="p">
  <Body name="B">
    <Translation>0 0.072 0</Translation>
    <Geom type="box"><extents>0.02 0.03 0.02</extents></Geom>
    <Mass type="box"><total>0.1</total></Mass>
  </Body>
</KinBody>
"#;

const ACT: &str = r#"<actuation>
  <validRobot robotName="r.robot.xml"/>
  <actuationModule name="PatternGenerator_sinusoidal">
    <jointConfiguration joints="11"/>
    <parameter name="Amplitude" values="30 40"/>
  </actuationModule>
</actuation>
"#;

const ENV: &str = r#"<Environment>
  <KinBody name="floor">
    <Body type="static">
      <Geom type="box">
        <extents>4 4 0.01</extents>
        <friction>0.5</friction>
      </Geom>
    </Body>
  </KinBody>
</Environment>
"#;

const OPT: &str = r#"<greatDeluge>
  <properties>
    <credits>10</credits>
    <retries>200</retries>
    <initialWaterLevel>0.15</initialWaterLevel>
    <rain>0.01</rain>
    <confidence>20</confidence>
    <registeredParameters>
      <parameter number="0" controlAlgorithm="PatternGenerator_sinusoidal" parameter="Amplitude"/>
    </registeredParameters>
  </properties>
  <genomeConfig number="0" activeJoints="11">
    <upperBounds>40</upperBounds>
    <lowerBounds>0</lowerBounds>
    <boundsIncrements>0.25</boundsIncrements>
    <uniform>0</uniform>
  </genomeConfig>
</greatDeluge>
"#;

const FILES: [(&str, &str); 6] = [
    ("cfg/s.simulation.xml", SIM),
    ("cfg/r.robot.xml", ROBOT),
    ("cfg/parts/p.kinbody.xml", PART),
    ("cfg/a.actuation.xml", ACT),
    ("cfg/e.env.xml", ENV),
    ("cfg/o.gd.xml", OPT),
];

/// Loads the set with `file`'s text changed by replacing `from` with `to`.
fn load_with(file: &str, from: &str, to: &str) -> Result<proleg::config::Simulation, ConfigError> {
    let mut src = MemSource::new();
    let mut replaced = false;
    for (name, text) in FILES {
        if name.ends_with(file) {
            assert!(text.contains(from), "{from:?} not in {name}");
            src.insert(name, text.replacen(from, to, 1));
            replaced = true;
        } else {
            src.insert(name, text);
        }
    }
    assert!(replaced || file.is_empty(), "no file {file}");
    load_simulation_with(
        &src,
        Path::new("cfg/s.simulation.xml"),
        &ModuleRegistry::default(),
    )
}

/// Expects an error of `kind` in `file` at `line`, whose message contains every `needle`.
fn expect(
    result: Result<proleg::config::Simulation, ConfigError>,
    kind: ErrorKind,
    file: &str,
    line: u32,
    needles: &[&str],
) {
    let e = match result {
        Ok(_) => panic!("expected a {kind:?} error, but it loaded"),
        Err(e) => e,
    };
    let shown = e.to_string();
    assert_eq!(e.kind, kind, "{shown}");
    assert!(e.file.ends_with(file), "wrong file in: {shown}");
    assert_eq!(e.pos.line, line, "wrong line in: {shown}");
    assert!(
        shown.starts_with(&format!("{}:{}:", e.file.display(), line)),
        "{shown}"
    );
    for n in needles {
        assert!(shown.contains(n), "{n:?} missing in: {shown}");
    }
}

#[test]
fn the_valid_set_loads() {
    let sim = load_with("", "", "").unwrap();
    assert_eq!(sim.robot.links.len(), 3);
    assert_eq!(sim.robot.pattern(), "PY");
    assert_eq!(sim.optimizer.unwrap().search_space(), 161.0 * 161.0);
}

#[test]
fn malformed_xml() {
    expect(
        load_with("r.robot.xml", "</Joint>\n  </KinBody>", "</Joint>\n"),
        ErrorKind::Syntax,
        "r.robot.xml",
        27,
        &["malformed XML"],
    );
    let e = load_with(
        "a.actuation.xml",
        "<jointConfiguration",
        "<jointConfiguration <",
    );
    expect(
        e,
        ErrorKind::Syntax,
        "a.actuation.xml",
        4,
        &["malformed XML"],
    );
}

#[test]
fn empty_and_non_xml_files() {
    expect(
        load_with("e.env.xml", ENV, ""),
        ErrorKind::Syntax,
        "e.env.xml",
        1,
        &["no XML element"],
    );
    expect(
        load_with("e.env.xml", ENV, "just text"),
        ErrorKind::Syntax,
        "e.env.xml",
        1,
        &["text outside the root"],
    );
}

#[test]
fn unknown_element() {
    let e = load_with(
        "e.env.xml",
        "<friction>0.5</friction>",
        "<frictoin>0.5</frictoin>",
    );
    expect(
        e,
        ErrorKind::UnknownElement,
        "e.env.xml",
        6,
        &["<frictoin>", "expected one of", "friction"],
    );
    let e = load_with(
        "s.simulation.xml",
        "<stepWidth>",
        "<stepwidht>0</stepwidht><stepWidth>",
    );
    expect(
        e,
        ErrorKind::UnknownElement,
        "s.simulation.xml",
        8,
        &["stepwidht"],
    );
}

#[test]
fn non_numeric_and_nan_values() {
    let e = load_with("r.robot.xml", "<mass>0.1</mass>", "<mass>heavy</mass>");
    expect(
        e,
        ErrorKind::InvalidValue,
        "r.robot.xml",
        6,
        &["expected a number", "heavy"],
    );
    let e = load_with("r.robot.xml", "<axis>1 0 0</axis>", "<axis>1 NaN 0</axis>");
    expect(
        e,
        ErrorKind::InvalidValue,
        "r.robot.xml",
        17,
        &["finite", "NaN"],
    );
    let e = load_with("r.robot.xml", "<axis>1 0 0</axis>", "<axis>1 0</axis>");
    expect(
        e,
        ErrorKind::InvalidValue,
        "r.robot.xml",
        17,
        &["expected 3 numbers, found 2"],
    );
    let e = load_with("a.actuation.xml", "values=\"30 40\"", "values=\"30 inf\"");
    expect(
        e,
        ErrorKind::InvalidValue,
        "a.actuation.xml",
        5,
        &["finite"],
    );
}

#[test]
fn out_of_range_values() {
    // Negative mass, in an included part file: the error names the part and where it was included.
    let e = load_with("p.kinbody.xml", "<total>0.1</total>", "<total>-0.1</total>");
    expect(
        e,
        ErrorKind::OutOfRange,
        "parts/p.kinbody.xml",
        5,
        &[
            "the mass (kg) is -0.1",
            "must be between 0.000001 and 1000000",
            "included from cfg/r.robot.xml:3",
        ],
    );
    let e = load_with(
        "e.env.xml",
        "<friction>0.5</friction>",
        "<friction>-0.3</friction>",
    );
    expect(
        e,
        ErrorKind::OutOfRange,
        "e.env.xml",
        6,
        &["<friction> is -0.3", "between 0 and 100"],
    );
    let e = load_with(
        "r.robot.xml",
        "<limitsdeg>-90 90</limitsdeg>",
        "<limitsdeg>60 -30</limitsdeg>",
    );
    expect(
        e,
        ErrorKind::OutOfRange,
        "r.robot.xml",
        18,
        &["joint J1", "lower limit 60", "greater than upper limit -30"],
    );
    let e = load_with(
        "r.robot.xml",
        "<extents>0.02 0.03 0.02</extents></Geom>\n      <mass>",
        "<extents>0.02 0 0.02</extents></Geom>\n      <mass>",
    );
    expect(
        e,
        ErrorKind::OutOfRange,
        "r.robot.xml",
        5,
        &["extents", "must all be between 0.000001 and 10000"],
    );
    let e = load_with("a.actuation.xml", "values=\"30 40\"", "values=\"30 95\"");
    expect(
        e,
        ErrorKind::OutOfRange,
        "a.actuation.xml",
        5,
        &["Amplitude", "between 0 and 90"],
    );
    let e = load_with("s.simulation.xml", "<stepWidth>0.001", "<stepWidth>1000");
    expect(
        e,
        ErrorKind::OutOfRange,
        "s.simulation.xml",
        8,
        &["in seconds", "µs"],
    );
    let e = load_with(
        "o.gd.xml",
        "<lowerBounds>0</lowerBounds>",
        "<lowerBounds>50</lowerBounds>",
    );
    expect(
        e,
        ErrorKind::OutOfRange,
        "o.gd.xml",
        14,
        &["lower bound 50 is greater than upper bound 40"],
    );
}

#[test]
fn mask_length_differs_from_joint_count() {
    let e = load_with("a.actuation.xml", "joints=\"11\"", "joints=\"111\"");
    expect(
        e,
        ErrorKind::MaskLength,
        "a.actuation.xml",
        4,
        &["\"111\" has 3 characters", "robot has 2 joints"],
    );
    let e = load_with("o.gd.xml", "activeJoints=\"11\"", "activeJoints=\"1\"");
    expect(
        e,
        ErrorKind::MaskLength,
        "o.gd.xml",
        12,
        &["has 1 characters", "2 joints"],
    );
    let e = load_with("a.actuation.xml", "joints=\"11\"", "joints=\"1x\"");
    expect(
        e,
        ErrorKind::InvalidValue,
        "a.actuation.xml",
        4,
        &["character 2 is 'x'", "only 0 and 1"],
    );
    // The column points at the attribute's value.
    let e = load_with("a.actuation.xml", "joints=\"11\"", "joints=\"111\"")
        .err()
        .unwrap();
    assert_eq!(e.pos.col, 33, "{e}");
}

#[test]
fn per_joint_values_must_match_the_mask() {
    let e = load_with("a.actuation.xml", "values=\"30 40\"", "values=\"30 40 50\"");
    expect(
        e,
        ErrorKind::InvalidValue,
        "a.actuation.xml",
        5,
        &["3 values", "drives 2 joints"],
    );
}

#[test]
fn unknown_module_lists_the_known_ones() {
    let e = load_with(
        "a.actuation.xml",
        "name=\"PatternGenerator_sinusoidal\"",
        "name=\"PatternGenerator_sine\"",
    );
    expect(
        e,
        ErrorKind::UnknownModule,
        "a.actuation.xml",
        3,
        &[
            "\"PatternGenerator_sine\"",
            "known modules:",
            "DirectJointAccess",
            "PatternGenerator_sinusoidal",
            "Global_Adaptive_Touch",
        ],
    );
}

#[test]
fn unknown_parameter_lists_the_module_parameters() {
    let e = load_with(
        "a.actuation.xml",
        "name=\"Amplitude\"",
        "name=\"Amplitdue\"",
    );
    expect(
        e,
        ErrorKind::UnknownReference,
        "a.actuation.xml",
        5,
        &["no parameter \"Amplitdue\"", "Amplitude, Frequency"],
    );
}

#[test]
fn missing_include_file() {
    let e = load_with("r.robot.xml", "parts/p.kinbody.xml", "parts/q.kinbody.xml");
    expect(
        e,
        ErrorKind::MissingFile,
        "r.robot.xml",
        3,
        &["\"parts/q.kinbody.xml\" not found"],
    );
    let e = load_with("s.simulation.xml", "e.env.xml", "nowhere.env.xml");
    expect(
        e,
        ErrorKind::MissingFile,
        "s.simulation.xml",
        4,
        &["environment file \"nowhere.env.xml\" not found"],
    );
}

#[test]
fn missing_top_level_file() {
    let e = proleg::control::load_simulation("no/such.simulation.xml")
        .err()
        .unwrap();
    assert_eq!(e.kind, ErrorKind::MissingFile);
    assert!(e.to_string().starts_with("no/such.simulation.xml:"), "{e}");
}

#[test]
fn include_cycle() {
    let e = load_with(
        "p.kinbody.xml",
        "<Body name=\"B\">",
        "<KinBody prefix=\"x\" file=\"p.kinbody.xml\"/>\n  <Body name=\"B\">",
    );
    expect(
        e,
        ErrorKind::IncludeCycle,
        "parts/p.kinbody.xml",
        2,
        &[
            "include cycle",
            "cfg/parts/p.kinbody.xml -> cfg/parts/p.kinbody.xml",
        ],
    );
}

#[test]
fn unknown_body_reference() {
    let e = load_with("r.robot.xml", "<Body>A</Body>", "<Body>Z</Body>");
    expect(
        e,
        ErrorKind::UnknownReference,
        "r.robot.xml",
        13,
        &["body \"Z\"", "bodies: 1B, A, C"],
    );
}

#[test]
fn optimizer_parameter_that_names_nothing() {
    let e = load_with(
        "o.gd.xml",
        "parameter=\"Amplitude\"",
        "parameter=\"Wavelength\"",
    );
    expect(
        e,
        ErrorKind::UnknownReference,
        "o.gd.xml",
        9,
        &["no parameter \"Wavelength\""],
    );
    let e = load_with(
        "o.gd.xml",
        "controlAlgorithm=\"PatternGenerator_sinusoidal\"",
        "controlAlgorithm=\"Global Adaptive Touch\"",
    );
    expect(
        e,
        ErrorKind::UnknownReference,
        "o.gd.xml",
        9,
        &["Global_Adaptive_Touch", "does not use"],
    );
    let e = load_with(
        "o.gd.xml",
        "controlAlgorithm=\"PatternGenerator_sinusoidal\"",
        "controlAlgorithm=\"Hopf\"",
    );
    expect(
        e,
        ErrorKind::UnknownModule,
        "o.gd.xml",
        9,
        &["unknown actuation module \"Hopf\""],
    );
    let e = load_with(
        "o.gd.xml",
        "<genomeConfig number=\"0\"",
        "<genomeConfig number=\"1\"",
    );
    expect(
        e,
        ErrorKind::UnknownReference,
        "o.gd.xml",
        12,
        &["genomeConfig number 1 belongs to no registered parameter"],
    );
}

#[test]
fn optimizer_mode_mismatch() {
    let e = load_with(
        "s.simulation.xml",
        "Great Deluge optimization",
        "GA optimization",
    );
    expect(
        e,
        ErrorKind::InvalidValue,
        "s.simulation.xml",
        5,
        &["needs genetic algorithm settings"],
    );
    let e = load_with(
        "s.simulation.xml",
        "Great Deluge optimization",
        "Fast Forward",
    );
    expect(
        e,
        ErrorKind::InvalidValue,
        "s.simulation.xml",
        7,
        &["unknown mode \"Fast Forward\"", "Single Run Simulation"],
    );
}

#[test]
fn thesis_mode_spellings_are_accepted() {
    for mode in ["great deluge", "GD", "Great_Deluge_Optimization"] {
        let sim = load_with("s.simulation.xml", "Great Deluge optimization", mode).unwrap();
        assert_eq!(
            sim.files.simulation.properties.mode,
            proleg::config::simulation::Mode::GreatDeluge
        );
    }
}

#[test]
fn deep_nesting_is_refused_not_overflowed() {
    let deep = format!("{}{}", "<a>".repeat(100_000), "</a>".repeat(100_000));
    let e = load_with("e.env.xml", ENV, &deep).err().unwrap();
    assert_eq!(e.kind, ErrorKind::Syntax);
    assert!(e.to_string().contains("nested deeper than"), "{e}");
}

#[test]
fn a_heightfield_mesh_must_be_a_height_map() {
    // A tetrahedron: its vertices span a 2 x 2 x-y grid, but node (1, 1) has none.
    let tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n";
    let geom = r#"<Geom type="heightfield">
        <data>tetra.obj</data>
      </Geom>
      <Geom type="box">"#;
    let mut src = MemSource::new();
    for (name, text) in FILES {
        let text = if name.ends_with("e.env.xml") {
            text.replacen(r#"<Geom type="box">"#, geom, 1)
        } else {
            text.to_string()
        };
        src.insert(name, text);
    }
    src.insert("cfg/tetra.obj", tetra);
    let result = load_simulation_with(
        &src,
        Path::new("cfg/s.simulation.xml"),
        &ModuleRegistry::default(),
    );
    expect(
        result,
        ErrorKind::InvalidValue,
        "e.env.xml",
        4,
        &[
            "tetra.obj cannot be a heightfield",
            "grid node (1, 1) has no vertex",
        ],
    );
}

#[test]
fn an_unknown_articulation_names_its_line_and_the_two_kinds() {
    let physics = "<Environment>\n  <physicsengine type=\"ode\"><odeproperties>\n    \
                   <articulation>floppy</articulation>\n  </odeproperties></physicsengine>";
    expect(
        load_with("e.env.xml", "<Environment>", physics),
        ErrorKind::InvalidValue,
        "e.env.xml",
        3,
        &["<articulation> is maximal or reduced, not `floppy`"],
    );
    let reduced = physics.replace("floppy", "Reduced");
    let sim = load_with("e.env.xml", "<Environment>", &reduced).unwrap();
    assert_eq!(
        sim.environment.physics.articulation,
        proleg::config::environment::Articulation::Reduced
    );
}

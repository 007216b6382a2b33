//! Task suites (`*.suite.xml`): locomotion tasks, each a procedural terrain family at a
//! difficulty, an episode length, a goal line and two disjoint seed lists — train seeds an
//! optimizer may tune on and test seeds a controller is scored on. A task with no train
//! seeds is held out: scored only, never trained on; a family all of whose tasks are held
//! out measures generalization to a new kind of ground.
//!
//! ```xml
//! <Suite name="locomotion">
//!   <Task name="pegs-easy" family="pegs" difficulty="easy" duration="60" goal="10"
//!         train="1-20" test="101-110" reference="2.4"/>
//! </Suite>
//! ```
//!
//! Seed lists are numbers and ranges (`1-20 31 40-42`). `reference` is the distance (m) a
//! task's score is normalized by: the thesis's sine's mean test distance on it.

use std::collections::BTreeSet;
use std::path::Path;

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::terrain::{Family, TerrainSpec};
use crate::config::xml::dom::Element;
use crate::config::xml::read::{Reader, read_document};
use crate::config::xml::write::{XmlWriter, num};

/// Episode length of a task that names none (s).
pub const DEFAULT_DURATION: f64 = 60.0;
/// Longest episode a task may ask for (s).
pub const MAX_DURATION: f64 = 3600.0;
/// Most seeds one list may hold.
pub const MAX_SEEDS: usize = 10_000;

/// One task of a suite.
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// Its name, unique in the suite (`pegs-easy`).
    pub name: String,
    /// The course: family, difficulty, length, width (its seed is each episode's).
    pub terrain: TerrainSpec,
    /// Episode length (s).
    pub duration: f64,
    /// The goal line (m ahead of the start): crossing it is success.
    pub goal: f64,
    /// Seeds of the terrains an optimizer may tune on (none: held out).
    pub train: Vec<u64>,
    /// Seeds of the terrains a controller is scored on.
    pub test: Vec<u64>,
    /// The distance (m) scores are normalized by, when known.
    pub reference: Option<f64>,
    /// Where it was written (line, column).
    pub pos: Pos,
}

impl Task {
    /// Whether it is held out (test seeds only).
    pub fn held_out(&self) -> bool {
        self.train.is_empty()
    }

    /// The course's forward direction in the world (its +y, turned by its placement).
    pub fn direction(&self) -> [f64; 3] {
        self.terrain.pose.rotate([0.0, 1.0, 0.0])
    }

    /// The course of terrain seed `seed`.
    pub fn course(&self, seed: u64) -> TerrainSpec {
        TerrainSpec {
            seed,
            ..self.terrain.clone()
        }
    }
}

/// A suite file as written.
#[derive(Debug, Clone, PartialEq)]
pub struct SuiteFile {
    /// Its name.
    pub name: String,
    /// What it is for.
    pub description: Option<String>,
    /// Its tasks, in file order.
    pub tasks: Vec<Task>,
}

impl SuiteFile {
    /// The task named `name` (case, `_` and `-` ignored).
    pub fn task(&self, name: &str) -> Option<&Task> {
        self.tasks
            .iter()
            .find(|t| crate::config::xml::read::same_name(&t.name, name))
    }

    /// The families none of whose tasks has train seeds.
    pub fn held_out_families(&self) -> Vec<Family> {
        Family::ALL
            .into_iter()
            .filter(|f| {
                let tasks: Vec<&Task> = self
                    .tasks
                    .iter()
                    .filter(|t| t.terrain.family == *f)
                    .collect();
                !tasks.is_empty() && tasks.iter().all(|t| t.held_out())
            })
            .collect()
    }
}

/// Reads and parses the suite file at `path` through `src`.
pub fn load_suite(src: &dyn crate::config::FileSource, path: &Path) -> ConfigResult<SuiteFile> {
    let text = src.read(path).map_err(|e| {
        crate::config::ConfigError::new(
            path,
            Pos::new(0, 0),
            ErrorKind::MissingFile,
            format!("cannot read the suite: {e}"),
        )
        .caused_by(e)
    })?;
    parse_suite_file(&path.display().to_string(), &text)
}

/// Reads a suite file's text.
pub fn parse_suite_file(file: &str, text: &str) -> ConfigResult<SuiteFile> {
    let (doc, r) = read_document(file, text, "Suite", "a suite file")?;
    let root = &doc.root;
    r.only_children(root, &["description", "task"])?;
    r.only_attrs(root, &["name"])?;
    let name = r.required_attr(root, "name")?.value.clone();
    let description = r
        .at_most_one(root, "description")?
        .map(|d| d.text.trim().to_string());
    let mut tasks: Vec<Task> = Vec::new();
    for el in root.children_named("task") {
        let task = read_task(&r, el)?;
        if tasks
            .iter()
            .any(|t| crate::config::xml::read::same_name(&t.name, &task.name))
        {
            return Err(r.err(
                el.pos,
                ErrorKind::InvalidValue,
                format!("a second task named {:?}", task.name),
            ));
        }
        tasks.push(task);
    }
    if tasks.is_empty() {
        return Err(r.err(
            root.pos,
            ErrorKind::Missing,
            "a suite needs at least one <Task>",
        ));
    }
    Ok(SuiteFile {
        name,
        description,
        tasks,
    })
}

const TASK_ATTRS: [&str; 7] = [
    "name",
    "duration",
    "goal",
    "train",
    "test",
    "reference",
    "seed",
];

fn read_task(r: &Reader, el: &Element) -> ConfigResult<Task> {
    let terrain = TerrainSpec::read_with(r, el, &TASK_ATTRS)?;
    if let Some(a) = el.attr("seed") {
        return Err(r.err(
            a.pos,
            ErrorKind::UnknownElement,
            "a task's terrain seeds are its train= and test= lists, not seed=",
        ));
    }
    let name = r.required_attr(el, "name")?.value.trim().to_string();
    let number =
        |attr: &str, default: Option<f64>, min: f64, max: f64| -> ConfigResult<Option<f64>> {
            match el.attr(attr) {
                Some(a) => {
                    let v = r.number(&a.value, a.pos, attr)?;
                    r.check_range(v, min, max, a.pos, attr)?;
                    Ok(Some(v))
                }
                None => Ok(default),
            }
        };
    let duration = number("duration", Some(DEFAULT_DURATION), 0.001, MAX_DURATION)?
        .unwrap_or(DEFAULT_DURATION);
    let goal = number("goal", None, 0.001, terrain.length)?.unwrap_or(terrain.length);
    let reference = number("reference", None, 1e-6, f64::INFINITY)?;
    let train = match el.attr("train") {
        Some(a) => seeds(r, &a.value, a.pos, "train")?,
        None => Vec::new(),
    };
    let t = r.required_attr(el, "test")?;
    let test = seeds(r, &t.value, t.pos, "test")?;
    if test.is_empty() {
        return Err(r.err(t.pos, ErrorKind::Missing, "test= names no seed"));
    }
    let train_set: BTreeSet<u64> = train.iter().copied().collect();
    if let Some(both) = test.iter().find(|s| train_set.contains(s)) {
        return Err(r.err(
            t.pos,
            ErrorKind::InvalidValue,
            format!("seed {both} is both a train and a test seed of task {name:?}: a test world must be one no training saw"),
        ));
    }
    Ok(Task {
        name,
        terrain,
        duration,
        goal,
        train,
        test,
        reference,
        pos: el.pos,
    })
}

/// A seed list: whole numbers and ranges `a-b`, separated by spaces or commas.
fn seeds(r: &Reader, text: &str, pos: Pos, what: &str) -> ConfigResult<Vec<u64>> {
    let bad = |item: &str| {
        r.err(
            pos,
            ErrorKind::InvalidValue,
            format!("{what}: {item:?} is neither a seed (a whole number) nor a range a-b"),
        )
    };
    let mut out = Vec::new();
    for item in text.split([' ', ',', '\t', '\n']).filter(|s| !s.is_empty()) {
        let (a, b) = match item.split_once('-') {
            Some((a, b)) => (a.parse::<u64>(), b.parse::<u64>()),
            None => (item.parse::<u64>(), item.parse::<u64>()),
        };
        let (Ok(a), Ok(b)) = (a, b) else {
            return Err(bad(item));
        };
        if b < a || (b - a) as usize >= MAX_SEEDS || out.len() + (b - a) as usize >= MAX_SEEDS {
            return Err(r.err(
                pos,
                ErrorKind::OutOfRange,
                format!("{what}: {item:?} is empty or makes more than {MAX_SEEDS} seeds"),
            ));
        }
        out.extend(a..=b);
    }
    let mut seen = BTreeSet::new();
    if let Some(twice) = out.iter().find(|s| !seen.insert(**s)) {
        return Err(r.err(
            pos,
            ErrorKind::InvalidValue,
            format!("{what}: seed {twice} is listed twice"),
        ));
    }
    Ok(out)
}

/// Seeds as the shortest list of numbers and ranges.
fn seeds_text(seeds: &[u64]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < seeds.len() {
        let mut j = i;
        while j + 1 < seeds.len() && seeds[j + 1] == seeds[j] + 1 {
            j += 1;
        }
        parts.push(if j > i {
            format!("{}-{}", seeds[i], seeds[j])
        } else {
            seeds[i].to_string()
        });
        i = j + 1;
    }
    parts.join(" ")
}

/// Writes a suite file.
pub fn write_suite_file(suite: &SuiteFile) -> String {
    let mut w = XmlWriter::new();
    w.open("Suite", &[("name", suite.name.clone())]);
    if let Some(d) = &suite.description {
        w.leaf("description", d);
    }
    for t in &suite.tasks {
        let mut attrs = vec![("name", t.name.clone())];
        attrs.extend(t.terrain.attributes());
        attrs.push(("duration", num(t.duration)));
        attrs.push(("goal", num(t.goal)));
        if !t.train.is_empty() {
            attrs.push(("train", seeds_text(&t.train)));
        }
        attrs.push(("test", seeds_text(&t.test)));
        if let Some(x) = t.reference {
            attrs.push(("reference", num(x)));
        }
        w.empty("Task", &attrs);
    }
    w.close();
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SUITE: &str = r#"<Suite name="s">
  <Task name="pegs-easy" family="pegs" difficulty="easy" goal="10" train="1-3 7" test="101-102"/>
  <Task name="rubble-hard" family="rubble" difficulty="hard" duration="30" test="101-103" reference="1.5"/>
</Suite>"#;

    #[test]
    fn a_suite_reads_and_round_trips() {
        let s = parse_suite_file("s.suite.xml", SUITE).unwrap();
        assert_eq!(s.tasks[0].train, vec![1, 2, 3, 7]);
        assert_eq!(s.tasks[0].duration, DEFAULT_DURATION);
        assert_eq!(s.tasks[1].goal, s.tasks[1].terrain.length);
        assert!(s.tasks[1].held_out() && !s.tasks[0].held_out());
        assert_eq!(s.held_out_families(), vec![Family::Rubble]);
        let again = parse_suite_file("s.suite.xml", &write_suite_file(&s)).unwrap();
        assert_eq!(s, again);
    }

    #[test]
    fn bad_suites_are_located_errors() {
        let cases = [
            (r#"train="1-5" test="5-6""#, "both a train and a test seed"),
            (r#"test="3 3""#, "listed twice"),
            (r#"test="x""#, "neither a seed"),
            (r#"test="9-2""#, "empty"),
            (r#"test="1" seed="4""#, "not seed="),
            (r#"test="1" goal="99""#, "goal"),
        ];
        for (attrs, says) in cases {
            let text = format!(
                "<Suite name=\"s\">\n<Task name=\"t\" family=\"pegs\" difficulty=\"easy\" {attrs}/>\n</Suite>"
            );
            let e = parse_suite_file("s.suite.xml", &text).unwrap_err();
            assert_eq!(e.pos.line, 2, "{attrs}: {e}");
            assert!(e.to_string().contains(says), "{attrs}: {e}");
        }
        let twice = "<Suite name=\"s\"><Task name=\"a\" family=\"pegs\" difficulty=\"easy\" test=\"1\"/><Task name=\"A\" family=\"rough\" difficulty=\"easy\" test=\"1\"/></Suite>";
        assert!(
            parse_suite_file("s", twice)
                .unwrap_err()
                .to_string()
                .contains("second task")
        );
        let empty = "<Suite name=\"s\"></Suite>";
        assert_eq!(
            parse_suite_file("s", empty).unwrap_err().kind,
            ErrorKind::Missing
        );
    }
}

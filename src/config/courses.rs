//! Our extension `<courses>` of optimizer files: train on a task suite's train courses.
//!
//! ```xml
//! <courses suite="../suites/locomotion.suite.xml" tasks="pegs-medium steps-medium"/>
//! ```
//!
//! Each candidate is scored over K episodes, episode k on a train course: task
//! `tasks[k mod n]`, train seed number `k div n` of that task (cycling through its train
//! seeds). K is `<robustness>`'s `<episodes>` when the file has one (the randomized physics
//! then comes on top of each course), else the attribute `episodes` (default: one episode
//! per task). Without `tasks`, every task of the suite that has train seeds is used. Test
//! seeds are never trained on, and a held-out task (no train seeds) cannot be named. The
//! courses are generated once, when the simulation is loaded, and every candidate meets
//! the same ones (common random numbers, as `<robustness>`'s draws). Episodes keep the
//! simulation's own duration and fitness.
//!
//! A curriculum names its tasks stage by stage instead of in `tasks`:
//!
//! ```xml
//! <courses suite="../suites/locomotion.suite.xml" episodes="2">
//!   <stage tasks="steps-easy" until="5"/>
//!   <stage tasks="steps-medium" until="5"/>
//!   <stage tasks="steps-hard"/>
//! </courses>
//! ```
//!
//! Every stage but the last ends once its best score reaches `until`; the last has none
//! (`proleg optimize` runs the stages one after another, [`crate::optimize::curriculum`]).
//! A simulation loaded from such a file trains on the first stage's tasks.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::config::error::{ConfigResult, ErrorKind, Pos};
use crate::config::resolve::environment::EnvironmentModel;
use crate::config::suite::{SuiteFile, Task};
use crate::config::xml::dom::Element;
use crate::config::xml::read::Reader;
use crate::config::xml::write::XmlWriter;

/// Most episodes `<courses episodes>` may ask for.
const MAX_EPISODES: u32 = 1000;

/// `<courses>` as written.
#[derive(Debug, Clone, PartialEq)]
pub struct CoursesSpec {
    /// The suite file, as written (found beside the optimizer file or in a folder above).
    pub suite: String,
    /// The tasks named (none: every task with train seeds).
    pub tasks: Vec<String>,
    /// Episodes per candidate when the file has no `<robustness>`.
    pub episodes: Option<u32>,
    /// A curriculum's stages, in order (none: `tasks` is the one set of tasks).
    pub stages: Vec<StageSpec>,
    /// Where the element is.
    pub pos: Pos,
}

/// One `<stage>` of a curriculum.
#[derive(Debug, Clone, PartialEq)]
pub struct StageSpec {
    /// The tasks this stage trains on.
    pub tasks: Vec<String>,
    /// The best score that ends the stage (every stage but the last has one).
    pub until: Option<f64>,
    /// Where the element is.
    pub pos: Pos,
}

impl CoursesSpec {
    /// The tasks a simulation loaded from this element trains on: `tasks`, or the first
    /// stage's.
    pub fn first_tasks(&self) -> &[String] {
        self.stages.first().map_or(&self.tasks, |s| &s.tasks)
    }

    /// Stage `k` (0-based) as an element of its own: its tasks, no stages.
    pub fn stage(&self, k: usize) -> Option<CoursesSpec> {
        let stage = self.stages.get(k)?;
        Some(CoursesSpec {
            tasks: stage.tasks.clone(),
            stages: Vec::new(),
            pos: stage.pos,
            ..self.clone()
        })
    }
}

/// One train course: a task's course of one train seed, generated.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainCourse {
    /// The task's name.
    pub task: String,
    /// The terrain seed (one of the task's train seeds).
    pub seed: u64,
    /// The course as a world, with the simulation's physics and start pose.
    pub environment: EnvironmentModel,
}

/// The courses of a run, episode by episode (shared: every episode's simulation holds
/// the list).
#[derive(Debug, Clone, PartialEq)]
pub struct TrainCourses {
    /// The suite file.
    pub suite: PathBuf,
    /// Episode k's course.
    pub courses: Arc<Vec<TrainCourse>>,
}

impl TrainCourses {
    /// Episode `k`'s course.
    pub fn course(&self, k: usize) -> Option<&TrainCourse> {
        self.courses.get(k)
    }

    /// Episodes per candidate.
    pub fn len(&self) -> usize {
        self.courses.len()
    }

    /// Whether there are none (never, once resolved).
    pub fn is_empty(&self) -> bool {
        self.courses.is_empty()
    }

    /// A short description, e.g. `pegs-medium seeds 1-4, steps-medium seeds 1-4`.
    pub fn describe(&self) -> String {
        let mut tasks: Vec<(&str, Vec<u64>)> = Vec::new();
        for c in self.courses.iter() {
            match tasks.iter_mut().find(|(t, _)| *t == c.task) {
                Some((_, seeds)) => seeds.push(c.seed),
                None => tasks.push((&c.task, vec![c.seed])),
            }
        }
        let parts: Vec<String> = tasks
            .iter()
            .map(|(t, s)| {
                let seeds: Vec<String> = s.iter().map(u64::to_string).collect();
                format!("{t} seeds {}", seeds.join(" "))
            })
            .collect();
        format!("{} train courses: {}", self.len(), parts.join(", "))
    }
}

/// Reads `<courses>` (a child of the optimizer file's root).
pub fn read_courses(r: &Reader, el: &Element) -> ConfigResult<CoursesSpec> {
    r.only_attrs(el, &["suite", "tasks", "episodes"])?;
    r.only_children(el, &["stage"])?;
    let suite = r.required_attr(el, "suite")?.value.trim().to_string();
    let tasks = el
        .attr("tasks")
        .map(|a| names(&a.value))
        .unwrap_or_default();
    let episodes = match el.attr("episodes") {
        Some(a) => {
            let k = r.u32_str(&a.value, a.pos, "episodes")?;
            if !(1..=MAX_EPISODES).contains(&k) {
                return Err(r.err(
                    a.pos,
                    ErrorKind::InvalidValue,
                    format!("episodes must be 1 ..= {MAX_EPISODES}, not {k}"),
                ));
            }
            Some(k)
        }
        None => None,
    };
    let stages = read_stages(r, el)?;
    if !stages.is_empty() && el.attr("tasks").is_some() {
        return Err(r.err(
            el.pos,
            ErrorKind::InvalidValue,
            "<courses> names its tasks either in `tasks` or stage by stage in <stage>s, not both",
        ));
    }
    Ok(CoursesSpec {
        suite,
        tasks,
        episodes,
        stages,
        pos: el.pos,
    })
}

/// Task names as written, separated by white space.
fn names(text: &str) -> Vec<String> {
    text.split_whitespace().map(str::to_string).collect()
}

/// The `<stage>` children of `<courses>`: each names tasks; every one but the last ends at
/// a score (`until`), the last has none.
fn read_stages(r: &Reader, el: &Element) -> ConfigResult<Vec<StageSpec>> {
    let elements: Vec<&Element> = el.children_named("stage").collect();
    let last = elements.len().saturating_sub(1);
    elements
        .iter()
        .enumerate()
        .map(|(k, st)| {
            r.only_attrs(st, &["tasks", "until"])?;
            r.only_children(st, &[])?;
            let tasks = names(&r.required_attr(st, "tasks")?.value);
            if tasks.is_empty() {
                return Err(r.err(
                    st.pos,
                    ErrorKind::InvalidValue,
                    "<stage tasks> names no task",
                ));
            }
            let until = st
                .attr("until")
                .map(|a| r.number(&a.value, a.pos, "until"))
                .transpose()?;
            match (k == last, until) {
                (false, None) => Err(r.err(
                    st.pos,
                    ErrorKind::Missing,
                    format!(
                        "stage {} of {} needs `until` (the best score that ends it)",
                        k + 1,
                        last + 1
                    ),
                )),
                (true, Some(_)) => Err(r.err(
                    st.pos,
                    ErrorKind::InvalidValue,
                    "the last stage has no `until`: it runs to the end of the budget",
                )),
                _ => Ok(StageSpec {
                    tasks,
                    until,
                    pos: st.pos,
                }),
            }
        })
        .collect()
}

/// Writes `<courses>`.
pub fn write_courses(w: &mut XmlWriter, c: &CoursesSpec) {
    let mut attrs = vec![("suite", c.suite.clone())];
    if !c.tasks.is_empty() {
        attrs.push(("tasks", c.tasks.join(" ")));
    }
    if let Some(k) = c.episodes {
        attrs.push(("episodes", k.to_string()));
    }
    if c.stages.is_empty() {
        w.empty("courses", &attrs);
        return;
    }
    w.open("courses", &attrs);
    for stage in &c.stages {
        let mut attrs = vec![("tasks", stage.tasks.join(" "))];
        if let Some(u) = stage.until {
            attrs.push(("until", crate::config::xml::write::num(u)));
        }
        w.empty("stage", &attrs);
    }
    w.close();
}

/// The tasks `spec` trains on, from `suite` (file `suite_path`); `file` is the optimizer
/// file (what errors name). A curriculum trains on its first stage's tasks; every stage's
/// names are checked.
pub fn train_tasks<'a>(
    file: &Path,
    spec: &CoursesSpec,
    suite: &'a SuiteFile,
    suite_path: &Path,
) -> ConfigResult<Vec<&'a Task>> {
    let r = Reader::new(file);
    for (k, _) in spec.stages.iter().enumerate().skip(1) {
        if let Some(stage) = spec.stage(k) {
            train_tasks(file, &stage, suite, suite_path)?;
        }
    }
    if let Some(first) = spec.stage(0) {
        return train_tasks(file, &first, suite, suite_path);
    }
    if spec.tasks.is_empty() {
        let trainable: Vec<&Task> = suite.tasks.iter().filter(|t| !t.held_out()).collect();
        if trainable.is_empty() {
            return Err(r.err(
                spec.pos,
                ErrorKind::InvalidValue,
                format!(
                    "{}: no task has train seeds; every task is held out",
                    suite_path.display()
                ),
            ));
        }
        return Ok(trainable);
    }
    spec.tasks
        .iter()
        .map(|name| {
            let task = suite.tasks.iter().find(|t| t.name == *name).ok_or_else(|| {
                let known: Vec<&str> = suite.tasks.iter().map(|t| t.name.as_str()).collect();
                r.err(
                    spec.pos,
                    ErrorKind::UnknownReference,
                    format!(
                        "{} has no task {name:?}; it has {}",
                        suite_path.display(),
                        known.join(", ")
                    ),
                )
            })?;
            if task.held_out() {
                return Err(r.err(
                    spec.pos,
                    ErrorKind::InvalidValue,
                    format!(
                        "task {name:?} is held out (test seeds only): a controller is never trained on it"
                    ),
                ));
            }
            Ok(task)
        })
        .collect()
}

/// Episode `k`'s task and train seed among `tasks`: task `k mod n`, its train seed
/// number `k div n` (cycling); none when there are no tasks or the task has no train seed.
pub fn pick<'a>(tasks: &[&'a Task], k: usize) -> Option<(&'a Task, u64)> {
    let task = *tasks.get(k % tasks.len().max(1))?;
    let seed = *task
        .train
        .get((k / tasks.len()) % task.train.len().max(1))?;
    Some((task, seed))
}

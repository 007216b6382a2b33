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
    /// Where the element is.
    pub pos: Pos,
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
    r.only_children(el, &[])?;
    let suite = r.required_attr(el, "suite")?.value.trim().to_string();
    let tasks = el
        .attr("tasks")
        .map(|a| a.value.split_whitespace().map(str::to_string).collect())
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
    Ok(CoursesSpec {
        suite,
        tasks,
        episodes,
        pos: el.pos,
    })
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
    w.empty("courses", &attrs);
}

/// The tasks `spec` trains on, from `suite` (file `suite_path`); `file` is the optimizer
/// file (what errors name).
pub fn train_tasks<'a>(
    file: &Path,
    spec: &CoursesSpec,
    suite: &'a SuiteFile,
    suite_path: &Path,
) -> ConfigResult<Vec<&'a Task>> {
    let r = Reader::new(file);
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

//! A curriculum: an optimizer file whose `<courses>` names its tasks stage by stage
//! (`<stage tasks="steps-easy" until="5"/>`, ..., a last stage without `until`), run as a
//! chain of ordinary runs sharing the evaluation budget. Stage 1 starts from the
//! configured candidate on its tasks' train courses; a stage ends, finished, at the end of
//! the first round whose best score reaches its `until`, and the next starts from that
//! best with the evaluations left. A stage whose budget runs out before it reaches its
//! `until` ends the curriculum there. Each stage is stored as a run of its own, with the
//! optimizer file as that stage sees it (its tasks in `<courses tasks>`, no stages), so a
//! shared store's workers, `proleg results`, replays and `proleg suite --run` need
//! nothing new; its algorithm names the stage ("CMA-ES, curriculum stage 2 of 3
//! (steps-medium)"). `--resume` finds each stage's last run: a finished stage is replayed
//! from the store (nothing simulated, the same best), an unfinished one continues, and
//! the stages after it start anew.

use crate::config::Simulation;
use crate::config::courses::StageSpec;
use crate::config::optimizer::write_optimizer_file;
use crate::config::{FsSource, load_simulation_with};
use crate::control::ModuleRegistry;
use crate::optimize::error::OptimizeError;
use crate::optimize::experiment::{Experiment, ExperimentReport, ExperimentRequest, StageRequest};
use crate::optimize::session::Evaluation;
use crate::optimize::settings::RunSettings;
use crate::optimize::space::Genome;

/// A curriculum's stage about to run.
#[derive(Debug, Clone, Copy)]
pub struct StageOf<'a> {
    /// The curriculum.
    pub curriculum: &'a Curriculum,
    /// The stage, 1-based.
    pub number: usize,
}

/// Runs `request`: its curriculum's stages one after another when its optimizer file has
/// one, else the one run. `on_open` is told of each run before it starts (with its
/// curriculum and 1-based stage, if any), `on_eval` of every evaluation (numbered across a
/// curriculum's stages). What `proleg optimize` and the control window's optimization view
/// call.
pub fn run_request(
    request: &ExperimentRequest,
    registry: &ModuleRegistry,
    on_open: &mut dyn FnMut(Option<StageOf<'_>>, &Experiment),
    on_eval: &mut dyn FnMut(&Evaluation),
) -> Result<ExperimentReport, OptimizeError> {
    // The configuration is loaded once for an ordinary run; a curriculum's file is read
    // again as stages (each stage a run of its own).
    let curriculum = match Experiment::open(request, registry) {
        Ok(experiment) => {
            on_open(None, &experiment);
            return experiment.run(registry, on_eval);
        }
        Err(e @ OptimizeError::CurriculumAsOneRun { .. }) => {
            Curriculum::of(request, registry)?.ok_or(e)?
        }
        Err(e) => return Err(e),
    };
    let mut opened = |number: usize, x: &Experiment| {
        on_open(
            Some(StageOf {
                curriculum: &curriculum,
                number,
            }),
            x,
        );
    };
    curriculum.run(request, registry, &mut opened, on_eval)
}

/// A curriculum read from a simulation's optimizer file.
#[derive(Debug, Clone, PartialEq)]
pub struct Curriculum {
    /// The optimizer file.
    file: std::path::PathBuf,
    /// The optimizer file's text for each stage.
    texts: Vec<String>,
    /// The stages as written.
    stages: Vec<StageSpec>,
    /// The evaluation budget the stages share.
    budget: u64,
}

/// How one stage went.
#[derive(Debug, Clone, PartialEq)]
pub struct StageSummary {
    /// 1-based stage number.
    pub number: usize,
    /// Stages in the curriculum.
    pub of: usize,
    /// The stage's tasks.
    pub tasks: Vec<String>,
    /// The score that ends it (none for the last).
    pub until: Option<f64>,
    /// Its run in the store.
    pub run: i64,
    /// Evaluations it did (simulated or replayed from the store).
    pub evaluations: u64,
    /// Of them simulated in this call.
    pub simulated: u64,
    /// Its best score.
    pub best_score: f64,
    /// Whether its best reached `until`.
    pub reached: bool,
}

impl Curriculum {
    /// The curriculum of `request`'s configuration, if its optimizer file has one.
    pub fn of(
        request: &ExperimentRequest,
        registry: &ModuleRegistry,
    ) -> Result<Option<Curriculum>, OptimizeError> {
        let sim = load_simulation_with(&FsSource, &request.config, registry)
            .map_err(|e| OptimizeError::Config(Box::new(e)))?;
        Curriculum::of_simulation(&sim, request)
    }

    fn of_simulation(
        sim: &Simulation,
        request: &ExperimentRequest,
    ) -> Result<Option<Curriculum>, OptimizeError> {
        let Some(model) = &sim.optimizer else {
            return Ok(None);
        };
        let Some(courses) = model.spec.courses.as_ref().filter(|c| !c.stages.is_empty()) else {
            return Ok(None);
        };
        let texts = (0..courses.stages.len())
            .map(|k| {
                let mut file = model.spec.clone();
                file.courses = courses.stage(k);
                write_optimizer_file(&file)
            })
            .collect();
        Ok(Some(Curriculum {
            file: model.file.clone(),
            texts,
            stages: courses.stages.clone(),
            budget: RunSettings::of(sim, &request.choices)?.max_evaluations,
        }))
    }

    /// Stages in the curriculum.
    pub fn len(&self) -> usize {
        self.stages.len()
    }

    /// Whether it has no stage (never: a curriculum has at least one).
    pub fn is_empty(&self) -> bool {
        self.stages.is_empty()
    }

    /// The evaluation budget all stages share.
    pub fn budget(&self) -> u64 {
        self.budget
    }

    /// Stage `k`'s (0-based) tasks.
    pub fn tasks(&self, k: usize) -> &[String] {
        self.stages.get(k).map_or(&[], |s| &s.tasks)
    }

    /// The request of stage `k` (0-based) after `used` evaluations: `base`'s, with the
    /// stage's optimizer file, start and the evaluations left (the testing aid
    /// `crash_after` counts across the stages too).
    pub fn stage_request(
        &self,
        base: &ExperimentRequest,
        k: usize,
        start: Option<Genome>,
        used: u64,
    ) -> ExperimentRequest {
        let (spec, n) = (&self.stages[k], self.stages.len());
        let mut request = base.clone();
        request.choices.max_evaluations = Some(self.budget.saturating_sub(used));
        request.crash_after = base.crash_after.map(|c| c.saturating_sub(used));
        request.stage = Some(StageRequest {
            label: format!(
                "curriculum stage {} of {n} ({})",
                k + 1,
                spec.tasks.join(" ")
            ),
            optimizer: (self.file.clone(), self.texts[k].clone()),
            start,
            until: spec.until,
            may_start: k > 0,
        });
        request
    }

    /// Runs the stages in order: `on_open` is told of each stage's experiment (1-based
    /// number) before it runs, `on_eval` of every evaluation, numbered across the stages.
    /// The report is the last stage's (its best is the curriculum's), with every stage's
    /// summary.
    pub fn run(
        &self,
        base: &ExperimentRequest,
        registry: &ModuleRegistry,
        on_open: &mut dyn FnMut(usize, &Experiment),
        on_eval: &mut dyn FnMut(&Evaluation),
    ) -> Result<ExperimentReport, OptimizeError> {
        let (mut start, mut used, mut stages) = (None, 0u64, Vec::new());
        let mut last = None;
        for (k, spec) in self.stages.iter().enumerate() {
            if used >= self.budget {
                break;
            }
            let experiment = Experiment::open(&self.stage_request(base, k, start, used), registry)?;
            on_open(k + 1, &experiment);
            let offset = used;
            let report = experiment.run(registry, |e: &Evaluation| {
                on_eval(&Evaluation {
                    number: e.number + offset,
                    ..e.clone()
                })
            })?;
            let o = &report.outcome;
            used += o.evaluations;
            stages.push(StageSummary {
                number: k + 1,
                of: self.stages.len(),
                tasks: spec.tasks.clone(),
                until: spec.until,
                run: report.store.1,
                evaluations: o.evaluations,
                simulated: o.simulated,
                best_score: o.best_score,
                reached: o.reached,
            });
            start = Some(o.best.clone());
            let go_on = o.reached && !o.stopped;
            last = Some(report);
            if !go_on {
                break;
            }
        }
        let mut last: ExperimentReport = last.ok_or(OptimizeError::NothingEvaluated)?;
        last.curriculum = stages;
        Ok(last)
    }
}

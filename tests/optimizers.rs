//! The optimizers on known objectives, their reproducibility, the genome
//! encoding, and the evaluator's independence from the number of workers.

mod common;

use proleg::config::fitness::Fitness;
use proleg::config::optimizer::{GaSettings, GdSettings};
use proleg::control::ModuleRegistry;
use proleg::control::load_simulation;
use proleg::optimize::Optimizer;
use proleg::optimize::cmaes::CmaOptimizer;
use proleg::optimize::deluge::GreatDeluge;
use proleg::optimize::evaluate::Evaluator;
use proleg::optimize::ga::GeneticAlgorithm;
use proleg::optimize::run::prepare;
use proleg::optimize::space::{Alleles, Gene, Genome, SearchSpace};

const TARGET: [f64; 5] = [10.0, 20.0, 30.0, 5.0, 35.0];

/// Five amplitudes 0..40 deg in 0.25 deg steps, like experiment 1.
fn space() -> SearchSpace {
    SearchSpace {
        genes: (0..5)
            .map(|j| Gene {
                module: "PatternGenerator_sinusoidal",
                parameter: "Amplitude",
                joints: vec![j],
                alleles: Alleles::Range {
                    first: 0.0,
                    inc: 0.25,
                    count: 161,
                },
                network: None,
            })
            .collect(),
    }
}

/// A separable quadratic with its maximum 0 on the grid at TARGET.
fn objective(space: &SearchSpace, g: &Genome) -> f64 {
    -space
        .decode(g)
        .iter()
        .zip(TARGET)
        .map(|(v, t)| (v - t).powi(2))
        .sum::<f64>()
}

/// Runs an optimizer on the objective; returns the best score and every candidate asked.
fn drive(mut o: impl Optimizer, space: &SearchSpace) -> (f64, Vec<Genome>) {
    let mut asked = Vec::new();
    while !o.finished() {
        let c = o.ask();
        if c.is_empty() {
            break;
        }
        let scores: Vec<f64> = c.iter().map(|g| objective(space, g)).collect();
        asked.extend(c);
        o.tell(&scores);
    }
    (o.best().map(|b| b.1).unwrap_or(f64::NEG_INFINITY), asked)
}

fn ga(seed: u64, max: u64) -> GeneticAlgorithm {
    let s = space();
    let settings = GaSettings {
        popsize: 40,
        pmut: 0.1,
        pcross: 0.9,
        n_convergence: 100,
        p_convergence: 0.9999,
        flush_frequency: 1,
        ga_mode: 1,
    };
    GeneticAlgorithm::new(s.clone(), settings, vec![160; 5], seed, max)
}

fn gd(seed: u64, batch: usize, max: u64) -> GreatDeluge {
    let settings = GdSettings {
        credits: 10,
        retries: 200,
        initial_water_level: -8000.0,
        rain: 5.0,
        confidence: 20,
    };
    GreatDeluge::new(space(), settings, vec![160; 5], seed, batch, max)
}

#[test]
fn the_genetic_algorithm_finds_the_optimum_of_a_quadratic() {
    let s = space();
    let start = objective(&s, &vec![160; 5]);
    let (best, asked) = drive(ga(1, 20_000), &s);
    eprintln!(
        "GA: start {start}, best {best} after {} evaluations",
        asked.len()
    );
    assert!(best > -1.0, "best {best}");
    assert!(asked.len() <= 20_000);
}

#[test]
fn the_great_deluge_finds_the_optimum_of_a_quadratic() {
    let s = space();
    let (best, asked) = drive(gd(1, 1, 20_000), &s);
    eprintln!("GD: best {best} after {} evaluations", asked.len());
    assert!(best > -1.0, "best {best}");
}

#[test]
fn cma_es_finds_the_optimum_of_a_quadratic_on_the_allele_grid() {
    let s = space();
    let o = CmaOptimizer::new(s.clone(), vec![160; 5], 0.3, 0, 1, 20_000);
    let (best, asked) = drive(o, &s);
    eprintln!("CMA-ES: best {best} after {} evaluations", asked.len());
    // The grid's optimum (0) exactly, long before the GA's budget: converged, it stops.
    assert_eq!(best, 0.0, "best {best}");
    assert!(asked.len() <= 2_000, "{} evaluations", asked.len());
    assert_eq!(asked[0], vec![160; 5], "the start is evaluated first");
}

#[test]
fn cma_es_restarts_with_a_doubled_population_after_converging() {
    let s = space();
    let alone = drive(
        CmaOptimizer::new(s.clone(), vec![160; 5], 0.3, 0, 1, 5_000),
        &s,
    );
    let o = CmaOptimizer::with_restarts(s.clone(), vec![160; 5], 0.3, 0, 1, 5_000, 2);
    let (best, asked) = drive(o, &s);
    assert_eq!(best, 0.0);
    // Without restarts it stops at convergence; with two it goes on, with 8 then 16 then
    // 32 candidates per generation (the default for 5 genes is 8).
    assert!(
        asked.len() > alone.1.len(),
        "{} vs {}",
        asked.len(),
        alone.1.len()
    );
    let mut o = CmaOptimizer::with_restarts(s.clone(), vec![160; 5], 0.3, 0, 1, 5_000, 2);
    let mut sizes = Vec::new();
    while !o.finished() {
        let c = o.ask();
        sizes.push(c.len());
        let scores: Vec<f64> = c.iter().map(|g| objective(&s, g)).collect();
        o.tell(&scores);
    }
    assert_eq!(o.restarts_done(), 2);
    assert_eq!(sizes[1], 8);
    assert!(sizes.contains(&16) && sizes.contains(&32), "{sizes:?}");
}

#[test]
fn the_great_deluge_stops_when_its_credits_are_gone() {
    // A water level no candidate reaches: every credit is spent on failures.
    let settings = GdSettings {
        credits: 3,
        retries: 10,
        initial_water_level: 1.0,
        rain: 0.1,
        confidence: 2,
    };
    let s = space();
    let o = GreatDeluge::new(s.clone(), settings, vec![0; 5], 7, 1, u64::MAX);
    let (_, asked) = drive(o, &s);
    assert_eq!(
        asked.len(),
        1 + 4 * 10,
        "the start, then (credits + 1) x retries failures"
    );
}

#[test]
fn the_same_seed_gives_the_same_candidates() {
    let s = space();
    let (_, a) = drive(ga(5, 2_000), &s);
    let (_, b) = drive(ga(5, 2_000), &s);
    let (_, c) = drive(ga(6, 2_000), &s);
    assert_eq!(a, b);
    assert_ne!(a, c);
    let (_, a) = drive(gd(5, 4, 2_000), &s);
    let (_, b) = drive(gd(5, 4, 2_000), &s);
    assert_eq!(a, b);
    assert_eq!(a.len(), 2_000, "the evaluation budget is kept");
    let cma = |seed| CmaOptimizer::new(space(), vec![0; 5], 0.3, 0, seed, 300);
    let (_, a) = drive(cma(5), &s);
    let (_, b) = drive(cma(5), &s);
    let (_, c) = drive(cma(6), &s);
    assert_eq!(a, b);
    assert_ne!(a, c);
    assert!(a.len() <= 300, "the evaluation budget is kept");
}

#[test]
fn genomes_round_trip_through_a_kernel_and_an_actuation_file() {
    let sim =
        load_simulation(common::root().join("configs/experiment1_gd.simulation.xml")).unwrap();
    let (space, start) = prepare(&sim, &ModuleRegistry::standard()).unwrap();
    assert_eq!(space.genes.len(), 5);
    assert_eq!(
        space.decode(&start),
        vec![40.0; 5],
        "experiment 1 starts at uniform 40 deg"
    );
    let genome: Genome = vec![0, 17, 80, 123, 160];
    let mut kernel = proleg::sim::Simulator::new(&sim, &Default::default())
        .unwrap()
        .kernel(0)
        .unwrap()
        .clone();
    space.apply(&genome, &mut kernel).unwrap();
    assert_eq!(space.encode_kernel(&kernel), genome);
    // The best-candidate actuation file loads and holds the values.
    let file = proleg::optimize::result::actuation_with(&sim, &space, &genome);
    let text = proleg::config::actuation::write_actuation_file(&file);
    let parsed =
        proleg::config::actuation::parse_actuation_file("best.actuation.xml", &text).unwrap();
    let amp = parsed.modules[0]
        .params
        .iter()
        .find(|p| p.name == "Amplitude")
        .unwrap();
    assert_eq!(
        amp.value,
        proleg::config::actuation::ParamValue::PerJoint(vec![0.0, 4.25, 20.0, 30.75, 40.0])
    );
}

#[test]
fn scores_do_not_depend_on_workers_or_batching() {
    let sim =
        load_simulation(common::root().join("configs/experiment1_gd.simulation.xml")).unwrap();
    let (space, start) = prepare(&sim, &ModuleRegistry::standard()).unwrap();
    let genomes: Vec<Genome> = vec![
        start.clone(),
        vec![80; 5],
        vec![160, 120, 80, 40, 0],
        vec![40; 5],
    ];
    let eval = |workers: usize, batch: usize| {
        Evaluator {
            batch,
            workers,
            ..Evaluator::new(
                &sim,
                &ModuleRegistry::standard(),
                &space,
                Fitness::Displacement,
                2.0,
                1,
            )
        }
        .evaluate(&genomes)
        .unwrap()
    };
    let one = eval(1, 1);
    assert_eq!(eval(2, 1), one, "workers");
    assert_eq!(eval(2, 2), one, "two robots per world");
    assert_eq!(eval(1, 4), one, "four robots per world");
    assert!(
        one[0] > one[1],
        "40 deg crawls farther than 20 deg: {one:?}"
    );
}

#[test]
fn an_episode_stops_scoring_when_its_robot_falls_off_the_floor_end() {
    use proleg::config::simulation::EngineKind;
    use proleg::optimize::evaluate::EpisodeWorld;
    let dir = common::scratch("floor-end");
    let mut engines = vec![EngineKind::Rapier];
    if common::mujoco_here("an_episode_stops_scoring_when_its_robot_falls_off_the_floor_end") {
        engines.push(EngineKind::Mujoco);
    }
    let registry = ModuleRegistry::standard();
    let score = |sim: &proleg::config::Simulation, engine, seconds| {
        let space = SearchSpace::default();
        Evaluator::new(sim, &registry, &space, Fitness::Distance, seconds, 1)
            .run_world(sim, EpisodeWorld::nominal(1, Some(engine)), &[vec![]])
            .unwrap()[0]
    };
    let (short, long) = (
        common::floor_ending_at(&dir, 0.8),
        common::floor_ending_at(&dir, 20.0),
    );
    for engine in engines {
        // On a long floor the gait goes on: farther at 15 s than at 12 s.
        let (on_12, on_15) = (score(&long, engine, 12.0), score(&long, engine, 15.0));
        assert!(
            on_12 > 0.8 && on_15 > on_12 + 0.1,
            "{engine:?}: the gait crawls on a long floor: {on_12} m at 12 s, {on_15} m at 15 s"
        );
        // Where the floor ends 0.8 m ahead it falls off before 12 s, and its score is
        // where it left the world, whatever the episode's length.
        let (off_12, off_15) = (score(&short, engine, 12.0), score(&short, engine, 15.0));
        assert_eq!(off_12, off_15, "{engine:?}: the score stood once it fell");
        assert!(
            off_12 > 0.4 && off_12 < 1.2,
            "{engine:?}: scored {off_12} m on a floor that ends 0.66 m ahead of its centre"
        );
    }
}

#[test]
fn a_stopped_experiment_stays_unfinished_and_resumes_to_the_uninterrupted_result() {
    use proleg::optimize::experiment::{Experiment, ExperimentRequest};
    use proleg::optimize::settings::RunChoices;
    use proleg::optimize::store::{Store, StoreLocation};
    use proleg::signal::StopFlag;
    let dir = common::scratch("stopped-experiment");
    let registry = ModuleRegistry::standard();
    let request = |store: &str, stop: StopFlag, resume: bool| ExperimentRequest {
        config: common::root().join("configs/experiment1_gd.simulation.xml"),
        choices: RunChoices {
            workers: Some(2),
            max_evaluations: Some(24),
            duration: Some(1.0),
            ..RunChoices::default()
        },
        store: Some(dir.join(store).display().to_string()),
        resume,
        stop,
        ..ExperimentRequest::default()
    };
    let whole = Experiment::open(
        &request("whole.sqlite", StopFlag::default(), false),
        &registry,
    )
    .unwrap()
    .run(&registry, |_| {})
    .unwrap();
    assert!(!whole.outcome.stopped && whole.outcome.evaluations == 24);
    // Stopped during the run: its round ends, the run stays unfinished.
    let stop = StopFlag::default();
    let flag = stop.clone();
    let first = Experiment::open(&request("parts.sqlite", stop, false), &registry)
        .unwrap()
        .run(&registry, |e| {
            if e.number == 5 {
                flag.stop();
            }
        })
        .unwrap();
    assert!(first.outcome.stopped, "{:?}", first.outcome);
    assert!(first.outcome.evaluations < 24);
    let location = StoreLocation::parse(&dir.join("parts.sqlite").display().to_string()).unwrap();
    let mut store = Store::open_existing(&location).unwrap();
    assert!(!store.run_finished(first.store.1).unwrap());
    drop(store);
    // Resumed, it reuses what was stored and ends where the whole run ended.
    let rest = Experiment::open(
        &request("parts.sqlite", StopFlag::default(), true),
        &registry,
    )
    .unwrap()
    .run(&registry, |_| {})
    .unwrap();
    assert_eq!(rest.store.1, first.store.1, "the same run continued");
    assert_eq!(rest.outcome.simulated, 24 - first.outcome.evaluations);
    assert_eq!(
        (rest.outcome.best.clone(), rest.outcome.best_score),
        (whole.outcome.best.clone(), whole.outcome.best_score)
    );
}

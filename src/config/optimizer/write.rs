//! Writing an optimizer file back (the reader's inverse).

use crate::config::cross_engine::write_cross_engine;
use crate::config::fitness::Fitness;
use crate::config::optimizer::{Algorithm, OptimizerFile};
use crate::config::robustness::write_robustness;
use crate::config::xml::write::XmlWriter;

/// Writes an optimizer file.
pub fn write_optimizer_file(o: &OptimizerFile) -> String {
    let mut w = XmlWriter::new();
    let root = match &o.algorithm {
        Algorithm::Genetic(_) => "geneticAlgorithm",
        Algorithm::GreatDeluge(_) => "greatDeluge",
        Algorithm::CmaEs(_) => "cmaEvolutionStrategy",
        Algorithm::MapElites(_) => "mapElites",
        Algorithm::Es(_) => "evolutionStrategy",
    };
    w.open(root, &[]);
    w.open("properties", &[]);
    write_algorithm(&mut w, &o.algorithm);
    if o.fitness != Fitness::Displacement {
        w.leaf("fitness", o.fitness.name());
    }
    if let Some(m) = o.max_evaluations {
        w.leaf("maxEvaluations", &m.to_string());
    }
    if o.random_start {
        w.flag("randomStart", true);
    }
    if let Some(c) = &o.cross_engine {
        write_cross_engine(&mut w, c);
    }
    w.leaf("numOfParametersToOptimize", &o.parameters.len().to_string());
    w.open("registeredParameters", &[]);
    for p in &o.parameters {
        w.empty(
            "parameter",
            &[
                ("number", p.number.to_string()),
                ("controlAlgorithm", p.module.clone()),
                ("parameter", p.parameter.clone()),
            ],
        );
    }
    w.close();
    w.close();
    for g in &o.genome {
        w.open(
            "genomeConfig",
            &[
                ("number", g.number.to_string()),
                ("allJoints", if g.all_joints { "1" } else { "0" }.into()),
                ("genomeType", g.genome_type.to_string()),
                ("valueType", g.value_type.to_string()),
                ("valueSpace", g.value_space.to_string()),
                ("activeJoints", g.active_joints.to_string()),
            ],
        );
        for (name, v) in [
            ("upperBounds", &g.upper),
            ("lowerBounds", &g.lower),
            ("boundsIncrements", &g.increments),
        ] {
            if !v.is_empty() {
                w.nums(name, v);
            }
        }
        w.leaf("lowerBoundTypes", &(g.lower_bound_type as u32).to_string());
        w.leaf("upperBoundTypes", &(g.upper_bound_type as u32).to_string());
        if !g.values.is_empty() {
            w.nums("values", &g.values);
        }
        w.flag("uniform", g.uniform);
        w.close();
    }
    if let Some(rb) = &o.robustness {
        write_robustness(&mut w, rb);
    }
    if let Some(c) = &o.courses {
        crate::config::courses::write_courses(&mut w, c);
    }
    if let Some(m) = &o.morphology {
        crate::config::morphology::write_morphology(&mut w, m);
    }
    w.finish()
}

/// The algorithm's own properties.
fn write_algorithm(w: &mut XmlWriter, algorithm: &Algorithm) {
    match algorithm {
        Algorithm::Genetic(g) => {
            w.leaf("popsize", &g.popsize.to_string());
            w.num("pmut", g.pmut);
            w.num("pcross", g.pcross);
            w.leaf("nConvergence", &g.n_convergence.to_string());
            w.num("pConvergence", g.p_convergence);
            w.leaf("flushFrequency", &g.flush_frequency.to_string());
            w.leaf("gaMode", &g.ga_mode.to_string());
        }
        Algorithm::GreatDeluge(g) => {
            w.leaf("credits", &g.credits.to_string());
            w.leaf("retries", &g.retries.to_string());
            w.num("initialWaterLevel", g.initial_water_level);
            w.num("rain", g.rain);
            w.leaf("confidence", &g.confidence.to_string());
        }
        Algorithm::Es(e) => {
            w.leaf("popsize", &e.popsize.to_string());
            w.num("sigma", e.sigma);
            w.num("learningRate", e.learning_rate);
            w.num("weightDecay", e.weight_decay);
        }
        Algorithm::CmaEs(c) => {
            w.leaf("popsize", &c.popsize.to_string());
            w.num("sigma", c.sigma);
            if c.restarts > 0 {
                w.leaf("restarts", &c.restarts.to_string());
            }
        }
        Algorithm::MapElites(m) => {
            w.leaf("initialSamples", &m.initial.to_string());
            w.leaf("batch", &m.batch.to_string());
            w.num("mutation", m.mutation);
            for d in &m.descriptors {
                let bins = ("bins", d.bins.to_string());
                let attrs = match (&d.measured, d.yaw_share) {
                    (Some(q), _) => vec![
                        ("name", q.quantity.name().to_string()),
                        ("min", q.range[0].to_string()),
                        ("max", q.range[1].to_string()),
                        bins,
                    ],
                    (None, true) => vec![("name", "yaw-share".to_string()), bins],
                    (None, false) => vec![("gene", d.gene.to_string()), bins],
                };
                w.empty("descriptor", &attrs);
            }
        }
    }
}

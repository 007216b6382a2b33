//! Parameter optimization (thesis 3.4, 4.3.3, B.7), free of rendering: the search space
//! built from the registered parameters ([`space`]), the genetic algorithm ([`ga`]) and
//! the modified great deluge ([`deluge`]) behind one ask/tell interface
//! ([`Optimizer`]), fitness functions ([`fitness`]) and the evaluator that runs
//! candidates as seeded headless episodes, batched per world, on every core
//! ([`evaluate`]); the experiment store ([`store`]: SQLite, or PostgreSQL shared by a
//! driver and workers on many hosts, [`shared`]).

pub mod archive;
pub mod behaviour;
pub mod cmaes;
pub mod curve;
pub mod deluge;
pub mod design;
pub mod error;
pub mod es;
pub mod evaluate;
pub mod experiment;
pub mod export;
pub mod fitness;
pub mod ga;
pub mod gallery;
pub mod local;
pub mod map_elites;
pub mod prepare;
pub mod replay;
pub mod result;
pub mod robust;
pub mod run;
pub mod scorer;
pub mod scores;
pub mod session;
pub mod settings;
pub mod shared;
pub mod space;
pub mod store;

pub use space::{Genome, SearchSpace};

/// A search strategy: hands out candidates, is told their scores (higher is better).
pub trait Optimizer: Send {
    /// The next candidates to evaluate (empty when finished).
    fn ask(&mut self) -> Vec<Genome>;
    /// The scores of the candidates of the last `ask`, in order.
    fn tell(&mut self, scores: &[f64]);
    /// The scores and the quantities measured in their episodes (MAP-Elites places
    /// candidates by measured descriptors; the others use the scores alone).
    fn tell_measured(&mut self, scores: &[f64], _measures: &[Vec<f64>]) {
        self.tell(scores);
    }
    /// Whether the search has stopped.
    fn finished(&self) -> bool;
    /// The best candidate seen and its score.
    fn best(&self) -> Option<(&Genome, f64)>;
}

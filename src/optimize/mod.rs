//! Parameter optimization (thesis 3.4, 4.3.3, B.7), free of rendering: optimizers behind
//! one ask/tell interface ([`Optimizer`]), the evaluator that runs candidates as seeded
//! headless episodes on every core, and the experiment store every evaluation is written to.
//!
//! The search:
//! - [`space`]: the search space (one gene per registered parameter or joint, eq. 3.3)
//! - [`prepare`]: a simulation's search space and start candidate
//! - [`ga`]: the genetic algorithm; [`deluge`]: the modified great deluge (thesis 3.4.2)
//! - [`cmaes`]: CMA-ES; [`es`]: OpenAI's evolution strategy (policies' many weights)
//! - [`map_elites`]: MAP-Elites over two behaviour descriptors; [`archive`]: a stored run's
//!   archive rebuilt and drawn; [`behaviour`]: the descriptors measured in an episode
//! - [`design`]: co-design candidates (a body and a gait in one genome)
//!
//! Running one:
//! - [`session`]: one optimization, prepared once and run round by round; [`run`]: the
//!   same in one call, and the names its callers use
//! - [`settings`]: seed, workers, batching, budget, episode and fitness, from files and choices
//! - [`experiment`]: an optimization recorded in a store (`proleg optimize`, the window's view)
//! - [`curriculum`]: a curriculum's stages run one after another, each a stored run
//! - [`evaluate`]: the evaluator: candidates as episodes of the episode runner, batched per
//!   world, on threads; [`robust`]: scores over randomized episodes
//! - [`scorer`]: how a round gets its scores (this host: [`local`]; a shared store's
//!   workers: [`shared`]); [`scores`]: the records passed between them
//! - [`store`]: the experiment store (SQLite, or PostgreSQL shared by many hosts)
//! - [`error`]: the layer's errors
//!
//! What a run leaves:
//! - [`replay`]: a stored evaluation replayed step for step (headless, a window, a video)
//! - [`result`]: a candidate written back as an actuation file (and its networks' weights)
//! - [`export`]: a stored candidate as a folder that runs on its own
//! - [`curve`]: learning curves; [`gallery`]: which co-design bodies a gallery shows

pub mod archive;
pub mod behaviour;
pub mod cmaes;
pub mod curriculum;
pub mod curve;
pub mod deluge;
pub mod design;
pub mod error;
pub mod es;
pub mod evaluate;
pub mod experiment;
pub mod export;
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

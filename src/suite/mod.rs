//! Task suites run: a controller scored on every task's held-out test courses on both
//! engines, with a journal to resume from and a report of per-task figures and
//! interquartile means with bootstrap intervals.
//!
//! | module | role |
//! |---|---|
//! | [`episode`] | one episode on one engine, measured along the course ([`episode::EpisodeResult`]) |
//! | [`run`] | the run: which episodes, in parallel, journaled ([`run::SuiteRun`]) |
//! | [`journal`] | the journal of finished episodes, resumed from |
//! | [`report`] | the table and the aggregates ([`report::SuiteReport`]) |
//! | [`chart`] | its picture: a bar per task, the goal lines |
//! | [`error`] | [`SuiteError`] |

pub mod chart;
pub mod episode;
pub mod error;
pub mod journal;
pub mod report;
pub mod run;

pub use error::SuiteError;
pub use report::SuiteReport;
pub use run::SuiteRun;

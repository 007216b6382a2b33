//! Task suites run: a controller scored on every task's held-out test courses on both
//! engines (each episode run by [`crate::sim::episode::course`]), on the local cores or a
//! shared store's workers, with a journal to resume from and a report of per-task figures and
//! interquartile means with bootstrap intervals.
//!
//! | module | role |
//! |---|---|
//! | [`run`] | the run: which episodes, in parallel, journaled ([`run::SuiteRun`]) |
//! | [`shared`] | the run on a shared store's workers ([`shared::SharedSuite`]) |
//! | [`journal`] | the journal of finished episodes, resumed from |
//! | [`report`] | the table and the aggregates ([`report::SuiteReport`]) |
//! | [`chart`] | its picture: a bar per task, the goal lines |
//! | [`error`] | [`SuiteError`] |

pub mod chart;
pub mod error;
pub mod journal;
pub mod report;
pub mod run;
pub mod shared;

pub use error::SuiteError;
pub use report::SuiteReport;
pub use run::SuiteRun;

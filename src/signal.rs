//! One door for Ctrl-C and SIGTERM: a process-wide handler, installed once by the first
//! [`subscribe`], raises the flag of every live [`Subscription`] (and calls its wake-up),
//! so any number of parts of one process (a run, a worker pool, a window) each get a stop
//! flag that a signal really sets. A dropped subscription hears no more signals.
//!
//! The first signal asks every subscriber to stop (the episode runner sees it between
//! chunks of steps, so a long command answers within about a second); a second one ends
//! the process at once with the status a shell gives a killed program (130 for Ctrl-C,
//! 143 for SIGTERM), and [`received`] tells the program's `main` which signal stopped it.
//! The handlers are signal-hook's (a flag set in the handler itself, a thread that wakes
//! the subscribers), so the second signal ends the process even when that thread is busy.

use std::sync::atomic::{AtomicBool, AtomicI32, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

use signal_hook::consts::{SIGINT, SIGTERM};

/// Called on the signal thread after a subscriber's flag is raised.
type Wake = Box<dyn Fn() + Send + Sync>;

struct Subscriber {
    id: u64,
    flag: Arc<AtomicBool>,
    wake: Option<Wake>,
}

static SUBSCRIBERS: Mutex<Vec<Subscriber>> = Mutex::new(Vec::new());
static INSTALLED: OnceLock<Result<(), Arc<std::io::Error>>> = OnceLock::new();
static NEXT_ID: AtomicU64 = AtomicU64::new(0);
/// The first signal received (0: none yet).
static RECEIVED: AtomicI32 = AtomicI32::new(0);

/// The process's signal handler could not be installed.
#[derive(Debug, Clone, thiserror::Error)]
#[error("cannot handle Ctrl-C and SIGTERM: {0}")]
pub struct SignalError(#[source] Arc<std::io::Error>);

/// A flag that asks a run to stop: raised by a signal through a [`Subscription`], or from
/// another thread (the control window's Stop). The episode runner reads it between chunks
/// of steps, an optimizer between rounds.
#[derive(Debug, Clone, Default)]
pub struct StopFlag(pub Arc<AtomicBool>);

impl StopFlag {
    /// Asks the run to stop.
    pub fn stop(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether the run was asked to stop.
    pub fn is_set(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }
}

impl PartialEq for StopFlag {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// A stop flag raised by the next Ctrl-C or SIGTERM, as long as it is kept.
pub struct Subscription {
    id: u64,
    flag: Arc<AtomicBool>,
}

impl Subscription {
    /// Whether a signal arrived since this subscription was made.
    pub fn is_raised(&self) -> bool {
        self.flag.load(Ordering::SeqCst)
    }

    /// The flag itself, to hand to code that polls it (it is raised only while this
    /// subscription lives).
    pub fn flag(&self) -> StopFlag {
        StopFlag(self.flag.clone())
    }
}

impl Drop for Subscription {
    fn drop(&mut self) {
        subscribers().retain(|s| s.id != self.id);
    }
}

/// The signal that stopped this process (`SIGINT` = 2, `SIGTERM` = 15), if one arrived.
pub fn received() -> Option<i32> {
    match RECEIVED.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}

/// The exit status a shell gives a program that `signal` ended (128 + its number).
pub fn exit_status(signal: i32) -> u8 {
    u8::try_from(128 + signal).unwrap_or(u8::MAX)
}

/// The subscribers, also after a subscriber's wake-up panicked while they were held.
fn subscribers() -> MutexGuard<'static, Vec<Subscriber>> {
    SUBSCRIBERS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Installs the handlers: per signal, first a shutdown armed by an earlier signal, then the
/// flag that arms it (signal-hook's double Ctrl-C pattern); and the thread that raises the
/// subscribers' flags.
fn install_handlers() -> std::io::Result<()> {
    let armed = Arc::new(AtomicBool::new(false));
    for sig in [SIGINT, SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(
            sig,
            i32::from(exit_status(sig)),
            armed.clone(),
        )?;
        signal_hook::flag::register(sig, armed.clone())?;
    }
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM])?;
    std::thread::Builder::new()
        .name("proleg-signals".into())
        .spawn(move || {
            for sig in signals.forever() {
                // Only the first signal is kept: it is the one that asked to stop (this
                // thread is the only writer).
                if received().is_none() {
                    RECEIVED.store(sig, Ordering::SeqCst);
                }
                for s in subscribers().iter() {
                    s.flag.store(true, Ordering::SeqCst);
                    if let Some(wake) = &s.wake {
                        wake();
                    }
                }
            }
        })?;
    Ok(())
}

fn install() -> Result<(), SignalError> {
    INSTALLED
        .get_or_init(|| install_handlers().map_err(Arc::new))
        .clone()
        .map_err(SignalError)
}

fn add(wake: Option<Wake>) -> Result<Subscription, SignalError> {
    let (id, flag) = (
        NEXT_ID.fetch_add(1, Ordering::SeqCst),
        Arc::new(AtomicBool::new(false)),
    );
    // Listed before the handlers exist: a signal that comes as they are installed finds it.
    subscribers().push(Subscriber {
        id,
        flag: flag.clone(),
        wake,
    });
    let subscription = Subscription { id, flag };
    install()?;
    Ok(subscription)
}

/// A stop flag for the next Ctrl-C / SIGTERM (installs the handler on first use).
pub fn subscribe() -> Result<Subscription, SignalError> {
    add(None)
}

/// [`subscribe`], and `wake` is called (on the signal thread) when the signal arrives: to
/// wake an event loop that waits for input, or to say at once that the command is stopping.
pub fn subscribe_with(
    wake: impl Fn() + Send + Sync + 'static,
) -> Result<Subscription, SignalError> {
    add(Some(Box::new(wake)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exit_statuses_are_the_shells() {
        assert_eq!(exit_status(SIGINT), 130);
        assert_eq!(exit_status(SIGTERM), 143);
    }
}

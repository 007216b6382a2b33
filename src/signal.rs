//! One door for Ctrl-C and SIGTERM: a process-wide handler, installed once by the first
//! [`subscribe`], raises the flag of every live [`Subscription`] (and calls its wake-up),
//! so any number of parts of one process (a run, a worker pool, a window) each get a stop
//! flag that a signal really sets. A dropped subscription hears no more signals.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

/// Called on the signal handler's thread after a subscriber's flag is raised.
type Wake = Box<dyn Fn() + Send + Sync>;

struct Subscriber {
    id: u64,
    flag: Arc<AtomicBool>,
    wake: Option<Wake>,
}

static SUBSCRIBERS: Mutex<Vec<Subscriber>> = Mutex::new(Vec::new());
static INSTALLED: OnceLock<Result<(), Arc<ctrlc::Error>>> = OnceLock::new();
static NEXT_ID: AtomicU64 = AtomicU64::new(0);

/// The process's signal handler could not be installed (another one owns the signals).
#[derive(Debug, Clone, thiserror::Error)]
#[error("cannot handle Ctrl-C and SIGTERM: {0}")]
pub struct SignalError(Arc<ctrlc::Error>);

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

    /// The flag itself, to hand to code that polls an `AtomicBool` (it is raised only
    /// while this subscription lives).
    pub fn flag(&self) -> Arc<AtomicBool> {
        self.flag.clone()
    }
}

impl Drop for Subscription {
    fn drop(&mut self) {
        subscribers().retain(|s| s.id != self.id);
    }
}

/// The subscribers, also after a subscriber's wake-up panicked while they were held.
fn subscribers() -> MutexGuard<'static, Vec<Subscriber>> {
    SUBSCRIBERS.lock().unwrap_or_else(|e| e.into_inner())
}

fn install() -> Result<(), SignalError> {
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                for s in subscribers().iter() {
                    s.flag.store(true, Ordering::SeqCst);
                    if let Some(wake) = &s.wake {
                        wake();
                    }
                }
            })
            .map_err(Arc::new)
        })
        .clone()
        .map_err(SignalError)
}

fn add(wake: Option<Wake>) -> Result<Subscription, SignalError> {
    install()?;
    let (id, flag) = (
        NEXT_ID.fetch_add(1, Ordering::SeqCst),
        Arc::new(AtomicBool::new(false)),
    );
    subscribers().push(Subscriber {
        id,
        flag: flag.clone(),
        wake,
    });
    Ok(Subscription { id, flag })
}

/// A stop flag for the next Ctrl-C / SIGTERM (installs the handler on first use).
pub fn subscribe() -> Result<Subscription, SignalError> {
    add(None)
}

/// [`subscribe`], and `wake` is called (on the handler's thread) when the signal arrives:
/// to wake an event loop that waits for input.
pub fn subscribe_with(
    wake: impl Fn() + Send + Sync + 'static,
) -> Result<Subscription, SignalError> {
    add(Some(Box::new(wake)))
}

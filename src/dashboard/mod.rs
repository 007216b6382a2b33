//! `proleg dashboard STORE`: a live web page over any experiment store (SQLite or
//! PostgreSQL), for runs on hosts without a display — reached in a browser, through an SSH
//! tunnel for a remote host. Read-only: one thread reads the store ([`snapshot`]) and the
//! web server ([`routes`], axum on a small tokio runtime) answers every browser from that
//! snapshot, telling pages when it changed by server-sent events. Loopback by default; a
//! bind to another address requires a token, printed once at start and never logged.
//!
//! - [`snapshot`]: the store as last read, and the thread that reads it
//! - [`media`]: evaluations' videos and data files, made on demand by one thread in turn
//! - [`routes`]: the page, its assets, the JSON, the CSV and the event stream
//! - [`views`]: the JSON shapes
//! - [`error`]: why it could not serve

pub mod error;
pub mod media;
pub mod routes;
pub mod snapshot;
pub mod views;

use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};
use std::time::Duration;

pub use error::DashboardError;

use crate::control::ModuleRegistry;
use crate::optimize::store::StoreLocation;

/// How `proleg dashboard` serves.
#[derive(Clone)]
pub struct DashboardOptions {
    /// The store to show.
    pub location: StoreLocation,
    /// The address to listen on.
    pub bind: SocketAddr,
    /// Where evaluations' videos and data files are kept once made.
    pub cache: std::path::PathBuf,
    /// What renders videos (`None`: a build without renderer, which makes none).
    pub renderer: Option<Arc<dyn media::VideoRenderer>>,
}

/// Where the dashboard listens, once it does.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ready {
    /// The address it listens on (the port the system chose, for port 0).
    pub addr: SocketAddr,
    /// The token a request must present (a bind other than loopback), to print once.
    pub token: Option<String>,
    /// The store, as it may be shown (no password).
    pub store: String,
}

impl Ready {
    /// The address to open in a browser (with the token, when one is needed).
    pub fn url(&self) -> String {
        match &self.token {
            Some(t) => format!("http://{}/?token={t}", self.addr),
            None => format!("http://{}/", self.addr),
        }
    }
}

/// A token of 32 random letters and digits (the system's random source).
fn new_token() -> String {
    use rand::RngExt;
    const ALPHABET: &[u8] = b"ABCDEFGHJKLMNPQRSTUVWXYZabcdefghijkmnopqrstuvwxyz23456789";
    let mut rng = rand::rng();
    (0..32)
        .map(|_| ALPHABET[rng.random_range(0..ALPHABET.len())] as char)
        .collect()
}

/// Serves until `stop` is set: reads the store (an error there ends it at once), listens,
/// tells `on_ready` where, and answers until stopped.
pub fn serve(
    options: &DashboardOptions,
    registry: &ModuleRegistry,
    stop: &Arc<AtomicBool>,
    on_ready: impl FnOnce(&Ready),
) -> Result<(), DashboardError> {
    let (store, first) = snapshot::first_read(&options.location, registry)?;
    let store_name = first.store.clone();
    let (versions_tx, versions) = tokio::sync::watch::channel(first.version);
    let shared: snapshot::Shared = Arc::new(RwLock::new(first));
    let token = (!options.bind.ip().is_loopback()).then(new_token);
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(DashboardError::Server)?;
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(options.bind))
        .map_err(|source| DashboardError::Listen {
            addr: options.bind,
            source,
        })?;
    let addr = listener.local_addr().map_err(DashboardError::Server)?;
    let media = Arc::new(media::Media::new(
        &options.cache,
        &store_name,
        options.renderer.clone(),
    ));
    let app = routes::App {
        shared: shared.clone(),
        token: token.as_deref().map(Arc::from),
        versions,
        media: media.clone(),
    };
    on_ready(&Ready {
        addr,
        token,
        store: store_name,
    });
    std::thread::scope(|s| {
        let shared = &shared;
        // The sender lives in the reader: when it ends (stopped), the event streams end,
        // so the server's graceful shutdown does not wait for open pages.
        s.spawn(move || {
            snapshot::keep_reading(&options.location, registry, store, shared, stop, &|v| {
                versions_tx.send_replace(v);
            })
        });
        s.spawn(|| media.work(&options.location, registry, stop));
        let stopping = stop.clone();
        let served = runtime.block_on(async {
            axum::serve(listener, routes::router(app))
                .with_graceful_shutdown(async move {
                    while !stopping.load(Ordering::Relaxed) {
                        tokio::time::sleep(Duration::from_millis(200)).await;
                    }
                })
                .await
        });
        // The reader ends with the server (an error of the server stops it too).
        stop.store(true, Ordering::Relaxed);
        served.map_err(DashboardError::Server)
    })
}

//! The dashboard's routes from raw bytes: a request (`METHOD TARGET` on the first line,
//! then `Name: value` header lines, a blank line and a body) answered by the dashboard's
//! router over a small store (`fuzz/fixtures/dashboard.sqlite`: a CMA-ES run of four
//! evaluations), as served on loopback (no token) and on a network address (a token).
//! Every request gets a status and a whole body; a panic or a 500 is a finding, and so is
//! anything but 401 for a request to the guarded router that does not carry its token.

use std::path::PathBuf;
use std::sync::{Arc, OnceLock, RwLock};

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode};
use proleg::dashboard::media::Media;
use proleg::dashboard::routes::{App, router};
use proleg::dashboard::snapshot::first_read;
use proleg::optimize::store::StoreLocation;
use tower::ServiceExt;

/// The guarded router's token.
const TOKEN: &str = "fuzzTokenK7PqZ2";

/// The largest body read back (the fixture's biggest answer is a few kB).
const BODY_LIMIT: usize = 1 << 24;

/// The routers and the runtime they answer on, made once per process.
struct Served {
    runtime: tokio::runtime::Runtime,
    open: Router,
    guarded: Router,
}

fn served() -> Option<&'static Served> {
    static SERVED: OnceLock<Option<Served>> = OnceLock::new();
    SERVED
        .get_or_init(|| {
            let dir: PathBuf =
                std::env::temp_dir().join(format!("proleg-fuzz-dashboard-{}", std::process::id()));
            std::fs::create_dir_all(&dir).ok()?;
            let store = dir.join("dashboard.sqlite");
            std::fs::write(&store, include_bytes!("../../fixtures/dashboard.sqlite")).ok()?;
            let (_, snapshot) =
                first_read(&StoreLocation::sqlite(&store), crate::registry()).ok()?;
            let name = snapshot.store.clone();
            // The version's sender is dropped: event streams end after the first event.
            let (_, versions) = tokio::sync::watch::channel(snapshot.version);
            let app = App {
                shared: Arc::new(RwLock::new(snapshot)),
                token: None,
                versions,
                media: Arc::new(Media::new(&dir.join("media"), &name, None)),
            };
            let guarded = router(App {
                token: Some(Arc::from(TOKEN)),
                ..app.clone()
            });
            Some(Served {
                runtime: tokio::runtime::Builder::new_current_thread()
                    .enable_all()
                    .build()
                    .ok()?,
                open: router(app),
                guarded,
            })
        })
        .as_ref()
}

/// The request the bytes spell, when they spell one.
fn request(data: &[u8]) -> Option<Request<Body>> {
    let end = data
        .windows(2)
        .position(|w| w == b"\n\n")
        .unwrap_or(data.len());
    let head = std::str::from_utf8(&data[..end]).ok()?;
    let body = data.get(end + 2..).unwrap_or(&[]);
    let mut lines = head.lines();
    let (method, target) = lines.next()?.split_once(' ')?;
    let mut builder = Request::builder().method(method).uri(target);
    for line in lines {
        let (name, value) = line.split_once(':')?;
        builder = builder.header(name.trim(), value.trim());
    }
    builder.body(Body::from(body.to_vec())).ok()
}

/// The target: the fuzzer's bytes in, a panic on a finding.
pub fn run(data: &[u8]) {
    let Some(served) = served() else {
        return;
    };
    let carries_token = data.windows(TOKEN.len()).any(|w| w == TOKEN.as_bytes());
    for (router, guarded) in [(&served.open, false), (&served.guarded, true)] {
        let Some(req) = request(data) else {
            return;
        };
        let status = served.runtime.block_on(async {
            let Ok(response) = router.clone().oneshot(req).await;
            let status = response.status();
            let body = axum::body::to_bytes(response.into_body(), BODY_LIMIT).await;
            assert!(body.is_ok(), "{status}: the body could not be read");
            status
        });
        assert_ne!(status, StatusCode::INTERNAL_SERVER_ERROR);
        if guarded && !carries_token {
            assert_eq!(
                status,
                StatusCode::UNAUTHORIZED,
                "answered without the token"
            );
        }
    }
}

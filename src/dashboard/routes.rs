//! The dashboard's routes: the page and its assets (built into the binary), the JSON of the
//! runs and of a run's evaluations, a run's evaluations as CSV, an evaluation's media (video,
//! data file, and the 3D replay's page and pose streams on either engine), and the event
//! stream that tells the page when the store changed (server-sent events). A remote bind
//! requires the token ([`guard`]); a bad request gets its status and a one-line message.

use std::convert::Infallible;
use std::sync::Arc;
use std::time::Duration;

use axum::Router;
use axum::extract::{Path, Query, Request, State};
use axum::http::{HeaderValue, StatusCode, header};
use axum::middleware::Next;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Json, Response};
use axum::routing::get;

use crate::config::simulation::EngineKind;
use crate::dashboard::media::{Job, Kind, Media, MediaState};
use crate::playback::page;
use tokio_stream::StreamExt;
use tokio_stream::wrappers::WatchStream;

use crate::dashboard::snapshot::{Shared, Snapshot};
use crate::dashboard::views::{
    EpisodeView, EvaluationView, EvaluationsView, RunView, RunsView, data_plot,
};
use crate::optimize::store::table;
use crate::optimize::store::{RunRow, StoredEval};

/// What every request may read.
#[derive(Clone)]
pub struct App {
    /// The store as last read.
    pub shared: Shared,
    /// The token a request must present (None: a loopback bind, no token).
    pub token: Option<Arc<str>>,
    /// The snapshot's version, announced when it changes.
    pub versions: tokio::sync::watch::Receiver<u64>,
    /// Evaluations' videos and data files, made on demand.
    pub media: Arc<Media>,
}

/// The name of the cookie that carries the token once the page was opened with it.
const COOKIE: &str = "proleg_token";

/// The router.
pub fn router(app: App) -> Router {
    Router::new()
        .route("/", get(page))
        .route("/app.js", get(|| asset("text/javascript", APP_JS)))
        .route("/style.css", get(|| asset("text/css", STYLE_CSS)))
        .route(
            "/vendor/uPlot.iife.min.js",
            get(|| asset("text/javascript", UPLOT_JS)),
        )
        .route(
            "/vendor/uPlot.min.css",
            get(|| asset("text/css", UPLOT_CSS)),
        )
        .route("/replay", get(replay_page))
        .route(
            "/viewer.js",
            get(|| asset("text/javascript", page::VIEWER_JS)),
        )
        .route("/viewer.css", get(|| asset("text/css", page::VIEWER_CSS)))
        .route(
            "/replay-sources.js",
            get(|| asset("text/javascript", REPLAY_SOURCES_JS)),
        )
        .route(
            "/vendor/three.iife.min.js",
            get(|| asset("text/javascript", page::THREE_JS)),
        )
        .route("/api/runs", get(runs))
        .route("/api/runs/{id}", get(run))
        .route("/api/runs/{id}/evaluations.csv", get(run_csv))
        .route("/api/runs/{id}/map", get(run_map))
        .route(
            "/api/runs/{id}/evaluations/{n}/media",
            get(media_state).post(media_request),
        )
        .route("/api/runs/{id}/evaluations/{n}/video.webm", get(video))
        .route("/api/runs/{id}/evaluations/{n}/data.xml", get(data_file))
        .route("/api/runs/{id}/evaluations/{n}/data.json", get(data_json))
        .route(
            "/api/runs/{id}/evaluations/{n}/replay/{engine}",
            get(replay_state).post(replay_request),
        )
        .route(
            "/api/runs/{id}/evaluations/{n}/replay/{engine}/stream.json",
            get(replay_stream),
        )
        .route("/api/events", get(events))
        .fallback(|| async { (StatusCode::NOT_FOUND, "no such page") })
        .layer(axum::middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app)
}

const INDEX_HTML: &str = include_str!("../../assets/dashboard/index.html");
const APP_JS: &str = include_str!("../../assets/dashboard/app.js");
const STYLE_CSS: &str = include_str!("../../assets/dashboard/style.css");
const UPLOT_JS: &str = include_str!("../../assets/dashboard/vendor/uPlot.iife.min.js");
const UPLOT_CSS: &str = include_str!("../../assets/dashboard/vendor/uPlot.min.css");

/// The 3D replay's page (assets/viewer/dashboard.html): the viewer, fetching the pose
/// streams `?a=RUN/N/ENGINE&b=…` names.
const REPLAY_HTML: &str = include_str!("../../assets/viewer/dashboard.html");
/// What turns the replay page's query into streams asked of this server.
const REPLAY_SOURCES_JS: &str = include_str!("../../assets/viewer/dashboard-sources.js");

/// The page, with a policy that lets it load nothing but this server's own files.
async fn page() -> Response {
    own_files_only(asset("text/html; charset=utf-8", INDEX_HTML).await)
}

/// The 3D replay's page, under the same policy.
async fn replay_page() -> Response {
    own_files_only(asset("text/html; charset=utf-8", REPLAY_HTML).await)
}

/// `r` with a policy that lets its page load nothing but this server's own files.
fn own_files_only(mut r: Response) -> Response {
    r.headers_mut().insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data: blob:",
        ),
    );
    r
}

async fn asset(kind: &'static str, body: &'static str) -> Response {
    ([(header::CONTENT_TYPE, kind)], body).into_response()
}

/// The token a request presents: `?token=`, `Authorization: Bearer`, or the cookie.
fn presented(req: &Request) -> Option<String> {
    let query = req.uri().query().unwrap_or("");
    let from_query = query
        .split('&')
        .find_map(|kv| kv.strip_prefix("token="))
        .map(str::to_string);
    let header_text = |name| req.headers().get(name).and_then(|v| v.to_str().ok());
    let from_bearer = header_text(header::AUTHORIZATION)
        .and_then(|v| v.strip_prefix("Bearer "))
        .map(str::to_string);
    let from_cookie = header_text(header::COOKIE).and_then(|c| {
        c.split(';').find_map(|kv| {
            kv.trim()
                .strip_prefix(&format!("{COOKIE}="))
                .map(str::to_string)
        })
    });
    from_query.or(from_bearer).or(from_cookie)
}

/// Lets a request through when no token is needed or it presents the token (a page opened
/// with `?token=` gets it as a cookie, so its own requests need not repeat it); else 401.
async fn guard(State(app): State<App>, req: Request, next: Next) -> Response {
    let Some(token) = app.token.clone() else {
        return next.run(req).await;
    };
    let given = presented(&req);
    if given
        .as_deref()
        .is_some_and(|g| constant_time_eq(g, &token))
    {
        let mut r = next.run(req).await;
        if let Ok(v) = HeaderValue::from_str(&format!(
            "{COOKIE}={token}; HttpOnly; SameSite=Strict; Path=/"
        )) {
            r.headers_mut().insert(header::SET_COOKIE, v);
        }
        return r;
    }
    (
        StatusCode::UNAUTHORIZED,
        "this dashboard needs its token: open the address `proleg dashboard` printed at start",
    )
        .into_response()
}

/// Equality that takes as long whatever the first difference.
fn constant_time_eq(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

async fn runs(State(app): State<App>) -> Result<Response, ApiError> {
    let s = app.shared.read().map_err(|_| ApiError::Unavailable)?;
    Ok(Json(RunsView {
        store: s.store.clone(),
        version: s.version,
        reconnecting: s.reconnecting.clone(),
        runs: s.runs.iter().rev().map(|r| RunView::of(&s, r)).collect(),
    })
    .into_response())
}

/// A request the dashboard cannot answer: its status and a one-line message.
#[derive(Debug, thiserror::Error)]
pub enum ApiError {
    /// The snapshot's lock was poisoned (a reader panicked).
    #[error("the store's snapshot is not readable")]
    Unavailable,
    /// A run id that is not a number.
    #[error("run id {0:?} is not a number")]
    BadId(String),
    /// `from` that is not a number.
    #[error("from must be a number of evaluations")]
    BadFrom,
    /// A run the store does not hold.
    #[error("the store holds no run {0}")]
    NoRun(i64),
    /// A run without a MAP-Elites archive (or one that cannot be rebuilt here).
    #[error("{0}")]
    NoMap(#[from] crate::dashboard::snapshot::NoArchive),
    /// An evaluation number that is not a number.
    #[error("evaluation {0:?} is not a number")]
    BadNumber(String),
    /// An evaluation the run has not finished (or does not have).
    #[error("run {run} has no finished evaluation {number}")]
    NoEvaluation {
        /// The run.
        run: i64,
        /// The evaluation.
        number: u64,
    },
    /// A medium that is not made (yet).
    #[error("evaluation {number} of run {run} has no {what} yet: ask for it first")]
    NotMade {
        /// The run.
        run: i64,
        /// The evaluation.
        number: u64,
        /// Video or data file.
        what: &'static str,
    },
    /// An engine name that is no engine's.
    #[error("{0}")]
    BadEngine(#[from] crate::config::simulation::UnknownEngine),
    /// A request to make media without the page's header (another site's form).
    #[error("ask for media from the dashboard's page (the X-Proleg header is missing)")]
    NotFromPage,
    /// A made file that cannot be read.
    #[error("{}: {source}", path.display())]
    Unreadable {
        /// The file.
        path: std::path::PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// A made data file that does not parse.
    #[error("{0}")]
    DataFile(#[from] crate::data::read::DataError),
    /// The task reading a file ended without an answer.
    #[error("reading the file stopped: {0}")]
    Task(#[from] tokio::task::JoinError),
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = match self {
            ApiError::Unavailable => StatusCode::SERVICE_UNAVAILABLE,
            ApiError::BadId(_)
            | ApiError::BadFrom
            | ApiError::BadNumber(_)
            | ApiError::BadEngine(_)
            | ApiError::NotFromPage => StatusCode::BAD_REQUEST,
            ApiError::NoRun(_)
            | ApiError::NoMap(_)
            | ApiError::NoEvaluation { .. }
            | ApiError::NotMade { .. } => StatusCode::NOT_FOUND,
            ApiError::Unreadable { .. } | ApiError::DataFile(_) | ApiError::Task(_) => {
                StatusCode::INTERNAL_SERVER_ERROR
            }
        };
        (status, self.to_string()).into_response()
    }
}

/// Run `id` of the snapshot and its evaluations read so far.
fn run_in(s: &Snapshot, id: i64) -> Result<(&RunRow, &[StoredEval]), ApiError> {
    let row = s
        .runs
        .iter()
        .find(|r| r.id == id)
        .ok_or(ApiError::NoRun(id))?;
    Ok((row, s.evaluations.get(&id).map_or(&[][..], Vec::as_slice)))
}

fn run_id(text: &str) -> Result<i64, ApiError> {
    text.parse().map_err(|_| ApiError::BadId(text.to_string()))
}

/// `?from=N`.
#[derive(serde::Deserialize)]
struct From {
    from: Option<u64>,
}

async fn run(
    State(app): State<App>,
    Path(id): Path<String>,
    query: Result<Query<From>, axum::extract::rejection::QueryRejection>,
) -> Result<Response, ApiError> {
    let id = run_id(&id)?;
    let Query(From { from }) = query.map_err(|_| ApiError::BadFrom)?;
    let s = app.shared.read().map_err(|_| ApiError::Unavailable)?;
    let (row, all) = run_in(&s, id)?;
    let first = (from.unwrap_or(0) as usize).min(all.len());
    let details = s.details.get(&id);
    Ok(Json(EvaluationsView {
        run: RunView::of(&s, row),
        read: all.len() as u64,
        episodes: details.map_or_else(Vec::new, |d| {
            d.episodes.iter().map(EpisodeView::of).collect()
        }),
        unloadable: details.and_then(|d| d.unloadable.clone()),
        evaluations: table::run_rows(&s.store, id, all.to_vec())[first..]
            .iter()
            .map(EvaluationView::of)
            .collect(),
    })
    .into_response())
}

async fn run_csv(State(app): State<App>, Path(id): Path<String>) -> Result<Response, ApiError> {
    let id = run_id(&id)?;
    let s = app.shared.read().map_err(|_| ApiError::Unavailable)?;
    let (row, all) = run_in(&s, id)?;
    let disposition = format!("attachment; filename=\"run{id}_evaluations.csv\"");
    Ok((
        [
            (header::CONTENT_TYPE, "text/csv; charset=utf-8".to_string()),
            (header::CONTENT_DISPOSITION, disposition),
        ],
        table::csv(&table::run_rows(&s.store, row.id, all.to_vec())),
    )
        .into_response())
}

async fn run_map(State(app): State<App>, Path(id): Path<String>) -> Result<Response, ApiError> {
    let id = run_id(&id)?;
    let s = app.shared.read().map_err(|_| ApiError::Unavailable)?;
    if !s.runs.iter().any(|r| r.id == id) {
        return Err(ApiError::NoRun(id));
    }
    match s.maps.get(&id) {
        Some(Ok(map)) => Ok(Json(map).into_response()),
        Some(Err(why)) => Err(ApiError::NoMap(why.clone())),
        None => Err(ApiError::NoMap(
            crate::dashboard::snapshot::NoArchive::NotKept(id),
        )),
    }
}

/// The event stream: the snapshot's version now and at every change (the page then reads
/// what it shows again), with a keep-alive comment every 15 s.
async fn events(
    State(app): State<App>,
) -> Sse<impl tokio_stream::Stream<Item = Result<Event, Infallible>>> {
    let stream = WatchStream::new(app.versions.clone())
        .map(|v| Ok(Event::default().event("changed").data(v.to_string())));
    Sse::new(stream).keep_alive(KeepAlive::new().interval(Duration::from_secs(15)))
}

/// Evaluation `n` of run `id` as a medium `kind`'s job, when the snapshot holds it done.
fn job_of(app: &App, (id, n): (String, String), kind: Kind) -> Result<Job, ApiError> {
    let run = run_id(&id)?;
    let number: u64 = n.parse().map_err(|_| ApiError::BadNumber(n.clone()))?;
    let s = app.shared.read().map_err(|_| ApiError::Unavailable)?;
    let (row, all) = run_in(&s, run)?;
    if number >= all.len() as u64 {
        return Err(ApiError::NoEvaluation { run, number });
    }
    Ok(Job {
        run,
        started: row.started.clone(),
        number,
        kind,
    })
}

/// An evaluation's video and data file: where each is.
#[derive(serde::Serialize)]
struct MediaView {
    video: MediaState,
    data: MediaState,
}

fn media_view(app: &App, at: (String, String)) -> Result<MediaView, ApiError> {
    Ok(MediaView {
        video: app.media.state(&job_of(app, at.clone(), Kind::Video)?),
        data: app.media.state(&job_of(app, at, Kind::Data)?),
    })
}

async fn media_state(
    State(app): State<App>,
    Path(at): Path<(String, String)>,
) -> Result<Response, ApiError> {
    Ok(Json(media_view(&app, at)?).into_response())
}

/// Asks for an evaluation's data file and video (a request from the page: it carries the
/// `X-Proleg` header, which another site's form cannot send).
async fn media_request(
    State(app): State<App>,
    Path(at): Path<(String, String)>,
    headers: axum::http::HeaderMap,
) -> Result<Response, ApiError> {
    if !headers.contains_key("x-proleg") {
        return Err(ApiError::NotFromPage);
    }
    app.media.request(job_of(&app, at.clone(), Kind::Data)?);
    app.media.request(job_of(&app, at.clone(), Kind::Video)?);
    Ok(Json(media_view(&app, at)?).into_response())
}

/// A made medium's file (404 until it is made).
fn made(app: &App, at: (String, String), kind: Kind) -> Result<std::path::PathBuf, ApiError> {
    let job = job_of(app, at, kind)?;
    if app.media.state(&job) != MediaState::Ready {
        return Err(ApiError::NotMade {
            run: job.run,
            number: job.number,
            what: kind.what(),
        });
    }
    Ok(app.media.file(&job))
}

/// A made medium's bytes.
async fn bytes(app: &App, at: (String, String), kind: Kind) -> Result<Vec<u8>, ApiError> {
    let path = made(app, at, kind)?;
    tokio::task::spawn_blocking(move || {
        std::fs::read(&path).map_err(|source| ApiError::Unreadable { path, source })
    })
    .await?
}

async fn video(
    State(app): State<App>,
    Path(at): Path<(String, String)>,
) -> Result<Response, ApiError> {
    let bytes = bytes(&app, at, Kind::Video).await?;
    Ok(([(header::CONTENT_TYPE, "video/webm")], bytes).into_response())
}

async fn data_file(
    State(app): State<App>,
    Path(at): Path<(String, String)>,
) -> Result<Response, ApiError> {
    let name = format!("run{}_eval{}.data.xml", at.0, at.1);
    let bytes = bytes(&app, at, Kind::Data).await?;
    Ok((
        [
            (header::CONTENT_TYPE, "application/xml".to_string()),
            (
                header::CONTENT_DISPOSITION,
                format!("attachment; filename=\"{name}\""),
            ),
        ],
        bytes,
    )
        .into_response())
}

async fn data_json(
    State(app): State<App>,
    Path(at): Path<(String, String)>,
) -> Result<Response, ApiError> {
    let file = made(&app, at, Kind::Data)?;
    let plot = tokio::task::spawn_blocking(move || data_plot(&file)).await??;
    Ok(Json(plot).into_response())
}

/// Evaluation `n` of run `id` replayed on `engine`: its 3D replay's job.
fn replay_job(app: &App, (id, n, engine): (String, String, String)) -> Result<Job, ApiError> {
    let engine: EngineKind = engine.parse()?;
    job_of(app, (id, n), Kind::Replay(engine))
}

/// Where an evaluation's 3D replay on an engine is.
async fn replay_state(
    State(app): State<App>,
    Path(at): Path<(String, String, String)>,
) -> Result<Response, ApiError> {
    Ok(Json(app.media.state(&replay_job(&app, at)?)).into_response())
}

/// Asks for an evaluation's 3D replay on an engine (from the page: `X-Proleg`).
async fn replay_request(
    State(app): State<App>,
    Path(at): Path<(String, String, String)>,
    headers: axum::http::HeaderMap,
) -> Result<Response, ApiError> {
    if !headers.contains_key("x-proleg") {
        return Err(ApiError::NotFromPage);
    }
    Ok(Json(app.media.request(replay_job(&app, at)?)).into_response())
}

/// A made 3D replay's pose stream.
async fn replay_stream(
    State(app): State<App>,
    Path(at): Path<(String, String, String)>,
) -> Result<Response, ApiError> {
    let job = replay_job(&app, at)?;
    let bytes = bytes(
        &app,
        (job.run.to_string(), job.number.to_string()),
        job.kind,
    )
    .await?;
    Ok(([(header::CONTENT_TYPE, "application/json")], bytes).into_response())
}

//! `hdgear serve`: a local web server with one page (the live explorer) and a small JSON API.
//!
//! - `GET /` (and `/app.js`, `/app.css`): the page, embedded in the binary (`include_str!`).
//! - `GET /api/view?alpha=…&gamma=…&eps=…&mu=…&delta=…&omega=…` (any subset; the rest from the
//!   study's default point): [`hdgear::explore::View`] as JSON.
//! - `GET /api/boundaries?…`: the bursting boundaries located by simulation (seconds).
//! - `GET /api/drives` and `GET /api/drive?name=CSF-20-50`: the catalogue drives and one drive's
//!   reduction to the dimensionless parameters.
//!
//! Bad parameters get a 400 with the CLI's one-line message; a parameter set whose run would
//! exceed the explorer's step budget ([`hdgear::explore::STEP_BUDGET`], checked before any work)
//! a 422 with the reason; every computation runs on the blocking pool (never on the async
//! runtime, so requests do not block each other), at most two per core at once. A request not
//! answered [`VIEW_TIMEOUT`] after it came (boundaries: [`BOUNDARY_TIMEOUT`]) gets a 503 with
//! `Retry-After`, and its computation stops at that deadline (see [`compute`]).

use crate::cli::ServeArgs;
use anyhow::{Context, Result};
use axum::Json;
use axum::extract::{Query, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use hdgear::params::{Param, Params, Warning};
use std::collections::BTreeMap;
use std::io::Write;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::Semaphore;

/// Longest a view may take before the request is answered with a 503.
pub const VIEW_TIMEOUT: Duration = Duration::from_secs(5);
/// Longest a boundary search may take.
pub const BOUNDARY_TIMEOUT: Duration = Duration::from_secs(30);

const PAGE: &str = include_str!("assets/index.html");
const APP_JS: &str = include_str!("assets/app.js");
const APP_CSS: &str = include_str!("assets/app.css");

/// An API error: status and one line.
struct ApiError(StatusCode, String);

/// The body of an error answer: `{"error": "…"}`.
#[derive(serde::Serialize)]
struct ErrorBody<'a> {
    error: &'a str,
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let mut r = (self.0, Json(ErrorBody { error: &self.1 })).into_response();
        if self.0 == StatusCode::SERVICE_UNAVAILABLE {
            // busy or too slow now: a client may try again in a moment
            r.headers_mut()
                .insert(header::RETRY_AFTER, header::HeaderValue::from_static("1"));
        }
        r
    }
}

/// The answer of `/api/drives`: the catalogue's drive names and the assumptions every preset
/// makes (fields in the order the API has always sent them).
#[derive(serde::Serialize)]
struct DrivesBody {
    assumptions: Vec<&'static str>,
    drives: Vec<&'static str>,
}

/// The answer of `/api/drive`: a catalogue drive, its stiffness fit and its reduction (fields in
/// the order the API has always sent them).
#[derive(serde::Serialize)]
struct DriveBody<'a> {
    alpha_eps: f64,
    drive: hdgear::physical::PhysicalParams,
    fit: hdgear::physical::catalogue::Fit,
    name: &'a str,
    reduction: hdgear::physical::Reduction,
}

impl From<hdgear::Error> for ApiError {
    fn from(e: hdgear::Error) -> Self {
        match e {
            hdgear::Error::RunTooLong {
                estimated_steps, ..
            } => ApiError(
                StatusCode::UNPROCESSABLE_ENTITY,
                format!(
                    "refused: this parameter set needs about {estimated_steps:.1e} integration \
                     steps, beyond the explorer's budget of {:.0e} (about a second); a larger ω \
                     shortens the run, or use `hdgear analyze` for it",
                    hdgear::explore::STEP_BUDGET as f64
                ),
            ),
            hdgear::Error::Solver(s) => ApiError(
                StatusCode::UNPROCESSABLE_ENTITY,
                format!("the integration failed: {s}"),
            ),
            other => ApiError(StatusCode::BAD_REQUEST, other.to_string()),
        }
    }
}

/// Query → checked parameters (the CLI's validation and messages).
fn params(q: &BTreeMap<String, String>) -> Result<(Params, Vec<Warning>), ApiError> {
    let bad = |m: String| ApiError(StatusCode::BAD_REQUEST, m);
    let mut p = Params::preset("paper")?;
    for (k, v) in q {
        let param: Param = k.parse().map_err(|e: hdgear::Error| bad(e.to_string()))?;
        let value: f64 = v
            .trim()
            .parse()
            .map_err(|_| bad(format!("invalid value '{v}' for {k}: not a number")))?;
        p = p.with(param, value);
    }
    let warnings = p.validate()?;
    Ok((p, warnings))
}

/// Runs `f` on the blocking pool under the concurrency limit; the request is answered with a 503
/// once `limit` has passed since it came (waiting for a permit included). `f` gets that
/// deadline for its integrations ([`hdgear::integrate::Options::deadline`]): abandoned work
/// stops there, and it holds its permit until it has stopped, so at most the limit's number of
/// computations ever run.
async fn compute<T: Send + 'static>(
    permits: &Permits,
    limit: Duration,
    f: impl FnOnce(std::time::Instant) -> hdgear::Result<T> + Send + 'static,
) -> Result<T, ApiError> {
    let deadline = std::time::Instant::now() + limit;
    let work = async {
        let permit = permits
            .clone()
            .acquire_owned()
            .await
            .map_err(|_| ApiError(StatusCode::SERVICE_UNAVAILABLE, "shutting down".into()))?;
        tokio::task::spawn_blocking(move || {
            let _permit = permit;
            f(deadline)
        })
        .await
        .map_err(|e| {
            ApiError(
                StatusCode::INTERNAL_SERVER_ERROR,
                format!("the computation failed: {e}"),
            )
        })
    };
    match tokio::time::timeout(limit, work).await {
        Ok(r) => Ok(r??),
        Err(_) => Err(ApiError(
            StatusCode::SERVICE_UNAVAILABLE,
            format!(
                "refused: the computation took longer than {} s (waiting for a free worker \
                 included)",
                limit.as_secs()
            ),
        )),
    }
}

/// The explorer's detection options with the integrations' deadline.
fn options_until(deadline: std::time::Instant) -> hdgear::burst::BurstOptions {
    let mut o = hdgear::explore::View::options();
    o.tol.deadline = Some(deadline);
    o
}

type Permits = Arc<Semaphore>;
type Q = Query<BTreeMap<String, String>>;

async fn view(State(permits): State<Permits>, Query(q): Q) -> Result<Response, ApiError> {
    let (p, warnings) = params(&q)?;
    let v = compute(&permits, VIEW_TIMEOUT, move |deadline| {
        hdgear::explore::View::compute(&p, warnings, &options_until(deadline))
    })
    .await?;
    Ok(Json(v).into_response())
}

async fn boundaries(State(permits): State<Permits>, Query(q): Q) -> Result<Response, ApiError> {
    let (p, _) = params(&q)?;
    let b = compute(&permits, BOUNDARY_TIMEOUT, move |deadline| {
        hdgear::burst::boundaries(&p, &options_until(deadline))
    })
    .await?;
    Ok(Json(b).into_response())
}

async fn drives() -> Response {
    let names: Vec<&str> = hdgear::physical::card::builtin()
        .card
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    Json(DrivesBody {
        drives: names,
        assumptions: hdgear::physical::catalogue::assumption_texts(),
    })
    .into_response()
}

async fn drive(Query(q): Q) -> Result<Response, ApiError> {
    let name = q.get("name").map_or("CSF-20-50", String::as_str);
    let (d, fit) = hdgear::physical::catalogue::preset(name, None)?;
    let reduction = d.reduce()?;
    let alpha_eps = reduction.params.alpha * reduction.params.eps;
    Ok(Json(DriveBody {
        name,
        drive: d,
        fit,
        reduction,
        alpha_eps,
    })
    .into_response())
}

fn asset(kind: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, kind),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

/// The application: routes and their shared state.
pub fn router() -> axum::Router {
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    let permits: Permits = Arc::new(Semaphore::new(2 * cores));
    axum::Router::new()
        .route(
            "/",
            get(|| async { asset("text/html; charset=utf-8", PAGE) }),
        )
        .route(
            "/app.js",
            get(|| async { asset("text/javascript; charset=utf-8", APP_JS) }),
        )
        .route(
            "/app.css",
            get(|| async { asset("text/css; charset=utf-8", APP_CSS) }),
        )
        .route("/api/view", get(view))
        .route("/api/boundaries", get(boundaries))
        .route("/api/drives", get(drives))
        .route("/api/drive", get(drive))
        .fallback(|| async { ApiError(StatusCode::NOT_FOUND, "no such page".into()) })
        .with_state(permits)
}

/// Runs the serve command until Ctrl-C.
pub fn run(a: ServeArgs) -> Result<()> {
    let ip: std::net::IpAddr = a.bind.parse().map_err(|_| {
        anyhow::anyhow!(
            "invalid --bind '{}': expected an IP address such as 127.0.0.1",
            a.bind
        )
    })?;
    let addr = std::net::SocketAddr::new(ip, a.port);
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the server's runtime")?;
    rt.block_on(async move {
        let listener = tokio::net::TcpListener::bind(addr)
            .await
            .with_context(|| format!("cannot listen on {addr}"))?;
        let local = listener.local_addr()?;
        let url = format!("http://{local}/");
        crate::sink::outln!("hdgear serve: {url}  (Ctrl-C stops it)");
        std::io::stdout().flush()?;
        if !ip.is_loopback() {
            crate::sink::note(&format!(
                "listening on {ip}: anyone who can reach this machine can use the explorer"
            ));
        }
        if a.open {
            open(&url);
        }
        axum::serve(listener, router())
            .await
            .context("the server stopped")
    })
}

/// Opens `url` in the desktop's browser, if there is one (a note otherwise).
fn open(url: &str) {
    let tried = std::env::var("BROWSER")
        .ok()
        .into_iter()
        .chain(["xdg-open".to_string(), "open".to_string()]);
    for cmd in tried {
        let spawned = std::process::Command::new(&cmd)
            .arg(url)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn();
        if spawned.is_ok() {
            return;
        }
    }
    crate::sink::note(&format!("--open: no browser found; open {url} yourself"));
}

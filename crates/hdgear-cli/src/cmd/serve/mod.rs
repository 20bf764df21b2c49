//! `hdgear serve`: a local web server with one page (the live explorer) and a small JSON API.
//!
//! - `GET /` (and `/app.js`, `/app.css`): the page, embedded in the binary (`include_str!`); the
//!   script starts with its sliders' table, from the library's parameter list.
//! - `GET /api/view?alpha=…&gamma=…&eps=…&mu=…&delta=…&omega=…` (any subset; the rest from the
//!   study's default point): [`hdgear::explore::View`] as JSON.
//! - `GET /api/boundaries?…`: the bursting boundaries located by simulation (seconds).
//! - `GET /api/control?law=vdamping&gain=…&…`: one control law ([`hdgear::control::LAWS`]) on the
//!   parameters, assessed at `gain` or, without it, tuned to its least gain
//!   ([`hdgear::control::Comparison`]); `ww`, `wd`, `taud` as `hdgear control` takes them.
//! - `GET /api/laws`: the control laws, and those `hdgear control` runs by default.
//! - `GET /api/drives` and `GET /api/drive?name=CSF-20-50`: the catalogue drives and one drive's
//!   reduction to the dimensionless parameters.
//!
//! Bad parameters get a 400 with the CLI's one-line message; a parameter set whose run would
//! exceed the explorer's step budget ([`hdgear::explore::STEP_BUDGET`], checked before any work)
//! a 422 with the reason; every computation runs on the blocking pool (never on the async
//! runtime, so requests do not block each other), at most two per core at once. A request not
//! answered [`VIEW_TIMEOUT`] after it came (boundaries: [`BOUNDARY_TIMEOUT`]) gets a 503 with
//! `Retry-After`, and its computation stops at that deadline (see [`compute`]). At most
//! [`QUEUE_PER_WORKER`] requests per worker wait for one; beyond that a request is answered
//! with a 503 at once.
//!
//! Connections: at most [`MAX_CONNECTIONS`] are open at once (the next waits in the kernel's
//! backlog until one closes), and a client that has not sent a request's headers within
//! [`HEADER_TIMEOUT`] (after connecting, or after its last answer on a kept-alive connection)
//! is disconnected, so half-sent requests cannot hold connections or memory.

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

use clap::Args;

/// Arguments of `hdgear serve`.
#[derive(Args, Debug)]
pub struct ServeArgs {
    /// Port (0: any free port; the URL is printed).
    #[arg(long, default_value_t = 8080)]
    pub port: u16,
    /// Address to listen on. The default, 127.0.0.1, serves this machine only; 0.0.0.0 exposes
    /// the explorer (and its CPU) to everyone who can reach this machine.
    #[arg(long, default_value = "127.0.0.1", value_name = "ADDR")]
    pub bind: String,
    /// Open the page in the desktop's browser.
    #[arg(long)]
    pub open: bool,
}

/// Longest a view may take before the request is answered with a 503.
pub const VIEW_TIMEOUT: Duration = Duration::from_secs(5);
/// Longest a boundary search may take.
pub const BOUNDARY_TIMEOUT: Duration = Duration::from_secs(30);

/// Requests that may wait for a worker, per worker. A view is refused before any work when it
/// would need more than the step budget, about a second of one core; so a request behind this
/// many per worker could not be answered within [`VIEW_TIMEOUT`] anyway, and waiting
/// longer only delays its 503.
pub const QUEUE_PER_WORKER: usize = 5;

/// Longest a client may take to send a request's headers, and longest a kept-alive connection
/// may sit idle between requests. A browser sends a GET's headers in one packet, in well under
/// a second even on a slow link; a client that takes longer is not a browser, and the explorer's
/// page reconnects on its own when an idle connection was closed.
pub const HEADER_TIMEOUT: Duration = Duration::from_secs(10);

/// Most connections open at once: half the usual soft limit of 1,024 file descriptors a
/// process may hold, so that open connections never starve the server of descriptors for its
/// own files and listener; a browser holds at most six connections to one server.
pub const MAX_CONNECTIONS: usize = 512;

const PAGE: &str = include_str!("assets/index.html");
const APP_JS: &str = include_str!("assets/app.js");
const APP_CSS: &str = include_str!("assets/app.css");
/// Where app.js holds its sliders' table (an empty list until the server writes it).
const SLIDERS: &str = "/*PARAMS*/[]";

/// The range a parameter's slider spans at first, and whether on a log scale: all the explorer
/// adds to the library's parameter list (a value typed beyond it widens it).
fn slider(q: Param) -> (f64, f64, bool) {
    match q {
        Param::Alpha => (0.5, 100.0, true),
        Param::Gamma => (1e-3, 100.0, true),
        Param::Eps => (0.0, 2.0, false),
        Param::Mu => (-0.5, 0.5, false),
        Param::Delta => (0.0, 40.0, false),
        Param::Omega => (1e-4, 0.3, true),
    }
}

/// One slider of the page: the library's name, symbol, meaning and default of a parameter with
/// its [`slider`] range.
#[derive(serde::Serialize)]
struct Slider {
    key: &'static str,
    sym: &'static str,
    hint: &'static str,
    def: f64,
    min: f64,
    max: f64,
    log: bool,
}

/// `/app.js`: the page's script with its sliders' table `PARAMS` written in, read from the
/// library's parameter list (the study's model's definitions, in [`Param::ALL`]'s order).
static APP: std::sync::LazyLock<String> = std::sync::LazyLock::new(|| {
    let sliders: Vec<Slider> = Param::ALL
        .iter()
        .map(|&q| {
            let info = hdgear::model::study_param(q);
            let (min, max, log) = slider(q);
            Slider {
                key: info.name,
                sym: info.symbol,
                hint: info.meaning,
                def: info.default,
                min,
                max,
                log,
            }
        })
        .collect();
    let table = serde_json::to_string(&sliders).expect("plain data serialises");
    assert!(
        APP_JS.matches(SLIDERS).count() == 1,
        "app.js holds one {SLIDERS}"
    );
    APP_JS.replacen(SLIDERS, &table, 1)
});

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
            e @ hdgear::Error::RateTooHigh { .. } => {
                ApiError(StatusCode::UNPROCESSABLE_ENTITY, format!("refused: {e}"))
            }
            other => ApiError(StatusCode::BAD_REQUEST, other.to_string()),
        }
    }
}

/// A query value as a number, or a 400 naming it.
fn number(k: &str, v: &str) -> Result<f64, ApiError> {
    v.trim().parse().map_err(|_| {
        ApiError(
            StatusCode::BAD_REQUEST,
            format!("invalid value '{v}' for {k}: not a number"),
        )
    })
}

/// Query → checked parameters (the CLI's validation and messages).
fn params(q: &BTreeMap<String, String>) -> Result<(Params, Vec<Warning>), ApiError> {
    let mut p = Params::preset("paper")?;
    for (k, v) in q {
        let param: Param = k
            .parse()
            .map_err(|e: hdgear::Error| ApiError(StatusCode::BAD_REQUEST, e.to_string()))?;
        p = p.with(param, number(k, v)?);
    }
    let warnings = p.validate()?;
    Ok((p, warnings))
}

/// The computations' limits: workers running at once, and requests admitted (running or
/// waiting for a worker).
#[derive(Clone)]
struct Workers {
    running: Arc<Semaphore>,
    admitted: Arc<Semaphore>,
    count: usize,
}

impl Workers {
    /// Two per core: a computation that waits on nothing keeps a core busy, and the second lets
    /// a cheap view run beside a long boundary search.
    fn new() -> Workers {
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
        let count = 2 * cores;
        Workers {
            running: Arc::new(Semaphore::new(count)),
            admitted: Arc::new(Semaphore::new(count * (1 + QUEUE_PER_WORKER))),
            count,
        }
    }
}

/// Runs `f` on the blocking pool under the concurrency limit; the request is answered with a 503
/// at once when [`QUEUE_PER_WORKER`] requests per worker are already waiting, and once `limit`
/// has passed since it came (waiting for a worker included). `f` gets that deadline for its
/// integrations ([`hdgear::integrate::Options::deadline`]): abandoned work stops there, and it
/// holds its permits until it has stopped, so at most the limit's number of computations ever
/// run and the queue's bound counts them.
async fn compute<T: Send + 'static>(
    workers: &Workers,
    limit: Duration,
    f: impl FnOnce(std::time::Instant) -> hdgear::Result<T> + Send + 'static,
) -> Result<T, ApiError> {
    let deadline = std::time::Instant::now() + limit;
    let admitted = workers.admitted.clone().try_acquire_owned().map_err(|_| {
        ApiError(
            StatusCode::SERVICE_UNAVAILABLE,
            format!(
                "busy: all {} workers and {} waiting places are taken; try again in a moment",
                workers.count,
                workers.count * QUEUE_PER_WORKER
            ),
        )
    })?;
    let work =
        async {
            let permit =
                workers.running.clone().acquire_owned().await.map_err(|_| {
                    ApiError(StatusCode::SERVICE_UNAVAILABLE, "shutting down".into())
                })?;
            tokio::task::spawn_blocking(move || {
                let _permits = (permit, admitted);
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
    let too_long = || {
        ApiError(
            StatusCode::SERVICE_UNAVAILABLE,
            format!(
                "refused: the computation took longer than {} s (waiting for a free worker \
                 included)",
                limit.as_secs()
            ),
        )
    };
    match tokio::time::timeout(limit, work).await {
        // the integrations' own deadline is the same limit, seen from inside: whichever notices
        // first, the answer is the timeout's
        Ok(Ok(Err(hdgear::Error::Solver(hdgear::error::SolverError::Deadline { .. }))))
        | Err(_) => Err(too_long()),
        Ok(r) => Ok(r??),
    }
}

/// The explorer's detection options with the integrations' deadline.
fn options_until(deadline: std::time::Instant) -> hdgear::burst::BurstOptions {
    let mut o = hdgear::explore::View::options();
    o.tol.deadline = Some(deadline);
    o
}

type Q = Query<BTreeMap<String, String>>;

async fn view(State(workers): State<Workers>, Query(q): Q) -> Result<Response, ApiError> {
    let (p, warnings) = params(&q)?;
    let v = compute(&workers, VIEW_TIMEOUT, move |deadline| {
        hdgear::explore::View::compute(&p, warnings, &options_until(deadline))
    })
    .await?;
    Ok(Json(v).into_response())
}

async fn boundaries(State(workers): State<Workers>, Query(q): Q) -> Result<Response, ApiError> {
    let (p, _) = params(&q)?;
    let b = compute(&workers, BOUNDARY_TIMEOUT, move |deadline| {
        hdgear::burst::boundaries(&p, &options_until(deadline))
    })
    .await?;
    Ok(Json(b).into_response())
}

/// The keys of `/api/control` beside the parameters: the law, and the options of
/// [`hdgear::control::ControlOptions`] the explorer sets.
const CONTROL_KEYS: [&str; 5] = ["law", "gain", "ww", "wd", "taud"];

async fn control(State(workers): State<Workers>, Query(mut q): Q) -> Result<Response, ApiError> {
    let mut take = |k: &str| q.remove(k);
    let [law, gain, ww, wd, taud] = CONTROL_KEYS.map(&mut take);
    let law = law.ok_or_else(|| {
        ApiError(
            StatusCode::BAD_REQUEST,
            format!("law is needed: one of {}", hdgear::control::LAWS.join(", ")),
        )
    })?;
    let value = |k: &str, v: Option<String>| v.map(|v| number(k, &v)).transpose();
    let c = hdgear::control::ControlOptions {
        gain: value("gain", gain)?,
        ww: value("ww", ww)?,
        wd: value("wd", wd)?,
        taud: value("taud", taud)?,
        ..hdgear::control::ControlOptions::default()
    };
    let (p, _) = params(&q)?;
    let doc = compute(&workers, BOUNDARY_TIMEOUT, move |deadline| {
        hdgear::control::compare(&p, &[law.as_str()], &c, &options_until(deadline))
    })
    .await?;
    Ok(Json(doc).into_response())
}

/// The answer of `/api/laws`.
#[derive(serde::Serialize)]
struct LawsBody {
    laws: [&'static str; hdgear::control::LAWS.len()],
    default: [&'static str; hdgear::control::DEFAULT_LAWS.len()],
}

async fn laws() -> Response {
    Json(LawsBody {
        laws: hdgear::control::LAWS,
        default: hdgear::control::DEFAULT_LAWS,
    })
    .into_response()
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
    axum::Router::new()
        .route(
            "/",
            get(|| async { asset("text/html; charset=utf-8", PAGE) }),
        )
        .route(
            "/app.js",
            get(|| async { asset("text/javascript; charset=utf-8", APP.as_str()) }),
        )
        .route(
            "/app.css",
            get(|| async { asset("text/css; charset=utf-8", APP_CSS) }),
        )
        .route("/api/view", get(view))
        .route("/api/boundaries", get(boundaries))
        .route("/api/control", get(control))
        .route("/api/laws", get(laws))
        .route("/api/drives", get(drives))
        .route("/api/drive", get(drive))
        .fallback(|| async { ApiError(StatusCode::NOT_FOUND, "no such page".into()) })
        .with_state(Workers::new())
}

/// Serves `app` on `listener`: one task per connection, at most [`MAX_CONNECTIONS`] at once,
/// each closed when a request's headers take longer than [`HEADER_TIMEOUT`].
async fn serve(listener: tokio::net::TcpListener, app: axum::Router) {
    let slots = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    loop {
        let Ok(slot) = slots.clone().acquire_owned().await else {
            return; // never closed
        };
        let stream = match listener.accept().await {
            Ok((stream, _)) => stream,
            // out of descriptors, or a connection reset before it was accepted: the listener
            // itself is fine, so wait a moment and go on
            Err(_) => {
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
        };
        let service = hyper_util::service::TowerToHyperService::new(app.clone());
        tokio::spawn(async move {
            let _slot = slot;
            // a connection's errors (a client gone, a timeout, a malformed request) end that
            // connection only
            let _ = hyper::server::conn::http1::Builder::new()
                .timer(hyper_util::rt::TokioTimer::new())
                .header_read_timeout(HEADER_TIMEOUT)
                .serve_connection(hyper_util::rt::TokioIo::new(stream), service)
                .await;
        });
    }
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
        serve(listener, router()).await;
        Ok(())
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

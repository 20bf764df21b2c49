//! `hdgear serve`: a local web server with one page (the live explorer) and a small JSON API.
//!
//! - `GET /` (and `/app.js`, `/app.css`): the page, embedded in the binary (`include_str!`); the
//!   script starts with its sliders' table, from the served model's parameter list: the study's
//!   six, and with `--config FILE` every parameter of the scenario's terms.
//! - `GET /api/view?alpha=…&gamma=…&eps=…&mu=…&delta=…&omega=…` (any subset; the rest from the
//!   served model; a model's term parameters by name, `fc=…`, or `friction.fc=…`):
//!   [`hdgear::explore::View`] as JSON, or [`hdgear::explore::ModelView`] for a model with terms.
//! - `GET /api/boundaries?…`: the bursting boundaries located by simulation (seconds; the
//!   study's set only: a 422 for a model with terms).
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
//! `Retry-After`, and its computation stops at that deadline, or as soon as its client hangs up
//! ([`work`]). At most
//! [`QUEUE_PER_WORKER`] requests per worker wait for one; beyond that a request is answered
//! with a 503 at once.
//!
//! Connections: at most [`MAX_CONNECTIONS`] are open at once (the next waits in the kernel's
//! backlog until one closes), and a client that has not sent a request's headers within
//! [`HEADER_TIMEOUT`] (after connecting, or after its last answer on a kept-alive connection)
//! is disconnected, so half-sent requests cannot hold connections or memory.

use crate::sources::ParamArgs;
use anyhow::{Context, Result};
use axum::Json;
use axum::extract::{Query, State};
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use hdgear::model::terms::Domain;
use hdgear::model::{Model, Subject};
use hdgear::params::{Param, Warning};
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
    /// The model the page starts from: the study's set (preset and flags), or a scenario file's
    /// model, whose every parameter is a slider.
    #[command(flatten)]
    pub params: ParamArgs,
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

/// The range a term parameter's slider spans at first, around its value `v` in the model, by
/// its domain: two decades either way on a log scale for a positive one, up to four times it
/// for a non-negative one, [0, 1] for a fraction, ±4|v| for any sign. A view's choice, not a
/// verdict: a value typed beyond it widens it. `None` for whole-number parameters (a
/// multisine's line, an exponent), which keep the model's value.
fn term_slider(domain: Domain, v: f64) -> Option<(f64, f64, bool)> {
    let size = if v != 0.0 { v.abs() } else { 1.0 };
    match domain {
        Domain::Positive => Some((size / 100.0, size * 100.0, true)),
        Domain::NonNegative => Some((0.0, 4.0 * size, false)),
        Domain::Fraction => Some((0.0, 1.0, false)),
        Domain::Any => Some((v - 4.0 * size, v + 4.0 * size, false)),
        Domain::Exponent | Domain::Line => None,
    }
}

/// One slider of the page: the library's name, symbol, meaning and value of a parameter with
/// its range ([`slider`], [`term_slider`]).
#[derive(serde::Serialize)]
struct Slider {
    key: String,
    sym: &'static str,
    hint: &'static str,
    def: f64,
    min: f64,
    max: f64,
    log: bool,
}

/// `/app.js` for the model `base`: the page's script with its sliders' table `PARAMS` written
/// in, read from the model's parameter list (the study's six in [`Param::ALL`]'s order, then
/// each term's), each keyed by its name, or by TERM.NAME where two terms share the name.
fn app_script(base: &Model) -> String {
    let mut values = base.param_values();
    // the study's six first, in their usual order, then the terms' in the model's (stable)
    values.sort_by_key(|v| {
        Param::ALL
            .iter()
            .position(|q| q.name() == v.info.name)
            .unwrap_or(usize::MAX)
    });
    let sliders: Vec<Slider> = values
        .into_iter()
        .filter_map(|v| {
            let info = v.info;
            // a name no other parameter of the model shares is its own key
            let unique = base.param(info.name).is_ok();
            let (min, max, log) = match info.name.parse::<Param>() {
                Ok(q) if unique => slider(q),
                _ => term_slider(info.domain, v.value)?,
            };
            let key = if unique {
                info.name.to_string()
            } else {
                format!("{}.{}", v.term, info.name)
            };
            Some(Slider {
                key,
                sym: info.symbol,
                hint: info.meaning,
                def: v.value,
                min,
                max,
                log,
            })
        })
        .collect();
    let table = serde_json::to_string(&sliders).expect("plain data serialises");
    assert!(
        APP_JS.matches(SLIDERS).count() == 1,
        "app.js holds one {SLIDERS}"
    );
    APP_JS.replacen(SLIDERS, &table, 1)
}

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
    fit: hdgear::physical::catalogue::CubicFit,
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

/// Query → what to compute: the server's model with the query's values, checked (the CLI's
/// validation and messages), and its study set's warnings.
fn params(base: &Model, q: &BTreeMap<String, String>) -> Result<(Subject, Vec<Warning>), ApiError> {
    let bad = |e: hdgear::Error| ApiError(StatusCode::BAD_REQUEST, e.to_string());
    if let Subject::Study(mut p) = base.subject() {
        for (k, v) in q {
            let param: Param = k.parse().map_err(bad)?;
            p = p.with(param, number(k, v)?);
        }
        let warnings = p.validate()?;
        return Ok((Subject::Study(p), warnings));
    }
    let mut changes = Vec::new();
    for (k, v) in q {
        changes.push((base.param(k).map_err(bad)?, number(k, v)?));
    }
    let m = base.with_all(&changes).map_err(bad)?;
    Ok((m.subject(), m.study_warnings()?))
}

mod work;
use work::{Workers, compute, options_until};

type Q = Query<BTreeMap<String, String>>;

/// What the handlers share: the workers, and the model the page was served for.
#[derive(Clone)]
struct App {
    workers: Workers,
    base: Model,
}

async fn view(State(app): State<App>, Query(q): Q) -> Result<Response, ApiError> {
    use hdgear::explore::{ModelView, View};
    Ok(match params(&app.base, &q)? {
        (Subject::Study(p), warnings) => {
            let v = compute(&app.workers, VIEW_TIMEOUT, move |stop| {
                View::compute(&p, warnings, &options_until(stop))
            })
            .await?;
            Json(v).into_response()
        }
        (Subject::Model(m), warnings) => {
            let remarks = warnings.iter().map(ToString::to_string).collect();
            let v = compute(&app.workers, VIEW_TIMEOUT, move |stop| {
                ModelView::compute(&m, remarks, &options_until(stop))
            })
            .await?;
            Json(v).into_response()
        }
    })
}

async fn boundaries(State(app): State<App>, Query(q): Q) -> Result<Response, ApiError> {
    let p = match params(&app.base, &q)? {
        (Subject::Study(p), _) => p,
        (Subject::Model(_), _) => {
            return Err(ApiError(
                StatusCode::UNPROCESSABLE_ENTITY,
                "the simulated boundaries are searched in the study's gamma and omega: not for a \
                 model with terms (hdgear boundary --config FILE traces a model's)"
                    .into(),
            ));
        }
    };
    let b = compute(&app.workers, BOUNDARY_TIMEOUT, move |stop| {
        hdgear::burst::boundaries(&p, &options_until(stop))
    })
    .await?;
    Ok(Json(b).into_response())
}

/// The keys of `/api/control` beside the parameters: the law, and the options of
/// [`hdgear::control::ControlOptions`] the explorer sets.
const CONTROL_KEYS: [&str; 5] = ["law", "gain", "ww", "wd", "taud"];

async fn control(State(app): State<App>, Query(mut q): Q) -> Result<Response, ApiError> {
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
    let (subject, _) = params(&app.base, &q)?;
    hdgear::on_subject!(subject, |p| {
        let doc = compute(&app.workers, BOUNDARY_TIMEOUT, move |stop| {
            hdgear::control::compare(&p, &[law.as_str()], &c, &options_until(stop))
        })
        .await?;
        Ok(Json(doc).into_response())
    })
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

fn asset(kind: &'static str, body: impl IntoResponse) -> Response {
    (
        [
            (header::CONTENT_TYPE, kind),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

/// The application for the model `base`: routes and their shared state.
pub fn router(base: Model) -> axum::Router {
    let script = app_script(&base);
    axum::Router::new()
        .route(
            "/",
            get(|| async { asset("text/html; charset=utf-8", PAGE) }),
        )
        .route(
            "/app.js",
            get(move || async move { asset("text/javascript; charset=utf-8", script) }),
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
        .with_state(App {
            workers: Workers::new(),
            base,
        })
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
    let (_, model, warnings) = a.params.resolve_model()?;
    crate::sink::warn(&warnings);
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
        serve(listener, router(model)).await;
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

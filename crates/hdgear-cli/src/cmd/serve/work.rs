//! How the explorer runs its computations: on the blocking pool, at most two per core, a bounded
//! queue before them, each stopped at its deadline or as soon as its client hangs up.
//!
//! A computation stops through its integrations ([`hdgear::integrate::Options::deadline`] and
//! [`hdgear::integrate::Options::cancel`]), which look at both every few hundred steps. The
//! cancel flag is one of a fixed set of `static` flags ([`FLAGS`]), one per computation in
//! flight, so that the integrator's options stay `Copy`. The request's future holds it with the
//! computation: when the future is dropped before the answer (hyper drops it when the client
//! closes the connection, as on a timeout) the flag is set, and the flag goes back to the free
//! set only once both the future and the computation are done with it, so a flag is never set
//! for a computation it no longer belongs to.

use super::{ApiError, QUEUE_PER_WORKER};
use axum::http::StatusCode;
use hdgear::integrate::{Cancel, Shared};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::sync::Semaphore;

/// Cancel flags: as many as computations can be admitted at once on a machine of up to
/// `MAX_FLAGS / (2·(1 + QUEUE_PER_WORKER))` = 341 cores ([`Workers::new`] admits no more).
const MAX_FLAGS: usize = 4096;

/// The cancel flags, one per computation in flight ([`Flag`]).
static FLAGS: [AtomicBool; MAX_FLAGS] = [const { AtomicBool::new(false) }; MAX_FLAGS];

/// The flags no computation holds.
static FREE: std::sync::LazyLock<Mutex<Vec<usize>>> =
    std::sync::LazyLock::new(|| Mutex::new((0..MAX_FLAGS).rev().collect()));

/// One computation's cancel flag, cleared when taken and freed when the last of its holders
/// (the request's future, the computation) drops it.
struct Flag(usize);

impl Flag {
    /// A free flag, cleared; `None` when every flag is held (more computations than admitted).
    fn take() -> Option<Flag> {
        let i = FREE.lock().unwrap_or_else(|e| e.into_inner()).pop()?;
        FLAGS[i].store(false, Ordering::Relaxed);
        Some(Flag(i))
    }

    fn cancel(&self) -> Cancel {
        Shared(&FLAGS[self.0])
    }
}

impl Drop for Flag {
    fn drop(&mut self) {
        FREE.lock().unwrap_or_else(|e| e.into_inner()).push(self.0);
    }
}

/// Held by the request's future: sets its computation's flag when dropped, whether the answer
/// came (the computation is over: no effect), the timeout fired or the client hung up.
struct HangUp(Arc<Flag>);

impl Drop for HangUp {
    fn drop(&mut self) {
        FLAGS[self.0.0].store(true, Ordering::Relaxed);
    }
}

/// Where a computation stops: its deadline, and its flag.
#[derive(Clone, Copy)]
pub(super) struct Stop {
    deadline: Instant,
    cancel: Cancel,
}

/// The explorer's detection options, stopping where `stop` says.
pub(super) fn options_until(stop: Stop) -> hdgear::burst::BurstOptions {
    let mut o = hdgear::explore::View::options();
    o.tol.deadline = Some(stop.deadline);
    o.tol.cancel = Some(stop.cancel);
    o
}

/// The computations' limits: workers running at once, and requests admitted (running or
/// waiting for a worker).
#[derive(Clone)]
pub(super) struct Workers {
    running: Arc<Semaphore>,
    admitted: Arc<Semaphore>,
    count: usize,
}

impl Workers {
    /// Two per core: a computation that waits on nothing keeps a core busy, and the second lets
    /// a cheap view run beside a long boundary search.
    pub(super) fn new() -> Workers {
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
        let count = 2 * cores;
        let admitted = (count * (1 + QUEUE_PER_WORKER)).min(MAX_FLAGS);
        Workers {
            running: Arc::new(Semaphore::new(count)),
            admitted: Arc::new(Semaphore::new(admitted)),
            count,
        }
    }

    fn busy(&self) -> ApiError {
        ApiError(
            StatusCode::SERVICE_UNAVAILABLE,
            format!(
                "busy: all {} workers and {} waiting places are taken; try again in a moment",
                self.count,
                self.count * QUEUE_PER_WORKER
            ),
        )
    }
}

/// Runs `f` on the blocking pool under the concurrency limit; the request is answered with a 503
/// at once when [`QUEUE_PER_WORKER`] requests per worker are already waiting, and once `limit`
/// has passed since it came (waiting for a worker included). `f` gets where to stop for its
/// integrations ([`options_until`]): at that deadline, or as soon as the request's future is
/// dropped (its client hung up). It holds its permits until it has stopped, so at most the
/// limit's number of computations ever run and the queue's bound counts them.
pub(super) async fn compute<T: Send + 'static>(
    workers: &Workers,
    limit: Duration,
    f: impl FnOnce(Stop) -> hdgear::Result<T> + Send + 'static,
) -> Result<T, ApiError> {
    let deadline = Instant::now() + limit;
    let admitted = workers
        .admitted
        .clone()
        .try_acquire_owned()
        .map_err(|_| workers.busy())?;
    let flag = Arc::new(Flag::take().ok_or_else(|| workers.busy())?);
    let stop = Stop {
        deadline,
        cancel: flag.cancel(),
    };
    let held = flag.clone();
    let _hang_up = HangUp(flag);
    let work =
        async {
            let permit =
                workers.running.clone().acquire_owned().await.map_err(|_| {
                    ApiError(StatusCode::SERVICE_UNAVAILABLE, "shutting down".into())
                })?;
            tokio::task::spawn_blocking(move || {
                let _held = (permit, admitted, held);
                f(stop)
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

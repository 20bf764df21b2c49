//! `hdgear serve`: the JSON API (answers, refusals with the CLI's messages), 2,000 requests from
//! 16 concurrent clients (every answer checked against the library, memory flat), and the page
//! driven in a real Chromium (tests/browser/explorer.py, Playwright with the system Chromium).
//!
//! **Why one file.** The tests of one command, the explorer, in one module of the test binary.

use hdgear::Params;
use hdgear::explore::View;
use std::io::{BufRead, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running `hdgear serve --port 0`, killed on drop.
struct Server {
    child: Child,
    addr: String,
}

impl Server {
    fn start() -> Server {
        Server::start_with(&[])
    }

    /// `hdgear serve --port 0` with `args` (a scenario's `--config FILE`).
    fn start_with(args: &[&str]) -> Server {
        let mut child = Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
            .args(["serve", "--port", "0", "--quiet"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        // "hdgear serve: http://127.0.0.1:PORT/  (Ctrl-C stops it)"
        let addr = line
            .split("http://")
            .nth(1)
            .and_then(|r| r.split('/').next())
            .unwrap_or_else(|| panic!("no URL in {line:?}"))
            .to_string();
        Server { child, addr }
    }

    /// Resident memory of the server process, in kB.
    fn rss_kb(&self) -> u64 {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).unwrap();
        status
            .lines()
            .find_map(|l| l.strip_prefix("VmRSS:"))
            .and_then(|v| v.split_whitespace().next()?.parse().ok())
            .unwrap()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One HTTP/1.1 GET on a fresh connection: (status, body).
fn get(addr: &str, path: &str) -> (u16, String) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).unwrap();
    let text = String::from_utf8_lossy(&raw);
    let (head, body) = text.split_once("\r\n\r\n").unwrap();
    assert!(
        !head
            .to_ascii_lowercase()
            .contains("transfer-encoding: chunked"),
        "{head}"
    );
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, body.to_string())
}

fn json(body: &str) -> serde_json::Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {body:.200}"))
}

/// A scenario file in `dir` with smooth friction f_c·tanh(x'/v_s) on the study's point: its path.
fn friction_scenario(dir: &std::path::Path) -> String {
    let path = dir.join("friction.toml");
    std::fs::write(&path, "[friction]\nfc = 0.1\nvs = 0.05\n").unwrap();
    path.display().to_string()
}

#[test]
fn a_scenario_s_model_is_served_with_its_parameters_as_sliders() {
    use hdgear::explore::ModelView;
    use hdgear::model::{Model, terms::AnyTerm};
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start_with(&["--config", &friction_scenario(dir.path())]);
    // the page's sliders: the study's six, then the friction's two, each at the model's value
    let (code, script) = get(&s.addr, "/app.js");
    assert_eq!(code, 200);
    let table = script
        .split("const PARAMS = ")
        .nth(1)
        .and_then(|r| r.split(";\n").next())
        .unwrap();
    let sliders = json(table);
    let keys: Vec<&str> = sliders
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["key"].as_str().unwrap())
        .collect();
    assert_eq!(
        keys,
        ["alpha", "gamma", "eps", "mu", "delta", "omega", "fc", "vs"]
    );
    assert_eq!(sliders[6]["def"], 0.1);
    // a view with the friction raised is the library's view of that model, to the last bit
    let (code, body) = get(&s.addr, "/api/view?fc=0.2&friction.vs=0.04&delta=12");
    assert_eq!(code, 200, "{body}");
    let p = Params {
        delta: 12.0,
        ..Params::default()
    };
    let m = Model::study(&p)
        .with_term(AnyTerm::new("friction", &[0.2, 0.04]).unwrap())
        .unwrap();
    let remarks = p
        .validate()
        .unwrap()
        .iter()
        .map(|w| w.to_string())
        .collect();
    let want = ModelView::compute(&m, remarks, &View::options()).unwrap();
    assert_eq!(json(&body), serde_json::to_value(&want).unwrap());
    assert!((want.analysis.damping_at_rest - 6.0).abs() < 1e-12); // 1 + f_c/v_s
    // refusals name what was wrong, in one line
    let (code, body) = get(&s.addr, "/api/view?fs=1");
    assert_eq!(code, 400);
    assert!(body.contains("'fs'") && body.contains("fc, vs"), "{body}");
    let (code, body) = get(&s.addr, "/api/view?fc=-1");
    assert_eq!(code, 400);
    assert!(body.contains("fc = -1"), "{body}");
    let (code, body) = get(&s.addr, "/api/boundaries?fc=0.2");
    assert_eq!(code, 422);
    assert!(body.contains("not for a model with terms"), "{body}");
}

#[test]
fn the_api_answers_and_refuses_with_the_cli_messages() {
    let s = Server::start();
    let (code, body) = get(&s.addr, "/api/view?gamma=0.1");
    assert_eq!(code, 200);
    let v = json(&body);
    let want = View::compute(&Params::default(), Vec::new(), &View::options()).unwrap();
    assert_eq!(v["classification"]["mode"], "pronounced-bursting");
    assert_eq!(
        v["response"]["peak_abs_xdot"].as_f64(),
        Some(want.response.rates.peak_abs_xdot),
        "the served view is the library's, to the last bit"
    );
    let len = |v: &serde_json::Value| v.as_array().unwrap().len();
    assert_eq!(len(&v["trace"]["t"]), want.trace.t.len());
    assert_eq!(len(&v["curve"]["a"]), hdgear::explore::CURVE_POINTS);
    // the CLI's messages for the same values
    let cli = |flag: &str| {
        let o = crate::common::hdgear()
            .args(["analyze", "--no-response", flag])
            .output()
            .unwrap();
        String::from_utf8_lossy(&o.stderr)
            .trim()
            .trim_start_matches("error: ")
            .to_string()
    };
    for (query, flag) in [
        ("omega=0", "--omega=0"),
        ("alpha=-2", "--alpha=-2"),
        ("delta=nan", "--delta=nan"),
    ] {
        let (code, body) = get(&s.addr, &format!("/api/view?{query}"));
        assert_eq!(code, 400, "{query}");
        assert_eq!(json(&body)["error"], cli(flag), "{query}");
    }
    for (query, code, needle) in [
        ("beta=1", 400, "invalid parameter name 'beta'"),
        ("gamma=abc", 400, "invalid value 'abc' for gamma"),
        ("omega=1e-7", 422, "beyond the explorer's budget"),
        ("omega=1e-9", 422, "steps, beyond the explorer's budget"),
    ] {
        let (c, body) = get(&s.addr, &format!("/api/view?{query}"));
        assert_eq!(c, code, "{query}: {body}");
        let e = json(&body)["error"].as_str().unwrap().to_string();
        assert!(e.contains(needle) && !e.contains('\n'), "{query}: {e}");
    }
    let (code, body) = get(&s.addr, "/api/drive?name=CSF-14-50");
    assert_eq!(code, 200);
    assert!((json(&body)["alpha_eps"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(get(&s.addr, "/api/drive?name=nope").0, 400);
    assert_eq!(get(&s.addr, "/nope").0, 404);
    for page in ["/", "/app.js", "/app.css"] {
        let (code, body) = get(&s.addr, page);
        assert_eq!(code, 200, "{page}");
        assert!(body.len() > 1000, "{page}");
    }
    // the sliders are the library's parameters, with its symbols and defaults
    let js = get(&s.addr, "/app.js").1;
    let start = js.find("const PARAMS = ").unwrap() + "const PARAMS = ".len();
    let end = start + js[start..].find(";\n").unwrap();
    let sliders: serde_json::Value = serde_json::from_str(&js[start..end]).unwrap();
    let defaults = hdgear::Params::default();
    for (q, s) in hdgear::params::Param::ALL
        .iter()
        .zip(sliders.as_array().unwrap())
    {
        assert_eq!(s["key"], q.name());
        assert_eq!(s["def"].as_f64().unwrap(), defaults.value(*q));
        let (lo, hi, def) = (
            s["min"].as_f64().unwrap(),
            s["max"].as_f64().unwrap(),
            defaults.value(*q),
        );
        assert!(
            lo < def && def < hi,
            "{q}: {def} outside the slider [{lo}, {hi}]"
        );
    }
    assert_eq!(sliders.as_array().unwrap().len(), 6);
}

/// Latency quantile (ms) of sorted durations.
fn quantile(sorted: &[Duration], q: f64) -> f64 {
    let i = ((sorted.len() - 1) as f64 * q).round() as usize;
    sorted[i].as_secs_f64() * 1e3
}

#[test]
fn two_thousand_requests_from_sixteen_clients() {
    let s = Server::start();
    // eight parameter sets across the bursting boundary, and one bad request in ten
    let gammas: Vec<f64> = (0..8).map(|k| 0.05 * 600f64.powf(k as f64 / 7.0)).collect();
    let expected: Vec<(bool, f64)> = gammas
        .iter()
        .map(|&g| {
            let v = View::compute(
                &Params::default().with(hdgear::params::Param::Gamma, g),
                Vec::new(),
                &View::options(),
            )
            .unwrap();
            (v.classification.bursting, v.response.rates.peak_abs_xdot)
        })
        .collect();
    assert!(expected.iter().any(|e| e.0) && expected.iter().any(|e| !e.0));
    let mut rss = Vec::new();
    let mut all = Vec::new();
    let t0 = Instant::now();
    for round in 0..2 {
        let lat: Vec<Duration> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..16)
                .map(|client| {
                    let (addr, gammas, expected) = (&s.addr, &gammas, &expected);
                    scope.spawn(move || {
                        let mut lat = Vec::new();
                        for k in 0..63 {
                            let n = client * 63 + k + round;
                            let t = Instant::now();
                            if n % 10 == 9 {
                                let (code, body) = get(addr, "/api/view?omega=0");
                                assert_eq!(code, 400);
                                assert!(json(&body)["error"].as_str().unwrap().contains("omega"));
                            } else {
                                let i = n % 8;
                                let (code, body) =
                                    get(addr, &format!("/api/view?gamma={:?}", gammas[i]));
                                assert_eq!(code, 200, "{body:.300}");
                                let v = json(&body);
                                assert_eq!(
                                    v["classification"]["bursting"].as_bool(),
                                    Some(expected[i].0)
                                );
                                assert_eq!(
                                    v["response"]["peak_abs_xdot"].as_f64(),
                                    Some(expected[i].1)
                                );
                            }
                            lat.push(t.elapsed());
                        }
                        lat
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| h.join().unwrap())
                .collect()
        });
        all.extend(lat);
        rss.push(s.rss_kb());
    }
    let wall = t0.elapsed().as_secs_f64();
    all.sort();
    assert_eq!(all.len(), 2016);
    eprintln!(
        "serve load: {} requests from 16 clients in {wall:.2} s ({:.0} requests/s); latency p50 {:.1} ms, p99 {:.1} ms, max {:.1} ms; resident memory after each half {} kB, {} kB",
        all.len(),
        all.len() as f64 / wall,
        quantile(&all, 0.5),
        quantile(&all, 0.99),
        quantile(&all, 1.0),
        rss[0],
        rss[1]
    );
    // flat: the second thousand requests may not grow the server by more than 32 MB (each
    // response is ~200 kB; a leak of one per request would be 200 MB)
    assert!(rss[1] < rss[0] + 32 * 1024, "memory grew: {rss:?} kB");
}

/// A Python with Playwright: `HDGEAR_PLAYWRIGHT_PYTHON`, or a virtual environment made once
/// under the test's target directory.
fn playwright_python() -> Result<String, String> {
    if let Ok(p) = std::env::var("HDGEAR_PLAYWRIGHT_PYTHON") {
        return Ok(p);
    }
    let venv = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("playwright-venv");
    let python = venv.join("bin/python");
    let ok = |c: &mut Command| c.status().is_ok_and(|s| s.success());
    if !ok(Command::new(&python).args(["-c", "import playwright"])) {
        let made = ok(Command::new("python3").arg("-m").arg("venv").arg(&venv))
            && ok(Command::new(&python).args(["-m", "pip", "install", "-q", "playwright"]));
        if !made {
            return Err(format!("cannot install playwright into {}", venv.display()));
        }
    }
    Ok(python.display().to_string())
}

#[test]
#[cfg_attr(
    hdgear_no_chromium,
    ignore = "no Chromium on this machine: install chromium or set HDGEAR_CHROMIUM"
)]
fn the_explorer_in_a_real_browser() {
    let ci = std::env::var_os("CI").is_some();
    let name = crate::common::chromium().expect("no Chromium found (CI installs it)");
    // Playwright wants a path
    let browser = if name.contains('/') {
        name
    } else {
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default())
            .map(|d| d.join(&name))
            .find(|p| p.is_file())
            .map(|p| p.display().to_string())
            .unwrap_or(name)
    };
    let python = match playwright_python() {
        Ok(p) => p,
        Err(e) if !ci => {
            eprintln!("SKIPPED the browser test: {e} (set HDGEAR_PLAYWRIGHT_PYTHON)");
            return;
        }
        Err(e) => panic!("{e}"),
    };
    let s = Server::start();
    let dir = tempfile::tempdir().unwrap();
    let scenario = friction_scenario(dir.path());
    let m = Server::start_with(&["--config", &scenario]);
    let shots = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("explorer-screenshots");
    std::fs::create_dir_all(&shots).unwrap();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/browser/explorer.py");
    let out = Command::new(python)
        .arg(script)
        .arg(format!("http://{}/", s.addr))
        .arg(browser)
        .arg(&shots)
        .arg(format!("http://{}/", m.addr))
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}\n{stderr}");
    eprintln!(
        "explorer in Chromium: {stdout} (screenshots in {})",
        shots.display()
    );
    for name in [
        "explorer-g30-1400.png",
        "explorer-g0.1-1400.png",
        "explorer-g0.1-800.png",
        "explorer-g0.1-zoom.png",
        "explorer-model-1400.png",
    ] {
        assert!(
            std::fs::metadata(shots.join(name)).unwrap().len() > 20_000,
            "{name}"
        );
    }
}

/// CPU time (user + system) the server process has used so far, in seconds.
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    // the fields after the command name in parentheses; utime and stime are the 14th and 15th
    let after = stat.rsplit_once(") ").unwrap().1;
    let f: Vec<u64> = after
        .split_whitespace()
        .map(|v| v.parse().unwrap_or(0))
        .collect();
    // clock ticks: 100 per second on Linux
    (f[11] + f[12]) as f64 / 100.0
}

/// Work that clients gave up on stops when they hang up: eight slow views (α = 1e-7) abandoned
/// after half a second each. A second after the last hung up, well before the view timeout's
/// deadline, the server is idle (under a fifth of a CPU second over the next second, where
/// its two busy cores would use two). That such a view is work up to the deadline is shown after:
/// asked for by a client that waits, it is answered with the timeout's 503.
#[test]
fn abandoned_views_stop_when_their_clients_hang_up() {
    let s = Server::start();
    let sent = Instant::now();
    std::thread::scope(|scope| {
        for i in 1..=8 {
            let addr = s.addr.clone();
            scope.spawn(move || {
                let mut c = TcpStream::connect(&addr).unwrap();
                let path = format!("/api/view?alpha=1e-7&gamma=0.00{i}");
                write!(c, "GET {path} HTTP/1.1\r\nHost: {addr}\r\n\r\n").unwrap();
                std::thread::sleep(Duration::from_millis(500));
            });
        }
    });
    std::thread::sleep(
        (sent + Duration::from_millis(1500)).saturating_duration_since(Instant::now()),
    );
    let before = cpu_seconds(s.child.id());
    std::thread::sleep(Duration::from_secs(1));
    let used = cpu_seconds(s.child.id()) - before;
    assert!(
        used < 0.2,
        "the server used {used} s of CPU after its clients hung up"
    );
    let (status, body) = get(&s.addr, "/api/view?alpha=1e-7&gamma=0.001");
    assert_eq!(status, 503, "{body}");
    assert!(body.contains("longer than 5 s"), "{body}");
    let (status, _) = get(&s.addr, "/api/view");
    assert_eq!(status, 200);
}

/// The server's workers: two per core, as `hdgear serve` counts them.
fn workers() -> usize {
    2 * std::thread::available_parallelism().map_or(2, |n| n.get())
}

/// The queue for workers is bounded: of many slow views sent at once, those beyond the workers
/// and [`QUEUE_PER_WORKER`] waiting per worker are refused at once with a 503 and
/// `Retry-After`, instead of waiting out the view timeout; the rest are admitted.
#[test]
fn a_full_queue_is_refused_at_once() {
    const QUEUE_PER_WORKER: usize = 5; // the server's, documented in the guide
    let s = Server::start();
    let admitted = workers() * (1 + QUEUE_PER_WORKER);
    let sent = admitted + 12;
    let answers: Vec<(Duration, String)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..sent)
            .map(|i| {
                let addr = s.addr.clone();
                scope.spawn(move || {
                    let t = Instant::now();
                    let mut c = TcpStream::connect(&addr).unwrap();
                    c.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
                    // α = 1e-7: each view runs until the view timeout stops it
                    let gamma = 1e-3 * (1.0 + i as f64 / 64.0);
                    write!(
                        c,
                        "GET /api/view?alpha=1e-7&gamma={gamma} HTTP/1.1\r\nHost: {addr}\r\n\
                         Connection: close\r\n\r\n"
                    )
                    .unwrap();
                    let mut raw = Vec::new();
                    c.read_to_end(&mut raw).unwrap();
                    (t.elapsed(), String::from_utf8_lossy(&raw).into_owned())
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let busy: Vec<_> = answers
        .iter()
        .filter(|(_, a)| a.contains("busy:"))
        .collect();
    assert_eq!(busy.len(), sent - admitted, "{:?}", answers.len());
    for (t, a) in &busy {
        assert!(a.starts_with("HTTP/1.1 503"), "{a:.200}");
        assert!(
            a.to_ascii_lowercase().contains("retry-after: 1"),
            "{a:.300}"
        );
        assert!(*t < Duration::from_secs(2), "refused only after {t:?}");
    }
    // the admitted ones were computed: most ran into the view timeout and got its 503
    let timed_out = answers
        .iter()
        .filter(|(_, a)| a.contains("took longer than"))
        .count();
    let statuses: Vec<&str> = answers
        .iter()
        .map(|(_, a)| a.get(9..12).unwrap_or(""))
        .collect();
    assert!(timed_out > admitted / 2, "{timed_out}: {statuses:?}");
    let (status, _) = get(&s.addr, "/api/view");
    assert_eq!(status, 200);
}

/// Slow clients (slowloris): connections that never finish a request's headers are closed
/// after the header timeout, at most 512 are served at once (the rest wait, unaccepted,
/// until slots free), and the server's memory stays flat. 600 such clients: at most 512 are
/// closed in the first timeout, every one by the second; a normal request sent meanwhile is
/// answered once slots are free.
#[test]
fn slow_clients_are_cut_off_and_capped() {
    const HEADER_TIMEOUT: Duration = Duration::from_secs(10);
    const MAX_CONNECTIONS: usize = 512;
    let s = Server::start();
    let (status, _) = get(&s.addr, "/api/view");
    assert_eq!(status, 200);
    let rss_before = s.rss_kb();
    let t0 = Instant::now();
    let slow: Vec<TcpStream> = (0..600)
        .map(|_| {
            let mut c = TcpStream::connect(&s.addr).unwrap();
            // a request line and part of the headers, never the blank line that ends them
            write!(c, "GET /api/view HTTP/1.1\r\nHost: x\r\nX-Slow: ").unwrap();
            c
        })
        .collect();
    let closed_at: Vec<Duration> = std::thread::scope(|scope| {
        let handles: Vec<_> = slow
            .into_iter()
            .map(|mut c| {
                scope.spawn(move || {
                    c.set_read_timeout(Some(3 * HEADER_TIMEOUT)).unwrap();
                    let mut buf = [0u8; 1024];
                    // the server's close: end of stream (or a reset), possibly after a short
                    // error answer
                    loop {
                        match c.read(&mut buf) {
                            Ok(0) | Err(_) => break,
                            Ok(_) => {}
                        }
                    }
                    t0.elapsed()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let first = closed_at
        .iter()
        .filter(|t| **t < HEADER_TIMEOUT + HEADER_TIMEOUT / 2)
        .count();
    assert!(
        closed_at
            .iter()
            .all(|t| *t >= HEADER_TIMEOUT - Duration::from_secs(1)),
        "a connection was closed before the header timeout: {:?}",
        closed_at.iter().min()
    );
    assert!(
        closed_at
            .iter()
            .all(|t| *t < 2 * HEADER_TIMEOUT + HEADER_TIMEOUT / 2),
        "a connection was kept past two header timeouts: {:?}",
        closed_at.iter().max()
    );
    assert!(
        (MAX_CONNECTIONS - 16..=MAX_CONNECTIONS).contains(&first),
        "{first} closed in the first timeout"
    );
    let (status, _) = get(&s.addr, "/api/view");
    assert_eq!(status, 200);
    let rss_after = s.rss_kb();
    assert!(
        rss_after < rss_before + 32 * 1024,
        "memory grew from {rss_before} kB to {rss_after} kB"
    );
}

/// `/api/control`: the served comparison is the library's, to the last bit; its refusals are
/// one line each.
#[test]
fn the_control_api_is_the_library_s_and_refuses_bad_laws_and_gains() {
    let s = Server::start();
    let (code, body) = get(&s.addr, "/api/control?law=vdamping&gain=3&gamma=0.1");
    assert_eq!(code, 200, "{body}");
    let want = hdgear::control::compare(
        &Params::default(),
        &["vdamping"],
        &hdgear::control::ControlOptions {
            gain: Some(3.0),
            ..Default::default()
        },
        &View::options(),
    )
    .unwrap();
    let a = &json(&body)["assessments"][0];
    assert_eq!(a["verdict"], "no-bursts");
    assert_eq!(
        a["peak_xdot"].as_f64(),
        Some(want.assessments[0].peak_xdot),
        "the served assessment is the library's, to the last bit"
    );
    let (code, body) = get(&s.addr, "/api/laws");
    assert_eq!(code, 200);
    assert_eq!(
        json(&body)["laws"].as_array().unwrap().len(),
        hdgear::control::LAWS.len()
    );
    for (query, needle) in [
        ("gain=3", "law is needed"),
        ("law=pid&gain=3", "pid"),
        ("law=vdamping&gain=abc", "invalid value 'abc' for gain"),
        ("law=vdamping&gain=-1", "-1"),
        ("law=vdamping&ww=2", "only the washout law"),
        (
            "law=vdamping&gain=3&beta=1",
            "invalid parameter name 'beta'",
        ),
    ] {
        let (c, body) = get(&s.addr, &format!("/api/control?{query}"));
        assert_eq!(c, 400, "{query}: {body}");
        let e = json(&body)["error"].as_str().unwrap().to_string();
        assert!(e.contains(needle) && !e.contains('\n'), "{query}: {e}");
    }
}

/// The hostile pass over the JSON API: every parameter of `/api/view` and `/api/boundaries`,
/// and the gain and options of `/api/control`, with each of the CLI generator's hostile values, malformed queries and drive names, sent by
/// four clients at once. Every answer is a known status with, when it is not 200, one JSON line
/// naming the problem; the server stays up and answers a normal view afterwards.
#[test]
fn hostile_queries_get_one_line_errors_and_the_server_stays_up() {
    let mut s = Server::start();
    let mut paths: Vec<String> = Vec::new();
    for endpoint in ["view", "boundaries"] {
        for param in hdgear::params::Param::ALL {
            for v in crate::hostile::VALUES {
                paths.push(format!("/api/{endpoint}?{}={v}", param.name()));
            }
        }
        for q in [
            "gamma",
            "gamma=1&gamma=abc",
            "%ZZ=1",
            "gamma=%ZZ",
            "=1",
            "&&&",
            "beta",
        ] {
            paths.push(format!("/api/{endpoint}?{q}"));
        }
    }
    // a control law's gain and options (with a gain: assessed, not tuned)
    for (law, key) in [
        ("vdamping", "gain"),
        ("washout", "ww"),
        ("dither", "wd"),
        ("delay", "taud"),
    ] {
        for v in crate::hostile::VALUES {
            let gain = if key == "gain" { "" } else { "&gain=1" };
            paths.push(format!("/api/control?law={law}&{key}={v}{gain}"));
        }
    }
    for name in [
        "",
        "%2F",
        "..%2F..%2Fetc%2Fpasswd",
        "%00",
        &"x".repeat(5000),
    ] {
        paths.push(format!("/api/drive?name={name}"));
    }
    paths.push("/api/drive".into());
    let total = paths.len();
    let chunks: Vec<Vec<String>> = paths.chunks(total.div_ceil(4)).map(<[_]>::to_vec).collect();
    let addr = s.addr.clone();
    let refused: usize = std::thread::scope(|scope| {
        let handles: Vec<_> = chunks
            .iter()
            .map(|chunk| {
                let addr = addr.clone();
                scope.spawn(move || {
                    let mut refused = 0;
                    for path in chunk {
                        let (code, body) = get(&addr, path);
                        assert!(
                            [200, 400, 422, 503].contains(&code),
                            "{path}: {code} {body:.200}"
                        );
                        if code != 200 {
                            let e = json(&body)["error"].as_str().unwrap_or("").to_string();
                            assert!(!e.is_empty() && !e.contains('\n'), "{path}: {body:.200}");
                            refused += 1;
                        }
                    }
                    refused
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).sum()
    });
    eprintln!("sent {total} hostile queries, {refused} refused");
    assert!(total >= 170 && refused * 2 > total, "{refused} of {total}");
    assert!(s.child.try_wait().unwrap().is_none(), "the server died");
    assert_eq!(get(&s.addr, "/api/view?gamma=1").0, 200);
}

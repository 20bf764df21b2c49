//! The figures of the study (and beyond), as data ([`Figure`]) built from computations.
//! Rendering is [`crate::output::plot`]'s job.

use crate::burst::{BurstOptions, Mode};
use crate::error::Result;
use crate::fast::{self, curve};
use crate::output::plot::{Figure, Map, Panel, Series, Style};
use crate::params::{Param, Params};
use crate::study::{Case, GridRun, Study};
use crate::sweep::Axis;
use crate::table::STUDY_GAMMAS;
use rayon::prelude::*;

/// The figure kinds (`hdgear plot KIND`, the report's figures). Adding a figure is a variant
/// here, a line in [`KINDS`] and its function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FigureKind {
    /// x'(τ) over one slow period for the study's four γ.
    XdotGamma,
    /// x(τ) with the equilibrium over it.
    XEquilibrium,
    /// The trajectory over the equilibrium curve in the (a, x) plane.
    TransformedPhase,
    /// (x, x').
    PhasePlane,
    /// |dx/da| against a.
    Slope,
    /// Peak |x'| and spikes against γ.
    Sweep,
    /// The (γ, δ) plane coloured by mode.
    Map,
    /// The bursting boundary in the (ω, γ) plane, predicted and simulated.
    Boundary,
    /// The frequency-response curve with stable and unstable branches, folds and doublings.
    FrequencyResponse,
    /// The stroboscopic orbit diagram against ω, swept up and down, with Benettin's exponent.
    OrbitDiagram,
    /// The largest Lyapunov exponent over (ω, δ).
    LyapunovMap,
}

/// How a figure kind is named, what it varies and how it is built.
pub struct KindEntry {
    /// The kind.
    pub kind: FigureKind,
    /// The name users write (and the serde name).
    pub name: &'static str,
    /// The parameters the figure varies itself (so a value given for them would be ignored).
    pub varies: &'static [Param],
    /// Builds the figure at a parameter point from (and into) the shared computations.
    pub build: fn(&Params, &mut Study) -> Result<Figure>,
}

/// The one list of figure kinds, in the order listed to users.
pub const KINDS: [KindEntry; 11] = [
    KindEntry {
        kind: FigureKind::XdotGamma,
        name: "xdot-gamma",
        varies: &[Param::Gamma],
        build: xdot_gamma,
    },
    KindEntry {
        kind: FigureKind::XEquilibrium,
        name: "x-equilibrium",
        varies: &[],
        build: x_equilibrium,
    },
    KindEntry {
        kind: FigureKind::TransformedPhase,
        name: "transformed-phase",
        varies: &[],
        build: transformed_phase,
    },
    KindEntry {
        kind: FigureKind::PhasePlane,
        name: "phase-plane",
        varies: &[],
        build: phase_plane,
    },
    KindEntry {
        kind: FigureKind::Slope,
        name: "slope",
        varies: &[Param::Gamma],
        build: slope,
    },
    KindEntry {
        kind: FigureKind::Sweep,
        name: "sweep",
        varies: &[Param::Gamma],
        build: sweep_figure,
    },
    KindEntry {
        kind: FigureKind::Map,
        name: "map",
        varies: &[Param::Gamma, Param::Delta],
        build: map_figure,
    },
    KindEntry {
        kind: FigureKind::Boundary,
        name: "boundary",
        varies: &[Param::Gamma, Param::Omega],
        build: boundary_figure,
    },
    KindEntry {
        kind: FigureKind::FrequencyResponse,
        name: "frequency-response",
        varies: &[Param::Omega],
        build: frequency_response_kind,
    },
    KindEntry {
        kind: FigureKind::OrbitDiagram,
        name: "orbit-diagram",
        varies: &[Param::Omega],
        build: orbit_diagram_kind,
    },
    KindEntry {
        kind: FigureKind::LyapunovMap,
        name: "lyapunov-map",
        varies: &[Param::Omega, Param::Delta],
        build: lyapunov_map_kind,
    },
];

impl FigureKind {
    /// Every kind, in the order listed to users.
    pub const ALL: [FigureKind; KINDS.len()] = {
        let mut all = [FigureKind::XdotGamma; KINDS.len()];
        let mut i = 0;
        while i < KINDS.len() {
            all[i] = KINDS[i].kind;
            i += 1;
        }
        all
    };

    fn entry(self) -> &'static KindEntry {
        // every kind has its line in KINDS (a test checks the order)
        &KINDS[self as usize]
    }

    /// The name users write.
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// The parameters the figure varies itself (so a value given for them would be ignored).
    pub fn varies(self) -> &'static [Param] {
        self.entry().varies
    }

    /// Builds the figure at `p` (the base point of figures that vary parameters), reusing and
    /// filling `study`.
    pub fn build(self, p: &Params, study: &mut Study) -> Result<Figure> {
        (self.entry().build)(p, study)
    }
}

impl std::fmt::Display for FigureKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl std::str::FromStr for FigureKind {
    type Err = crate::Error;
    fn from_str(name: &str) -> Result<FigureKind> {
        crate::error::by_name(&FigureKind::ALL, FigureKind::name, "figure kind", name)
    }
}

/// Drops points a straight line through their neighbours already represents to within `tol`
/// (in y), keeping every turn of the signal: plots stay exact to a fraction of a pixel with far
/// fewer points.
///
/// From an anchor, the line to a candidate end must pass within `tol` of every point between
/// them. Each such point allows an interval of slopes through the anchor, so the points between
/// are carried as the intersection of their intervals (a "sleeve", narrowed as each point joins)
/// and a candidate is one comparison: linear time. (Checking every point between again for each
/// candidate was quadratic in the length of a straight run: 34 ms of the report's single-threaded
/// figure stage went to it.) The same test as that check, rearranged; a vertical line (an end
/// straight above the anchor) asks every point between to lie within `tol` of the anchor.
///
/// ```
/// use hdgear::figures::decimate;
/// let line: Vec<(f64, f64)> = (0..100).map(|i| (f64::from(i), 2.0 * f64::from(i))).collect();
/// assert_eq!(decimate(&line, 1e-9), vec![(0.0, 0.0), (99.0, 198.0)]);
/// let corner = [(0.0, 0.0), (1.0, 1.0), (2.0, 2.0), (3.0, 0.0)];
/// assert_eq!(decimate(&corner, 1e-9), vec![(0.0, 0.0), (2.0, 2.0), (3.0, 0.0)]);
/// ```
pub fn decimate(points: &[(f64, f64)], tol: f64) -> Vec<(f64, f64)> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut out = vec![points[0]];
    let mut anchor = 0;
    let mut sleeve = Sleeve::default();
    for i in 2..points.len() {
        let (x0, y0) = points[anchor];
        // the point before the candidate joins those between the anchor and it
        let (xj, yj) = points[i - 1];
        sleeve.narrow(xj - x0, yj - y0, tol);
        let (x1, y1) = points[i];
        if !sleeve.admits(x1 - x0, y1 - y0) {
            anchor = i - 1;
            out.push(points[anchor]);
            sleeve = Sleeve::default();
        }
    }
    out.push(*points.last().expect("non-empty"));
    out
}

/// The lines through an anchor that pass within a tolerance of some points: slopes in
/// [`lo`, `hi`], and whether every point lies within it of the anchor's height (for a vertical
/// line).
#[derive(Clone, Copy, Debug)]
struct Sleeve {
    lo: f64,
    hi: f64,
    level: bool,
}

impl Default for Sleeve {
    /// No points yet: every line.
    fn default() -> Self {
        Sleeve {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
            level: true,
        }
    }
}

impl Sleeve {
    /// Adds the point (dx, dy) from the anchor: |dy − s·dx| ≤ tol. A point straight above the
    /// anchor allows every slope or none; a NaN allows none.
    fn narrow(&mut self, dx: f64, dy: f64, tol: f64) {
        let (a, b) = if dx > 0.0 {
            ((dy - tol) / dx, (dy + tol) / dx)
        } else if dx < 0.0 {
            ((dy + tol) / dx, (dy - tol) / dx)
        } else if dy.abs() <= tol {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (f64::INFINITY, f64::NEG_INFINITY)
        };
        if a <= b {
            self.lo = self.lo.max(a);
            self.hi = self.hi.min(b);
        } else {
            (self.lo, self.hi) = (f64::INFINITY, f64::NEG_INFINITY);
        }
        self.level &= dy.abs() <= tol;
    }

    /// Whether the line to the end (dx, dy) from the anchor passes within the tolerance of every
    /// point added.
    fn admits(&self, dx: f64, dy: f64) -> bool {
        if dx == 0.0 {
            return self.level;
        }
        let s = dy / dx;
        self.lo <= s && s <= self.hi
    }
}

fn burst_spans(w: &Case, t1: f64) -> Vec<(f64, f64, usize)> {
    w.response
        .bursts
        .iter()
        .filter(|b| b.onset < t1)
        .map(|b| (b.onset, b.end.min(t1), 1))
        .collect()
}

/// The legend label of shaded bursts (none when there are none).
fn burst_label(w: &Case) -> String {
    if w.response.bursts.is_empty() {
        String::new()
    } else {
        "burst".into()
    }
}

fn y_span(points: &[(f64, f64)]) -> f64 {
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), q| {
            (l.min(q.1), h.max(q.1))
        });
    (hi - lo).max(1e-12)
}

/// x'(t) over one slow period for the study's four γ, bursts shaded.
pub fn xdot_gamma(base: &Params, study: &mut Study) -> Result<Figure> {
    let mut panels = Vec::new();
    let points = STUDY_GAMMAS.map(|(gamma, _)| Params { gamma, ..*base });
    for w in study.cases(&points)? {
        let (gamma, c) = (w.params.gamma, &w.classification);
        let t1 = w.sample_end();
        let pts: Vec<(f64, f64)> = w.samples.iter().map(|s| (s.0, s.2)).collect();
        let tol = 1e-3 * y_span(&pts);
        panels.push(Panel {
            title: format!(
                "γ = {gamma}: {} (max |x'| = {:.4})",
                c.mode.name(),
                w.response.rates.peak_abs_xdot
            ),
            x_label: "τ".into(),
            y_label: "x'".into(),
            x_range: Some((w.response.window_start, t1)),
            series: vec![Series {
                label: String::new(),
                points: decimate(&pts, tol),
                color: 0,
                style: Style::Line,
            }],
            shaded: burst_spans(w, t1),
            shaded_label: burst_label(w),
            ..Panel::default()
        });
    }
    Ok(Figure {
        name: "xdot-gamma".into(),
        caption: "x'(τ) over one slow period 2π/ω after the transient, for γ = 30, 10, 1 and 0.1 \
                  (each panel its own scale). For γ = 30 and 10 x' is the smooth slow wave of a \
                  state that follows its equilibrium; for γ = 1 and 0.1 it is flat except for two \
                  bursts per period (shaded: detected bursts), each a fast pulse followed by \
                  ringing that decays within about ten time units."
            .into(),
        size: (1000, 1000),
        panels,
        map: None,
    })
}

/// x*(a(τ)) along the stable branch nearest the state, at the samples of `w`.
fn tracked_equilibrium(p: &Params, w: &Case) -> Vec<(f64, f64)> {
    w.samples
        .iter()
        .map(|s| {
            let a = (p.omega * s.0).sin();
            (
                s.0,
                fast::nearest_stable_equilibrium(p, a, s.1).unwrap_or(f64::NAN),
            )
        })
        .collect()
}

/// x(τ) with the equilibrium x*(a(τ)) over it, one slow period.
pub fn x_equilibrium(p: &Params, study: &mut Study) -> Result<Figure> {
    let w = study.case(p)?;
    let t1 = w.sample_end();
    let x: Vec<(f64, f64)> = w.samples.iter().map(|s| (s.0, s.1)).collect();
    let tol = 1e-3 * y_span(&x);
    let xs = tracked_equilibrium(p, w);
    let mut panels = vec![Panel {
        title: format!("x and x*(a), γ = {}, one slow period", p.gamma),
        x_label: "τ".into(),
        y_label: "x".into(),
        x_range: Some((w.response.window_start, t1)),
        series: vec![
            Series {
                label: "x*(a(τ))".into(),
                points: decimate(&xs, tol),
                color: 1,
                style: Style::Line,
            },
            Series {
                label: "x(τ)".into(),
                points: decimate(&x, tol),
                color: 0,
                style: Style::Thin,
            },
        ],
        shaded: burst_spans(w, t1),
        shaded_label: burst_label(w),
        ..Panel::default()
    }];
    let (z0, z1) = zoom_range(w, &xs);
    let zoom = |v: &[(f64, f64)]| {
        v.iter()
            .copied()
            .filter(|q| q.0 >= z0 && q.0 <= z1)
            .collect::<Vec<_>>()
    };
    panels.push(Panel {
        title: format!("zoom: τ from {z0:.0} to {z1:.0}"),
        x_label: "τ".into(),
        y_label: "x".into(),
        x_range: Some((z0, z1)),
        series: vec![
            Series {
                label: "x*(a(τ))".into(),
                points: zoom(&xs),
                color: 1,
                style: Style::Line,
            },
            Series {
                label: "x(τ)".into(),
                points: zoom(&x),
                color: 0,
                style: Style::Line,
            },
        ],
        shaded: burst_spans(w, t1)
            .into_iter()
            .filter(|b| b.1 > z0 && b.0 < z1)
            .collect(),
        shaded_label: burst_label(w),
        ..Panel::default()
    });
    Ok(Figure {
        name: "x-equilibrium".into(),
        caption: format!(
            "x(τ) and the stable equilibrium x*(a(τ)) of the fast subsystem over one slow period \
             (top) and around one burst (bottom), γ = {}. In the quiescent areas the state lies on \
             its equilibrium; where the equilibrium curve is steep x* runs across almost at once, \
             the state lags behind (max |x − x*| = {:.4}) and catches up with damped ringing \
             (shaded: the detected burst).",
            p.gamma, w.response.rates.max_tracking_error
        ),
        size: (1000, 800),
        panels,
        map: None,
    })
}

/// Around the first burst (or the steepest passage of x* when there is none).
fn zoom_range(w: &Case, xs: &[(f64, f64)]) -> (f64, f64) {
    match w.response.bursts.first() {
        Some(b) => (b.onset - 15.0, b.end + 15.0),
        None => {
            let i = xs
                .windows(2)
                .enumerate()
                .max_by(|a, b| {
                    (a.1[1].1 - a.1[0].1)
                        .abs()
                        .total_cmp(&(b.1[1].1 - b.1[0].1).abs())
                })
                .map_or(0, |(i, _)| i);
            (xs[i].0 - 40.0, xs[i].0 + 40.0)
        }
    }
}

/// The caption of the transformed phase portrait.
fn transformed_phase_caption(gamma: f64, areas: &[fast::Interval], has_folds: bool) -> String {
    format!(
        "The transformed phase portrait: the trajectory (a(τ), x(τ)) over one slow period on \
         the equilibrium curve of the fast subsystem, γ = {} (top: the whole range; bottom: \
         a zoom around a ≈ 0). Shaded: the spiking area{} predicted by the fast subsystem \
         ({}). {}",
        gamma,
        if areas.len() == 1 { "" } else { "s" },
        if areas.is_empty() {
            "none".to_string()
        } else {
            areas
                .iter()
                .map(|s| format!("a ∈ [{:.4}, {:.4}]", s.a_min, s.a_max))
                .collect::<Vec<_>>()
                .join(", ")
        },
        if !has_folds {
            "The curve has no fold: one stable equilibrium for every a. The trajectory \
             follows it in the quiescent areas and leaves it only where the curve is steep, \
             overshooting and ringing back onto it."
        } else {
            "Folds (crosses) lie in the traversed range: between them the curve has three \
             branches (the middle one saddles), and the trajectory jumps between the stable \
             branches (hysteresis)."
        }
    )
}

/// The trajectory of `w` in the (a, x) plane and the equilibrium curve (stable points, and
/// saddles where there are any).
fn phase_series(p: &Params, w: &Case) -> Result<Vec<Series>> {
    let c = curve(p, crate::fast::A_RANGE, 2000)?;
    let traj: Vec<(f64, f64)> = w
        .samples
        .iter()
        .map(|s| ((p.omega * s.0).sin(), s.1))
        .collect();
    let stable: Vec<(f64, f64)> = c
        .iter()
        .filter(|q| q.kind.is_stable())
        .map(|q| (q.a, q.x))
        .collect();
    let saddle: Vec<(f64, f64)> = c
        .iter()
        .filter(|q| !q.kind.is_stable())
        .map(|q| (q.a, q.x))
        .collect();
    let mut series = vec![Series {
        label: "trajectory".into(),
        points: decimate(&traj, 1e-4),
        color: 0,
        style: Style::Thin,
    }];
    series.push(Series {
        label: "stable equilibria".into(),
        points: stable,
        color: 1,
        style: Style::Points,
    });
    if !saddle.is_empty() {
        series.push(Series {
            label: "saddles".into(),
            points: saddle,
            color: 3,
            style: Style::Points,
        });
    }
    Ok(series)
}

/// The trajectory in the (a, x) plane over the equilibrium curve; spiking areas shaded, folds
/// marked.
pub fn transformed_phase(p: &Params, study: &mut Study) -> Result<Figure> {
    let w = study.case(p)?;
    let an = &w.analysis;
    let series = phase_series(p, w)?;
    let folds: Vec<(f64, f64, String)> = an
        .equilibria
        .folds
        .iter()
        .filter(|f| f.in_range)
        .map(|f| (f.a, f.x, "fold".into()))
        .collect();
    let areas = &an.equilibria.spiking_areas;
    let full = Panel {
        title: format!("trajectory in the (a, x) plane, γ = {}", p.gamma),
        x_label: "a = sin(ωτ)".into(),
        y_label: "x".into(),
        x_range: Some((-1.02, 1.02)),
        series: series.clone(),
        shaded: areas.iter().map(|s| (s.a_min, s.a_max, 4)).collect(),
        shaded_label: if areas.is_empty() {
            String::new()
        } else {
            "spiking area".into()
        },
        markers: folds.clone(),
        ..Panel::default()
    };
    // zoom on the spiking areas (or the steepest point): where the trajectory leaves the curve
    let (lo, hi) = match (areas.first(), areas.last()) {
        (Some(f), Some(l)) => (f.a_min, l.a_max),
        _ => (an.equilibria.max_slope.a, an.equilibria.max_slope.a),
    };
    let half = (3.0 * (hi - lo)).max(0.06);
    let (z0, z1) = (
        (0.5 * (lo + hi) - half).max(-1.0),
        (0.5 * (lo + hi) + half).min(1.0),
    );
    let zoomed: Vec<Series> = series
        .iter()
        .map(|s| Series {
            points: s
                .points
                .iter()
                .copied()
                .filter(|q| q.0 >= z0 && q.0 <= z1)
                .collect(),
            ..s.clone()
        })
        .collect();
    let zoom = Panel {
        title: format!("zoom: a from {z0:.3} to {z1:.3}"),
        x_range: Some((z0, z1)),
        series: zoomed,
        ..full.clone()
    };
    Ok(Figure {
        name: "transformed-phase".into(),
        caption: transformed_phase_caption(p.gamma, areas, !folds.is_empty()),
        size: (1000, 1000),
        panels: vec![full, zoom],
        map: None,
    })
}

/// The phase plane (x, x') over one slow period.
pub fn phase_plane(p: &Params, study: &mut Study) -> Result<Figure> {
    let w = study.case(p)?;
    let pts: Vec<(f64, f64)> = w.samples.iter().map(|s| (s.1, s.2)).collect();
    Ok(Figure {
        name: "phase-plane".into(),
        caption: format!(
            "The phase plane (x, x') over one slow period, γ = {}. Slow drift along x' ≈ 0; each \
             burst is a loop away from it that spirals back (the fast subsystem's equilibria are \
             stable foci or nodes).",
            p.gamma
        ),
        size: (800, 600),
        panels: vec![Panel {
            title: format!("phase plane, γ = {}", p.gamma),
            x_label: "x".into(),
            y_label: "x'".into(),
            series: vec![Series {
                label: String::new(),
                points: decimate(&pts, 1e-4 * y_span(&pts)),
                color: 0,
                style: Style::Line,
            }],
            ..Panel::default()
        }],
        map: None,
    })
}

/// |dx/da| against a (log scale) for the four γ of the study.
pub fn slope(base: &Params, _study: &mut Study) -> Result<Figure> {
    let mut series = Vec::new();
    for (i, (gamma, _)) in STUDY_GAMMAS.iter().enumerate() {
        let p = Params {
            gamma: *gamma,
            ..*base
        };
        let c = curve(&p, crate::fast::A_RANGE, 2000)?;
        series.push(Series {
            label: format!("γ = {gamma}"),
            points: c.iter().map(|q| (q.a, q.slope.abs())).collect(),
            color: i,
            style: Style::Line,
        });
    }
    Ok(Figure {
        name: "slope".into(),
        caption: "The slope |dx/da| = δ/|g'(x)| of the equilibrium curve against a, log scale. \
                  As γ falls toward 1/(3α) the peak near a ≈ 0 grows from 0.47 (γ = 30, whose \
                  steepest point lies outside the range) through 1.5 and 15.3 to 189.5 (γ = 0.1): \
                  a sharp quantitative change, with no fold (the slope stays finite)."
            .into(),
        size: (1000, 550),
        panels: vec![Panel {
            title: "slope of the equilibrium curve".into(),
            x_label: "a".into(),
            y_label: "|dx/da|".into(),
            y_log: true,
            x_range: Some(crate::fast::A_RANGE),
            series,
            ..Panel::default()
        }],
        map: None,
    })
}

/// Peak |x'| and spikes per burst against γ.
pub fn sweep_figure(base: &Params, study: &mut Study) -> Result<Figure> {
    let rows = &study.sweep(base)?.rows;
    let gc = base.critical_gamma();
    let peak: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.params.gamma, r.rates.peak_abs_xdot))
        .collect();
    let spikes: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.params.gamma, r.rates.spikes_per_burst))
        .collect();
    let bursting = rows
        .iter()
        .filter(|r| r.rates.bursts_per_period.is_some_and(|b| b > 0.0))
        .map(|r| r.params.gamma)
        .fold(0.0, f64::max);
    let vline = vec![(gc, format!("1/(3α) = {gc:.4}"))];
    Ok(Figure {
        name: "sweep".into(),
        caption: format!(
            "A sweep of γ from 0.01 to 30 (log-spaced, {} points; the other parameters as in the \
             study). Top: the largest |x'| after the transient; bottom: spikes per burst. Bursts \
             appear below γ ≈ {:.2}, far above the fold threshold 1/(3α) = {:.4} (grey line): \
             the bursting sets in through the steepening of the curve, not through a bifurcation.",
            rows.len(),
            bursting,
            gc
        ),
        size: (1000, 800),
        panels: vec![
            Panel {
                title: "peak |x'| against γ".into(),
                x_label: "γ".into(),
                y_label: "max |x'|".into(),
                x_log: true,
                y_log: true,
                series: vec![Series {
                    label: "peak |x'|".into(),
                    points: peak,
                    color: 0,
                    style: Style::Line,
                }],
                vlines: vline.clone(),
                ..Panel::default()
            },
            Panel {
                title: "spikes per burst against γ".into(),
                x_label: "γ".into(),
                y_label: "spikes per burst".into(),
                x_log: true,
                series: vec![Series {
                    label: "spikes per burst".into(),
                    points: spikes,
                    color: 1,
                    style: Style::Points,
                }],
                vlines: vline,
                ..Panel::default()
            },
        ],
        map: None,
    })
}

/// The smallest δ at which the folds of the fast subsystem lie inside a ∈ [−1, 1]:
/// max |g(x±) − μ| (γ < 1/(3α)).
pub fn fold_delta(p: &Params) -> Option<f64> {
    fast::fold_abscissae(p).map(|(xm, xp)| (p.g(xm) - p.mu).abs().max((p.g(xp) - p.mu).abs()))
}

/// The edges of grid cell `i` on `ax`: halfway between grid values (geometric for log axes).
fn cell_edges(ax: &Axis, i: usize) -> (f64, f64) {
    let v = ax.value(i);
    let prev = if i > 0 { ax.value(i - 1) } else { v };
    let next = if i + 1 < ax.count { ax.value(i + 1) } else { v };
    if ax.log {
        let lo = if i > 0 {
            (prev * v).sqrt()
        } else {
            v * (v / next).sqrt()
        };
        let hi = if i + 1 < ax.count {
            (v * next).sqrt()
        } else {
            v * (v / prev).sqrt()
        };
        (lo, hi)
    } else {
        let lo = if i > 0 {
            0.5 * (prev + v)
        } else {
            v - 0.5 * (next - v)
        };
        let hi = if i + 1 < ax.count {
            0.5 * (v + next)
        } else {
            v + 0.5 * (v - prev)
        };
        (lo, hi)
    }
}

/// The boundary of the region where folds lie in a ∈ [−1, 1]: δ ≥ δ_fold(γ) for γ from `g_min`
/// to 1/(3α), closed on the right by γ = 1/(3α) up to `d_max`.
fn fold_boundary(base: &Params, g_min: f64, d_max: f64) -> Vec<(f64, f64)> {
    let gc = base.critical_gamma();
    let cusp = Params { gamma: gc, ..*base };
    let mut fold: Vec<(f64, f64)> = (0..199)
        .map(|k| g_min * (gc / g_min).powf(k as f64 / 199.0))
        .filter_map(|g| fold_delta(&Params { gamma: g, ..*base }).map(|d| (g, d)))
        .collect();
    fold.push((gc, (cusp.g(gc) - cusp.mu).abs()));
    fold.push((gc, d_max));
    fold
}

/// The (γ, δ) boundary predicted from the equilibrium curve alone: for each γ in `xr` the δ in
/// `yr` above which bursting is predicted.
fn predicted_delta_boundary(base: &Params, xr: (f64, f64), yr: (f64, f64)) -> Vec<(f64, f64)> {
    let gc = base.critical_gamma();
    // one bisection of predictions per γ, the γs side by side (the figure stage is otherwise
    // on one core)
    (0..160)
        .into_par_iter()
        .map(|k| xr.0 * (xr.1 / xr.0).powf(f64::from(k) / 159.0))
        .filter(|&g| g > gc)
        .filter_map(|g| {
            let quiet = |d: f64| {
                !fast::predict(&Params {
                    gamma: g,
                    delta: d,
                    ..*base
                })
                .bursting
            };
            fast::bisect_log(yr.0, yr.1, quiet).map(|d| (g, d))
        })
        .collect()
}

/// The (γ, δ) plane coloured by mode, with the fold curve and the cusp over it.
pub fn map_figure(base: &Params, study: &mut Study) -> Result<Figure> {
    let GridRun { grid, rows } = study.map(base)?;
    let modes = [
        Mode::Normal,
        Mode::Transitional,
        Mode::FastSlow,
        Mode::PronouncedBursting,
        Mode::Relaxation,
        Mode::NotFastSlow,
    ];
    let (ga, da) = (&grid.axes[0], &grid.axes[1]);
    let edges = cell_edges;
    let mut cells = Vec::new();
    for r in rows {
        let (i, j) = (r.index % ga.count, r.index / ga.count);
        let (x0, x1) = edges(ga, i);
        let (y0, y1) = edges(da, j);
        if let Some(k) = modes.iter().position(|&m| Some(m) == r.mode) {
            cells.push((x0, x1, y0, y1, k));
        }
    }
    let gc = base.critical_gamma();
    let cusp = Params { gamma: gc, ..*base };
    let cusp_delta = (cusp.g(gc) - cusp.mu).abs();
    let (xr, yr) = (
        (edges(ga, 0).0, edges(ga, ga.count - 1).1),
        (edges(da, 0).0, edges(da, da.count - 1).1),
    );
    let fold = fold_boundary(base, ga.start, yr.1);
    let predicted = predicted_delta_boundary(base, xr, yr);
    Ok(Figure {
        name: "map".into(),
        caption: format!(
            "Oscillation mode over the (γ, δ) plane ({} × {} simulations, both axes logarithmic; \
             the other parameters as in the study). Black: the fold boundary — inside it (left \
             of γ = 1/(3α) = {:.4} and above the fold curve) the folds of the fast subsystem lie \
             in the traversed range a ∈ [−1, 1] and the bursting is fold-hysteresis; the cross \
             marks the cusp. Everything that bursts outside it bursts with no bifurcation at all \
             (sharp-quantitative-change): by far the larger part of the bursting region. Dots: the \
             boundary predicted from the equilibrium curve alone (bursting above them), to compare \
             with the simulated modes.",
            ga.count, da.count, gc
        ),
        size: (1000, 700),
        panels: Vec::new(),
        map: Some(Map {
            frame: Panel {
                title: "mode over (γ, δ)".into(),
                x_label: "γ".into(),
                y_label: "δ".into(),
                x_log: true,
                y_log: true,
                legend_left: true,
                x_range: Some(xr),
                y_range: Some(yr),
                series: vec![
                    Series {
                        label: "fold boundary".into(),
                        points: fold,
                        color: 6,
                        style: Style::Line,
                    },
                    Series {
                        label: "predicted bursting boundary".into(),
                        points: predicted,
                        color: 6,
                        style: Style::Points,
                    },
                ],
                markers: if cusp_delta <= yr.1 {
                    vec![(gc, cusp_delta.max(yr.0), "cusp".into())]
                } else {
                    Vec::new()
                },
                ..Panel::default()
            },
            cells,
            categories: modes.iter().map(|m| m.name().to_string()).collect(),
        }),
    })
}

/// Builds one figure by kind for `hdgear plot` (sweep sizes: 120 γ values; map 40 × 24).
pub fn by_kind(
    kind: FigureKind,
    p: &Params,
    opts: &BurstOptions,
    threads: usize,
) -> Result<Figure> {
    let mut study = Study::new(*opts, *opts, threads, 120, (40, 24));
    kind.build(p, &mut study)
}

/// The predicted bursting boundary (ω at which κ reaches the threshold) and the edge of the
/// fast-slow domain, for 200 γ log-spaced from just above the cusp to 30, as (ω, γ).
type Curve = Vec<(f64, f64)>;

fn boundary_curves(base: &Params) -> (Curve, Curve) {
    let gc = base.critical_gamma();
    let (g0, g1) = (gc * 1.001, 30.0_f64);
    let gammas: Vec<f64> = (0..200)
        .map(|i| g0 * (g1 / g0).powf(f64::from(i) / 199.0))
        .collect();
    let at = |g: f64| Params { gamma: g, ..*base };
    let predicted: Vec<(f64, f64)> = gammas
        .par_iter()
        .map(|&g| (fast::predict(&at(g)).omega_boundary, g))
        .filter(|q| q.0.is_finite() && q.0 > 0.0)
        .collect();
    let domain: Vec<(f64, f64)> = gammas
        .iter()
        .map(|&g| {
            let r = crate::burst::turning_point_rate(&at(g));
            (r / crate::burst::TIME_SCALE_SEPARATION, g)
        })
        .collect();
    (predicted, domain)
}

/// The bursting boundary in the (ω, γ) plane: predicted from the equilibrium curve alone
/// (κ = [`crate::fast::FORCING_RATE_THRESHOLD`]) for γ from just above the cusp to 30, the edge
/// of the fast-slow domain (ω = r/10), and the boundaries located by simulation through `base` (in
/// γ and in ω) and through γ = 1 (in ω).
pub fn boundary_figure(base: &Params, study: &mut Study) -> Result<Figure> {
    let gc = base.critical_gamma();
    let at = |g: f64| Params { gamma: g, ..*base };
    let (predicted, domain) = boundary_curves(base);
    let b = study.boundaries(&[*base, at(1.0)])?;
    let simulated: Vec<(f64, f64)> = [
        b[0].simulated_gamma.map(|g| (base.omega, g)),
        b[0].simulated_omega.map(|w| (w, base.gamma)),
        b[1].simulated_omega.map(|w| (w, 1.0)),
    ]
    .into_iter()
    .flatten()
    .collect();
    // the largest factor between a simulated boundary and its prediction
    let ratio = |p: Option<f64>, s: Option<f64>| match (p, s) {
        (Some(p), Some(s)) if p > 0.0 && s > 0.0 => (p / s).max(s / p),
        _ => 1.0,
    };
    let factor = ratio(b[0].predicted_gamma, b[0].simulated_gamma)
        .max(ratio(Some(b[0].predicted_omega), b[0].simulated_omega))
        .max(ratio(Some(b[1].predicted_omega), b[1].simulated_omega));
    let x_min = predicted.iter().map(|q| q.0).fold(base.omega, f64::min) / 2.0;
    let x_max = domain.iter().map(|q| q.0).fold(base.omega, f64::max) * 2.0;
    let series = vec![
        Series {
            label: "predicted boundary (κ = threshold)".into(),
            points: predicted,
            color: 0,
            style: Style::Line,
        },
        Series {
            label: "fast-slow domain edge ω = r/10".into(),
            points: domain,
            color: 2,
            style: Style::Thin,
        },
        Series {
            label: "fold threshold γ = 1/(3α)".into(),
            points: vec![(x_min, gc), (x_max, gc)],
            color: 3,
            style: Style::Thin,
        },
        Series {
            label: "located by simulation".into(),
            points: simulated,
            color: 1,
            style: Style::Points,
        },
    ];
    Ok(Figure {
        name: "boundary".into(),
        caption: format!(
            "The bursting boundary in the (ω, γ) plane (the other parameters as at the study's \
             point). Bursting lies to the right of and below the predicted curve: faster forcing \
             or a steeper equilibrium curve. The dots are where the simulated verdict switches, to {} % \
             (γ at ω = {}, ω at γ = {} and at γ = 1); they lie within a factor \
             {factor:.2} of the prediction, which uses the equilibrium curve alone. As ω → 0 the boundary runs \
             down to the fold threshold 1/(3α) = {gc:.4}: without folds every burst vanishes \
             (Fenichel). Right of the domain edge the forcing is too fast for a fast-slow reading.",
            100.0 * crate::burst::BOUNDARY_REL_TOL,
            base.omega,
            base.gamma
        ),
        size: (1000, 700),
        panels: vec![Panel {
            title: "bursting boundary".into(),
            x_label: "ω".into(),
            y_label: "γ".into(),
            x_log: true,
            y_log: true,
            x_range: Some((x_min, x_max)),
            series,
            markers: vec![(base.omega, base.gamma, "study's point".into())],
            legend_left: true,
            ..Panel::default()
        }],
        map: None,
    })
}

/// Splits a branch into runs of equal stability, as (stable, points (λ, y)) with the boundary
/// point in both neighbours so the curve stays connected.
fn stability_runs(
    b: &crate::periodic::Branch<Param>,
    xy: &impl Fn(usize, &crate::periodic::BranchPoint) -> (f64, f64),
) -> Vec<(bool, Vec<(f64, f64)>)> {
    let mut runs: Vec<(bool, Vec<(f64, f64)>)> = Vec::new();
    for (i, q) in b.points.iter().enumerate() {
        let pt = xy(i, q);
        match runs.last_mut() {
            Some((s, pts)) if *s == q.stable || q.special.is_some() => pts.push(pt),
            Some((_, pts)) => {
                let last = *pts.last().expect("runs are never empty");
                runs.push((q.stable, vec![last, pt]));
            }
            None => runs.push((q.stable, vec![pt])),
        }
    }
    runs
}

/// One panel of a frequency-response figure: the points `xy(i, point i)` of the branch, with
/// the axis labels.
fn response_panel(
    b: &crate::periodic::Branch<Param>,
    (title, x_label): (&str, &str),
    xy: impl Fn(usize, &crate::periodic::BranchPoint) -> (f64, f64),
) -> Panel {
    use crate::periodic::Special;
    let mut series = Vec::new();
    let (mut stable_named, mut unstable_named) = (false, false);
    for (stable, points) in stability_runs(b, &xy) {
        let named = if stable {
            &mut stable_named
        } else {
            &mut unstable_named
        };
        let label = match (*named, stable) {
            (true, _) => String::new(),
            (false, true) => "stable".into(),
            (false, false) => "unstable".into(),
        };
        *named = true;
        series.push(Series {
            label,
            points,
            color: usize::from(!stable),
            style: if stable { Style::Line } else { Style::Thin },
        });
    }
    let markers = b
        .points
        .iter()
        .enumerate()
        .filter(|(_, q)| q.special.is_some())
        .map(|(i, q)| {
            let label = match q.special {
                Some(Special::Fold) => "fold",
                Some(Special::PeriodDoubling) => "period doubling",
                _ => "branch point",
            };
            let (x, y) = xy(i, q);
            (x, y, label.to_string())
        })
        .collect();
    Panel {
        title: title.into(),
        x_label: x_label.into(),
        y_label: title.into(),
        x_log: true,
        series,
        markers,
        ..Panel::default()
    }
}

/// The frequency-response curve: peak-to-peak x and max |x'| against ω (log), stable branches
/// thick, unstable thin, folds and period doublings marked.
pub fn frequency_response_figure(p: &Params, b: &crate::periodic::Branch<Param>) -> Figure {
    use crate::periodic::Special;
    let folds: Vec<String> = b
        .specials()
        .filter(|q| q.special == Some(Special::Fold))
        .map(|q| format!("{:.4}", q.param))
        .collect();
    let pds = b
        .specials()
        .filter(|q| q.special == Some(Special::PeriodDoubling))
        .count();
    Figure {
        name: "frequency-response".into(),
        caption: format!(
            "Frequency response of the periodic response (period 2π/ω) at α = {}, γ = {}, ε = {}, \
             μ = {}, δ = {}, by pseudo-arclength continuation in ln ω with Floquet multipliers \
             from the variational equations. Thick: stable; thin: unstable. {} {}",
            p.alpha,
            p.gamma,
            p.eps,
            p.mu,
            p.delta,
            if folds.is_empty() {
                "No fold: the response is single-valued, a slow sweep of ω does not jump."
                    .to_string()
            } else {
                format!(
                    "Folds at ω = {}: the hardening stiffness bends the resonance peak to the \
                     right, and a slow sweep of ω jumps at the folds (up at the upper fold, down \
                     at the lower), with hysteresis between them.",
                    folds.join(", ")
                )
            },
            if pds > 0 {
                format!(
                    "{pds} period doubling(s): between them the period-1 response is unstable and \
                     the response has twice the forcing period."
                )
            } else {
                String::new()
            }
        ),
        size: (1000, 800),
        panels: vec![
            response_panel(b, ("peak-to-peak x", "ω"), |_, q| {
                (q.param, q.amplitude.peak_to_peak)
            }),
            response_panel(b, ("max |x'|", "ω"), |_, q| {
                (q.param, q.amplitude.max_abs_xdot)
            }),
        ],
        map: None,
    }
}

/// The stroboscopic orbit diagram: x at phase 0 of every recorded period against the parameter,
/// up-sweep and down-sweep in two colours (where they differ, the response is hysteretic).
pub fn orbit_diagram_figure(
    p: &Params,
    param: Param,
    points: &[crate::periodic::DiagramPoint],
) -> Figure {
    use crate::periodic::Sweep;
    let series = [Sweep::Up, Sweep::Down]
        .into_iter()
        .enumerate()
        .map(|(i, s)| Series {
            label: format!("sweep {}", s.name()),
            points: points
                .iter()
                .filter(|q| q.sweep == s)
                .flat_map(|q| q.section.iter().map(move |y| (q.param, y[0])))
                .collect(),
            color: i,
            style: Style::Points,
        })
        .collect();
    let positive = points.iter().all(|q| q.param > 0.0);
    let (lo, hi) = points.iter().fold((f64::INFINITY, 0.0f64), |(l, h), q| {
        (l.min(q.param), h.max(q.param))
    });
    let lyap: Vec<(f64, f64)> = points
        .iter()
        .filter(|q| q.sweep == Sweep::Up)
        .filter_map(|q| q.lyapunov.map(|l| (q.param, l)))
        .collect();
    let x_log = positive && hi > 10.0 * lo;
    let mut panels = vec![Panel {
        title: format!("stroboscopic section against {param}"),
        x_label: param.to_string(),
        y_label: "x at phase 0".into(),
        x_log,
        series,
        ..Panel::default()
    }];
    if !lyap.is_empty() {
        panels.push(Panel {
            title: "largest Lyapunov exponent (up-sweep)".into(),
            x_label: param.to_string(),
            y_label: "λ_max".into(),
            x_log,
            series: vec![Series {
                label: String::new(),
                points: lyap,
                color: 2,
                style: Style::Line,
            }],
            ..Panel::default()
        });
    }
    Figure {
        name: "orbit-diagram".into(),
        caption: format!(
            "Orbit diagram against {param} (the other parameters: α = {}, γ = {}, ε = {}, μ = {}, \
             δ = {}, ω = {}): x at phase 0 of each recorded forcing period after the transient, \
             each value started from the previous value's state. One dot per value: a period-1 \
             response; two: period 2 (after a period doubling); a cloud: no periodic response \
             within the record. Where the up- and down-sweeps differ, two stable responses \
             coexist and the sweep direction decides (hysteresis between folds).",
            p.alpha, p.gamma, p.eps, p.mu, p.delta, p.omega
        ),
        size: (1000, if panels.len() > 1 { 800 } else { 600 }),
        panels,
        map: None,
    }
}

/// Bins of the Lyapunov map, as (upper bound, name), the last unbounded. −1/2 is the exponent of
/// every orbit whose multipliers are a complex pair (|m| = e^{−T/2}, SPEC §3's trace −1), the
/// most strongly attracting a response of this damping can be; near 0 a multiplier is near the
/// unit circle (a fold or a period doubling close by); above 0, sensitive dependence.
pub const LYAPUNOV_BINS: [(f64, &str); 5] = [
    (-0.45, "λ ≈ −1/2: complex multipliers"),
    (-0.1, "−0.45 < λ ≤ −0.1"),
    (-0.01, "−0.1 < λ ≤ −0.01: near a bifurcation"),
    (0.01, "|λ| ≤ 0.01: at a bifurcation, or not periodic"),
    (f64::INFINITY, "λ > 0.01: chaotic"),
];

/// The Lyapunov exponent over a grid: a curve for one axis, a map in [`LYAPUNOV_BINS`] for two.
pub fn lyapunov_figure(grid: &crate::sweep::Grid, rows: &[crate::periodic::LyapunovRow]) -> Figure {
    let p = grid.base;
    let caption = format!(
        "Largest Lyapunov exponent (Benettin, variational equations) of the response reached \
         from the default start, over {} point(s) (the other parameters: α = {}, γ = {}, ε = {}, \
         μ = {}, δ = {}, ω = {}). For a periodic response it equals the largest Floquet exponent; \
         −1/2 wherever the multipliers are a complex pair; near 0 at folds and period doublings.",
        rows.len(),
        p.alpha,
        p.gamma,
        p.eps,
        p.mu,
        p.delta,
        p.omega
    );
    let ax = &grid.axes[0];
    if grid.axes.len() == 1 {
        return lyapunov_curve(ax, rows, caption);
    }
    let ay = &grid.axes[1];
    let cells = rows
        .iter()
        .filter(|r| r.lyapunov.is_finite())
        .map(|r| {
            let (i, j) = (r.index % ax.count, r.index / ax.count);
            let (x0, x1) = cell_edges(ax, i);
            let (y0, y1) = cell_edges(ay, j);
            let k = LYAPUNOV_BINS
                .iter()
                .position(|(hi, _)| r.lyapunov <= *hi)
                .unwrap_or(LYAPUNOV_BINS.len() - 1);
            (x0, x1, y0, y1, k)
        })
        .collect();
    let (xr, yr) = (
        (cell_edges(ax, 0).0, cell_edges(ax, ax.count - 1).1),
        (cell_edges(ay, 0).0, cell_edges(ay, ay.count - 1).1),
    );
    Figure {
        name: "lyapunov".into(),
        caption,
        size: (1000, 700),
        panels: Vec::new(),
        map: Some(Map {
            frame: Panel {
                title: format!(
                    "largest Lyapunov exponent over ({}, {})",
                    ax.param, ay.param
                ),
                x_label: ax.param.to_string(),
                y_label: ay.param.to_string(),
                x_log: ax.log,
                y_log: ay.log,
                x_range: Some(xr),
                y_range: Some(yr),
                legend_left: true,
                ..Panel::default()
            },
            cells,
            categories: LYAPUNOV_BINS.iter().map(|b| b.1.to_string()).collect(),
        }),
    }
}

/// A drive's frequency-response curve in SI units: peak-to-peak twist \[mrad\] and the largest
/// elastic torque \[N m\] against the disturbance frequency \[Hz\].
pub fn physical_response_figure(r: &crate::periodic::PhysicalResponse) -> Figure {
    let d = &r.drive;
    let folds: Vec<String> = r
        .points
        .iter()
        .filter(|q| q.special == Some(crate::periodic::Special::Fold))
        .map(|q| format!("{:.1} Hz", q.frequency_hz))
        .collect();
    let peak = r
        .points
        .iter()
        .max_by(|a, b| a.twist_peak_to_peak.total_cmp(&b.twist_peak_to_peak));
    Figure {
        name: "physical-frequency-response".into(),
        caption: format!(
            "Frequency response of the drive (J_i = {} kg m², J_o = {} kg m², N = {}, k1 = {} N m/rad, \
             k2 = {} N m/rad³, φ = {} rad, C = {} N m s/rad, T_m = {} N m, T_am = {} N m) against \
             the disturbance frequency, from the reduced model's continuation converted to SI \
             (θ = L x, Ω = ω/T). {} {}",
            d.j_in,
            d.j_out,
            d.ratio,
            d.k1,
            d.k2,
            d.backlash,
            d.c_eq,
            d.t_m,
            d.t_am,
            peak.map_or(String::new(), |q| format!(
                "The largest response, {:.3} mrad peak to peak, is at {:.1} Hz.",
                1e3 * q.twist_peak_to_peak,
                q.frequency_hz
            )),
            if folds.is_empty() {
                "No fold: at this disturbance amplitude the response is single-valued and a \
                 frequency sweep does not jump."
                    .to_string()
            } else {
                format!(
                    "Folds (jumps of a frequency sweep) at {}.",
                    folds.join(", ")
                )
            }
        ),
        size: (1000, 800),
        panels: vec![
            // the SI values of point i are r.points[i] (one per branch point)
            response_panel(
                &r.branch,
                ("peak-to-peak twist [mrad]", "f [Hz]"),
                |i, _| {
                    let q = &r.points[i];
                    (q.frequency_hz, 1e3 * q.twist_peak_to_peak)
                },
            ),
            response_panel(
                &r.branch,
                ("largest elastic torque [N m]", "f [Hz]"),
                |i, _| (r.points[i].frequency_hz, r.points[i].torque_range[1]),
            ),
        ],
        map: None,
    }
}

/// The Lyapunov exponent against the one axis of a sweep.
fn lyapunov_curve(
    ax: &crate::sweep::Axis,
    rows: &[crate::periodic::LyapunovRow],
    caption: String,
) -> Figure {
    let points = rows
        .iter()
        .filter(|r| r.lyapunov.is_finite())
        .map(|r| (r.params.value(ax.param), r.lyapunov))
        .collect();
    Figure {
        name: "lyapunov".into(),
        caption,
        size: (1000, 500),
        panels: vec![Panel {
            title: format!("largest Lyapunov exponent against {}", ax.param),
            x_label: ax.param.to_string(),
            y_label: "λ_max".into(),
            x_log: ax.log,
            series: vec![Series {
                label: String::new(),
                points,
                color: 2,
                style: Style::Line,
            }],
            ..Panel::default()
        }],
        map: None,
    }
}

/// [`frequency_response_figure`] over the default ω range of `p`.
pub fn frequency_response_kind(p: &Params, _study: &mut Study) -> Result<Figure> {
    let b = crate::periodic::frequency_response(
        p,
        None,
        &crate::periodic::ContinuationOptions::default(),
    )?;
    Ok(frequency_response_figure(p, &b))
}

/// [`orbit_diagram_figure`] over ω ∈ [ω_s/2, 1.5 ω_s] (ω_s: the stiffest static frequency, see
/// [`crate::periodic::default_frequency_range`]), the resonance and its bend, 161 values.
pub fn orbit_diagram_kind(p: &Params, _study: &mut Study) -> Result<Figure> {
    // the default range is [ω_s/20, 3 ω_s]
    let ws = crate::periodic::default_frequency_range(p).1 / 3.0;
    let values: Vec<f64> = (0..=160)
        .map(|i| 0.5 * ws + ws * f64::from(i) / 160.0)
        .collect();
    let opts = crate::periodic::DiagramOptions {
        lyapunov: Some(200),
        ..crate::periodic::DiagramOptions::default()
    };
    let mut points = Vec::new();
    crate::periodic::orbit_diagram(p, Param::Omega, &values, &opts, |q| points.push(q))?;
    Ok(orbit_diagram_figure(p, Param::Omega, &points))
}

/// [`lyapunov_figure`] over ω ∈ [ω_s/4, 2ω_s] × δ ∈ [δ/8, 8δ] (log, 32 × 20).
pub fn lyapunov_map_kind(p: &Params, study: &mut Study) -> Result<Figure> {
    let ws = crate::periodic::default_frequency_range(p).1 / 3.0;
    let d = if p.delta > 0.0 { p.delta } else { 1.0 };
    let grid = crate::sweep::Grid::new(
        *p,
        vec![
            Axis {
                param: Param::Omega,
                start: ws / 4.0,
                end: 2.0 * ws,
                count: 32,
                log: true,
            },
            Axis {
                param: Param::Delta,
                start: d / 8.0,
                end: 8.0 * d,
                count: 20,
                log: true,
            },
        ],
    )?;
    let opts = crate::periodic::DiagramOptions {
        discard: 100,
        lyapunov: Some(100),
        ..crate::periodic::DiagramOptions::default()
    };
    let rows = crate::periodic::lyapunov_map(&grid, &opts, study.threads)?;
    Ok(lyapunov_figure(&grid, &rows))
}

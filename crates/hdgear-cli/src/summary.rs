//! Readable (non-JSON) summaries for the terminal.

use hdgear::fast::Analysis;
use std::fmt::Write;

fn num(v: f64) -> String {
    if v.is_infinite() {
        "infinite (a fold)".into()
    } else {
        format!("{v:.6}")
    }
}

/// The readable form of `hdgear analyze`.
pub fn analysis_text(an: &Analysis) -> String {
    let p = &an.params;
    let e = &an.equilibria;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "fast subsystem x'' + x' + {a}x^3 - x^2 + {g}(x - {ep}) = {mu} + {d}a,  a in [{a0}, {a1}]",
        a = p.alpha,
        g = p.gamma,
        ep = p.eps,
        mu = p.mu,
        d = p.delta,
        a0 = an.a_range[0],
        a1 = an.a_range[1]
    );
    let _ = writeln!(
        s,
        "critical gamma 1/(3 alpha) = {:.6}; gamma - critical = {:.6} ({})",
        an.critical_gamma,
        an.gamma_margin,
        an.regime.name()
    );
    let _ = writeln!(
        s,
        "cusp: gamma = {:.6}, a = {:.6}, x = {:.6}",
        an.cusp.gamma, an.cusp.a, an.cusp.x
    );
    let _ = writeln!(
        s,
        "equilibria per a: {}..{}; stable everywhere: {}",
        e.min_count, e.max_count, e.stable_everywhere
    );
    if e.folds.is_empty() {
        let _ = writeln!(s, "folds: none (gamma >= 1/(3 alpha))");
    }
    for f in &e.folds {
        fold_line(&mut s, f);
    }
    let _ = writeln!(
        s,
        "largest |dx/da| on the range: {} at a = {:.6}, x = {:.6}",
        num(e.max_slope.value),
        e.max_slope.a,
        e.max_slope.x
    );
    if let Some(sp) = &an.steepest_point {
        let _ = writeln!(
            s,
            "steepest point of the whole curve: x = 1/(3 alpha) = {:.6}, a = {:.6}, slope = {:.6}",
            sp.x, sp.a, sp.value
        );
    }
    if let Some(s0) = e.slope_at_a0 {
        let _ = writeln!(s, "dx/da at a = 0: {s0:.6}");
    }
    let _ = writeln!(s, "Hopf bifurcation possible: no ({})", e.hopf_reason);
    let r = &e.slowest_relaxation;
    let _ = writeln!(
        s,
        "slowest relaxation on the traversed path ({}): rate {:.4e} at a = {:.6}, x = {:.6}; \
         fast-slow for omega <= {:.4e}",
        r.along.name(),
        r.rate,
        r.a,
        r.x,
        hdgear::burst::fast_slow_omega_max(&an.params)
    );
    prediction_text(&mut s, e);
    s
}

/// One fold's line of an analysis, appended to `s`.
fn fold_line(s: &mut String, f: &hdgear::fast::Fold) {
    let outside = if f.in_range {
        ""
    } else {
        " (outside the a-range)"
    };
    let _ = writeln!(s, "fold: a = {:.12}, x = {:.12}{outside}", f.a, f.x);
}

/// The readable analysis of a model's equilibrium curve ([`hdgear::fast::CurveAnalysis`]).
pub fn curve_analysis_text(an: &hdgear::fast::CurveAnalysis) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "fast subsystem (forcing frozen at a), a in [{}, {}]: damping at rest c = {}, focus above \
         g' = c^2/4 = {}",
        an.a_range[0], an.a_range[1], an.damping_at_rest, an.focus_gprime
    );
    let _ = writeln!(s, "equilibria per a: {}..{}", an.min_count, an.max_count);
    if an.folds.is_empty() {
        let _ = writeln!(s, "folds: none (the static torque rises monotonically)");
    }
    for f in &an.folds {
        fold_line(&mut s, f);
    }
    let r = &an.slowest_relaxation;
    let _ = writeln!(
        s,
        "slowest relaxation on the traversed path ({}): rate {:.4e} at a = {:.6}, x = {:.6}",
        r.along.name(),
        r.rate,
        r.a,
        r.x
    );
    let _ = writeln!(
        s,
        "largest equilibrium speed |dx*/dtau| on the settled branch: {}; first-order lag {}",
        num(an.max_equilibrium_speed),
        num(an.max_first_order_lag)
    );
    s
}

/// The prediction and the spiking and quiescent areas, appended to `s`.
fn prediction_text(s: &mut String, e: &hdgear::fast::EquilibriaSummary) {
    let c = &e.prediction;
    if c.fold_in_range {
        let _ = writeln!(
            *s,
            "prediction: bursting (both folds lie in a in [-1, 1]: jumps at every omega)"
        );
    } else {
        if c.folds_in_range == 1 {
            let _ = writeln!(
                *s,
                "one fold lies in a in [-1, 1]: the state jumps at most once, in the transient, \
                 onto the branch that spans the range, and stays there"
            );
        }
        let _ = writeln!(
            *s,
            "prediction: {} (kappa = rate of change of the equilibrium's speed on the focus part = {:.4} at a = {:.6}; \
             threshold {}); predicted boundary omega = {:.4e}{}",
            if c.bursting { "bursting" } else { "no bursts" },
            c.forcing_rate,
            c.at_a,
            c.threshold,
            c.omega_boundary,
            e.predicted_gamma_boundary
                .map_or(String::new(), |g| format!(", gamma = {g:.4}"))
        );
    }
    if let Some(cp) = c.cusp {
        let _ = writeln!(
            *s,
            "passage near the cusp: a node part about the inflection (g' down to {:.4} < 1/4) at \
             a = {:.6}; ramp rate s = {:.4e} against the normal form's threshold {:.4e}: {}",
            cp.gprime_min,
            cp.at_a,
            cp.ramp_rate,
            cp.threshold,
            if cp.rings() { "rings" } else { "no ringing" }
        );
    } else if let Some(g) = c.node_min_gprime {
        let _ = writeln!(
            *s,
            "caveat: the branch passes a node part (g' down to {g:.4} < 1/4) away from the \
             inflection, whose excitation kappa does not see: the predicted omega boundary can be \
             too high (simulate to be sure: analyze --simulated-boundaries)"
        );
    }
    if e.spiking_areas.is_empty() {
        let _ = writeln!(
            *s,
            "spiking areas: none (the state follows the equilibrium everywhere)"
        );
    }
    for i in &e.spiking_areas {
        let _ = writeln!(*s, "spiking area: a in [{:.6}, {:.6}]", i.a_min, i.a_max);
    }
    for i in &e.quiescent_areas {
        let _ = writeln!(*s, "quiescent area: a in [{:.6}, {:.6}]", i.a_min, i.a_max);
    }
}

/// The readable form of a measured response and its classification.
pub fn response_text(r: &hdgear::burst::Response, c: &hdgear::burst::Classification) -> String {
    let mut s = String::new();
    let rate = r.rates.bursts_per_period.map_or_else(
        || "continuous fast motion (no separate bursts)".to_string(),
        |b| format!("{b} bursts per slow period"),
    );
    let _ = writeln!(
        s,
        "response (window t in [{:.1}, {:.1}]): {rate}, {:.2} spikes per burst, \
         burst amplitude {:.4}, peak |x'| {:.4}, quiescent {:.1} time units ({:.1} % of the time), \
         max |x - x*| {:.4}",
        r.window_start,
        r.window_end,
        r.rates.spikes_per_burst,
        r.rates.burst_amplitude,
        r.rates.peak_abs_xdot,
        r.rates.quiescent_duration,
        100.0 * r.rates.quiescent_fraction,
        r.rates.max_tracking_error
    );
    let g = &r.signatures;
    let yes = |b: bool| if b { "yes" } else { "no" };
    let _ = writeln!(
        s,
        "signatures: jump {} ({} per period), overshoot {} (largest lead {:.3e} X), ringing {} \
         (largest swing {:.3e} omega X)",
        yes(g.jump),
        g.jumps_per_period,
        yes(g.overshoot),
        g.max_overshoot,
        yes(g.ringing),
        g.max_ringing_swing
    );
    let m = &r.measures;
    let _ = writeln!(
        s,
        "measures: peak |x'| / (omega max|dx*/da|) = {:.4}, lag / first-order adiabatic lag = {:.4}, \
         lag / X = {:.4}",
        m.speed_ratio, m.lag_ratio, m.relative_lag
    );
    let _ = writeln!(
        s,
        "classification: {} ({}), mode {}, mechanism {}{}",
        if c.bursting {
            "bursting"
        } else {
            "not bursting"
        },
        c.verdict.name(),
        c.mode.name(),
        c.mechanism.name(),
        if c.fast_slow_domain {
            ""
        } else {
            "; outside the fast-slow domain (omega is not slow against the fast subsystem)"
        }
    );
    s
}

/// A drive's values on one line (with its newline), as `hdgear physical` and `hdgear control`
/// print them.
pub fn drive_line(d: &hdgear::physical::PhysicalParams) -> String {
    format!(
        "drive: J_in = {:e} kg m^2, J_out = {:e} kg m^2, N = {}, k1 = {:e} N m/rad, k2 = {:e} N m/rad^3, \
         backlash = {:e} rad, C = {:e} N m s/rad, T_m = {} N m, T_am = {} N m, Omega = {} rad/s\n",
        d.j_in, d.j_out, d.ratio, d.k1, d.k2, d.backlash, d.c_eq, d.t_m, d.t_am, d.omega
    )
}

/// The readable form of `hdgear physical` (from its JSON document).
pub fn physical_text(doc: &hdgear::physical::design::DriveSummary) -> String {
    let mut s = drive_line(&doc.drive);
    let c = &doc.catalogue;
    let _ = writeln!(
        s,
        "catalogue {}: k1, k2 fitted up to T = {} N m (twist error {:.1} % at T1, {:.1} % at T2)",
        c.name,
        c.fit.t_fit,
        100.0 * c.fit.twist_error_t1,
        100.0 * c.fit.twist_error_t2
    );
    for x in &c.assumptions {
        let _ = writeln!(s, "  assumed: {x}");
    }
    let r = &doc.reduced;
    let _ = writeln!(
        s,
        "J_eq = {:.6e} kg m^2, time scale T = {:.6e} s, length scale L = {:.6e} rad",
        doc.j_eq, doc.time_scale, doc.length_scale
    );
    let _ = writeln!(
        s,
        "reduced: alpha = {:.6}, gamma = {:.6}, eps = {:.6}, mu = {:.6}, delta = {:.6}, omega = {:.6} (alpha*eps = {:.6})",
        r.alpha, r.gamma, r.eps, r.mu, r.delta, r.omega, doc.alpha_eps
    );
    let _ = writeln!(
        s,
        "critical gamma 1/(3 alpha) = {:.6}, gamma margin = {:.6}",
        doc.critical_gamma, doc.gamma_margin
    );
    let _ = writeln!(
        s,
        "damping ratio zeta = C/(2 sqrt(k1 J_eq)) = {:.4} (gamma = 1/(4 zeta^2)); 3*alpha*gamma = \
         3 k1/(k2 phi^2) = {:.4}: {}",
        doc.zeta,
        doc.three_alpha_gamma,
        if doc.three_alpha_gamma < 1.0 {
            "the fast subsystem has folds"
        } else {
            "no folds, whatever the damping"
        }
    );
    let pr = &doc.predicted;
    let _ = writeln!(
        s,
        "response: {} (signature {}, mode {}, mechanism {}){}",
        if pr.judgement.bursting {
            "bursting"
        } else {
            "not bursting"
        },
        pr.judgement.label(),
        pr.mode.map_or("-", |m| m.name()),
        pr.mechanism.map_or("-", |m| m.name()),
        match pr.judgement.basis {
            hdgear::physical::design::Basis::Simulation => "",
            hdgear::physical::design::Basis::Prediction =>
                "; not simulated (reduced omega too small): predicted from the equilibrium curve",
        }
    );
    s
}

/// The readable form of the design check.
pub fn design_text(c: &hdgear::physical::design::DesignCheck) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "the drive {} (decided by {}); signature {}, mode {}, mechanism {}{}",
        if c.judgement.bursting {
            "bursts"
        } else {
            "does not burst"
        },
        match c.judgement.basis {
            hdgear::physical::design::Basis::Simulation => "simulation",
            hdgear::physical::design::Basis::Prediction => "prediction from the equilibrium curve",
        },
        c.judgement.verdict.map_or("-", |v| v.name()),
        c.mode.map_or("-", |m| m.name()),
        c.mechanism.map_or("-", |m| m.name()),
        if c.judgement.fast_slow_domain {
            ""
        } else {
            " (outside the fast-slow domain)"
        }
    );
    let _ = writeln!(
        s,
        "reduced gamma = {:.6} (margin to the fold regime {:.6}); predicted: {} (kappa = {:.4}, threshold {})",
        c.reduced.params.gamma,
        c.gamma_margin,
        if c.prediction.bursting {
            "bursting"
        } else {
            "no bursts"
        },
        c.prediction.forcing_rate,
        c.prediction.threshold
    );
    let _ = writeln!(
        s,
        "steepest point of the equilibrium curve at a = {:.4} (the slow variable covers [-1, 1]; distance {:.4})",
        c.steepest_point_a, c.distance_in_a
    );
    margin_lines(&mut s, &c.margins, c.judgement.bursting);
    s
}

/// One line per margin: the change that crosses the bursting boundary, with the verdicts just
/// inside and just outside, or why there is none (the drive bursting now or not).
pub fn margin_lines<P: std::fmt::Display>(
    s: &mut String,
    margins: &[hdgear::physical::design::Margin<P>],
    bursting: bool,
) {
    for m in margins {
        match (m.factor, m.boundary_value) {
            (Some(f), Some(v)) => {
                let side = |x: &Option<hdgear::physical::design::BracketEnd>| {
                    x.map_or("-".into(), |x| x.to_string())
                };
                let _ = writeln!(
                    s,
                    "  {:<9} {:.6e} -> {:.6e} ({:+.1} %, x{:.4}) {}; inside {}, outside {}",
                    m.parameter,
                    m.current,
                    v,
                    100.0 * (f - 1.0),
                    f,
                    m.effect,
                    side(&m.inside),
                    side(&m.outside)
                );
            }
            _ => {
                let why = m.refused.clone().unwrap_or_else(|| {
                    format!(
                        "no single change within x1/64..x64 {}",
                        if bursting {
                            "stops the bursts"
                        } else {
                            "makes it burst"
                        }
                    )
                });
                let _ = writeln!(s, "  {:<9} {:.6e}: {why}", m.parameter, m.current);
            }
        }
    }
}

/// `, supercritical (c = …)` at a period doubling with its normal-form coefficient, empty
/// elsewhere: what a summary line of a branch's special point adds.
pub fn criticality(q: &hdgear::periodic::OrbitPoint) -> String {
    match (q.flip_coefficient, q.criticality()) {
        (Some(c), Some(k)) => format!(", {} (c = {c:.3e})", k.name()),
        _ => String::new(),
    }
}

/// The special points of a response, one line each (`line` writes what follows the name), or
/// `none` when there are none.
pub fn specials<T>(
    points: impl IntoIterator<Item = T>,
    name: impl Fn(&T) -> &'static str,
    line: impl Fn(&T) -> String,
    none: &str,
) -> anyhow::Result<()> {
    let mut any = false;
    for q in points {
        any = true;
        crate::sink::outln!("  {:<16} {}", name(&q), line(&q));
    }
    if !any {
        crate::sink::outln!("  {none}");
    }
    Ok(())
}

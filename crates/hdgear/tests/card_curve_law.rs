//! The verdict with the catalogue's own piecewise-linear stiffness law
//! (`hdgear::physical::curve_law`): the reduced law returns every card's catalogue rows, the two
//! integrators agree on it, and its bursts are the knees'.

use hdgear::burst::BurstOptions;
use hdgear::integrate::Method;
use hdgear::physical::PhysicalParams;
use hdgear::physical::card::{Card, builtin, builtin_card};
use hdgear::physical::catalogue::assemble;
use hdgear::physical::curve_law::{self, CatalogueLaw};

/// The drive `check_card` builds from `c` with the assumed damping.
fn drive(c: &Card) -> PhysicalParams {
    assemble(c, None, None).unwrap().drive
}

/// For every built-in card, the reduced law back in N m at twist θ + φ equals the catalogue's
/// torque at θ, computed here from the card's own T1, T2, K1, K2, K3 (K2 beyond T2 without a K3):
/// at both knees (to 1e-12: the knees are where the rows are defined) and on each segment.
#[test]
fn the_reduced_law_returns_every_cards_catalogue_rows() {
    let f = builtin();
    for c in &f.card {
        let s = &c.stiffness;
        let (t1, t2, k1, k2) = (s.t1.unwrap(), s.t2.unwrap(), s.k1.unwrap(), s.k2.unwrap());
        let k3 = s.k3.unwrap_or(k2);
        let (th1, th2) = (t1 / k1, t1 / k1 + (t2 - t1) / k2);
        let catalogue = |th: f64| {
            if th <= th1 {
                k1 * th
            } else if th <= th2 {
                t1 + k2 * (th - th1)
            } else {
                t2 + k3 * (th - th2)
            }
        };
        let d = drive(c);
        let r = d.reduce().unwrap();
        let law = curve_law::term(c, &d, &r, 0.0).unwrap();
        let unit = r.torque_unit();
        let back = |th: f64| law.torque((th + d.backlash) / r.length_scale, 0.0, 0.0) * unit;
        for th in [th1, th2] {
            let rel = (back(th) - catalogue(th)).abs() / catalogue(th);
            assert!(rel < 1e-12, "{}: θ = {th}: {rel:e}", c.name);
        }
        for th in [0.5 * th1, 0.5 * (th1 + th2), 1.5 * th2] {
            let rel = (back(th) - catalogue(th)).abs() / catalogue(th);
            assert!(rel < 1e-9, "{}: θ = {th}: {rel:e}", c.name);
        }
        // and the law is odd about the offset: the other side of the backlash is the mirror
        let (lo, hi) = (back(-th1), back(th1));
        assert!((lo + hi).abs() < 1e-9 * hi, "{}", c.name);
    }
}

fn checked(c: &Card, d: &PhysicalParams, method: Method) -> CatalogueLaw {
    let mut o = BurstOptions::default();
    o.tol.method = method;
    curve_law::check(c, d, 0.0, &o).unwrap()
}

/// CSF-20-50 at its card's loads (T_m = T1, crossing the first knee both ways): the Taylor steps,
/// which end on the kinks, and DOP853, whose error control shortens its steps about them, give
/// the same verdict and the same sizes (1e-6 relative: both at their default 1e-10).
#[test]
fn taylor_and_dop853_agree_on_the_catalogue_law() {
    let c = builtin_card("CSF-20-50").unwrap();
    let d = drive(c);
    let (a, b) = (
        checked(c, &d, Method::Taylor),
        checked(c, &d, Method::Dop853),
    );
    let (oa, ob) = (a.outcome.unwrap(), b.outcome.unwrap());
    assert_eq!(oa, ob);
    assert!(a.knee_residual < 1e-12);
    let (ga, gb) = (a.signatures.unwrap(), b.signatures.unwrap());
    for (x, y) in [
        (ga.max_overshoot, gb.max_overshoot),
        (ga.max_ringing_swing, gb.max_ringing_swing),
    ] {
        assert!((x - y).abs() <= 1e-6 * x.abs().max(1e-12), "{x} vs {y}");
    }
    assert_eq!(ga.ringing_bursts_per_period, gb.ringing_bursts_per_period);
}

/// The bursts are the knees': the same drive and loads ring where the load crosses a knee
/// (twice a period here), not where the knees are removed (every slope K1: a linear law, tracked
/// adiabatically), nor where the load stays below the first knee.
#[test]
fn the_catalogue_laws_bursts_are_its_knees() {
    let c = builtin_card("CSF-20-50").unwrap();
    let d = drive(c);
    let t1 = c.stiffness.t1.unwrap();
    let with = checked(c, &d, Method::Taylor);
    assert!(with.outcome.unwrap().judgement.bursting);
    assert_eq!(with.signatures.unwrap().ringing_bursts_per_period, 2.0);

    let mut linear = c.clone();
    linear.stiffness.k2 = linear.stiffness.k1;
    linear.stiffness.k3 = linear.stiffness.k1;
    let without = checked(&linear, &d, Method::Taylor);
    assert!(!without.outcome.unwrap().judgement.bursting);

    // the load T_m ± T_am within 0.4 … 0.6 T1: on the first segment throughout
    let below = PhysicalParams {
        t_m: 0.5 * t1,
        t_am: 0.1 * t1,
        ..d
    };
    let low = checked(c, &below, Method::Taylor);
    assert!(!low.outcome.unwrap().judgement.bursting);
}

/// Every built-in card gets a verdict with its catalogue law, with the damping from its
/// hysteresis loss and with the assumed 10 %: the assumed mean load T1 puts many a start on the
/// first knee to a rounding error, on either side.
#[test]
fn every_builtin_card_is_judged_with_its_catalogue_law() {
    let f = builtin();
    for c in &f.card {
        let from_loss = hdgear::physical::check::loss_damping(c, &f.sources).map(|l| l.zeta);
        for zeta in [from_loss, None] {
            let d = assemble(c, None, zeta).unwrap().drive;
            let law = curve_law::check(c, &d, 0.0, &BurstOptions::default())
                .unwrap_or_else(|e| panic!("{} (zeta {zeta:?}): {e}", c.name));
            assert!(law.outcome.is_some(), "{} (zeta {zeta:?})", c.name);
            assert!(law.knee_residual < 1e-12, "{}", c.name);
        }
    }
}

/// The load map's catalogue column is, at every point, the verdict `curve_law::check` gives on
/// that point's drive; on CSG-20-50 (a card whose fit never bursts at these loads) the knees
/// make it burst.
#[test]
fn the_load_map_carries_the_catalogue_verdict() {
    use hdgear::physical::check::{DampingChoice, MapGrid, check_card, load_map};
    let c = builtin_card("CSG-20-50").unwrap();
    let sources = &builtin().sources;
    let opts = BurstOptions::default();
    let grid = MapGrid {
        t_am_max: 33.0,
        amplitudes: 2,
        hz: (0.1, 1.0),
        frequencies: 2,
        coarse: 1,
    };
    let choice = DampingChoice::HysteresisLoss;
    let map = load_map(c, sources, choice, &grid, &opts, Some(0.0)).unwrap();
    let drive = check_card(c, sources, choice, 0.0, &opts)
        .unwrap()
        .summary
        .drive;
    for p in &map {
        let d = PhysicalParams {
            t_am: p.t_am,
            omega: std::f64::consts::TAU * p.frequency_hz,
            ..drive
        };
        let law = curve_law::check(c, &d, 0.0, &opts).unwrap();
        assert_eq!(p.catalogue, law.outcome.map(|o| o.judgement), "{p:?}");
        assert!(!p.judgement.bursting, "{p:?}");
        assert!(p.catalogue.unwrap().bursting, "{p:?}");
    }
}

/// A vanishing rounding is the corner: CSF-20-50 (its card's loads, assumed damping) with its
/// knees rounded over 1e-6, 1e-9 and 1e-12 of θ(T₁) gives the corner's verdict and ringing swing.
/// The load passes such a rounding in 1.7e-4 torsional periods or less (the passage of
/// `rounded_knees_ring_less_than_the_catalogues_corners`, which halves the swing at 0.17
/// periods): a change of the swing of that order, held here to 1 %. Two things make this run:
/// the rounding's square (x_r² down to 1e-24 of θ(T₁)²) lies far below the rounding errors of x²
/// at the knee, so the rows are formed from the distance to the knee itself; and far from a knee
/// the rows show no trace of it, so each step stays inside the hyperbola's radius of convergence
/// instead of stepping over the knee.
#[test]
fn a_vanishing_knee_rounding_is_the_corner() {
    let c = builtin_card("CSF-20-50").unwrap();
    let d = drive(c);
    let o = BurstOptions::default();
    let corner = curve_law::check(c, &d, 0.0, &o).unwrap();
    let corner_sig = corner.signatures.unwrap();
    for rounding in [1e-6, 1e-9, 1e-12] {
        let law = curve_law::check(c, &d, rounding, &o)
            .unwrap_or_else(|e| panic!("rounding {rounding}: {e}"));
        let sig = law.signatures.unwrap();
        println!("rounding {rounding:e}: {sig:?}");
        assert_eq!(
            law.outcome.map(|o| o.judgement.bursting),
            corner.outcome.map(|o| o.judgement.bursting),
            "{rounding}"
        );
        let change = (sig.max_ringing_swing / corner_sig.max_ringing_swing - 1.0).abs();
        assert!(change < 0.01, "{rounding}: {sig:?} against {corner_sig:?}");
    }
}

/// A rounded knee rings less: CSF-20-50 (its card's loads, assumed damping) judged with its knees
/// rounded over a growing fraction of θ(T₁). The load crosses the first knee at x' ≈ δω/k₁ (in
/// the reduced units), so it takes x_r·k₁/(δω) to pass a rounding x_r. The corner overshoots and
/// rings; as that passage lengthens towards a torsional period 2π/√k₁ the ringing swing falls
/// (here tenfold by half a period), and a rounding the load takes several periods to pass leaves
/// no burst, the smooth fit's verdict. A rounding outside 0 to 1 is refused, naming it.
#[test]
fn rounded_knees_ring_less_than_the_catalogues_corners() {
    let c = builtin_card("CSF-20-50").unwrap();
    let d = drive(c);
    let o = BurstOptions::default();
    let judged = |rounding: f64| {
        let law = curve_law::check(c, &d, rounding, &o).unwrap();
        assert_eq!(law.rounding, rounding);
        (
            law.outcome.unwrap().judgement.bursting,
            law.signatures.unwrap(),
            law.reduced,
        )
    };
    let (corner_bursts, corner, reduced) = judged(0.0);
    assert!(
        corner_bursts && corner.overshoot && corner.ringing,
        "{corner:?}"
    );
    let r = d.reduce().unwrap();
    let (k1, x1) = (reduced[0], reduced[3]);
    let crossing_speed = r.params.delta * r.params.omega / k1;
    let period = std::f64::consts::TAU / k1.sqrt();
    let mut last = corner.max_ringing_swing;
    for rounding in [0.001, 0.003, 0.01, 0.03, 0.1] {
        let (bursts, sig, reduced) = judged(rounding);
        assert!((reduced[6] - rounding * x1).abs() <= 1e-15 * x1);
        let passage = rounding * x1 / crossing_speed / period;
        println!("rounding {rounding}: passage {passage:.2} torsional periods, {bursts}, {sig:?}");
        // the rounding removes the corner's overshoot at once; the ringing fades with it
        assert!(
            sig.max_overshoot < corner.max_overshoot,
            "{rounding}: {sig:?}"
        );
        assert!(
            sig.max_ringing_swing < last || sig.max_ringing_swing == 0.0,
            "{rounding}: {sig:?} after a swing of {last:e}"
        );
        last = sig.max_ringing_swing;
        if passage > 0.5 {
            assert!(
                sig.max_ringing_swing < 0.1 * corner.max_ringing_swing,
                "{rounding}: {sig:?}"
            );
        }
        if passage > 3.0 {
            assert!(!bursts, "{rounding}: passage {passage} periods: {sig:?}");
        }
    }
    for bad in [-0.1, 1.5, f64::NAN] {
        let e = curve_law::check(c, &d, bad, &o).unwrap_err().to_string();
        assert!(e.contains("knee_rounding"), "{bad}: {e}");
    }
}

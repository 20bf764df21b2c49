//! Identification (`hdgear::fit`): the truth recovered from noise-free data of each kind and law
//! family, derivatives against finite differences written here, the Dahl loop against its closed
//! form, intervals that cover over noisy sets, and identifiability warnings where the data
//! cannot tell parameters apart.
//!
//! **Why one file.** The tests of one capability, identification, in one module of the test binary.

use hdgear::fit::{Data, DataKind, Fit, FitLaw, FitOptions, FitWarning, Free, fit, predict};
use hdgear::model::terms::AnyTerm;

fn law(terms: &[(&str, &[f64])]) -> FitLaw {
    FitLaw::new(
        terms
            .iter()
            .map(|(k, v)| AnyTerm::new(k, v).unwrap())
            .collect(),
    )
    .unwrap()
}

/// A catalogue-like curve in SI units (a CSG-20 drive's: N m/rad, rad).
const SPRING: [f64; 7] = [1.3e4, 1.7e4, 2.5e4, 5.4e-4, 1.06e-3, 0.0, 0.0];

/// The free parameters of a curve with Bouc–Wen hysteresis (A, n, ρ held).
const BOUC_WEN_DRIVE: [&str; 6] = [
    "k1=1e3:1e5",
    "k2=1e3:1e5",
    "k3=1e3:1e5",
    "kh=1e2:1e5",
    "betah=10:1e5",
    "gammah=-1e4:1e4",
];

fn frees(list: &[&str]) -> Vec<Free> {
    list.iter().map(|f| f.parse().unwrap()).collect()
}

/// Speeds of a sweep: both directions, log-spaced from 1e-3 to 2 rad/s.
fn speeds() -> Vec<f64> {
    let up: Vec<f64> = (0..30)
        .map(|i| 1e-3 * 2000f64.powf(i as f64 / 29.0))
        .collect();
    up.iter()
        .map(|v| -v)
        .rev()
        .chain(up.iter().copied())
        .collect()
}

/// A lost-motion test's twist path: from 0 up to +A, down to −A and up to +A, 60 points a leg.
fn twist_path(amplitude: f64) -> Vec<f64> {
    let leg = |a: f64, b: f64| (1..=60).map(move |i| a + (b - a) * i as f64 / 60.0);
    std::iter::once(0.0)
        .chain(leg(0.0, amplitude))
        .chain(leg(amplitude, -amplitude))
        .chain(leg(-amplitude, amplitude))
        .collect()
}

/// Normal deviates from a fixed seed (SplitMix64 and Box–Muller), independent of the library's.
struct Noise(u64);
impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 + 0.5 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// Fits `free` of `start` to what `truth` predicts on `x`, plus noise of `sd`.
fn fit_synthetic(
    (truth, start, kind): (&FitLaw, &FitLaw, DataKind),
    x: &[f64],
    free: &[Free],
    sd: f64,
    noise: &mut Noise,
    options: &FitOptions,
) -> Fit {
    let mut tau = predict(truth, kind, x, options.repeat).unwrap();
    tau.iter_mut().for_each(|t| *t += sd * noise.normal());
    let (data, warnings) = Data::new(kind, x.to_vec(), tau, None).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    fit(start, &data, free, options).unwrap()
}

fn assert_recovered(f: &Fit, truth: &FitLaw) {
    for e in &f.estimates {
        let want = truth.get(&truth.param(&e.name).unwrap());
        assert!(
            (e.value - want).abs() <= 1e-6 * want.abs(),
            "{}: {} against {want} ({:?})",
            e.name,
            e.value,
            f.warnings
        );
    }
}

#[test]
fn friction_sweeps_return_the_truth() {
    let none = &mut Noise(0);
    let opts = FitOptions {
        profile: false,
        ..FitOptions::default()
    };
    // sticking Coulomb–Stribeck–viscous, the regularised Stribeck law and LuGre's steady curve
    let cases: [(FitLaw, FitLaw, Vec<Free>); 3] = [
        (
            law(&[("coulomb", &[0.5, 0.8, 0.02, 0.3])]),
            law(&[("coulomb", &[1.0, 1.0, 0.1, 0.0])]),
            frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:2"]),
        ),
        (
            law(&[("stribeck", &[0.33, 0.69, 0.0097, 0.48, 1e-4])]),
            law(&[("stribeck", &[1.0, 1.0, 0.1, 0.0, 1e-4])]),
            frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:2"]),
        ),
        (
            law(&[("lugre", &[0.4, 0.7, 0.05, 1e4, 30.0, 0.2])]),
            law(&[("lugre", &[1.0, 1.0, 0.1, 1e4, 30.0, 0.0])]),
            frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "sigma2=0:2"]),
        ),
    ];
    for (truth, start, free) in cases {
        let f = fit_synthetic(
            (&truth, &start, DataKind::Friction),
            &speeds(),
            &free,
            0.0,
            none,
            &opts,
        );
        assert_recovered(&f, &truth);
        assert!(f.converged());
    }
}

#[test]
fn loops_return_the_truth() {
    let none = &mut Noise(0);
    let opts = FitOptions {
        profile: false,
        starts: 8,
        ..FitOptions::default()
    };
    let cases: [(FitLaw, FitLaw, Vec<Free>); 2] = [
        (
            // a catalogue curve with Bouc–Wen hysteresis (A = 1, n = 1, ρ = 0 fixed: the
            // law's scale and its linear part would otherwise repeat the curve's)
            law(&[
                ("piecewise", &SPRING),
                ("boucwen", &[1.0e4, 0.0, 1.0, 3000.0, 2000.0, 1.0]),
            ]),
            law(&[
                ("piecewise", &[1e4, 1e4, 1e4, 5.4e-4, 1.06e-3, 0.0, 0.0]),
                ("boucwen", &[5e3, 0.0, 1.0, 1000.0, 1000.0, 1.0]),
            ]),
            frees(&BOUC_WEN_DRIVE),
        ),
        (
            law(&[("piecewise", &SPRING), ("dahl", &[2e4, 1.5, 1.0])]),
            law(&[
                ("piecewise", &[1e4, 1e4, 1e4, 5.4e-4, 1.06e-3, 0.0, 0.0]),
                ("dahl", &[1e4, 1.0, 1.0]),
            ]),
            frees(&[
                "k1=1e3:1e5",
                "k2=1e3:1e5",
                "k3=1e3:1e5",
                "sigmad=1e2:1e6",
                "tcd=0.01:10",
            ]),
        ),
    ];
    for (truth, start, free) in cases {
        let f = fit_synthetic(
            (&truth, &start, DataKind::Loop),
            &twist_path(3e-3),
            &free,
            0.0,
            none,
            &opts,
        );
        assert_recovered(&f, &truth);
    }
}

/// The loop's Dahl torque (exponent 1) against its closed form on each monotone leg:
/// T = sT_c + (T_r − sT_c)·exp(−σ·s·(x − x_r)/T_c) from the reversal (x_r, T_r).
#[test]
fn a_dahl_loop_matches_its_closed_form() {
    let (sigma, tc) = (2e4, 1.5);
    let l = law(&[("dahl", &[sigma, tc, 1.0])]);
    let x = twist_path(3e-4);
    let tau = predict(&l, DataKind::Loop, &x, 0).unwrap();
    let (mut xr, mut tr, mut s) = (0.0, 0.0, 1.0);
    let mut worst = 0.0_f64;
    for i in 1..x.len() {
        let side = (x[i] - x[i - 1]).signum();
        if side != s {
            (xr, tr, s) = (x[i - 1], tau[i - 1], side);
        }
        let exact = s * tc + (tr - s * tc) * (-sigma * s * (x[i] - xr) / tc).exp();
        worst = worst.max((tau[i] - exact).abs());
    }
    assert!(worst < 1e-11 * tc, "worst {worst:e}");
}

/// The fit's Jacobian (forward sensitivities) against central differences of `predict`, on a
/// loop with two states and on LuGre's steady curve.
#[test]
fn sensitivities_match_finite_differences() {
    let cases = [
        (
            law(&[
                (
                    "piecewise",
                    &[1.3e4, 1.7e4, 2.5e4, 5.4e-4, 1.06e-3, 0.0, 1e-5],
                ),
                ("boucwen", &[1e4, 0.1, 1.0, 3000.0, 2000.0, 2.0]),
            ]),
            DataKind::Loop,
            twist_path(3e-3),
            vec!["k2", "x1", "kh", "rho", "betah", "gammah"],
        ),
        (
            law(&[("lugre", &[0.4, 0.7, 0.05, 1e4, 30.0, 0.2])]),
            DataKind::Friction,
            speeds(),
            vec!["fc", "fs", "vst", "sigma2"],
        ),
    ];
    for (l, kind, x, names) in cases {
        let base = predict(&l, kind, &x, 0).unwrap();
        // the fit's Jacobian at the truth: residuals are exactly 0 there, J is reported via a
        // fit that stops at once; read it instead through a one-parameter-at-a-time check
        for name in names {
            let q = l.param(name).unwrap();
            let p = l.get(&q);
            let h = 1e-5 * p.abs();
            let plus = predict(
                &l.with(std::slice::from_ref(&q), &[p + h]).unwrap(),
                kind,
                &x,
                0,
            )
            .unwrap();
            let minus = predict(
                &l.with(std::slice::from_ref(&q), &[p - h]).unwrap(),
                kind,
                &x,
                0,
            )
            .unwrap();
            let jac = hdgear::fit::jacobian(&l, kind, &x, &[name], 0).unwrap();
            let scale = base.iter().fold(0.0_f64, |m, t| m.max(t.abs())) / p.abs();
            for i in 0..x.len() {
                let fd = (plus[i] - minus[i]) / (2.0 * h);
                assert!(
                    (jac[i] - fd).abs() <= 1e-6 * scale,
                    "{name} at point {i}: {} against {fd}",
                    jac[i]
                );
            }
        }
    }
}

/// The share of (set, parameter) pairs whose reported 95 % interval holds the truth, over `sets`
/// data sets with normal noise of 1 % of the largest torque.
fn coverage(
    truth: &FitLaw,
    start: &FitLaw,
    kind: DataKind,
    x: &[f64],
    free: &[Free],
    sets: usize,
    options: &FitOptions,
) -> f64 {
    let scale = predict(truth, kind, x, 0)
        .unwrap()
        .iter()
        .fold(0.0_f64, |m, t| m.max(t.abs()));
    let mut noise = Noise(2026);
    let (mut inside, mut total) = (0, 0);
    for _ in 0..sets {
        let f = fit_synthetic(
            (truth, start, kind),
            x,
            free,
            0.01 * scale,
            &mut noise,
            options,
        );
        for e in &f.estimates {
            let want = truth.get(&truth.param(&e.name).unwrap());
            let [lo, hi] = e
                .interval()
                .unwrap_or_else(|| panic!("{}: no interval ({:?})", e.name, f.warnings));
            inside += usize::from(lo <= want && want <= hi);
            total += 1;
        }
    }
    inside as f64 / total as f64
}

/// One family of the coverage test: name, truth, start, kind, abscissa, free, options.
type Family<'a> = (
    &'a str,
    FitLaw,
    FitLaw,
    DataKind,
    Vec<f64>,
    Vec<Free>,
    &'a FitOptions,
);

/// The families of the coverage test.
fn coverage_families<'a>(sweep: &'a FitOptions, loops: &'a FitOptions) -> Vec<Family<'a>> {
    vec![
        (
            "Stribeck (sticking Coulomb) sweep, profile",
            law(&[("coulomb", &[0.5, 0.8, 0.02, 0.3])]),
            law(&[("coulomb", &[0.6, 0.9, 0.03, 0.2])]),
            DataKind::Friction,
            speeds(),
            frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:2"]),
            sweep,
        ),
        (
            "LuGre sweep, profile",
            law(&[("lugre", &[0.4, 0.7, 0.05, 1e4, 30.0, 0.2])]),
            law(&[("lugre", &[0.5, 0.8, 0.04, 1e4, 30.0, 0.1])]),
            DataKind::Friction,
            speeds(),
            frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "sigma2=0:2"]),
            sweep,
        ),
        (
            "piecewise curve loop, JᵀJ",
            law(&[("piecewise", &SPRING)]),
            law(&[("piecewise", &[1.2e4, 1.8e4, 2.4e4, 5e-4, 1.1e-3, 0.0, 0.0])]),
            DataKind::Loop,
            twist_path(3e-3),
            frees(&[
                "k1=1e3:1e5",
                "k2=1e3:1e5",
                "k3=1e3:1e5",
                "x1=1e-5:1e-2",
                "w2=1e-5:1e-2",
            ]),
            loops,
        ),
        (
            "Bouc–Wen drive loop, JᵀJ",
            law(&[
                ("piecewise", &SPRING),
                ("boucwen", &[1.0e4, 0.0, 1.0, 3000.0, 2000.0, 1.0]),
            ]),
            law(&[
                (
                    "piecewise",
                    &[1.2e4, 1.8e4, 2.4e4, 5.4e-4, 1.06e-3, 0.0, 0.0],
                ),
                ("boucwen", &[0.9e4, 0.0, 1.0, 2800.0, 2200.0, 1.0]),
            ]),
            DataKind::Loop,
            twist_path(3e-3),
            frees(&BOUC_WEN_DRIVE),
            loops,
        ),
    ]
}

/// Over 100 noisy sets per family the 95 % intervals hold the truth 90–99 % of the time (the
/// binomial spread of 400–600 trials at 95 % is ±1 %): profile intervals on the friction sweeps,
/// JᵀJ intervals on the loops (whose profiles cost a minute per family; the sweeps show the two
/// agree where the sum of squares is near quadratic). `--nocapture` prints the table the guide
/// shows.
#[test]
fn intervals_cover_the_truth() {
    let sweep = FitOptions {
        starts: 4,
        ..FitOptions::default()
    };
    let loops = FitOptions {
        starts: 2,
        profile: false,
        ..FitOptions::default()
    };
    let families = coverage_families(&sweep, &loops);
    println!("| family | sets | parameters | coverage of the 95 % interval |\n|---|---|---|---|");
    for (name, truth, start, kind, x, free, options) in families {
        let c = coverage(&truth, &start, kind, &x, &free, 100, options);
        println!("| {name} | 100 | {} | {:.1} % |", free.len(), 100.0 * c);
        assert!((0.90..=0.99).contains(&c), "{name}: coverage {c}");
    }
}

/// LuGre's bristle stiffness and damping do not act at constant speed: a sweep cannot see them,
/// and the fit says so by name. Bouc–Wen's A and k_h repeat one another (with exponent 1, z
/// scaled by c is the law with c·A and k_h/c, β and γ unchanged): the warning names that
/// combination and no other. The spectrum shows the rule's
/// threshold (1e-10 of the largest) is decades from both the seen and the unseen directions.
#[test]
fn undetermined_parameters_are_named() {
    let truth = law(&[("lugre", &[0.4, 0.7, 0.05, 1e4, 30.0, 0.2])]);
    let opts = FitOptions {
        starts: 2,
        profile: false,
        ..FitOptions::default()
    };
    let f = fit_synthetic(
        (&truth, &truth, DataKind::Friction),
        &speeds(),
        &frees(&["fc=0:5", "sigma0=1:1e6", "sigma1=0:1e3"]),
        1e-3,
        &mut Noise(5),
        &opts,
    );
    let named: Vec<&str> = f
        .warnings
        .iter()
        .filter_map(|w| match w {
            FitWarning::Undetermined { combination, .. } => Some(combination.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(named, ["lugre.sigma0", "lugre.sigma1"], "{:?}", f.warnings);
    assert!(f.estimates[0].interval().is_some() && f.estimates[1].interval().is_none());

    let truth = law(&[
        ("piecewise", &SPRING),
        ("boucwen", &[1.0e4, 0.0, 1.0, 3000.0, 2000.0, 1.0]),
    ]);
    let loop_fit = |free: &[&str]| {
        let free = frees(free);
        let case = (&truth, &truth, DataKind::Loop);
        fit_synthetic(case, &twist_path(3e-3), &free, 1e-3, &mut Noise(6), &opts)
    };
    let f = loop_fit(&["kh=1e2:1e5", "ah=0.1:10", "betah=10:1e5", "gammah=-1e4:1e4"]);
    let undetermined = |f: &Fit| -> Vec<String> {
        f.warnings
            .iter()
            .filter(|w| matches!(w, FitWarning::Undetermined { .. }))
            .map(|w| w.to_string())
            .collect()
    };
    let text = undetermined(&f);
    assert_eq!(text.len(), 1, "{text:?}");
    assert!(
        text[0].contains("boucwen.ah")
            && text[0].contains("boucwen.kh")
            && !text[0].contains("betah"),
        "{text:?}"
    );
    let largest = f.spectrum.last().unwrap();
    assert!(f.spectrum[0] < 1e-12 * largest, "{:?}", f.spectrum);
    // without A free every direction is seen, far above the threshold
    let f = loop_fit(&["kh=1e2:1e5", "betah=10:1e5", "gammah=-1e4:1e4"]);
    assert!(
        f.spectrum[0] > 1e-8 * f.spectrum.last().unwrap(),
        "{:?}",
        f.spectrum
    );
    assert!(undetermined(&f).is_empty(), "{:?}", f.warnings);
}

/// A fitted card cites the fit, carries the fitted friction and curve, turns the curve's
/// standard errors into robust's bands, and reads back as a valid card file.
#[test]
fn a_fit_becomes_a_card() {
    let base = hdgear::physical::card::builtin_card("CSG-20-50").unwrap();
    let sources = &hdgear::physical::card::builtin().sources;
    let opts = FitOptions {
        starts: 4,
        ..FitOptions::default()
    };
    let truth = law(&[("coulomb", &[0.5, 0.8, 0.02, 0.3])]);
    let f = fit_synthetic(
        (&truth, &truth, DataKind::Friction),
        &speeds(),
        &frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:2"]),
        5e-3,
        &mut Noise(7),
        &opts,
    );
    let file = hdgear::fit::fitted_card(base, sources, &f).unwrap();
    let card = &file.card[0];
    let friction = card.friction_law().unwrap().unwrap();
    assert_eq!(friction.breakaway, f.estimates[1].value);
    let source = &file.sources[&card.friction.as_ref().unwrap().source];
    assert!(source.cite.contains("coulomb.fs") && source.cite.contains("CRC-32"));
    // the catalogue's stiffness untouched
    assert_eq!(card.stiffness, base.stiffness);

    let truth = law(&[("piecewise", &SPRING)]);
    let free = frees(&["k1=1e3:1e5", "k2=1e3:1e5", "k3=1e3:1e5"]);
    let f = fit_synthetic(
        (&truth, &truth, DataKind::Loop),
        &twist_path(3e-3),
        &free,
        0.05,
        &mut Noise(8),
        &FitOptions {
            profile: false,
            ..opts
        },
    );
    let file = hdgear::fit::fitted_card(base, sources, &f).unwrap();
    let card = &file.card[0];
    assert_eq!(card.stiffness.k2, Some(f.estimates[1].value));
    assert!((card.stiffness.t1.unwrap() - f.estimates[0].value * 5.4e-4).abs() < 1e-9);
    let band = &card.tolerance.as_ref().unwrap().bands["k1"];
    assert_eq!(
        band,
        &format!("normal:{:e}", f.estimates[0].std_error.unwrap())
    );
}

/// Bad data: missing numbers and speed 0 are left out with a warning naming the first line;
/// too few points, a unit the quantity does not take, a missing column, a repeated or unknown
/// parameter and bounds that do not hold the law each refused in a line.
#[test]
fn bad_data_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sweep.csv");
    std::fs::write(
        &path,
        "speed [rpm],torque [N m]\n10,1.0\nnan,2\n0,0.1\n20,1.1\n30,1.2\n-10,-1\n",
    )
    .unwrap();
    let plain = hdgear::fit::Column::default();
    let (data, warnings) = Data::read(&path, DataKind::Friction, &plain, &plain).unwrap();
    assert_eq!(data.len(), 4);
    assert!((data.x[0] - 10.0 * std::f64::consts::PI / 30.0).abs() < 1e-15);
    let text: Vec<String> = warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(text.len(), 2, "{text:?}");
    assert!(
        text[0].contains("line 3") && text[1].contains("line 4"),
        "{text:?}"
    );
    assert_eq!(data.source.crc32.len(), 8);

    let start = law(&[("coulomb", &[0.5, 0.8, 0.02, 0.3])]);
    let err = fit(
        &start,
        &data,
        &frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:2"]),
        &FitOptions::default(),
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("4 usable points for 4 free parameters"),
        "{err}"
    );
    let err = fit(
        &start,
        &data,
        &frees(&["fc=0:5", "coulomb.fc=0:5"]),
        &FitOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("given twice"), "{err}");
    let err = fit(&start, &data, &frees(&["f_c=0:5"]), &FitOptions::default()).unwrap_err();
    assert!(err.to_string().contains("coulomb.fc"), "{err}");
    assert!("fc=5:0".parse::<Free>().is_err() && "fc".parse::<Free>().is_err());

    std::fs::write(&path, "speed [furlong/s],torque [N m]\n1,1\n").unwrap();
    let err = Data::read(&path, DataKind::Friction, &plain, &plain).unwrap_err();
    assert!(
        err.to_string().contains("furlong/s") && err.to_string().contains("rpm"),
        "{err}"
    );
    std::fs::write(&path, "v,torque [N m]\n1,1\n").unwrap();
    let err = Data::read(&path, DataKind::Friction, &plain, &plain).unwrap_err();
    assert!(err.to_string().contains("no column speed"), "{err}");
    std::fs::write(&path, "speed,torque [N m]\n1,1\n").unwrap();
    let err = Data::read(&path, DataKind::Friction, &plain, &plain).unwrap_err();
    assert!(
        err.to_string().contains("give its unit (speed=rad/s)"),
        "{err}"
    );

    // a rate-dependent law on a quasi-static loop is refused by name
    let (data, _) = Data::new(DataKind::Loop, twist_path(1e-3), vec![0.0; 181], None).unwrap();
    let lugre = law(&[("lugre", &[0.4, 0.7, 0.05, 1e4, 30.0, 0.2])]);
    let err = fit(&lugre, &data, &frees(&["fc=0:1"]), &FitOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("lugre") && err.to_string().contains("friction sweep"),
        "{err}"
    );
}

/// The ergoCub humanoid's published joint friction (Sorrentino et al. 2024), simulated as a
/// speed sweep and fitted back from a start far off: each value returned to 1e-6.
#[test]
fn published_ergocub_laws_are_fitted_back() {
    let joints = hdgear::fit::ergocub();
    assert_eq!(joints.len(), 6);
    let start = law(&[("coulomb", &[1.0, 1.0, 0.1, 0.0])]);
    let free = frees(&["fc=0:5", "fs=0:5", "vst=1e-4:1", "cv=0:5"]);
    let opts = FitOptions {
        profile: false,
        ..FitOptions::default()
    };
    for j in joints {
        let f = fit_synthetic(
            (&j.law, &start, DataKind::Friction),
            &speeds(),
            &free,
            0.0,
            &mut Noise(0),
            &opts,
        );
        assert_recovered(&f, &j.law);
    }
}

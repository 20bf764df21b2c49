//! The drive stepped by a host (`physical::cosim`) and the FMU instance around it
//! (`physical::fmu`): against the one-run simulation, a closed form, the momentum balance and
//! FMI's call-order rules.

use hdgear::integrate::Options;
use hdgear::physical::PhysicalParams;
use hdgear::physical::cosim::CoSimulation;
use hdgear::physical::fmu::{FmuDrive, Instance, Phase, Role};
use hdgear::physical::model::{Bearings, Physical};
use hdgear::physical::simulate::simulate_drive;

/// A drive with every law of the two-inertia model: cubic stiffness with backlash, the mean
/// torque and the disturbance, Stribeck friction at the output bearing.
fn loaded() -> Physical {
    let d = PhysicalParams {
        j_in: 1e-4,
        j_out: 1.0,
        ratio: 50.0,
        k1: 2e3,
        k2: 1e9,
        backlash: 1e-3,
        c_eq: 5.0,
        t_m: 1.0,
        t_am: 0.5,
        omega: 20.0,
    };
    let law = Bearings::parse_law("output", "stribeck:fc=0.3,fs=0.5,vst=0.05,cv=0.01,vr=1e-3");
    Physical::with_bearings(d, Bearings::new(Some(law.unwrap()), None).unwrap())
}

/// The linear drive of `loaded` (no cubic, no backlash, no load of its own): its twist under
/// constant outside torques has a closed form.
fn linear() -> Physical {
    let d = PhysicalParams {
        k2: 0.0,
        backlash: 0.0,
        t_m: 0.0,
        t_am: 0.0,
        ..*loaded().drive()
    };
    Physical::new(d)
}

fn tight() -> Options {
    Options {
        rtol: 1e-12,
        atol: 1e-12,
        ..Options::default()
    }
}

/// Largest difference of each column over that column's range.
fn worst(a: &[[f64; 4]], b: &[[f64; 4]]) -> f64 {
    let mut out: f64 = 0.0;
    for c in 0..4 {
        let (lo, hi) = a
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), r| (l.min(r[c]), h.max(r[c])));
        let range = (hi - lo).max(f64::MIN_POSITIVE);
        for (p, q) in a.iter().zip(b) {
            out = out.max((p[c] - q[c]).abs() / range);
        }
    }
    out
}

#[test]
fn stepping_without_inputs_is_the_one_run_at_any_communication_step() {
    let sys = loaded();
    let t_end = 0.6;
    // fine, coarse and cutting steps: the 0.6 seconds in 600, 60 and 7 communication steps
    for n in [600usize, 60, 7] {
        let h = t_end / n as f64;
        let mut one = Vec::new();
        simulate_drive(&sys, t_end, h, tight(), |s| {
            one.push([s.theta_in, s.theta_out, s.theta, s.theta_dot])
        })
        .unwrap();
        let mut run = CoSimulation::new(sys, 0.0, tight()).unwrap();
        let mut stepped = vec![[0.0; 4]];
        for k in 1..=n {
            run.advance(k as f64 * h, 0.0, 0.0).unwrap();
            let o = run.outputs();
            stepped.push([o.phi_in, o.phi_out, o.twist, o.twist_rate]);
        }
        assert_eq!(one.len(), stepped.len());
        let e = worst(&one, &stepped);
        assert!(e < 1e-9, "{n} steps: {e:e} of a column's range");
    }
}

#[test]
fn constant_torques_follow_the_closed_form_and_the_momentum_balance() {
    let sys = linear();
    let d = *sys.drive();
    let (motor, load) = (0.02, 1.5);
    // J_eq θ'' + C θ' + k1 θ = F, F = J_eq (load/J_o − motor/(N J_i)), from rest
    let j_eq = d.j_eq();
    let f = j_eq * (load / d.j_out - motor / (d.ratio * d.j_in));
    let wn = (d.k1 / j_eq).sqrt();
    let zeta = d.c_eq / (2.0 * (d.k1 * j_eq).sqrt());
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let twist = |t: f64| {
        let decay = (-zeta * wn * t).exp();
        f / d.k1 * (1.0 - decay * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin()))
    };
    let mut run = CoSimulation::new(sys, 0.0, tight()).unwrap();
    let (mut err, mut momentum) = (0.0f64, 0.0f64);
    for k in 1..=200 {
        let t = k as f64 * 1e-3;
        run.advance(t, motor, load).unwrap();
        let o = run.outputs();
        err = err.max((o.twist - twist(t)).abs() / (f / d.k1).abs());
        // J_o θo' + N J_i θi' grows by (load + N·motor) per second, whatever the twist does
        let p = d.j_out * o.w_out + d.ratio * d.j_in * o.w_in;
        let want = (load + d.ratio * motor) * t;
        momentum = momentum.max((p - want).abs() / want.abs());
        // the transmitted torque is the linear law's
        let law = d.c_eq * o.twist_rate + d.k1 * o.twist;
        assert!((o.tau_gear - law).abs() <= 1e-12 * law.abs().max(1.0));
    }
    assert!(
        err < 1e-9,
        "twist off the closed form by {err:e} of its static value"
    );
    assert!(momentum < 1e-9, "momentum off by {momentum:e}");
}

#[test]
fn a_failed_step_leaves_the_drive_where_it_was() {
    let mut run = CoSimulation::new(loaded(), 0.0, tight()).unwrap();
    run.advance(0.01, 0.0, 0.0).unwrap();
    let (t, o) = (run.time(), run.outputs());
    assert!(run.advance(0.005, 0.0, 0.0).is_err());
    assert!(run.advance(f64::NAN, 0.0, 0.0).is_err());
    assert!(run.advance(0.02, f64::INFINITY, 0.0).is_err());
    assert_eq!((run.time(), run.outputs()), (t, o));
}

fn spec() -> FmuDrive {
    FmuDrive::new("test drive", &loaded(), 1e-12).unwrap()
}

fn vr(spec: &FmuDrive, name: &str) -> u32 {
    let at = spec.variables().iter().position(|v| v.name == name);
    at.unwrap_or_else(|| panic!("no variable {name}")) as u32
}

#[test]
fn the_description_lists_every_parameter_once_with_its_start_value() {
    let spec = spec();
    let vars = spec.variables();
    let xml = spec.model_description(1e-3, 1.0);
    for p in hdgear::physical::DriveParam::ALL {
        let v = &vars[vr(&spec, p.name()) as usize];
        assert_eq!(v.role, Role::Parameter(spec.drive.value(p)));
        assert_eq!(xml.matches(&format!("name=\"{}\"", p.name())).count(), 1);
    }
    for name in [
        "output_bearing.fc",
        "output_bearing.vr",
        "tau_motor",
        "tau_load",
        "tau_gear",
    ] {
        assert_eq!(
            xml.matches(&format!("name=\"{name}\"")).count(),
            1,
            "{name}"
        );
    }
    // every unit a variable names is defined
    for v in &vars {
        if let Some(u) = v.unit {
            assert!(xml.contains(&format!("<Unit name=\"{u}\">")), "{u}");
        }
    }
    assert!(xml.contains(&spec.guid()));
    // the GUID follows the values
    let mut other = spec.clone();
    other.drive.k1 *= 2.0;
    assert_ne!(other.guid(), spec.guid());
    assert_eq!(spec.clone().guid(), spec.guid());
}

#[test]
fn an_instance_follows_the_call_order_and_steps_as_the_drive_does() {
    let spec = spec();
    let mut fmu = Instance::new(spec.clone());
    // stepping before initialisation is refused
    assert!(fmu.do_step(0.0, 1e-3).is_err());
    fmu.setup(Some(1e-12), 0.0).unwrap();
    fmu.enter_initialisation().unwrap();
    fmu.exit_initialisation().unwrap();
    assert_eq!(fmu.phase(), Phase::Stepping);
    assert!(fmu.set_real(vr(&spec, "k1"), 1.0).is_err());
    assert!(fmu.set_real(vr(&spec, "tau_gear"), 1.0).is_err());
    assert!(fmu.get_real(9999).is_err());
    let mut run = CoSimulation::new(loaded(), 0.0, tight()).unwrap();
    for k in 0..50 {
        let (t, h) = (k as f64 * 2e-3, 2e-3);
        let load = if k < 25 { 0.8 } else { -0.4 };
        fmu.set_real(vr(&spec, "tau_load"), load).unwrap();
        fmu.do_step(t, h).unwrap();
        run.advance(t + h, 0.0, load).unwrap();
        assert_eq!(
            fmu.get_real(vr(&spec, "phi_out")).unwrap(),
            run.outputs().phi_out
        );
    }
    // a point that is not the drive's time fails the instance; only reset helps
    assert!(fmu.do_step(0.5, 1e-3).is_err());
    assert_eq!(fmu.phase(), Phase::Failed);
    assert!(fmu.terminate().is_err());
    fmu.reset();
    assert_eq!(fmu.phase(), Phase::Instantiated);
    assert_eq!(fmu.get_real(vr(&spec, "phi_out")).unwrap(), 0.0);
}

#[test]
fn a_parameter_out_of_its_domain_is_refused_by_name() {
    let spec = spec();
    let mut fmu = Instance::new(spec.clone());
    assert!(fmu.set_real(vr(&spec, "j_in"), f64::NAN).is_err());
    fmu.set_real(vr(&spec, "j_in"), -1.0).unwrap();
    fmu.set_real(vr(&spec, "output_bearing.fs"), 0.1).unwrap();
    fmu.enter_initialisation().unwrap();
    let e = fmu.exit_initialisation().unwrap_err().to_string();
    assert!(e.contains("j_in") && e.contains("-1"), "{e}");
    assert_eq!(fmu.phase(), Phase::Failed);
    // reset brings the description's start values back
    fmu.reset();
    assert_eq!(fmu.get_real(vr(&spec, "j_in")).unwrap(), spec.drive.j_in);
    // the law's own rule: fs below fc is refused naming it
    fmu.set_real(vr(&spec, "output_bearing.fs"), 0.1).unwrap();
    fmu.enter_initialisation().unwrap();
    let e = fmu.exit_initialisation().unwrap_err().to_string();
    assert!(e.contains("fs"), "{e}");
}

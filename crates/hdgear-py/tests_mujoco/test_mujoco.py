"""hdgear.mujoco: a drive between two MuJoCo hinges against hdgear's own two-inertia simulation
of the same inertias (first-order convergence in MuJoCo's step), and the linear drive against
MuJoCo's own spring and damper on the twist (a fixed tendon), an independent check of signs and
the ratio. Run by scripts/python-tests.sh in the environment that has MuJoCo."""

import math

import mujoco
import numpy as np
import pytest

import hdgear
from hdgear.mujoco import DriveJoint

T_END = 0.1
SAMPLE = 0.005  # the spacing of the comparison [seconds]


def mjcf(drive, dt, integrator, tendon=""):
    d = drive.to_dict()
    return f"""
<mujoco>
  <option timestep="{dt!r}" integrator="{integrator}" gravity="0 0 0"/>
  <worldbody>
    <body name="rotor">
      <joint name="rotor" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="1" diaginertia="{d['j_in']!r} {d['j_in']!r} {d['j_in']!r}"/>
    </body>
    <body name="link">
      <joint name="output" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="1" diaginertia="{d['j_out']!r} {d['j_out']!r} {d['j_out']!r}"/>
    </body>
  </worldbody>
  {tendon}
</mujoco>"""


def loads(drive, t):
    """The loads of hdgear's two-inertia model: −T_m/N on the rotor, T_m + T_am sin Ωt on the
    output."""
    d = drive.to_dict()
    return -d["t_m"] / d["ratio"], d["t_m"] + d["t_am"] * math.sin(d["omega"] * t)


def run_coupled(drive, dt, integrator="Euler"):
    model = mujoco.MjModel.from_xml_string(mjcf(drive, dt, integrator))
    data = mujoco.MjData(model)
    joint = DriveJoint(model, drive, "rotor", "output")
    return sampled(model, data, dt, lambda t: joint.step(model, data, *loads(drive, t)))


def run_native(drive, dt):
    """The linear drive as MuJoCo's own fixed tendon θo − θi/N with stiffness k1 and damping C."""
    d = drive.to_dict()
    tendon = f"""<tendon><fixed name="twist" stiffness="{d['k1']!r}" damping="{d['c_eq']!r}"
        springlength="0"><joint joint="output" coef="1"/><joint joint="rotor"
        coef="{-1 / d['ratio']!r}"/></fixed></tendon>"""
    model = mujoco.MjModel.from_xml_string(mjcf(drive, dt, "Euler", tendon))
    data = mujoco.MjData(model)

    def step(t):
        motor, load = loads(drive, t)
        data.qfrc_applied[:] = [motor, load]
        mujoco.mj_step(model, data)

    return sampled(model, data, dt, step)


def sampled(model, data, dt, step):
    """(θi, θo) every SAMPLE seconds up to T_END."""
    per = round(SAMPLE / dt)
    out = [(data.qpos[0], data.qpos[1])]
    for k in range(round(T_END / dt)):
        step(k * dt)
        if (k + 1) % per == 0:
            out.append((data.qpos[0], data.qpos[1]))
    return np.array(out)


def reference(drive):
    r = drive.simulate(T_END, SAMPLE, rtol=1e-12, atol=1e-12)
    return np.column_stack([r.theta_in, r.theta_out])


def error(run, ref):
    """Largest difference of the twist θo − θi/N over its range."""
    n = len(ref)
    ratio = 50.0
    twist = lambda a: a[:n, 1] - a[:n, 0] / ratio
    return np.max(np.abs(twist(run) - twist(ref))) / np.ptp(twist(ref))


@pytest.fixture(scope="module")
def card():
    return hdgear.Drive.catalogue("CSF-20-50")


@pytest.mark.parametrize("integrator", ["Euler", "RK4"])
def test_coupling_converges_at_first_order_to_hdgears_answer(card, integrator):
    ref = reference(card)
    steps = [4e-5, 2e-5, 1e-5]
    errors = [error(run_coupled(card, dt, integrator), ref) for dt in steps]
    # the torque is held over each step: halving the step halves the error, whatever MuJoCo's
    # integrator does with the rest
    for coarse, fine in zip(errors, errors[1:]):
        assert 1.6 < coarse / fine < 2.5, errors
    assert errors[-1] < 2e-2, errors


def test_linear_drive_equals_mujocos_own_spring(card):
    d = card.to_dict()
    linear = hdgear.Drive(**{**d, "k2": 0.0, "backlash": 0.0})
    ref = reference(linear)
    for dt in [2e-5, 1e-5]:
        coupled, native = run_coupled(linear, dt), run_native(linear, dt)
        # MuJoCo's Euler evaluates the tendon's spring and damper at the step's start, as the
        # coupling holds its torque over the step: the same computation, so the same twist to
        # rounding (a wrong sign or ratio would be off by the whole twist)
        apart = error(coupled, native)
        assert apart < 1e-9, apart
    assert error(coupled, ref) < 2e-2


def test_implicit_integrators_are_refused(card):
    model = mujoco.MjModel.from_xml_string(mjcf(card, 1e-4, "implicitfast"))
    with pytest.raises(ValueError, match="2433"):
        DriveJoint(model, card, "rotor", "output")
    model = mujoco.MjModel.from_xml_string(mjcf(card, 1e-4, "Euler"))
    with pytest.raises(KeyError):
        DriveJoint(model, card, "rotor", "nothing")


def test_the_guide_example_runs(tmp_path, monkeypatch):
    """The ```python mujoco block of docs/src/fmu.md."""
    from pathlib import Path
    page = (Path(__file__).resolve().parents[3] / "docs" / "src" / "fmu.md").read_text()
    code = page.split("```python mujoco\n")[1].split("```")[0]
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/src/fmu.md", "exec"), {})


def test_a_bearing_holds_the_output_until_its_breakaway_torque(card):
    """A motor torque ramped slowly on the rotor: the output bearing's Stribeck friction holds
    the link (its speed stays below the Stribeck speed) until the transmitted torque reaches the
    law's breakaway f_s, then lets it go; without the law the link moves at once."""
    fs, vst = 9.5, 0.01
    law = f"stribeck:fc=6.5,fs={fs},vst={vst},cv=0.01,vr=1e-4"
    dt, ramp = 2e-5, 1.2  # N m per second on the rotor: 60 N m/s transmitted (ratio 50)

    def breakaway(bearing):
        """The largest transmitted torque |T| before the link's speed passes v_st, and when."""
        model = mujoco.MjModel.from_xml_string(mjcf(card, dt, "Euler"))
        data = mujoco.MjData(model)
        joint = DriveJoint(model, card, "rotor", "output", output_bearing=bearing)
        most = 0.0
        for k in range(20000):
            most = max(most, abs(joint.step(model, data, motor=ramp * k * dt)))
            if abs(data.qvel[1]) > vst:
                return most, k * dt
        raise AssertionError("the link never moved")

    held, at = breakaway(law)
    assert abs(held - fs) / fs < 0.01, held
    # quasi-static: the ramp reaches f_s, transmitted at ratio 50, after f_s/(50·ramp) seconds
    assert abs(at - fs / (50 * ramp)) / at < 0.05, at
    # without the law, the link moves at once (the spring's backlash term pushes it at rest)
    assert breakaway(None)[1] < 0.01 * at
    with pytest.raises(ValueError, match="stribeck"):
        DriveJoint(mujoco.MjModel.from_xml_string(mjcf(card, dt, "Euler")), card, "rotor",
                   "output", output_bearing="stribeck:fc=1")


def test_installed_drive_keeps_rk4_at_order_four(card):
    """With the torques evaluated at every stage (mjcb_passive), RK4 converges at order 4 and
    Euler at order 1, to hdgear's answer."""
    ref = reference(card)

    def installed(dt, integrator):
        model = mujoco.MjModel.from_xml_string(mjcf(card, dt, integrator))
        data = mujoco.MjData(model)
        joint = DriveJoint(model, card, "rotor", "output")
        joint.install(lambda t: loads(card, t))
        try:
            return sampled(model, data, dt, lambda t: mujoco.mj_step(model, data))
        finally:
            DriveJoint.remove()

    rk4 = [error(installed(dt, "RK4"), ref) for dt in [1e-4, 5e-5, 2.5e-5]]
    for coarse, fine in zip(rk4, rk4[1:]):
        assert 12 < coarse / fine < 20, rk4
    euler = [error(installed(dt, "Euler"), ref) for dt in [4e-5, 2e-5]]
    assert 1.6 < euler[0] / euler[1] < 2.5, euler

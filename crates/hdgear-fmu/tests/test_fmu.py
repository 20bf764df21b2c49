"""The drive's FMU as its users check it: FMPy's validation, FMPy's simulation against
`hdgear physical --simulate` of the same drive, large and cutting communication steps, inputs,
two instances in one process, and bad values refused without a crash.

Run by scripts/fmu-tests.sh (HDGEAR_BIN: the hdgear binary, with libhdgear_fmu.so beside it).
"""

import os
import shutil
import subprocess
import tempfile

import numpy as np
import pytest
import fmpy
from ctypes import byref
from fmpy.fmi1 import calloc, free
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy
from fmpy.validation import validate_fmu

BIN = os.environ.get("HDGEAR_BIN", "target/release/hdgear")

# the FMU's outputs and the columns of `physical --simulate` they are
SAME = {"phi_in": "theta_in", "phi_out": "theta_out", "twist": "theta", "twist_rate": "theta_dot"}

# Stribeck friction at the output bearing above the mean load (7 N m on the default card) with a
# breakaway above it: the output sticks while the disturbance (1.75 N m) cannot break it away
STICKING = "stribeck:fc=6.5,fs=9.5,vst=0.01,cv=0.01,vr=1e-4"


def hdgear(*args, cwd):
    r = subprocess.run([BIN, *args], cwd=cwd, capture_output=True, text=True)
    return r


def export(folder, name, *extra):
    r = hdgear("export", "fmu", "--out", name, *extra, cwd=folder)
    assert r.returncode == 0, r.stderr
    return os.path.join(folder, name)


def physical(folder, t_end, dt, *extra):
    out = os.path.join(folder, "physical.csv")
    r = hdgear("physical", "--simulate", "--t-end", repr(t_end), "--dt", repr(dt), "--out", out,
               *extra, cwd=folder)
    assert r.returncode == 0, r.stderr
    return np.genfromtxt(out, delimiter=",", names=True)


def worst(result, reference, columns):
    """Largest difference of each column over that column's range, at common times."""
    n = min(len(result), len(reference))
    t_fmu, t_ref = result["time"][:n], reference[reference.dtype.names[0]][:n]
    assert np.max(np.abs(t_fmu - t_ref)) <= 1e-9 * max(1.0, t_ref[-1])
    out = {}
    for mine, theirs in columns.items():
        b = reference[theirs][:n]
        out[mine] = np.max(np.abs(result[mine][:n] - b)) / max(np.ptp(b), 1e-300)
    return out


@pytest.fixture(scope="module")
def folder():
    d = tempfile.mkdtemp(prefix="hdgear-fmu-")
    yield d
    shutil.rmtree(d)


@pytest.fixture(scope="module")
def drive(folder):
    return export(folder, "drive.fmu")


def default_step(fmu):
    return float(fmpy.read_model_description(fmu).defaultExperiment.stepSize)


def test_validation_is_clean(drive):
    assert validate_fmu(drive) == []
    md = fmpy.read_model_description(drive)
    names = {v.name: v for v in md.modelVariables}
    # the drive's parameters, with units; the inputs and outputs the guide lists
    for p in ["j_in", "j_out", "ratio", "k1", "k2", "backlash", "c_eq", "t_m", "t_am", "omega"]:
        assert names[p].causality == "parameter" and names[p].start is not None
    assert names["k1"].unit == "N.m/rad"
    assert [v.name for v in md.modelVariables if v.causality == "input"] == ["tau_motor", "tau_load"]
    assert md.coSimulation.modelIdentifier == "hdgear_fmu"


def test_equals_physical_simulate(drive, folder):
    h = default_step(drive)
    result = fmpy.simulate_fmu(drive, start_time=0.0, stop_time=2.0, step_size=h, output_interval=h)
    reference = physical(folder, 2.0, h)
    errors = worst(result, reference, SAME)
    assert max(errors.values()) < 1e-8, errors


@pytest.mark.parametrize("h", [0.1, 0.5])
def test_large_communication_steps(drive, folder, h):
    # 242 and 1210 times the drive's own output spacing; hdgear's stepper runs inside each
    result = fmpy.simulate_fmu(drive, start_time=0.0, stop_time=4.0, step_size=h, output_interval=h)
    reference = physical(folder, 4.0, h)
    errors = worst(result, reference, SAME)
    assert max(errors.values()) < 1e-8, errors


def test_communication_points_cut_through_sticking(folder):
    fmu = export(folder, "sticking.fmu", "--output-bearing", STICKING)
    h = 0.013  # no multiple of the disturbance's period or of the drive's spacing
    result = fmpy.simulate_fmu(fmu, start_time=0.0, stop_time=4.0, step_size=h, output_interval=h)
    reference = physical(folder, 4.0, h, "--output-bearing", STICKING)
    # the output stands still for part of each period, and moves for another part
    w = reference["theta_out"]
    rate = np.abs(np.diff(w)) / h
    stuck = np.mean(rate < 1e-3 * np.max(rate))
    assert 0.1 < stuck < 0.9, stuck
    errors = worst(result, reference, SAME)
    assert max(errors.values()) < 1e-8, errors


def test_inputs_give_the_reference_result(folder):
    # torques that jump between communication points: FMPy steps to each jump, and so does the
    # reference (a repeated time in the input is a jump)
    h = 0.002
    t = np.arange(0, 101) * h
    jumps = [(0.0, 0.0, 0.0), (0.0301, 0.05, 0.0), (0.0801, 0.05, -3.0), (0.1501, -0.02, 2.0)]
    rows = []
    for (t0, m, l), nxt in zip(jumps, jumps[1:] + [(0.3, None, None)]):
        rows += [(t0, m, l), (nxt[0], m, l)]
    profile = os.path.join(folder, "profile.csv")
    with open(profile, "w") as f:
        f.write("time,tau_motor,tau_load\n")
        for r in rows:
            f.write("%r,%r,%r\n" % r)
    fmu = export(folder, "inputs.fmu", "--input", profile, "--step", repr(h), "--stop", "0.2")
    signal = np.array(rows, dtype=[("time", float), ("tau_motor", float), ("tau_load", float)])
    result = fmpy.simulate_fmu(fmu, start_time=0.0, stop_time=0.2, step_size=h, output_interval=h,
                               input=signal, record_events=False)
    # FMPy records a row at each input event too: keep the communication points
    on_grid = np.abs(result["time"] / h - np.round(result["time"] / h)) < 1e-9
    result = result[on_grid]
    reference = np.genfromtxt(fmu[:-4] + "_ref.csv", delimiter=",", names=True)
    outputs = {n: n for n in reference.dtype.names[1:]}
    errors = worst(result, reference, outputs)
    assert max(errors.values()) < 1e-12, errors
    # the torques moved the drive: the load's jump reverses the output's speed
    assert np.ptp(reference["w_out"]) > 0.0


def run_slave(slave, vr, loads, h):
    out = []
    for k, load in enumerate(loads):
        slave.setReal([vr["tau_load"]], [load])
        slave.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
        out.append(slave.getReal([vr["phi_out"], vr["twist"]]))
    return np.array(out)


def slave(fmu, unzipped, name):
    md = fmpy.read_model_description(fmu)
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    return s


def test_two_instances_do_not_share_state(drive, folder):
    unzipped = fmpy.extract(drive, os.path.join(folder, "unzipped"))
    md = fmpy.read_model_description(drive)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    h, n = 0.01, 100
    loads_a, loads_b = [1.0] * n, [-2.0 if k % 20 < 10 else 0.5 for k in range(n)]
    alone = []
    for loads in (loads_a, loads_b):
        s = slave(drive, unzipped, "alone")
        alone.append(run_slave(s, vr, loads, h))
        s.terminate()
        s.freeInstance()
    a, b = slave(drive, unzipped, "a"), slave(drive, unzipped, "b")
    got_a, got_b = [], []
    for k in range(n):
        # interleaved, one step each
        got_a.append(run_slave_step(a, vr, loads_a[k], k, h))
        got_b.append(run_slave_step(b, vr, loads_b[k], k, h))
    for s in (a, b):
        s.terminate()
        s.freeInstance()
    assert np.array_equal(np.array(got_a), alone[0])
    assert np.array_equal(np.array(got_b), alone[1])
    assert not np.array_equal(alone[0], alone[1])


def run_slave_step(s, vr, load, k, h):
    s.setReal([vr["tau_load"]], [load])
    s.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
    return s.getReal([vr["phi_out"], vr["twist"]])


def test_saved_state_replays_the_same_steps(drive, folder):
    unzipped = fmpy.extract(drive, os.path.join(folder, "unzipped-state"))
    md = fmpy.read_model_description(drive)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = slave(drive, unzipped, "state")
    run_slave(s, vr, [1.0] * 10, 0.01)
    saved = s.getFMUstate()
    first = [run_slave_step(s, vr, -1.0, 10 + k, 0.01) for k in range(5)]
    s.setFMUstate(saved)
    again = [run_slave_step(s, vr, -1.0, 10 + k, 0.01) for k in range(5)]
    s.freeFMUstate(saved)
    s.terminate()
    s.freeInstance()
    assert np.array_equal(np.array(first), np.array(again))


# What the FMU logged, through callbacks that live as long as the process. FMPy's logging proxy
# (fmpy.logging.addLoggerProxy) keeps the last logger it was given in a global and calls it for
# every later instance, so a logger made for one call (simulate_fmu(logger=...)) would be
# called after it is freed.
MESSAGES = []


def capture(env, name, status, category, message):
    MESSAGES.append(message.decode())


CALLBACKS = fmi2CallbackFunctions()
CALLBACKS.logger = fmi2CallbackLoggerTYPE(capture)
CALLBACKS.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
CALLBACKS.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
addLoggerProxy(byref(CALLBACKS))


@pytest.mark.parametrize("value", [-1.0, float("nan")])
def test_a_bad_parameter_is_an_error_with_a_message(drive, folder, value):
    unzipped = fmpy.extract(drive, os.path.join(folder, "unzipped-bad"))
    md = fmpy.read_model_description(drive)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bad")
    s.instantiate(callbacks=CALLBACKS)
    s.setupExperiment(startTime=0.0)
    MESSAGES.clear()
    with pytest.raises(Exception):
        s.setReal([vr["j_in"]], [value])
        s.enterInitializationMode()
        s.exitInitializationMode()
    assert any("j_in" in m for m in MESSAGES), MESSAGES
    # after the error the host may still reset the instance and free it
    s.reset()
    s.freeInstance()


def test_a_wrong_guid_is_refused(drive, folder):
    unzipped = fmpy.extract(drive, os.path.join(folder, "unzipped-guid"))
    md = fmpy.read_model_description(drive)
    s = FMU2Slave(guid="{00000000-0000-0000-0000-000000000000}", unzipDirectory=unzipped,
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName="wrong")
    MESSAGES.clear()
    with pytest.raises(Exception):
        s.instantiate(callbacks=CALLBACKS)
    assert any("GUID" in m for m in MESSAGES), MESSAGES


def test_the_guide_page_runs(folder):
    """The Python of docs/src/fmu.md, after the page's command, in a folder of its own."""
    root = os.path.join(os.path.dirname(__file__), "..", "..", "..")
    page = open(os.path.join(root, "docs", "src", "fmu.md")).read()
    code = page.split("```python fmpy\n")[1].split("```")[0]
    here = os.path.join(folder, "guide")
    os.mkdir(here)
    export(here, "drive.fmu")
    previous = os.getcwd()
    os.chdir(here)
    try:
        exec(compile(code, "docs/src/fmu.md", "exec"), {})
    finally:
        os.chdir(previous)


# every function of FMI 2.0's fmi2Functions.h: the common ones, co-simulation's, and model
# exchange's (refusing, since the FMU is co-simulation only), so that an importer that loads
# them all finds them (PyFMI #240)
FMI2_FUNCTIONS = """GetTypesPlatform GetVersion SetDebugLogging Instantiate FreeInstance SetupExperiment
EnterInitializationMode ExitInitializationMode Terminate Reset GetReal GetInteger GetBoolean
GetString SetReal SetInteger SetBoolean SetString GetFMUstate SetFMUstate FreeFMUstate
SerializedFMUstateSize SerializeFMUstate DeSerializeFMUstate GetDirectionalDerivative
EnterEventMode NewDiscreteStates EnterContinuousTimeMode CompletedIntegratorStep SetTime
SetContinuousStates GetDerivatives GetEventIndicators GetContinuousStates
GetNominalsOfContinuousStates SetRealInputDerivatives GetRealOutputDerivatives DoStep CancelStep
GetStatus GetRealStatus GetIntegerStatus GetBooleanStatus GetStringStatus""".split()


def test_the_library_exports_every_fmi2_function(drive, folder):
    import ctypes
    unzipped = fmpy.extract(drive, os.path.join(folder, "unzipped-symbols"))
    lib = ctypes.CDLL(os.path.join(unzipped, "binaries", "linux64", "hdgear_fmu.so"))
    missing = [f for f in FMI2_FUNCTIONS if not hasattr(lib, "fmi2" + f)]
    assert missing == []
    assert len(FMI2_FUNCTIONS) == 44
    lib.fmi2GetVersion.restype = ctypes.c_char_p
    assert lib.fmi2GetVersion() == b"2.0"

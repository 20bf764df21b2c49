"""A harmonic drive between two hinge joints of a MuJoCo model.

MuJoCo owns the two inertias: the *rotor* hinge (the motor and the wave generator, J_i, on the
input side) and the *output* hinge (the flexspline and the link, J_o). Put no spring, damping or
tendon between them: the drive is the torque across its compliance, T = (k1 + k2θ²)(θ − φ) + Cθ'
with θ = θo − θi/N (:meth:`hdgear.Drive.twist_torque`), which acts as −T on the output and +T/N on
the rotor, as in hdgear's two-inertia model (guide: the physical drive).

Each step, :meth:`DriveJoint.step` reads both joints' angles and speeds, computes T and writes the
torques to ``data.qfrc_applied`` (with the motor and load torques you give), then calls
``mujoco.mj_step``. The torque is held over the step, so the coupling is first order in the
time step whatever MuJoCo's integrator: halving ``model.opt.timestep`` halves the error (the
tests check this against hdgear's own two-inertia simulation). :meth:`DriveJoint.install`
instead has MuJoCo evaluate the torques at every stage of its integrator (its ``mjcb_passive``
callback): RK4 then converges at order 4. Use an explicit integrator
(``Euler`` or ``RK4``): MuJoCo's implicit integrators do not see applied forces in their
derivatives (MuJoCo issue #2433), which the constructor refuses. Keep the step well below the
drive's torsional period: ``timestep`` ≤ 0.05/f, f = √(k/J_eq)/2π with k the stiffness at the
largest twist (:meth:`DriveJoint.largest_step`).
"""

import math

import mujoco

from . import _hdgear

__all__ = ["DriveJoint"]


class DriveJoint:
    """The drive ``drive`` (an :class:`hdgear.Drive`; its t_m, t_am and omega are not used:
    loads are what you apply) between the hinge joints ``rotor`` and ``output`` of ``model``.

    ``output_bearing`` and ``input_bearing`` add friction at the output bearing (on θo') and at
    the wave generator (on θi'), written as ``hdgear physical``'s ``--output-bearing`` takes it:
    ``"stribeck:fc=0.8,fs=1.2,vst=0.05,cv=0.01,vr=1e-3"`` or ``"friction:fc=0.8,vs=1e-3"``, in
    N m, rad/s and N m s/rad."""

    def __init__(self, model, drive, rotor, output, output_bearing=None, input_bearing=None):
        explicit = (mujoco.mjtIntegrator.mjINT_EULER, mujoco.mjtIntegrator.mjINT_RK4)
        if model.opt.integrator not in explicit:
            raise ValueError(
                f"integrator {mujoco.mjtIntegrator(model.opt.integrator).name}: the drive's "
                "torque is an applied force, which MuJoCo's implicit integrators leave out of "
                "their derivatives (MuJoCo #2433); use Euler or RK4")
        self.drive = drive
        self.ratio = drive.ratio
        law = lambda side, text: None if text is None else _hdgear.Bearing(side, text)
        self._bearings = (law("input", input_bearing), law("output", output_bearing))
        self._q, self._v = [], []
        for name in (rotor, output):
            joint = model.joint(name)
            if model.jnt_type[joint.id] != mujoco.mjtJoint.mjJNT_HINGE:
                raise ValueError(f"joint {name!r} is not a hinge")
            self._q.append(int(model.jnt_qposadr[joint.id]))
            self._v.append(int(model.jnt_dofadr[joint.id]))

    def twist(self, data):
        """(θ, θ') = (θo − θi/N, θo' − θi'/N) [rad, rad/s] from the joints."""
        (qi, qo), (vi, vo) = self._q, self._v
        n = self.ratio
        return (data.qpos[qo] - data.qpos[qi] / n, data.qvel[vo] - data.qvel[vi] / n)

    def torque(self, data):
        """The torque across the compliance T [N m] in the joints' present state."""
        return self.drive.twist_torque(*self.twist(data))

    def friction(self, data):
        """The bearings' friction torques (rotor, output) [N m] at the joints' speeds, each
        opposing its speed (0 without a law)."""
        return tuple(0.0 if law is None else law.torque(data.qvel[v])
                     for law, v in zip(self._bearings, self._v))

    def forces(self, data, motor=0.0, load=0.0):
        """(rotor, output) [N m]: T/N + ``motor`` and −T + ``load``, each less its bearing's
        friction, in the joints' present state; and T."""
        t = self.torque(data)
        f_in, f_out = self.friction(data)
        return t / self.ratio + motor - f_in, -t + load - f_out, t

    def apply(self, data, motor=0.0, load=0.0):
        """Writes the drive's torques to ``data.qfrc_applied`` (:meth:`forces`). Returns T."""
        rotor, output, t = self.forces(data, motor, load)
        vi, vo = self._v
        data.qfrc_applied[vi] = rotor
        data.qfrc_applied[vo] = output
        return t

    def install(self, loads=None):
        """Makes MuJoCo compute the drive's torques itself, at every evaluation of its forces
        (MuJoCo's ``mjcb_passive`` callback), so that RK4 keeps its order 4 instead of the
        held torque's order 1. ``loads(t)`` gives (motor, load) [N m] at the time MuJoCo
        evaluates. Step with ``mujoco.mj_step`` then, not :meth:`step`. The callback is global
        in MuJoCo: one drive per process while installed; :meth:`remove` takes it out."""
        vi, vo = self._v

        def passive(model, data):
            motor, load = loads(data.time) if loads else (0.0, 0.0)
            rotor, output, _ = self.forces(data, motor, load)
            data.qfrc_passive[vi] += rotor
            data.qfrc_passive[vo] += output

        self._passive = passive  # MuJoCo holds only a reference
        mujoco.set_mjcb_passive(passive)

    @staticmethod
    def remove():
        """Takes the installed drive out of MuJoCo's force evaluation."""
        mujoco.set_mjcb_passive(None)

    def step(self, model, data, motor=0.0, load=0.0):
        """One MuJoCo step with the drive's torques held over it. Returns T at its start."""
        t = self.apply(data, motor, load)
        mujoco.mj_step(model, data)
        return t

    def largest_step(self, twist):
        """The largest ``timestep`` [s] the module recommends for twists up to ``twist`` [rad]:
        0.05 of the torsional period at the stiffness k1 + 3k2θ² there."""
        d = self.drive.to_dict()
        n2ji = d["ratio"] ** 2 * d["j_in"]
        j_eq = n2ji * d["j_out"] / (n2ji + d["j_out"])
        k = d["k1"] + 3.0 * d["k2"] * (abs(twist) + d["backlash"]) ** 2
        return 0.05 * 2.0 * math.pi / math.sqrt(k / j_eq)

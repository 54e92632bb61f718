"""A planar linkage's MuJoCo run in float32 through MuJoCo Warp (``mujoco_warp``), against the
same run in MuJoCo's float64 and against the closed form.

MuJoCo Warp steps in 10–20 ms on this machine's CPU, about the same for 1 to a few hundred
worlds (measured on models/fourbar.xml, docs/float32.md), so a whole
revolution at the validation settings (~12 600 steps) is out of reach but many short stretches
are not: ``worlds`` stretches spread evenly over a turn run as the worlds of one batch, each
started from the closed-form state at its crank angle (as linkgen's float64 runs start their
segments), for ``steps`` steps; MuJoCo's float64 runs the same stretches from the same states.
At the end of each stretch: the loop gap (the two sites of every loop-closing revolute, as
``simulate`` measures it), relative to the mechanism's size; the generalised constraint force
``qfrc_constraint`` of float32 against float64's and against the closed form's loop forces
mapped through the closures' Jacobian (Jᵀ·f), relative to the largest of the closed form's.

The float32 tolerances (``tolerances``): a coordinate held in float32 is rounded to
eps32·|x| (eps32 = 1.19e-7), once a step; the loop-closing connect removes a gap within its
time constant τ, so roundings pile up over τ/dt steps, and the gap is the difference of two
such positions: gap ≈ 2·eps32·size·τ/dt. A gap δ held by
the connect's stiffness moves its force by δ/τ² in acceleration, against the accelerations'
scale a = size·ω² + |g| (``loops.acceleration_scale``): force/peak ≈ (gap/size)·size/(τ²·a).
Each tolerance is PREDICTION_FACTOR times its prediction (the factor the fidelity decision
allows between a predicted and a measured error). float32 passes when it adds no more than its
tolerance to what float64 reaches on the same stretches (at MuJoCo's usual settings float64
itself is far from the closed form). The stretches tile one turn: up to WORLDS stretches, each
at least SETTLE_TIMES loop time constants long (a stretch starts with the connects' transient)."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.errors import SimulationError
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinetostatics import forces
from linkgen.mujoco.forces import has_loads, load_schedule
from linkgen.mujoco.loops import acceleration_scale, closure_forces, closure_jacobian, mechanism_size
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import PLACEHOLDER, Settings
from linkgen.mujoco.settings import apply, derive
from linkgen.mujoco.state import initial_state

EPS32 = float(np.finfo(np.float32).eps)
# A prediction holds when the measured figure is within this factor of it (issue 30's decision).
PREDICTION_FACTOR = 3.0
# Stretches (worlds of one batch): MuJoCo Warp's step costs the same for 1 to 128 worlds on CPU.
WORLDS = 64
# A stretch lasts at least this many loop time constants: the start transient decays as e^(−t/τ).
SETTLE_TIMES = 5
INSTALL = "pip install 'linkgen[mjwarp]' (mujoco-warp, which brings warp-lang)"


def engine():
    """The ``mujoco_warp`` module and ``warp``, or a SimulationError saying how to install them."""
    try:
        import warp

        warp.config.quiet = True  # before MuJoCo Warp loads its kernels: no line per kernel
        warp.config.log_level = warp.LOG_WARNING
        import mujoco_warp
    except ImportError as exc:
        raise SimulationError(f"--engine mjwarp needs MuJoCo Warp, which is not installed ({exc}); {INSTALL}") from None
    return mujoco_warp, warp


@dataclass(frozen=True)
class Float32Check:
    """One mechanism's float32 stretches against float64 and the closed form (module docstring):
    the worst over the worlds of each figure, relative as said there, with the tolerances."""

    name: str
    settings: str
    timestep: float
    worlds: int
    steps: int
    gap32: float
    gap64: float
    force32_vs_64: float
    force32_vs_closed: float
    force64_vs_closed: float
    tolerances: dict
    wall: float

    @property
    def ok(self) -> bool:
        return (self.gap32 <= self.gap64 + self.tolerances["loop_gap"]
                and self.force32_vs_closed <= self.force64_vs_closed + self.tolerances["constraint_force"])

    def to_json(self) -> dict:
        return {"model": self.name, "engine": "mjwarp", "ok": self.ok, "settings": self.settings,
                "timestep": self.timestep, "worlds": self.worlds, "steps": self.steps,
                "errors_relative": {"loop_gap_float32": self.gap32, "loop_gap_float64": self.gap64,
                                    "constraint_force_float32_vs_float64": self.force32_vs_64,
                                    "constraint_force_float32": self.force32_vs_closed,
                                    "constraint_force_float64": self.force64_vs_closed},
                "tolerances": self.tolerances, "seconds": self.wall}

    def summary(self) -> str:
        tol = self.tolerances
        return (f"{'ok  ' if self.ok else 'FAIL'} float32 (MuJoCo Warp, {self.worlds} stretches of {self.steps} steps "
                f"of {self.timestep:.3g} s, {self.settings} settings): loop gap {self.gap32:.2e} of the size "
                f"(float64 {self.gap64:.2e}; tolerance float64's + {tol['loop_gap']:.2e}), loop forces "
                f"{self.force32_vs_closed:.2e} of their peak off the closed form (float64 {self.force64_vs_closed:.2e}, "
                f"float32 vs float64 {self.force32_vs_64:.2e}; tolerance float64's + {tol['constraint_force']:.2e}), "
                f"{self.wall:.1f} s")


def tolerances(size: float, timestep: float, timeconst: float, accel: float) -> dict:
    """The float32 tolerances (module docstring): the loop gap relative to the size and the loop
    forces relative to their peak."""
    gap = 2.0 * EPS32 * max(timeconst / timestep, 1.0)
    return {"loop_gap": PREDICTION_FACTOR * gap,
            "constraint_force": PREDICTION_FACTOR * gap * size / (timeconst * timeconst * accel)}


def float32_check(asm: Assembly, *, worlds: int | None = None, steps: int | None = None, settings: Settings | None = None,
                  progress=None) -> Float32Check:
    """The stretches (module docstring) at ``settings`` (default derived, as ``validate``'s run),
    ``worlds`` stretches (default: up to WORLDS, each SETTLE_TIMES·τ or longer) of ``steps`` each
    (default: a turn's steps / ``worlds``);
    ``progress(fraction, seconds)`` every few seconds of float32 stepping."""
    mjw, wp = engine()
    wall0 = time.perf_counter()
    mech = asm.mechanism
    w0 = mech.drive.omega
    if not (math.isfinite(w0) and w0 > 0):
        raise SimulationError(f"drive.omega: must be > 0 rad/s for a MuJoCo run, got {w0!r}")
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    label = "derived" if settings is None else settings.label
    if settings is None:
        settings, _ = derive(asm, model, omega=w0, epsilon=0.0, duration=2 * math.pi / w0)
    apply(model, settings, mech.drive.joint)
    span = mech.drive.stop - mech.drive.start
    dt = model.opt.timestep
    if worlds is None:
        worlds = max(1, min(WORLDS, int(span / w0 / (SETTLE_TIMES * settings.timeconst))))
    phi0 = mech.drive.start + span * np.arange(worlds) / worlds
    if steps is None:
        steps = max(1, math.ceil(span / w0 / dt / worlds))
    phi1 = phi0 + w0 * steps * dt
    data = mujoco.MjData(model)
    qpos = np.zeros((worlds, model.nq))
    qvel = np.zeros((worlds, model.nv))
    for k in range(worlds):
        qpos[k], qvel[k] = initial_state(asm, model, float(phi0[k]), w0)

    # the description's loads and the pairs' friction, as linkgen's float64 runs apply them: the
    # closed form's at the crank angle each step starts from (mujoco.forces.load_schedule)
    xfrc = None
    if has_loads(asm):
        at = phi0[:, None] + w0 * dt * np.arange(steps)[None, :]
        xfrc = np.stack([load_schedule(asm, model, at[k], w0, 0.0) for k in range(worlds)])  # (worlds, steps, 6·nbody)
        xfrc = xfrc.reshape(worlds, steps, model.nbody, 6)

    # float64: MuJoCo, world by world
    q64, f64, j64 = np.zeros_like(qpos), np.zeros((worlds, model.nv)), []
    for k in range(worlds):
        mujoco.mj_resetData(model, data)
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        for i in range(steps):
            if xfrc is not None:
                data.xfrc_applied[:] = xfrc[k, i]
            mujoco.mj_step(model, data)
        mujoco.mj_forward(model, data)
        q64[k], f64[k] = data.qpos, data.qfrc_constraint
        j64.append(closure_jacobian(asm, model, data))
    gap64 = _gaps(asm, model, q64)

    # float32: MuJoCo Warp, every world in one batch
    mujoco.mj_resetData(model, data)
    m = mjw.put_model(model)
    d = mjw.put_data(model, data, nworld=worlds)
    d.qpos.assign(qpos.astype(np.float32))
    d.qvel.assign(qvel.astype(np.float32))
    for i in range(steps):
        if xfrc is not None:
            d.xfrc_applied.assign(xfrc[:, i].astype(np.float32))
        mjw.step(m, d)
        if progress is not None and i % 50 == 49:
            wp.synchronize()
            progress((i + 1) / steps, time.perf_counter() - wall0)
    mjw.forward(m, d)
    wp.synchronize()
    q32 = d.qpos.numpy().astype(float)
    f32 = d.qfrc_constraint.numpy().astype(float)
    if not (np.isfinite(q32).all() and np.isfinite(f32).all()):
        raise SimulationError(f"{mech.name}: the float32 run diverged in MuJoCo Warp within {steps} steps of "
                              f"{dt:g} s")
    gap32 = _gaps(asm, model, q32)

    # the closed form at the angles the stretches end at
    react = forces(asm, phi1 % (2 * math.pi) if span >= 2 * math.pi - 1e-12 else phi1, w0).reactions
    fcf = np.array([j64[k].T @ closure_forces(asm, model, react, k) for k in range(worlds)])
    if float(np.abs(fcf + f64).max()) < float(np.abs(fcf - f64).max()):
        fcf = -fcf  # Jᵀ·f on body1 against MuJoCo's sign convention for qfrc_constraint
    peak = float(np.abs(fcf).max()) or 1.0
    size = mechanism_size(asm)
    accel = acceleration_scale(size, w0, 0.0, float(np.hypot(*mech.gravity)))
    return Float32Check(mech.name, label, dt, worlds, steps, float(gap32.max() / size), float(gap64.max() / size),
                        float(np.abs(f32 - f64).max() / peak), float(np.abs(f32 - fcf).max() / peak),
                        float(np.abs(f64 - fcf).max() / peak), tolerances(size, dt, settings.timeconst, accel),
                        time.perf_counter() - wall0)


def _gaps(asm: Assembly, model: mujoco.MjModel, qpos: np.ndarray) -> np.ndarray:
    """Largest loop gap [m] of each state (float64 kinematics of the given coordinates)."""
    from linkgen.mujoco.tree import site_name, spanning_tree

    data = mujoco.MjData(model)
    out = np.zeros(qpos.shape[0])
    for k, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        for pair in spanning_tree(asm).closures:
            point = asm.mechanism.revolute(pair.name).point
            a, b = (data.site(site_name(asm, link, point)).xpos for link in pair.links)
            out[k] = max(out[k], float(np.linalg.norm(a - b)))
    return out


__all__ = ["EPS32", "SETTLE_TIMES", "WORLDS", "Float32Check", "INSTALL", "engine", "float32_check", "tolerances"]

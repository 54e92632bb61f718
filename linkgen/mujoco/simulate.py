"""MuJoCo run of the driven crank: settings from the mechanism, the range split into segments
that run side by side in one ``mujoco.rollout`` call, stepped in chunks that keep only the
sampled states (memory bounded whatever the duration) and report progress.

Each segment starts from the closed-form state a settling window before its part of the
range, so that the compared curves cover the whole range and no sample sits in a start-up
transient. Samples within a settling window after a load switches on or off are left out; the
run counts them (``Run.left_out``).
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass
from typing import Callable

import mujoco
import numpy as np
from mujoco import rollout

from linkgen.model.turn import full_turn
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.blocks import default_threads
from linkgen.errors import AssemblyError, SimulationError, SingularityError
from linkgen.families.planar.kinematics import solve
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.tree import sensor_name, spanning_tree
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.forces import has_loads, load_schedule
from linkgen.mujoco.loops import mechanism_size
from linkgen.mujoco.sample import Samples, read_samples
from linkgen.mujoco.options import PLACEHOLDER, PROGRESS_AFTER, Settings
from linkgen.mujoco.posed import Posed, slider_reference, torque_schedule
from linkgen.mujoco.settings import MAX_STEPS, Scales, apply, check_budget, crank_only, derive
from linkgen.mujoco.state import tree_state
from linkgen.families.planar.pose import state
from linkgen.mujoco.state import initial_state, joint_state, joint_states
from linkgen.mujoco.warm_start import settled_start
from linkgen.mujoco.windows import LEAD_SIGMA, LeftOut, lead_sigma, switch_windows
from linkgen.mujoco.timing import LEAD_TARGET, SETTLE_TARGET, crank_phi, crank_time, settle_window

# A run whose loop gap passes this fraction of the mechanism's size has failed (not a result):
# the loop has come apart, far beyond anything the comparison could judge.
GAP_ABORT = 1e-4
# Steps per rollout call: bounds the memory of a run (states and sensors of one chunk) and
# sets how often progress is reported.
CHUNK_STEPS = 20_000


@dataclass(frozen=True)
class Run:
    """A MuJoCo run: the model, the settings and what they came from, the sampled quantities,
    the steps taken (all segments), the wall time [s], the largest loop gap over the compared
    part [m] and the crank angle [rad] where it occurred, the settling window [s] and what was
    left out."""

    def __repr__(self) -> str:
        return f"Run({self.steps} steps of {self.settings.timestep:.3g} s, {self.samples.time.shape[0]} samples)"


    model: mujoco.MjModel
    settings: Settings
    scales: Scales | None  # None where the closed form does not cover the mechanism
    samples: Samples
    steps: int
    wall: float
    gap_max: float
    gap_max_at: float
    window: float
    left_out: tuple[LeftOut, ...]
    segments: int


@no_log_file()
def build_model(asm: Assembly, settings: Settings | None = None) -> mujoco.MjModel:
    """The compiled MJCF of the mechanism, with ``settings`` (default: derived)."""
    return mujoco.MjModel.from_xml_string(write_mjcf(asm, settings))


def _assembles(asm: Assembly | Posed, phi: np.ndarray) -> bool:
    try:
        if isinstance(asm, Posed):
            state(asm.mechanism, phi)
        else:
            solve(asm, phi)
    except (AssemblyError, SingularityError):
        return False
    return True


def _start_state(asm: Assembly | Posed, model: mujoco.MjModel, phi: float, omega: float):
    """qpos, qvel at crank angle φ [rad] and speed ω [rad/s]: closed form, or the numeric pose."""
    if isinstance(asm, Posed):
        qpos, qvel = tree_state(asm.mechanism, model, [phi], omega)
        return qpos[0], qvel[0]
    return initial_state(asm, model, phi, omega)


# Samples a run compares over the range, by default (``validate``'s).
SAMPLES = 360
# A run coarsened to the step budget (and run anyway: validate reports what it reaches) stops
# only when its loop gap passes this many times the predicted gap (measured within 3× of it on
# the fidelity corpus, docs/fidelity.md), and never past BUDGET_ABORT_CAP of the size.
BUDGET_ABORT_FACTOR = 30.0
BUDGET_ABORT_CAP = 0.05


@no_log_file()
def simulate(asm: Assembly | Posed, *, revolutions: float = 1.0, omega: float | None = None,
             epsilon: float | None = None, settings: Settings | None = None, samples: int = SAMPLES,
             nthread: int | None = None, progress: Callable[[float, float], None] | None = None,
             gap_abort: float = GAP_ABORT, settle: bool = True, scales: Scales | None = None,
             max_steps: int = MAX_STEPS, refuse_over_budget: bool = True) -> Run:
    """Drive the crank over its range (``revolutions`` times for a full-turn range) and sample.

    Args:
        omega, epsilon: crank speed at the range's start [rad/s] (> 0) and constant
            acceleration [rad/s²]; default the description's drive.
        settings: MuJoCo settings; default derived from the mechanism (``mujoco.settings.derive``;
            from the crank speed alone for a ``Posed`` mechanism, which the closed form does not
            cover: then gravity and link torques are the only loads).
        samples: sampled states over the range (before left-out windows).
        nthread: threads (= segments of the range); default every core.
        progress: called as progress(fraction done, seconds elapsed) after each chunk of steps
            once a run has lasted PROGRESS_AFTER seconds.
        gap_abort: the loop gap, as a fraction of the size, at which the run stops.
        settle: leave out the samples in settling windows (after the start where no lead-in is
            possible, after load switches); False keeps every sample, transients included.
        scales: what an earlier run of the same mechanism, speed and range derived its settings
            from (``Run.scales``); given with ``settings``, the scan is not repeated.
        max_steps: the step budget per segment for derived settings; beyond it they are
            coarsened, and a run whose loop gap is then predicted past its tolerance
            is not started (``mujoco.settings.check_budget``) unless ``refuse_over_budget``
            is False (validate runs it at the budget and reports what it reaches).

    Raises:
        SimulationError: the run diverged, MuJoCo warned, or the loop gap passed GAP_ABORT of
            the mechanism's size (names the crank angle, the time and the settings).
    """
    wall0 = _time.perf_counter()
    mech = asm.mechanism
    w0 = mech.drive.omega if omega is None else float(omega)
    eps = mech.drive.epsilon if epsilon is None else float(epsilon)
    if not (math.isfinite(w0) and w0 > 0):
        raise SimulationError(f"{'drive.omega' if omega is None else 'omega'}: must be > 0 rad/s for a MuJoCo run "
                              f"(it drives the crank forwards through its range), got {w0!r}")
    if not math.isfinite(eps):
        raise SimulationError(f"epsilon must be finite, got {eps!r}")
    span = mech.drive.stop - mech.drive.start
    full = full_turn(mech)
    if not (math.isfinite(revolutions) and revolutions > 0):
        raise SimulationError(f"revolutions must be > 0, got {revolutions!r}")
    if not full and revolutions != 1.0:
        raise SimulationError(f"the crank turns only over its range of {math.degrees(span):.6g}°: revolutions must be 1")
    phi_a, phi_b = mech.drive.start, mech.drive.start + span * revolutions
    duration = float(crank_time(np.array([phi_b]), phi_a, w0, eps)[0])
    w_peak = max(w0, abs(w0 + eps * duration))
    derived_here = settings is None
    if isinstance(asm, Posed):
        model = mujoco.MjModel.from_xml_string(write_mjcf(mech, PLACEHOLDER))
        settings, scales = crank_only(mech, w_peak) if settings is None else settings, None
    else:
        model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
        if settings is None or scales is None:
            derived, scales = derive(asm, model, omega=w_peak, epsilon=eps, duration=duration, max_steps=max_steps)
            settings = derived if settings is None else settings
    apply(model, settings, mech.drive.joint)
    try:
        if derived_here and refuse_over_budget and scales is not None and scales.capped:
            check_budget(scales, settings, duration, max_steps)
        elif derived_here and scales is not None and scales.capped:  # run at the budget: abort on divergence only
            gap_abort = max(gap_abort, min(BUDGET_ABORT_CAP, BUDGET_ABORT_FACTOR * scales.predicted_gap(settings.timeconst)
                                           / max(scales.size, 1e-300)))
        return _run(asm, model, settings, scales, w0, eps, phi_a, phi_b, full, duration, samples, nthread, progress,
                    gap_abort, wall0, settle, max_steps)
    except SimulationError as exc:  # the settings it ran with, and whether a step budget capped them
        exc.settings, exc.scales = settings, scales
        raise


def _run(asm: Assembly | Posed, model: mujoco.MjModel, settings: Settings, scales: Scales | None, w0: float,
         eps: float,
         phi_a: float, phi_b: float, full: bool, duration: float, samples: int, nthread: int | None,
         progress, gap_abort: float, wall0: float, settle: bool, max_steps: int = MAX_STEPS) -> Run:
    mech = asm.mechanism
    dt = settings.timestep
    g = float(np.hypot(*mech.gravity))
    window = settle_window(settings, scales, eps, SETTLE_TARGET, g) if settle else 0.0
    lead_needed = settle_window(settings, scales, eps, LEAD_TARGET, g)
    # A lead-in costs steps like the run: at most the step budget. A slow loop mode
    # (``loop_modes``) may need longer; the samples its rest would cover are left out below.
    lead_window = min(lead_needed, max_steps * dt)

    # Samples over the range, and which are left out (load switches).
    phi_s, t_s, keep, left = switch_windows(asm, phi_a, phi_b, w0, eps, samples, full, dt, window)

    # Segments: equal parts of the range, each started a window early.
    nseg = max(1, min(default_threads() if nthread is None else nthread, samples))
    bounds = np.linspace(phi_a, phi_b, nseg + 1)
    t_bounds = crank_time(bounds, phi_a, w0, eps)
    t_start = t_bounds[:-1] - lead_window
    lead = crank_phi(t_start[0], phi_a, w0, eps)
    if not full and (not _assembles(asm, np.linspace(lead, phi_a, 16))  # the range starts near a limit
                     or (settle and scales is not None
                         and lead_sigma(asm, model, np.linspace(lead, phi_a, 16)) < scales.sigma_min / LEAD_SIGMA)):
        t_start[0] = 0.0
        t_start = np.maximum(t_start, 0.0)  # the first segment has no lead-in: its start is left out below
    seg_of = np.clip(np.searchsorted(bounds, phi_s, side="right") - 1, 0, nseg - 1)
    short = lead_needed - (t_bounds[:-1] - t_start) - dt  # each segment's lead-in shortfall [s], rounding aside
    hit = (t_s - t_bounds[seg_of]) < short[seg_of]
    if settle and hit.any():
        keep &= ~hit
        left.append(LeftOut("start", float(phi_s[hit].min()), float(phi_s[hit].max()), int(hit.sum())))
    step_of = np.maximum(np.rint((t_s - t_start[seg_of]) / dt).astype(np.int64), 1)
    nsteps = int(np.ceil((t_bounds[1:] - t_start) / dt).max()) + 1

    if np.count_nonzero(keep) < 2:  # known before any step: the run would compare nothing
        exc = SimulationError(f"every sample falls in a settling window: the loops take {window:.3g} s to settle "
                              f"with timestep {settings.timestep:g} s and loop time constant {settings.timeconst:g} s, "
                              f"and the range lasts {duration:.3g} s")
        exc.nothing_to_compare = True
        raise exc

    # Initial states and open-loop inputs.
    datas = [mujoco.MjData(model) for _ in range(nseg)]
    nstate = mujoco.mj_stateSize(model, mujoco.mjtState.mjSTATE_FULLPHYSICS)
    state = np.zeros((nseg, nstate))
    for k in range(nseg):
        d = datas[0]
        phi_k = crank_phi(t_start[k], phi_a, w0, eps)
        d.qpos[:], d.qvel[:] = _start_state(asm, model, phi_k, w0 + eps * t_start[k])
        if settle and not isinstance(asm, Posed):  # the loops start open by the gap they settle to (``warm_start``)
            d.qpos[:] = settled_start(asm, model, settings, float(phi_k), w0 + eps * t_start[k], eps, d.qpos, d.qvel)
        d.time = t_start[k]
        mujoco.mj_getState(model, d, state[k], mujoco.mjtState.mjSTATE_FULLPHYSICS)
    drive_ctrl = settings.armature * eps
    spec = mujoco.mjtState.mjSTATE_CTRL
    loads = has_loads(asm)
    if loads:
        spec |= mujoco.mjtState.mjSTATE_XFRC_APPLIED
    gap_sensors = _gap_sensors(asm, model)
    size = mechanism_size(asm)

    got = np.zeros((samples, 1 + model.nq + model.nv))
    gap_max, gap_at = 0.0, phi_a
    done, steps_total = 0, 0
    for c0 in range(0, nsteps, CHUNK_STEPS):
        n = min(CHUNK_STEPS, nsteps - c0)
        ctrl = np.full((nseg, n, model.nu), drive_ctrl)
        t_step = t_start[:, None] + (c0 + 1 + np.arange(n))[None, :] * dt  # time after each step
        if loads:
            phis = crank_phi(t_step - dt, phi_a, w0, eps)  # the angle at the step's start
            xfrc = np.stack([torque_schedule(asm, model, n) if isinstance(asm, Posed)
                             else load_schedule(asm, model, phis[k], w0 + eps * (t_step[k] - dt), eps)
                             for k in range(nseg)])
            ctrl = np.concatenate([ctrl, xfrc], axis=2)
        states, sensors = rollout.rollout(model, datas, state, ctrl, control_spec=spec, nstep=n)
        steps_total += n * nseg
        if not np.all(np.isfinite(states[:, -1])):
            k, i = np.argwhere(~np.all(np.isfinite(states), axis=2))[0]
            raise SimulationError(_where("the run diverged", float(t_step[k, i]), phi_a, w0, eps, settings))
        gap = _gap(sensors, gap_sensors)  # (nseg, n)
        live = t_step >= t_start[:, None] + lead_window  # past each segment's lead-in
        if np.any(live):
            g = np.where(live, gap, 0.0)
            k, i = np.unravel_index(int(np.argmax(g)), g.shape)
            if g[k, i] > gap_max:
                gap_max, gap_at = float(g[k, i]), float(crank_phi(t_step[k, i], phi_a, w0, eps))
            if gap_max > gap_abort * size:
                raise SimulationError(_where(f"the loop gap reached {gap_max:.3g} m ({gap_max / size:.2g} of the "
                                             f"mechanism's size, limit {gap_abort:g})", float(t_step[k, i]),
                                             phi_a, w0, eps, settings))
        rows = (step_of > c0) & (step_of <= c0 + n)
        for j in np.flatnonzero(rows):
            got[j] = states[seg_of[j], step_of[j] - c0 - 1, :1 + model.nq + model.nv]
        state = states[:, -1].copy()
        done += n
        elapsed = _time.perf_counter() - wall0
        if progress is not None and elapsed > PROGRESS_AFTER:
            progress(done / nsteps, elapsed)
    for d in datas:
        for kind, w in enumerate(d.warning):
            if w.number:
                name = mujoco.mjtWarning(kind).name.removeprefix("mjWARN_")
                why = (" (MuJoCo rejects joint accelerations beyond mjMAXVAL = 1e10 rad/s² or m/s²: the "
                       "crank is too fast for MuJoCo)" if name == "BADQACC" else "")
                raise SimulationError(f"MuJoCo warned during the run: {name}{why}, {w.number} times, last at step "
                                      f"{w.lastinfo}; settings: timestep {settings.timestep:g} s, loop time "
                                      f"constant {settings.timeconst:g} s")
    idx = np.flatnonzero(keep)
    sampled = read_samples(asm, model, got[idx, 0], got[idx, 1:1 + model.nq], got[idx, 1 + model.nq:], drive_ctrl,
                           slider_reference(asm))
    return Run(model, settings, scales, sampled, steps_total, _time.perf_counter() - wall0, gap_max, gap_at,
               window, tuple(left), nseg)


def steps_per_revolution(run: Run) -> float:
    """Steps one revolution of the crank takes at the run's mean speed and timestep."""
    w = abs(float(np.mean(run.samples.crank[1]))) if run.samples.time.size else 0.0
    return 2 * math.pi / (w * run.settings.timestep) if w > 0 else math.nan


def _where(what: str, t: float, phi0: float, w0: float, eps: float, settings: Settings) -> str:
    phi = float(crank_phi(t, phi0, w0, eps))
    return (f"{what} at crank angle {math.degrees(phi):.3f}° (t = {t:.6g} s) with timestep {settings.timestep:g} s "
            f"and loop time constant {settings.timeconst:g} s")


def _gap_sensors(asm: Assembly, model: mujoco.MjModel) -> list[tuple[int, int]]:
    """Sensor addresses of the two sites of every loop-closing revolute."""
    out = []
    for pair in spanning_tree(asm).closures:
        point = asm.mechanism.revolute(pair.name).point
        a, b = (model.sensor(sensor_name(asm, link, point)).adr[0] for link in pair.links)
        out.append((a, b))
    return out


def _gap(sensors: np.ndarray, pairs: list[tuple[int, int]]) -> np.ndarray:
    """Largest loop gap [m] per step, (nseg, n)."""
    gap = np.zeros(sensors.shape[:2])
    for a, b in pairs:
        gap = np.maximum(gap, np.linalg.norm(sensors[..., a:a + 3] - sensors[..., b:b + 3], axis=-1))
    return gap


def simulate_mechanism(mech, **options) -> Run:
    """``simulate`` for a planar description: assembled by its Assur groups, or posed
    numerically where they do not cover it (class III and higher: MuJoCo needs no groups)."""
    from linkgen.errors import StructureError
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.posed import posed

    try:
        source = assemble(mech)
    except StructureError:
        source = posed(mech)
    return simulate(source, **options)


__all__ = ["LeftOut", "Run", "simulate_mechanism", "build_model", "initial_state", "joint_state", "joint_states", "settle_window",
           "simulate", "steps_per_revolution"]

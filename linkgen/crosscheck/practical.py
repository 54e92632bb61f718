"""What MuJoCo's usual settings cost in accuracy: the same mechanism run at the settings a
robotics user starts from (timestep 2 ms, MuJoCo's default solref/solimp and Euler integrator)
and at steps between those and the derived validation settings; for each, the loop gap, the
reaction and driving-torque errors against the closed form, and the cost per revolution. Every
sample counts (no settling windows: a user's run has its transients too); each run is started a
settling window before the range where the mechanism assembles there."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.crosscheck.compare import compare, force_scale, kinematic_scales
from linkgen.errors import SimulationError
from linkgen.mujoco.options import Settings
from linkgen.mujoco.simulate import PROGRESS_AFTER, simulate, steps_per_revolution

# MuJoCo's defaults (its XML reference): timestep 2 ms, Euler, solref "0.02 1",
# solimp "0.9 0.95 0.001 0.5 2", 100 iterations, tolerance 1e-8.
USER = Settings(timestep=2e-3, timeconst=0.02, impedance=0.9, integrator="Euler", iterations=100,
                tolerance=1e-8, solimp=(0.9, 0.95, 0.001, 0.5, 2.0), label="MuJoCo defaults (timestep 2 ms)")
# Samples per revolution for the study (errors are maxima over them).
SAMPLES = 120
# How the progress of the study's runs is labelled on stderr.
PROGRESS_WHAT = "practical-settings runs"
# A practical run is reported, not aborted, until its loops open by this fraction of the size.
GAP_REPORT_LIMIT = 0.2


def finite_or_none(x: float) -> float | None:
    """JSON carries no NaN or Infinity: a value that is not finite (a run that failed) is null."""
    return float(x) if math.isfinite(x) else None


@dataclass(frozen=True)
class PracticalRow:
    """One setting: its label and values, loop gap relative to the size, reaction error
    relative to the peak reaction, driving-torque error relative to peak reaction × size, steps
    and wall time [s] per revolution, or why it failed."""

    settings: Settings
    gap: float
    reaction_error: float
    torque_error: float
    steps_per_revolution: float
    wall_per_revolution: float
    failure: str | None = None

    def to_json(self) -> dict:
        s = self.settings
        return {"label": s.label, "timestep": s.timestep, "integrator": s.integrator,
                "solref": [s.timeconst, 1.0], "solimp": [float(x) for x in s.solimp_text.split()],
                "loop_gap_relative": finite_or_none(self.gap), "reaction_error_relative": finite_or_none(self.reaction_error),
                "driving_torque_error_relative": finite_or_none(self.torque_error),
                "steps_per_revolution": finite_or_none(self.steps_per_revolution),
                "wall_s_per_revolution": finite_or_none(self.wall_per_revolution), "failure": self.failure}


def ladder(validation: Settings) -> list[Settings]:
    """From MuJoCo's defaults to the validation settings, one change at a time."""
    user = replace(USER, armature=validation.armature)
    rk4 = replace(user, integrator="RK4", label="+ RK4")
    stiff_tau = 2 * user.timestep  # MuJoCo raises τ to 2·timestep anyway (refsafe)
    stiff = replace(rk4, timeconst=stiff_tau, impedance=validation.impedance, solimp=None, iterations=50,
                    tolerance=0.0, label="+ stiff loops (τ = 2·timestep, impedance 0.9999)")
    dt_mid = math.sqrt(user.timestep * validation.timestep)
    tau_mid = max(math.sqrt(stiff_tau * validation.timeconst), 2 * dt_mid)
    mid = replace(stiff, timestep=dt_mid, timeconst=tau_mid, label="halfway (geometric) to validation")
    return [user, rk4, stiff, mid, replace(validation, label="validation (derived)")]


def practical_study(asm: Assembly, validation: Settings, *, nthread: int | None = None,
                    scales=None, progress=None) -> list[PracticalRow]:
    """One row per setting of ``ladder(validation)`` (one revolution, or the range); ``scales``:
    the validation run's (``Run.scales``), so that each run does not scan the range again.
    ``progress(fraction of the study done, seconds elapsed, what)`` is called during each run
    that lasts long enough (``mujoco.simulate``) and after each run once the study has lasted
    PROGRESS_AFTER seconds."""
    rows = []
    steps = ladder(validation)
    t0 = time.perf_counter()
    for i, s in enumerate(steps):
        what = PROGRESS_WHAT
        inner = None if progress is None else (
            lambda f, _t, i=i, what=what: progress((i + f) / len(steps), time.perf_counter() - t0, what))
        try:
            run = simulate(asm, settings=s, samples=SAMPLES, nthread=nthread, gap_abort=GAP_REPORT_LIMIT,
                           settle=False, scales=scales, progress=inner)  # what a user sees: transients included
            cmp = compare(asm, run, inverse=False)
        except SimulationError as exc:
            rows.append(PracticalRow(s, math.nan, math.nan, math.nan, math.nan, math.nan, str(exc)))
            _report(progress, (i + 1) / len(steps), t0)
            continue
        cf = cmp.closed_forces
        f = force_scale(cf, asm, cmp.size, kinematic_scales(cmp.size, *run.samples.crank[1:],
                                                             float(np.hypot(*asm.mechanism.gravity)))["acceleration"])
        if not f > 0:  # the crank stood still and nothing loads the mechanism: no force to compare
            w = float(np.abs(run.samples.crank[1]).max())
            rows.append(PracticalRow(s, math.nan, math.nan, math.nan, math.nan, math.nan,
                                     f"the crank turned at {w:.3g} rad/s at most in this run, with no load on the mechanism: its "
                                     "closed-form forces vanish, so its force errors have no scale"))
            _report(progress, (i + 1) / len(steps), t0)
            continue
        reac = [np.linalg.norm(run.samples.forces.reactions[k] - v, axis=1).max() for k, v in cf.reactions.items()]
        reac += [np.abs(run.samples.forces.normal_force[k] - v).max() for k, v in cf.normal_force.items()]
        torque = float(np.abs(run.samples.forces.balancing_torque - cf.balancing_torque).max())
        per_rev = steps_per_revolution(run)
        arm = 1.0 if asm.mechanism.slide_drive else cmp.size  # a prismatic drive's balancing load is a force
        rows.append(PracticalRow(s, cmp.gap.relative_error, float(max(reac)) / f, torque / (f * arm),
                                 per_rev, run.wall * per_rev / run.steps))
        _report(progress, (i + 1) / len(steps), t0)
    return rows


def _report(progress, fraction: float, t0: float) -> None:
    if progress is not None and time.perf_counter() - t0 > PROGRESS_AFTER:
        progress(fraction, time.perf_counter() - t0, PROGRESS_WHAT)


__all__ = ["PracticalRow", "USER", "ladder", "practical_study"]

"""One mechanism through MuJoCo and the closed form: settings derived, run, compared, retried
once with finer settings when it misses, failures diagnosed; plus what MuJoCo's usual settings
cost in accuracy (``practical``)."""

from __future__ import annotations

import math

import numpy as np
from dataclasses import dataclass, replace

from linkgen.families.planar.assembly import Assembly
from linkgen.crosscheck.compare import Comparison, compare
from linkgen.crosscheck.diagnose import Finding, diagnose
from linkgen.crosscheck.prediction import Prediction, Verdict, came_apart, predict_run, verdict
from linkgen.errors import SimulationError
from linkgen.mujoco.options import Settings
from linkgen.mujoco.result_shape import loop_gap, validation
from linkgen.mujoco.settings import MAX_STEPS
from linkgen.crosscheck.practical import PracticalRow, finite_or_none, practical_study
from linkgen.mujoco.simulate import simulate, steps_per_revolution


@dataclass(frozen=True)
class Attempt:
    """One run: its settings, whether everything held, the worst quantity (error/tolerance),
    steps and wall time [s], or the error that stopped it."""

    settings: Settings | None  # None: the run failed before its settings were derived
    ok: bool
    worst: str
    worst_ratio: float
    steps: int
    wall: float
    error: str | None = None
    capped: bool = False  # a step budget coarsened the settings
    scales: object = None  # what the settings were derived from (mujoco.settings.Scales), when derived
    nothing_to_compare: bool = False  # its settling windows covered every sample (known before any step)

    def to_json(self) -> dict:
        return {"settings": self.settings.to_json() if self.settings else None, "ok": self.ok, "worst": self.worst,
                "worst_error_over_tolerance": finite_or_none(self.worst_ratio), "steps": self.steps,
                "wall_s": self.wall, "error": self.error, "capped_by_step_budget": self.capped}


@dataclass(frozen=True)
class CrossCheck:
    """The final comparison (None if every run failed), the attempts, the diagnosis of what
    missed, and the practical-settings table."""

    def __repr__(self) -> str:
        return f"CrossCheck({self.model!r}, ok={self.ok}, {len(self.attempts)} run(s), {len(self.diagnosis)} finding(s))"


    model: str
    comparison: Comparison | None
    attempts: tuple[Attempt, ...]
    diagnosis: tuple[Finding, ...]
    practical: tuple[PracticalRow, ...]
    prediction: Prediction | None = None  # before the first run (None: not modelled, e.g. a cam's contact)
    prediction_unavailable: str = ""  # why there is no prediction
    verdict: Verdict | None = None  # the compared run against the prediction

    @property
    def ok(self) -> bool:
        return self.comparison is not None and self.comparison.ok and not self.diagnosis

    @property
    def status(self) -> str:
        """"ok", "explained failure" (predicted to miss, and missed as predicted: within
        ``prediction.EXPLAINED_FACTOR``) or "failed"."""
        if self.ok:
            return "ok"
        return self.verdict.status if self.verdict is not None else "failed"

    def summary(self, wall: str | None = None) -> str:
        """One line; ``wall``: the wall time as the caller measured it (default: the runs')."""
        return headline(self.to_json(), wall)

    def to_dict(self) -> dict:
        """The result as ``linkgen validate --json`` gives it."""
        return self.to_json()

    @property
    def settings(self) -> Settings | None:
        """The settings of the run compared (None when every run failed)."""
        return None if self.comparison is None else self.comparison.run.settings

    @property
    def quantities(self) -> dict | None:
        """Each compared quantity as ``mujoco.result_shape`` gives it (the loop gap on its own)."""
        c = self.comparison
        return None if c is None else {k: q.to_json() for k, q in c.quantities.items() if k != "loop_gap"}

    @property
    def loop_gap(self) -> dict | None:
        """The largest loop gap [m], relative to the size, its tolerance, the crank angle φ [rad]
        where it is largest, and whether it holds."""
        c = self.comparison
        return None if c is None else loop_gap(c.gap.relative_error, c.gap.tolerance, max_m=c.gap.max_abs_error,
                                               phi=float(c.run.gap_max_at))

    def to_json(self) -> dict:
        """``mujoco.result_shape``'s keys (settings, quantities and loop_gap None when every run
        failed), then the run's own: scales, size, steps, the attempts, the practical settings."""
        out = validation(self.model, self.ok, settings=None if self.settings is None else self.settings.to_json(),
                         quantities=self.quantities, loop_gap=self.loop_gap, diagnosis=self.diagnosis)
        c = self.comparison
        if c is not None:
            run = c.run
            out |= {
                "scales": run.scales.to_json() if run.scales else None,
                "size_m": c.size,
                "steps": run.steps, "segments": run.segments, "wall_s": run.wall,
                "steps_per_revolution": steps_per_revolution(run),
                "settling_window_s": run.window,
                "samples_compared": int(run.samples.time.shape[0]),
                "left_out": [lo.to_json() for lo in run.left_out],
            }
        out["attempts"] = [a.to_json() for a in self.attempts]
        out["practical_settings"] = [r.to_json() for r in self.practical]
        out["status"] = self.status
        out["prediction"] = (self.prediction.to_json() | {"text": self.prediction.text()} if self.prediction
                             else {"unavailable": self.prediction_unavailable or "no run was derived"})
        if self.verdict is not None:
            out["prediction"] |= {"measured": self.verdict.to_json()["measured"],
                                  "measured_over_predicted": self.verdict.to_json()["measured_over_predicted"],
                                  "worst_factor": self.verdict.to_json()["worst_factor"]}
        out["best_achievable"] = self._best_achievable()
        return out

    def _best_achievable(self) -> dict | None:
        """What the compared run reached at its settings (the step budget's, when it binds): the
        loop gap, the worst quantity and the four predicted quantities' errors."""
        c = self.comparison
        if c is None:
            return None
        worst = max(c.quantities, key=lambda k: c.quantities[k].relative_error / c.quantities[k].tolerance)
        q = c.quantities[worst]
        return {"settings": c.run.settings.to_json(), "loop_gap_relative": c.gap.relative_error,
                "worst": worst, "worst_relative_error": q.relative_error, "worst_tolerance": q.tolerance,
                "errors": self.verdict.measured.to_dict() if self.verdict is not None else None}


def headline_worst(r: dict) -> tuple[str, float, float]:
    """The quantity a linkage's validate line names (``r``: ``CrossCheck.to_json``): the worst
    relative to its tolerance of every compared quantity and the loop gap (name, relative
    error, tolerance)."""
    q = {k: (v["relative_error"], v["tolerance"]) for k, v in r["quantities"].items()}
    q["loop gap"] = (r["loop_gap"]["relative"], r["loop_gap"]["tolerance"])
    worst = max(q, key=lambda k: q[k][0] / q[k][1] if q[k][1] > 0 else math.inf)
    return worst, *q[worst]


def headline(r: dict, wall: str | None = None) -> str:
    """The validate line of a linkage's check from its JSON (``CrossCheck.to_json``, with a
    machine's comparison joined: ``ok`` is then both): ok or FAIL, the worst quantity, the loop
    gap, the steps and ``wall`` (default: the runs' wall time)."""
    if not r.get("quantities"):  # no run compared anything: the diagnosis says why
        if r.get("status") != "explained failure":
            return "FAIL"
        what = "nothing left to compare" if (r.get("prediction") or {}).get("unsettled") else "the loops came apart"
        return f"FAIL (explained, as predicted): {what}"
    worst, err, tol = headline_worst(r)
    gap = worst == "loop gap"
    explained = r.get("status") == "explained failure"
    return (f"{'ok  ' if r['ok'] else 'FAIL (explained, as predicted)' if explained else 'FAIL'} worst {worst} {err:.2e} " + ("of the size " if gap else "")
            + f"(tolerance {tol:g}), " + ("" if gap else f"loop gap {r['loop_gap']['relative']:.1e} of the size, ")
            + f"{r['steps']} steps, {wall or format(r['wall_s'], '.2f') + ' s'}")


def _attempt(asm: Assembly, settings: Settings | None, progress, nthread,
             scales=None, max_steps: int = MAX_STEPS) -> tuple[Attempt, Comparison | None]:
    try:  # a run the step budget coarsens still runs: validate reports what it reaches there
        run = simulate(asm, settings=settings, progress=progress, nthread=nthread, scales=scales, max_steps=max_steps,
                       refuse_over_budget=False)
    except SimulationError as exc:
        scales = getattr(exc, "scales", None)
        return Attempt(getattr(exc, "settings", settings), False, "run", math.inf, 0, 0.0, str(exc),
                       bool(scales and scales.capped and settings is None), scales,
                       bool(getattr(exc, "nothing_to_compare", False))), None
    cmp = compare(asm, run)
    worst = max(cmp.quantities, key=lambda k: cmp.quantities[k].relative_error / cmp.quantities[k].tolerance)
    q = cmp.quantities[worst]
    return Attempt(run.settings, cmp.ok, worst, q.relative_error / q.tolerance, run.steps, run.wall,
                   capped=bool(run.scales.capped and settings is None), scales=run.scales), cmp


# Aim of a further run: the worst error at this fraction of its tolerance.
RETRY_MARGIN = 0.5
# Runs at most (the derived settings, then finer ones while the errors miss and fall).
MAX_ATTEMPTS = 3


def finer(settings: Settings, ratio: float, exponent: float, steps_per_segment: int,
          tau_floor: float = 0.0, max_steps: int = MAX_STEPS) -> Settings | None:
    """Settings for another run after a miss whose worst error was ``ratio`` × its tolerance,
    or None when the step budget allows none.

    Both τ and dt are divided by k = (ratio/margin)^(1/p), keeping dt/τ, where p is how the
    errors scale with τ: 2 for the loop gap (∝ τ²), as assumed for the first retry; measured
    from the two previous runs for the next (near an assembly limit the amplified errors went as
    τ^0.9 on the seven-link). The cost grows by k; τ stays above ``tau_floor``, the precision
    floor (``mujoco.settings.precision_floor``)."""
    k = (ratio / RETRY_MARGIN) ** (1.0 / exponent) if math.isfinite(ratio) else 4.0
    k = min(max(k, 2.0), max_steps / max(steps_per_segment, 1), settings.timeconst / max(tau_floor, 1e-300))
    if k < 1.5:
        return None
    k = math.ceil(k * 10) / 10
    return replace(settings, timeconst=settings.timeconst / k, timestep=settings.timestep / k,
                   label=f"after a miss: τ and timestep ÷{k:g}")


def crosscheck(asm: Assembly, *, practical: bool = True, progress=None, nthread: int | None = None,
               max_steps: int = MAX_STEPS) -> CrossCheck:
    """Validate ``asm`` in MuJoCo against the closed form (see the module docstring);
    ``max_steps``: the step budget of each run, per segment (``mujoco.settings.MAX_STEPS``);
    ``progress(fraction, seconds[, what])``: the validation runs' progress, then the
    practical-settings runs' (``what`` names them)."""
    first, cmp = _attempt(asm, None, progress, nthread, max_steps=max_steps)
    prediction, why_not = _predict(asm, first, max_steps, cmp.run.left_out if cmp is not None else ())
    attempts = [first]
    exponent = 2.0
    exhausted = False  # a finer run would pass the step budget or the float64 floor
    while (cmp is not None and not cmp.ok and len(attempts) < MAX_ATTEMPTS
           and not (cmp.run.scales and cmp.run.scales.capped)):
        last = attempts[-1]
        if len(attempts) >= 2:  # how the errors fell with τ between the last two runs
            prev = attempts[-2]
            drop = prev.worst_ratio / last.worst_ratio
            shrink = prev.settings.timeconst / last.settings.timeconst
            if not (drop > 1.2 and shrink > 1):
                break  # finer settings stopped helping
            exponent = min(max(math.log(drop) / math.log(shrink), 0.5), 4.0)
        nxt = finer(cmp.run.settings, last.worst_ratio, exponent, cmp.run.steps // max(cmp.run.segments, 1),
                    cmp.run.scales.tau_floor, max_steps)
        if nxt is None:
            exhausted = True
            break
        again, cmp2 = _attempt(asm, nxt, progress, nthread, cmp.run.scales, max_steps)
        attempts.append(again)
        if cmp2 is None:
            break
        cmp = cmp2
    findings: list[Finding] = []
    if cmp is not None and not cmp.ok:
        findings = diagnose(cmp, budget_exhausted=exhausted)
    elif cmp is None:
        findings = [Finding("run", [], math.inf, 0.0, "time budget" if first.capped else "run failed",
                            first.error or "")]
    rows = practical_study(asm, cmp.run.settings, nthread=nthread, scales=cmp.run.scales,
                           progress=progress) if (practical and cmp is not None) else []
    verdict_ = came_apart(prediction) if cmp is None and first.settings is not None else None
    if cmp is not None:
        from linkgen.mujoco.accuracy import sample_errors

        verdict_ = verdict(prediction, sample_errors(asm, cmp.run.samples), cmp.ok and not findings)
    return CrossCheck(asm.mechanism.name, cmp, tuple(attempts), tuple(findings), tuple(rows), prediction, why_not,
                      verdict_)


def _predict(asm: Assembly, first: Attempt, max_steps: int, left_out=()) -> tuple[Prediction | None, str]:
    """The prediction from the first run's derived settings and what they were derived from,
    over the angles the run compares (its settling windows, ``left_out``, follow from the
    settings): all fixed before its first step. None and why where it cannot be made."""
    from linkgen.errors import LinkgenError

    if first.settings is None or first.scales is None:
        return None, "the settings were not derived from the closed form (no scan of the loop forces)"
    try:
        return predict_run(asm, first.settings, first.scales, max_steps, left_out, first.nothing_to_compare), ""
    except LinkgenError as exc:
        return None, str(exc)
    except np.linalg.LinAlgError as exc:  # the constraint model has no solution at some scanned state
        return None, f"MuJoCo's constraint model could not be solved at the scanned states ({exc})"


__all__ = ["Attempt", "CrossCheck", "crosscheck", "finer", "headline", "headline_worst"]

"""One mechanism through MuJoCo and the closed form: settings derived, run, compared, retried
once with finer settings when it misses, failures diagnosed; plus what MuJoCo's usual settings
cost in accuracy (``practical``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .assembly import Assembly
from .compare import Comparison, compare
from .diagnose import Finding, diagnose
from .errors import SimulationError
from .mjsettings import MAX_STEPS, Settings
from .practical import PracticalRow, practical_study
from .simulate import simulate, steps_per_revolution


@dataclass(frozen=True)
class Attempt:
    """One run: its settings, whether everything held, the worst quantity (error/tolerance),
    steps and wall time [s], or the error that stopped it."""

    settings: Settings
    ok: bool
    worst: str
    worst_ratio: float
    steps: int
    wall: float
    error: str | None = None

    def to_json(self) -> dict:
        return {"settings": self.settings.to_json(), "ok": self.ok, "worst": self.worst,
                "worst_error_over_tolerance": self.worst_ratio, "steps": self.steps, "wall_s": self.wall,
                "error": self.error}


@dataclass(frozen=True)
class CrossCheck:
    """The final comparison (None if every run failed), the attempts, the diagnosis of what
    missed, and the practical-settings table."""

    model: str
    comparison: Comparison | None
    attempts: tuple[Attempt, ...]
    diagnosis: tuple[Finding, ...]
    practical: tuple[PracticalRow, ...]

    @property
    def ok(self) -> bool:
        return self.comparison is not None and self.comparison.ok and not self.diagnosis

    def to_json(self) -> dict:
        out: dict = {"model": self.model, "ok": self.ok}
        c = self.comparison
        if c is not None:
            run = c.run
            out |= {
                "settings": run.settings.to_json(),
                "scales": run.scales.to_json() if run.scales else None,
                "size_m": c.size,
                "steps": run.steps, "segments": run.segments, "wall_s": run.wall,
                "steps_per_revolution": steps_per_revolution(run),
                "settling_window_s": run.window,
                "samples_compared": int(run.samples.time.shape[0]),
                "left_out": [lo.to_json() for lo in run.left_out],
                "loop_gap": {"max_m": c.gap.max_abs_error, "relative": c.gap.relative_error,
                             "tolerance": c.gap.tolerance, "at_deg": math.degrees(run.gap_max_at), "ok": c.gap.ok},
                "quantities": {k: q.to_json() for k, q in c.quantities.items() if k != "loop_gap"},
            }
        out["diagnosis"] = [f.to_json() for f in self.diagnosis]
        out["attempts"] = [a.to_json() for a in self.attempts]
        out["practical_settings"] = [r.to_json() for r in self.practical]
        return out


def _attempt(asm: Assembly, settings: Settings | None, progress, nthread) -> tuple[Attempt, Comparison | None]:
    try:
        run = simulate(asm, settings=settings, progress=progress, nthread=nthread)
    except SimulationError as exc:
        s = settings or Settings(timestep=math.nan, timeconst=math.nan)
        return Attempt(s, False, "run", math.inf, 0, 0.0, str(exc)), None
    cmp = compare(asm, run)
    worst = max(cmp.quantities, key=lambda k: cmp.quantities[k].relative_error / cmp.quantities[k].tolerance)
    q = cmp.quantities[worst]
    return Attempt(run.settings, cmp.ok, worst, q.relative_error / q.tolerance, run.steps, run.wall), cmp


def finer(settings: Settings) -> Settings:
    """Half the loop time constant (a quarter of the gap) and a quarter of the timestep (a
    sixteenth of the integration error, which goes as (dt/τ)²): 4× the steps."""
    return replace(settings, timeconst=settings.timeconst / 2, timestep=settings.timestep / 4,
                   label="derived, τ/2 and dt/4 after a miss")


def crosscheck(asm: Assembly, *, practical: bool = True, progress=None, nthread: int | None = None) -> CrossCheck:
    """Validate ``asm`` in MuJoCo against the closed form (see the module docstring)."""
    first, cmp = _attempt(asm, None, progress, nthread)
    attempts = [first]
    if cmp is not None and not cmp.ok and not (cmp.run.scales and cmp.run.scales.capped):
        nxt = finer(first.settings)
        if cmp.run.steps * 4 <= MAX_STEPS * max(cmp.run.segments, 1):
            second, cmp2 = _attempt(asm, nxt, progress, nthread)
            attempts.append(second)
            if cmp2 is not None and (cmp2.ok or second.worst_ratio < first.worst_ratio):
                cmp = cmp2
    findings: list[Finding] = []
    if cmp is not None and not cmp.ok:
        findings = diagnose(cmp)
        tried = "; ".join(f"τ {a.settings.timeconst:g} s, dt {a.settings.timestep:g} s → worst {a.worst} "
                          f"{a.worst_ratio:.2g}× tolerance" for a in attempts)
        findings = [replace(f, detail=f"{f.detail} (runs: {tried})") for f in findings]
    elif cmp is None:
        findings = [Finding("run", [], math.inf, 0.0, "run failed", first.error or "")]
    rows = practical_study(asm, cmp.run.settings, nthread=nthread) if (practical and cmp is not None) else []
    return CrossCheck(asm.mechanism.name, cmp, tuple(attempts), tuple(findings), tuple(rows))


__all__ = ["Attempt", "CrossCheck", "crosscheck", "finer"]

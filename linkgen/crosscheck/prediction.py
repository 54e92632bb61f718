"""What a validation run can reach, predicted from the mechanism before any step, and the
verdict that compares the run with it.

MuJoCo's soft loops open by r = (1 − d)·d·τ²·A·λ (``mujoco.settings``): the derived settings pick
the loop time constant τ that holds the gap under its target, and the step budget (``max_steps``
per segment) caps the steps, so τ cannot go below STEPS_PER_TAU·duration/max_steps; float64's
rounding sets another floor on τ (``mujoco.settings.precision_floor``). Which of the two binds,
if either, and the errors MuJoCo is predicted to reach at the settings it will run with
(``mujoco.accuracy.predict``: MuJoCo's constraint model at the closed-form states) are the
prediction. A run that misses its tolerances is an *explained failure* when it was predicted to
miss and its measured loop gap and errors are within EXPLAINED_FACTOR of the predicted ones; any
other miss is a failure the prediction did not foresee.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkgen.mujoco.accuracy import QUANTITIES, Errors
from linkgen.mujoco.tolerances import FORCE_TOL, REL_TOL, gap_tolerance

# A miss counts as explained when every measured figure that misses is within this factor of
# its predicted value (issue 30's criterion; check-settings' predictions were measured within
# 3× on its corpus, docs/check-settings.md).
EXPLAINED_FACTOR = 3.0

BINDS = ("none", "step budget", "float64 floor")
# A run is predicted to come apart when its joints, at EXPLAINED_FACTOR times their predicted
# error, would move by this fraction of the size: the loop gap's linear model no longer holds
# there, and a run at the step budget stops at that gap (``mujoco.simulate.BUDGET_ABORT_CAP``).
APART = 0.05


@dataclass(frozen=True)
class Prediction:
    """Before the run: the loop time constant the mechanism needs [s] (``tau_needed``), the one
    the run uses (``tau_run``), float64's floor on it (``tau_floor``), the steps per revolution
    the needed τ takes and the step budget per segment, which limit binds (``BINDS``), the
    tolerances of the four quantities (``accuracy.QUANTITIES``) and the errors predicted at
    the run's settings."""

    binding: str
    tau_needed: float
    tau_run: float
    tau_floor: float
    steps_per_revolution_needed: float
    step_budget: int
    tolerances: Errors
    predicted: Errors
    # The settling windows after the load switches (the loops' slowest mode, fixed by the
    # settings) leave fewer than two samples to compare: the run can compare nothing.
    unsettled: bool = False

    @property
    def passes(self) -> bool:
        """Whether the run is predicted to pass: no limit binds and every predicted error is
        within its tolerance by the prediction's own factor (EXPLAINED_FACTOR). A prediction
        within that factor of a tolerance cannot tell a pass from a miss; it is not a pass, and
        a miss there is explained when measured within the factor."""
        return self.binding == "none" and not self.unsettled and all(EXPLAINED_FACTOR * getattr(self.predicted, q) <= getattr(self.tolerances, q)
                                              for q in QUANTITIES)

    @property
    def apart(self) -> bool:
        """Whether the loops are predicted to come apart: a limit binds and the joints'
        predicted error, within the prediction's factor, reaches APART of the size."""
        return self.binding != "none" and EXPLAINED_FACTOR * self.predicted.position >= APART

    def text(self) -> str:
        p = self.predicted
        if self.unsettled:
            return (f"predicted to leave nothing to compare: the loops settling after the start and the load switches cover "
                    f"every sample (their slowest mode at the run's τ = {self.tau_run:.3g} s); predicted loop gap "
                    f"{p.gap:.2g} of the size")
        if self.apart:
            return (f"predicted to come apart ({self.binding} binds: the loops need τ = {self.tau_needed:.3g} s, "
                    f"{self.steps_per_revolution_needed:.3g} steps per revolution; at the run's τ = {self.tau_run:.3g} s "
                    f"the joints are predicted {p.position:.2g} of the size off, where the soft loops' linear model "
                    f"ends); predicted loop gap {p.gap:.2g} of the size")
        over = any(getattr(p, q) > getattr(self.tolerances, q) for q in QUANTITIES)
        head = ("predicted to pass" if self.passes else
                f"{'predicted to miss' if over else 'predicted within its tolerances, though a limit binds'} "
                f"({self.binding} binds: the loops need τ = {self.tau_needed:.3g} s, "
                f"{self.steps_per_revolution_needed:.3g} steps per revolution; the run can use τ = {self.tau_run:.3g} s)"
                if self.binding != "none" else "predicted within the prediction's factor "
                f"{EXPLAINED_FACTOR:g} of a tolerance: it may miss")
        return (f"{head}; predicted loop gap {p.gap:.2g} of the size, positions {p.position:.2g}, "
                f"reactions {p.reaction:.2g}, crank torque {p.torque:.2g}")

    def to_json(self) -> dict:
        return {"binding": self.binding, "passes": self.passes, "apart": self.apart, "unsettled": self.unsettled, "tau_needed_s": _num(self.tau_needed),
                "tau_run_s": _num(self.tau_run), "tau_floor_s": _num(self.tau_floor),
                "steps_per_revolution_needed": _num(self.steps_per_revolution_needed),
                "step_budget": self.step_budget, "tolerances": self.tolerances.to_dict(),
                "predicted": self.predicted.to_dict()}


def _num(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def tolerances(sigma_min: float) -> Errors:
    """The four quantities' tolerances: the loop gap's derived from the positions' (its own
    ``gap_tolerance``), positions REL_TOL of the size, reactions and the crank torque FORCE_TOL
    of their peaks."""
    return Errors(gap_tolerance(sigma_min), REL_TOL, FORCE_TOL, FORCE_TOL)


def binding(scales, settings) -> str:
    """Which limit binds the run's loop time constant: the step budget (the derived settings
    were coarsened to it), float64's floor (the τ the gap needs is below it), or none."""
    if scales.capped:
        return "step budget"
    if min(scales.tau_gap, scales.tau_phase) < scales.tau_floor:
        return "float64 floor"
    return "none"


def predict_run(asm, settings, scales, step_budget: int, left_out=(), nothing_to_compare: bool = False) -> Prediction:
    """The prediction for a run of ``asm`` at ``settings`` derived with ``scales``
    (``mujoco.settings.derive``), over the crank angles the run compares (``left_out``: its
    settling windows, ``mujoco.windows.LeftOut``, fixed by the settings before any step;
    ``nothing_to_compare``: they cover every sample, which the run found before its first step):
    raises UnsupportedError for linkages ``mujoco.accuracy.predict`` does not model (cams, gears)."""
    from linkgen.mujoco.accuracy import predict
    from linkgen.mujoco.settings import STEPS_PER_TAU
    from linkgen.mujoco.simulate import SAMPLES
    from linkgen.mujoco.timing import switch_angles

    d = asm.mechanism.drive
    # A load switch steps the loop force, and the gap's rates (differences over the scan) straddle
    # it: the scan's samples within two steps of a switch carry a step over a sample spacing, an
    # artefact that grows with the samples (3e-5, 5.8e-5, 2.3e-4 at 240, 360, 720 on a press with
    # a stroke load). They are left out of the prediction, as the run's windows are.
    step = (d.stop - d.start) / SAMPLES
    windows = tuple((w.phi_from, w.phi_to) for w in left_out) + tuple(
        (sw - 2.0 * step, sw + 2.0 * step) for sw in switch_angles(asm.mechanism, d.start, d.stop))
    # at the run's own sample angles: a sharp peak of an error (near a dead centre) is then read
    # where the run reads it (on a coarser scan its maximum fell between scan angles: seed 162 of
    # the fidelity corpus, 3.1× under the run's maximum; 2.5× at the run's angles)
    acc = predict(asm, settings, omega=scales.omega, epsilon=asm.mechanism.drive.epsilon, left_out=windows, warm=True,
                  samples=SAMPLES)
    tau_needed = min(scales.tau_gap, scales.tau_phase)  # what the loops need, before any floor or budget
    per_rev = 2 * math.pi / max(scales.omega, 1e-300) * STEPS_PER_TAU / tau_needed
    return Prediction(binding(scales, settings), tau_needed, settings.timeconst, scales.tau_floor, per_rev,
                      int(step_budget), tolerances(scales.sigma_min), acc.errors, nothing_to_compare)


@dataclass(frozen=True)
class Verdict:
    """A run against its prediction: ``status`` is "ok", "explained failure" or "failed";
    ``measured`` the four quantities' errors the run reached (its best achievable at the
    budget), ``ratios`` measured over predicted for those compared (``compared``), and
    the worst such ratio (≥ 1, the larger of r and 1/r)."""

    status: str
    measured: Errors | None  # None: the run came apart before it could be compared
    ratios: dict
    worst_ratio: float

    def to_json(self) -> dict:
        return {"status": self.status, "measured": None if self.measured is None else self.measured.to_dict(),
                "measured_over_predicted": {k: _num(v) for k, v in self.ratios.items()},
                "worst_factor": _num(self.worst_ratio)}


def compared(prediction: Prediction, measured: Errors) -> tuple[str, ...]:
    """The quantities the verdict holds the prediction to: those that miss their tolerance, or
    were predicted to possibly miss it (EXPLAINED_FACTOR × predicted ≥ tolerance). One predicted
    and measured both within their tolerance by the factor is a pass either way: how far inside
    does not decide anything."""
    return tuple(q for q in QUANTITIES
                 if getattr(measured, q) > getattr(prediction.tolerances, q)
                 or EXPLAINED_FACTOR * getattr(prediction.predicted, q) >= getattr(prediction.tolerances, q))


def verdict(prediction: Prediction | None, measured: Errors, ok: bool) -> Verdict:
    """``ok``: the run's own comparison held. A miss is explained when it was predicted and every
    ``compared`` quantity was measured within EXPLAINED_FACTOR of its prediction, or, where the
    loops were predicted to come apart (``Prediction.apart``), when the joints were measured as
    far off as that prediction says (EXPLAINED_FACTOR × position error ≥ APART of the size)."""
    ratios: dict = {}
    if prediction is not None:
        for q in compared(prediction, measured):
            p, m = getattr(prediction.predicted, q), getattr(measured, q)
            ratios[q] = m / p if p > 0 else math.inf
    worst = max((max(r, 1.0 / r) if r > 0 else math.inf for r in ratios.values()), default=1.0)
    if ok:
        status = "ok"
    elif prediction is not None and prediction.apart and EXPLAINED_FACTOR * measured.position >= APART:
        status = "explained failure"  # the linear model's figures no longer hold: apart, as predicted
    elif prediction is not None and not prediction.passes and worst <= EXPLAINED_FACTOR:
        status = "explained failure"
    else:
        status = "failed"
    return Verdict(status, measured, ratios, worst)


def came_apart(prediction: Prediction | None) -> Verdict:
    """The verdict on a run that came apart or left nothing to compare (stopped before it could
    be compared): explained when that was predicted (``apart``, ``unsettled``), a failure
    otherwise."""
    explained = prediction is not None and (prediction.apart or prediction.unsettled)
    return Verdict("explained failure" if explained else "failed", None, {}, 1.0 if explained else math.inf)


__all__ = ["APART", "BINDS", "came_apart", "compared", "EXPLAINED_FACTOR", "Prediction", "Verdict", "binding", "predict_run",
           "tolerances", "verdict"]

"""``linkgen validate``'s prediction before the run (issue 30): the binding limit, the errors MuJoCo
is predicted to reach at the settings it runs with, the run at the step budget instead of a
refusal, and the verdict "ok" / "explained failure" / "failed"."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from linkgen.crosscheck.prediction import EXPLAINED_FACTOR, Prediction, verdict
from linkgen.crosscheck.run import crosscheck
from linkgen.families.planar.assembly import assemble
from linkgen.mujoco.accuracy import QUANTITIES, Errors
from linkgen.mujoco.tolerances import GAP_TOL, REL_TOL, gap_tolerance
from linkgen.pipeline.registry import from_dict, load

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
# Issue 30: a mechanism predicted to fail must miss within a factor 3 of the prediction.
FACTOR = 3.0
# A step budget small enough that the heavy slider-crank below cannot hold its loop (it needs
# ~1e5 steps per revolution at 60 rad/s): a cheap run that must end an explained failure.
SMALL_BUDGET = 4000


def heavy_slider_crank() -> dict:
    """A 20 kg block on a 50 g rod at 60 rad/s: loop forces large against the rod's inverse inertia."""
    return {
        "mechanism": {"name": "heavy_block", "gravity": [0.0, -9.81]},
        "points": {"O": [0.0, 0.0], "A": [0.05, 0.0], "B": [0.25, 0.0]},
        "links": {"ground": {"points": ["O"]},
                  "crank": {"points": ["O", "A"], "inertial": {"mass": 0.2, "com": [0.025, 0.0], "inertia": 1e-4}},
                  "rod": {"points": ["A", "B"], "inertial": {"mass": 0.05, "com": [0.1, 0.0], "inertia": 2e-4}},
                  "block": {"points": ["B"], "inertial": {"mass": 20.0, "com": [0.0, 0.0], "inertia": 0.01}}},
        "prismatic": {"guide": {"slider": "block", "guide": "ground", "point": "B", "through": "O"}},
        "drive": {"joint": "O", "omega": 60.0},
    }


def test_gap_tolerance_is_the_position_tolerance_times_sigma():
    # A gap r moves the joints by r/σ: r ≤ REL_TOL·σ keeps positions within REL_TOL; σ capped at 1.
    assert gap_tolerance(0.25) == pytest.approx(REL_TOL * 0.25, rel=1e-15)
    assert gap_tolerance(4.0) == REL_TOL
    assert gap_tolerance(float("nan")) == GAP_TOL


def test_an_easy_model_is_predicted_to_pass_and_passes():
    cc = crosscheck(assemble(load(MODELS / "fourbar.toml")), practical=False)
    out = cc.to_json()
    assert cc.status == "ok" and out["status"] == "ok"
    p = out["prediction"]
    assert p["binding"] == "none" and p["passes"] is True
    assert set(p["predicted"]) == set(QUANTITIES) == set(p["measured"])
    assert out["loop_gap"]["tolerance"] == pytest.approx(gap_tolerance(out["scales"]["sigma_min"]), rel=1e-12)
    for q in QUANTITIES:  # the prediction is close where it matters, not only within a factor 3
        if p["predicted"][q] > 0.1 * p["tolerances"][q]:
            assert 1 / FACTOR <= p["measured"][q] / p["predicted"][q] <= FACTOR, q
    assert out["best_achievable"]["loop_gap_relative"] == out["loop_gap"]["relative"]


@pytest.fixture(scope="module")
def heavy():
    return crosscheck(assemble(from_dict(heavy_slider_crank())), practical=False, nthread=1, max_steps=SMALL_BUDGET)


def test_a_mechanism_over_the_step_budget_runs_and_misses_as_predicted(heavy):
    out = heavy.to_json()
    assert heavy.prediction is not None and heavy.prediction.binding == "step budget"
    assert not heavy.prediction.passes
    assert heavy.comparison is not None, "it must run at the budget, not be refused"
    assert out["status"] == heavy.status == "explained failure"
    assert not heavy.ok
    assert 1.0 <= out["prediction"]["worst_factor"] <= FACTOR
    for q, ratio in out["prediction"]["measured_over_predicted"].items():
        assert 1 / FACTOR <= ratio <= FACTOR, q
    assert out["prediction"]["tau_needed_s"] < out["prediction"]["tau_run_s"]
    best = out["best_achievable"]
    assert best["loop_gap_relative"] > out["loop_gap"]["tolerance"]  # what MuJoCo reaches there, over it
    assert heavy.summary().startswith("FAIL (explained, as predicted)")


def test_the_cli_says_explained_and_exits_1(tmp_path):
    import tomlkit

    path = tmp_path / "heavy_block.toml"
    path.write_text(tomlkit.dumps(heavy_slider_crank()))
    cmd = [sys.executable, "-m", "linkgen", "validate", str(path), "--no-practical", "--max-steps", str(SMALL_BUDGET)]
    done = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert done.returncode == 1, done.stderr
    assert "FAIL (explained, as predicted)" in done.stdout
    assert "predicted to miss (step budget binds" in done.stdout
    done = subprocess.run(cmd + ["--json"], capture_output=True, text=True, timeout=300)
    r = json.loads(done.stdout)
    assert r["status"] == "explained failure" and r["prediction"]["binding"] == "step budget"


def _prediction(predicted: Errors, binding: str = "step budget") -> Prediction:
    return Prediction(binding, 1e-6, 1e-4, 1e-7, 1e6, 1000, Errors(1e-6, 1e-6, 1e-6, 1e-6), predicted)


def test_the_verdict_needs_the_miss_within_a_factor_3():
    pred = _prediction(Errors(1e-4, 1e-4, 1e-3, 1e-3))
    assert EXPLAINED_FACTOR == FACTOR
    assert verdict(pred, Errors(2e-4, 0.5e-4, 2.9e-3, 0.4e-3), ok=False).status == "explained failure"
    assert verdict(pred, Errors(1e-4, 1e-4, 3.1e-3, 1e-3), ok=False).status == "failed"  # reactions 3.1×
    assert verdict(pred, Errors(1e-4, 1e-4, 1e-3, 0.3e-3), ok=False).status == "failed"  # torque 1/3.3
    # predicted to pass, and missed: not explained, however close the figures
    passes = _prediction(Errors(1e-7, 1e-7, 1e-7, 1e-7), binding="none")
    assert passes.passes
    assert verdict(passes, Errors(1e-7, 1e-7, 2e-7, 1e-7), ok=False).status == "failed"
    assert verdict(None, Errors(1e-7, 1e-7, 2e-7, 1e-7), ok=False).status == "failed"
    assert verdict(passes, Errors(1e-7, 1e-7, 2e-7, 1e-7), ok=True).status == "ok"
    zero = _prediction(Errors(1e-4, 1e-4, 0.0, 1e-3))  # a figure predicted nil and measured over the tolerance
    v = verdict(zero, Errors(1e-4, 1e-4, 1e-3, 1e-3), ok=False)
    assert math.isinf(v.worst_ratio) and v.status == "failed"

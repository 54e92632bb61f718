"""The soft loops' slowest mode and what validate's prediction makes of it (issue 30): the lead-in
and settling windows last as long as that mode rings, the tracked gap's acceleration is not lost
in a stiff cancellation, a prediction near a tolerance is not a pass, and loops predicted to come
apart that come apart are an explained failure."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg

from linkgen.crosscheck.prediction import APART, EXPLAINED_FACTOR, Prediction, came_apart, verdict
from linkgen.crosscheck.run import crosscheck
from linkgen.families.planar.assembly import assemble
from linkgen.mujoco.accuracy import QUANTITIES, Errors
from linkgen.mujoco.gap_dynamics import gap_states
from linkgen.mujoco.loop_modes import decay_rate, slowest_share
from linkgen.mujoco.options import IMPEDANCE, PLACEHOLDER, Settings
from linkgen.pipeline.registry import load

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data"
# Issue 30: a run predicted to miss must miss within a factor 3 of the prediction.
FACTOR = 3.0
# The fidelity corpus' step budget (validation/fidelity_corpus.py): the heavy body below then
# runs at the budget, its loops' slowest mode at a share ρ ≈ 0.15 of the soft model.
CORPUS_BUDGET = 50_000


def test_decay_rate_is_the_slower_root_of_the_loop_mode():
    # s² + ρ·B·s + ρ·K·d = 0 with K = 1/(d²τ²ζ²), B = 2/(dτ): numpy's roots of the same polynomial.
    s = Settings(timestep=1e-5, timeconst=2e-4)
    d, tau = IMPEDANCE, s.timeconst
    for rho in (d, 0.5, 0.1, 1e-3):
        roots = np.roots([1.0, rho * 2.0 / (d * tau), rho / (d * tau * tau)])
        assert decay_rate(s, rho) == pytest.approx(min(-roots.real), rel=1e-6)
    assert decay_rate(s, d) == pytest.approx(1.0 / tau, rel=1e-6)  # the critically damped loop the settings aim at


def test_slowest_share_is_the_generalised_eigenvalue_of_a_and_a_plus_r():
    # ρ = min eig(A·(A + R)⁻¹) = min of the symmetric-definite pencil A·v = ρ·(A + R)·v (scipy's eigh).
    import mujoco

    from linkgen.mujoco.loop_terms import diag_approx
    from linkgen.mujoco.loops import closure_jacobian
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.state import joint_states

    asm = assemble(load(DATA / "heavy_body_light_rods.toml"))
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    phi = np.array([0.3, 2.0])
    qpos, qvel, _ = joint_states(asm, model, phi, np.full(2, 1.0), np.zeros(2))
    got = slowest_share(asm, model, qpos, qvel, IMPEDANCE)
    data = mujoco.MjData(model)
    want = []
    for k in range(2):
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        mujoco.mj_forward(model, data)
        jac = closure_jacobian(asm, model, data)
        m = np.zeros((model.nv, model.nv))
        for i in range(model.nv):  # M column by column (M·eᵢ), inverted densely: not mj_solveM's route
            e, col = np.zeros(model.nv), np.zeros(model.nv)
            e[i] = 1.0
            mujoco.mj_mulM(model, data, col, e)
            m[:, i] = col
        a = jac @ np.linalg.solve(m, jac.T)
        r = np.diag((1 - IMPEDANCE) / IMPEDANCE * diag_approx(asm, model, data))
        want.append(scipy.linalg.eigh(a, a + r, eigvals_only=True).min())
    assert got == pytest.approx(min(want), rel=1e-6)
    assert got < 0.5  # the heavy body on light rods: a slow mode, not the critically damped loop


def test_a_tracked_gap_has_the_acceleration_of_its_motion():
    # One loop row, stiff beside the crank (rate 1/τ ≫ ω), driven by r_λ = r0·sin(ωt): the exact
    # steady response of r̈ + B·ṙ + K·(r − r_λ) = 0 is r = H·r_λ, H = K/(K − ω² + iωB), so
    # a1 = r̈ = −ω²·r. Computed as g·(r_λ − r) − hd·s from the first-order lag, it came out (B²/K)·r̈_λ.
    tau, omega, r0 = 1e-4, 10.0, 1e-6
    h = tau / 20
    k_ref, b_ref = 1.0 / tau**2, 2.0 / tau
    t = np.linspace(0.0, 2 * math.pi / omega, 240, endpoint=False)
    n = t.shape[0]
    r_lam = (r0 * np.sin(omega * t))[:, None]
    g, hd = np.full((n, 1, 1), k_ref), np.full((n, 1, 1), b_ref)
    zero = np.zeros((n, 1))
    r, s, a1 = gap_states("RK4", r_lam, zero, zero, g, hd, h, t, omega, True, False)
    resp = k_ref / (k_ref - omega**2 + 1j * omega * b_ref)
    exact = (-omega**2 * r0 * np.imag(resp * np.exp(1j * omega * t)))
    # 240 samples a turn: the central difference of s is (2π/240)²/6 ≈ 1.1e-4 off; 1 % is ample.
    assert np.max(np.abs(a1[:, 0] - exact)) <= 1e-2 * np.max(np.abs(exact))


def _prediction(position: float, binding: str = "step budget", scale: float = 1.0) -> Prediction:
    tol = Errors(1e-6, 1e-6, 1e-6, 1e-6)
    pred = Errors(*(scale * 1e-6,) * 4) if binding == "none" else Errors(position, position, position, position)
    return Prediction(binding, 1e-6, 1e-5, 1e-7, 1e6, CORPUS_BUDGET, tol, pred)


def test_a_prediction_within_its_factor_of_a_tolerance_is_not_a_pass():
    assert _prediction(0.0, "none", 1.0 / (2 * EXPLAINED_FACTOR)).passes
    assert not _prediction(0.0, "none", 0.5).passes  # half the tolerance: a miss of 2× is within the factor
    assert "may miss" in _prediction(0.0, "none", 0.5).text()


def test_loops_predicted_to_come_apart_that_come_apart_are_explained():
    apart, holds = _prediction(APART / EXPLAINED_FACTOR * 1.01), _prediction(APART / EXPLAINED_FACTOR * 0.99)
    assert apart.apart and not holds.apart
    assert came_apart(apart).status == "explained failure"
    assert came_apart(holds).status == "failed" and came_apart(None).status == "failed"
    assert "come apart" in apart.text()


def test_a_heavy_body_on_light_rods_misses_as_predicted_from_its_first_sample():
    # Fidelity corpus seed 47: its slow loop mode (ρ ≈ 0.15) rang through the first samples
    # after a lead-in sized for the critically damped loop; their reactions were 380× the rest's
    # and 252× the prediction.
    cc = crosscheck(assemble(load(DATA / "heavy_body_light_rods.toml")), practical=False, nthread=1,
                    max_steps=CORPUS_BUDGET)
    out = cc.to_json()
    assert out["status"] == "explained failure", out["prediction"]
    ratios = out["prediction"]["measured_over_predicted"]
    assert set(ratios) == set(QUANTITIES)
    for q, r in ratios.items():
        assert 1 / FACTOR <= r <= FACTOR, (q, r)


def test_the_cli_says_the_loops_came_apart_as_predicted():
    # Fidelity corpus seed 195: a slow crank under gravity whose loops need 8e8 steps a turn.
    proc = subprocess.run([sys.executable, "-m", "linkgen", "validate", str(DATA / "slow_crank_apart.toml"),
                           "--max-steps", "50000", "--json"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr
    out = json.loads(proc.stdout)
    r = out["results"][0] if "results" in out else out
    assert r["status"] == "explained failure" and r["prediction"]["apart"] is True
    assert r["prediction"]["measured"] is None and r["best_achievable"] is None
    text = subprocess.run([sys.executable, "-m", "linkgen", "validate", str(DATA / "slow_crank_apart.toml"),
                           "--max-steps", "50000"], capture_output=True, text=True, timeout=300).stdout
    assert "came apart, as predicted" in text and "FAIL (explained, as predicted)" in text


def test_figures_inside_their_tolerance_by_the_factor_are_not_held_to_it():
    # Fidelity corpus seed 85: gap and positions missed as predicted (1.0×); reactions predicted
    # at 0.14 of their tolerance and measured at 1e-4 of it. Both pass; the miss is explained.
    pred = Prediction("step budget", 1e-6, 1e-4, 1e-7, 1e6, CORPUS_BUDGET, Errors(1e-6, 1e-6, 1e-6, 1e-6),
                      Errors(8.7e-6, 1.7e-5, 1.4e-7, 1.2e-7))
    v = verdict(pred, Errors(8.7e-6, 1.7e-5, 1.1e-10, 6.5e-11), ok=False)
    assert v.status == "explained failure" and set(v.ratios) == {"gap", "position"}
    # a figure predicted inside by the factor that then misses is held to its prediction
    assert verdict(pred, Errors(8.7e-6, 1.7e-5, 2e-6, 6.5e-11), ok=False).status == "failed"


def test_loops_predicted_apart_that_run_far_off_are_explained():
    apart = _prediction(0.1)
    assert verdict(apart, Errors(0.005, APART / EXPLAINED_FACTOR, 0.5, 0.2), ok=False).status == "explained failure"
    assert verdict(apart, Errors(1e-4, 1e-3, 1e-3, 1e-3), ok=False).status == "failed"  # far better than foreseen


def test_a_run_whose_settling_covers_every_sample_is_told_before_any_step():
    # Fidelity corpus seed 196: its slowest loop mode settles after the load switches for longer
    # than the range lasts. The run stops before its first step; the prediction says so.
    cc = crosscheck(assemble(load(DATA / "settling_covers_range.toml")), practical=False, nthread=1,
                    max_steps=CORPUS_BUDGET)
    out = cc.to_json()
    assert out["attempts"][0]["steps"] == 0 and "every sample falls in a settling window" in out["attempts"][0]["error"]
    assert out["prediction"]["unsettled"] is True and out["status"] == "explained failure"
    assert "nothing to compare" in out["prediction"]["text"]


def test_a_stroke_load_does_not_make_the_prediction_depend_on_its_sampling(monkeypatch):
    # A 500 kg ram on a light rod at 2 rpm under a 20 kN stroke load (written by a user for an
    # audit): the gap's rates straddled the load switches, and the predicted forces grew with the
    # samples (3e-5, 5.8e-5, 2.3e-4 at 240, 360, 720) where the run measured 2.3e-5 and 1.1e-5.
    import mujoco

    import linkgen.mujoco.simulate as simulate
    from linkgen.crosscheck.prediction import predict_run
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.settings import derive

    asm = assemble(load(DATA / "vertical_press_stroke.toml"))
    d = asm.mechanism.drive
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    settings, scales = derive(asm, model, omega=d.omega, duration=(d.stop - d.start) / d.omega, max_steps=1_000_000)
    got = []
    for n in (240, 720):
        monkeypatch.setattr(simulate, "SAMPLES", n)
        got.append(predict_run(asm, settings, scales, 1_000_000).predicted)
    for q in ("reaction", "torque"):
        # a quantity's maximum moves with the sampling by the curve's own variation, a few per cent
        assert getattr(got[1], q) == pytest.approx(getattr(got[0], q), rel=0.1), q

"""``linkgen check-settings``: the predicted accuracy at a user's MuJoCo settings against a run,
MuJoCo's constraint model as the prediction reads it, the cheapest settings it answers, and its
one-line refusals of bad options."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest

from linkgen.crosscheck.check_settings import AGREEMENT, check_settings, measure, user_settings
from linkgen.families.planar.assembly import assemble
from linkgen.mujoco.accuracy import QUANTITIES, effective_timeconst, predict
from linkgen.mujoco.gap_dynamics import impedance
from linkgen.pipeline.registry import load

MODELS = Path(__file__).resolve().parents[1] / "models"
# Issue 24: the prediction must be within a factor 3 of the measured value.
FACTOR = 3.0
# MuJoCo computes its impedance and gains in float64 from the same formulas: they agree to rounding.
MODEL_TOL = 1e-12
# A point's position read back from MuJoCo's body frames: float64 rounding of a metre-sized
# mechanism, a few 1e-16 (measured 5.6e-16).
ROUNDING_POSITION = 1e-14


@pytest.fixture(scope="module", params=["fourbar", "slider_crank_offset"])
def at_2ms(request):
    """One prediction and one run per model at 2 ms, implicitfast, MuJoCo's solref and solimp."""
    asm = assemble(load(MODELS / f"{request.param}.toml"))
    return check_settings(asm, user_settings(timestep=2e-3, integrator="implicitfast"), search=False)


def test_the_prediction_is_within_a_factor_3_of_the_run(at_2ms):
    assert AGREEMENT == FACTOR
    for q in QUANTITIES:
        p, m = getattr(at_2ms.predicted.errors, q), getattr(at_2ms.measured.errors, q)
        assert 1 / FACTOR <= p / m <= FACTOR, (at_2ms.model, q, p, m)
    assert all(at_2ms.agrees().values())
    assert "NOT within" not in at_2ms.text()


def test_the_prediction_takes_no_mujoco_step(monkeypatch):
    asm = assemble(load(MODELS / "fourbar.toml"))

    def refuse(*args, **kwargs):
        raise AssertionError("a MuJoCo step was taken")

    for name in ("mj_step", "mj_step1", "mj_step2", "mj_Euler", "mj_RungeKutta", "mj_implicit"):
        monkeypatch.setattr(mujoco, name, refuse)
    monkeypatch.setattr(mujoco.rollout, "rollout", refuse)
    p = predict(asm, replace(user_settings(timestep=2e-3, integrator="Euler"), armature=1e6), samples=24)
    assert all(np.isfinite(getattr(p.errors, q)) and getattr(p.errors, q) > 0 for q in QUANTITIES)


def test_a_linkage_without_loops_is_predicted_exact():
    # before: the prediction of a crank alone (no loop to close) failed on an empty array
    asm = assemble(load(MODELS / "dc_motor_startup.toml"))
    p = predict(asm, replace(user_settings(timestep=2e-3, integrator="RK4"), armature=1e6), samples=12)
    assert p.errors.gap == 0.0 and p.errors.reaction == 0.0 and p.errors.torque == 0.0
    assert p.errors.position < ROUNDING_POSITION


def test_a_time_constant_below_two_timesteps_predicts_as_two_timesteps():
    # MuJoCo's refsafe: solref's time constant is raised to 2·timestep (its XML reference).
    asm = assemble(load(MODELS / "fourbar.toml"))
    dt = 2e-3
    low = replace(user_settings(timestep=dt, integrator="RK4", solref=(1e-3, 1.0)), armature=1e6)
    clamped = replace(low, timeconst=2 * dt)
    assert effective_timeconst(low) == 2 * dt
    a, b = predict(asm, low, samples=24), predict(asm, clamped, samples=24)
    assert a.timeconst == 2 * dt
    assert a.errors == b.errors


_CONNECT = """<mujoco><option timestep="{dt}"/><worldbody>
  <body name="a"><joint name="ja" type="slide" axis="1 0 0"/><geom size="0.1" mass="2"/></body>
  <body name="b" pos="0 1 0"><joint name="jb" type="hinge" axis="0 0 1"/><geom size="0.1" pos="1 0 0" mass="3"/></body>
</worldbody><equality><connect body1="a" body2="b" anchor="0 0 0" solref="{tau} 0.7" solimp="{imp}"/></equality></mujoco>"""


@pytest.mark.parametrize("gap", [0.0, 2e-4, 5e-4, 8e-4, 3e-3])
def test_the_impedance_and_gains_are_mujocos(gap):
    imp = (0.9, 0.95, 0.001, 0.5, 2.0)
    dt, tau = 2e-3, 3e-3  # τ < 2·dt: MuJoCo uses 2·dt
    model = mujoco.MjModel.from_xml_string(_CONNECT.format(dt=dt, tau=tau, imp=" ".join(map(str, imp))))
    data = mujoco.MjData(model)
    data.qpos[0] = gap  # the slide opens the connect by ``gap`` along x
    mujoco.mj_forward(model, data)
    r = np.linalg.norm(data.efc_pos[:3])
    np.testing.assert_allclose(r, gap, atol=MODEL_TOL)
    d = float(impedance(imp, np.array([r]))[0])
    np.testing.assert_allclose(data.efc_KBIP[0, 2], d, rtol=MODEL_TOL)
    s = replace(user_settings(timestep=dt, integrator="Euler", solref=(tau, 0.7), solimp=imp))
    t = effective_timeconst(s)
    np.testing.assert_allclose(data.efc_KBIP[0, 0], 1 / (imp[1] ** 2 * t**2 * 0.7**2), rtol=MODEL_TOL)
    np.testing.assert_allclose(data.efc_KBIP[0, 1], 2 / (imp[1] * t), rtol=MODEL_TOL)


def test_the_cheapest_settings_meet_the_tolerance_when_run():
    asm = assemble(load(MODELS / "fourbar.toml"))
    tol = 1e-2
    result = check_settings(asm, user_settings(timestep=2e-3, integrator="Euler"), tolerance=tol)
    assert result.cheapest is not None, result.note
    chosen = result.cheapest.settings
    assert result.verified[-1].settings == chosen and result.verified[-1].errors.worst <= tol
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.options import PLACEHOLDER
    from linkgen.mujoco.settings import derive

    _, scales = derive(asm, mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER)), omega=10.0)
    run = measure(asm, chosen, scales)  # run again, apart from the search's own verification
    assert run.errors is not None and run.errors.worst <= tol, run
    # MuJoCo's defaults meet it here: the answer costs no more than they do
    assert result.measured.errors.worst <= tol
    assert result.cheapest.evaluations_per_second <= result.predicted.evaluations_per_second


@pytest.mark.parametrize("option, value, says", [
    ("--timestep", "0", "--timestep: must be > 0 s, got '0'"),
    ("--integrator", "foo", "--integrator: must be one of Euler, implicitfast, RK4, got 'foo'"),
    ("--solref", "a b", "--solref: expected two numbers: a time constant [s] and a damping ratio, got 'a b'"),
    ("--tolerance", "-1", "--tolerance: must be a relative error > 0, e.g. 1e-3, got '-1'"),
])
def test_a_bad_option_is_one_line(capsys, option, value, says):
    from linkgen.cli.main import main

    with pytest.raises(SystemExit) as exc:
        main(["check-settings", str(MODELS / "fourbar.toml"), option, value])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err, err


def test_spatial_and_cam_files_are_refused_in_one_line(capsys):
    from linkgen.cli.main import main

    for name, family in (("rssr", "spatial four-bars"), ("cam_translating", "stand-alone cams")):
        assert main(["check-settings", str(MODELS / f"{name}.toml")]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "check-settings` is for planar linkages" in err and family in err, err


def test_a_crank_that_does_not_turn_forwards_is_refused_before_any_prediction(tmp_path, capsys):
    # before: a header/prediction of "loop gap 8.3e+57 of the size" with overflow warnings, then the
    # run's refusal, and exit status 0
    from linkgen.cli.main import main

    text = (MODELS / "fourbar.toml").read_text()
    assert "omega = 10.0" in text
    bad = tmp_path / "backwards.toml"
    bad.write_text(text.replace("omega = 10.0", "omega = -8.0"))
    with _no_warning():
        assert main(["check-settings", str(bad), "--no-search"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err == f"linkgen: error: {bad}: drive.omega: must be > 0 rad/s for a MuJoCo run (it drives the crank " \
                  "forwards through its range), got -8.0\n"


class _no_warning:
    def __enter__(self):
        import warnings

        self._w = warnings.catch_warnings()
        self._w.__enter__()
        warnings.simplefilter("error")
        self._np = np.seterr(all="raise")

    def __exit__(self, *exc):
        np.seterr(**self._np)  # NumPy's own defaults back (underflow ignored)
        return self._w.__exit__(*exc)


def test_the_exit_status_says_when_a_prediction_misses_its_factor(capsys):
    # The press at 1 ms, RK4, solref 4 ms: its crank torque is predicted 3.15× the run's (measured
    # on this machine), past the factor 3 the command claims: status 1, and the row says so.
    from linkgen.cli.main import main

    status = main(["check-settings", str(MODELS / "press.toml"), "--timestep", "1ms", "--integrator", "RK4",
                   "--solref", "0.004 1", "--no-search"])
    out = capsys.readouterr().out
    assert "prediction NOT within a factor 3" in out
    assert status == 1
    assert main(["check-settings", str(MODELS / "fourbar.toml"), "--timestep", "2ms", "--no-search"]) == 0


def test_a_run_whose_crank_stalls_at_a_singular_pose_is_a_failed_run_not_a_traceback():
    # Generated seed 2 (ω 76.5 rad/s) at MuJoCo's defaults: its loops come apart and the crank
    # stops at 171.5°, where the closed form's PRP group is singular. Comparing raised there.
    from linkgen.families.planar.corpus import random_description
    from linkgen.pipeline.registry import from_dict

    asm = assemble(from_dict(random_description(np.random.default_rng(2))))
    got = check_settings(asm, user_settings(timestep=2e-3, integrator="Euler"), search=False).measured
    assert got.errors is None and "where the closed form cannot compare it" in got.failure

"""validate's honesty about cams and its own figures: a cam's MuJoCo step moves the follower only
by the forces acting at the step's start (no contact found only at a trial state of the step),
the step derived from the cam's motion, the diagnosis of a cam run that misses, the report's cam
section, the headline naming the failing quantity, one wall time per model, and progress of the
practical-settings runs. MuJoCo runs are a fraction of a turn."""

import math
import time
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
import pytest

from linkgen.families.cam.description import cam_from_dict
from linkgen.families.cam.kinetics import state

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"

# A user's cam (issue 21): oscillating roller follower, 20° cycloidal rise, 3-4-5 return, 300 rpm.
USER_CAM = {
    "mechanism": {"name": "user_cam", "title": "Oscillating roller follower, 300 rpm"},
    "cam": {"omega": "300rpm"},
    "follower": {"kind": "oscillating", "pivot_distance": 0.25, "arm_length": 0.25, "roller_radius": 0.04,
                 "lowest_angle": "27deg", "inertia": 0.05, "spring_rate": 200.0, "spring_preload": 100.0},
    "segment": [{"kind": "rise", "span": "120deg", "law": "cycloidal", "height": "20deg"},
                {"kind": "dwell", "span": "60deg"},
                {"kind": "return", "span": "120deg", "law": "poly345", "height": "20deg"},
                {"kind": "dwell", "span": "60deg"}],
}
# float64 rounding of v + h·a, relative to the follower's peak speed: a few ulps, with margin.
ROUNDING = 1e-12
# Textbook peaks (any cam-design text), per h/β² and h/β³: the cycloidal law's acceleration 2π
# exceeds the 3-4-5 law's 10√3/3, the 3-4-5 law's jerk 60 the cycloidal's 4π². Over the user's
# cam (both spans 120°, both heights 20°): max|q″|/max|q‴| = β·2π/60.
TIME_SCALE = 2 * math.pi / 60
# Sampling 3600 points a turn finds the peaks of |q″| and |q‴| to this relative accuracy (the
# peaks are smooth maxima: (Δθ/β)² ≈ 1e-4 at worst).
SAMPLED_PEAK = 1e-3


def _user_cam():
    return cam_from_dict(USER_CAM)


def test_a_step_starting_off_the_cam_moves_the_follower_by_the_free_forces_only():
    """Issue 21: one step starting with the roller off the cam changed the follower's speed from
    0.001 to −25.4 rad/s: RK4 found contacts at its trial states that the step's start had not.
    Over the first eighth of a turn, every step that starts with no contact changes the speed by
    h·(the acceleration at the step's start), to rounding."""
    from linkgen.mujoco.cam import CAM, FOLLOWER, cam_mjcf

    cm = _user_cam()
    model = mujoco.MjModel.from_xml_string(cam_mjcf(cm))
    data = mujoco.MjData(model)
    cam, fol = model.joint(CAM).dofadr[0], model.joint(FOLLOWER).dofadr[0]
    st = state(cm, [0.0])
    data.qpos[model.joint(FOLLOWER).qposadr[0]] = -st.displacement[0]
    data.qvel[cam], data.qvel[fol] = cm.omega, -st.velocity[0]
    h = model.opt.timestep
    peak = float(np.abs(state(cm, np.linspace(0, 2 * math.pi, 3600)).velocity).max())
    off, worst = 0, 0.0
    for _ in range(int(2 * math.pi / cm.omega / h / 8)):
        mujoco.mj_forward(model, data)
        v0, a0, touching = data.qvel[fol], data.qacc[fol], data.ncon > 0
        mujoco.mj_step(model, data)
        if not touching:
            off += 1
            worst = max(worst, abs(data.qvel[fol] - v0 - h * a0))
    assert off > 0  # the roller does leave the faceted profile between steps
    assert worst <= ROUNDING * peak


def test_the_step_comes_from_the_cams_fastest_motion():
    """The user's cam: the step is one STEPS_PER_SCALE-th of its time scale max|q″|/(max|q‴|·ω),
    shorter than one STEPS_PER_TURN-th of a turn."""
    from linkgen.mujoco.cam import STEPS_PER_SCALE, STEPS_PER_TURN, timestep

    cm = _user_cam()
    expected = TIME_SCALE * math.radians(120.0) / cm.omega / STEPS_PER_SCALE
    assert timestep(cm) == pytest.approx(expected, rel=SAMPLED_PEAK)
    assert timestep(cm) < 2 * math.pi / cm.omega / STEPS_PER_TURN


# Where MuJoCo's roller leaves the cam against where the closed form's force turns negative:
# measured 0.5° apart with the sphere roller (63.6° and 64.1°); 1° is twice that.
LEAVE_DEG = 1.0
# The free follower drifts past the displacement tolerance (2e-4 of the stroke) 3.7° of cam turn
# after leaving (measured: off at 63.6°, past the tolerance at 67.8°, the diagnosed range from
# 67.4°); 5° bounds it. (With the cylinder roller the bouncing put the miss before the leaving.)
DRIFT_DEG = 5.0


def test_a_cam_whose_spring_cannot_hold_the_follower_is_diagnosed():
    """Twice the leave speed: the run misses, and the diagnosis says where and that the closed
    form's follower leaves the cam (a quarter of a turn covers the rise's deceleration)."""
    from linkgen.families.cam.kinetics import leave_speed
    from linkgen.crosscheck.diagnose_cam import diagnose_cam
    from linkgen.mujoco.cam_run import compare_cam, run_cam

    slow = _user_cam()
    data = dict(USER_CAM, cam={"omega": 2 * leave_speed(slow)})
    cm = cam_from_dict(data)
    run = run_cam(cm, revolutions=0.25)
    r = compare_cam(cm, run=run)
    found = diagnose_cam(cm, run, r["errors_relative"], r["windows"])
    assert found and found[0].quantity == "followers.follower.angle"  # an oscillating follower: a rocker's angle
    assert found[0].cause == "follower leaves the cam"
    assert "spring" in found[0].detail
    ref = state(cm, run.theta % (2 * math.pi))
    deg = np.degrees(run.theta % (2 * math.pi))
    negative = deg[ref.contact_force < 0]
    # MuJoCo's roller leaves the cam where the closed form's contact force turns negative
    first_off = deg[~run.touching & (deg >= negative.min() - LEAVE_DEG)].min()
    assert abs(first_off - negative.min()) <= LEAVE_DEG
    lo, hi = (math.degrees(x) for x in found[0].ranges[0])
    # the miss starts there, or once the free follower has drifted by the tolerance
    assert negative.min() - LEAVE_DEG <= lo <= negative.min() + DRIFT_DEG


def _synthetic_fly_off(cm):
    """A run on the closed form except a fly-off: off the cam from 200° to 210°, the follower
    0.01 rad away, landing with an impact of 2 kN."""
    from linkgen.mujoco.cam_run import CamRun

    th = np.linspace(math.radians(45), math.radians(405), 20000, endpoint=False)
    ref = state(cm, th)
    q = cm.follower.output(th)[0].copy()
    touching = np.ones_like(th, dtype=bool)
    force = ref.contact_force.copy()
    deg = np.degrees(th) % 360
    off = (deg >= 200) & (deg < 210)
    q[off] += 0.01
    touching[off] = False
    force[off] = 0.0
    land = int(np.flatnonzero(off)[-1]) + 1
    force[land] = 2000.0
    return CamRun(th, np.full_like(th, cm.omega), q, force, ref.cam_torque, th.shape[0], 2 * math.pi / cm.omega / 20000,
                  ref.velocity, ref.acceleration, np.zeros_like(th), touching)


def test_a_fly_off_is_diagnosed_as_contact_lost_with_its_landing_impact():
    from linkgen.crosscheck.diagnose_cam import diagnose_cam
    from linkgen.mujoco.cam_run import compare_cam

    cm = _user_cam()
    run = _synthetic_fly_off(cm)
    r = compare_cam(cm, run=run)
    found = {f.quantity: f for f in diagnose_cam(cm, run, r["errors_relative"], r["windows"])}
    d = found["followers.follower.angle"]
    assert d.cause == "contact lost"
    lo, hi = (math.degrees(x) for x in d.ranges[0])
    assert 199.9 <= lo <= 200.1 and 209.8 <= hi <= 210.1
    assert "left the cam at 200.0" in d.detail and "impact of 2e+03 N" in d.detail


def test_the_report_has_a_section_for_a_stand_alone_cam(tmp_path):
    from linkgen.cli.mujoco import _summary, wall_text
    from linkgen.crosscheck.cam import CamCheck
    from linkgen.crosscheck.diagnose_cam import diagnose_cam
    from linkgen.report.figures_cam import plot_cam
    from linkgen.mujoco.cam import CAM_TOLERANCES
    from linkgen.mujoco.cam_run import compare_cam
    from linkgen.pipeline.registry import report_parts
    from linkgen.report.report import write_index

    cm = _user_cam()
    run = _synthetic_fly_off(cm)  # no MuJoCo needed to draw a run
    figs = plot_cam(cm, run, tmp_path)
    assert figs == ["user_cam_drawing.png", "user_cam_motion.png", "user_cam_forces.png"]
    for f in figs:
        assert (tmp_path / f).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    c = compare_cam(cm, run=run)
    check = CamCheck("user_cam", c, CAM_TOLERANCES, tuple(diagnose_cam(cm, run, c["errors_relative"], c["windows"])), run)
    r = {"file": "user_cam.toml", "family": "cam"} | check.to_dict() | {"figures": figs, "total_wall_s": 1.234,
                                                        "line": check.summary(wall_text(1.234))}
    text = write_index([r], tmp_path, 1.3, 1.0, report_parts).read_text()
    section = text[text.index("## user_cam (a cam)"):]
    for f in figs:
        assert f"![{f}]({f})" in section
    assert "contact lost" in section and "| `followers.follower.angle` |" in section
    line = _summary(r)
    assert "contact lost" in line and wall_text(1.234) in line and "| 1.23 |" in text


def test_the_headline_names_the_failing_loop_gap():
    from linkgen.crosscheck.run import headline

    r = {"model": "m", "ok": False, "steps": 10, "wall_s": 1.0,
         "quantities": {"points.B.position": {"relative_error": 5e-7, "tolerance": 1e-6}},
         "loop_gap": {"relative": 3e-8, "tolerance": 1e-8}}
    assert "worst loop gap 3.00e-08" in headline(r)


def test_the_validate_line_and_the_report_give_one_wall_time(tmp_path, monkeypatch):
    """A spatial model whose file took 5 s before its check began: the line and the report's
    table both give the whole validation's wall time."""
    import linkgen.cli.mujoco as cli_mujoco
    from linkgen.cli.mujoco import _check_one, _summary
    from linkgen.pipeline.registry import report_parts
    from linkgen.report.report import write_index

    class Clock:  # the validation's first reading of the clock 5 s early
        calls = 0

        @classmethod
        def perf_counter(cls):
            cls.calls += 1
            return time.perf_counter() - (5.0 if cls.calls == 1 else 0.0)

    monkeypatch.setattr(cli_mujoco, "time", Clock)
    r = _check_one(MODELS / "bennett.toml", None, True, None, False)
    shown = f"{r['total_wall_s']:.2f}"
    assert r["total_wall_s"] > 5.0
    assert f"validated in {shown} s" in _summary(r)
    assert f"| {shown} |" in write_index([r], tmp_path, 1.0, 1.0, report_parts).read_text()


def test_the_practical_settings_runs_report_progress(monkeypatch):
    from linkgen import assemble, load
    from linkgen.crosscheck import practical
    from linkgen.mujoco.mjcf import settings_for

    asm = assemble(load(MODELS / "fourbar.toml"))
    monkeypatch.setattr(practical, "PROGRESS_AFTER", 0.0)
    calls = []
    rows = practical.practical_study(asm, settings_for(asm), progress=lambda f, t, what: calls.append((f, what)))
    assert len(rows) == len(practical.ladder(settings_for(asm)))
    assert calls and calls[-1][0] == pytest.approx(1.0)
    assert all(w == "practical-settings runs" for _, w in calls)
    assert [f for f, _ in calls] == sorted(f for f, _ in calls)


def test_a_knife_edges_small_roller_starts_on_the_profile_not_in_it():
    """MuJoCo gives a knife edge a roller of KNIFE_RADIUS of the base circle: the profile mesh is
    offset by that radius, so the follower placed at its closed-form state touches the profile
    (it sat the whole radius deep, and was thrown off the cam at the first step)."""
    from linkgen.mujoco.cam import FOLLOWER, KNIFE_RADIUS, PROFILE_POINTS, cam_mjcf

    data = dict(USER_CAM, follower=dict(USER_CAM["follower"], roller_radius=0.0))
    cm = cam_from_dict(data)
    model = mujoco.MjModel.from_xml_string(cam_mjcf(cm))
    d = mujoco.MjData(model)
    d.qpos[model.joint(FOLLOWER).qposadr[0]] = -state(cm, [0.0]).displacement[0]
    mujoco.mj_forward(model, d)
    # the profile polygon's chord sag, L²/(8ρ) with L its longest edge and ρ its least radius of
    # curvature, bounds how far the true profile lies inside it
    th = np.linspace(0.0, 2 * math.pi, PROFILE_POINTS, endpoint=False)
    pitch = cm.follower.pitch_curve(th)[0]  # a knife edge's profile; the mesh's lies inside it, edges no longer
    edge = float(np.hypot(*np.diff(pitch, axis=0).T).max())
    sag = edge**2 / (8 * float(cm.follower.pitch_curvature_radius(th).min() - KNIFE_RADIUS * cm.follower.base_radius))
    assert d.ncon >= 1
    assert min(-d.contact[i].dist for i in range(d.ncon)) <= sag


def test_a_cam_linkage_run_that_misses_is_diagnosed():
    """A cam on a linkage's crank: the same diagnosis, on the cam's contact (a synthetic run: the
    roller off the cam from 100° to 104°, the follower's displacement off by 1e-3 of its stroke)."""
    from linkgen.cli.mujoco import _summary
    from linkgen.crosscheck.diagnose_cam import cam_linkage_findings
    from linkgen.mujoco.cam_linkage import CamLinkageCheck

    n = 36000
    th = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    deg = np.degrees(th)
    off = (deg >= 100) & (deg < 104)
    force = np.where(off, 0.0, 50.0)
    curves = {"followers.follower.displacement": np.where(off, 1e-3, 1e-5), "contact.disc.normal_force": np.full(n, 1e-2),
              "points": np.full(n, 1e-5), "balancing_torque": np.full(n, 1e-2)}
    errors = {k: (float(v.max()), 2e-4 if k in ("followers.follower.displacement", "points") else 0.07)
              for k, v in curves.items()}
    contacts = {"disc": {"theta": th, "touching": ~off, "force": force, "force_closed": np.full(n, 50.0),
                         "penetration": np.zeros(n), "step_angle": 2 * math.pi / n, "travel": 0.1}}
    r = CamLinkageCheck("rocker", errors, n, 1e-5, 1.0, curves, contacts)
    found = cam_linkage_findings(r)
    assert [f.quantity for f in found] == ["followers.follower.displacement"]
    assert found[0].cause == "contact lost" and "left the cam at 100.0" in found[0].detail
    assert "landed at 104.00°" in found[0].detail
    line = _summary(replace(r, diagnosis=tuple(found)).to_dict() | {"line": r.summary("1 s"), "total_wall_s": 1.0})
    assert "followers.follower.displacement" in line.splitlines()[1] and "contact lost" in line


def test_a_cam_run_reports_progress(monkeypatch):
    from linkgen.mujoco import options
    from linkgen.mujoco.cam_run import run_cam

    monkeypatch.setattr(options, "PROGRESS_AFTER", 0.0)
    calls = []
    run_cam(_user_cam(), revolutions=0.25, progress=lambda f, t: calls.append(f))
    assert calls and all(0 < f < 1 for f in calls) and calls == sorted(calls)


def test_a_run_that_cannot_advance_is_diagnosed_without_a_crash():
    """A trace whose steps turned the cam by no measurable angle (a spring of 2e15 N/m, fuzz
    campaign seed 2029) is diagnosed, not divided by zero."""
    import numpy as np

    from linkgen.crosscheck import diagnose_cam

    assert diagnose_cam._steps(0.1, type("T", (), {"step_angle": 0.0})()) == 0
    assert diagnose_cam._steps(0.1, type("T", (), {"step_angle": 0.01})()) == 10
    assert np.isfinite(diagnose_cam.LOOK_BACK)

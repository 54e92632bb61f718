"""Cam descriptions end to end: the follower's motion against finite differences of its
displacement, the inversion geometry (the roller touches the profile, the oscillating arm keeps
its length), the cam torque by power against its moment from the contact force, the leave speed
against the contact force's sign, the textbook's oscillating follower, bad files, the command
line, and MuJoCo's contact model within its measured tolerance."""

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from linkgen.families.cam.description import cam_from_dict
from linkgen.pipeline.registry import load
from linkgen.families.cam.kinetics import leave_speed, state
from linkgen.errors import DescriptionError
from independent_checks import zoomed_peak

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
CAMS = ["cam_translating", "cam_oscillating", "cam_flat_face"]
SCRIPT = shutil.which("linkgen", path=str(Path(sys.executable).parent))
# Central differences with step h of a smooth function: truncation h²/6·f‴ ≈ 1e-10 relative at
# h = 1e-5 rad, rounding 1e-16/h² on the second derivative: 1e-6 relative bounds both.
FD_TOL = 1e-6


@pytest.mark.parametrize("name", CAMS)
def test_motion_against_finite_differences(name):
    cm = load(MODELS / f"{name}.toml")
    w, h = 3.0, 1e-5
    th = np.linspace(0.05, 2 * math.pi - 0.05, 97)
    joints = np.cumsum([seg.span for seg in getattr(cm.follower.program, "segments", ())])
    th = th[np.all([np.abs(th - b) > 1e-3 for b in joints], axis=0)] if joints.size else th  # segment joints
    q = lambda t: cm.follower.output(t)[0]  # noqa: E731
    st = state(cm, th, w)
    v_fd = (q(th + h) - q(th - h)) / (2 * h) * w
    a_fd = (q(th + h) - 2 * q(th) + q(th - h)) / h**2 * w * w
    j_fd = (state(cm, th + h, w).acceleration - state(cm, th - h, w).acceleration) / (2 * h) * w
    scale = lambda x: max(float(np.abs(x).max()), 1e-12)  # noqa: E731
    assert np.abs(st.velocity - v_fd).max() <= FD_TOL * scale(st.velocity)
    assert np.abs(st.acceleration - a_fd).max() <= 1e3 * FD_TOL * scale(st.acceleration)  # h² rounding
    assert np.abs(st.jerk - j_fd).max() <= FD_TOL * scale(st.jerk)


@pytest.mark.parametrize("name", CAMS)
def test_the_roller_touches_the_profile_and_the_arm_keeps_its_length(name):
    cm = load(MODELS / f"{name}.toml")
    f = cm.follower
    th = np.linspace(0, 2 * math.pi, 721)
    pitch, profile = f.pitch_curve(th)[0], f.profile(th)
    # every profile point is a roller radius from the pitch curve, and none is closer (a dense check)
    dense = f.pitch_curve(np.linspace(0, 2 * math.pi, 20001))[0]
    d = np.sqrt(((profile[:, None, :] - dense[None, ::10, :]) ** 2).sum(-1)).min(axis=1)
    assert np.abs(np.hypot(*(profile - pitch).T) - f.roller_radius).max() < 1e-12
    assert d.min() > f.roller_radius - 1e-6
    c = f.centre(th)[0]
    if f.kind == "oscillating":
        assert np.abs(np.hypot(c[:, 0] - f.pivot_distance, c[:, 1]) - f.arm_length).max() < 1e-12
        # the textbook's law: ψ = π/4 + (π/10)·sin θ, the angle at the pivot from the line to the cam's axis
        psi = np.arctan2(c[:, 1], f.pivot_distance - c[:, 0])
        assert np.abs(psi - (math.pi / 4 + math.pi / 10 * np.sin(th))).max() < 1e-12
    # the pitch curve turned back by θ is the roller centre in the fixed frame
    back = np.column_stack([np.cos(th) * pitch[:, 0] - np.sin(th) * pitch[:, 1],
                            np.sin(th) * pitch[:, 0] + np.cos(th) * pitch[:, 1]])
    assert np.abs(back - c).max() < 1e-12


@pytest.mark.parametrize("name", CAMS)
def test_cam_torque_by_power_equals_the_contact_forces_moment(name):
    cm = load(MODELS / f"{name}.toml")
    th = np.linspace(0, 2 * math.pi, 1441)
    st = state(cm, th)
    c, n = cm.follower.centre(th)[0], cm.follower.normal(th)
    moment = st.contact_force * (c[:, 0] * n[:, 1] - c[:, 1] * n[:, 0])
    assert np.abs(moment - st.cam_torque).max() <= 1e-12 * np.abs(st.cam_torque).max()


@pytest.mark.parametrize("name", CAMS)
def test_leave_speed_is_where_the_contact_force_reaches_zero(name):
    cm = load(MODELS / f"{name}.toml")
    w = leave_speed(cm)
    th = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    assert state(cm, th, 0.999 * w).contact_force.min() > 0
    assert state(cm, th, 1.001 * w).contact_force.min() < 0


def test_bad_cam_files_name_the_field(tmp_path):
    base = {"mechanism": {"name": "c"}, "cam": {"base_radius": 0.2, "omega": 1.0},
            "follower": {"kind": "translating", "roller_radius": 0.02},
            "segment": [{"kind": "rise", "span": "180deg", "law": "harmonic", "height": 0.02},
                        {"kind": "return", "span": "180deg", "law": "cycloidal", "height": 0.02}]}
    assert cam_from_dict(base).follower.kind == "translating"
    cases = [({"follower": {"kind": "sliding"}}, "follower.kind"),
             ({"segment": base["segment"][:1]}, "360°"),
             ({"segment": [dict(base["segment"][0], law="parabolic"), base["segment"][1]]}, "segment[0].law"),
             ({"cam": {"base_radius": 0.2, "omega": -1.0}}, "cam.omega"),
             ({"follower": {"kind": "translating", "offset": 0.5}}, "offset"),
             ({"follower": {"kind": "translating", "arm_length": 0.5}}, "follower.arm_length"),
             ({"law": {"kind": "sine", "amplitude": 0.01}}, "not both")]
    for change, words in cases:
        with pytest.raises(DescriptionError, match=words.replace("[", r"\[").replace("]", r"\]")):
            cam_from_dict({**base, **change})


def test_cam_command_line(tmp_path):
    p = subprocess.run([SCRIPT, "analyze", MODELS / "cam_translating.toml", "--angle", "30deg", "--omega", "1",
                        "--json"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    f = json.loads(p.stdout)["followers"]["follower"]
    assert set(f) >= {"displacement", "velocity", "acceleration", "jerk", "pressure_angle"}
    # a harmonic rise of 0.05 m over 120°: at 30°, s = 0.025·(1 − cos 45°), v = 0.025·(π/(2π/3))·sin 45°
    assert f["displacement"] == pytest.approx(0.025 * (1 - math.cos(math.pi / 4)), rel=1e-12)
    assert f["velocity"] == pytest.approx(0.025 * 1.5 * math.sin(math.pi / 4), rel=1e-12)
    p = subprocess.run([SCRIPT, "profile", MODELS / "cam_oscillating.toml", "-o", tmp_path / "p.csv", "--points", "90"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and len((tmp_path / "p.csv").read_text().splitlines()) == 91
    p = subprocess.run([SCRIPT, "draw", MODELS / "cam_oscillating.toml", "--angles", "0:360:45", "-o", tmp_path / "c.png"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and (tmp_path / "c.png").stat().st_size > 10_000
    p = subprocess.run([SCRIPT, "analyze", MODELS / "cam_translating.toml", "--summary"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "leaves the cam above" in p.stdout


def test_a_flat_face_touches_its_profile_at_ds_dtheta():
    """A flat face's height at every cam angle is the profile's support function in its
    direction (the envelope), reached at the point x = ds/dθ from the follower's axis."""
    cm = load(MODELS / "cam_flat_face.toml")
    f = cm.follower
    th = np.linspace(0, 2 * math.pi, 2001)
    prof = f.profile(np.linspace(0, 2 * math.pi, 20001))
    for t in th[::40]:
        up = np.array([math.sin(t), math.cos(t)])  # the face's normal in the cam's frame
        assert float((prof @ up).max()) == pytest.approx(f.base_radius + float(f.output([t])[0][0]), abs=1e-7)
    c = f.centre(th)[0]
    assert np.abs(c[:, 0] - f.output(th)[1]).max() == 0.0
    assert np.all(state(cm, th).pressure_angle == 0.0)


def test_modified_trapezoid_meets_its_textbook_figures():
    """Peak acceleration 4.888·h/β², peak velocity 2·h/β, the rise ends at h with zero speed."""
    from linkgen.families.cam.laws import rise

    x = np.linspace(0, 1, 8001)
    s, v, a, _ = rise("modtrap", x)
    assert s[-1] == pytest.approx(1.0, abs=1e-15) and abs(v[-1]) < 1e-12 and abs(a[-1]) < 1e-12
    assert a.max() == pytest.approx(4.888, abs=5e-4) and v.max() == pytest.approx(2.0, abs=1e-9)
    h = 1e-6
    inner = x[(x > 1e-3) & (x < 1 - 1e-3)]
    assert np.abs((rise("modtrap", inner + h)[0] - rise("modtrap", inner - h)[0]) / (2 * h)
                  - rise("modtrap", inner)[1]).max() < 1e-8


def test_cam_in_mujoco_within_its_measured_tolerance():
    from linkgen.mujoco.cam import CAM_TOLERANCES
    from linkgen.mujoco.cam_run import compare_cam

    r = compare_cam(load(MODELS / "cam_translating.toml"))
    for k, tol in CAM_TOLERANCES.items():
        assert r["errors_relative"][k] <= tol, (k, r["errors_relative"])


def test_smallest_base_circle_meets_the_pressure_angle():
    """By the generic follower and by the translating cam's own bisection (two codes, two grids):
    the same radius, and at it the largest pressure angle is the limit."""
    from dataclasses import replace

    from linkgen.families.cam.follower import smallest_base_radius
    from linkgen.families.cam.profile import min_base_radius

    f = load(MODELS / "cam_translating.toml").follower
    limit = math.radians(30.0)
    rb = smallest_base_radius(f, limit)
    assert rb == pytest.approx(min_base_radius(f.program, limit, f.roller_radius, f.offset), rel=1e-6)
    th = np.linspace(0, 2 * math.pi, 200_000, endpoint=False)

    def worst(follower):  # the largest |α| by a dense scan zoomed in on its best sample
        def alpha(x):
            return np.abs(follower.pressure_angle(x))
        return zoomed_peak(alpha, th, alpha(th))

    assert worst(replace(f, base_radius=rb)) == pytest.approx(limit, abs=1e-12)
    # the textbook's oscillating follower (pivot and arm 0.25 m) reaches 40.8°; at 45° a smaller
    # base circle still holds, and at it the largest pressure angle is the limit
    osc = load(MODELS / "cam_oscillating.toml").follower
    rb = smallest_base_radius(osc, math.radians(45.0))
    assert rb < osc.base_radius
    assert worst(replace(osc, base_radius=rb)) == pytest.approx(math.radians(45.0), abs=1e-12)

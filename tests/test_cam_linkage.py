"""A cam on the crank driving a follower link that carries further Assur groups ([cam.NAME]):
the linkage form of the stand-alone cams against their own closed form, the sketch's sense of
rising, the follower's spring, MuJoCo's contact run, the CLI and the errors."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import linkgen
from linkgen.families.cam.kinetics import state
from linkgen.errors import DescriptionError, SimulationError
from linkgen.families.planar.assembly import assemble
from linkgen.families.planar.cam_pair import contact, lift
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces

from conftest import ROOT

# The same mechanism by two closed forms (the stand-alone cam's follower geometry in its own
# frame, and the linkage's world-frame jets and pitch-curve normal): they differ by rounding of
# a few operations on numbers of order one — 1e-9 of each quantity's peak leaves a wide margin
# and still catches any wrong term, which shows at the size of the quantity itself.
SAME_TOL = 1e-9
TURN = np.linspace(0.0, 2 * math.pi, 361)[:-1]

# The cam's own link (balanced: its centre of mass on the axis) and the drive, shared by both.
CAM_LINK = """[links.cam]
points = ["O", "K"]
[links.cam.inertial]
mass = 1.0
com = [0.0, 0.0]
inertia = 0.001
"""
DRIVE = """[drive]
joint = "O"
omega = 10.0
"""

OSCILLATING = """
[mechanism]
name = "cam_oscillating_as_linkage"

[points]
O = [0.0, 0.0]
K = [0.1, 0.0]
P = [0.25, 0.0]
C = [{cx!r}, {cy!r}]

[links.ground]
points = ["O", "P"]

{cam_link}
[links.follower]
points = ["P", "C"]
[links.follower.inertial]
mass = 1.0
com = [0.0, 0.0]
inertia = 0.05

[cam.disc]
follower = "follower"
roller = "C"
roller_radius = 0.04
spring_rate = 20.0
spring_preload = 10.0

[cam.disc.law]
kind = "sine"
amplitude = "18deg"
mean = "45deg"

{drive}"""

TRANSLATING = """
[mechanism]
name = "cam_translating_as_linkage"

[points]
O = [0.0, 0.0]
K = [0.1, 0.0]
Q = [0.1, 0.0]
C = [0.1, {cy!r}]

[links.ground]
points = ["O", "Q"]

{cam_link}
[links.follower]
points = ["C"]
[links.follower.inertial]
mass = 2.0
com = [0.0, 0.0]
inertia = 0.001

[prismatic.stem]
slider = "follower"
guide = "ground"
point = "C"
through = "Q"
angle = "90deg"

[cam.disc]
follower = "follower"
roller = "C"
roller_radius = 0.04
spring_rate = 2000.0
spring_preload = 40.0

[[cam.disc.segment]]
kind = "rise"
span = "120deg"
law = "harmonic"
height = 0.05

[[cam.disc.segment]]
kind = "dwell"
span = "60deg"

[[cam.disc.segment]]
kind = "return"
span = "120deg"
law = "harmonic"
height = 0.05

[[cam.disc.segment]]
kind = "dwell"
span = "60deg"

{drive}"""


def _oscillating_text() -> str:
    psi = math.pi / 4  # the sine law's value at θ = 0: the sketch shows the follower there
    return OSCILLATING.format(cx=0.25 - 0.25 * math.cos(psi), cy=0.25 * math.sin(psi), cam_link=CAM_LINK, drive=DRIVE)


def _translating_text() -> str:
    return TRANSLATING.format(cy=math.sqrt(0.29**2 - 0.1**2), cam_link=CAM_LINK, drive=DRIVE)  # the roller on the base circle


def _load(tmp_path, text: str, name: str = "m.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return linkgen.load(path), path


@pytest.mark.parametrize("kind", ["oscillating", "translating"])
def test_the_linkage_form_of_a_cam_equals_the_stand_alone_cam(tmp_path, kind):
    """The bundled cams written as linkages: follower motion, pressure angle, contact force and
    the torque on the cam agree with the stand-alone cam's closed form."""
    text = _oscillating_text() if kind == "oscillating" else _translating_text()
    mech, _ = _load(tmp_path, text)
    cm = linkgen.load(ROOT / "models" / f"cam_{kind}.toml")
    ref = state(cm, TURN)
    asm = assemble(mech)
    kin = solve(asm, TURN)
    cam = mech.cams[0]
    w = cm.omega
    d0, d1, d2, d3 = lift(cam, TURN)
    lowest = cm.follower.output(np.zeros(1))[0][0]  # the stand-alone coordinate at θ = 0
    for got, want in ((d0 + lowest, ref.displacement), (d1 * w, ref.velocity), (d2 * w * w, ref.acceleration),
                      (d3 * w**3, ref.jerk), (contact(kin, cam)[2], ref.pressure_angle)):
        assert np.abs(got - want).max() <= SAME_TOL * max(np.abs(want).max(), 1.0)
    # the follower's link really moves that way: its angle or its roller centre, from the closed form
    if kind == "oscillating":
        turned = kin.links["follower"].angle.v - asm.shapes["follower"].sketch_angle
        assert np.abs(np.abs(turned) - np.abs(d0)).max() <= SAME_TOL
    else:
        assert np.abs(kin.points["C"].p[:, 1] - kin.points["C"].p[0, 1] - d0).max() <= SAME_TOL
    f = forces(asm, TURN, w, 0.0)
    for got, want in ((f.contact["disc"], ref.contact_force), (f.balancing_torque, ref.cam_torque)):
        assert np.abs(got - want).max() <= SAME_TOL * np.abs(want).max()


def test_the_bundled_cam_linkage_balances_by_virtual_work():
    """cam_rocker_slider: the group-by-group torque (through the contact force) equals the power
    balance, which never sees the contact force; the contact force pushes (N > 0) all round."""
    asm = assemble(linkgen.load(ROOT / "models" / "cam_rocker_slider.toml"))
    f = forces(asm, TURN, 10.0, 0.0)
    scale = np.abs(f.power_balance_torque).max()
    assert np.abs(f.balancing_torque - f.power_balance_torque).max() <= SAME_TOL * scale
    assert f.contact["disc"].min() > 0


def test_the_roller_centre_keeps_off_the_profile_by_its_radius():
    """Every roller position over a turn, seen from the cam, is the roller's radius from the
    profile polygon (the profile is the pitch curve's inner offset)."""
    from linkgen.families.planar.cam_profile import profile

    asm = assemble(linkgen.load(ROOT / "models" / "cam_rocker_slider.toml"))
    cam = asm.mechanism.cams[0]
    prof = profile(asm, cam, 20000)
    kin = solve(asm, TURN)
    ang = kin.links["cam"].angle.v
    c = kin.points["C"].p
    local = np.stack([np.cos(ang) * c[:, 0] + np.sin(ang) * c[:, 1], -np.sin(ang) * c[:, 0] + np.cos(ang) * c[:, 1]], 1)
    dist = np.hypot(*(local[:, None, :] - prof[None, :, :]).transpose(2, 0, 1)).min(axis=1)
    # a 20000-gon's vertices lie within (pitch-length / 20000)² / (8·ρ) ≈ 1e-9 m of the true curve
    assert np.abs(dist - cam.roller_radius).max() < 1e-6 * cam.roller_radius


def test_the_sketch_decides_which_way_the_follower_rises(tmp_path):
    """The same cam with the follower sketched on the other side of the line O–P: the follower
    turns the other way and the roller still moves away from the cam's axis as q rises."""
    text = _oscillating_text()
    mech, _ = _load(tmp_path, text)
    cy = 0.25 * math.sin(math.pi / 4)
    mirrored, _ = _load(tmp_path, text.replace(f"{cy!r}]", f"{-cy!r}]"), "mirror.toml")
    for m, sign in ((mech, 1.0), (mirrored, -1.0)):
        kin = solve(m, TURN)
        r = np.hypot(*kin.points["C"].p.T)
        d = lift(m.cams[0], TURN)[0]
        assert np.corrcoef(r, d)[0, 1] > 0.99  # further from the axis as the program rises
    a = solve(mech, TURN).links["follower"].angle.d1
    b = solve(mirrored, TURN).links["follower"].angle.d1
    assert np.allclose(a, -b, atol=1e-12)


def test_cam_linkage_in_mujoco_within_the_cam_tolerances():
    r = linkgen.validate(linkgen.load(ROOT / "models" / "cam_rocker_slider.toml"))
    assert r.ok, r.summary()
    assert {"followers.follower.displacement", "contact.disc.normal_force", "points", "balancing_torque"} <= set(r.errors)


def test_a_follower_that_would_leave_the_cam_is_named(tmp_path):
    text = _oscillating_text().replace("spring_preload = 10.0", "spring_preload = 0.0").replace(
        "spring_rate = 20.0", "spring_rate = 0.0")
    mech, _ = _load(tmp_path, text)
    with pytest.raises(SimulationError, match=r"leave the cam at crank angles .*spring"):
        linkgen.validate(mech)


def test_a_concave_profile_is_refused_for_mujoco(tmp_path):
    """A roller larger than the pitch curve's flattest bend makes the profile concave (undercut):
    MuJoCo would collide its convex hull, so it is refused with the angle."""
    from linkgen.mujoco.mjcf import PLACEHOLDER, write_mjcf

    # the textbook cam's pitch curve bends to a radius of 0.167 m at its flattest (the stand-alone
    # cam's pitch_curvature_radius): a roller of 0.18 m cannot follow it
    text = _oscillating_text().replace("roller_radius = 0.04", "roller_radius = 0.18")
    mech, _ = _load(tmp_path, text)
    with pytest.raises(SimulationError, match=r"concave near crank angle"):
        write_mjcf(mech, PLACEHOLDER)


@pytest.mark.parametrize("edit, field", [
    (("follower = \"follower\"", "follower = \"cam\""), "cam.disc.follower"),
    (("roller = \"C\"", "roller = \"K\""), "cam.disc.roller"),
    (("roller_radius = 0.04", "roller_radius = 0.5"), "cam.disc.roller_radius"),
    (("spring_rate = 20.0", "spring_rate = \"stiff\""), "cam.disc.spring_rate"),
    (("kind = \"sine\"", "kind = \"cosine\""), "cam.disc.law.kind"),
    (("[cam.disc]", "[cam.disc]\nlift = 3"), "cam.disc.lift"),
])
def test_bad_cam_pairs_name_the_field(tmp_path, edit, field):
    path = tmp_path / "bad.toml"
    path.write_text(_oscillating_text().replace(*edit), encoding="utf-8")
    with pytest.raises(DescriptionError) as info:
        linkgen.load(path)
    assert info.value.field == field and str(info.value).startswith(f"{path}: {field}: ")


def test_a_sketch_where_rising_is_undefined_is_refused(tmp_path):
    """The roller centre sketched where its path is tangent to the circle about the cam's axis
    (the arm along the line from the axis): rising cannot be told from falling."""
    bad = _oscillating_text().replace(f"C = [{0.25 - 0.25 * math.cos(math.pi / 4)!r}, {0.25 * math.sin(math.pi / 4)!r}]",
                                      "C = [0.5, 0.0]")
    path = tmp_path / "tangent.toml"
    path.write_text(bad, encoding="utf-8")
    with pytest.raises(DescriptionError, match=r"rising cannot be told from falling"):
        solve(linkgen.load(path), TURN)


def test_cli_structure_analyze_forces_for_a_cam_linkage():
    model = ROOT / "models" / "cam_rocker_slider.toml"

    def run(*args):
        p = subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True, cwd=ROOT)
        assert p.returncode == 0, p.stderr
        return p.stdout

    assert "- p4 = 3·4 - 2·5 - 1 = 1" in run("structure", model) and "cam pair 'disc'" in run("structure", model)
    d = json.loads(run("analyze", model, "--angle", "30deg", "--omega", "1", "--json"))
    fol = d["followers"]["follower"]
    assert set(fol) >= {"displacement", "velocity", "acceleration", "jerk", "pressure_angle"}
    # ψ = π/4 + (π/10)·sin θ from its lowest π/4 − π/10, at θ = 30°, ω = 1: by hand
    assert math.isclose(fol["displacement"], math.pi / 10 * (1 + math.sin(math.radians(30))), rel_tol=1e-12)
    assert math.isclose(fol["velocity"], math.pi / 10 * math.cos(math.radians(30)), rel_tol=1e-12)
    f = json.loads(run("forces", model, "--angle", "30deg", "--json"))
    assert f["contact"]["disc"]["normal_force"] > 0 and f["contact"]["disc"]["on"] == "follower"


# ---- generated cams: the linkage form against the stand-alone closed form ----

from hypothesis import HealthCheck, Phase, assume, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from linkgen.families.cam.description import cam_from_dict  # noqa: E402
from linkgen.families.cam.laws import LAWS  # noqa: E402
from linkgen.pipeline.registry import from_dict  # noqa: E402

GENERATED = dict(max_examples=40, deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
                 suppress_health_check=[HealthCheck.too_slow])
# Pressure angles kept below this [rad]: near 90° the contact force's direction is ill-conditioned.
MAX_PRESSURE = math.radians(75.0)


@st.composite
def translating_cams(draw):
    rb = draw(st.floats(0.1, 0.4))
    rr = draw(st.floats(0.0, 0.05))
    e = draw(st.floats(-0.5, 0.5)) * rb
    rise, dwell, ret = (draw(st.floats(90.0, 150.0)), draw(st.floats(20.0, 60.0)), draw(st.floats(90.0, 150.0)))
    h = draw(st.floats(0.1, 0.4)) * rb
    laws = (draw(st.sampled_from(list(LAWS))), draw(st.sampled_from(list(LAWS))))
    segs = [{"kind": "rise", "span": f"{rise}deg", "law": laws[0], "height": h}, {"kind": "dwell", "span": f"{dwell}deg"},
            {"kind": "return", "span": f"{ret}deg", "law": laws[1], "height": h},
            {"kind": "dwell", "span": f"{360.0 - rise - dwell - ret}deg"}]
    m, k, f0 = draw(st.floats(0.1, 5.0)), draw(st.floats(0.0, 5e3)), draw(st.floats(0.0, 100.0))
    stand = {"mechanism": {"name": "t"}, "cam": {"base_radius": rb, "omega": 10.0},
             "follower": {"kind": "translating", "roller_radius": rr, "offset": e, "mass": m, "spring_rate": k,
                          "spring_preload": f0}, "segment": segs}
    cy = math.sqrt((rb + rr) ** 2 - e * e)
    linkage = {"mechanism": {"name": "t"}, "points": {"O": [0.0, 0.0], "K": [0.1, 0.0], "Q": [e, 0.0], "C": [e, cy]},
               "links": {"ground": {"points": ["O", "Q"]},
                         "cam": {"points": ["O", "K"], "inertial": {"mass": 1.0, "com": [0.0, 0.0], "inertia": 0.001}},
                         "follower": {"points": ["C"], "inertial": {"mass": m, "com": [0.0, 0.0], "inertia": 0.001}}},
               "prismatic": {"stem": {"slider": "follower", "guide": "ground", "point": "C", "through": "Q",
                                      "angle": "90deg"}},
               "cam": {"disc": {"follower": "follower", "roller": "C", "roller_radius": rr, "spring_rate": k,
                                "spring_preload": f0, "segment": segs}},
               "drive": {"joint": "O", "omega": 10.0}}
    return stand, linkage


@st.composite
def oscillating_cams(draw):
    a, arm = draw(st.floats(0.2, 0.4)), draw(st.floats(0.15, 0.35))
    mean, amp = draw(st.floats(35.0, 60.0)), draw(st.floats(5.0, 15.0))
    reach = math.sqrt(a * a + arm * arm - 2 * a * arm * math.cos(math.radians(mean - amp)))
    rr = draw(st.floats(0.0, 0.3)) * reach
    inertia, k, f0 = draw(st.floats(0.01, 0.5)), draw(st.floats(0.0, 50.0)), draw(st.floats(0.0, 20.0))
    law = {"kind": "sine", "amplitude": f"{amp}deg", "mean": f"{mean}deg"}
    stand = {"mechanism": {"name": "o"}, "cam": {"omega": 10.0},
             "follower": {"kind": "oscillating", "roller_radius": rr, "pivot_distance": a, "arm_length": arm,
                          "inertia": inertia, "lowest_angle": f"{mean - amp}deg", "spring_rate": k,
                          "spring_preload": f0}, "law": law}
    psi = math.radians(mean)
    linkage = {"mechanism": {"name": "o"},
               "points": {"O": [0.0, 0.0], "K": [0.1, 0.0], "P": [a, 0.0],
                          "C": [a - arm * math.cos(psi), arm * math.sin(psi)]},
               "links": {"ground": {"points": ["O", "P"]},
                         "cam": {"points": ["O", "K"], "inertial": {"mass": 1.0, "com": [0.0, 0.0], "inertia": 0.001}},
                         "follower": {"points": ["P", "C"], "inertial": {"mass": 1.0, "com": [0.0, 0.0],
                                                                          "inertia": inertia}}},
               "cam": {"disc": {"follower": "follower", "roller": "C", "roller_radius": rr, "spring_rate": k,
                                "spring_preload": f0, "law": law}},
               "drive": {"joint": "O", "omega": 10.0}}
    return stand, linkage


def _same(stand: dict, linkage: dict) -> None:
    cm = cam_from_dict(stand)
    ref = state(cm, TURN)
    assume(np.abs(ref.pressure_angle).max() < MAX_PRESSURE)
    mech = from_dict(linkage)
    asm = assemble(mech)
    kin = solve(asm, TURN)
    cam = mech.cams[0]
    d0, d1, d2, d3 = lift(cam, TURN)
    base = cm.follower.output(np.zeros(1))[0][0]
    w = cm.omega
    for got, want in ((d0 + base, ref.displacement), (d1 * w, ref.velocity), (d2 * w * w, ref.acceleration),
                      (d3 * w**3, ref.jerk), (contact(kin, cam)[2], ref.pressure_angle)):
        assert np.abs(got - want).max() <= SAME_TOL * max(np.abs(want).max(), 1.0)
    f = forces(asm, TURN, w, 0.0)
    for got, want in ((f.contact["disc"], ref.contact_force), (f.balancing_torque, ref.cam_torque)):
        assert np.abs(got - want).max() <= SAME_TOL * max(np.abs(want).max(), 1e-300)


@settings(**GENERATED)
@given(translating_cams())
def test_generated_translating_cams_agree_as_linkages(pair):
    _same(*pair)


@settings(**GENERATED)
@given(oscillating_cams())
def test_generated_oscillating_cams_agree_as_linkages(pair):
    _same(*pair)

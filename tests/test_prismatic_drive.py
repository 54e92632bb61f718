"""A prismatic drive (issue 26): a linear actuator drives a linkage, the input its stroke s [m].

Two topologies: a hydraulic cylinder pivoted on the ground with its rod pinned to a boom
(models/hydraulic_boom.toml: the cylinder, rod and boom form one group) and a piston on a guide
fixed to the ground (the slider leads, the rest are class-II groups). Each is checked against an
independent route written here: positions from Newton's method on the loop equations, velocities
and accelerations by central differences of those, and the balancing force from virtual work with
the links' masses read from the file; then MuJoCo, and the messages for what cannot run.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from scipy.optimize import fsolve

import linkgen
from conftest import ROOT
from linkgen.errors import ArgumentError, AssemblyError, DescriptionError
from linkgen.families.planar.assembly import assemble
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces
from linkgen.families.planar.reader import loads

BOOM = ROOT / "models" / "hydraulic_boom.toml"
G = 9.81  # the files' |gravity| [m/s²]
# The loop equations' residual [m] the numerical solution must reach (a few ulps of the ~1 m sizes).
LOOP_TOL = 1e-14
# Newton's method on the loop equations stops at fsolve's xtol = 1e-14 (relative); the closed form
# rounds at ~1e-15 per operation: positions and angles agree to 1e-11 of the 2.8 m size (or rad).
POSITION_TOL = 1e-11
# Central differences with step H of the numerical solution: truncation H²/6·|x‴| ~ 2e-9·|x‴| and
# rounding ~1e-14/H ~ 1e-10 for first derivatives; H²/12·|x⁗| and ~1e-14/H² ~ 1e-6 for second
# ones (x‴, x⁗ of order 1 to 10 per m here, the loop solution good to ~1e-14 m). Both to 1e-5 of
# the mechanism's peak velocity or acceleration (measured: 5e-8 and 5e-8).
H = 1e-4
VELOCITY_TOL = 1e-5
ACCELERATION_TOL = 1e-5
# The balancing force from virtual work with the differences above: their error reaches the
# force through the virtual displacements and inertia forces, so the same 1e-5 of the force's
# peak (measured: 2e-8).
FORCE_TOL = 1e-5

# A piston on a guide fixed to the ground pushes a rod that raises a boom: the slider leads.
PISTON = """
[mechanism]
name = "piston_boom"
gravity = [0.0, -9.81]

[points]
O = [0.0, 0.0]
G = [-0.2, -0.3]
P = [0.3, -0.3]
B = [0.5, 0.2]
T = [1.5, 0.4]

[links.ground]
points = ["O", "G"]

[links.piston]
points = ["P"]
inertial = { mass = 2.0, com = [0.0, 0.0], inertia = 0.01 }

[links.rod]
points = ["P", "B"]
density = 5.0

[links.boom]
points = ["O", "B", "T"]
inertial = { mass = 20.0, com = [0.7, -0.05], inertia = 2.0 }

[prismatic.ram]
slider = "piston"
guide = "ground"
point = "P"
through = "G"

[[force]]
link = "boom"
point = "T"
force = [0.0, -300.0]

[drive]
joint = "ram"
start = 0.35
stop = 0.55
velocity = 0.2
acceleration = 0.0
"""


def _rot(a: float) -> np.ndarray:
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


def _solve_loops(residual, guess: np.ndarray, strokes: np.ndarray) -> np.ndarray:
    """The unknowns at each stroke by fsolve on the loop equations, continued from ``guess``."""
    out = []
    x = np.asarray(guess, dtype=float)
    for s in strokes:
        x, info, ok, msg = fsolve(residual, x, args=(s,), xtol=1e-14, full_output=True)
        assert np.abs(info["fvec"]).max() < LOOP_TOL, msg  # converged, or as far as doubles go
        out.append(x)
    return np.array(out)


def _boom_route(data: dict, strokes: np.ndarray) -> dict:
    """The hydraulic boom by the loop equations: the cylinder's angle ψ (its axis A→B) and the boom's
    θ with A + s·e(ψ) = O + R(θ)·(|OB|, 0); every point, angle and centre of mass from them."""
    p = {k: np.array(v, dtype=float) for k, v in data["points"].items()}
    ob = float(np.hypot(*(p["B"] - p["O"])))
    t_local = _rot(-math.atan2(*(p["B"] - p["O"])[::-1])) @ (p["T"] - p["O"])
    ac, rb = float(np.hypot(*(p["C"] - p["A"]))), float(np.hypot(*(p["B"] - p["R"])))

    def loop(x, s):
        psi, theta = x
        return p["A"] + s * np.array([math.cos(psi), math.sin(psi)]) - p["O"] - ob * np.array(
            [math.cos(theta), math.sin(theta)])

    d0 = p["B"] - p["A"]
    x = _solve_loops(loop, [math.atan2(d0[1], d0[0]), math.atan2(p["B"][1], p["B"][0])], strokes)
    e = np.stack([np.cos(x[:, 0]), np.sin(x[:, 0])], axis=1)
    b = p["A"] + strokes[:, None] * e
    boom_com = np.array(data["links"]["boom"]["inertial"]["com"])
    return {
        "angles": {"cylinder": x[:, 0], "rod": x[:, 0], "boom": x[:, 1]},
        "points": {"B": b, "C": p["A"] + ac * e, "R": b - rb * e,
                   "T": p["O"] + np.einsum("nij,j->ni", np.array([_rot(t) for t in x[:, 1]]), t_local)},
        "com": {"cylinder": p["A"] + 0.5 * ac * e, "rod": b - 0.5 * rb * e,
                "boom": p["O"] + np.einsum("nij,j->ni", np.array([_rot(t) for t in x[:, 1]]), boom_com)},
        "mass": {"cylinder": data["links"]["cylinder"]["density"] * ac, "rod": data["links"]["rod"]["density"] * rb,
                 "boom": data["links"]["boom"]["inertial"]["mass"]},
        "inertia": {"cylinder": data["links"]["cylinder"]["density"] * ac ** 3 / 12.0,
                    "rod": data["links"]["rod"]["density"] * rb ** 3 / 12.0,
                    "boom": data["links"]["boom"]["inertial"]["inertia"]},
    }


def _piston_route(data: dict, strokes: np.ndarray) -> dict:
    """The piston boom by the loop equations: the piston at G + (s, 0), the rod's angle φr and the
    boom's θ with P + |PB|·e(φr) = O + R(θ)·(|OB|, 0)."""
    p = {k: np.array(v, dtype=float) for k, v in data["points"].items()}
    ob, pb = float(np.hypot(*(p["B"] - p["O"]))), float(np.hypot(*(p["B"] - p["P"])))
    rot0 = -math.atan2(*(p["B"] - p["O"])[::-1])
    t_local = _rot(rot0) @ (p["T"] - p["O"])

    def piston(s):
        return p["G"] + np.array([s, 0.0])

    def loop(x, s):
        rod, theta = x
        return piston(s) + pb * np.array([math.cos(rod), math.sin(rod)]) - ob * np.array([math.cos(theta),
                                                                                          math.sin(theta)])

    d0 = p["B"] - p["P"]
    x = _solve_loops(loop, [math.atan2(d0[1], d0[0]), math.atan2(p["B"][1], p["B"][0])], strokes)
    pp = np.array([piston(s) for s in strokes])
    b = pp + pb * np.stack([np.cos(x[:, 0]), np.sin(x[:, 0])], axis=1)
    turn = np.array([_rot(t) for t in x[:, 1]])
    return {
        "angles": {"piston": np.zeros_like(strokes), "rod": x[:, 0], "boom": x[:, 1]},
        "points": {"P": pp, "B": b, "T": np.einsum("nij,j->ni", turn, t_local)},
        "com": {"piston": pp, "rod": 0.5 * (pp + b),
                "boom": np.einsum("nij,j->ni", turn, np.array(data["links"]["boom"]["inertial"]["com"]))},
        "mass": {"piston": 2.0, "rod": 5.0 * pb, "boom": 20.0},
        "inertia": {"piston": 0.01, "rod": 5.0 * pb ** 3 / 12.0, "boom": 2.0},
    }


def _virtual_work_force(route, strokes: np.ndarray, v: float, tip: np.ndarray) -> np.ndarray:
    """The force along the stroke that balances gravity, the tip load at T and the inertia forces
    (ṡ = v constant): F·δs + Σ (m·g − m·a)·δr_c − I·α·δθ + F_T·δT = 0, every δ and a from central
    differences of the loop equations' solution at s ± H (``route`` of three stroke arrays)."""
    at = {k: route(strokes + k * H) for k in (-1, 0, 1)}
    force = np.zeros_like(strokes)
    for link, m in at[0]["mass"].items():
        c = {k: at[k]["com"][link] for k in at}
        th = {k: np.unwrap(at[k]["angles"][link]) for k in at}
        dc, ddc = (c[1] - c[-1]) / (2 * H), (c[1] - 2 * c[0] + c[-1]) / H ** 2
        dth, ddth = (th[1] - th[-1]) / (2 * H), (th[1] - 2 * th[0] + th[-1]) / H ** 2
        load = m * np.array([0.0, -G]) - m * ddc * v * v
        force -= np.einsum("ni,ni->n", load, dc) - at[0]["inertia"][link] * ddth * v * v * dth
    dt = (at[1]["points"]["T"] - at[-1]["points"]["T"]) / (2 * H)
    return force - dt @ tip


CASES = {"hydraulic_boom": (lambda: BOOM.read_bytes(), _boom_route, 2000.0),
         "piston_boom": (lambda: PISTON, _piston_route, 300.0)}


@pytest.fixture(params=list(CASES), ids=list(CASES))
def case(request):
    text, route, tip = CASES[request.param]
    raw = text()
    data = tomllib.loads(raw.decode() if isinstance(raw, bytes) else raw)
    mech = loads(raw)
    d = mech.drive
    strokes = np.linspace(d.start, d.stop, 9)[1:-1]  # inside, so that s ± H is too
    return mech, data, route, strokes, np.array([0.0, -tip])


def test_positions_match_a_numerical_solution_of_the_loop_equations(case):
    mech, data, route, strokes, _ = case
    kin = solve(assemble(mech), strokes)
    ref = route(data, strokes)
    size = float(np.ptp(np.array(list(mech.points.values())), axis=0).max())
    for name, xy in ref["points"].items():
        np.testing.assert_allclose(kin.points[name].p, xy, rtol=0, atol=POSITION_TOL * size, err_msg=name)
    for name, a in ref["angles"].items():
        np.testing.assert_allclose(np.remainder(kin.links[name].angle.v - a + math.pi, 2 * math.pi) - math.pi, 0.0,
                                   atol=POSITION_TOL, err_msg=name)
    drive = kin.sliders[mech.drive.joint]  # the driven pair's own stroke is the input
    assert np.array_equal(drive.v, strokes) and np.all(drive.d1 == 1.0) and np.all(drive.d2 == 0.0)


def test_velocities_and_accelerations_match_differences_of_the_numerical_solution(case):
    mech, data, route, strokes, _ = case
    v = mech.drive.velocity
    mo = linkgen.kinematics(mech, strokes)
    at = {k: route(data, strokes + k * H) for k in (-1, 0, 1)}
    want = {}
    for name in at[0]["points"]:
        xy = {k: at[k]["points"][name] for k in at}
        want[name] = (xy[1] - xy[-1]) / (2 * H) * v, (xy[1] - 2 * xy[0] + xy[-1]) / H ** 2 * v * v
    peak_v, peak_a = (max(np.abs(w[i]).max() for w in want.values()) for i in (0, 1))
    for name, (vel, acc) in want.items():
        got = mo.points[name]
        np.testing.assert_allclose(got.velocity, vel, rtol=0, atol=VELOCITY_TOL * peak_v, err_msg=name)
        np.testing.assert_allclose(got.acceleration, acc, rtol=0, atol=ACCELERATION_TOL * peak_a, err_msg=name)


def test_balancing_force_matches_virtual_work(case):
    mech, data, route, strokes, tip = case
    f = forces(assemble(mech), strokes, mech.drive.velocity, 0.0)
    want = _virtual_work_force(lambda s: route(data, s), strokes, mech.drive.velocity, tip)
    np.testing.assert_allclose(f.balancing_torque, want, rtol=0, atol=FORCE_TOL * np.abs(want).max())
    assert np.all(want > 0.0)  # the actuator pushes: both loads would retract it


def test_results_speak_of_the_stroke():
    mech = linkgen.load(BOOM)
    k = linkgen.kinematics(mech, "0.9m")
    assert k.text().startswith("hydraulic_boom: s = 0.9 m, ṡ = 0.1 m/s")
    d = k.to_dict()
    assert (d["units"]["phi"], d["units"]["omega"], d["units"]["epsilon"]) == ("m", "m/s", "m/s²")
    assert "phi [m]" in linkgen.kinematics(mech, [0.85, 0.9]).columns()
    f = linkgen.forces(mech, 0.9)
    assert "balancing force on the slider along its guide" in f.text() and f.to_dict()["units"]["torque"] == "N"
    summary = linkgen.summary(mech).text()
    assert "per m of input stroke" in summary and "s = 0.8..1.05 m" in summary


def test_a_stroke_that_does_not_assemble_is_named():
    """The triangle A–B–O closes only while s ≤ |OA| + |OB| = 1.657785 m (from the sketch)."""
    mech = linkgen.load(BOOM)
    with pytest.raises(AssemblyError) as exc:
        linkgen.kinematics(mech, [1.0, 1.6, 1.7])
    text = str(exc.value)
    assert "cannot be assembled at strokes s = 1.7 m" in text and "[cylinder, rod, boom]" in text, text


def test_an_angle_for_a_stroke_and_a_stroke_for_an_angle_are_refused():
    with pytest.raises(ArgumentError, match="prismatic pair: give its stroke"):
        linkgen.kinematics(linkgen.load(BOOM), "30deg")
    with pytest.raises(ArgumentError, match="turns a crank: give an angle"):
        linkgen.kinematics(linkgen.load(ROOT / "models" / "fourbar.toml"), "0.3m")


@pytest.mark.parametrize("edit,field,words", [
    (('joint = "lift"', 'joint = "lifter"'), "drive.joint", "unknown prismatic pair 'lifter'"),
    (('joint = "lift"', 'joint = "Q"'), "drive.joint", "prismatic pairs: ['lift']"),
    (("stop = 1.05", "stop = 0.7"), "drive", "start < stop, got start = 0.8 m, stop = 0.7 m"),
    (("velocity = 0.1", 'velocity = "2rad/s"'), "drive.velocity", "must be a speed"),
    (("velocity = 0.1", "omega = 0.1"), "drive.omega", "allowed keys: ['acceleration', 'joint', 'start', 'stop', "
                                                        "'velocity']"),
])
def test_a_bad_drive_names_the_field_and_what_is_allowed(edit, field, words):
    text = BOOM.read_text().replace(*edit)
    with pytest.raises(DescriptionError) as exc:
        loads(text, "boom.toml")
    assert exc.value.field == field and words in str(exc.value) and "boom.toml" in str(exc.value), str(exc.value)


def test_the_piston_validates_in_mujoco():
    """The slider-led topology in MuJoCo (models/hydraulic_boom.toml, the cylinder's, runs in
    tests/test_mujoco.py with every bundled model)."""
    from linkgen.crosscheck.compare import compare
    from linkgen.mujoco.simulate import simulate

    asm = assemble(loads(PISTON.replace("stop = 0.55", "stop = 0.45")))
    cmp = compare(asm, simulate(asm))
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad
    assert cmp.quantities["balancing_torque"].relative_error < 1e-6
    assert cmp.quantities["sliders.ram.displacement"].max_abs_error < 1e-9


def test_a_cylinder_held_otherwise_says_what_is_needed():
    """The pair's guide must be the cylinder pivoted on the ground: the same file with slider and
    guide swapped (the 'rod' now the guide, not pivoted on the ground) is a structure error."""
    from linkgen.errors import StructureError

    text = BOOM.read_text().replace('slider = "rod"\nguide = "cylinder"', 'slider = "cylinder"\nguide = "rod"')
    text = text.replace('point = "B"\nthrough = "A"', 'point = "A"\nthrough = "B"')
    with pytest.raises(StructureError) as exc:
        linkgen.structure(loads(text))
    assert ("its guide 'rod' (the cylinder) must be pivoted on 'ground'" in str(exc.value)
            and "'rod' has 0 revolutes with 'ground'" in str(exc.value)), str(exc.value)

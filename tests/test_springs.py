"""Springs and dampers between points ([[spring]]) and torsion springs at revolutes
([[torsion_spring]]): the description's checks, the force by hand, the power balance, an
independent finite-difference energy check on generated mechanisms, the reduced damping in the
machine's equation, the summary's peak, the drawing and MuJoCo (tendons, joint springs)."""

from __future__ import annotations

import copy
import math
import tomllib

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import ROOT
from independent_checks import mass_properties
from linkgen import assemble, load
from linkgen.errors import DescriptionError
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces
from linkgen.families.planar.loads import applied_loads
from linkgen.families.planar.reader import from_dict, loads

MODELS = ROOT / "models"
SPRING_MODELS = [MODELS / f"{n}.toml" for n in ("slider_crank_spring", "fourbar_torsion", "compressor_gas_spring")]


def _desc(name: str) -> dict:
    return tomllib.loads((MODELS / f"{name}.toml").read_text())


def _text(desc: dict) -> str:
    from linkgen.model.toml_text import to_toml

    return to_toml(desc)


# ---------------------------------------------------------------- the description


@pytest.mark.parametrize("edit, field, words", [
    (lambda d: d["spring"][0].update(points=["B", "Q"]), "spring[0].points[1]", "unknown point 'Q'"),
    (lambda d: d["spring"][0].update(points=["O", "S"]), "spring[0].points", "both on link 'ground'"),
    (lambda d: d["spring"][0].update(points=["A", "B"]), "spring[0].points", "both on link 'rod'"),
    (lambda d: d["spring"][0].update(stiffness=-1.0), "spring[0].stiffness", "must be >= 0 N/m, got -1.0"),
    (lambda d: d["spring"][0].update(damping=-0.5), "spring[0].damping", "must be >= 0 N·s/m, got -0.5"),
    (lambda d: d["spring"][0].update(stiffness=math.inf), "spring[0].stiffness", "finite"),
    (lambda d: d["spring"][0].update(rest_length=math.nan), "spring[0].rest_length", "finite"),
    (lambda d: d["spring"][0].update(rest_length="-1mm"), "spring[0].rest_length", "must be >= 0 m"),
    (lambda d: d["spring"][0].update(points=["B"]), "spring[0].points", "must be two names"),
    (lambda d: d["spring"][0].update(spring_rate=1.0), "spring[0].spring_rate", "unknown key"),
    (lambda d: d["spring"][0].pop("rest_length"), "spring[0].rest_length", "is required"),
])
def test_a_bad_spring_is_a_description_error(edit, field, words):
    d = _desc("slider_crank_spring")
    edit(d)
    with pytest.raises(DescriptionError) as e:
        loads(_text(d), "bad.toml")
    assert e.value.field == field and words in str(e.value) and "bad.toml" in str(e.value), str(e.value)


@pytest.mark.parametrize("edit, field, words", [
    (lambda d: d["torsion_spring"][0].update(joint="Z"), "torsion_spring[0].joint", "unknown revolute 'Z'"),
    (lambda d: d["torsion_spring"][0].update(links=["crank", "rocker"]), "torsion_spring[0].links",
     "carry the revolute 'C'"),
    (lambda d: d["torsion_spring"][0].update(links=["rocker", "rocker"]), "torsion_spring[0].links", "two different"),
    (lambda d: d["torsion_spring"][0].update(stiffness=-40.0), "torsion_spring[0].stiffness", ">= 0 N·m/rad"),
    (lambda d: d["torsion_spring"][0].update(damping=-1.0), "torsion_spring[0].damping", ">= 0 N·m·s/rad"),
    (lambda d: d["torsion_spring"][0].update(rest_angle="ninety"), "torsion_spring[0].rest_angle", "angle"),
])
def test_a_bad_torsion_spring_is_a_description_error(edit, field, words):
    d = _desc("fourbar_torsion")
    edit(d)
    with pytest.raises(DescriptionError) as e:
        loads(_text(d), "bad.toml")
    assert e.value.field == field and words in str(e.value), str(e.value)


def test_spring_points_that_coincide_are_an_error_in_the_sketch_and_along_the_motion():
    d = _desc("slider_crank_spring")
    d["points"]["S"] = [0.45, 0.0]  # on B in the sketch
    with pytest.raises(DescriptionError, match=r"coincide in the sketch") as e:
        loads(_text(d), "bad.toml")
    assert e.value.field == "spring[0].points"
    d = _desc("slider_crank_spring")
    d["points"]["S"] = [0.3, 0.0]  # inside the slider's stroke 0.25 … 0.45 m: B passes over it
    mech = from_dict(d)  # accepted: apart in the sketch
    with pytest.raises(DescriptionError, match=r"coincide along the motion .*no line of action") as e:
        forces(mech, np.linspace(0.0, 2 * math.pi, 361), 10.0)
    assert e.value.field == "spring[0].points"


# ---------------------------------------------------------------- by hand

# Hand-derived figures: exact to rounding, compared to a few ulps of their size.
HAND_TOL = 1e-12


def test_the_spring_force_by_hand():
    """models/slider_crank_spring.toml at φ = 90°: B = (√(l² − r²), 0) = (0.335410 m, 0), so
    L = |SB| = 0.65 − 0.335410 m; the slider's speed there is −ω·r = −1 m/s (dx_B/dφ = −r·sinφ −
    r²·sinφ·cosφ/√(l² − r²·sin²φ) = −r), so L̇ = +1 m/s and the tension is
    T = k·(L − L₀) + c·L̇ = 2000·(0.314590 − 0.45) + 20·1 = −250.820 N: the spring pushes B
    (on the rod, its first carrier) by T along B → S, i.e. (−250.820, 0) N."""
    r, l, k, l0, c, w = 0.1, 0.35, 2000.0, 0.45, 20.0, 10.0
    xb = math.sqrt(l * l - r * r)
    tension = k * ((0.65 - xb) - l0) + c * (w * r)
    asm = assemble(load(MODELS / "slider_crank_spring.toml"))
    kin = solve(asm, np.array([math.pi / 2]))
    bare = applied_loads(asm, kin, gravity=False, omega=w, springs=False)["rod"]
    given = applied_loads(asm, kin, gravity=False, omega=w)["rod"]
    np.testing.assert_allclose(given.force[0] - bare.force[0], [tension, 0.0], rtol=0, atol=HAND_TOL * abs(tension))
    # about the rod's centre (A + B)/2: the force at B, arm (B − A)/2
    ax, ay = 0.0, r
    arm = (0.5 * (xb - ax), 0.5 * (0.0 - ay))
    moment = arm[0] * 0.0 - arm[1] * tension
    assert given.moment[0] - bare.moment[0] == pytest.approx(moment, abs=HAND_TOL * abs(tension) * l)
    assert tension == pytest.approx(-250.8203932, abs=1e-6)


def test_the_torsion_spring_torque_by_hand():
    """models/fourbar_torsion.toml: the torque on the rocker is −k·(θ − 90°) − c·θ̇, θ the rocker's
    angle from the positions of C and B, θ̇ = ω·dθ/dφ by central differences of those positions."""
    asm = assemble(load(MODELS / "fourbar_torsion.toml"))
    phi, h, w = 1.3, 1e-6, 10.0
    kin = solve(asm, np.array([phi - h, phi, phi + h]))
    theta = [math.atan2(*(kin.points["B"].p[i] - kin.points["C"].p[i])[::-1]) for i in range(3)]
    expected = -40.0 * (theta[1] - math.pi / 2) - 0.5 * w * (theta[2] - theta[0]) / (2 * h)
    bare = applied_loads(asm, kin, gravity=False, omega=w, springs=False)["rocker"]
    given = applied_loads(asm, kin, gravity=False, omega=w)["rocker"]
    # the central difference's error: ~h²·θ‴/6 ≈ 1e-12 rad/rad, and the rounding eps·θ/h ≈ 3e-10,
    # times c·ω = 5 N·m·s/rad: ~2e-9 N·m
    assert given.moment[1] - bare.moment[1] == pytest.approx(expected, abs=1e-8)


def test_the_peak_spring_force_in_the_summary_by_hand():
    """models/compressor_gas_spring.toml: the gas spring (no damping) is most compressed with the
    piston at the top, φ = 90°: |GB| = 0.26 − 0.2 = 0.06 m, so |T| = 1000·(1.2 − 0.06) = 1140 N."""
    from linkgen.families.planar.summary import summarize

    s = summarize(assemble(load(MODELS / "compressor_gas_spring.toml")))
    peak = s.peak_spring_forces["spring[0]"]
    assert peak.value == pytest.approx(1140.0, rel=1e-9)
    assert abs(math.remainder(peak.phi - math.pi / 2, 2 * math.pi)) < 1e-6
    d = s.to_dict()
    assert d["peak_spring_forces"]["spring[0]"]["value"] == pytest.approx(1140.0, rel=1e-9)
    assert "peak force of spring[0]: 1140 N at φ = 90°" in s.text()
    from linkgen.report.sections import _summary_lines

    assert "- peak spring forces: spring[0] 1140 N at 90°" in _summary_lines(d)  # the validation report's
    plain = summarize(assemble(load(MODELS / "fourbar.toml"))).to_dict()
    assert plain["peak_spring_forces"] == {}  # no springs, no peaks


# ---------------------------------------------------------------- balances


@pytest.mark.parametrize("path", SPRING_MODELS, ids=[p.stem for p in SPRING_MODELS])
def test_power_balance_with_springs(path):
    """The group-by-group balancing torque equals the power balance's (``forces`` raises
    BalanceError beyond BALANCE_TOL), with the dampers at a varying speed and ε ≠ 0."""
    from linkgen.families.planar.kinetostatics import BALANCE_TOL

    mech = load(path)
    phi = np.linspace(0.0, 2 * math.pi, 721)
    w = mech.drive.omega * (1.0 + 0.3 * np.sin(phi))
    f = forces(mech, phi, w, 5.0)
    scale = np.abs(f.balancing_torque).max()
    assert np.abs(f.balancing_torque - f.power_balance_torque).max() <= BALANCE_TOL * scale


# The finite-difference energy check. Velocities by a 4th-order central stencil of the positions
# with step DELTA (truncation ~DELTA⁴·|S⁽⁵⁾|/30 ≈ 3e-14 of the size, rounding ~eps·size/DELTA ≈
# 2e-13), the energy's derivative by the same stencil with step H: its truncation ~H⁴/30 of the
# energy's 5th derivative (≈ 3e-14 of the energy scale) and the velocities' errors (~1e-12 of the
# kinetic energy) divided by H: ~1e-9 of the torque scale. 1e-7 leaves a margin of 100 and
# still catches a wrong sign, a missing spring or a wrong rest length (all at the scale itself).
# Measured on 200 generated mechanisms: ≤ 5.1e-10; a torsion spring of the wrong sign shows at 1.9,
# a spring force 0.1 % too large at 2e-3.
DELTA = 1e-3
H = 1e-3
ENERGY_TOL = 1e-7


def _d4(f, x: float, step: float):
    """4th-order central difference of f at x."""
    return (f(x - 2 * step) - 8 * f(x - step) + 8 * f(x + step) - f(x + 2 * step)) / (12 * step)


def _fourbar(rng: np.random.Generator) -> dict:
    """A Grashof crank-rocker (OC = 1 m, the coupler and rocker long enough to assemble at every
    crank angle with 0.1 m to spare), its sketch at φ = 0 on the upper branch."""
    while True:
        r, l, c = rng.uniform(0.1, 0.3), rng.uniform(0.6, 1.3), rng.uniform(0.6, 1.3)
        if abs(l - c) + 0.1 <= 1.0 - r and 1.0 + r <= l + c - 0.1 and abs(c - 1.0) > 0.05:
            break
    a = np.array([r, 0.0])
    d = np.hypot(*(np.array([1.0, 0.0]) - a))
    x = (l * l - c * c + d * d) / (2 * d)
    b = a + x * (np.array([1.0, 0.0]) - a) / d + math.sqrt(l * l - x * x) * np.array([0.0, 1.0])
    return {
        "mechanism": {"name": "fb", "gravity": [0.0, -9.81]},
        "points": {"O": [0.0, 0.0], "A": a.tolist(), "B": b.tolist(), "C": [1.0, 0.0],
                   "G": [float(rng.uniform(-0.5, 1.5)), -1.5]},
        "links": {"ground": {"points": ["O", "C", "G"]},
                  "crank": {"points": ["O", "A"], "length": r, "density": float(rng.uniform(1, 10))},
                  "coupler": {"points": ["A", "B"], "length": l, "density": float(rng.uniform(1, 10))},
                  "rocker": {"points": ["C", "B"], "length": c, "density": float(rng.uniform(1, 10))}},
        "drive": {"joint": "O", "omega": float(rng.uniform(1, 20))},
    }, [("O", "B"), ("A", "C"), ("G", "A"), ("G", "B")], [("O", ("ground", "crank")), ("A", ("crank", "coupler")),
                                                         ("B", ("coupler", "rocker")), ("C", ("ground", "rocker"))]


def _slider_crank(rng: np.random.Generator) -> dict:
    """An offset slider-crank (the rod longer than crank + offset + 0.1 m), sketch at φ = 0."""
    r, e = rng.uniform(0.05, 0.3), rng.uniform(-0.1, 0.1)
    l = r + abs(e) + rng.uniform(0.1, 0.8)
    xb = r + math.sqrt(l * l - e * e)
    return {
        "mechanism": {"name": "sc", "gravity": [0.0, -9.81]},
        "points": {"O": [0.0, 0.0], "A": [r, 0.0], "B": [xb, e], "G": [float(rng.uniform(-1, 2)), e - 1.5]},
        "links": {"ground": {"points": ["O", "G"]},
                  "crank": {"points": ["O", "A"], "length": r, "density": float(rng.uniform(1, 10))},
                  "rod": {"points": ["A", "B"], "length": l, "density": float(rng.uniform(1, 10))},
                  "slider": {"points": ["B"], "inertial": {"mass": float(rng.uniform(0.1, 5)), "com": [0.0, 0.0],
                                                           "inertia": 0.0}}},
        "prismatic": {"slider": {"slider": "slider", "guide": "ground", "point": "B", "through": "O", "offset": e}},
        "drive": {"joint": "O", "omega": float(rng.uniform(1, 20))},
    }, [("O", "B"), ("G", "A"), ("G", "B")], [("O", ("ground", "crank")), ("A", ("crank", "rod")),
                                             ("B", ("rod", "slider"))]


def _with_springs(rng: np.random.Generator, kind: int):
    desc, pairs, joints = (_fourbar if kind == 0 else _slider_crank)(rng)
    p, q = pairs[rng.integers(len(pairs))]
    if rng.integers(2):
        p, q = q, p
    desc["spring"] = [{"points": [p, q], "stiffness": float(rng.uniform(10, 5000)),
                       "rest_length": float(rng.uniform(0.0, 2.0))}]
    joint, links = joints[rng.integers(len(joints))]
    if rng.integers(2):
        links = links[::-1]
    desc["torsion_spring"] = [{"joint": joint, "links": list(links), "stiffness": float(rng.uniform(1, 100)),
                               "rest_angle": float(rng.uniform(-4, 4))}]
    return desc


def _link_angle(kin, link: str) -> np.ndarray:
    return kin.links[link].angle.v


def _energy(desc: dict, asm, phi0: float, omega: float):
    """φ → the energy E(φ) = kinetic (at constant ω) + springs' + gravity's potential, from the
    closed form's positions only (velocities by finite differences, the torsion spring's angle
    made continuous by following it from the sketch)."""
    g = np.asarray(desc["mechanism"]["gravity"], dtype=float)
    spring, torsion = desc["spring"][0], desc["torsion_spring"][0]
    a, b = torsion["links"]
    moving = [n for n in desc["links"] if n != "ground"]
    props = {n: mass_properties(desc, n) for n in moving}
    # the torsion spring's angle at φ0, followed continuously from the sketch (φ = 0)
    path = solve(asm, np.linspace(0.0, phi0, 2001))
    rel = np.unwrap(_link_angle(path, b) - _link_angle(path, a))
    rel0 = float(rel[-1])

    def state(phi: float):
        kin = solve(asm, np.array([phi]))
        com = {n: kin.links[n].point(props[n][1]).p[0] for n in moving}
        ang = {n: float(_link_angle(kin, n)[0]) for n in moving + ["ground"]}
        pts = {p: kin.points[p].p[0] for p in spring["points"]}
        return com, ang, pts

    def energy(phi: float) -> float:
        com, ang, pts = state(phi)
        near = [state(phi + k * DELTA) for k in (-2, -1, 1, 2)]
        e = 0.0
        for n in moving:
            m, _, inertia = props[n]
            v = omega * (near[0][0][n] - 8 * near[1][0][n] + 8 * near[2][0][n] - near[3][0][n]) / (12 * DELTA)
            th = [math.remainder(s[1][n] - ang[n], 2 * math.pi) for s in near]
            wl = omega * (th[0] - 8 * th[1] + 8 * th[2] - th[3]) / (12 * DELTA)
            e += 0.5 * m * float(v @ v) + 0.5 * inertia * wl * wl - m * float(g @ com[n])
        length = float(np.hypot(*(pts[spring["points"][1]] - pts[spring["points"][0]])))
        e += 0.5 * spring["stiffness"] * (length - spring["rest_length"]) ** 2
        rel = rel0 + math.remainder((ang[b] - ang[a]) - rel0, 2 * math.pi)
        e += 0.5 * torsion["stiffness"] * (rel - torsion["rest_angle"]) ** 2
        return e

    return energy


@settings(max_examples=40, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), kind=st.integers(0, 1), phi=st.floats(0.0, 2 * math.pi))
def test_the_balancing_torque_is_the_energys_rate_on_generated_mechanisms(seed, kind, phi):
    """At constant ω without dampers, T·ω = dE/dt, i.e. T = dE/dφ with E the kinetic energy plus
    the springs' and gravity's potential: E from the positions alone (module ``_energy``)."""
    rng = np.random.default_rng(seed)
    desc = _with_springs(rng, kind)
    mech = from_dict(desc)
    asm = assemble(mech)
    w = mech.drive.omega
    torque = float(forces(asm, np.array([phi]), w, 0.0).balancing_torque[0])
    energy = _energy(desc, asm, phi, w)
    rate = _d4(energy, phi, H)
    # the scale: the largest of the terms that the balance adds up, as the torque's size over a turn
    grid = np.linspace(0.0, 2 * math.pi, 73)
    f = forces(asm, grid, w, 0.0)
    scale = float(np.abs(f.balancing_torque).max())
    assert abs(torque - rate) <= ENERGY_TOL * scale, (seed, kind, phi, torque, rate, scale)


# ---------------------------------------------------------------- dampers in the machine


def test_reduced_damping_is_the_moments_derivative_in_omega():
    """M(φ, ω) is linear in ω with slope ReducedDynamics.damping (exactly: the dampers' forces are)."""
    mech = load(MODELS / "slider_crank_spring.toml")
    phi = np.linspace(0.0, 2 * math.pi, 37)
    m1, m2 = forces(mech, phi, 5.0).reduced, forces(mech, phi, 15.0).reduced
    np.testing.assert_allclose(m1.damping, m2.damping, rtol=0, atol=1e-14)
    np.testing.assert_allclose((m2.moment - m1.moment) / 10.0, m1.damping, rtol=0,
                               atol=1e-12 * np.abs(m1.moment).max())
    # hand: −c·(dL/dφ)², dL/dφ = −dx_B/dφ = r at φ = 90° → −20·0.01 = −0.2 N·m·s/rad
    assert m1.damping[9] == pytest.approx(-0.2, rel=1e-12)
    assert (m1.damping <= 0).all()


# The machine against the exact solution of J·ω̇ = M − c·ω: a hundred times the ODE's relative
# tolerance (machine.RTOL), as tests/test_dynamics.py's EXACT_TOL.
def test_a_damped_crank_under_constant_torque_reaches_m_over_c():
    """A lone crank (J = 2 kg·m², centre of mass on its axis) with a torsional damper c = 4 N·m·s/rad
    at its ground pivot, driven by a constant 8 N·m from rest: ω(t) = (M/c)·(1 − exp(−c·t/J))."""
    from linkgen.machine.machine import RTOL, run_machine
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import load_machine

    text = """
[mechanism]
name = "damped_crank"
[points]
O = [0.0, 0.0]
A = [0.5, 0.0]
[links.ground]
points = ["O"]
[links.crank]
points = ["O", "A"]
[links.crank.inertial]
mass = 1.0
com = [0.0, 0.0]
inertia = 2.0
[[torsion_spring]]
joint = "O"
links = ["ground", "crank"]
stiffness = 0.0
damping = 4.0
[drive]
joint = "O"
omega = 2.0
[machine]
duration = 3.0
[machine.motor]
kind = "constant"
torque = 8.0
"""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "damped_crank.toml"
        path.write_text(text)
        asm, machine = load_machine(path)
    run = run_machine(machine, reduce(asm), samples=301)
    exact = 2.0 * (1.0 - np.exp(-4.0 * run.t / 2.0))
    np.testing.assert_allclose(run.omega, exact, rtol=0, atol=100 * RTOL * 2.0)


# The machine's ω from the default table of M against a table 4× finer (whose own error is 16×
# smaller, linear interpolation): a tenth of MuJoCo's machine tolerance (tests/test_dynamics.py's
# MUJOCO_TOL = 1e-6), so that the table never decides that comparison. Measured 3.6e-8.
TABLE_TOL = 1e-7


def test_the_reduced_moments_table_is_fine_enough_for_a_spring():
    """models/slider_crank_spring.toml driven by a linear motor from 10 rad/s: at 4096 cells the
    table moved ω by 3.0e-6 of its peak over 3 s against one 4× finer (MuJoCo's full linkage disagreed
    with it by 3.0e-6; with 32768 cells, by 3.1e-8)."""
    from linkgen.machine.machine import run_machine
    from linkgen.machine.reduced import MOMENT_GRID, reduce
    from linkgen.model.machine import machine_from_dict

    d = _desc("slider_crank_spring")
    d["machine"] = {"rotor_inertia": 0.05, "duration": 3.0, "start_speed": 10.0,
                    "motor": {"kind": "linear", "stall_torque": 60.0, "no_load_speed": 12.0}}
    asm, machine = assemble(from_dict(d)), machine_from_dict(d)
    coarse = run_machine(machine, reduce(asm), samples=301)
    fine = run_machine(machine, reduce(asm, moment_grid=4 * MOMENT_GRID), samples=301)
    assert np.abs(coarse.omega - fine.omega).max() <= TABLE_TOL * np.abs(fine.omega).max()


def test_the_flywheels_driving_torque_pays_the_damper_at_the_mean_speed():
    """A crank (J = 2 kg·m², 1 kg at 0.5 m off its axis, gravity) with a torsional damper
    c = 4 N·m·s/rad at its pivot: gravity's moment averages to 0 over a turn, so the mean driving
    torque is the damper's c·ω_m = 4·10 = 40 N·m (by hand)."""
    from linkgen.machine.flywheel import size_flywheel
    from linkgen.machine.reduced import reduce

    d = {"mechanism": {"name": "damped_crank", "gravity": [0.0, -9.81]},
         "points": {"O": [0.0, 0.0], "A": [0.5, 0.0]},
         "links": {"ground": {"points": ["O"]},
                   "crank": {"points": ["O", "A"], "inertial": {"mass": 1.0, "com": [0.5, 0.0], "inertia": 2.0}}},
         "torsion_spring": [{"joint": "O", "links": ["ground", "crank"], "stiffness": 0.0, "damping": 4.0}],
         "drive": {"joint": "O", "omega": 10.0}}
    fw = size_flywheel(reduce(assemble(from_dict(d))), 10.0, 0.05)
    assert fw.driving_torque == pytest.approx(40.0, rel=1e-9)


# ---------------------------------------------------------------- the drawing


def test_the_drawing_has_a_zigzag_and_a_spiral():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from linkgen.draw.skeleton import draw_skeleton, frame_of
    from linkgen.draw.springs import SPRING_COLOR
    from linkgen.families.planar.positions import positions

    for name, count in (("slider_crank_spring", 5), ("fourbar_torsion", 1)):  # zig-zag + a dashpot of 4 lines; a spiral
        mech = load(MODELS / f"{name}.toml")
        pos = positions(mech, np.array([0.5]))
        fig, ax = plt.subplots()
        try:
            draw_skeleton(ax, pos, frame_of(pos), 0)
            ours = [ln for ln in ax.lines if tuple(ln.get_color()[:3]) == SPRING_COLOR]
        finally:
            plt.close(fig)
        assert len(ours) == count, name


# ---------------------------------------------------------------- MuJoCo


@pytest.fixture(scope="module")
def comparisons():
    """One MuJoCo run of each spring model compared with the closed form (shared by the tests)."""
    from linkgen.crosscheck.compare import compare
    from linkgen.mujoco.simulate import simulate

    out = {}
    for path in SPRING_MODELS:
        asm = assemble(load(path))
        out[path.stem] = compare(asm, simulate(asm))
    return out


@pytest.mark.parametrize("name", [p.stem for p in SPRING_MODELS])
def test_mujoco_validates_the_spring_models(comparisons, name):
    cmp = comparisons[name]
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad
    assert "inverse.balancing_torque" in cmp.quantities and "balancing_torque" in cmp.quantities


def test_the_mjcf_has_the_springs():
    from linkgen.mujoco.mjcf import write_mjcf

    m = mujoco.MjModel.from_xml_string(write_mjcf(assemble(load(MODELS / "slider_crank_spring.toml"))))
    t = m.tendon("spring:0")
    assert (m.tendon_stiffness[t.id], m.tendon_damping[t.id], m.tendon_lengthspring[t.id, 0]) == (2000.0, 20.0, 0.45)
    m = mujoco.MjModel.from_xml_string(write_mjcf(assemble(load(MODELS / "fourbar_torsion.toml"))))
    j = m.joint("C")
    assert (m.jnt_stiffness[j.id], m.dof_damping[j.dofadr[0]]) == (40.0, 0.5)


# MuJoCo's passive force against the closed form's at one state: both are the same few products
# of exact inputs; the closed form's pose and MuJoCo's differ by the written placements' rounding
# (~1e-16 of the size): 1e-10 of the spring's torque scale k·1 rad.
PASSIVE_TOL = 1e-10


@pytest.mark.parametrize("joint, links, tree", [("C", ("ground", "rocker"), True), ("C", ("rocker", "ground"), True),
                                                 ("B", ("coupler", "rocker"), False),
                                                 ("A", ("coupler", "crank"), True)])
def test_the_torsion_springs_sign_and_rest_angle_in_mujoco(joint, links, tree):
    """At a pose away from the rest angle, with the closed form's joint speeds: MuJoCo's passive
    generalised force does the closed form's work, qfrc_passive·q̇ = τ·(θ̇_b − θ̇_a), and on the
    spring's own hinge (a tree joint) it is τ itself, signed for the child link."""
    from linkgen.families.planar.spring_loads import torsion_torque
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.state import joint_states
    from linkgen.mujoco.tree import spanning_tree

    d = _desc("fourbar_torsion")
    d["torsion_spring"] = [{"joint": joint, "links": list(links), "stiffness": 40.0, "rest_angle": "75deg",
                            "damping": 0.5}]
    mech = from_dict(d)
    asm = assemble(mech)
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm))
    data = mujoco.MjData(model)
    phi, w = np.array([2.2]), np.array([10.0])
    qpos, qvel, _ = joint_states(asm, model, phi, w, np.zeros(1))
    data.qpos[:], data.qvel[:] = qpos[0], qvel[0]
    mujoco.mj_forward(model, data)
    kin = solve(asm, phi)
    t = mech.torsion_springs[0]
    tau = float(torsion_torque(kin, t, w)[0])
    rate = w[0] * float(kin.links[links[1]].angle.d1[0] - kin.links[links[0]].angle.d1[0])
    assert abs(tau) > 5.0  # away from the rest angle
    assert float(data.qfrc_passive @ data.qvel) == pytest.approx(tau * rate, abs=PASSIVE_TOL * 40.0 * abs(rate))
    info = spanning_tree(mech)
    hinge = next(((p, c) for p, c, pair in info.tree if pair.name == joint), None)
    assert (hinge is not None and set(hinge) == set(links)) == tree
    if tree:
        dof = model.joint(joint).dofadr[0]
        on_child = tau if hinge[1] == links[1] else -tau
        assert data.qfrc_passive[dof] == pytest.approx(on_child, abs=PASSIVE_TOL * 40.0)


# The inverse route at the closed form's state: both sides are the same loads at the same pose;
# what is left is MuJoCo's rounding of a 3×3 solve and the RNE (crosscheck.compare's INVERSE_TOL,
# 1e-10 of the peak force, or force × size for a moment).
def test_mujocos_reactions_with_torsion_springs_at_a_tree_and_a_closing_revolute():
    """A slider-crank with torsion springs at A (a tree hinge: the hinge's own spring) and at B
    (the loop's closing revolute: a fixed tendon over O and A). MuJoCo applies the fixed tendon's
    torque to the tree's hinges, so the slide joint's couple (cfrc_int) would count it as the
    guide's: ``mujoco.springs.spring_wrenches`` puts the torques on the links for that reading
    (without it the slider's moment was off by 11.1 N·m at φ = 0.7 rad). The rod turns fully
    against the crank, so at φ = 2.5 and 4.4 rad the hinge at A has turned past ±π from the sketch:
    ``mujoco.state.joint_states`` counts it along the motion, as a run does (wrapped, A's spring
    torque was off by 30 N·m/rad·2π and A's reaction by 560 N)."""
    from linkgen.crosscheck.compare import INVERSE_TOL
    from linkgen.mujoco.forces import inverse_forces
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.state import joint_states

    d = _desc("slider_crank_spring")
    d["torsion_spring"] = [{"joint": "A", "links": ["crank", "rod"], "stiffness": 30.0, "rest_angle": "10deg",
                            "damping": 0.3},
                           {"joint": "B", "links": ["rod", "slider"], "stiffness": 20.0, "rest_angle": "-20deg",
                            "damping": 0.2}]
    asm = assemble(from_dict(d))
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm))
    assert model.tendon("torsion:1").id >= 0 and model.jnt_stiffness[model.joint("A").id] == 30.0
    data = mujoco.MjData(model)
    phi = np.array([0.7, 2.5, 4.4])
    w, e = np.full(3, 10.0), np.full(3, 3.0)
    qpos, qvel, qacc = joint_states(asm, model, phi, w, e)
    cf = forces(asm, phi, w, e)
    force = max(np.abs(r).max() for r in cf.reactions.values())
    for k in range(3):
        mj = inverse_forces(asm, model, data, float(phi[k]), qpos[k], qvel[k], qacc[k])
        for name, r in cf.reactions.items():
            np.testing.assert_allclose(mj.reactions[name], r[k], rtol=0, atol=INVERSE_TOL * force, err_msg=name)
        assert mj.normal_force["slider"] == pytest.approx(cf.normal_force["slider"][k], abs=INVERSE_TOL * force)
        assert mj.moment["slider"] == pytest.approx(cf.moment["slider"][k], abs=INVERSE_TOL * force * 0.65)
        assert mj.balancing_torque == pytest.approx(cf.balancing_torque[k], abs=INVERSE_TOL * force * 0.65)

"""PSSR and PSSP: spatial four-bars driven by a slider (models/pssr.toml, models/pssp.toml),
against routes that share nothing with the closed form: the loop closure solved numerically
in 3-D from the geometry written here (scipy), its finite differences for the transfer
functions and the jerk, and the power balance of the kinetic energy built from those
positions for the balancing force. MuJoCo's agreement on the two models is
tests/test_spatial_mujoco.py's (every bundled spatial model)."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from scipy.optimize import brentq, least_squares

import linkgen
from linkgen.errors import DescriptionError, StructureError
from linkgen.families.spatial.description import spatial_from_dict
from linkgen.families.spatial.forces import forces
from linkgen.families.spatial.kinematics import solve
from linkgen.families.spatial.mass import ROD_RADIUS
from linkgen.families.spatial.results import kinematics

from conftest import ROOT

PSSR, PSSP = ROOT / "models" / "pssr.toml", ROOT / "models" / "pssp.toml"
# Positions from the numerical solve against the closed form, over the size: the root finder
# stops at xtol = 1e-15 of the unknowns, a few roundings of float64 on 0.5 m.
POSITION_TOL = 1e-12
# Transfer functions by central differences of the numerical positions (step H of the input):
# d1 and d2 (3-point) lose ~H²·q⁽⁴⁾/12 (q⁽⁴⁾ up to ~1e5 per m⁴ near PSSR's s = −0.1 m: ~3e-4 of
# d2's 60 per m²) and rounding eps/H² ≈ 5e-9; d3 (5-point) ~H²·q⁽⁵⁾/4 plus eps/H³ ≈ 3e-5 —
# relative to each one's largest magnitude.
H = 2e-4
D12_TOL = 1e-4
D3_TOL = 1e-3
# Time derivatives by central differences over a time step DT of the numerical positions at
# s(t) = s0 + v·t + a·t²/2: the same truncation and rounding as above, in time.
DT = 2e-3
# The balancing force against ½·J′·v² + J·a − Σ m·g·c′ with J built from numerical finite
# differences (a step of 1e-5 m for c′, then of HJ for J′): truncation HJ²·J‴/6 and rounding
# (eps·|B|/1e-5 on c′, over HJ on J′: ~1e-7).
HJ = 1e-4
POWER_TOL = 1e-5
INPUTS = 41


def _data(path) -> dict:
    return tomllib.loads(path.read_text(encoding="utf-8"))


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _numerical_b(path, s: np.ndarray) -> np.ndarray:
    """B (n, 3) at input displacements s, from the description's geometry only: A moves along the
    input's line; B on the rocker's circle (PSSR) or the follower's line (PSSP), at the coupler's
    length from A; continued from the sketch's B along s."""
    d = _data(path)
    pts = {k: np.array(v, dtype=float) for k, v in d["points"].items()}
    u = _unit(d["prismatic"]["input"]["direction"])
    L = d["links"]["coupler"]["length"]
    out = []
    if "rocker" in d["links"]:
        b0, k = pts["B0"], _unit(d["joints"]["B0"]["axis"])
        # the rocker's length is exact: B's sketch is moved along B0→B onto it (docs/format.md)
        r = d["links"]["rocker"]["length"]
        off = float((pts["B"] - b0) @ k) * r / float(np.linalg.norm(pts["B"] - b0))

        def closure(b, a):
            return [np.linalg.norm(b - b0) - r, (b - b0) @ k - off, np.linalg.norm(b - a) - L]
    else:
        p0, k = pts["B"], _unit(d["prismatic"]["guide"]["direction"])
    order = np.argsort(np.abs(s))  # continue outward from the sketch, s = 0
    guess = {}
    for i in order:
        a = pts["A"] + s[i] * u
        if "rocker" in d["links"]:
            start = guess.get("b", pts["B"])
            sol = least_squares(closure, start, args=(a,), xtol=1e-15, ftol=1e-15, gtol=1e-15, method="lm")
            b = sol.x
        else:  # on the line's side of A's foot where the sketch's B lies, a root between the foot and 2L past it
            foot = float((a - p0) @ k)
            side = 1.0 if float((pts["A"] - p0) @ k) <= 0.0 else -1.0
            t = brentq(lambda t: np.linalg.norm(p0 + t * k - a) - L, foot, foot + side * 2 * L, xtol=1e-16, rtol=1e-15)
            b = p0 + t * k
        guess["b"] = b
        out.append((i, b))
    res = np.zeros((len(s), 3))
    for i, b in out:
        res[i] = b
    return res


@pytest.mark.parametrize("path", [PSSR, PSSP], ids=["pssr", "pssp"])
def test_positions_match_a_numerical_3d_solution(path):
    mech = linkgen.load(path)
    s = np.linspace(*mech.drive.range, INPUTS)
    closed = solve(mech, s).points["B"].d[0]
    numeric = _numerical_b(path, s)
    size = solve(mech, [0.0]).chain.size
    assert np.abs(closed - numeric).max() <= POSITION_TOL * size


def _output(path, b: np.ndarray) -> np.ndarray:
    """The output's variable from B alone: the rocker's angle about its axis (unwrapped), or
    the follower's travel along its line."""
    d = _data(path)
    pts = {k: np.array(v, dtype=float) for k, v in d["points"].items()}
    if "rocker" in d["links"]:
        k = _unit(d["joints"]["B0"]["axis"])
        e1 = _unit(np.cross(k, [1.0, 0.0, 0.0]))
        e2 = np.cross(k, e1)
        r = b - pts["B0"]
        return np.unwrap(np.arctan2(r @ e2, r @ e1))
    return (b - pts["B"]) @ _unit(d["prismatic"]["guide"]["direction"])


@pytest.mark.parametrize("path", [PSSR, PSSP], ids=["pssr", "pssp"])
def test_transfer_functions_match_finite_differences_of_the_numerical_solution(path):
    mech = linkgen.load(path)
    lo, hi = mech.drive.range
    s = np.linspace(lo + 2 * H, hi - 2 * H, 9)
    q = {j: _output(path, _numerical_b(path, s + j * H)) for j in (-2, -1, 0, 1, 2)}
    # one output, unwrapped per stencil: shift every branch onto the centre's
    for j in q:
        q[j] = q[0] + np.remainder(q[j] - q[0] + math.pi, 2 * math.pi) - math.pi if "rocker" in _data(path)["links"] else q[j]
    d1 = (q[1] - q[-1]) / (2 * H)
    d2 = (q[1] - 2 * q[0] + q[-1]) / H**2
    d3 = (q[2] - 2 * q[1] + 2 * q[-1] - q[-2]) / (2 * H**3)
    out = solve(mech, s).output
    for got, ref, tol in ((out.d[1], d1, D12_TOL), (out.d[2], d2, D12_TOL), (out.d[3], d3, D3_TOL)):
        assert np.abs(got - ref).max() <= tol * np.abs(ref).max(), (got, ref)


@pytest.mark.parametrize("path", [PSSR, PSSP], ids=["pssr", "pssp"])
def test_velocity_acceleration_and_jerk_match_time_differences(path):
    """B's velocity, acceleration and jerk at v = 0.5 m/s, a = 2 m/s² against central
    differences in time of the numerical B(s(t))."""
    mech = linkgen.load(path)
    v, acc = 0.5, 2.0
    lo, hi = mech.drive.range
    s0 = np.linspace(lo + 0.02, hi - 0.02, 5)  # the stencil's reach v·2·DT + a·2·DT² stays inside

    def b_at(t):
        return _numerical_b(path, s0 + v * t + 0.5 * acc * t**2)

    b = {j: b_at(j * DT) for j in (-2, -1, 0, 1, 2)}
    ref = ((b[1] - b[-1]) / (2 * DT), (b[1] - 2 * b[0] + b[-1]) / DT**2,
           (b[2] - 2 * b[1] + 2 * b[-1] - b[-2]) / (2 * DT**3))
    k = kinematics(mech, s0, v, acc).points["B"]
    for got, want, tol in ((k.velocity, ref[0], D12_TOL), (k.acceleration, ref[1], D12_TOL), (k.jerk, ref[2], D3_TOL)):
        assert np.abs(got - want).max() <= tol * np.abs(want).max()


def _rod_inertia(m, x, span, size) -> np.ndarray:
    """The mass model of docs/spatial.md: a uniform rod, m·ℓ²/12 across and ½·m·r² along,
    r = ROD_RADIUS·size."""
    r = ROD_RADIUS * size
    return m * span**2 / 12 * (np.eye(3) - np.outer(x, x)) + 0.5 * m * r**2 * np.outer(x, x)


@pytest.mark.parametrize("path", [PSSR, PSSP], ids=["pssr", "pssp"])
def test_balancing_force_is_the_power_balance_of_the_numerical_motion(path):
    """F = ½·J′(s)·v² + J(s)·a − Σ m·g·c′(s): the power the drive gives goes into the kinetic
    energy ½·J·v² and against gravity; J = Σ m·|c′|² + Ω′ᵀ·I·Ω′ from the numerical positions."""
    mech = linkgen.load(path)
    d = _data(path)
    size = solve(mech, [0.0]).chain.size
    g = np.array(mech.gravity)
    lo, hi = mech.drive.range
    s = np.linspace(lo + 2 * HJ, hi - 2 * HJ, 7)
    h = 1e-5
    pts = {k: np.array(v, dtype=float) for k, v in d["points"].items()}
    u = _unit(d["prismatic"]["input"]["direction"])

    def parts(x):
        """Σ m·c′·(…) pieces at inputs x: J (n,) and Σ m·g·c′ (n,)."""
        bp, bm = _numerical_b(path, x + h), _numerical_b(path, x - h)
        b1 = (bp - bm) / (2 * h)
        bb = _numerical_b(path, x)
        a = pts["A"] + np.outer(x, u)
        J = mech.link("slider").mass * np.ones_like(x)  # the input slider: c′ = u
        grav = mech.link("slider").mass * (u @ g) * np.ones_like(x)
        mc = mech.link("coupler").mass
        c1 = 0.5 * (u + b1)  # the coupler's midpoint
        J += mc * np.einsum("ij,ij->i", c1, c1)
        grav += mc * (c1 @ g)
        ab = bb - a
        ell = np.linalg.norm(ab, axis=1)[:, None]
        w1 = np.cross(ab / ell, (b1 - u) / ell)  # its turn rate without spin about its line
        J += mc * ell[:, 0] ** 2 / 12 * np.einsum("ij,ij->i", w1, w1)
        if "rocker" in d["links"]:
            mr = mech.link("rocker").mass
            c1r = 0.5 * b1
            J += mr * np.einsum("ij,ij->i", c1r, c1r)
            grav += mr * (c1r @ g)
            k = _unit(d["joints"]["B0"]["axis"])
            rb = bb - pts["B0"]
            dpsi = np.einsum("ij,ij->i", np.cross(k, rb - np.outer(rb @ k, k)), b1) / np.einsum(
                "ij,ij->i", rb - np.outer(rb @ k, k), rb - np.outer(rb @ k, k))
            span = d["links"]["rocker"]["length"]
            J += np.array([dp**2 * k @ _rod_inertia(mr, r / np.linalg.norm(r), span, size) @ k for dp, r in zip(dpsi, rb)])
        else:
            mf = mech.link("follower").mass
            J += mf * np.einsum("ij,ij->i", b1, b1)
            grav += mf * (b1 @ g)
        return J, grav

    v, acc = 0.5, 2.0
    J, grav = parts(s)
    jp = (parts(s + HJ)[0] - parts(s - HJ)[0]) / (2 * HJ)
    expected = 0.5 * jp * v**2 + J * acc - grav
    got = forces(mech, s, v, acc).balancing_torque
    assert np.abs(got - expected).max() <= POWER_TOL * np.abs(expected).max()


def test_the_input_pair_carries_no_force_along_its_line():
    """The reaction at the input's prismatic pair is square to its line: the drive's force is
    the only one along it (and the two together balance the slider)."""
    mech = linkgen.load(PSSR)
    s = np.linspace(*mech.drive.range, 11)
    f = forces(mech, s, 0.5, 0.0)
    u = np.array(mech.slides[0].direction) if mech.slides[0].name == "input" else None
    assert np.abs(f.reactions["input"].force @ u).max() <= 1e-12 * np.abs(f.reactions["input"].force).max()


def _with_drive(path, **drive) -> dict:
    data = _data(path)
    data["drive"] = {k: v for k, v in (data["drive"] | drive).items() if v is not None}
    return data


@pytest.mark.parametrize("drive, field, words", [
    ({"stop": 0.45}, "drive.stop", "the input range -0.1..0.45 m does not assemble: the coupler cannot reach the "
                                   "output at input displacements 0.3"),
    ({"start": -0.6}, "drive.start", "does not assemble"),
    ({"velocity": None}, "drive.velocity", "missing: a prismatic input needs the slider's velocity [m/s]"),
    ({"start": None}, "drive.start", "missing"),
    ({"stop": -0.2}, "drive.stop", "must be greater than drive.start (-0.1 m)"),
    ({"omega": 3.0}, "drive.omega", "unknown key; allowed: acceleration, joint, start, stop, velocity"),
])
def test_a_bad_prismatic_drive_is_named_by_field_and_value(drive, field, words):
    with pytest.raises(DescriptionError) as err:
        solve(spatial_from_dict(_with_drive(PSSR, **drive), "pssr.toml"), [0.0])
    text = str(err.value)
    assert text.startswith(f"pssr.toml: {field}: ") and words in text, text


def test_the_range_error_names_where_it_assembles():
    """The part of the range that assembles, as the error names it, does assemble; a step of the
    check's spacing past its edge does not."""
    with pytest.raises(DescriptionError) as err:
        solve(spatial_from_dict(_with_drive(PSSR, stop=0.45)), [0.0])
    text = str(err.value)
    lo, hi = (float(x) for x in text.split("it assembles only at input displacements ")[1].split(" m")[0].split(".."))
    assert lo == pytest.approx(-0.1) and 0.1 < hi < 0.45
    spatial_from_dict(_with_drive(PSSR, stop=hi))  # accepted
    step = 0.55 / 2000
    with pytest.raises(DescriptionError):
        solve(spatial_from_dict(_with_drive(PSSR, stop=hi + 2 * step)), [0.0])


def test_a_stroke_with_a_prismatic_input_is_refused():
    data = _data(PSSR) | {"force": [{"link": "rocker", "point": "B", "force": [1.0, 0, 0], "stroke": ["0deg", "90deg"]}]}
    with pytest.raises(DescriptionError, match=r"^force\[0\]\.stroke: is a range of crank angles; with a prismatic input"):
        spatial_from_dict(data)


def test_a_four_revolute_chain_cannot_be_driven_by_a_slider():
    data = _data(PSSR)
    data["joints"]["A"] = {"kind": "revolute", "axis": [0.0, 0.0, 1.0]}
    data["joints"]["B"] = {"kind": "revolute", "axis": [0.0, 0.0, 1.0]}
    with pytest.raises(StructureError, match="and the input slides; linkgen solves RSSR, RSSP, PSSR and PSSP"):
        solve(spatial_from_dict(data), [0.0])


def test_the_cli_speaks_of_the_slider_input(tmp_path):
    import subprocess
    import sys

    def run(*args):
        p = subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True, cwd=ROOT)
        assert p.returncode == 0, p.stderr
        return p.stdout

    assert "over s = -0.1..0.1 m at v = 0.5 m/s" in run("analyze", PSSP, "--summary")
    text = run("forces", PSSR)
    assert "s = -0.1 m" in text and "balancing force" in text and " N (power balance" in text
    csv = run("forces", PSSR, "--samples", "3").splitlines()[0]
    assert csv.startswith("phi [m],balancing_torque [N],power_balance_torque [N]")  # the names of every family, the unit saying it
    assert "input slider 'slider' (driven at 'input')" in run("structure", PSSR)
    # the command line's --angle number is the displacement in metres, refused outside the range
    p = subprocess.run([sys.executable, "-m", "linkgen", "analyze", PSSR, "--angle", "0.2rad"], capture_output=True,
                       text=True, cwd=ROOT)
    assert p.returncode != 0 and "outside its [drive] range -0.1..0.1 m" in p.stderr and "Traceback" not in p.stderr

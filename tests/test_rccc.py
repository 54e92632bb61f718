"""RCCC (models/rccc.toml): a crank and three cylindrical pairs, against routes that share
nothing with the closed form: the loop closure solved numerically in 3-D for the coupler's pose
and the output's turn and slide (scipy; the geometry written here from the description), its
finite differences for the transfer functions and the jerk, and the kinetic energy built from
those poses for the balancing torque. MuJoCo's agreement on the model is
tests/test_spatial_mujoco.py's (every bundled spatial model)."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import linkgen
from linkgen.errors import AssemblyError, StructureError
from linkgen.families.spatial.description import spatial_from_dict
from linkgen.families.spatial.forces import forces
from linkgen.families.spatial.kinematics import solve
from linkgen.families.spatial.mass import ROD_RADIUS
from linkgen.families.spatial.results import kinematics

from conftest import ROOT

RCCC = ROOT / "models" / "rccc.toml"
# The numerical solve against the closed form: least squares to xtol = ftol = 1e-15 on the
# pose's 8 unknowns, a few roundings of float64 on the 0.8 m size (positions, slides) or 1 rad.
POSITION_TOL = 1e-12
ANGLE_TOL = 1e-12
# Transfer functions by central differences of the numerical solution, step H [rad]: 3-point d1,
# d2 lose ~H²·q⁽⁴⁾/12 and eps/H² (2e-8 of q ~ 1); 5-point d3 ~H²·q⁽⁵⁾/4 and eps/H³ (2e-5) —
# relative to each one's largest magnitude over the turn.
H = 1e-3
D12_TOL = 1e-5
D3_TOL = 1e-3
# Time derivatives by central differences over DT [s] of the numerical positions at
# φ(t) = φ0 + ω·t + ε·t²/2 (ω = 10 rad/s: DT·ω = H).
DT = 1e-4
# The balancing torque against ½·J′·ω² − Σ m·g·c′, J from the numerical poses (c′ and Ω′ by a
# step of 1e-5 rad, J′ by HJ): truncation HJ²·J‴/6 and rounding eps·|x|/1e-5/HJ ≈ 2e-8.
HJ = 1e-4
POWER_TOL = 1e-6
ANGLES = 12


def _data() -> dict:
    return tomllib.loads(RCCC.read_text(encoding="utf-8"))


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _rotvec(v) -> np.ndarray:
    """The rotation matrix of rotation vector v (Rodrigues)."""
    a = math.sqrt(float(v @ v))
    if a < 1e-300:
        return np.eye(3)
    k = v / a
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(a) * kx + (1 - math.cos(a)) * (kx @ kx)


def _rot(axis, angle) -> np.ndarray:
    return _rotvec(_unit(axis) * angle)


class Geometry:
    """The description's points and axes, and the loop's 8 unknowns: the coupler's rotation
    vector and translation from the sketch, the output's turn θ and slide d."""

    def __init__(self, data=None):
        d = _data() if data is None else data
        self.p = {k: np.array(v, dtype=float) for k, v in d["points"].items()}
        self.k = {k: _unit(v["axis"]) for k, v in d["joints"].items()}

    def crank(self, phi):  # the crank's rotation: about A0's axis by φ (the sketch at φ = 0)
        return _rot(self.k["A0"], phi)

    def residual(self, x, phi):
        p, k = self.p, self.k
        rc, tc, th, d = _rotvec(x[:3]), x[3:6], x[6], x[7]
        ro, rk = _rot(k["B0"], th), self.crank(phi)

        def on_crank(v):  # a point of the crank
            return p["A0"] + rk @ (v - p["A0"])

        def on_coupler(v):
            return rc @ v + tc

        def on_output(v):
            return p["B0"] + ro @ (v - p["B0"]) + d * k["B0"]

        u1, c1 = rk @ k["A"], rc @ k["A"]  # A's axis as the crank and the coupler carry it
        u2, c2 = ro @ k["B"], rc @ k["B"]  # B's axis as the output and the coupler carry it
        return np.concatenate([np.cross(on_coupler(p["A"]) - on_crank(p["A"]), u1), np.cross(c1, u1),
                               np.cross(on_coupler(p["B"]) - on_output(p["B"]), u2), np.cross(c2, u2)])

    def _fit(self, x, phi):
        return least_squares(self.residual, x, args=(phi,), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15).x

    def solve(self, phis, guess=None):
        """The unknowns (n, 8) at crank angles ``phis``: from ``guess`` (n, 8) (a nearby solution),
        or marched from the sketch (x = 0 at φ = 0) up through the angles in steps of at most
        STEP, which keeps the branch."""
        phis = np.asarray(phis, dtype=float)
        if guess is not None:
            return np.stack([self._fit(x, phi) for x, phi in zip(guess, phis)])
        out, x, at = np.zeros((len(phis), 8)), np.zeros(8), 0.0
        for i in np.argsort(phis):
            for ph in np.linspace(at, phis[i], 2 + int(abs(phis[i] - at) / STEP))[1:]:
                x = self._fit(x, ph)
            out[i], at = x, phis[i]
        return out


# The numerical solution's march: steps of at most this [rad] stay on the sketch's branch.
STEP = 0.1


def test_positions_turn_and_slides_match_a_numerical_3d_solution():
    mech, g = linkgen.load(RCCC), Geometry()
    phi = np.linspace(0.0, 2 * math.pi, ANGLES, endpoint=False)
    x = g.solve(phi)
    k = solve(mech, phi)
    size = k.chain.size
    turn = np.remainder(k.turn.d[0] - x[:, 6] + math.pi, 2 * math.pi) - math.pi
    assert np.abs(turn).max() <= ANGLE_TOL
    assert np.abs(k.slides["B0"].d[0] - x[:, 7]).max() <= POSITION_TOL * size
    rc = Rotation.from_rotvec(x[:, :3]).as_matrix()
    a_cpl = np.einsum("nij,j->ni", rc, g.p["A"]) + x[:, 3:6]
    b_cpl = np.einsum("nij,j->ni", rc, g.p["B"]) + x[:, 3:6]
    assert np.abs(k.at("coupler", "A").d[0] - a_cpl).max() <= POSITION_TOL * size
    assert np.abs(k.points["B"].d[0] - b_cpl).max() <= POSITION_TOL * size
    # the pairs' slides: the coupler along A's axis from the crank's A, the output along B's from the coupler's B
    a_crank = g.p["A0"] + np.einsum("nij,j->ni", np.stack([g.crank(p) for p in phi]), g.p["A"] - g.p["A0"])
    u1 = np.einsum("nij,j->ni", np.stack([g.crank(p) for p in phi]), g.k["A"])
    assert np.abs(k.slides["A"].d[0] - np.einsum("ij,ij->i", a_cpl - a_crank, u1)).max() <= POSITION_TOL * size
    assert np.abs(k.frames["coupler"] - rc).max() <= ANGLE_TOL


def test_transfer_functions_match_finite_differences_of_the_numerical_solution():
    mech, g = linkgen.load(RCCC), Geometry()
    phi = np.linspace(0.0, 2 * math.pi, 5, endpoint=False) + 0.1
    base = g.solve(phi)
    x = {j: g.solve(phi + j * H, base) for j in (-2, -1, 0, 1, 2)}
    k = solve(mech, phi)
    for col, jet in ((6, k.turn), (7, k.slides["B0"])):  # the output's turn θ and slide d
        q = {j: x[j][:, col] for j in x}
        ref = ((q[1] - q[-1]) / (2 * H), (q[1] - 2 * q[0] + q[-1]) / H**2,
               (q[2] - 2 * q[1] + 2 * q[-1] - q[-2]) / (2 * H**3))
        for order, tol in ((1, D12_TOL), (2, D12_TOL), (3, D3_TOL)):
            assert np.abs(jet.d[order] - ref[order - 1]).max() <= tol * np.abs(ref[order - 1]).max(), (col, order)


def test_velocity_acceleration_and_jerk_match_time_differences():
    """The coupler's B at ω = 10 rad/s, ε = 30 rad/s² against central differences in time."""
    mech, g = linkgen.load(RCCC), Geometry()
    w, e = 10.0, 30.0
    phi0 = np.linspace(0.0, 2 * math.pi, 3, endpoint=False) + 0.2

    base = g.solve(phi0)

    def b_at(t):
        x = g.solve(phi0 + w * t + 0.5 * e * t**2, base)
        return np.einsum("nij,j->ni", Rotation.from_rotvec(x[:, :3]).as_matrix(), g.p["B"]) + x[:, 3:6]

    b = {j: b_at(j * DT) for j in (-2, -1, 0, 1, 2)}
    ref = ((b[1] - b[-1]) / (2 * DT), (b[1] - 2 * b[0] + b[-1]) / DT**2,
           (b[2] - 2 * b[1] + 2 * b[-1] - b[-2]) / (2 * DT**3))
    p = kinematics(mech, phi0, w, e).points["B"]
    for got, want, tol in ((p.velocity, ref[0], D12_TOL), (p.acceleration, ref[1], D12_TOL), (p.jerk, ref[2], D3_TOL)):
        assert np.abs(got - want).max() <= tol * np.abs(want).max()


def _rod(m, x, span, size) -> np.ndarray:
    """docs/spatial.md's mass model: a uniform rod, m·ℓ²/12 across, ½·m·r² along, r = ROD_RADIUS·size."""
    r = ROD_RADIUS * size
    return m * span**2 / 12 * (np.eye(3) - np.outer(x, x)) + 0.5 * m * r**2 * np.outer(x, x)


def test_balancing_torque_is_the_power_balance_of_the_numerical_motion():
    """T = ½·J′(φ)·ω² − Σ m·g·c′(φ) at constant ω, with J = Σ m·|c′|² + Ω′ᵀ·I·Ω′ over the crank,
    the coupler and the output, every c′ and Ω′ from the numerical poses."""
    mech, g = linkgen.load(RCCC), Geometry()
    size = solve(mech, [0.0]).chain.size
    grav = np.array(mech.gravity)
    h = 1e-5

    phi = np.linspace(0.0, 2 * math.pi, 6, endpoint=False) + 0.05
    base = g.solve(phi)

    def bodies(at):
        """(mass, points of the rod (2, n, 3) in the world, rotation (n, 3, 3)) per link at
        angles ``at`` near ``phi``."""
        x = g.solve(at, base)
        rc = Rotation.from_rotvec(x[:, :3]).as_matrix()
        rk = np.stack([g.crank(p) for p in at])
        ro = np.stack([_rot(g.k["B0"], t) for t in x[:, 6]])
        crank = [g.p["A0"] + rk @ (g.p[q] - g.p["A0"]) for q in ("A0", "A")]
        coupler = [rc @ g.p[q] + x[:, 3:6] for q in ("A", "B")]
        output = [g.p["B0"] + ro @ (g.p[q] - g.p["B0"]) + x[:, 7:8] * g.k["B0"] for q in ("B0", "B")]
        return [(mech.link(n).mass, np.stack(pts), r) for n, pts, r in
                (("crank", crank, rk), ("coupler", coupler, rc), ("output", output, ro))]

    def parts(phi):
        plus, minus, here = bodies(phi + h), bodies(phi - h), bodies(phi)
        J, gw = np.zeros(len(phi)), np.zeros(len(phi))
        for (m, pp, rp), (_, pm, rm), (_, p0, r0) in zip(plus, minus, here):
            c1 = (pp.mean(axis=0) - pm.mean(axis=0)) / (2 * h)
            skew = np.einsum("nij,nkj->nik", (rp - rm) / (2 * h), r0)  # R′·Rᵀ = [Ω′]×
            om = np.stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]], axis=1)
            rod = p0[1] - p0[0]
            span = np.linalg.norm(rod, axis=1)
            inertia = np.stack([_rod(m, r / s, s, size) for r, s in zip(rod, span)])
            J += m * np.einsum("ij,ij->i", c1, c1) + np.einsum("ni,nij,nj->n", om, inertia, om)
            gw += m * (c1 @ grav)
        return J, gw

    w = 10.0
    J, gw = parts(phi)
    jp = (parts(phi + HJ)[0] - parts(phi - HJ)[0]) / (2 * HJ)
    expected = 0.5 * jp * w**2 - gw
    got = forces(mech, phi, w, 0.0).balancing_torque
    assert np.abs(got - expected).max() <= POWER_TOL * np.abs(expected).max()


def test_every_reaction_is_determinate_and_square_to_its_axis():
    """RCCC's 18 unknowns are all determined; a cylindrical pair carries neither a force nor a
    moment along its axis."""
    mech = linkgen.load(RCCC)
    phi = np.linspace(0.0, 2 * math.pi, 13)
    k = solve(mech, phi)
    f = forces(mech, phi, motion=k)
    assert f.indeterminate == 0
    axes = {"A": np.einsum("nij,j->ni", k.frames["crank"], k.chain.ua), "B": np.einsum("nij,j->ni", k.frames["output"], k.chain.ub),
            "B0": np.broadcast_to(k.chain.kb, (phi.shape[0], 3))}
    for pair, u in axes.items():
        r = f.reactions[pair]
        scale = np.abs(r.force).max() + np.abs(r.moment).max()
        assert np.abs(np.einsum("ij,ij->i", r.force, u)).max() <= 1e-12 * scale
        assert np.abs(np.einsum("ij,ij->i", r.moment, u)).max() <= 1e-12 * scale


def _with(**joints) -> dict:
    data = _data()
    data["joints"] = data["joints"] | joints
    return data


def test_successive_parallel_axes_are_refused():
    with pytest.raises(StructureError, match="the axes of B and B0 are parallel; an RCCC needs skew successive axes"):
        solve(spatial_from_dict(_with(B={"kind": "cylindrical", "axis": [1.0, 0.15, 0.25]})), [0.0])


def test_a_chain_mixing_cylindrical_with_other_pairs_is_named():
    with pytest.raises(StructureError, match="with cylindrical pairs linkgen solves the RCCC chain"):
        solve(spatial_from_dict(_with(B={"kind": "spherical"})), [0.0])


def test_where_the_twist_cannot_be_kept_the_crank_angles_are_named():
    """A's axis turned to 60° from the drive axis: the coupler's twist cannot be kept over part
    of the turn; the error names the crank angles."""
    mech = spatial_from_dict(_with(A={"kind": "cylindrical", "axis": [0.0, 1.0, 0.5773502691896258]}))
    with pytest.raises(AssemblyError, match=r"group RCCC \[crank, coupler, output\] cannot be assembled at crank angles "
                                            r"[0-9.]+°\.\.[0-9.]+°, [0-9.]+°\.\.[0-9.]+°: the coupler's twist cannot be kept"):
        solve(mech, np.linspace(0.0, 2 * math.pi, 360))


def test_the_cli_lists_the_pairs_slides_and_the_copies():
    import json
    import subprocess
    import sys

    p = subprocess.run([sys.executable, "-m", "linkgen", "analyze", RCCC, "--angle", "30deg", "--json"],
                       capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert {"A", "B", "B0"} <= set(d["sliders"]) and "output" in d["links"]
    assert {"A:coupler", "B:output", "B0:output"} <= set(d["points"])
    k = solve(linkgen.load(RCCC), [math.radians(30.0)])
    assert d["sliders"]["B0"]["displacement"] == pytest.approx(float(k.slides["B0"].d[0][0]), abs=1e-15)

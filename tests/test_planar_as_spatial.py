"""One convention for every family (docs/format.md, "Conventions"), proved on one mechanism
described twice: a planar four-bar, and the same four-bar written as a spatial RSSR (every pair
axis along z, every point in the plane z = 0, the coupler on two spherical pairs, whose idle spin
about its own line carries nothing).

Both must give the same reaction at every pair (the same link acted on, the same link acting,
the same in-plane components), the same balancing torque, the same time ratio K and the same
summary (swing, limit positions at the same crank angles with the same values, peak torque and
peak reactions). The balancing torque is also checked against virtual work computed here from an
independent position solution of the four-bar (circle intersection) and finite differences —
nothing from linkgen's closed forms.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import strategies as st

import linkgen
from linkgen.families.planar.kinetostatics import forces as planar_forces
from linkgen.families.spatial.forces import forces as spatial_forces
from linkgen.pipeline.registry import loads

ROOT = Path(__file__).resolve().parents[1]

# The two families solve the same statics by different routes (the planar one 6×6 LU per group,
# the spatial one a least-squares solve of 18 equations in 17 unknowns): each rounds at ~eps
# times the condition number of its system, which the least transmission angle kept here
# (≥ MIN_TRANSMISSION) and link ratios ≤ 16 bound by ~1e3, i.e. ~2e-13 of the largest force.
# Measured over 25 generated four-bars: 1.1e-14. 1e-10 leaves a margin and still catches any sign or
# lever-arm error, which shows at the size of the force itself.
REACTION_TOL = 1e-10
# The same crank angle of a limit position refined by each family's Brent search to 1e-13 rad
# (a simple root of dq/dφ): both within a few ulps of 2π of the root.
LIMIT_ANGLE_TOL = 1e-11
# A peak's crank angle from Brent's bounded minimiser on two different sample grids (planar
# 3601 samples with the end, spatial 3600 periodic): near a smooth maximum the objective is flat
# to ~f″·δ²/2, so rounding (eps·|f|) leaves the location free by δ ~ √(2·eps·|f|/|f″|) ≈ 1.5e-8·
# √(2|f|/|f″|), up to ~1e-6 rad for the flat peaks here — far below the 1.7e-3 rad sample step
# that a different convention would shift it by. Measured over 25 generated four-bars: 1.1e-7.
PEAK_ANGLE_TOL = 1e-5
# A peak's value is second-order in the location error: eps-level. Measured: 9e-15.
PEAK_VALUE_TOL = 1e-12
# The virtual-work torque from 5-point finite differences with step H: truncation ~H⁴/90·q⁽⁶⁾ and
# rounding ~eps·|q|/H² ≈ 6e-11·|q| in the second derivatives (rounding dominates: H = 5e-4 gives
# 1.6e-8, H = 2e-3 1.1e-9 over 25 generated four-bars), so 1e-7 of the torque scale (Σ|terms|)
# bounds it with a margin and still catches a missing or wrong load, which shows at its own size.
FD_TOL = 1e-7
H = 2e-3
# Generated four-bars keep this least transmission angle (conditioning of both statics) and the
# rocker this far from ±π (where an angle's representative is a matter of wrapping).
MIN_TRANSMISSION = math.radians(25.0)
ANGLE_MARGIN = 0.05
GRAVITY = 9.81

PLANAR = """
[mechanism]
name = "fourbar"
gravity = [0.0, {g_y!r}]

[points]
O = [0.0, 0.0]
A = [{a!r}, 0.0]
B = [{bx!r}, {by!r}]
C = [{d!r}, 0.0]

[links.ground]
points = ["O", "C"]

[links.crank]
points = ["O", "A"]
length = {a!r}
density = {rho!r}

[links.coupler]
points = ["A", "B"]
length = {b!r}
density = {rho!r}

[links.rocker]
points = ["C", "B"]
length = {c!r}
density = {rho!r}

[[force]]
link = "rocker"
point = "B"
force = [{fx!r}, {fy!r}]

[[torque]]
link = "coupler"
torque = {m!r}

[drive]
joint = "O"
omega = {omega!r}
"""

SPATIAL = """
[mechanism]
name = "fourbar_rssr"
space = "spatial"
gravity = [0.0, {g_y!r}, 0.0]

[points]
O = [0.0, 0.0, 0.0]
A = [{a!r}, 0.0, 0.0]
B = [{bx!r}, {by!r}, 0.0]
C = [{d!r}, 0.0, 0.0]

[links.ground]
points = ["O", "C"]

[links.crank]
points = ["O", "A"]
length = {a!r}
density = {rho!r}

[links.coupler]
points = ["A", "B"]
length = {b!r}
density = {rho!r}

[links.rocker]
points = ["C", "B"]
length = {c!r}
density = {rho!r}

[joints.O]
kind = "revolute"
axis = [0.0, 0.0, 1.0]

[joints.A]
kind = "spherical"

[joints.B]
kind = "spherical"

[joints.C]
kind = "revolute"
axis = [0.0, 0.0, 1.0]

[[force]]
link = "rocker"
point = "B"
force = [{fx!r}, {fy!r}, 0.0]

[[torque]]
link = "coupler"
torque = [0.0, 0.0, {m!r}]

[drive]
joint = "O"
omega = {omega!r}
"""

# models/fourbar.toml's numbers (crank 0.3 m, coupler 1.0 m, rocker 0.7 m, ground 1.0 m, 10 kg/m,
# 10 rad/s, B above the x axis), without loads.
FOURBAR = dict(a=0.3, b=1.0, c=0.7, d=1.0, rho=10.0, omega=10.0, fx=0.0, fy=0.0, m=0.0, branch=1)


def _poses(p: dict, phi: np.ndarray) -> dict[str, np.ndarray]:
    """Points (n, 2) [m] of the four-bar at crank angles ``phi``: B where the circles about A (the
    coupler) and C (the rocker) meet, on the side ``branch`` of the line A→C (+1: left)."""
    a_pt = p["a"] * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    u = np.array([p["d"], 0.0]) - a_pt
    dist = np.hypot(u[:, 0], u[:, 1])
    x = (p["b"] ** 2 - p["c"] ** 2 + dist**2) / (2 * dist)
    h = p["branch"] * np.sqrt(p["b"] ** 2 - x**2)
    e = u / dist[:, None]
    b_pt = a_pt + x[:, None] * e + h[:, None] * np.stack([-e[:, 1], e[:, 0]], axis=1)
    return {"O": np.zeros_like(a_pt), "A": a_pt, "B": b_pt, "C": np.broadcast_to([p["d"], 0.0], a_pt.shape)}


def _texts(p: dict) -> tuple[str, str]:
    b = _poses(p, np.array([0.0]))["B"][0]
    values = dict(p, bx=float(b[0]), by=float(b[1]), g_y=-GRAVITY)
    return PLANAR.format(**values), SPATIAL.format(**values)


def _d(f, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First and second derivatives of ``f`` (vectorised over φ) by 5-point central differences."""
    fm2, fm1, f0, fp1, fp2 = (f(phi + k * H) for k in (-2, -1, 0, 1, 2))
    return (fm2 - 8 * fm1 + 8 * fp1 - fp2) / (12 * H), (-fm2 + 16 * fm1 - 30 * f0 + 16 * fp1 - fp2) / (12 * H * H)


def _virtual_work_torque(p: dict, phi: np.ndarray, omega: float, epsilon: float) -> tuple[np.ndarray, float]:
    """The torque on the crank that balances gravity, inertia and the loads, T + Σ F·v′ + M·θ′ = 0
    with d'Alembert's loads, from the independent poses; and the scale Σ|terms| it rounds at."""
    links = {"crank": ("O", "A", p["a"]), "coupler": ("A", "B", p["b"]), "rocker": ("C", "B", p["c"])}
    torque, scale = np.zeros_like(phi), np.zeros_like(phi)
    for name, (s, e, length) in links.items():
        mass, inertia = p["rho"] * length, p["rho"] * length**3 / 12.0
        com1, com2 = _d(lambda x: 0.5 * (_poses(p, x)[s] + _poses(p, x)[e]), phi)
        vec = _poses(p, phi)[e] - _poses(p, phi)[s]
        v1, v2 = _d(lambda x: _poses(p, x)[e] - _poses(p, x)[s], phi)
        th1 = (vec[:, 0] * v1[:, 1] - vec[:, 1] * v1[:, 0]) / length**2  # dθ/dφ = v × v′ / |v|²
        th2 = (vec[:, 0] * v2[:, 1] - vec[:, 1] * v2[:, 0]) / length**2  # d²θ/dφ² (|v| is constant)
        force = -mass * (com2 * omega**2 + com1 * epsilon) + np.array([0.0, -mass * GRAVITY])
        moment = -inertia * (th2 * omega**2 + th1 * epsilon)
        terms = [np.einsum("ij,ij->i", force, com1), moment * th1]
        if name == "rocker":
            terms.append(_d(lambda x: _poses(p, x)["B"], phi)[0] @ np.array([p["fx"], p["fy"]]))
        if name == "coupler":
            terms.append(p["m"] * th1)
        for t in terms:
            torque -= t
            scale += np.abs(t)
    return torque, float(scale.max())


def _check_forces(planar, spatial, p: dict, epsilon: float) -> None:
    phi = np.linspace(0.0, 2 * math.pi, 240, endpoint=False)
    omega = p["omega"]
    fp = planar_forces(planar, phi, omega, epsilon)
    fs = spatial_forces(spatial, phi, omega, epsilon)
    scale = max(float(np.abs(r).max()) for r in fp.reactions.values())
    assert set(fs.reactions) == set(fp.reactions) == {"O", "A", "B", "C"}
    for name, r in fs.reactions.items():
        assert (r.on, r.by) == (fp.on[name], fp.by[name]), name
        np.testing.assert_allclose(r.force[:, :2], fp.reactions[name], rtol=0, atol=REACTION_TOL * scale,
                                   err_msg=f"in-plane reaction at {name}")
        np.testing.assert_allclose(r.force[:, 2], 0.0, atol=REACTION_TOL * scale, err_msg=f"z force at {name}")
    expected, t_scale = _virtual_work_torque(p, phi, omega, epsilon)
    np.testing.assert_allclose(fp.balancing_torque, expected, rtol=0, atol=FD_TOL * t_scale)
    np.testing.assert_allclose(fs.balancing_torque, expected, rtol=0, atol=FD_TOL * t_scale)


# The summary keys only one family has: the planar one's least transmission angle of each Assur
# group (the spatial family defines no transmission angle) and its springs' peaks and friction losses (a spatial
# description has neither), the spatial one's chain kind (RSSR,
# RSSP, ...) and its degree of static indeterminacy (a planar chain is always determinate).
# ``model`` both have, with the names of two different files.
PLANAR_ONLY = {"min_transmission_angle", "peak_spring_forces", "peak_friction_power", "mean_friction_power",
               "stroke", "drive_joint"}  # the last two: whether the drive is a prismatic pair, and its name
SPATIAL_ONLY = {"kind", "statically_indeterminate"}


def _same(a, b, path: tuple) -> None:
    """Planar summary data ``a`` and spatial ``b`` are equal: the same keys and strings, drive
    angles equal modulo 2π and numbers equal, to the tolerances above (the peaks' own, the
    rest — limits, travel, strokes, K, ω, the drive's range — to LIMIT_ANGLE_TOL)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), (path, sorted(set(a) ^ set(b or {})))
        for k in a:
            _same(a[k], b[k], path + (k,))
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), (path, a, b)
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, path + (i,))
    elif isinstance(a, float) and path[-1] == "phi":
        tol = PEAK_ANGLE_TOL if path[0].startswith("peak_") else LIMIT_ANGLE_TOL
        assert abs(math.remainder(b - a, 2 * math.pi)) <= tol, (path, a, b)
    elif isinstance(a, float) and path[0].startswith("peak_"):
        assert b == pytest.approx(a, rel=PEAK_VALUE_TOL), (path, a, b)
    elif isinstance(a, float):
        assert b == pytest.approx(a, abs=LIMIT_ANGLE_TOL), (path, a, b)
    else:
        assert a == b, (path, a, b)


def _check_summary(planar, spatial) -> None:
    """The two summaries' dicts are equal for every key both have (``_same``): the output under
    the same key (the link's name), its swing, limit positions at the same crank angles with the
    same absolute angles, strokes and K ≥ 1, the peak torque and the peak reaction at each pair."""
    dp = linkgen.summary(planar).to_dict()
    ds = linkgen.summary(spatial).to_dict()
    assert set(dp) - set(ds) == PLANAR_ONLY and set(ds) - set(dp) == SPATIAL_ONLY, sorted(set(dp) ^ set(ds))
    assert list(ds["outputs"]) == list(dp["outputs"]) == ["rocker"]
    assert ds["forces_note"] is None and ds["statically_indeterminate"] == 0
    for key in sorted((set(dp) & set(ds)) - {"model", "units"}):
        _same(dp[key], ds[key], (key,))
    for key in set(dp["units"]) & set(ds["units"]):
        assert dp["units"][key] == ds["units"][key], key
    (out,) = ds["outputs"].values()
    assert out["time_ratio"] >= 1.0 and len(out["limits"]) == 2
    # the terminal says the same, line for line, but for the header naming the kind and the
    # planar transmission angle (the spatial family defines none); the last digit may differ
    tp = [ln for ln in linkgen.summary(planar).text().splitlines()[1:] if "transmission angle" not in ln]
    ts = linkgen.summary(spatial).text().splitlines()[1:]
    assert [re.sub(r"\d+(\.\d+)?", "#", ln) for ln in tp] == [re.sub(r"\d+(\.\d+)?", "#", ln) for ln in ts]


def test_the_bundled_fourbar_template_is_models_fourbar():
    """The planar text above with FOURBAR's numbers describes models/fourbar.toml's mechanism."""
    planar, _ = _texts(FOURBAR)
    mine, bundled = loads(planar), linkgen.load(ROOT / "models" / "fourbar.toml")
    phi = np.linspace(0.0, 2 * math.pi, 36, endpoint=False)
    np.testing.assert_array_equal(planar_forces(mine, phi, 10.0).balancing_torque,
                                  planar_forces(bundled, phi, 10.0).balancing_torque)


# A crank-rocker whose min → max stroke takes the shorter crank turn (175° of 360°): there a
# time ratio taken as min → max over max → min falls below 1 (0.942; planar K = 1.0618).
SHORT_RISE = dict(FOURBAR, a=0.27, b=0.71, c=0.69, branch=-1)


@pytest.mark.parametrize("p", [FOURBAR, SHORT_RISE], ids=["fourbar", "short-rise"])
def test_fourbar_as_rssr_gives_the_same_reactions_torque_and_summary(p):
    planar, spatial = (loads(t) for t in _texts(p))
    _check_forces(planar, spatial, p, epsilon=3.0)
    _check_summary(planar, spatial)


def _crank_rocker(a: float, b: float, c: float) -> bool:
    """Grashof crank-rocker with the crank shortest and a margin of 0.05 m from a change point."""
    d = 1.0
    lengths = sorted((a, b, c, d))
    return lengths[0] == a and a + lengths[-1] <= sum(lengths[1:3]) - 0.05


@settings(max_examples=8, deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(a=st.floats(0.1, 0.4), b=st.floats(0.4, 1.6), c=st.floats(0.4, 1.6), rho=st.floats(1.0, 20.0),
       omega=st.floats(-20.0, 20.0).filter(lambda w: abs(w) >= 0.5), epsilon=st.floats(-50.0, 50.0),
       fx=st.floats(-100.0, 100.0), fy=st.floats(-100.0, 100.0), m=st.floats(-20.0, 20.0),
       branch=st.sampled_from([1, -1]))
def test_generated_crank_rockers_as_rssr_agree(a, b, c, rho, omega, epsilon, fx, fy, m, branch):
    """Planar crank-rockers (ground 1 m, loads on the rocker and the coupler, either branch, either
    sense of rotation) written as spatial RSSRs: the same reactions, torque, K and summary."""
    assume(_crank_rocker(a, b, c))
    p = dict(a=a, b=b, c=c, d=1.0, rho=rho, omega=omega, fx=fx, fy=fy, m=m, branch=branch)
    phi = np.linspace(0.0, 2 * math.pi, 720, endpoint=False)
    pts = _poses(p, phi)
    ab, cb = pts["B"] - pts["A"], pts["B"] - pts["C"]
    assume(np.all(np.abs(ab[:, 0] * cb[:, 1] - ab[:, 1] * cb[:, 0]) >= b * c * math.sin(MIN_TRANSMISSION)))
    assume(np.all(np.abs(np.arctan2(cb[:, 1], cb[:, 0])) <= math.pi - ANGLE_MARGIN))
    planar, spatial = (loads(t) for t in _texts(p))
    _check_forces(planar, spatial, p, epsilon)
    _check_summary(planar, spatial)


# The structure keys only one family has: planar the structure formula and the Assur groups,
# spatial the chain's kind, its coupler, output link and output pair. ``lines`` both have with
# each family's own wording, ``model`` with the names of two different files.
STRUCTURE_PLANAR_ONLY = {"formula", "groups"}
STRUCTURE_SPATIAL_ONLY = {"kind", "coupler", "output", "pair_out"}


def test_fourbar_as_rssr_gives_the_same_structure_keys():
    """mobility, crank and drive pair: the same keys and the same values in both families."""
    planar, spatial = (loads(t) for t in _texts(FOURBAR))
    dp, ds = linkgen.structure(planar).to_dict(), linkgen.structure(spatial).to_dict()
    assert set(dp) - set(ds) == STRUCTURE_PLANAR_ONLY and set(ds) - set(dp) == STRUCTURE_SPATIAL_ONLY
    assert {k: dp[k] for k in set(dp) & set(ds) - {"model", "lines"}} == {"mobility": 1, "crank": "crank", "drive": "O"}
    assert {k: ds[k] for k in set(dp) & set(ds) - {"model", "lines"}} == {"mobility": 1, "crank": "crank", "drive": "O"}


# The twin's motion from the spatial closed form (a rotation-matrix chain) against the planar one
# (Assur groups): both round at ~eps times the conditioning the transmission angle keeps ≤ ~1e3,
# and the third derivatives (jerk) multiply ω³ = 1e3 on values of order 1: 1e-9 of each quantity's
# largest magnitude bounds that, and any other name, sign or reference shows at the value's size.
KINEMATICS_TOL = 1e-9


def test_fourbar_as_rssr_gives_the_same_kinematics_keys_and_values():
    """The RSSR twin's kinematics dict equals the planar one for every key both have: the crank and
    the rocker under ``links`` by their link names (angle, angular_velocity, ... and d1..d3), no
    slider, and the points' in-plane motion (the twin's z is 0)."""
    planar, spatial = (loads(t) for t in _texts(FOURBAR))
    phi = np.linspace(0.0, 2 * math.pi, 24, endpoint=False)
    dp, ds = linkgen.kinematics(planar, phi).to_dict(), linkgen.kinematics(spatial, phi).to_dict()
    assert set(ds) - set(dp) == {"kind"} and set(dp) - set(ds) == {"singular"}, sorted(set(dp) ^ set(ds))
    assert list(ds["links"]) == ["crank", "rocker"] and ds["sliders"] == dp["sliders"] == {}
    for name in ds["links"]:
        assert ds["links"][name].keys() == dp["links"][name].keys(), name
        for q, v in ds["links"][name].items():
            want = np.asarray(dp["links"][name][q])
            if q == "angle":  # the same direction: equal modulo 2π (the planar link's is wrapped to (-π, π])
                v = want + np.remainder(np.asarray(v) - want + math.pi, 2 * math.pi) - math.pi
            np.testing.assert_allclose(v, want, rtol=0, atol=KINEMATICS_TOL * max(1.0, np.abs(want).max()),
                                       err_msg=f"links.{name}.{q}")
    for name, p in ds["points"].items():
        assert p.keys() == dp["points"][name].keys(), name
        for q, v in p.items():
            want = np.asarray(dp["points"][name][q])
            np.testing.assert_allclose(np.asarray(v)[:, :2], want, rtol=0,
                                       atol=KINEMATICS_TOL * max(1.0, np.abs(want).max()), err_msg=f"points.{name}.{q}")
            np.testing.assert_allclose(np.asarray(v)[:, 2], 0.0, atol=KINEMATICS_TOL, err_msg=f"points.{name}.{q}.z")
    for top in ("phi", "omega", "epsilon"):
        np.testing.assert_allclose(np.broadcast_to(ds[top], np.shape(dp[top])), dp[top], rtol=0, atol=0)

"""Spatial four-bars in closed form: the bundled models assemble over the turn; the three transfer
functions of every point and of the output against central differences; the RSSR's sketch; the
planar four-bar as a spatial RSSR and as a planar 4R against the planar solver; the spherical
chain on its sphere; Bennett's conditions and the coupler's common normal along the motion; and
the errors (not a movable 4R, a coupler that cannot reach, a bad field)."""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest

import linkgen
from linkgen.errors import AssemblyError, DescriptionError, StructureError, angle_ranges
from linkgen.families.planar.kinematics import solve as planar_solve
from linkgen.families.spatial.chain import bennett_defects, build_chain, common_normal
from linkgen.families.spatial.description import spatial_from_dict
from linkgen.families.spatial.kinematics import solve

from conftest import ROOT

KINDS = {"rssr": "RSSR", "rssp": "RSSP", "spherical_fourbar": "spherical", "bennett": "Bennett"}
# The bundled models keep the normalised denominator this far from a dead centre over the whole
# turn: transfer functions lose no more than ~1/D² = 400 ulps (SINGULAR_TOL is 1e-4).
MIN_DENOMINATOR = 0.05
TURN = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False)

# Central differences of the order below with step H: truncation H²/6·|x⁽ᵏ⁺²⁾| (the leading
# term; the next, H⁴/120·|x⁽ᵏ⁺⁴⁾|, is 1e-10 of it) plus rounding ROUND_ULPS·ε·|x⁽ᵏ⁻¹⁾|/H:
# each closed-form value carries up to ~100 ulps of its scale (some 30 operations, conditioned
# by 1/|D| ≤ 20). |x⁽ᵏ⁺²⁾| is bounded over the turn from the jets' own third derivative,
# differenced with wider steps (H4, H5) where rounding stays far below the bound; FD_SAFETY
# covers the bound's estimation (a second difference at H5 is within ~H5²/12·|x⁽⁷⁾| of x⁽⁵⁾).
H = 1e-4
H4, H5 = 1e-3, 1e-2
ROUND_ULPS = 100.0
FD_SAFETY = 2.0
EPS = np.finfo(float).eps
FD_PHI = np.linspace(0.0, 2 * np.pi, 360, endpoint=False) + 0.0123  # off the special poses

# Printed to 6 significant digits in the RSSR's description: ±5e-6 m.
PRINTED_TOL = 5e-6
# Two closed forms of the same planar four-bar agree to rounding: metre-sized values after
# ~50 operations, a few ulps each (1e-12 m, m/rad, m/rad²).
PLANAR_TOL = 1e-12
# The spherical chain's points stay on their spheres (relative) and move square to the radius:
# the closed form carries every point by rotations about axes through the centre, to rounding.
SPHERE_TOL = 1e-12
# Bennett: the model's axes are exact to rounding (repr floats), and the coupler's common
# normal along the motion keeps its length [m] and twist [rad] to rounding of the closed form.
BENNETT_DEFECT_TOL = 1e-10
BENNETT_NORMAL_TOL = 1e-10


def _model(name: str):
    path = ROOT / "models" / f"{name}.toml"
    return spatial_from_dict(tomllib.loads(path.read_text(encoding="utf-8")), str(path))


@pytest.fixture(params=sorted(KINDS), ids=sorted(KINDS))
def name(request) -> str:
    return request.param


# --- the bundled models ----------------------------------------------------------------------


def test_model_is_its_kind_and_turns_fully(name):
    mech = _model(name)
    assert build_chain(mech).kind == KINDS[name]
    k = solve(mech, TURN)  # no AssemblyError, no SingularityError
    assert np.abs(k.denominator).min() > MIN_DENOMINATOR
    assert mech.drive.omega == 10.0
    assert all(l.mass > 0 for l in mech.links if l.name != "ground")
    assert mech.gravity == (0.0, 0.0, -9.81)


def _wrapped(x: np.ndarray, angle: bool) -> np.ndarray:
    return np.remainder(x + np.pi, 2 * np.pi) - np.pi if angle else x


def _fd_check(jet_at, angle: bool = False) -> list[float]:
    """For k = 1, 2, 3: the worst |central difference of x⁽ᵏ⁻¹⁾ − x⁽ᵏ⁾| over the tolerance."""
    d0, dp, dm = jet_at(FD_PHI), jet_at(FD_PHI + H), jet_at(FD_PHI - H)
    # bounds of x⁽⁴⁾ and x⁽⁵⁾ from x‴ (the jets' highest order) differenced with wider steps
    d3p4, d3m4 = jet_at(FD_PHI + H4)[3], jet_at(FD_PHI - H4)[3]
    d3p5, d3m5 = jet_at(FD_PHI + H5)[3], jet_at(FD_PHI - H5)[3]
    x4 = np.abs((d3p4 - d3m4) / (2 * H4)).max()
    x5 = np.abs((d3p5 - 2 * d0[3] + d3m5) / H5**2).max()
    higher = {1: np.abs(d0[3]).max(), 2: x4, 3: x5}
    ratios = []
    for k in (1, 2, 3):
        fd = _wrapped(dp[k - 1] - dm[k - 1], angle and k == 1) / (2 * H)
        err = np.abs(fd - d0[k]).max()
        scale = np.abs(d0[k - 1]).max() if not (angle and k == 1) else np.pi
        tol = FD_SAFETY * (H**2 / 6 * higher[k] + ROUND_ULPS * EPS * scale / H)
        ratios.append(err / tol)
    return ratios


def test_transfer_functions_of_every_point_match_central_differences(name):
    mech = _model(name)
    fixed = set(mech.link("ground").points)
    for point in mech.points:
        if point in fixed:  # a ground point: its derivatives are exactly zero
            assert not solve(mech, FD_PHI).points[point].d[1:].any(), point
            continue
        ratios = _fd_check(lambda phi: solve(mech, phi).points[point].d)
        assert max(ratios) <= 1.0, (point, ratios)


def test_transfer_functions_of_the_output_match_central_differences(name):
    mech = _model(name)
    angle = not build_chain(mech).output_slides
    ratios = _fd_check(lambda phi: solve(mech, phi).output.d, angle=angle)
    assert max(ratios) <= 1.0, ratios


# --- the RSSR's sketch -------------------------------------------------------------------------


def test_rssr_sketch_point_b():
    k = solve(_model("rssr"), [0.0])
    b = k.points["B"].d[0, 0]
    assert np.abs(b - np.array([0.6, 0.40038, 0.846875])).max() <= PRINTED_TOL
    assert b[1] > 0
    assert math.isclose(np.linalg.norm(b - k.points["A"].d[0, 0]), 1.0, abs_tol=1e-12)
    assert math.isclose(np.linalg.norm(b - np.array([0.6, 0.0, 0.4])), 0.6, abs_tol=1e-12)


# --- the planar four-bar as a special case -----------------------------------------------------

# models/fourbar.toml: O = (0, 0), A = (0.3, 0), B ≈ (1.0143, 0.6999), C = (1, 0); OA = 0.3 m,
# AB = 1.0 m, CB = 0.7 m; every axis along z, every point at z = 0.
FOURBAR_POINTS = {"O": [0.0, 0.0, 0.0], "A": [0.3, 0.0, 0.0], "B": [1.0143, 0.6999, 0.0], "C": [1.0, 0.0, 0.0]}


def _planar_as_spatial(a_kind: str, b_kind: str) -> dict:
    joints = {"O": {"kind": "revolute", "axis": [0.0, 0.0, 1.0]}, "C": {"kind": "revolute", "axis": [0.0, 0.0, 1.0]}}
    for p, kind in (("A", a_kind), ("B", b_kind)):
        joints[p] = {"kind": kind} | ({"axis": [0.0, 0.0, 1.0]} if kind == "revolute" else {})
    return {
        "mechanism": {"name": "fourbar3", "space": "spatial"},
        "points": copy.deepcopy(FOURBAR_POINTS),
        "links": {"ground": {"points": ["O", "C"]},
                  "crank": {"points": ["O", "A"], "length": 0.3},
                  "coupler": {"points": ["A", "B"], "length": 1.0},
                  "rocker": {"points": ["C", "B"], "length": 0.7}},
        "joints": joints,
        "drive": {"joint": "O", "omega": 10.0},
    }


@pytest.mark.parametrize("pairs, kind", [(("spherical", "spherical"), "RSSR"), (("revolute", "revolute"), "planar")])
def test_planar_fourbar_as_a_spatial_chain_matches_the_planar_solver(pairs, kind):
    planar = linkgen.load(ROOT / "models" / "fourbar.toml")
    phi = np.linspace(0.0, 2 * np.pi, 721)
    flat = planar_solve(planar, phi)
    mech = spatial_from_dict(_planar_as_spatial(*pairs))
    assert build_chain(mech).kind == kind
    k = solve(mech, phi)
    for p in FOURBAR_POINTS:
        d = k.points[p].d
        assert np.abs(d[:, :, 2]).max() <= PLANAR_TOL, p  # stays in the plane z = 0
        for order, planar_value in enumerate((flat.points[p].p, flat.points[p].d1, flat.points[p].d2)):
            assert np.abs(d[order, :, :2] - planar_value).max() <= PLANAR_TOL, (p, order)


# --- the spherical four-bar --------------------------------------------------------------------


def test_spherical_fourbar_axes_meet_at_the_centre():
    mech = _model("spherical_fourbar")
    chain = build_chain(mech)
    assert np.abs(chain.centre).max() <= SPHERE_TOL
    for j in mech.joints:  # each axis line passes through O = (0, 0, 0)
        p, u = mech.point(j.name), np.array(j.axis)
        assert np.linalg.norm(np.cross(p, u)) <= SPHERE_TOL, j.name


def test_spherical_fourbar_points_stay_on_their_spheres():
    mech = _model("spherical_fourbar")
    k = solve(mech, TURN)
    centre = np.zeros(3)
    for p in mech.points:
        r = k.points[p].d[0] - centre
        v, acc = k.points[p].d[1], k.points[p].d[2]
        radius = np.linalg.norm(mech.point(p) - centre)
        assert np.abs(np.linalg.norm(r, axis=1) - radius).max() <= SPHERE_TOL * radius, p
        # d/dφ |r|² = 2 r·r′ = 0 and d²/dφ² gives r·r″ + |r′|² = 0
        speed = np.abs(v).max() or 1.0
        assert np.abs(np.einsum("ij,ij->i", r, v)).max() <= SPHERE_TOL * radius * speed, p
        lhs = np.einsum("ij,ij->i", r, acc) + np.einsum("ij,ij->i", v, v)
        assert np.abs(lhs).max() <= SPHERE_TOL * radius * max(np.abs(acc).max(), speed), p


# --- Bennett -----------------------------------------------------------------------------------

LOOP = ("A0", "A", "B", "B0")


def test_bennett_model_meets_bennetts_conditions():
    mech = _model("bennett")
    axes = [(mech.point(p), np.array(mech.joint(p).axis)) for p in LOOP]
    defects = bennett_defects(axes)
    assert max(defects.values()) <= BENNETT_DEFECT_TOL, defects
    lengths = [common_normal(*axes[i], *axes[(i + 1) % 4])[0] for i in range(4)]
    assert np.allclose(lengths, [0.2, 0.4, 0.2, 0.4], rtol=0, atol=BENNETT_DEFECT_TOL)


def test_bennett_coupler_keeps_its_common_normal():
    mech = _model("bennett")
    chain = build_chain(mech)
    a_s, ua_s = mech.point("A"), np.array(mech.joint("A").axis)
    b_s, ub_s = mech.point("B"), np.array(mech.joint("B").axis)
    length_s, twist_s, _, _ = common_normal(a_s, ua_s, b_s, ub_s)
    k = solve(mech, TURN)
    crank, coupler, rocker = (k.frames[n] for n in (chain.crank, chain.coupler, chain.output))
    ua, ub = crank @ ua_s, rocker @ ub_s  # the joint axes carried by the crank and the rocker
    # the coupler's own frame carries the same two axes
    assert np.abs(coupler @ ua_s - ua).max() <= BENNETT_NORMAL_TOL
    assert np.abs(coupler @ ub_s - ub).max() <= BENNETT_NORMAL_TOL
    a, b = k.points["A"].d[0], k.points["B"].d[0]
    for i in range(0, TURN.size, 7):
        length, twist, foot_a, foot_b = common_normal(a[i], ua[i], b[i], ub[i])
        assert abs(length - length_s) <= BENNETT_NORMAL_TOL, TURN[i]
        assert abs(math.remainder(twist - twist_s, 2 * math.pi)) <= BENNETT_NORMAL_TOL, TURN[i]
        # zero offsets: the normal's feet stay at the joint points
        assert np.abs(foot_a - a[i]).max() <= BENNETT_NORMAL_TOL and np.abs(foot_b - b[i]).max() <= BENNETT_NORMAL_TOL


def test_bennett_passes_its_folded_poses():
    """At φ = 0 and 180° the four joints lie on the x axis (the crank's and the ground's normals
    parallel); the linkage moves through, and the transfer functions are finite there."""
    k = solve(_model("bennett"), [0.0, np.pi])
    for p in LOOP:
        assert np.abs(k.points[p].d[0, :, 1:]).max() <= 1e-12, p
    assert np.isfinite(k.output.d).all()


# --- errors ------------------------------------------------------------------------------------


def _rssr_dict() -> dict:
    return tomllib.loads((ROOT / "models" / "rssr.toml").read_text(encoding="utf-8"))


def test_a_4r_chain_that_cannot_move_is_refused_naming_bennett():
    data = _rssr_dict()
    data["joints"]["A"] = {"kind": "revolute", "axis": [0.0, 1.0, 0.0]}
    data["joints"]["B"] = {"kind": "revolute", "axis": [1.0, 1.0, 0.0]}
    with pytest.raises(StructureError, match="Bennett"):
        build_chain(spatial_from_dict(data))


def test_a_coupler_that_cannot_reach_names_the_crank_angle_ranges():
    data = _rssr_dict()
    data["links"]["coupler"]["length"] = 0.7  # reaches at the sketch, not around φ = 180°
    mech = spatial_from_dict(data)
    with pytest.raises(AssemblyError, match=r"crank angles \d+\.\d+°\.\.\d+\.\d+°") as info:
        solve(mech, TURN)
    # independently: A = (0.25·cos φ, 0.25·sin φ, 0); B on the circle of radius 0.6 about the
    # x axis through B0 = (0.6, 0, 0.4): the nearest point of that circle is farther than 0.7 m
    a = np.stack([0.25 * np.cos(TURN), 0.25 * np.sin(TURN), np.zeros_like(TURN)], axis=1)
    axial, radial = a[:, 0] - 0.6, np.hypot(a[:, 1], a[:, 2] - 0.4)
    far = np.hypot(axial, radial - 0.6) > 0.7
    assert info.value.ranges == angle_ranges(TURN, far)
    assert len(info.value.ranges) == 1 and info.value.ranges[0][0] < np.pi < info.value.ranges[0][1]


@pytest.mark.parametrize("edit, field", [
    (lambda d: d["joints"]["A0"].pop("axis"), "joints.A0.axis"),
    (lambda d: d["joints"]["A"].update(kind="ball"), "joints.A.kind"),
    (lambda d: d["joints"]["B"].update(axis=[0.0, 0.0, 1.0]), "joints.B.axis"),
    (lambda d: d["links"]["crank"].update(length=-0.25), "links.crank.length"),
    (lambda d: d["drive"].update(joint="A"), "drive.joint"),
])
def test_a_bad_field_is_named(edit, field):
    data = _rssr_dict()
    edit(data)
    with pytest.raises(DescriptionError) as info:
        spatial_from_dict(data, "rssr.toml")
    assert info.value.field == field
    assert field in str(info.value) and str(info.value).startswith("rssr.toml: ")


def test_a_slider_without_direction_is_named():
    data = tomllib.loads((ROOT / "models" / "rssp.toml").read_text(encoding="utf-8"))
    del data["prismatic"]["guide"]["direction"]
    with pytest.raises(DescriptionError, match=r"prismatic\.guide\.direction"):
        spatial_from_dict(data)


# A refined limit lies at or beyond every sampled value (up to the rounding of q, ~1e-14 of it),
# and beyond the best sample by at most (Δφ)²·max|q″|/8, Δφ the sampling step.
LIMIT_ROUNDING = 1e-12
SAMPLES = 36_000


@pytest.mark.parametrize("model", ["rssr", "rssp", "spherical_fourbar"])
def test_summary_limits_where_the_output_stops(model):
    """analyze --summary's limit positions: the output's extremes of a 0.001°-dense scan, and for
    RSSR/RSSP the crank pin's velocity square to the coupler there (B stands still, so A's velocity
    has no component along AB) — a geometric fact, not the transfer function the summary used."""
    from linkgen.families.spatial.summary import summarize

    mech = linkgen.load(ROOT / "models" / f"{model}.toml")
    sm = summarize(mech)
    (out,) = sm.outputs.values()
    limits = [(x.kind, x.phi, x.value) for x in out.limits]
    assert [k for k, _, _ in limits] in (["min", "max"], ["max", "min"])
    scan = solve(mech, np.linspace(0.0, 2 * math.pi, SAMPLES, endpoint=False)).output  # as analyze gives it
    q, bound = scan.d[0], (2 * math.pi / SAMPLES) ** 2 * np.abs(scan.d[2]).max() / 8 + LIMIT_ROUNDING
    values = {k: v for k, _, v in limits}
    assert -LIMIT_ROUNDING <= values["max"] - q.max() <= bound and -LIMIT_ROUNDING <= q.min() - values["min"] <= bound
    assert abs(out.travel - (values["max"] - values["min"])) == 0.0
    if model != "spherical_fourbar":
        chain = solve(mech, [0.0]).chain
        for _, a, _ in limits:
            k = solve(mech, [a])
            pa, pb = k.points[chain.pair_a].d[0][0], k.points[chain.pair_b].d[0][0]
            va = np.cross(chain.ka, pa - chain.a0)
            assert abs(va @ (pb - pa)) <= 1e-9 * np.linalg.norm(va) * np.linalg.norm(pb - pa)
    # the time ratio from the limit angles: the longer stroke's crank turn over the shorter's
    lo, hi = (next(a for k, a, _ in limits if k == kind) for kind in ("min", "max"))
    work = (hi - lo) % (2 * math.pi)
    assert out.strokes == pytest.approx((work, 2 * math.pi - work), rel=1e-12)
    assert out.time_ratio == pytest.approx(max(work, 2 * math.pi - work) / min(work, 2 * math.pi - work), rel=1e-12)


def test_the_python_api_gives_velocities_of_spatial_points():
    """linkgen.kinematics on a spatial model: each point's velocity and the output's rate are the
    time derivatives of the positions at ω (central differences in time, h = 1e-6 s)."""
    mech = linkgen.load(ROOT / "models" / "rssr.toml")
    w, h, phi = 10.0, 1e-6, np.radians([10.0, 130.0, 250.0])
    k = linkgen.kinematics(mech, phi, omega=w)
    ahead, behind = linkgen.kinematics(mech, phi + w * h, omega=w), linkgen.kinematics(mech, phi - w * h, omega=w)
    for p, q in k.points.items():
        fd = (ahead.points[p].position - behind.points[p].position) / (2 * h)
        assert np.abs(fd - q.velocity).max() <= 1e-7 * max(1.0, np.abs(q.velocity).max()), p
    fd = (ahead.links["rocker"].angle - behind.links["rocker"].angle) / (2 * h)
    assert np.abs(fd - k.links["rocker"].angular_velocity).max() <= 1e-7 * np.abs(k.links["rocker"].angular_velocity).max()
    assert k.points["B"].position.shape == (3, 3) and linkgen.kinematics(mech, 0.3).points["B"].position.shape == (3,)

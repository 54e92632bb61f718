"""Closed-form kinematics: constraints, transfer functions against finite differences, seeds."""

import math

import numpy as np
import pytest

import linkgen

from conftest import MODELS
from linkgen import AssemblyError, GroupKind, assemble, load, solve
from linkgen.cli.common import crank_grid

# Positions must satisfy every constraint equation to this [m]: a few ulps of metre-sized
# coordinates after ~20 floating-point operations per group.
CONSTRAINT_TOL = 1e-12
# Central differences with step H: truncation H²/6·|f'''| ≈ 2e-11·|f'''| and rounding
# ε·|f|/H ≈ 2e-11·|f|; 1e-7 of the quantity's peak leaves room for |f'''| up to ~1e3·peak
# near the dead centres of the tangent mechanism, and still catches a wrong sign or factor.
H = 1e-5
FD_REL_TOL = 1e-7


def _grid(mech, n=721):
    phi = crank_grid(mech, n)
    if mech.drive.stop - mech.drive.start < 2 * math.pi - 1e-12:  # keep ±H inside the range
        phi = np.clip(phi, mech.drive.start + 2 * H, mech.drive.stop - 2 * H)
    return phi


def test_every_group_kind_has_a_model():
    kinds = {g.kind for p in MODELS for g in assemble(load(p)).structure.groups}
    assert kinds == set(GroupKind)


def test_constraints_hold_over_the_drive_range(model_path):
    mech = load(model_path)
    asm = assemble(mech)
    kin = solve(asm, _grid(mech))
    # revolutes: the point is the same seen from both links, each placed here by its own
    # origin and angle (the solver hands back solved points as they are; this rebuilds them)
    def placed(link, point):
        origin, th = kin.links[link].origin.p, kin.links[link].angle.v
        x, y = asm.shapes[link].local[point]
        return origin + np.stack((np.cos(th) * x - np.sin(th) * y, np.sin(th) * x + np.cos(th) * y), axis=1)

    for j in mech.revolutes:
        a, b = (placed(l, j.point) for l in j.links)
        assert np.abs(a - b).max() < CONSTRAINT_TOL, j.name
        assert np.abs(a - kin.points[j.point].p).max() < CONSTRAINT_TOL, j.name
    # lengths given in the description
    for link in mech.links:
        if link.length is not None:
            p, q = (kin.points[n].p for n in link.points)
            assert np.abs(np.hypot(*(q - p).T) - link.length).max() < CONSTRAINT_TOL, link.name
    # prismatics: the slider point lies on the guide line, relative angle constant
    for pj in mech.prismatics:
        g = asm.guides[pj.name]
        guide = kin.links[pj.guide]
        base, u = guide.point(g.base).p, guide.direction(g.alpha).p
        r = kin.points[pj.point].p - base
        assert np.abs(r[:, 0] * u[:, 1] - r[:, 1] * u[:, 0]).max() < CONSTRAINT_TOL, pj.name
        rel = np.angle(np.exp(1j * (kin.links[pj.slider].angle.v - guide.angle.v - g.relative_angle)))
        assert np.abs(rel).max() < CONSTRAINT_TOL, pj.name


def _fd_errors(mech):
    asm = assemble(mech)
    phi = _grid(mech)
    k0, kp, km = solve(asm, phi), solve(asm, phi + H), solve(asm, phi - H)
    out = {}
    series = {f"points.{n}": (lambda k, n=n: (k.points[n].p, k.points[n].d1, k.points[n].d2)) for n in k0.points}
    series |= {f"links.{n}": (lambda k, n=n: (k.links[n].angle.v, k.links[n].angle.d1, k.links[n].angle.d2)) for n in k0.links}
    series |= {f"sliders.{n}": (lambda k, n=n: (k.sliders[n].v, k.sliders[n].d1, k.sliders[n].d2)) for n in k0.sliders}
    for name, get in series.items():
        (_, d1, d2), (xp, d1p, _), (xm, d1m, _) = get(k0), get(kp), get(km)
        dx = xp - xm
        if name.startswith("links."):
            dx = np.angle(np.exp(1j * dx))
        fd1, fd2 = dx / (2 * H), (d1p - d1m) / (2 * H)
        e1 = np.abs(fd1 - d1).max() / max(np.abs(d1).max(), 1e-300) if np.abs(d1).max() > 0 else np.abs(fd1).max()
        e2 = np.abs(fd2 - d2).max() / max(np.abs(d2).max(), 1e-300) if np.abs(d2).max() > 0 else np.abs(fd2).max()
        out[name] = (e1, e2)
    return asm, out


def test_transfer_functions_match_finite_differences(model_path):
    mech = load(model_path)
    _, errs = _fd_errors(mech)
    worst = {n: e for n, e in errs.items() if max(e) >= FD_REL_TOL}
    assert not worst, worst


def test_seed_002_slider_position_at_pi():
    # seed 002, eq. (3)/(27): x_B(π) = (-1 + √3)/50 ≈ 0.014641 m
    kin = solve(load(MODELS[0].parent / "slider_crank_offset.toml"), np.array([math.pi]))
    assert kin.points["B"].p[0, 0] == pytest.approx((-1 + math.sqrt(3)) / 50, abs=1e-15)
    assert kin.points["B"].p[0, 1] == pytest.approx(0.005, abs=1e-15)


def test_seed_002_slider_derivative_from_the_mechanism_not_the_print():
    # The correct x_B' = -l1·sinφ - l1·cosφ·(l1·sinφ - e1)/sqrt(l2² - (l1·sinφ - e1)²), derived by hand
    # from B_x; seed 002's eq. (11) writes it so but its eq. (7) and (19) are misprinted.
    l1, l2, e1 = 0.02, 0.035, 0.005
    phi = np.linspace(0.1, 6.2, 50)
    root = np.sqrt(l2**2 - (l1 * np.sin(phi) - e1) ** 2)
    expected = -l1 * np.sin(phi) - l1 * np.cos(phi) * (l1 * np.sin(phi) - e1) / root
    kin = solve(load(MODELS[0].parent / "slider_crank_offset.toml"), phi)
    np.testing.assert_allclose(kin.points["B"].d1[:, 0], expected, rtol=0, atol=1e-15)


def test_scotch_yoke_is_a_cosine():
    mech = load(MODELS[0].parent / "scotch_yoke.toml")
    phi = np.linspace(0, 2 * np.pi, 100)
    kin = solve(mech, phi)
    np.testing.assert_allclose(kin.sliders["yoke"].v, 0.1 * np.cos(phi), atol=1e-15)
    np.testing.assert_allclose(kin.sliders["yoke"].d2, -0.1 * np.cos(phi), atol=1e-15)


def test_tangent_mechanism_is_h_over_tan():
    kin = solve(load(MODELS[0].parent / "tangent_prp.toml"), np.radians([45.0, 60.0, 120.0]))
    np.testing.assert_allclose(kin.points["B"].p[:, 0], 0.2 / np.tan(np.radians([45.0, 60.0, 120.0])), atol=1e-15)
    # x = h·cot φ: x' = -h/sin²φ
    np.testing.assert_allclose(kin.points["B"].d1[:, 0], -0.2 / np.sin(np.radians([45.0, 60.0, 120.0])) ** 2,
                               rtol=1e-14)


def test_assembly_failure_names_the_angle_ranges():
    mech = load(MODELS[0].parent / "seven_link.toml")
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    with pytest.raises(AssemblyError) as info:
        solve(mech, phi)
    assert info.value.group == "II(6,7) RRR [coupler, lever]"
    # by hand: B reaches E only while |BF| <= BE + EF = 0.8413 m, i.e. for φ in about -76.3°..60.9°
    assert [(round(math.degrees(lo), 9), round(math.degrees(hi), 9)) for lo, hi in info.value.ranges] == [(61.0, 283.0)]
    assert str(info.value).startswith("group II(6,7) RRR [coupler, lever] cannot be assembled at crank angles "
                                      "61.000°..283.000°: the two links cannot reach each other")


def test_near_singular_positions_follow_one_rule():
    # The tangent mechanism's slot turns parallel to the guide at φ → 0: the denominator is the sine
    # of the angle between the two guides, sin φ (by hand). SINGULAR_TOL = 1e-4 separates the angles.
    from linkgen import SingularityError
    from linkgen.families.planar.kinematics import SINGULAR_TOL

    mech = load(MODELS[0].parent / "tangent_prp.toml")
    phi = np.array([0.5, 0.5 * SINGULAR_TOL, 2.0 * SINGULAR_TOL, 0.0])
    with pytest.raises(SingularityError) as info:
        solve(mech, phi)
    assert info.value.group == "II(2,3) PRP [block, slider]"
    assert [(lo, hi) for lo, hi in info.value.ranges] == [(phi[1], phi[1]), (0.0, 0.0)]
    assert str(info.value).startswith("group II(2,3) PRP [block, slider] is singular at crank angles 0.003°, 0.000°: "
                                      "its two guides are (nearly) parallel (normalised transfer-function "
                                      "denominator below SINGULAR_TOL = 0.0001")
    kin = solve(mech, phi, on_singular="mark")
    assert kin.singular.tolist() == [False, True, False, True]
    (mask,) = kin.near_singular.values()
    assert mask.tolist() == kin.singular.tolist()
    for v in kin.points.values():
        assert np.all(np.isfinite(v.p)) and np.all(np.isfinite(v.d1)) and np.all(np.isfinite(v.d2))
    # outside the marked angles the values are those of an ordinary solve: x = h·cot φ
    np.testing.assert_allclose(kin.points["B"].p[[0, 2], 0], 0.2 / np.tan(phi[[0, 2]]), rtol=1e-12)
    mo = linkgen.solve_motion(mech, phi, 2.0, on_singular="mark")
    assert mo.singular.tolist() == kin.singular.tolist()
    assert all(np.all(np.isfinite(a)) for t in mo.points.values() for a in t)
    with pytest.raises(SingularityError):
        linkgen.solve_motion(mech, phi, 2.0)
    with pytest.raises(linkgen.ArgumentError, match=r"on_singular must be one of \['raise', 'mark'\], got 'warn'"):
        solve(mech, phi, on_singular="warn")


def test_overflow_is_named_as_overflow():
    # ω = 1e160 rad/s: accelerations ~ ω²·x″ ≈ 1e320 m/s² exceed float64's range; the positions and
    # transfer functions are fine, so the message must speak of overflow, not of a dead centre.
    mech = load(MODELS[0].parent / "fourbar.toml")
    phi = np.radians([10.0, 20.0])
    # the family's own function: linkgen.solve_motion refuses ω past linkgen's limits first
    from linkgen.families.planar.kinematics import solve_motion

    with pytest.raises(linkgen.MagnitudeError, match=r"^the acceleration of point .* overflows float64 .* at crank "
                                                     r"angles 10.000°..20.000°: the description's lengths or the "
                                                     r"crank rates are too large"):
        solve_motion(mech, phi, 1e160)
    with pytest.raises(linkgen.MagnitudeError, match="overflows float64"):
        solve(mech, phi).motion(1e160)
    from linkgen.families.planar.kinetostatics import forces

    with pytest.raises(linkgen.MagnitudeError, match=r"^the solution of .* overflows float64"):
        forces(mech, phi, 1e160)


def test_overflowing_sketch_is_refused_at_load_and_overflow_is_named():
    # the four-bar drawn 1e155 times larger: squared distances (~1e310) would overflow float64,
    # so the description's limits refuse it at load
    import tomllib

    data = tomllib.loads((MODELS[0].parent / "fourbar.toml").read_text())
    data["points"] = {p: [1e155 * x for x in xy] for p, xy in data["points"].items()}
    for link in data["links"].values():
        for key in ("length", "inertial", "density"):
            link.pop(key, None)
    with pytest.raises(linkgen.DescriptionError, match=r"must be within ±1e\+12 m"):
        linkgen.from_dict(data)
    # from Python, rates past float64's range through ω² are named as overflow, not as a dead centre
    mech = linkgen.load(MODELS[0].parent / "fourbar.toml")
    from linkgen.families.planar.kinematics import solve_motion

    with pytest.raises(linkgen.MagnitudeError, match="overflow"):
        solve_motion(mech, np.array([0.3]), 1e160)
    with pytest.raises(linkgen.ArgumentError, match=r"^omega: expected a number within ±1e\+30 rad/s"):
        linkgen.solve_motion(mech, np.array([0.3]), 1e160)  # the API's limits


def test_parallel_guides_are_named_in_the_description():
    # The tangent mechanism drawn at φ = 0 with the slider's guide through O: the slot (along O→A)
    # and the guide are the same horizontal line, so B has no defined position.
    data = {
        "mechanism": {"name": "parallel"},
        "points": {"O": [0.0, 0.0], "A": [0.1, 0.0], "B": [0.3, 0.0]},
        "links": {"ground": {"points": ["O"]}, "crank": {"points": ["O", "A"]},
                  "block": {"points": ["B"]}, "slider": {"points": ["B"]}},
        "prismatic": {
            "p1": {"slider": "block", "guide": "crank", "point": "B", "through": "O", "angle": 0.0},
            "p2": {"slider": "slider", "guide": "ground", "point": "B", "through": "O", "angle": 0.0},
        },
        "drive": {"joint": "O", "omega": 1.0},
    }
    with pytest.raises(linkgen.DescriptionError) as info:
        assemble(linkgen.from_dict(data))
    assert str(info.value).startswith("prismatic.p1, prismatic.p2: the guides of group II(2,3) ")
    assert "are parallel in the sketch (sine of the angle between them 0, needs at least 0.0001)" in str(info.value)


# SINGULAR_TOL's promise: at |D| >= SINGULAR_TOL = 1e-4 positions and transfer functions keep at
# least 7 significant digits (relative error ~eps/D² in x′ and ~3·eps/D² in x″, <= 6.6e-8; see
# linkgen.groups). Measured here at D = 1.01e-4: 2.2e-8 (x′), 6.5e-8 (x″).
SEVEN_DIGITS = 1e-7


def test_seven_digits_down_to_the_singular_tolerance():
    # A slider-crank whose rod (0.05 m) is shorter than its crank (0.1 m): near sin φ = l2/l1 the rod
    # stands perpendicular to the guide and D = sqrt(l2² - (l1·sin φ)²)/l2 → 0. Reference: the exact
    # x_B(φ) = l1·cos φ + q, q = sqrt(l2² - s²), s = l1·sin φ, and its derivatives by hand, in 40-digit
    # decimal arithmetic from the same float sin φ and cos φ linkgen starts from.
    from decimal import Decimal, getcontext

    from linkgen import SingularityError
    from linkgen.families.planar.kinematics import SINGULAR_TOL

    getcontext().prec = 40
    l1, l2, phi0 = 0.1, 0.05, math.radians(10.0)
    a = (l1 * math.cos(phi0), l1 * math.sin(phi0))
    b = (a[0] + math.sqrt(l2**2 - a[1] ** 2), 0.0)
    mech = linkgen.from_dict({
        "mechanism": {"name": "short_rod"},
        "points": {"O": [0.0, 0.0], "A": list(a), "B": list(b)},
        "links": {"ground": {"points": ["O"]}, "crank": {"points": ["O", "A"], "length": l1},
                  "rod": {"points": ["A", "B"], "length": l2}, "slider": {"points": ["B"]}},
        "prismatic": {"slide": {"slider": "slider", "guide": "ground", "point": "B", "through": "O", "angle": 0.0}},
        "drive": {"joint": "O", "omega": 1.0},
    })

    def exact(phi):
        sn, cs, L1, L2 = Decimal(math.sin(phi)), Decimal(math.cos(phi)), Decimal(l1), Decimal(l2)
        s, s1, s2 = L1 * sn, L1 * cs, -L1 * sn
        q = (L2 * L2 - s * s).sqrt()
        return (L1 * cs + q, -L1 * sn - s * s1 / q, -L1 * cs - (s1 * s1 + s * s2) / q - s * s * s1 * s1 / q**3)

    dens = np.array([1e-2, 1e-3, 3e-4, 1.01 * SINGULAR_TOL])
    phi = np.arcsin(l2 * np.sqrt(1.0 - dens**2) / l1)
    kin = solve(mech, phi)
    got = (kin.points["B"].p[:, 0], kin.points["B"].d1[:, 0], kin.points["B"].d2[:, 0])
    for k, f in enumerate(phi):
        ref = exact(float(f))
        for g, r in zip(got, ref):
            err = abs((Decimal(float(g[k])) - r) / r)
            assert err < SEVEN_DIGITS, (dens[k], err)
    with pytest.raises(SingularityError, match="its link is \\(nearly\\) perpendicular to the guide line"):
        solve(mech, np.arcsin(l2 * np.sqrt(1.0 - (0.99 * SINGULAR_TOL) ** 2) / l1 + np.zeros(1)))

"""Solving in blocks and on threads gives the unblocked result, bit for bit, and the same errors."""

import math

import numpy as np
import pytest

from conftest import MODELS
from linkgen import ArgumentError, AssemblyError, LinkgenError, assemble, load
from linkgen.families.planar import blocks
# The family's own functions: their messages on arrays are the closed form's (``linkgen.solve``
# reads its arguments as the API does, tests/test_api_families.py).
from linkgen.families.planar.kinematics import solve, solve_motion
from linkgen.cli.common import crank_grid

# A block size that divides nothing in sight, so the last block is short.
ODD_BLOCK = 37
# cos/sin recomputed from an angle instead of cached from (B - A)/|B - A|: a few ulp.
RECOMPUTED_TRIG_TOL = 1e-14


def _series(kin):
    out = {f"points.{n}": (v.p, v.d1, v.d2) for n, v in kin.points.items()}
    out |= {f"links.{n}": (p.angle.v, p.angle.d1, p.angle.d2) for n, p in kin.links.items()}
    out |= {f"sliders.{n}": (s.v, s.d1, s.d2) for n, s in kin.sliders.items()}
    out |= {f"near.{g}": (m,) for g, m in kin.near_singular.items()}
    return out


def _motion_series(mo):
    return {f"{kind}.{n}": t for kind in ("points", "links", "sliders") for n, t in getattr(mo, kind).items()}


def _assert_identical(a: dict, b: dict):
    assert a.keys() == b.keys()
    for k in a:
        for x, y in zip(a[k], b[k]):
            assert x.shape == y.shape, k
            assert np.array_equal(x, y), k  # elementwise arithmetic: no rounding may differ


@pytest.mark.parametrize("threads", [1, 2])
def test_blocks_equal_one_piece(model_path, threads, monkeypatch):
    mech = load(model_path)
    asm = assemble(mech)
    phi = crank_grid(mech, 1000)
    whole = solve(asm, phi)  # 1000 angles < BLOCK: one piece
    monkeypatch.setattr(blocks, "BLOCK", ODD_BLOCK)
    parts = solve(asm, phi, threads=threads)
    _assert_identical(_series(whole), _series(parts))
    # Other points of a link: the joined poses drop the blocks' cached cos/sin of each angle
    # and recompute them from the angle, which may differ in the last bit (2 ulp of ~1 m).
    for link in mech.links:
        a, b = whole.point(link.name, (0.01, 0.02)), parts.point(link.name, (0.01, 0.02))
        for x, y in ((a.p, b.p), (a.d1, b.d1), (a.d2, b.d2)):
            np.testing.assert_allclose(y, x, rtol=0, atol=RECOMPUTED_TRIG_TOL * max(1.0, np.abs(x).max()))


@pytest.mark.parametrize("rates", ["scalar", "array"])
def test_solve_motion_equals_solve_then_motion(model_path, rates, monkeypatch):
    mech = load(model_path)
    asm = assemble(mech)
    phi = crank_grid(mech, 500)
    omega, epsilon = (3.0, -2.0) if rates == "scalar" else (1.0 + np.sin(phi), np.cos(phi))
    expected = solve(asm, phi).motion(omega, epsilon)
    monkeypatch.setattr(blocks, "BLOCK", ODD_BLOCK)
    got = solve_motion(asm, phi, omega, epsilon, threads=2)
    _assert_identical(_motion_series(expected), _motion_series(got))
    np.testing.assert_array_equal(got.omega, np.broadcast_to(omega, phi.shape))


def test_constant_quantities_stay_views():
    kin = solve(load(MODELS[0].parent / "fourbar.toml"), np.linspace(0, 1, 100))
    mo = kin.motion(2.0)
    for arr in (kin.points["O"].p, kin.points["C"].d1, mo.points["C"][1], mo.links["crank"][1], mo.links["ground"][2]):
        assert arr.strides[0] == 0 and not arr.flags.writeable
    assert mo.links["crank"][1][0] == 2.0 and not mo.points["C"][2].any()


def test_failure_in_a_later_block_names_the_same_ranges(monkeypatch):
    mech = load(MODELS[0].parent / "seven_link.toml")
    phi = np.radians(np.arange(0.0, 360.0, 1.0))
    with pytest.raises(AssemblyError) as whole:
        solve(mech, phi)
    monkeypatch.setattr(blocks, "BLOCK", ODD_BLOCK)
    for call in (lambda: solve(mech, phi, threads=2), lambda: solve_motion(mech, phi, 1.0)):
        with pytest.raises(AssemblyError) as parts:
            call()
        assert str(parts.value) == str(whole.value)
        assert [(round(math.degrees(a), 9), round(math.degrees(b), 9)) for a, b in parts.value.ranges] == [(61.0, 283.0)]


def test_carve_gives_separate_arrays_of_the_asked_layouts():
    like = [np.empty((3, 2), order="F"), np.empty(3, dtype=bool), np.empty((3, 2))]
    a, b, c = blocks.carve(1000, like)
    assert a.shape == (1000, 2) and a.flags.f_contiguous
    assert b.shape == (1000,) and b.dtype == bool
    assert c.shape == (1000, 2) and c.flags.c_contiguous
    a[:] = 1.0
    b[:] = False
    c[:] = 2.0
    assert (a == 1.0).all() and not b.any() and (c == 2.0).all()
    assert not np.shares_memory(a, c) and not np.shares_memory(a, b) and not np.shares_memory(b, c)


def test_leaves_refuses_what_it_cannot_split():
    with pytest.raises(TypeError, match="cannot split a str"):
        blocks.leaves({"a": "text"})


@pytest.mark.parametrize(("omega", "epsilon", "message"), [
    (np.ones(3), 0.0, "omega must be a scalar or an array of shape (10,) [rad/s], got shape (3,)"),
    (1.0, np.ones((10, 1)), "epsilon must be a scalar or an array of shape (10,) [rad/s²], got shape (10, 1)"),
    (float("nan"), 0.0, "omega must be finite [rad/s], got nan"),
    (1.0, np.r_[np.zeros(9), np.inf], "epsilon must be finite [rad/s²], got non-finite entries"),
])
def test_bad_crank_rates_are_named(omega, epsilon, message):
    mech = load(MODELS[0].parent / "fourbar.toml")
    phi = np.linspace(0, 1, 10)
    for call in (lambda: solve(mech, phi).motion(omega, epsilon), lambda: solve_motion(mech, phi, omega, epsilon)):
        with pytest.raises(ArgumentError) as info:
            call()
        assert str(info.value) == message


@pytest.mark.parametrize(("phi", "what"), [
    (np.array([]), "shape (0,)"),
    (np.zeros((2, 2)), "shape (2, 2)"),
    (np.array([0.0, np.nan]), "non-finite entries"),
])
def test_bad_crank_angles_are_named(phi, what):
    mech = load(MODELS[0].parent / "fourbar.toml")
    for call in (lambda: solve(mech, phi), lambda: solve_motion(mech, phi, 1.0)):
        with pytest.raises(ArgumentError) as info:
            call()
        assert isinstance(info.value, LinkgenError) and isinstance(info.value, ValueError)
        assert str(info.value) == f"phi must be a non-empty, finite 1-D array of crank angles [rad], got {what}"


@pytest.mark.parametrize("threads", [1, 2])
def test_marked_singular_angles_in_blocks_equal_one_piece(threads, monkeypatch):
    # the tangent mechanism through its dead centre φ = 0 in steps of 1e-4 rad: the denominator is
    # sin φ, below SINGULAR_TOL = 1e-4 at φ = 0 and ±1e-4 (sin x < x), not at ±2e-4
    mech = load(MODELS[0].parent / "tangent_prp.toml")
    phi = np.linspace(-0.05, 0.05, 1001)
    phi[500] = 0.0
    whole = solve(mech, phi, on_singular="mark")
    assert np.flatnonzero(whole.singular).tolist() == [499, 500, 501]
    monkeypatch.setattr(blocks, "BLOCK", ODD_BLOCK)
    parts = solve(mech, phi, threads=threads, on_singular="mark")
    _assert_identical(_series(whole), _series(parts))
    assert np.array_equal(whole.singular, parts.singular)
    mo = solve_motion(mech, phi, 2.0, threads=threads, on_singular="mark")
    assert np.array_equal(mo.singular, whole.singular)
    with pytest.raises(LinkgenError, match=r"is singular at crank angles -0.006°..0.006°: its two guides"):
        solve(mech, phi, threads=threads)

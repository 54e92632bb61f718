"""Third transfer functions d³x/dφ³ and jerk: the closed form against finite differences.

The third transfer functions come from differentiating each group's constraints a third time
(linkgen/families/planar/primitives.py); here they are checked against fourth-order central
differences of the second ones, on every bundled linkage (all five dyad kinds, the gear
planet) and on generated mechanisms, and the jerk x‴ω³ + 3x″ωε against a difference in time
of the accelerations for a crank with constant ε ≠ 0. The CLI and the API report it.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings

import linkgen
from conftest import MODELS, ROOT
from linkgen import GroupKind, assemble, load, solve, solve_motion
from linkgen.cli.common import crank_grid
from linkgen.cli.main import main
from linkgen.families.planar import blocks
from linkgen.families.planar.corpus import to_toml
from linkgen.families.planar.groups import input_poses, place, solve_group
from strategies import mechanisms

# Step of the differences [rad] (in time: the step that turns the crank by about H).
H = 1e-4
# Fourth-order central difference of a function f (here a second transfer function, or an
# acceleration in time): (-f(+2H) + 8f(+H) - 8f(-H) + f(-2H)) / 12H = f′ + H⁴/30·f⁽⁵⁾ + …
#   truncation: H⁴/30·|x⁽⁷⁾| = 3.3e-18·|x⁽⁷⁾|, below 1e-10 of the scale S unless x⁽⁷⁾ exceeds
#     3e7·S (a derivative of x that high is only met a hair from a dead centre): TRUNCATION_TOL.
#   rounding: the second transfer functions carry a relative error of ~3ε/D² (the rule of
#     SINGULAR_TOL, linkgen/families/planar/groups.py; D the smallest normalised denominator of the
#     groups at that angle) of their scale, and the stencil's weights sum to 18/12 over H:
#     4.5·ε/(D²·H) of S = L + peak |x″| + peak |x‴|, L the mechanism's size for points and
#     sliders and 1 rad for angles (a link that only translates has x″ = x‴ = 0 up to rounding
#     of L-sized terms); 1e-11 at D = 1, given ROUNDING_MARGIN for the constants hidden in "~".
# A wrong coefficient in a third-derivative formula (a Leibniz 3 written 2, a lost term) is
# off by a sizeable fraction of S: measured 1e-2 and more, far above the tolerance.
TRUNCATION_TOL = 1e-10
ROUNDING_MARGIN = 10.0
EPS = np.finfo(float).eps
# Generated mechanisms are checked at angles whose denominators are at least this (100 times
# SINGULAR_TOL: a transmission angle of 0.6°), where the rounding term stays below 5e-7.
D_MIN = 1e-2


def fd3_tolerance(d_min: float) -> float:
    """Largest |FD⁴(x″) − x‴| / S at angles whose smallest normalised denominator is d_min."""
    return TRUNCATION_TOL + ROUNDING_MARGIN * 4.5 * EPS / (d_min * d_min * H)


def _fd4(f: dict[int, np.ndarray], step: float) -> np.ndarray:
    return (-f[2] + 8.0 * f[1] - 8.0 * f[-1] + f[-2]) / (12.0 * step)


def _grid(mech, n=721):
    phi = crank_grid(mech, n)
    if mech.drive.stop - mech.drive.start < 2 * math.pi - 1e-12:  # keep ±2H inside the range
        phi = np.clip(phi, mech.drive.start + 3 * H, mech.drive.stop - 3 * H)
    return phi


def smallest_denominator(asm, phi: np.ndarray) -> np.ndarray:
    """(n,) the smallest |normalised transfer-function denominator| over the groups (1 if none)."""
    mech = asm.mechanism
    poses = input_poses(mech, asm.structure, asm.shapes, phi)
    out = np.ones(phi.shape[0])
    for group, m in zip(asm.structure.groups, asm.branches):
        p1, p2, res = solve_group(group, m, poses, asm.shapes, asm.guides, mech, phi)
        out = np.minimum(out, np.abs(np.broadcast_to(res.denominator, phi.shape)))
        place(group, poses, p1, p2, res)
    return out


def _second_and_third(kin) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    out = {f"points.{n}": (v.d2, v.d3) for n, v in kin.points.items()}
    out |= {f"links.{n}": (p.angle.d2, p.angle.d3) for n, p in kin.links.items()}
    out |= {f"sliders.{n}": (s.d2, s.d3) for n, s in kin.sliders.items()}
    return out


def size(mech) -> float:
    """The sketch's extent [m]: the larger side of the box round its points."""
    return float(np.ptp(np.array(list(mech.points.values()), dtype=float), axis=0).max())


def third_transfer_errors(asm, phi: np.ndarray) -> dict[str, float]:
    """Per quantity: max |FD⁴(x″) − x‴| / S over ``phi``, S = L + peak |x″| + peak |x‴| (L the
    size for points and sliders, 1 rad for link angles)."""
    at = {j: _second_and_third(solve(asm, phi + j * H)) for j in (-2, -1, 0, 1, 2)}
    length = size(asm.mechanism)
    out = {}
    for name, (d2, d3) in at[0].items():
        fd = _fd4({j: at[j][name][0] for j in at}, H)
        scale = (1.0 if name.startswith("links.") else length) + np.abs(d2).max() + np.abs(d3).max()
        out[name] = float(np.abs(fd - d3).max()) / scale
    return out


def test_the_models_cover_every_dyad_kind_and_the_gear_planet():
    kinds = {g.kind for p in MODELS for g in assemble(load(p)).structure.groups}
    assert kinds == set(GroupKind)
    assert any(load(p).gears for p in MODELS)


def test_third_transfer_functions_match_differences_of_the_second(model_path):
    mech = load(model_path)
    asm = assemble(mech)
    phi = _grid(mech)
    tol = fd3_tolerance(float(smallest_denominator(asm, phi).min()))
    errs = third_transfer_errors(asm, phi)
    worst = {n: e for n, e in errs.items() if e > tol}
    assert not worst, (tol, worst)


def test_jerk_matches_time_differences_of_the_acceleration(model_path):
    # A crank at ω0 with constant ε ≠ 0 (|ε| about ω0², so that 3x″ωε weighs as much as x‴ω³):
    # φ(t) = φ0 + ω0·t + ε·t²/2, ω(t) = ω0 + ε·t; the accelerations at t = jτ (j = -2..2)
    # differenced in time against the jerk at t = 0. The same stencil and error terms as above,
    # with the time step τ turning the crank by H and S = ω0³·(L or 1 rad) + peak |jerk| +
    # ω0·peak |acceleration|.
    mech = load(model_path)
    asm = assemble(mech)
    phi0 = _grid(mech, 181)
    w0, eps = 3.0, -7.0
    tau = H / w0
    steps = (-2, -1, 0, 1, 2)
    t = np.repeat(np.array(steps) * tau, phi0.shape[0])
    mo = solve(asm, np.tile(phi0, 5) + w0 * t + 0.5 * eps * t * t).motion(w0 + eps * t, eps)
    tol = fd3_tolerance(float(smallest_denominator(asm, phi0).min()))
    n = phi0.shape[0]
    for kind in ("points", "links", "sliders"):
        for name, (_, _, acc) in getattr(mo, kind).items():
            acc = np.broadcast_to(acc, (5 * n, *acc.shape[1:]))
            jerk = np.broadcast_to(mo.jerk[kind][name], acc.shape)[2 * n:3 * n]
            fd = _fd4({j: acc[(j + 2) * n:(j + 3) * n] for j in steps}, tau)
            scale = w0**3 * (1.0 if kind == "links" else size(mech)) + np.abs(jerk).max() + w0 * np.abs(acc).max()
            assert np.abs(fd - jerk).max() <= tol * scale, (kind, name, np.abs(fd - jerk).max() / scale)


def test_jerk_is_the_third_transfer_function_at_constant_rates():
    kin = solve(load(ROOT / "models" / "seven_link.toml"), np.linspace(-0.5, 0.5, 7))
    w, e = 2.5, -1.5
    mo = kin.motion(w, e)
    for n, v in kin.points.items():
        np.testing.assert_allclose(mo.jerk["points"][n], v.d3 * w**3 + 3.0 * v.d2 * w * e, rtol=1e-14, atol=1e-14)
    for n, lp in kin.links.items():
        np.testing.assert_allclose(mo.jerk["links"][n], lp.angle.d3 * w**3 + 3.0 * lp.angle.d2 * w * e,
                                   rtol=1e-14, atol=1e-14)
    for n, s in kin.sliders.items():
        np.testing.assert_allclose(mo.jerk["sliders"][n], s.d3 * w**3 + 3.0 * s.d2 * w * e, rtol=1e-14, atol=1e-14)
    # the crank itself: no angular jerk at constant ε; its pin A turns on a circle of radius r:
    # x‴ = -r·(cos, sin)′ = r·(sin φ, -cos φ)
    assert not np.any(mo.jerk["links"]["crank"])
    a = kin.points["A"]
    np.testing.assert_allclose(a.d3, -np.stack([-a.p[:, 1], a.p[:, 0]], axis=1), rtol=0, atol=1e-15)


@pytest.mark.parametrize("rates", ["scalar", "array"])
def test_jerk_in_blocks_equals_one_piece(model_path, rates, monkeypatch):
    mech = load(model_path)
    asm = assemble(mech)
    phi = crank_grid(mech, 500)
    omega, epsilon = (3.0, -2.0) if rates == "scalar" else (1.0 + np.sin(phi), np.cos(phi))
    expected = solve(asm, phi)
    mo = expected.motion(omega, epsilon)
    monkeypatch.setattr(blocks, "BLOCK", 37)
    got = solve(asm, phi, threads=2)
    fused = solve_motion(asm, phi, omega, epsilon, threads=2)
    for n, v in expected.points.items():
        assert np.array_equal(v.d3, got.points[n].d3), n
    for n, lp in expected.links.items():
        assert np.array_equal(lp.angle.d3, got.links[n].angle.d3), n
    for n, s in expected.sliders.items():
        assert np.array_equal(s.d3, got.sliders[n].d3), n
    for kind in ("points", "links", "sliders"):
        for n, j in mo.jerk[kind].items():
            assert np.array_equal(np.broadcast_to(j, fused.jerk[kind][n].shape), fused.jerk[kind][n]), (kind, n)


def test_fixed_quantities_keep_a_zero_stride_jerk():
    kin = solve(load(ROOT / "models" / "fourbar.toml"), np.linspace(0, 1, 100))
    mo = kin.motion(2.0)
    for arr in (kin.points["O"].d3, kin.links["crank"].angle.d3, mo.jerk["points"]["C"], mo.jerk["links"]["crank"]):
        assert arr.strides[0] == 0 and not arr.any()


def test_tangent_mechanism_third_derivative_by_hand():
    # x = h·cot φ: x′ = -h·csc²φ, x″ = 2h·csc²φ·cot φ, x‴ = -2h·csc²φ·(csc²φ + 2cot²φ)
    phi = np.radians([45.0, 60.0, 120.0])
    kin = solve(load(ROOT / "models" / "tangent_prp.toml"), phi)
    csc2, cot = 1.0 / np.sin(phi) ** 2, 1.0 / np.tan(phi)
    np.testing.assert_allclose(kin.points["B"].d3[:, 0], -0.4 * csc2 * (csc2 + 2.0 * cot * cot), rtol=1e-14)
    np.testing.assert_allclose(kin.points["B"].d3[:, 1], 0.0, atol=1e-15)


def test_singular_angles_marked_give_finite_zero_jerk():
    mech = load(ROOT / "models" / "tangent_prp.toml")
    kin = solve(mech, np.array([0.5, 0.0, 1.0]), on_singular="mark")
    assert kin.singular.tolist() == [False, True, False]
    mo = kin.motion(2.0, 1.0)
    for kind in ("points", "links", "sliders"):
        for j in mo.jerk[kind].values():
            j = np.broadcast_to(j, (3, *j.shape[1:]))
            assert np.all(np.isfinite(j)) and not np.any(j[1])


# Reproducible; examples are seeds of the generator (no shrinking): a failure prints its TOML.
COMMON = dict(deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


@settings(max_examples=120, **COMMON)
@given(mechanisms())
def test_generated_mechanisms_third_transfer_functions(mechanism):
    _, desc = mechanism
    asm = assemble(linkgen.from_dict(desc))
    mech = asm.mechanism
    phi = np.linspace(mech.drive.start + 3 * H, mech.drive.stop - 3 * H, 40)
    d = smallest_denominator(asm, phi)
    phi = phi[d >= D_MIN]  # clear of dead centres and parallel guides
    assume(phi.shape[0] > 0)
    tol = fd3_tolerance(float(d[d >= D_MIN].min()))
    errs = third_transfer_errors(asm, phi)
    assert max(errs.values()) <= tol, (tol, max(errs.items(), key=lambda kv: kv[1]), to_toml(desc))


def _analyze(capsys, model, *extra) -> dict:
    assert main(["analyze", str(ROOT / "models" / model), "--angle", "30deg", "--json", *extra]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("model", ["fourbar.toml", "seven_link.toml"])
def test_analyze_json_reports_jerk_scaling_as_omega_cubed(capsys, model):
    one = _analyze(capsys, model, "--omega", "1", "--transfer")
    two = _analyze(capsys, model, "--omega", "2")
    assert one["units"]["jerk"] == "m/s³" and one["units"]["angular_jerk"] == "rad/s³"
    assert one["units"]["d3"] == "per rad³"
    for n, q in one["points"].items():
        assert list(q) == ["position", "velocity", "acceleration", "jerk", "d1", "d2", "d3"] and len(q["jerk"]) == 2
        # ε = 0: jerk = x‴·ω³
        assert q["jerk"] == pytest.approx(q["d3"], rel=1e-15, abs=1e-300)
        assert two["points"][n]["jerk"] == pytest.approx([8.0 * x for x in q["jerk"]], rel=1e-14, abs=1e-300)
    for n, q in one["links"].items():
        assert q["angular_jerk"] == pytest.approx(q["d3"], rel=1e-15, abs=1e-300)
        assert two["links"][n]["angular_jerk"] == pytest.approx(8.0 * q["angular_jerk"], rel=1e-14, abs=1e-300)
    for n, q in one["sliders"].items():
        assert q["jerk"] == pytest.approx(q["d3"], rel=1e-15, abs=1e-300)
        assert two["sliders"][n]["jerk"] == pytest.approx(8.0 * q["jerk"], rel=1e-14, abs=1e-300)


def test_analyze_jerk_with_crank_acceleration(capsys):
    out = _analyze(capsys, "seven_link.toml", "--omega", "3", "--epsilon", "-4", "--transfer")
    for n, q in out["points"].items():
        expected = [d3 * 27.0 + 3.0 * d2 * 3.0 * -4.0 for d2, d3 in zip(q["d2"], q["d3"])]
        assert q["jerk"] == pytest.approx(expected, rel=1e-13, abs=1e-13)


def test_analyze_text_and_csv_carry_jerk(capsys, tmp_path):
    model = str(ROOT / "models" / "seven_link.toml")
    assert main(["analyze", model, "--angle", "30deg", "--transfer"]) == 0
    text = capsys.readouterr().out
    assert "jx [m/s³]" in text and "jerk [rad/s³]" in text and "j [m/s³]" in text and "d³x/dφ³ [m]" in text
    assert "d³/dφ³ [rad/rad]" in text
    csv_path = tmp_path / "out.csv"
    assert main(["analyze", model, "--samples", "8", "--csv", str(csv_path), "--transfer"]) == 0
    header = csv_path.read_text(encoding="utf-8").splitlines()[0].split(",")
    for col in ("B.jerk.x [m/s³]", "B.jerk.y [m/s³]", "lever.angular_jerk [rad/s³]", "slider.jerk [m/s³]",
                "B.d3.x [m/rad³]", "lever.d3 [rad/rad³]", "slider.d3 [m/rad³]"):
        assert col in header, col
    assert header.index("B.jerk.x [m/s³]") == header.index("B.acceleration.y [m/s²]") + 1


def test_api_reports_jerk_and_third_transfer_functions():
    mech = load(ROOT / "models" / "seven_link.toml")
    k = linkgen.kinematics(mech, 0.3, omega=2.0, epsilon=0.0)
    kin = solve(mech, np.array([0.3]))
    assert np.allclose(k.points["B"].jerk, 8.0 * kin.points["B"].d3[0], rtol=1e-15, atol=0)
    assert k.links["lever"].d3 == kin.links["lever"].angle.d3[0]
    assert k.sliders["slider"].jerk == pytest.approx(8.0 * kin.sliders["slider"].d3[0], rel=1e-15)
    d = k.to_dict()
    assert d["units"]["jerk"] == "m/s³" and d["units"]["d3"] == "per rad³"
    assert list(d["points"]["B"]) == ["position", "velocity", "acceleration", "jerk", "d1", "d2", "d3"]
    cols = linkgen.kinematics(mech, np.linspace(-0.2, 0.2, 5)).columns()
    for c in ("B.jerk.x [m/s³]", "B.d3.y [m/rad³]", "lever.angular_jerk [rad/s³]", "slider.d3 [m/rad³]"):
        assert c in cols and cols[c].shape == (5,), c

"""Coulomb friction in revolute and prismatic pairs ([[friction]]): the description's checks, the
kinetostatics by hand on a slider-crank, the power balance with the losses, still pairs, self-locking,
generated mechanisms as the coefficients go to zero, the machine's refusal and MuJoCo."""

from __future__ import annotations

import copy
import math
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import ROOT
from linkgen import assemble, load
from linkgen.errors import DescriptionError, FrictionError
from linkgen.families.planar.corpus import random_description
from linkgen.families.planar.kinetostatics import forces
from linkgen.families.planar.reader import from_dict

MODELS = ROOT / "models"
MODEL = MODELS / "slider_crank_friction.toml"

# A nearly massless slider-crank (crank r = 0.1 m, rod l = 0.35 m, the slider on the x axis through
# the crank's pivot O) with a gas force P along +x on the slider, no gravity, turning slowly: the
# inertia forces (m·ω²·r = 1e-6 kg · 1e-6 rad²/s² · 0.1 m = 1e-13 N) are 1e-16 of P, so the rod is a
# two-force member and the massless hand solution below holds to rounding.
R, L, P = 0.1, 0.35, 1000.0
W, MASS = 1e-3, 1e-6  # rad/s, kg


def _hand_desc(friction: list[dict], omega: float = W) -> dict:
    tiny = {"mass": MASS, "inertia": MASS * 1e-3}
    return {
        "mechanism": {"name": "hand", "gravity": [0.0, 0.0]},
        "points": {"O": [0.0, 0.0], "A": [R, 0.0], "B": [R + L, 0.0]},
        "links": {"ground": {"points": ["O"]},
                  "crank": {"points": ["O", "A"], "inertial": tiny | {"com": [0.05, 0.0]}},
                  "rod": {"points": ["A", "B"], "inertial": tiny | {"com": [0.1, 0.0]}},
                  "slider": {"points": ["B"], "inertial": tiny | {"com": [0.0, 0.0]}}},
        "prismatic": {"slider": {"slider": "slider", "guide": "ground", "point": "B", "through": "O"}},
        "force": [{"link": "slider", "point": "B", "force": [P, 0.0]}],
        "drive": {"joint": "O", "omega": omega},
        "friction": friction,
    }


def _pose(phi: float) -> tuple[np.ndarray, np.ndarray]:
    """A and the unit vector e from A to B at crank angle φ, by hand."""
    a = np.array([R * math.cos(phi), R * math.sin(phi)])
    b = np.array([a[0] + math.sqrt(L * L - a[1] ** 2), 0.0])
    return a, (b - a) / L


# The hand formulas and the closed form each round at ~1e-16 of the forces (~1e3 N) through a few
# dozen operations; the friction iteration stops within FRICTION_TOL = 1e-12 of its fixed point.
HAND_TOL = 1e-10
# Two sums of the same few products in another order (the pairs' losses): rounding, ~1e-15 each.
SUM_TOL = 1e-12


@pytest.mark.parametrize("deg", [60.0, 120.0, 250.0])
def test_slider_friction_by_hand(deg):
    """Textbook slider-crank with friction μ in the slider: the rod's tension T balances the slider
    along x with the gas force P and the friction μ·|N|, N = T·e_y, against the sliding speed:
    P − T·e_x + μ·|T·e_y|·sgn(−ẋ_B) = 0, so T = P / (e_x + μ·|e_y|·sgn(ẋ_B)) (T > 0), and the
    massless crank needs the torque M = −(A × T·e)_z."""
    mu, phi = 0.2, math.radians(deg)
    a, e = _pose(phi)
    # ẋ_B/ω = −r·sin φ − r·cos φ·a_y/√(l² − a_y²) (differentiate x_B = a_x + √(l² − a_y²))
    xb_dot = -R * math.sin(phi) - a[1] * R * math.cos(phi) / math.sqrt(L * L - a[1] ** 2)
    tension = P / (e[0] + mu * abs(e[1]) * math.copysign(1.0, xb_dot))
    torque = -(a[0] * tension * e[1] - a[1] * tension * e[0])
    desc = _hand_desc([{"pair": "slider", "coefficient": mu, "block_length": 0.04}])
    f = forces(from_dict(desc), np.array([phi]), W)
    assert f.balancing_torque[0] == pytest.approx(torque, rel=HAND_TOL)
    # the friction on the slider along +x opposes its motion, μ·|N| = μ·T·|e_y|
    assert f.friction["slider"][0] == pytest.approx(-math.copysign(mu * tension * abs(e[1]), xb_dot), rel=HAND_TOL)
    # the power lost is the friction force times the sliding speed
    assert f.friction_power[0] == pytest.approx(mu * tension * abs(e[1]) * abs(xb_dot) * W, rel=HAND_TOL)


def test_pin_friction_at_the_drive_by_hand():
    """Friction μ, radius r at the crank's pivot O only: the rod is a two-force member (T = P/e_x)
    and the massless crank's pivot carries |R_O| = T, so the drive adds μ·r·T (ω > 0) to the
    frictionless torque −(A × T·e)_z."""
    mu, radius, phi = 0.1, 0.006, math.radians(40.0)
    a, e = _pose(phi)
    tension = P / e[0]
    torque = -(a[0] * tension * e[1] - a[1] * tension * e[0]) + mu * radius * tension
    desc = _hand_desc([{"pair": "O", "coefficient": mu, "pin_radius": radius}])
    f = forces(from_dict(desc), np.array([phi]), W)
    assert f.balancing_torque[0] == pytest.approx(torque, rel=HAND_TOL)
    assert np.hypot(*f.reactions["O"][0]) == pytest.approx(tension, rel=HAND_TOL)


def test_pin_friction_couples_oppose_the_relative_rotation_on_the_model():
    """On the bundled model every pair's friction opposes its relative motion: the couple on a
    revolute's first link has the sign of −(θ̇_first − θ̇_second), the slider's force that of −ṡ,
    so each pair's power is ≤ 0 and the total lost power is their sum's opposite."""
    from linkgen.families.planar.kinematics import solve

    mech = load(MODEL)
    asm = assemble(mech)
    phi = np.linspace(0.0, 2 * math.pi, 73)[:-1]
    w = mech.drive.omega
    f = forces(asm, phi, w)
    kin = solve(asm, phi)
    rate = {n: kin.links[n].angle.d1 for n in mech.moving_links} | {"ground": np.zeros_like(phi)}
    lost = np.zeros_like(phi)
    for r in mech.revolutes:
        p = f.friction[r.name] * (rate[r.links[0]] - rate[r.links[1]]) * w
        assert (p <= 0).all(), r.name
        lost -= p
    p = f.friction["slider"] * kin.sliders["slider"].d1 * w
    assert (p <= 0).all()
    lost -= p
    np.testing.assert_allclose(f.friction_power, lost, rtol=SUM_TOL, atol=0)
    assert (f.friction_power > 0).all()


def test_still_pairs_have_no_friction():
    """At ω = 0 no pair moves: the friction is indeterminate and taken as zero (docs/format.md), so
    the forces are the frictionless ones; at the dead centre φ = 0 the slider stands still."""
    mech = load(MODEL)
    desc = tomllib.loads(MODEL.read_text())
    bare = from_dict({k: v for k, v in desc.items() if k != "friction"})
    phi = np.linspace(0.0, 2 * math.pi, 13)
    f, g = forces(mech, phi, 0.0, 3.0), forces(bare, phi, 0.0, 3.0)
    np.testing.assert_array_equal(f.balancing_torque, g.balancing_torque)
    assert all((v == 0).all() for v in f.friction.values())
    assert (f.friction_power == 0).all()
    moving = forces(mech, np.array([0.0, math.pi]), 10.0)
    assert (moving.friction["slider"] == 0).all() and (moving.friction["O"] != 0).all()


@pytest.mark.parametrize("entry, field, words", [
    ({"pair": "Q", "coefficient": 0.1, "pin_radius": 0.01}, "friction[0].pair", "unknown pair 'Q'"),
    ({"pair": "A", "coefficient": -0.1, "pin_radius": 0.01}, "friction[0].coefficient", "must be >= 0"),
    ({"pair": "A", "coefficient": float("nan"), "pin_radius": 0.01}, "friction[0].coefficient", "finite"),
    ({"pair": "A", "coefficient": 0.1}, "friction[0].pin_radius", "is required for the revolute 'A'"),
    ({"pair": "A", "coefficient": 0.1, "pin_radius": 0.0}, "friction[0].pin_radius", "must be > 0 m"),
    ({"pair": "A", "coefficient": 0.1, "block_length": 0.04}, "friction[0].block_length", "does not apply"),
    ({"pair": "slider", "coefficient": 0.1}, "friction[0].block_length", "is required for the prismatic pair"),
    ({"pair": "slider", "coefficient": 0.1, "block_length": "-4cm"}, "friction[0].block_length", "must be > 0 m"),
    ({"pair": "slider", "coefficient": 0.1, "block_length": 0.04, "size": 1}, "friction[0].size", "unknown key"),
    ({"pair": "slider", "coefficient": 11.0, "block_length": 0.04}, "friction[0].coefficient", "within ±10"),
])
def test_bad_friction_is_a_description_error(entry, field, words):
    desc = _hand_desc([entry])
    with pytest.raises(DescriptionError) as err:
        from_dict(desc)
    assert err.value.field == field and words in str(err.value), str(err.value)


def test_a_pair_with_friction_twice_is_refused():
    entry = {"pair": "A", "coefficient": 0.1, "pin_radius": 0.01}
    with pytest.raises(DescriptionError, match=r"friction\[1\]\.pair: pair 'A' already has friction in friction\[0\]"):
        from_dict(_hand_desc([entry, entry]))


# The slider self-locks where the friction the rod's pull calls for, μ·T·|e_y|, grows faster than
# the pull's useful part T·e_x: μ·|e_y| > e_x, with the slider moving towards the crank (0 < φ < 180°).
LOCK_MU = 5.0


def test_self_locking_is_an_error_naming_the_angles():
    mech = from_dict(_hand_desc([{"pair": "slider", "coefficient": LOCK_MU, "block_length": 0.04}]))
    with pytest.raises(FrictionError, match=r"finds no solution at crank angles 90\.000°: .*self-locks"):
        forces(mech, np.array([math.radians(90.0)]), W)
    phi = np.radians(np.arange(0.0, 181.0, 5.0))
    f = forces(mech, phi, W, on_singular="mark")
    ratio = np.array([LOCK_MU * abs(_pose(p)[1][1]) / _pose(p)[1][0] for p in phi])
    assert f.singular[ratio > 1.0].all() and not f.singular[ratio < 0.9].any()
    assert (f.balancing_torque[f.singular] == 0).all() and np.isfinite(f.balancing_torque).all()
    # where it moves, the hand formula (test_slider_friction_by_hand)
    k = int(np.argmax(~f.singular & (phi > 0)))
    a, e = _pose(phi[k])
    tension = P / (e[0] - LOCK_MU * abs(e[1]))
    assert f.balancing_torque[k] == pytest.approx(-(a[0] * tension * e[1] - a[1] * tension * e[0]), rel=HAND_TOL)


def _with_friction(desc: dict, mu: float) -> dict:
    """``desc`` with friction μ in every lower pair: pins of 1 % and blocks of 5 % of its size."""
    mech = from_dict(desc)
    xy = np.array(list(mech.points.values()))
    size = float(np.ptp(xy, axis=0).max())
    out = copy.deepcopy(desc)
    out["friction"] = ([{"pair": r.name, "coefficient": mu, "pin_radius": 0.01 * size} for r in mech.revolutes]
                       + [{"pair": p.name, "coefficient": mu, "block_length": 0.05 * size} for p in mech.prismatics])
    return out


# μ of the generated pairs: small enough that the balancing torque's change is linear in μ to
# ~μ·κ (κ the groups' force amplification, ≲ 1e2 five degrees from a dead centre), large enough
# that the change (~μ·1e-2 of the torque scale: pins of 1 % of the size) stands well above rounding.
SMALL_MU = 1e-5
# (T(2μ) − T0) − 2·(T(μ) − T0) is the second-order term: ≲ μ·κ = 1e-3 of the first (measured: up to
# 2.6e-3 over 60 seeds, the ones nearest a dead centre).
LINEAR_TOL = 1e-2
# The torques' rounding floor: the balance itself is checked at BALANCE_TOL = 1e-8 of the torque
# scale on every call (measured ≤ 3.5e-13 of the peak here); 1e-9 of the peak torque.
ROUND_TOL = 1e-9
# The summary refines the peak between 0.1° samples by a bracketed search on a curve with kinks
# (each friction's switch): within 1e-4 of the best sample, never below it.
PEAK_TOL = 1e-4


@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1))
def test_friction_tends_to_frictionless_on_generated_mechanisms(seed):
    """On generated mechanisms, friction in every pair: the losses are ≥ 0, the balancing torque's
    change is sgn(ω)·(lost power)/|ω| and, as μ → 0, linear in μ (so it vanishes with μ)."""
    desc = random_description(np.random.default_rng(seed), max_groups=3)
    d = desc["drive"]
    lo, hi = d.get("range", [0.0, 2 * math.pi])
    phi = np.linspace(lo, hi, 25)
    base = forces(from_dict(desc), phi, d["omega"]).balancing_torque
    one = forces(from_dict(_with_friction(desc, SMALL_MU)), phi, d["omega"])
    two = forces(from_dict(_with_friction(desc, 2 * SMALL_MU)), phi, d["omega"])
    assert (one.friction_power >= 0).all() and (two.friction_power >= 0).all()
    d1, d2 = one.balancing_torque - base, two.balancing_torque - base
    scale = np.abs(base).max()
    np.testing.assert_allclose(d1, np.sign(d["omega"]) * one.friction_power / abs(d["omega"]), rtol=0,
                               atol=ROUND_TOL * scale)
    assert np.abs(d2 - 2 * d1).max() <= LINEAR_TOL * np.abs(d2).max() + ROUND_TOL * scale, seed
    assert np.abs(d1).max() > 0


def test_the_summary_gives_the_power_lost_to_friction():
    """Peak and mean of the lost power over the range; none without friction."""
    from linkgen.families.planar.summary import summarize

    asm = assemble(load(MODEL))
    s = summarize(asm)
    phi = np.linspace(0.0, 2 * math.pi, 3601)
    lost = forces(asm, phi, asm.mechanism.drive.omega).friction_power
    assert s.peak_friction_power.value >= lost.max() and s.peak_friction_power.value == pytest.approx(lost.max(), rel=PEAK_TOL)
    assert s.mean_friction_power == pytest.approx(lost[:-1].mean(), rel=SUM_TOL)
    assert "power lost to friction: peak" in s.text()
    assert summarize(assemble(load(MODELS / "slider_crank_spring.toml"))).peak_friction_power is None


# A machine with friction in its pairs: tests/test_machine_friction.py.


# ---------------------------------------------------------------- MuJoCo


@pytest.fixture(scope="module")
def comparison():
    """One MuJoCo run of the friction model compared with the closed form (shared by the tests)."""
    from linkgen.crosscheck.compare import compare
    from linkgen.mujoco.simulate import simulate

    asm = assemble(load(MODEL))
    return compare(asm, simulate(asm))


def test_mujoco_validates_the_friction_model(comparison):
    """Friction applied each step by linkgen: MuJoCo's reactions and driving torque (forward run and
    inverse route) agree with the closed form's at the usual tolerances (linkgen.mujoco.tolerances)."""
    bad = {k: q.relative_error for k, q in comparison.quantities.items() if not q.ok}
    assert not bad, bad
    for name in ("balancing_torque", "reactions.A.force", "prismatic.slider.normal_force", "inverse.balancing_torque",
                 "friction.slider", "friction.O", "friction.A", "friction.B"):
        assert name in comparison.quantities


def test_the_friction_from_mujocos_own_reactions_is_the_one_applied(comparison):
    """The fixed point in MuJoCo's terms: the friction law applied to MuJoCo's reactions of the run
    gives back the friction linkgen applied (the closed form's), within what the reactions agree to."""
    from linkgen.mujoco.friction import friction_from_reactions
    from linkgen.mujoco.tolerances import FORCE_TOL

    s = comparison.run.samples
    phi, omega, _ = s.crank
    mj = s.forces
    ours = friction_from_reactions(comparison.assembly, phi, omega, mj.reactions, mj.normal_force, mj.moment)
    applied = comparison.closed_forces.friction
    mech = comparison.assembly.mechanism
    scale = max(float(np.abs(r).max()) for r in comparison.closed_forces.reactions.values())
    for fr in mech.frictions:
        # |Δ(μ·r·|R|)| ≤ μ·r·|ΔR| and |Δ(μ·max(|N|, 2|M|/L))| ≤ μ·(|ΔN| + 2|ΔM|/L): the reactions within FORCE_TOL
        arm = fr.pin_radius if fr.pin_radius is not None else 1.0
        tol = fr.coefficient * arm * FORCE_TOL * scale
        moving = applied[fr.pair] != 0
        assert np.abs(ours[fr.pair] - applied[fr.pair])[moving].max() <= tol, fr.pair


def test_the_mjcf_says_friction_is_applied_each_step():
    from linkgen.mujoco.mjcf import write_mjcf

    head = write_mjcf(assemble(load(MODEL))).split("-->")[0]
    assert "Friction in the pairs ([[friction]]) is not in this file" in head
    assert "[[friction]]" not in write_mjcf(assemble(load(MODELS / "slider_crank_spring.toml"))).split("-->")[0]


def test_friction_turned_against_the_pull_converges_where_a_plain_iteration_would_not():
    """At 270° the slider moves away from the crank: the friction μ·T·|e_y| opposes the gas force,
    so T = P / (e_x + μ·|e_y|) exists for any μ; with μ = LOCK_MU each plain pass overshoots by
    μ·|e_y|/e_x ≈ 1.5 (it diverged, reported as self-locking) and the under-relaxed one converges."""
    mech = from_dict(_hand_desc([{"pair": "slider", "coefficient": LOCK_MU, "block_length": 0.04}]))
    for deg in (250.0, 270.0, 300.0):
        phi = math.radians(deg)
        a, e = _pose(phi)
        assert LOCK_MU * abs(e[1]) / e[0] > 1.0  # where a plain iteration diverges
        tension = P / (e[0] + LOCK_MU * abs(e[1]))
        f = forces(mech, np.array([phi]), W)
        assert f.balancing_torque[0] == pytest.approx(-(a[0] * tension * e[1] - a[1] * tension * e[0]), rel=HAND_TOL)


def test_the_robot_model_names_each_pairs_friction(tmp_path):
    """A robot scene cannot carry the load-dependent friction either: its header says how to apply it."""
    from linkgen.cli.main import main

    out = tmp_path / "robot.xml"
    assert main(["build", "--robot", str(MODEL), "-o", str(out)]) == 0
    head = out.read_text().split("-->")[0]
    assert "[[friction]] in pair O: a couple μ·r·|R| (μ = 0.1, r = 0.006 m) between links ground and crank" in head
    assert "[[friction]] in pair slider: a force μ·max(|N|, 2|M|/L) (μ = 0.15, L = 0.04 m)" in head


def test_a_runs_lead_in_before_a_dead_centre_gets_zero_friction():
    """tangent_prp turns over 40°..140°, between dead centres; a coarse (practical-settings) run's
    lead-in starts ~65° early and crosses the one at 0°, where the closed form is singular: the
    loads scheduled there (friction included) are zero instead of an error (validate failed:
    SingularityError at −0.004°). Those steps only settle the run; no sample is compared there."""
    import mujoco

    from linkgen.mujoco.forces import load_schedule
    from linkgen.mujoco.mjcf import write_mjcf

    desc = tomllib.loads((MODELS / "tangent_prp.toml").read_text())
    asm = assemble(from_dict(_with_friction(desc, 0.1)))
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm))
    rows = load_schedule(asm, model, np.radians([-0.004, 10.0]), asm.mechanism.drive.omega)
    assert np.isfinite(rows).all() and not rows[0].any() and rows[1].any()


def test_sampled_forces_name_the_self_locked_samples(tmp_path, capsys):
    """`linkgen forces --samples` marks the samples where the friction has no solution and says so
    (they were marked singular silently, exit status 0)."""
    from linkgen.cli.main import main
    from linkgen.model.toml_text import to_toml

    desc = _hand_desc([{"pair": "slider", "coefficient": LOCK_MU, "block_length": 0.04}], omega=1.0)
    path = tmp_path / "lock.toml"
    path.write_text(to_toml(desc))
    assert main(["forces", str(path), "--samples", "37", "-o", str(tmp_path / "f.csv")]) == 3
    err = capsys.readouterr().err
    assert "the kinetostatics with friction finds no solution at crank angles 48.649°..136.216° (10 of 37" in err


def test_no_sample_is_compared_on_a_friction_switch(comparison):
    """The frictions turn round where the motions do, by hand for this centred slider-crank: the
    slider at 0° and 180°, the rod (pin B, and A relative to it) at 90° and 270°. A sample is read at
    its nearest step: the one due at 90° was read 4.6e-5 rad after the switch, inside no settling
    window, and carried the run's worst error (7.1e-7 of the scale, against 5.1e-8 elsewhere)."""
    phi = np.mod(comparison.run.samples.crank[0], 2 * math.pi)
    for deg in (0.0, 90.0, 180.0, 270.0):
        after = np.mod(phi - math.radians(deg), 2 * math.pi)
        assert not np.any(after < 1e-3), deg  # the settling windows here are ~3.5e-2 rad
    worst = comparison.quantities["links.rod.angular_acceleration"]
    assert worst.ok

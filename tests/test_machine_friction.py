"""Friction in the pairs in the machine's equation (issue 25, items 2 and 3): the friction's reduced
moment depends on the reactions, so on the crank's acceleration, and is solved with it at each state.

The checks stand outside the machine code: a lone crank with pin friction at its drive, whose
equation is written out here (|R| = m·r_c·√(ω⁴ + ε²) with no gravity) and integrated by scipy;
the kinetostatics' balancing torque at the run's states against the motor's; the friction's
limit μ → 0; MuJoCo's full linkage with the friction applied at its own states."""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from linkgen.errors import SimulationError
from linkgen.families.planar.kinetostatics import forces
from linkgen.machine.energy import ENERGY_TOL
from linkgen.machine.friction import STICK_SPEED, LockedError
from linkgen.machine.machine import RTOL, run_machine
from linkgen.machine.reduced import reduce
from linkgen.machine.study import load_machine

MODELS = Path(__file__).resolve().parents[1] / "models"
# The ODE against the hand-written one: a hundred times its relative tolerance (as test_dynamics.py).
EXACT_TOL = 100 * RTOL
# The kinetostatics' balancing torque at the run's states against the motor's torque: the ODE's
# M₀ is a table whose cubic spline errs by (2π/32768)²/8·|M″| ≈ 4.6e-9·|M″| (machine.reduced), with
# |M″| ≲ 10 N·m here per N·m of drive: 1e-7 of the drive torque (measured 1.3e-10).
TORQUE_TOL = 1e-7
# The friction's effect at full μ departs from μ times its slope at μ = 0 by its second-order part,
# of the order of the friction's own share of the reactions (a few % here: measured 1.4 % after
# 0.02 s); a wrong slope (a friction counted twice or not at all) is off by 100 %.
LINEAR_TOL = 0.05
# MuJoCo's machine against the ODE: crosscheck.machine.MACHINE_TOL (the machines' tolerance).
from linkgen.crosscheck.machine import MACHINE_TOL  # noqa: E402

CRANK = """
[mechanism]
name = "crank_friction"
gravity = [0.0, 0.0]
[points]
O = [0.0, 0.0]
A = [0.2, 0.0]
[links.ground]
points = ["O"]
[links.crank]
points = ["O", "A"]
[links.crank.inertial]
mass = 2.0
com = [0.1, 0.0]
inertia = 0.01
[[friction]]
pair = "O"
coefficient = {mu}
pin_radius = "10mm"
[drive]
joint = "O"
omega = 1.0
[machine]
start_speed = {w0}
duration = {duration}
[machine.motor]
kind = "constant"
torque = {torque}
"""
M, RC, IC, RP = 2.0, 0.1, 0.01, 0.01  # the crank above: mass, centre of mass, inertia about it, pin radius
IO = IC + M * RC**2  # its inertia about O


def _crank(tmp_path, mu=0.3, w0=5.0, duration=0.5, torque=0.5):
    p = tmp_path / "crank.toml"
    p.write_text(CRANK.format(mu=mu, w0=w0, duration=duration, torque=torque))
    return load_machine(p)


def _hand_rate(mu, torque):
    """(ω, φ) → (ω, ε) with I_O·ε = T − μ·r_p·m·r_c·√(ω⁴ + ε²)·sgn ω (the pin's reaction is the
    centre of mass's m·a, no gravity), ε by a bracketed root of that scalar equation."""
    def rate(t, y):
        w = y[1]
        f = lambda e: IO * e - torque + mu * RP * M * RC * math.sqrt(w**4 + e * e) * math.copysign(1.0, w)
        big = 10 * (abs(torque) + mu * RP * M * RC * w * w) / IO + 1.0
        return [w, brentq(f, -big, big, xtol=1e-15, rtol=1e-15)]
    return rate


def test_a_crank_with_pin_friction_follows_its_hand_written_equation(tmp_path):
    asm, machine = _crank(tmp_path)
    run = run_machine(machine, reduce(asm), samples=51)
    ref = solve_ivp(_hand_rate(0.3, 0.5), (0.0, 0.5), [0.0, 5.0], rtol=1e-12, atol=1e-14, dense_output=True)
    y = ref.sol(run.t)
    assert np.abs(run.omega - y[1]).max() <= EXACT_TOL * np.abs(y[1]).max()
    assert np.abs(run.phi - y[0]).max() <= EXACT_TOL * np.abs(y[0]).max()
    frictionless = 0.5 / IO  # the friction slows it: ε is well below T/I_O
    assert run.epsilon[0] < 0.99 * frictionless
    assert run.energy.ok and run.energy.friction[-1] < 0


def test_a_start_from_rest_has_no_friction_until_the_stick_speed(tmp_path):
    """At ω = 0 the regularised law gives no friction (ε = T/I_O), at half STICK_SPEED tanh(1/2)
    of Coulomb's, and from there on the run is the Coulomb one of the hand-written equation."""
    asm, machine = _crank(tmp_path, w0=0.0, duration=0.2, torque=0.5)
    red = reduce(asm)
    run = run_machine(machine, red, samples=41)
    assert run.epsilon[0] == pytest.approx(0.5 / IO, rel=1e-12)
    from linkgen.machine.equation import Model

    model = Model(machine, red)
    half = model.rhs(0.0, np.array([1.0, 0.5 * STICK_SPEED]))[1]
    # the friction scaled by tanh(1/2): tanh(1/2)·μ·r_p·m·r_c·√(ω⁴ + ε²), ω⁴ negligible
    f = lambda e: IO * e - 0.5 + math.tanh(0.5) * 0.3 * RP * M * RC * abs(e)
    assert half == pytest.approx(brentq(f, 0.0, 100.0, xtol=1e-15), rel=1e-9)
    later = run.t >= 0.05  # ω ≫ STICK_SPEED from here on: pure Coulomb
    start = float(run.t[later][0])
    ref = solve_ivp(_hand_rate(0.3, 0.5), (start, 0.2), [run.phi[later][0], run.omega[later][0]], rtol=1e-12,
                    atol=1e-14, dense_output=True)
    assert np.abs(run.omega[later] - ref.sol(run.t[later])[1]).max() <= EXACT_TOL * np.abs(run.omega).max()


def _scaled(tmp_path, factor: float):
    text = (MODELS / "machine_friction.toml").read_text()
    text = text.replace("coefficient = 0.15", f"coefficient = {0.15 * factor!r}")
    text = text.replace("coefficient = 0.1\n", f"coefficient = {0.1 * factor!r}\n")
    p = tmp_path / f"mf_{factor:g}.toml"
    p.write_text(text)
    return load_machine(p)


def test_as_friction_vanishes_the_run_tends_to_the_frictionless_one(tmp_path):
    """The friction's effect on ω is linear in μ to first order: a thousandth of μ, a thousandth
    of the effect (within LINEAR_TOL of it), and μ = 0 is the frictionless run itself."""
    asm, machine = _scaled(tmp_path, 1.0)
    red = reduce(asm)
    base = run_machine(replace(machine, duration=0.02), replace(red, friction=None), samples=11)
    full = run_machine(replace(machine, duration=0.02), red, samples=11)
    asm3, machine3 = _scaled(tmp_path, 1e-3)
    small = run_machine(replace(machine3, duration=0.02), reduce(asm3), samples=11)
    effect = full.omega - base.omega
    assert np.abs(effect).max() > 1e-3 * np.abs(base.omega).max()  # the friction does slow it
    np.testing.assert_allclose(small.omega - base.omega, 1e-3 * effect, rtol=0, atol=LINEAR_TOL * 1e-3 * np.abs(effect).max())
    asm0, machine0 = _scaled(tmp_path, 0.0)
    zero = run_machine(replace(machine0, duration=0.02), reduce(asm0), samples=11)
    assert np.abs(zero.omega - base.omega).max() <= EXACT_TOL * np.abs(base.omega).max()


def test_the_machine_with_friction_balances_its_energy_and_its_torque(tmp_path):
    """The energy balance counts the friction's work (leaving it out fails it), and the closed
    form's kinetostatics (reactions with friction, group by group) at the run's φ, ω, ε needs
    exactly the motor's torque."""
    asm, machine = load_machine(MODELS / "machine_friction.toml")
    run = run_machine(replace(machine, duration=0.05), reduce(asm), samples=26)
    e = run.energy
    assert e.ok and e.worst <= ENERGY_TOL
    assert e.friction[-1] < -1e-3 * e.scale
    without = np.abs(e.residual + e.friction).max() / e.scale
    assert without > 1e3 * ENERGY_TOL
    f = forces(asm, run.phi, run.omega, run.epsilon)
    drive = 40.0  # N·m, the model's constant motor, no gear
    assert np.abs(f.balancing_torque + machine.added_inertia * run.epsilon - drive).max() <= TORQUE_TOL * drive
    assert (f.friction_power > 0).all()


def test_mujoco_runs_the_machine_with_friction(tmp_path):
    from linkgen.crosscheck.machine import compare_machine_run

    asm, machine = load_machine(MODELS / "machine_friction.toml")
    out, _, _ = compare_machine_run(asm, replace(machine, duration=0.01))
    assert out["ok"], out
    assert out["errors_relative"]["omega"] <= MACHINE_TOL and out["errors_relative"]["reactions"] <= MACHINE_TOL


def test_a_machine_that_friction_locks_is_named_with_its_time_and_angle(tmp_path):
    """A pin friction k·√(ω⁴ + ε²), k = μ·r_p·m·r_c = 10·0.2·2·0.1 = 0.4 > I_O = 0.03: at ω = 10
    rad/s, I_O·ε + k·√(ω⁴ + ε²) is at least ω²·√(k² − I_O²) = 39.9 N·m for every ε, more than the
    0.5 N·m drive: no acceleration satisfies the equation, the pin locks."""
    text = CRANK.format(mu=10.0, w0=10.0, duration=0.1, torque=0.5).replace('pin_radius = "10mm"', 'pin_radius = "200mm"')
    p = tmp_path / "locked.toml"
    p.write_text(text)
    asm, machine = load_machine(p)
    with pytest.raises(SimulationError) as info:
        run_machine(machine, reduce(asm), samples=11)
    assert isinstance(info.value, LockedError)
    msg = str(info.value)
    assert "t = 0 s" in msg and "φ = 0.0000°" in msg and "[[friction]]" in msg


def test_a_released_fourbar_with_pin_friction_reverses_with_its_energy_balanced(tmp_path):
    """models/fourbar_released.toml with pin friction at O and C (μ = 0.2, r = 10 mm), released from
    rest: it swings back, each reversal through the regularised law, and loses energy to the
    friction — the balance holds along the run. With a linear ramp min(1, |ω|/ω_s), whose kink at
    ω_s the solver's steps and the energy quadrature cross, it did not: 3.0e-7 (now 7.8e-10)."""
    text = (MODELS / "fourbar_released.toml").read_text()
    text = text.replace("duration = 5.0", "duration = 0.8") + """
[[friction]]
pair = "O"
coefficient = 0.2
pin_radius = "10mm"

[[friction]]
pair = "C"
coefficient = 0.2
pin_radius = "10mm"
"""
    p = tmp_path / "released_friction.toml"
    p.write_text(text)
    asm, machine = load_machine(p)
    assert machine.free and machine.duration == 0.8
    run = run_machine(machine, reduce(asm), samples=101)
    assert np.count_nonzero(np.diff(np.sign(run.omega[1:])) != 0) >= 1  # it reverses
    e = run.energy
    assert e.ok and e.worst <= ENERGY_TOL and e.friction[-1] < 0

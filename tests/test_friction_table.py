"""The pairs' friction at a machine's state by Newton over tables of the frictionless reactions'
affine parts (``machine/friction_table.py``), against the closed form's own friction
kinetostatics (``kinetostatics.forces``, its fixed point on the reactions, group by group); the
machine's equation and MuJoCo's steps no longer build the kinetostatics at each state; validate's
window for machines with friction (a step budget, stated)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from linkgen import assemble, load
from linkgen.families.planar import kinetostatics
from linkgen.families.planar.kinetostatics import forces
from linkgen.machine.friction import PairFriction, acceleration, friction_values, scale
from linkgen.machine.friction_table import TABLE_TOL, build
from linkgen.machine.machine import run_machine
from linkgen.machine.reduced import reduce
from linkgen.machine.study import load_machine

MODELS = Path(__file__).resolve().parents[1] / "models"
# The table's route against the closed form's: the splines meet the closed form within TABLE_TOL
# = 1e-11 of each column's peak, the closed form's own fixed point is converged to FRICTION_TOL =
# 1e-12 of the friction, and a pair's friction is μ·r·|R| of reactions ~10–100 times itself:
# 1e-9 of the largest friction leaves a factor ~10 over their sum (measured 1e-13).
AGREE_TOL = 1e-9
# The float path (one state) against the array path (many): the same operations in another order.
SAME_TOL = 1e-13

# A press: a stroke-switched force (the reactions jump at 100° and 170°, so do the table's
# columns) and friction in every pair; and the same with a damper on a spring.
PRESS_FRICTION = """
[[friction]]
pair = "ram"
coefficient = 0.2
block_length = "60mm"

[[friction]]
pair = "O"
coefficient = 0.1
pin_radius = "8mm"

[[friction]]
pair = "A"
coefficient = 0.12
pin_radius = "6mm"

[[friction]]
pair = "B"
coefficient = 0.1
pin_radius = "6mm"
"""


def _press(tmp_path):
    p = tmp_path / "press_friction.toml"
    p.write_text((MODELS / "press.toml").read_text() + PRESS_FRICTION)
    return assemble(load(p))


def _states(n: int, seed: int):
    rng = np.random.default_rng(seed)
    return rng.uniform(0.0, 2 * math.pi, n), rng.uniform(-40.0, 40.0, n), rng.uniform(-300.0, 300.0, n)


@pytest.mark.parametrize("which", ["machine_friction", "slider_crank_friction", "press"])
def test_the_tables_friction_is_the_closed_forms(which, tmp_path):
    asm = _press(tmp_path) if which == "press" else assemble(load(MODELS / f"{which}.toml"))
    table = build(asm)
    assert table is not None and table.error <= TABLE_TOL
    phi, w, e = _states(300, 7)
    if which == "press":  # next to the force's switch angles, each side of the jump (at the angle
        # itself the table holds the later value, as tables.PeriodicTable does, the stroke its end's)
        phi[:4] = np.radians([100.0 - 1e-7, 100.0 + 1e-7, 170.0 - 1e-7, 170.0 + 1e-7])
    pairs, mf, _ = friction_values(asm, phi, w, e)
    ref = forces(asm, phi, w, e)
    peak = max(float(np.abs(v).max()) for v in ref.friction.values())
    for name, v in ref.friction.items():
        assert np.abs(pairs[name] - v).max() <= AGREE_TOL * peak, name
    loss = np.sign(w) * ref.friction_power / np.abs(w)
    assert np.abs(mf - loss).max() <= AGREE_TOL * np.abs(loss).max()


def test_the_machines_acceleration_with_friction_is_the_closed_forms():
    """ε of the machine's equation J·ε = free − s·M_f(φ, ω, ε) solved jointly with the pairs'
    friction over the table, against the secant iteration on the closed form's kinetostatics."""
    asm = assemble(load(MODELS / "machine_friction.toml"))
    phi, w, _ = _states(40, 11)
    w[:3] = [2e-4, -5e-4, 1e-2]  # inside the regularisation near rest
    rng = np.random.default_rng(12)
    free, inertia = rng.uniform(-60.0, 60.0, phi.size), rng.uniform(0.06, 0.2, phi.size)
    fast, mf_fast = acceleration(PairFriction(asm), phi, w, free, inertia)
    slow, mf_slow = acceleration(PairFriction(asm, exact=True), phi, w, free, inertia)
    assert np.abs(fast - slow).max() <= AGREE_TOL * np.abs(slow).max()
    assert np.abs(mf_fast - mf_slow).max() <= AGREE_TOL * np.abs(mf_slow).max()
    one = [acceleration(PairFriction(asm), phi[i:i + 1], w[i:i + 1], free[i:i + 1], inertia[i:i + 1])[0][0]
           for i in range(phi.size)]
    assert np.abs(np.array(one) - fast).max() <= SAME_TOL * np.abs(fast).max()
    assert np.all(scale(w[:2]) < 1)


def test_a_run_with_friction_builds_no_kinetostatics_per_state(monkeypatch):
    """The machine's right-hand side used to call the kinetostatics (a fixed point over every group,
    ~3–8 ms) two or three times per state; now the table answers and the closed form is not called
    along the run (the energy balance still holds)."""
    asm, machine = load_machine(MODELS / "machine_friction.toml")
    red = reduce(asm)
    build(asm)
    calls = []
    real = kinetostatics.forces
    monkeypatch.setattr(kinetostatics, "forces", lambda *a, **k: calls.append(1) or real(*a, **k))
    run = run_machine(replace(machine, duration=0.02), red, samples=11)
    assert not calls
    assert run.energy.ok


def test_validate_compares_a_machine_with_friction_over_its_step_budget(monkeypatch):
    """The window is the budget's steps (not validate's 1 s), said in the result and the CLI line;
    the comparison stays within the machines' tolerance."""
    from linkgen.cli.mujoco import _summary
    from linkgen.crosscheck import machine as cm

    monkeypatch.setattr(cm, "FRICTION_STEPS", 1500)
    asm, machine = load_machine(MODELS / "machine_friction.toml")
    out, mj, _ = cm.compare_machine_run(asm, machine)
    assert out["ok"], out
    window = out["window"]
    assert window["step_budget"] == 1500 and mj.steps <= 1500
    assert out["duration_s"] == pytest.approx(1500 * window["timestep"], rel=0.01)
    line = _summary({"model": "m", "line": "ok", "dynamics": out})
    assert "first 1500 MuJoCo steps" in line and "friction in the pairs" in line

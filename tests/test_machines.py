"""Machines beyond the first second: loads that jump (a press's stroke force) kept exact on both
sides, the mechanism's own [[force]]/[[torque]] in MuJoCo's machine, the comparison over the
start-up and steady cycles, and the textbook's motor start-up (dvig_0) reproduced by its own
first-order scheme converging onto the closed form."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from linkgen.machine.machine import run_machine
from linkgen.machine.reduced import reduce
from linkgen.machine.study import load_machine
from linkgen.crosscheck.machine import MACHINE_TOL, compare_machine_run
from linkgen.machine.tables import PeriodicTable, jump_grid, switch_angles
from linkgen.families.planar.kinematics import solve

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"


def test_a_table_keeps_its_jump_and_integrates_exactly():
    grid, where = jump_grid(0.0, 64, [1.0, 4.0])
    values = np.where((where >= 1.0) & (where <= 4.0), 2.0, 0.0) + np.sin(where)
    t = PeriodicTable(grid, values)
    assert t.at(1.0 - 1e-9) == pytest.approx(math.sin(1.0), abs=1e-3)
    assert t.at(1.0) == pytest.approx(2.0 + math.sin(1.0), abs=1e-3)
    # the mean over a step across the switch counts the part past it: 0.3 of the step
    a, b = 0.93, 1.03
    exact = (2.0 * 0.03 + (math.cos(a) - math.cos(b))) / (b - a)
    assert t.mean(a, b) == pytest.approx(exact, abs=1.3e-3)  # the sine between chords: (2π/64)²/8
    # over whole turns, the integral of the step is its width times its height (sin integrates to 0)
    assert t.integral(2 * math.pi) == pytest.approx(2.0 * 3.0, abs=1e-2)
    assert t.integral(3 * 2 * math.pi) == pytest.approx(3 * t.integral(2 * math.pi), rel=1e-12)


def test_switch_angles_wrap_into_the_turn():
    from linkgen.pipeline.registry import load

    mech = load(MODELS / "machine_press.toml")
    assert switch_angles(mech, 0.0) == pytest.approx([math.radians(100), math.radians(170)])
    assert switch_angles(mech, math.radians(150)) == pytest.approx([math.radians(170), math.radians(460)])


def test_the_reduced_moment_jumps_by_the_force_times_its_transfer_function():
    """At a switch angle s, M(φ) steps by F·dx_B/dφ (virtual work of the force alone) — from the
    kinematics, not from the kinetostatics that builds M."""
    asm, machine = load_machine(MODELS / "machine_press.toml")
    red = reduce(asm, machine.process_load)
    (force,) = asm.mechanism.forces
    for s in (math.radians(100), math.radians(170)):
        d1 = solve(asm, [s]).points["B"].d1[0]
        step = float(np.dot(force.force, d1))
        inside = red.moment(s + 1e-7) - red.moment(s - 1e-7)
        assert (inside if s == math.radians(100) else -inside) == pytest.approx(step, rel=1e-5, abs=1e-6)


def test_press_machine_with_its_own_loads_in_mujoco():
    """From rest, the stroke force switches on and off within 0.5 s; MuJoCo's full linkage, the
    motor's torque law applied each step, stays within the tolerance of the ODE."""
    from dataclasses import replace

    asm, machine = load_machine(MODELS / "machine_press.toml")
    machine = replace(machine, duration=0.5)
    out, mj, run = compare_machine_run(asm, machine)
    assert mj.phi[-1] - mj.phi[0] > math.radians(170)  # both switches crossed
    assert out["ok"], out
    assert out["errors_relative"]["omega"] <= MACHINE_TOL and out["errors_relative"]["motor_torque"] <= MACHINE_TOL


def test_dynamics_cli_compares_start_up_and_steady_cycles():
    script = Path(sys.executable).parent / "linkgen"
    p = subprocess.run([str(script), "dynamics", MODELS / "motor_startup.toml", "--mujoco", "--cycles", "2", "--json"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    m = json.loads(p.stdout)["mujoco"]
    e = m["errors_relative"]
    assert m["cycles"] == 2 and m["duration_s"] > m["steady_from_s"]
    assert max(e["omega_startup"], e["omega_steady"], e["motor_torque"]) <= MACHINE_TOL and m["ok"]


def _textbook_dvig_0(dt: float, t_end: float = 5.0, J: float = 30.0, kw: float = 6.0, km: float = 2000.0):
    """The textbook's program dvig_0 with its classes D, Dvig and M (bsc_dinam), step by step:
    the current by explicit Euler with the inductive drop of the previous step, the rotor by the
    half-step position update. Returns t, ω, M."""
    Uo, Lpr, Rpr, Ke, Tg = 1.0, 0.01, 0.01, 1.0, 0.05
    x = y = 0.0  # current and its rate
    pos = vel = 0.0
    t, ts, ws, fs = 0.0, [], [], []
    while t < t_end:
        w = vel / kw  # Dvig.F
        f = x * km
        acc = f / J  # M.step
        pos += 0.5 * dt * vel
        vel += dt * acc
        pos += 0.5 * dt * vel
        upr = Uo - x * Rpr - y * Lpr  # D.step
        y = ((upr - Ke * w) - x) / Tg
        x += y * dt
        ts.append(t)
        ws.append(vel)
        fs.append(f)
        t += dt
    return np.array(ts), np.array(ws), np.array(fs)


def test_the_textbook_start_up_converges_onto_the_closed_form():
    asm, machine = load_machine(MODELS / "dc_motor_startup.toml")
    run = run_machine(machine, reduce(asm), samples=20001, duration=5.0)
    errors = []
    for dt in (5e-4, 2.5e-4, 1.25e-4):  # the textbook's dt = 0.0005 s, then halved
        t, w, _ = _textbook_dvig_0(dt)
        errors.append(np.abs(w - run.state_at(t)[1]).max() / 6.0)
    # first order: each halving halves the error (measured 3.95e-3, 1.97e-3, 9.85e-4)
    assert errors[0] < 5e-3
    for big, small in zip(errors, errors[1:]):
        assert big / small == pytest.approx(2.0, rel=0.05)
    # its peak torque and speed tend to the closed form's (1202.4 N·m, an overshoot to 6.506 rad/s)
    t, w, f = _textbook_dvig_0(1.25e-4)
    assert f.max() == pytest.approx(run.motor_torque.max(), rel=2e-3)
    assert w.max() == pytest.approx(run.omega.max(), rel=5e-4)


def test_the_machine_file_runs_on_mujocos_own_motor_elements(tmp_path):
    """The --mjcf file: MuJoCo's dcmotor for a DC motor (one motor constant for torque and
    back-EMF, the motor's k_t ≠ k_e carried by the gear and the voltage and current scales), an
    affine general actuator for a linear motor. The linear one holds 1e-6; the dcmotor's error is
    first order in the timestep (halving the step halves it)."""
    import mujoco

    from linkgen.mujoco.machine_mjcf import START_KEY, machine_mjcf, run_native

    for name in ("dc_motor_startup", "motor_startup"):
        asm, machine = load_machine(MODELS / f"{name}.toml")
        model = mujoco.MjModel.from_xml_string(machine_mjcf(asm, machine))
        assert model.key(START_KEY).qpos.shape == (model.nq,)
        kind = model.actuator("machine:motor").dyntype
        assert (kind == mujoco.mjtDyn.mjDYN_DCMOTOR) == (name == "dc_motor_startup")
        run = run_machine(machine, reduce(asm), samples=61, duration=0.3)
        peak = np.abs(run.omega).max()
        if name == "motor_startup":
            mj = run_native(asm, machine, run.t)
            assert np.abs(mj.omega - run.solution(mj.t)[1]).max() <= MACHINE_TOL * peak
            continue
        errors = []
        for dt in (6e-5, 3e-5):
            mj = run_native(asm, machine, run.t, timestep=dt)
            errors.append(np.abs(mj.omega - run.solution(mj.t)[1]).max() / peak)
        assert errors[0] / errors[1] == pytest.approx(2.0, rel=0.05)  # first order (measured 2.00)
        assert errors[0] < 5e-4  # measured 2.4e-4
        # and its motor torque is the circuit's k_t·i: at the end of the start-up window within the same order
        torque = np.interp(mj.t, run.t, run.motor_torque)
        assert np.abs(mj.motor_torque - torque).max() <= 10 * errors[1] * np.abs(run.motor_torque).max()

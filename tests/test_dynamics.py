"""Machine dynamics: the one-mass machine against exact solutions, the flywheel sizing against
the exact energy relation and against integration, the energy balance over a steady cycle, and
the closed form against MuJoCo's full linkage."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from linkgen.machine import motors
from linkgen.machine.machine import RTOL, run_machine
from linkgen.machine.reduced import reduce
from linkgen.machine.study import cycle_forces, flywheel_study, load_machine
from linkgen.errors import DescriptionError
from linkgen.model.machine import Motor
from linkgen.mujoco.machine import run_machine_mujoco
from linkgen.families.planar.kinetostatics import forces

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
# MuJoCo's full linkage against the one- and two-mass ODE: 1e-6 of the peak speed (measured
# 2.7e-9 on the start-up, 1.4e-7 on the flywheel case, 7e-9 with the DC motor on the slider-crank,
# 3e-8 with the elastic shaft, over their first second).
MUJOCO_TOL = 1e-6
# The ODE against an exact solution: a hundred times its relative tolerance.
EXACT_TOL = 100 * RTOL
# The flywheel case's process load is a table every 5° through a periodic cubic spline: its
# energy swing is within ~3e-7 of the exact 100 J (interpolation error ~ h⁴), so 1e-5.
TABLE_TOL = 1e-5


def test_start_up_follows_the_exponential():
    asm, machine = load_machine(MODELS / "motor_startup.toml")
    run = run_machine(machine, reduce(asm), samples=1001)
    tau = 30.0 * 6.0 / 2000.0  # J·ω0/M0
    exact = 6.0 * (1.0 - np.exp(-run.t / tau))
    assert np.abs(run.omega - exact).max() <= EXACT_TOL * 6.0
    assert np.abs(run.phi - 6.0 * (run.t - tau * (1.0 - np.exp(-run.t / tau)))).max() <= EXACT_TOL * 6.0 * run.t[-1]
    assert run.steady is not None and run.steady.delta < 1e-6
    assert run.steady.omega_mean == pytest.approx(6.0, rel=1e-7)
    # within 1 % of ω0 from t = τ·ln 100 on; the samples are 5 ms apart
    assert abs(run.startup_time - tau * math.log(100.0)) <= run.t[1] - run.t[0]


def test_flywheel_against_the_exact_energy_relation_and_against_integration():
    asm, machine = load_machine(MODELS / "flywheel_sine.toml")
    fw, delta_run = flywheel_study(asm, machine, 0.02, 10.0)
    # constant J: ½·J·(ω_max² − ω_min²) = ΔE_max = ∫₀^π 50·sin φ dφ = 100 J, ω_max + ω_min = 2·ω_m
    exact = 100.0 / (0.02 * 10.0**2) - 0.1
    assert fw.energy_swing == pytest.approx(100.0, rel=TABLE_TOL)
    assert fw.inertia == pytest.approx(exact, rel=TABLE_TOL)
    assert fw.driving_torque == pytest.approx(100.0, rel=1e-9)
    assert delta_run == pytest.approx(0.02, rel=1e-6)


@pytest.fixture(scope="module")
def slider_crank_run():
    """The bundled slider-crank machine from rest to its steady cycle (~6 s of ODE), run once for
    the tests that read it."""
    asm, machine = load_machine(MODELS / "machine_slider_crank.toml")
    red = reduce(asm, machine.process_load)
    return asm, machine, red, run_machine(machine, red, samples=50)


def test_energy_balance_over_a_steady_cycle(slider_crank_run):
    """Over one steady turn the kinetic energy returns: ∫ (drive + loads)·ω dt = 0, the drive
    being u·η·M_motor and the loads the reduced moment M(φ) (a route through the work, not
    through the equation of motion)."""
    asm, machine, red, run = slider_crank_run
    s = run.steady
    assert s is not None and 0.05 < s.delta < 0.5
    t = np.linspace(s.t_start, s.t_start + s.period, 200001)
    y = run.solution(t)
    drive = machine.gear_ratio * machine.gear_efficiency * motors.torque(machine.motor, machine.gear_ratio * y[1], y[2])
    power = (drive + red.moment(y[0])) * y[1]
    work_in = np.trapezoid(np.abs(drive * y[1]), t)
    assert abs(np.trapezoid(power, t)) <= 1e-6 * work_in


def test_two_mass_energy_balance_with_the_shaft():
    """With the elastic shaft: the motor's work plus the loads' equals the change of kinetic
    energy (rotor and crank side) plus the spring's energy plus the damper's loss."""
    asm, machine = load_machine(MODELS / "machine_elastic_shaft.toml")
    red = reduce(asm, machine.process_load)
    run = run_machine(machine, red, samples=50, duration=1.0)
    t = np.linspace(0.0, 1.0, 400001)
    y = run.solution(t)  # φ, ω, θ, ω_r, i
    u, s = machine.gear_ratio, machine.shaft
    drive = u * machine.gear_efficiency * motors.torque(machine.motor, u * y[3], y[4])
    jr = machine.rotor_inertia * u**2
    ke = 0.5 * jr * y[3] ** 2 + 0.5 * (red.j(y[0]) + machine.flywheel_inertia) * y[1] ** 2
    pe = 0.5 * s.stiffness * (y[2] - y[0]) ** 2
    work = np.trapezoid(drive * y[3] + red.moment(y[0]) * y[1] - s.damping * (y[3] - y[1]) ** 2, t)
    assert work == pytest.approx((ke[-1] + pe[-1]) - (ke[0] + pe[0]), rel=1e-6)


def test_the_splines_reproduce_the_closed_form_between_grid_points():
    asm, machine = load_machine(MODELS / "machine_slider_crank.toml")
    red = reduce(asm, machine.process_load)
    mid = 0.5 * (red.phi[1:] + red.phi[:-1])
    f = forces(asm, mid, 0.0, 0.0)
    peak = np.abs(f.reduced.inertia).max()
    assert np.abs(red.j(mid) - f.reduced.inertia).max() <= 1e-8 * peak
    assert np.abs(red.dj(mid) - f.reduced.inertia_derivative).max() <= 1e-6 * np.abs(f.reduced.inertia_derivative).max()


def test_forces_along_the_real_motion_use_the_ode_acceleration(slider_crank_run):
    asm, machine, _, run = slider_crank_run
    cf = cycle_forces(asm, run, samples=2000)
    assert cf is not None and set(cf.peak_reactions) == {"O", "A", "B"}
    # the balancing torque the mechanism needs along the motion is what the drive and the process
    # load give it, less the rotor's inertia torque: u·η·M − J_rotor·u²·ε − M_process
    s = run.steady
    t = np.array([s.t_start + 0.3 * s.period])
    y = run.solution(t)
    h = 1e-5  # s: central difference of the dense output
    eps = (run.solution(t + h)[1] - run.solution(t - h)[1]) / (2 * h)
    f = forces(asm, y[0], y[1], eps)
    drive = motors.torque(machine.motor, y[1], y[2])
    from linkgen.machine.reduced import process_torque

    expect = drive - 250.0 * eps - process_torque(machine.process_load, y[0])
    assert f.balancing_torque[0] == pytest.approx(expect[0], rel=1e-6)


@pytest.mark.parametrize("model,duration", [("motor_startup", 2.0), ("flywheel_sine", 2.0),
                                            ("machine_slider_crank", 0.4), ("machine_elastic_shaft", 0.4)])
def test_mujoco_runs_the_same_machine(model, duration):
    asm, machine = load_machine(MODELS / f"{model}.toml")
    run = run_machine(machine, reduce(asm, machine.process_load), samples=201, duration=duration)
    mj = run_machine_mujoco(asm, machine, run.t)
    phi, w = run.state_at(mj.t)
    assert np.abs(mj.omega - w).max() <= MUJOCO_TOL * np.abs(w).max()
    assert np.abs(mj.phi - phi).max() <= MUJOCO_TOL * max(abs(phi[-1] - phi[0]), 1.0)


def test_kloss_formula_meets_its_catalogue_points():
    m = Motor("induction", (("rated_power", 5500.0), ("synchronous_speed", 157.08), ("rated_slip", 0.04),
                            ("breakdown_ratio", 2.2)))
    m_rated = 5500.0 / (157.08 * 0.96)
    assert float(motors.torque(m, 157.08 * 0.96)) == pytest.approx(m_rated, rel=1e-12)
    mk, sk = motors.kloss_constants(m)
    s = np.linspace(1e-4, 1.0, 200001)
    tq = motors.torque(m, 157.08 * (1 - s))
    assert tq.max() == pytest.approx(2.2 * m_rated, rel=1e-8)
    assert s[np.argmax(tq)] == pytest.approx(sk, abs=1e-4)
    assert float(motors.torque(m, 157.08)) == 0.0


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True,
                          timeout=300)


def test_cli_dynamics_and_flywheel(tmp_path):
    p = _cli("dynamics", MODELS / "motor_startup.toml", "--csv", tmp_path / "m.csv", "--samples", "11")
    assert p.returncode == 0, p.stderr
    lines = (tmp_path / "m.csv").read_text().splitlines()
    assert lines[0].split(",")[:5] == ["t [s]", "phi [rad]", "omega [rad/s]", "epsilon [rad/s²]",
                                       "motor_torque [N·m]"] and len(lines) == 12
    # the summary is still printed, and the message counts time samples, not crank angles
    assert "steady cycle from" in p.stdout and "wrote 11 time samples" in p.stderr
    p = _cli("dynamics", MODELS / "motor_startup.toml", "--json")
    out = json.loads(p.stdout)
    assert set(out["steady"]) >= {"omega_mean", "omega_min", "omega_max", "delta", "period"}
    assert out["startup_time"] == pytest.approx(0.09 * math.log(100.0), abs=0.01)
    p = _cli("flywheel", MODELS / "flywheel_sine.toml", "--delta", "0.02", "--json")
    assert json.loads(p.stdout)["inertia_required"] == pytest.approx(49.9, rel=TABLE_TOL)
    p = _cli("dynamics", MODELS / "fourbar.toml")
    assert p.returncode == 2 and "machine" in p.stderr and "fourbar.toml" in p.stderr and "Traceback" not in p.stderr


def test_a_bad_machine_table_is_named_at_load(tmp_path):
    text = (MODELS / "motor_startup.toml").read_text().replace('kind = "linear"', 'kind = "steam"')
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    from linkgen import load

    with pytest.raises(DescriptionError) as info:
        load(bad)
    assert "machine.motor.kind" in str(info.value) and "steam" in str(info.value) and "bad.toml" in str(info.value)


def test_a_rotor_alone_validates_with_its_armature_in_effect():
    """A crank turning about its own centre of mass is a "simple" body: MuJoCo takes its whole
    inertia from dof_M0, so a rotor inertia set after compiling must reach it too (before, J(φ)
    read back 1e6× off and the zero reactions divided by zero)."""
    from linkgen.crosscheck.run import crosscheck

    asm, _ = load_machine(MODELS / "motor_startup.toml")
    cc = crosscheck(asm, practical=False)
    assert cc.ok, cc.to_json()["diagnosis"]
    q = cc.comparison.quantities["reduced_inertia"]
    assert q.relative_error < 1e-9 and q.peak == pytest.approx(30.0, rel=1e-12)


def test_an_induction_motor_runs_the_same_in_mujoco():
    """Kloss's law has no MuJoCo element: its torque is applied each step at the mid-step speed."""
    from dataclasses import replace

    asm, machine = load_machine(MODELS / "machine_slider_crank.toml")
    kloss = Motor("induction", (("rated_power", 15000.0), ("synchronous_speed", 104.72), ("rated_slip", 0.05),
                                ("breakdown_ratio", 2.5)))
    machine = replace(machine, motor=kloss, gear_ratio=10.0, gear_efficiency=0.95)
    run = run_machine(machine, reduce(asm, machine.process_load), samples=101, duration=0.3)
    mj = run_machine_mujoco(asm, machine, run.t)
    phi, w = run.state_at(mj.t)
    assert np.abs(mj.omega - w).max() <= MUJOCO_TOL * np.abs(w).max()


def test_validate_includes_the_machine(capsys):
    from linkgen.cli.main import main

    assert main(["validate", str(MODELS / "motor_startup.toml"), "--json", "--no-practical"]) == 0
    out = json.loads(capsys.readouterr().out)
    dyn = out["dynamics"]
    assert dyn["ok"] and dyn["omega_error_relative"] <= MUJOCO_TOL and dyn["steps"] > 0 and out["ok"]
    assert main(["validate", str(ROOT / "models" / "fourbar.toml"), "--json", "--no-practical"]) == 0
    assert "dynamics" not in json.loads(capsys.readouterr().out)

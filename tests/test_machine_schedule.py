"""Motors switched on and off, run-down and braking (issue 26): ``[machine.schedule]`` and
``[machine.brake]`` in the machine's equation, its energy balance, MuJoCo and the errors.

The checks stand outside the machine code: a crank on a flywheel (J constant, no gravity) whose
speed, stopping time and braking angle follow by hand (ω_off = M·Δt/J; a constant brake T stops
it in ω·J/T over ω²·J/(2·T); a viscous one c slows it as ω·e^(−c·t/J)); a crank lifting a point
mass against gravity, integrated here by scipy's solve_ivp from the equation written out below,
its phases and events coded here; MuJoCo's full linkage."""

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from linkgen.cli.main import main
from linkgen.machine.machine import RTOL, run_machine
from linkgen.machine.reduced import reduce
from linkgen.machine.study import load_machine

MODELS = Path(__file__).resolve().parents[1] / "models"
G = 9.81  # m/s²
# The ODE against an exact solution: a hundred times its relative tolerance (as test_dynamics.py).
EXACT_TOL = 100 * RTOL
# Against the direct integration here (rtol 1e-12): what the published multibody benchmarks ask
# of a closed-form route (1e-8 relative, as REPRODUCE_TOL in test_machine_state.py).
DIRECT_TOL = 1e-8
# MuJoCo's machine against the ODE: validate's own bound (crosscheck.machine.MACHINE_TOL).
MUJOCO_TOL = 1e-6

CRANK = """
[mechanism]
name = "braked_crank"
gravity = [0.0, {g}]
[points]
O = [0.0, 0.0]
A = [0.5, 0.0]
[links.ground]
points = ["O"]
[links.crank]
points = ["O", "A"]
[links.crank.inertial]
mass = {mass}
com = [{com}, 0.0]
inertia = {inertia}
[drive]
joint = "O"
omega = 2.0
[machine]
flywheel_inertia = {flywheel}
start_angle = "{start}"
duration = {duration}
[machine.motor]
{motor}
[machine.schedule]
{schedule}
[machine.brake]
{brake}
"""


def _crank(tmp_path, name="crank.toml", g=0.0, mass=1.0, com=0.0, inertia=2.0, flywheel=0.5, start="0deg",
           duration=6.0, motor='kind = "constant"\ntorque = 8.0', schedule='motor_on = "0.3137s"\nmotor_off = "1.3137s"',
           brake='kind = "constant"\ntorque = 4.0\nfrom_time = "2.1s"'):
    path = tmp_path / name
    path.write_text(CRANK.format(g=g, mass=mass, com=com, inertia=inertia, flywheel=flywheel, start=start,
                                 duration=duration, motor=motor, schedule=schedule, brake=brake))
    return path


def test_a_constant_brake_stops_the_flywheel_in_the_hand_time_and_angle(tmp_path):
    """J = 2 + 0.5 kg·m², 8 N·m from 0.3137 s to 1.3137 s: ω_off = 8·1/2.5 = 3.2 rad/s; coasting
    to 2.1 s, then 4 N·m: at rest after ω·J/T = 2 s, over ω²·J/(2T) = 3.2 rad."""
    asm, machine = load_machine(_crank(tmp_path))
    run = run_machine(machine, reduce(asm), samples=401)
    j, w_off = 2.5, 8.0 * 1.0 / 2.5
    s = run.stopping
    assert s.held and run.t[-1] == pytest.approx(2.1 + w_off * j / 4.0, rel=EXACT_TOL)
    assert s.rest_at == pytest.approx(2.1 + w_off * j / 4.0, rel=EXACT_TOL)
    assert s.run_down_time == pytest.approx(2.1 + w_off * j / 4.0 - 1.3137, rel=EXACT_TOL)
    assert s.braking_angle == pytest.approx(w_off**2 * j / 8.0, rel=EXACT_TOL)
    assert s.braking_time == pytest.approx(w_off * j / 4.0, rel=EXACT_TOL)
    # before the motor is on the crank rests; the motor's torque is 0 outside its schedule
    before, on = run.t < 0.3137, (run.t >= 0.3137) & (run.t < 1.3137)
    assert np.all(run.omega[before] == 0.0) and np.all(run.motor_torque[~on] == 0.0)
    assert np.all(run.motor_torque[on] == 8.0)
    # the angle at the brake: ½·ω_off·1 s of the motor, then ω_off over the 0.7863 s of coasting
    assert s.brake_angle == pytest.approx(0.5 * w_off + w_off * (2.1 - 1.3137), rel=EXACT_TOL)


def test_a_viscous_brake_slows_the_flywheel_exponentially_and_never_stops_it(tmp_path):
    """c = 1.5 N·m·s/rad on J = 2.5 kg·m² from 2.1 s: ω = ω_b·e^(−c·(t − t_b)/J), the angle
    swept ω_b·J/c·(1 − e^(−c·(t − t_b)/J)); ω never reaches 0, so no rest and no braking angle."""
    path = _crank(tmp_path, brake='kind = "viscous"\ncoefficient = 1.5\nfrom_time = "2.1s"')
    asm, machine = load_machine(path)
    run = run_machine(machine, reduce(asm), samples=601)
    j, c, w_b = 2.5, 1.5, 3.2
    after = run.t >= 2.1
    tau = run.t[after] - 2.1
    np.testing.assert_allclose(run.omega[after], w_b * np.exp(-c * tau / j), rtol=EXACT_TOL, atol=EXACT_TOL * w_b)
    s = run.stopping
    swept = run.phi[after] - s.brake_angle
    np.testing.assert_allclose(swept, w_b * j / c * (1 - np.exp(-c * tau / j)), rtol=EXACT_TOL, atol=EXACT_TOL)
    assert s.rest_at is None and s.braking_angle is None and not s.held and run.t[-1] == 6.0
    # the viscous brake's work −∫c·ω² dt = −½·J·ω_b²·(1 − e^(−2c·Δt/J))
    assert run.energy.brake[-1] == pytest.approx(-0.5 * j * w_b**2 * (1 - math.exp(-2 * c * 3.9 / j)), rel=EXACT_TOL)


def test_a_motor_switched_off_without_a_brake_coasts_and_the_flywheel_is_sized_running(tmp_path, capsys):
    """No brake, no loads: after motor_off the flywheel coasts at ω_off = 3.2 rad/s for good (no
    rest, no run-down time; before: a TypeError on the solver's missing events), and ``flywheel``
    sizes models/machine_brake.toml's flywheel for steady running, without its schedule and brake
    (before: the same TypeError)."""
    text = _crank(tmp_path).read_text()
    path = tmp_path / "coasting.toml"
    path.write_text(text[:text.index("[machine.brake]")])
    asm, machine = load_machine(path)
    run = run_machine(machine, reduce(asm), samples=101)
    after = run.t >= 1.3137
    np.testing.assert_allclose(run.omega[after], 3.2, rtol=EXACT_TOL)
    s = run.stopping
    assert s.rest_at is None and s.run_down_time is None and s.brake_at is None and run.t[-1] == 6.0
    assert main(["flywheel", str(MODELS / "machine_brake.toml"), "--delta", "0.05", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["delta_integrated"] == pytest.approx(0.05, rel=1e-3)


# The lifted point mass: m = 1 kg at r = 0.5 m, its own inertia 0.01 kg·m², a 0.1 kg·m² flywheel;
# a linear motor (10 N·m stall, 20 rad/s no load) on from 0.05 s to 1.2 s, started at the lowest
# position (−90°, at rest: in equilibrium until the motor starts); a constant 3 N·m brake from the
# crank angle 12 rad.
M, R, I_C, J_F = 1.0, 0.5, 0.01, 0.1
M0, W0, ON, OFF, T_B, PHI_B = 10.0, 20.0, 0.05, 1.2, 3.0, 12.0


def _lifted(tmp_path):
    return _crank(tmp_path, "lifted.toml", g=-G, mass=M, com=R, inertia=I_C, flywheel=J_F, start="-90deg",
                  duration=5.0, motor=f'kind = "linear"\nstall_torque = {M0}\nno_load_speed = {W0}',
                  schedule=f'motor_on = "{ON}s"\nmotor_off = "{OFF}s"',
                  brake=f'kind = "constant"\ntorque = {T_B}\nfrom_angle = {PHI_B}')


def _direct(t_samples):
    """The lifted crank integrated here: J·ω̇ = −m·g·r·cos φ + k(t)·M0·(1 − ω/ω0) − T·[braking],
    J = m·r² + I_c + J_f, in phases (before the motor, with it, coasting, braked) with events on
    the brake's angle and the rest. Returns φ, ω at the samples and (t_brake, t_rest, φ_rest)."""
    j = M * R * R + I_C + J_F

    def rhs(motor, brake):
        return lambda t, y: [y[1], (-M * G * R * math.cos(y[0]) + motor * M0 * (1 - y[1] / W0) - brake) / j]

    reach = lambda t, y: y[0] - PHI_B  # noqa: E731
    reach.terminal = True
    rest = lambda t, y: y[1]  # noqa: E731
    rest.terminal = True
    pieces, y, t0 = [], [-math.pi / 2, 0.0], 0.0
    t_brake = t_rest = None
    for t1, motor in ((ON, 0.0), (OFF, 1.0), (10.0, 0.0)):
        sol = solve_ivp(rhs(motor, 0.0), (t0, t1), y, rtol=1e-12, atol=1e-14, dense_output=True, events=reach,
                        method="DOP853")
        pieces.append(sol)
        t0, y = sol.t[-1], sol.y[:, -1]
        if sol.status == 1:
            t_brake = t0
            break
    assert t_brake is not None and t_brake > OFF  # the brake comes on while the crank coasts
    sol = solve_ivp(rhs(0.0, T_B), (t0, 10.0), y, rtol=1e-12, atol=1e-14, dense_output=True, events=rest,
                    method="DOP853")
    pieces.append(sol)
    t_rest = sol.t[-1]
    ends = [p.t[-1] for p in pieces]
    out = np.empty((2, len(t_samples)))
    for i, t in enumerate(t_samples):
        k = min(int(np.searchsorted(ends, t)), len(pieces) - 1)
        out[:, i] = pieces[k].sol(t)
    return out[0], out[1], (t_brake, t_rest, float(sol.y[0, -1]))


def test_the_lifted_crank_follows_the_direct_integration(tmp_path):
    asm, machine = load_machine(_lifted(tmp_path))
    run = run_machine(machine, reduce(asm), samples=801)
    phi, w, (t_brake, t_rest, phi_rest) = _direct(run.t)
    s = run.stopping
    assert s.brake_at == pytest.approx(t_brake, rel=DIRECT_TOL) and s.brake_angle == pytest.approx(PHI_B, rel=DIRECT_TOL)
    assert s.rest_at == pytest.approx(t_rest, rel=DIRECT_TOL) and s.held
    assert s.run_down_time == pytest.approx(t_rest - OFF, rel=DIRECT_TOL)
    assert s.braking_angle == pytest.approx(phi_rest - PHI_B, rel=DIRECT_TOL)
    assert np.abs(run.phi - phi).max() <= DIRECT_TOL * np.abs(phi).max()
    assert np.abs(run.omega - w).max() <= DIRECT_TOL * np.abs(w).max()
    assert run.energy.ok


def test_the_lifted_crank_in_mujoco_agrees(tmp_path):
    """MuJoCo's full linkage with the motor's share of each step and the brake from the angle its
    own sweep reaches: within validate's tolerance of the ODE over the whole run, to the rest."""
    from linkgen.crosscheck.machine import compare_machine_run

    asm, machine = load_machine(_lifted(tmp_path))
    out, mj, run = compare_machine_run(asm, machine)
    assert out["ok"], out
    assert out["duration_s"] == pytest.approx(run.stopping.rest_at, rel=1e-12)
    assert out["errors_relative"]["omega"] <= MUJOCO_TOL and out["phi_error_rad"] <= MUJOCO_TOL * PHI_B
    assert out["stopping"]["held_by_brake"]


def test_the_brake_model_validates_and_its_balance_counts_the_brakes_work(capsys):
    """models/machine_brake.toml through ``linkgen validate``; its energy balance holds with the
    brake's work, which for a constant brake is −T·(the braking angle), and fails without it."""
    from linkgen.machine.energy import energy_balance
    from linkgen.machine.equation import Model

    assert main(["validate", str(MODELS / "machine_brake.toml"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    out = out[0] if isinstance(out, list) else out
    assert out["ok"] and out["dynamics"]["ok"] and out["dynamics"]["stopping"]["held_by_brake"]
    asm, machine = load_machine(MODELS / "machine_brake.toml")
    red = reduce(asm)
    run = run_machine(machine, red, samples=501)
    s, e = run.stopping, run.energy
    assert e.ok and e.brake[-1] == pytest.approx(-machine.brake.value * s.braking_angle, rel=1e-9)
    off = run.t >= s.motor_off
    assert np.all(e.drive[off] == e.drive[off][0])  # no drive work once the motor is off
    model = Model(machine, red)
    model.switching = replace(model.switching, brake_kind=None)  # the same run judged without the brake
    wrong = energy_balance(model, run.solution, run.t, run.t)
    assert not wrong.ok


@pytest.mark.parametrize("old,new,field,value,allowed", [
    ('motor_off = "1.3137s"', 'motor_off = "0.2s"', "machine.schedule.motor_off", "'0.2s'", "after motor_on (0.3137 s)"),
    ('motor_on = "0.3137s"', 'motor_on = "-1s"', "machine.schedule.motor_on", "'-1s'", "0 to machine.duration = 6 s"),
    ('motor_on = "0.3137s"', 'motor_on = "soon"', "machine.schedule.motor_on", "'soon'", "'0.2s', '200ms'"),
    ("torque = 4.0", "torque = -4.0", "machine.brake.torque", "-4.0", "must be > 0 N·m"),
    ('kind = "constant"\ntorque = 4.0', 'kind = "disc"\ntorque = 4.0', "machine.brake.kind", "'disc'",
     "['constant', 'viscous']"),
    ('from_time = "2.1s"', 'from_angle = "1deg"\nfrom_time = "2.1s"', "machine.brake", "both",
     "exactly one of from_time"),
    ("torque = 4.0", "coefficient = 4.0", "machine.brake.coefficient", "coefficient", "allowed keys"),
])
def test_a_bad_schedule_or_brake_names_the_file_field_value_and_what_is_allowed(tmp_path, capsys, old, new, field,
                                                                               value, allowed):
    path = _crank(tmp_path)
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))
    assert main(["dynamics", str(path)]) != 0
    err = capsys.readouterr().err
    assert f"{path}: {field}" in err and value in err and allowed in err and "Traceback" not in err


def test_dynamics_reports_the_run_down_time_and_the_braking_angle(tmp_path, capsys):
    assert main(["dynamics", str(_crank(tmp_path)), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["run_down_time"] == pytest.approx(2.1 + 2.0 - 1.3137, rel=EXACT_TOL)
    assert out["braking_angle"] == pytest.approx(3.2, rel=EXACT_TOL)
    assert out["units"]["run_down_time"] == "s" and out["units"]["braking_angle"] == "rad"
    assert main(["dynamics", str(_crank(tmp_path))]) == 0
    text = capsys.readouterr().out
    assert "run-down time (motor off → rest) 2.7863 s" in text and "the brake holds the crank" in text


# models/machine_brake.toml written out: the four-bar's bars (10 kg/m, uniform), O at the origin,
# C = (1, 0), B above the line OC; a 0.5 kg·m² flywheel; 60·(1 − ω/12) N·m from 0.1 s to 1 s;
# a constant 40 N·m brake from 1.2 s.
BARS = {"crank": 0.3, "coupler": 1.0, "rocker": 0.7}
DENSITY, FLYWHEEL, C_X = 10.0, 0.5, 1.0


def _fourbar_pose(phi):
    """Centres of mass (3, 2, n) and angles (3, n) of crank, coupler and rocker at crank angles phi
    (the circle intersection of the coupler about A and the rocker about C, B on the upper branch)."""
    a = 0.3 * np.array([np.cos(phi), np.sin(phi)])
    c = np.array([[C_X], [0.0]]) * np.ones_like(phi)
    d_vec = c - a
    d = np.hypot(*d_vec)
    along = (1.0**2 - 0.7**2 + d * d) / (2 * d)
    h = np.sqrt(1.0**2 - along**2)
    b = a + along * d_vec / d + h * np.array([-d_vec[1], d_vec[0]]) / d
    centres = np.array([0.5 * a, 0.5 * (a + b), 0.5 * (c + b)])
    angles = np.array([phi, np.arctan2(*(b - a)[::-1]), np.arctan2(*(b - c)[::-1])])
    return centres, angles


# The fourth-order central difference: df/dφ ≈ Σ w·f(φ + k·h)/h (error ~h⁴/30·f⁽⁵⁾, rounding ~1e-16/h).
H = 1e-3
STENCIL = H * np.arange(-2.0, 3.0)
WEIGHTS = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / 12


def _d(f, phi):
    """df/dφ at angles phi (n,) by the fourth-order central difference."""
    return np.tensordot(WEIGHTS, np.array([f(phi + k) for k in STENCIL]), axes=1) / H


MASSES = np.array([DENSITY * L for L in BARS.values()])
INERTIAS = MASSES * np.array(list(BARS.values())) ** 2 / 12  # uniform bars about their centres


def _inertia(phi):
    """J(φ) [kg·m²] of the bars and the flywheel at angles phi (n,)."""
    dc = _d(lambda p: _fourbar_pose(p)[0], phi)
    da = _d(lambda p: _fourbar_pose(p)[1], phi)
    return (MASSES[:, None] * (dc**2).sum(axis=1) + INERTIAS[:, None] * da**2).sum(axis=0) + FLYWHEEL


def _potential(phi):
    """V(φ) [J] of the bars under gravity at angles phi (n,)."""
    return G * (MASSES[:, None] * _fourbar_pose(phi)[0][:, 1]).sum(axis=0)


def test_the_bundled_model_against_a_direct_integration_of_its_fourbar():
    """models/machine_brake.toml's rest, run-down time and braking angle against the four-bar's
    equation J·ω̇ + ½·J′·ω² = −V′ + k(t)·M_motor − T·[t ≥ 1.2 s] integrated here (solve_ivp),
    J, J′, V′ from the circle intersection and differences written above."""
    def rhs(motor, brake):
        def f(t, y):
            at = y[0] + STENCIL  # J and V at the five angles of the difference, in one call
            js, vs = _inertia(at), _potential(at)
            j, dj, dv = js[2], (WEIGHTS @ js) / H, (WEIGHTS @ vs) / H
            m = motor * 60.0 * (1 - y[1] / 12.0)
            return [y[1], (-dv + m - brake - 0.5 * dj * y[1] ** 2) / j]
        return f

    rest = lambda t, y: y[1]  # noqa: E731
    rest.terminal = True
    y, t0, pieces = [0.0, 0.0], 0.0, []
    for t1, motor, brake in ((0.1, 0.0, 0.0), (1.0, 1.0, 0.0), (1.2, 0.0, 0.0), (3.0, 0.0, 40.0)):
        sol = solve_ivp(rhs(motor, brake), (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-13,
                        events=rest if brake else None, dense_output=True)
        pieces.append(sol)
        t0, y = sol.t[-1], sol.y[:, -1]
    t_rest, phi_rest = t0, y[0]
    phi_brake = pieces[2].y[0, -1]
    asm, machine = load_machine(MODELS / "machine_brake.toml")
    run = run_machine(machine, reduce(asm), samples=201)
    s = run.stopping
    assert s.held and s.rest_at == pytest.approx(t_rest, rel=DIRECT_TOL)
    assert s.run_down_time == pytest.approx(t_rest - 1.0, rel=DIRECT_TOL)
    assert s.brake_angle == pytest.approx(phi_brake, rel=DIRECT_TOL)
    assert s.braking_angle == pytest.approx(phi_rest - phi_brake, rel=DIRECT_TOL)
    ends = [p.t[-1] for p in pieces]
    direct = np.array([pieces[min(int(np.searchsorted(ends, t)), 3)].sol(t) for t in run.t]).T
    assert np.abs(run.phi - direct[0]).max() <= DIRECT_TOL * np.abs(direct[0]).max()
    assert np.abs(run.omega - direct[1]).max() <= DIRECT_TOL * np.abs(direct[1]).max()


def test_the_friction_pieces_start_where_the_schedules_piece_starts():
    """A machine with friction switches integrates each of the schedule's pieces in parts between
    the switches; those parts start at the piece's own start time (before: at t = 0 again, so a
    piece after motor_off re-ran the machine from t = 0 with the later state, and the run ended
    at a friction switch of that re-run, reported as a rest under the brake)."""
    from linkgen.machine.machine import _across_switches

    class Switches:  # one switch, never reached by the uniform motion below
        switches = np.array([100.0])

        def neighbours(self, phi):
            return phi + 100.0, phi - 100.0

    starts = []

    def one(t0, y0, more=()):
        starts.append(t0)
        return solve_ivp(lambda t, y: [y[1], 0.0], (t0, 2.0), y0, events=list(more), dense_output=True)

    sol = _across_switches(one, np.array([0.0, 1.0]), 0, Switches(), 2.0, 1.5)
    assert starts == [1.5] and sol.t[0] == 1.5 and sol.t[-1] == 2.0
    assert sol.sol(np.array([2.0]))[0][0] == pytest.approx(0.5, rel=1e-12)


def test_a_run_down_without_a_brake_ends_at_the_first_rest(tmp_path):
    """The lifted crank with its motor off at 0.2 s and no brake: it swings on under gravity, comes
    to rest for an instant (the run-down's end: the first ω = 0 after motor_off) and swings back,
    the run going on. Against the direct integration with that rest as an event."""
    text = _lifted(tmp_path).read_text()
    path = tmp_path / "swing.toml"
    path.write_text(text[:text.index("[machine.brake]")].replace(f'motor_off = "{OFF}s"', 'motor_off = "0.2s"'))
    asm, machine = load_machine(path)
    run = run_machine(machine, reduce(asm), samples=201)
    j = M * R * R + I_C + J_F
    rate = lambda motor: lambda t, y: [y[1], (-M * G * R * math.cos(y[0]) + motor * M0 * (1 - y[1] / W0)) / j]  # noqa: E731
    rest = lambda t, y: y[1]  # noqa: E731
    rest.terminal = True
    y = [-math.pi / 2, 0.0]
    for t0, t1, motor in ((0.0, ON, 0.0), (ON, 0.2, 1.0)):
        y = solve_ivp(rate(motor), (t0, t1), y, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
    swing = solve_ivp(rate(0.0), (0.2, 5.0), y, method="DOP853", rtol=1e-12, atol=1e-14, events=rest)
    assert swing.status == 1  # it does come to rest before 5 s
    s = run.stopping
    assert s.run_down_time == pytest.approx(swing.t[-1] - 0.2, rel=DIRECT_TOL)
    assert not s.held and s.braking_angle is None and run.t[-1] == 5.0
    assert run.omega.min() < -1.0  # and swings back

"""Machine runs at their edges: inputs past float range, stiff motors, the steady cycle of a
table-driven load, ε along the cycle where a stroke force switches, the start-up and the peak
motor torque between samples, and a machine that never settles compared with MuJoCo."""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import minimize_scalar

from linkgen.machine.machine import RTOL, run_machine
from linkgen.machine.reduced import reduce
from linkgen.machine.study import flywheel_study, load_machine
from linkgen.errors import DescriptionError, LinkgenError, SimulationError
from linkgen.families.planar.kinetostatics import forces

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
DATA = ROOT / "tests" / "data"
# The ODE against an exact solution: a hundred times its relative tolerance.
EXACT_TOL = 100 * RTOL
# flywheel_sine's load is a table every 5° through a cubic spline: within ~3e-7 of 100 + 50·sin φ
# (tests/test_dynamics.py), so its speeds within 1e-5 of the exact energy relation.
TABLE_TOL = 1e-5
# A forward difference of the dense output over H_EPS [s] errs by H_EPS·|dε/dt|/2: the press's
# ε changes by some 1e3 rad/s³ away from a switch, 1e-3 of a 1 rad/s² ε at most.
H_EPS = 1e-6
EPS_TOL = 1e-4
# A time found by a root of the dense output: ω within EXACT_TOL·ω0 moves it by that over ω̇
# (0.67 rad/s² where motor_startup crosses its band), 1e-7 s.
TIME_TOL = 1e-6


def _variant(tmp_path, model: str, old: str, new: str, name: str = "variant.toml") -> Path:
    text = (MODELS / model).read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


def test_flywheel_at_a_tiny_speed_is_sized_in_scaled_form_or_refused():
    asm, machine = load_machine(MODELS / "flywheel_sine.toml")
    fw, _ = flywheel_study(asm, machine, 0.02, 1e-10)
    # constant J: ½·J·(ω_max² − ω_min²) = 100 J with ω_max − ω_min = δ·ω_m: J = 100/(δ·ω_m²)
    assert fw.inertia == pytest.approx(100.0 / (0.02 * 1e-20) - 0.1, rel=TABLE_TOL)
    with pytest.raises(SimulationError, match="beyond float64's range"):
        flywheel_study(asm, machine, 0.02, 1e-300)


def test_a_process_load_past_linkgens_limits_is_refused_at_load(tmp_path):
    path = _variant(tmp_path, "flywheel_sine.toml", "torque = [100.0,", "torque = [1e300,")
    with pytest.raises(DescriptionError) as exc:
        load_machine(path)
    assert exc.value.field == "machine.process_load.torque[0]" and "1e+300" in str(exc.value)


@pytest.mark.parametrize("model,old,new", [
    ("motor_startup.toml", "stall_torque = 2000.0", "stall_torque = 1e100"),
    ("dc_motor_startup.toml", "voltage = 1.0", "voltage = 1e300"),
])
def test_a_huge_motor_parameter_gives_a_clear_error(tmp_path, model, old, new):
    """Refused at load (a top speed past linkgen's limits) or by the run (time constants no step
    resolves): either way an error naming the motor's table."""
    with pytest.raises(LinkgenError, match=r"machine\.motor"):
        asm, machine = load_machine(_variant(tmp_path, model, old, new))
        run_machine(machine, reduce(asm), samples=11)


def test_a_stiff_dc_motor_is_integrated_implicitly_and_exactly(tmp_path):
    """Without inductance the DC motor is a linear characteristic, M0 = k_t·U/R, ω0 = U/k_e:
    ω(t) = ω0·(1 − exp(−t/τ)), τ = J·R/(k_t·k_e) = 9.1 µs, 5e5 of them in the 5 s."""
    from linkgen.machine.machine import choose_method

    path = _variant(tmp_path, "dc_motor_startup.toml", "inductance = 0.06", "inductance = 0.0")
    path.write_text(path.read_text().replace("torque_constant = 2000.0", "torque_constant = 2e7"))
    asm, machine = load_machine(path)
    red = reduce(asm)
    tau = 30.0 * 1.01 / (2e7 / 6.0)
    method, fastest = choose_method(machine, red, machine.duration)
    assert method == "Radau" and fastest == pytest.approx(tau, rel=1e-3)
    run = run_machine(machine, red, samples=11)
    t = np.concatenate([np.linspace(0.0, 10 * tau, 201), run.t])
    _, w = run.state_at(t)
    assert np.abs(w - 6.0 * (1.0 - np.exp(-t / tau))).max() <= EXACT_TOL * 6.0


def test_a_long_integration_reports_progress_and_its_work_is_bounded(monkeypatch):
    from linkgen.machine import machine as m

    asm, machine = load_machine(MODELS / "motor_startup.toml")
    red = reduce(asm)
    monkeypatch.setattr(m, "PROGRESS_AFTER", 0.0)
    monkeypatch.setattr(m, "PROGRESS_EVERY", 0.0)
    seen = []
    run_machine(machine, red, samples=11, progress=lambda f, s: seen.append(f))
    assert seen and all(0.0 <= f <= 1.0 for f in seen) and seen == sorted(seen)
    monkeypatch.setattr(m, "MAX_EVALUATIONS", 300)
    with pytest.raises(SimulationError, match="evaluations"):
        run_machine(machine, red, samples=11)


def test_a_table_driven_load_finds_its_steady_cycle():
    """flywheel_sine: J = 50 kg·m² against 100 + 50·sin φ with a constant 100 N·m from the
    periodic speed 10.1 rad/s: ½·J·(ω² − 10.1²) = −50·(1 − cos φ), periodic from the start."""
    asm, machine = load_machine(MODELS / "flywheel_sine.toml")
    run = run_machine(machine, reduce(asm, machine.process_load), samples=11)
    s = run.steady
    assert s is not None and s.t_start < 2.5 * s.period  # the turn after the first two, compared
    assert s.omega_max == pytest.approx(10.1, rel=TABLE_TOL)
    assert s.omega_min == pytest.approx(math.sqrt(10.1**2 - 4.0), rel=TABLE_TOL)


def test_the_peak_balancing_torque_is_the_one_of_the_state_it_names():
    """The press's peak falls just past the stroke force's switch: ε there is the ODE's own
    (a forward difference of the dense output, on the switch's far side), not an average across
    the jump."""
    from linkgen.machine.study import cycle_forces

    asm, machine = load_machine(MODELS / "machine_press.toml")
    run = run_machine(machine, reduce(asm, machine.process_load), samples=11, duration=2.0)
    cf = cycle_forces(asm, run)
    s = run.steady
    t = np.linspace(s.t_start, s.t_start + s.period, 720, endpoint=False)
    phi, w = run.state_at(t)
    k = int(np.argmin(np.abs(np.mod(phi - cf.peak_balancing_torque.phi + np.pi, 2 * np.pi) - np.pi)))
    eps = (run.state_at(t[k] + H_EPS)[1] - w[k]) / H_EPS
    f = forces(asm, phi[k:k + 1], w[k:k + 1], np.array([eps]))
    assert cf.peak_balancing_torque.value == pytest.approx(abs(float(f.balancing_torque[0])), rel=EPS_TOL)


def test_the_start_up_time_is_a_root_not_a_sample():
    asm, machine = load_machine(MODELS / "motor_startup.toml")
    run = run_machine(machine, reduce(asm), samples=50)  # samples 0.1 s apart
    assert run.startup_time == pytest.approx(0.09 * math.log(100.0), abs=TIME_TOL)


def test_the_peak_motor_torque_is_refined_between_samples():
    """dc_motor_startup is linear: J·ω̇ = k_t·i, L·i̇ = U − R·i − k_e·ω from rest; its current
    (and torque k_t·i) peaks once, found here from the matrix exponential."""
    asm, machine = load_machine(MODELS / "dc_motor_startup.toml")
    run = run_machine(machine, reduce(asm), samples=2000)
    j, big_l, r, u, ke, kt = 30.0, 0.06, 1.01, 1.0, 1.0 / 6.0, 2000.0
    a = np.array([[0.0, kt / j], [-ke / big_l, -r / big_l]])
    b = np.array([0.0, u / big_l])

    def current(t):
        return float((np.linalg.solve(a, (expm(a * t) - np.eye(2)) @ b))[1])

    ts = np.linspace(0.0, 1.0, 201)
    k = int(np.argmax([current(x) for x in ts]))
    best = minimize_scalar(lambda x: -current(x), bounds=(ts[k - 1], ts[k + 1]), method="bounded",
                           options={"xatol": 1e-12})
    assert run.peak_motor_torque == pytest.approx(kt * -best.fun, rel=EXACT_TOL)


def test_a_machine_that_never_settles_is_compared_over_its_duration_at_the_speeds_it_reaches():
    from linkgen.crosscheck.machine import MACHINE_TOL, compare_machine_run
    from linkgen.mujoco.settings import derive  # noqa: F401  (what the settings come from)

    asm, machine = load_machine(DATA / "machine_constant_torque.toml")
    out, mj, run = compare_machine_run(asm, machine, cycles=10)
    assert out["no_steady_cycle"] and out["duration_s"] == machine.duration and "cycles" not in out
    assert out["omega_reached"] == pytest.approx(np.abs(run.omega).max()) and out["omega_reached"] > 3 * 10.0  # past the drive's 10 rad/s
    assert out["ok"], out
    errors = {k: v for k, v in out["errors_relative"].items() if v is not None}
    assert out["worst"] == max(errors, key=errors.get) and out["worst_error_relative"] <= MACHINE_TOL
    # the reactions against one scale, the mechanism's largest reaction
    peaks = [np.linalg.norm(r, axis=1).max() for r in mj.reactions.values()]
    assert out["reaction_scale_n"] == pytest.approx(max(peaks), rel=1e-3)


def test_validates_machine_line_names_the_failing_quantity():
    from linkgen.cli.mujoco import _summary
    from linkgen.crosscheck.run import headline

    r = {"model": "m", "ok": False, "wall_s": 1.0, "quantities": {"x": {"relative_error": 1e-9, "tolerance": 1e-6}},
         "loop_gap": {"relative": 1e-10, "tolerance": 1e-8}, "steps": 10, "total_wall_s": 1.0,
         "dynamics": {"ok": False, "duration_s": 1.0, "omega_error_relative": 1e-8, "tolerance": 1e-6,
                      "errors_relative": {"omega": 1e-8, "reactions": 5e-6}, "worst": "reactions",
                      "worst_error_relative": 5e-6}}
    line = _summary(r | {"line": headline(r)}).splitlines()[1]
    assert "reactions 5.00e-06" in line and "omega" not in line


def test_the_machine_docs_say_where_a_machine_starts():
    text = (ROOT / "docs" / "machine.md").read_text()
    assert "starts at the crank angle `[machine] start_angle` (by\ndefault `drive.range[0]`" in text
    # and it does: without a start_angle the run's first crank angle is the drive's start
    asm, machine = load_machine(MODELS / "motor_startup.toml")
    run = run_machine(machine, reduce(asm), samples=3)
    assert run.phi[0] == asm.mechanism.drive.start


@pytest.mark.parametrize("ratio", ["1e300", "1e-300"])
def test_a_gear_ratio_past_linkgens_limits_is_refused_at_load(tmp_path, ratio):
    path = _variant(tmp_path, "machine_press.toml", "gear_ratio = 12.0", f"gear_ratio = {ratio}")
    with pytest.raises(DescriptionError) as exc:
        load_machine(path)
    assert exc.value.field == "machine.gear_ratio"


def test_a_crank_jammed_by_its_load_is_reported_as_stalled(tmp_path, monkeypatch):
    """A load spike of 5.6e8 N·m on two table points (a fuzzed machine, seed 2027): the crank
    rocks against it and never completes a turn. The run stops with the stall named instead of
    integrating the rocking for minutes (3 M evaluations, 188 s before)."""
    from linkgen.machine import machine as machine_module

    monkeypatch.setattr(machine_module, "STALL_EVALUATIONS", 20_000)  # the same rule, sooner
    path = _variant(tmp_path, "machine_slider_crank.toml", ", 555.382221261,", ", 555382221.261,")
    asm, machine = load_machine(path)
    with pytest.raises(SimulationError, match="the machine stalls: the crank has completed no new turn"):
        run_machine(machine, reduce(asm, machine.process_load), samples=11)
    # the bundled machine itself completes its turns under the same rule
    asm, machine = load_machine(MODELS / "machine_slider_crank.toml")
    run = run_machine(machine, reduce(asm, machine.process_load), samples=11, duration=2.0)
    assert run.phi[-1] - run.phi[0] > 2 * math.pi


def test_a_load_that_drives_the_crank_past_ten_times_its_motors_speed_is_a_runaway(tmp_path):
    """A process load that pushes the crank (negative resisting torque) far harder than the
    motor: past RUNAWAY times the motor's top speed the run stops and says so."""
    from linkgen.machine.machine import RUNAWAY

    asm, machine = load_machine(MODELS / "machine_slider_crank.toml")
    text = (MODELS / "machine_slider_crank.toml").read_text()
    start = text.index("torque = [", text.index("[machine.process_load]"))
    end = text.index("]", start)
    n = text[start:end].count(",") + 1
    path = tmp_path / "runaway.toml"
    path.write_text(text[:start] + "torque = [" + ", ".join(["-1e6"] * n) + text[end:])
    asm, machine = load_machine(path)
    with pytest.raises(SimulationError, match=f"{RUNAWAY:g} times the motor's top speed"):
        run_machine(machine, reduce(asm, machine.process_load), samples=11)


def test_a_motor_whose_top_speed_is_past_linkgens_limits_is_refused_at_load(tmp_path):
    """A DC motor at 1e100 V (fuzz campaign seed 2027): its no-load speed U/k_e is 1e101 rad/s,
    beyond linkgen's speeds; refused naming the motor instead of integrating time constants of
    7e-98 s for 30 s."""
    path = _variant(tmp_path, "dc_motor_startup.toml", "voltage = ", "voltage = 1e100 #")
    with pytest.raises(DescriptionError) as exc:
        load_machine(path)
    assert exc.value.field == "machine.motor" and "top speed at the crank" in str(exc.value)


def test_a_dc_motor_at_twice_the_voltage_settles_at_its_no_load_speed(tmp_path):
    """dc_motor_startup at 2 V (fuzz campaign seed 2029): Radau's iteration matrix turned
    non-finite on the exactly settled state and the run ended in an error; the machine turns
    no load, so it must settle at the motor's no-load speed U/k_e = 2/(1/6) = 12 rad/s."""
    path = _variant(tmp_path, "dc_motor_startup.toml", "voltage = 1.0", "voltage = 2.0")
    asm, machine = load_machine(path)
    run = run_machine(machine, reduce(asm, machine.process_load), samples=101)
    assert run.steady is not None
    assert run.steady.omega_mean == pytest.approx(2.0 / machine.motor.emf_constant, rel=1e-6)

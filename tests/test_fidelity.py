"""MuJoCo fidelity for mechanisms nobody tuned for: settings derived from the mechanism, the
cost of a revolution, settling windows, bounded memory, near-zero quantities, diagnosis, the
practical-settings study. Real MuJoCo throughout."""

import json
import math
import tomllib
import tracemalloc

import mujoco
import numpy as np
import pytest

import linkgen.mujoco.simulate as simulate_module
from conftest import ROOT
from linkgen import SimulationError, assemble, from_dict, load
from linkgen.cli.main import main
from linkgen.crosscheck.compare import GAP_TOL, REL_TOL, compare
from linkgen.families.planar.geometry import link_shapes
from linkgen.mujoco.posed import posed
from linkgen.families.planar.pose import mechanism_size as compare_size
from linkgen.families.planar.pose import state
from linkgen.families.planar.corpus import scaled
from linkgen.crosscheck.run import crosscheck
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import PLACEHOLDER
from linkgen.mujoco.settings import PHASE, STEPS_PER_TAU, derive
from linkgen.mujoco.simulate import simulate, steps_per_revolution

# The loop gap MuJoCo shows against the one the settings rule predicts, (1 − d)·d·τ²·|A_diag·λ|
# from the closed-form loop forces: the prediction is the steady gap, the measured one lags it
# slightly as the forces change (measured 0.99-1.00 of it on the bundled models).
GAP_PREDICTION_BAND = (0.5, 1.05)


def _desc(name: str) -> dict:
    return tomllib.loads((ROOT / "models" / f"{name}.toml").read_text())


@pytest.mark.parametrize("name", ["fourbar", "seven_link", "ga31"])
def test_the_settings_rule_predicts_the_loop_gap(name):
    asm = assemble(load(ROOT / "models" / f"{name}.toml"))
    run = simulate(asm)
    s = run.settings
    predicted = (1 - s.impedance) * s.impedance * s.timeconst**2 * run.scales.loop_acceleration
    lo, hi = GAP_PREDICTION_BAND
    assert lo * predicted <= run.gap_max <= hi * predicted, (run.gap_max, predicted)
    assert run.gap_max < GAP_TOL * compare(asm, run, inverse=False).size


@pytest.mark.parametrize("factor", [0.01, 1.0, 30.0])
@pytest.mark.parametrize("omega", [0.1, 1.0, 10.0, 100.0, 1000.0])
def test_a_revolution_costs_the_same_steps_at_any_speed_and_size(omega, factor):
    # without gravity or loads the loop forces scale with ω², so τ is set by the crank's period
    asm = assemble(from_dict(scaled(_desc("fourbar"), factor, omega, gravity=False)))
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    settings, scales = derive(asm, model, omega=omega)
    assert scales.tau_phase < scales.tau_gap
    steps = 2 * math.pi / (omega * settings.timestep)
    assert steps == pytest.approx(2 * math.pi * STEPS_PER_TAU / PHASE, rel=1e-9)  # ω·τ = PHASE exactly here


@pytest.mark.parametrize("omega, factor", [(1000.0, 30.0), (300.0, 0.01), (0.3, 1.0)])
def test_extreme_speeds_and_sizes_validate(omega, factor):
    cc = crosscheck(assemble(from_dict(scaled(_desc("fourbar"), factor, omega))), practical=False)
    assert cc.ok, cc.to_json()["diagnosis"]
    assert len(cc.attempts) == 1  # the derived settings hold at the first run


def test_memory_does_not_grow_with_the_duration(monkeypatch):
    # small chunks so that both runs are many chunks long; 4× the steps, the same peak
    monkeypatch.setattr(simulate_module, "CHUNK_STEPS", 2000)
    asm = assemble(load(ROOT / "models" / "fourbar.toml"))
    peaks = []
    for omega in (2.0, 0.5):  # gravity-dominated: the slower run takes ~4× the steps
        tracemalloc.start()
        run = simulate(asm, omega=omega, samples=90)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
        assert run.samples.qpos.shape[0] == 90 and run.steps > 10 * 2000
    assert peaks[1] < 1.3 * peaks[0], peaks


def test_both_threads_agree_with_one():
    asm = assemble(load(ROOT / "models" / "ga2.toml"))
    one, two = simulate(asm, nthread=1, samples=72), simulate(asm, nthread=2, samples=72)
    assert (one.segments, two.segments) == (1, 2)
    for run in (one, two):
        cmp = compare(asm, run, inverse=False)
        assert cmp.ok, {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    # each segment starts at the exact speed; one long run drifts by the rotor's ~1e-6 relative
    np.testing.assert_allclose(two.samples.crank[0], one.samples.crank[0], atol=1e-5)


def test_a_quantity_that_is_zero_is_judged_against_its_scale():
    # OA = AB with the slider on the line through O: the rod turns as −φ, so its angular
    # acceleration is identically zero at constant ω (closed form: rounding only)
    desc = {
        "mechanism": {"name": "isosceles", "gravity": [0.0, -9.81]},
        "points": {"O": [0.0, 0.0], "A": [0.2 * math.cos(0.3), 0.2 * math.sin(0.3)], "B": [0.4 * math.cos(0.3), 0.0]},
        "links": {"ground": {"points": ["O"]}, "crank": {"points": ["O", "A"], "length": 0.2, "density": 2.0},
                  "rod": {"points": ["A", "B"], "length": 0.2, "density": 2.0},
                  "slider": {"points": ["B"], "inertial": {"mass": 0.5, "com": [0.0, 0.0], "inertia": 0.0}}},
        "prismatic": {"slide": {"slider": "slider", "guide": "ground", "point": "B", "through": "O"}},
        "drive": {"joint": "O", "omega": 12.0, "range": ["5deg", "60deg"]},  # B passes O at 90°: a change point
    }
    asm = assemble(from_dict(desc))
    cmp = compare(asm, simulate(asm), inverse=False)
    q = cmp.quantities["links.rod.angular_acceleration"]
    assert q.peak < 1e-5 * q.scale  # zero but for −ε of the crank, whose speed the rotor holds to ~1e-7
    xy = np.array(list(desc["points"].values()))
    size = float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))
    assert q.scale == pytest.approx(12.0**2 + 9.81 / size, rel=1e-6)  # judged against ω² + g/L, not its own peak
    assert cmp.ok, {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}


def _with_stroke_load() -> dict:
    desc = _desc("fourbar")
    desc["force"] = [{"link": "rocker", "point": "B", "force": [-400.0, 150.0], "stroke": ["60deg", "200deg"]}]
    return desc


def test_samples_after_a_load_switch_are_left_out_and_counted(capsys):
    asm = assemble(from_dict(_with_stroke_load()))
    run = simulate(asm)
    switches = [lo for lo in run.left_out if lo.reason == "load switch"]
    assert [round(math.degrees(lo.phi_from)) for lo in switches] == [60, 200]
    w = run.window * asm.mechanism.drive.omega
    for lo in switches:
        assert lo.samples >= 1 and lo.phi_to - lo.phi_from <= w + 1e-12
    cmp = compare(asm, run)
    assert cmp.ok, {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    # the compared curves still cover the whole revolution
    phi = np.degrees(run.samples.crank[0])
    assert phi.min() < 1.0 and phi.max() > 358.0


def test_near_an_assembly_limit_the_result_is_ok_or_explained(capsys, tmp_path):
    # the group BE-EF straightens at -76.3°: a range 0.8° from it
    path = tmp_path / "near_limit.toml"
    path.write_text((ROOT / "models" / "seven_link.toml").read_text().replace(
        'range = ["-60deg", "45deg"]', 'range = ["-75.5deg", "-50deg"]'))
    code = main(["validate", str(path), "--json", "--no-practical"])
    out = json.loads(capsys.readouterr().out)
    assert out["ok"] is (code == 0)
    if not out["ok"]:
        assert out["diagnosis"] and out["attempts"]
        first = out["diagnosis"][0]
        assert first["cause"] == "near-singular" and "condition number" in first["detail"]
        assert all(math.radians(-75.6) <= lo <= hi <= math.radians(-49.9) for lo, hi in first["ranges"])
        code = main(["validate", str(path), "--no-practical"])
        text = capsys.readouterr().out
        assert code == 1 and "near-singular" in text and "tried: timestep" in text


def test_practical_settings_show_what_mujoco_defaults_cost():
    cc = crosscheck(assemble(load(ROOT / "models" / "fourbar.toml")))
    rows = cc.to_json()["practical_settings"]
    assert [r["label"] for r in rows][0] == "MuJoCo defaults (timestep 2 ms)"
    user, valid = rows[0], rows[-1]
    assert (user["timestep"], user["integrator"], user["solref"], user["solimp"]) == (
        0.002, "Euler", [0.02, 1.0], [0.9, 0.95, 0.001, 0.5, 2.0])
    # against the closed form: the defaults open the loops and bend the forces by orders of magnitude more
    assert user["loop_gap_relative"] > 1e4 * valid["loop_gap_relative"]
    assert user["reaction_error_relative"] > 1e3 * valid["reaction_error_relative"]
    assert valid["reaction_error_relative"] < 1e-6 and valid["loop_gap_relative"] < GAP_TOL
    assert user["steps_per_revolution"] < valid["steps_per_revolution"]


def test_simulate_checks_the_output_name_before_running(tmp_path, capsys):
    assert main(["simulate", str(ROOT / "models" / "seven_link.toml"), "--out", str(tmp_path / "run.txt")]) == 2
    err = capsys.readouterr()
    assert "`linkgen simulate` writes .npz" in err.err and "steps" not in err.out


def test_slow_runs_report_progress(monkeypatch, capsys):
    monkeypatch.setattr(simulate_module, "PROGRESS_AFTER", 0.0)
    monkeypatch.setattr(simulate_module, "CHUNK_STEPS", 2000)
    assert main(["simulate", str(ROOT / "models" / "fourbar.toml")]) == 0
    err = capsys.readouterr().err
    assert "fourbar: MuJoCo run" in err and "100.0%" in err


def test_steps_per_revolution_is_reported():
    asm = assemble(load(ROOT / "models" / "fourbar.toml"))
    run = simulate(asm, samples=36)
    assert steps_per_revolution(run) == pytest.approx(2 * math.pi / (10.0 * run.settings.timestep), rel=1e-6)


def test_class_three_is_built_simulated_and_the_closed_form_says_it_does_not_cover_it(tmp_path, capsys):
    triad = ROOT / "tests" / "data" / "triad_sixbar.toml"
    assert main(["build", str(triad), "-o", str(tmp_path / "triad.xml")]) == 0
    assert mujoco.MjModel.from_xml_path(str(tmp_path / "triad.xml")).neq == 2
    assert main(["validate", str(triad)]) == 2
    err = capsys.readouterr().err
    assert str(triad) in err and "class III" in err and "`linkgen simulate` still work" in err
    assert main(["simulate", str(triad), "--out", str(tmp_path / "run.npz")]) == 0
    assert "the closed form does not cover this mechanism" in capsys.readouterr().err
    # MuJoCo's run against the numeric pose (Newton on the pair constraints) at the measured crank states
    mech = load(triad)
    run = simulate(posed(mech), samples=48)
    phi, omega = run.samples.crank[0], run.samples.crank[1]
    size = compare_size(mech)
    assert run.gap_max < GAP_TOL * size
    ref = state(mech, phi, omega)
    shapes = link_shapes(mech)
    for link in mech.moving_links:
        for p, local in shapes[link].local.items():
            if p in run.samples.points:
                pos, vel, _ = run.samples.points[p]
                np.testing.assert_allclose(pos, ref.point(link, local), rtol=0, atol=REL_TOL * size)
                np.testing.assert_allclose(vel, ref.point_velocity(link, local), rtol=0,
                                           atol=REL_TOL * size * float(np.abs(omega).max()))


def test_a_crank_too_fast_for_mujoco_is_named():
    asm = assemble(load(ROOT / "models" / "fourbar.toml"))
    with pytest.raises(SimulationError, match=r"MuJoCo warned during the run: BADQACC \(MuJoCo rejects joint "
                                              r"accelerations beyond mjMAXVAL = 1e10"):
        simulate(asm, omega=1e6, samples=12)

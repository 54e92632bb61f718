"""Published multibody benchmarks on the machine route (issue 25: "a 1e-8 relative agreement of
the crank angle after several turns from the closed-form route"): Andrews' squeezing mechanism
against the IVP test set's reference solution, the simple pendulum against its exact elliptic
motion, and the table in docs/machine.md against a run. The expected values are published
numbers typed here with their source, or scipy's elliptic functions — never linkgen's."""

import json
import math
import re
from pathlib import Path

import pytest
from scipy.special import ellipj, ellipk

import andrews_reference
from linkgen.cli.main import main
from linkgen.errors import DescriptionError
from linkgen.machine.study import load_machine

ROOT = Path(__file__).resolve().parents[1]
SQUEEZER = ROOT / "models" / "andrews_squeezer.toml"

# Mazzia & Magherini, "Test Set for IVP Solvers", problem "andrews" (Andrews' squeezing mechanism,
# Hairer & Wanner II §VII.7), subroutine SOLN: the reference solution at t = 0.03 s, computed by
# PSIDE on a Cray C90 at rtol = atol = 1e-14. β [rad] is the crank's angle, β′ [rad/s] its speed.
BETA_003 = 0.1581077119629904e+2
BETA_DOT_003 = 0.1139920302151208e+4
# The bound on the crank angle after several turns (2.5 here), relative.
BENCHMARK_TOL = 1e-8
# The closed form at every step: linkgen's converged β(0.03 s) is 15.8107711951515 ± 3e-12 rad (rtol
# 1e-10 to 1e-14, docs/machine.md), 7.3e-11 from the published value; 2e-10 is above that and below
# what the tables allow at the same rtol (4.2e-10 at 1e-12: J's spline between its 4096 angles).
CLOSED_FORM_TOL = 2e-10
# linkgen's closed form at every step against tests/andrews_reference.py (the benchmark's own seven
# coordinates with Lagrange multipliers, DOP853 at rtol 1e-11): both integrations' own errors over
# their 200–300 steps, 7e-13 measured; the published value lies 7.2e-11 from both.
INDEPENDENT_TOL = 1e-11


def _dynamics(path, capsys) -> dict:
    assert main(["dynamics", str(path), "--samples", "2", "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_andrews_crank_angle_after_two_and_a_half_turns_agrees_with_the_test_set(capsys):
    out = _dynamics(SQUEEZER, capsys)
    assert out["end"]["t"] == 0.03 and out["energy_balance"]["ok"]
    assert abs(out["end"]["phi"] - BETA_003) <= BENCHMARK_TOL * abs(BETA_003)
    assert abs(out["end"]["omega"] - BETA_DOT_003) <= BENCHMARK_TOL * abs(BETA_DOT_003)


def test_the_closed_form_at_every_step_removes_the_tables_floor(tmp_path, capsys):
    """``[machine] tables = false`` at rtol 1e-12: the crank angle to CLOSED_FORM_TOL of the
    published value, which the tables cannot reach at any rtol, and to INDEPENDENT_TOL of an
    integration of the benchmark's own equations; the run says where J and M came from."""
    text = SQUEEZER.read_text(encoding="utf-8").replace("duration = 0.03", "duration = 0.03\nrtol = 1e-12\ntables = false")
    path = tmp_path / "squeezer.toml"
    path.write_text(text, encoding="utf-8")
    out = _dynamics(path, capsys)
    assert out["integrator"]["rtol"] == 1e-12 and out["integrator"]["equation"] == "the closed form at every step"
    assert abs(out["end"]["phi"] - BETA_003) <= CLOSED_FORM_TOL * abs(BETA_003)
    assert out["energy_balance"]["ok"]
    q, qd, drift = andrews_reference.solve(0.03, rtol=1e-11)
    assert drift < 1e-12  # m: the referee's closure holds
    assert abs(out["end"]["phi"] - q[0]) <= INDEPENDENT_TOL * abs(q[0])
    assert abs(out["end"]["omega"] - qd[0]) <= INDEPENDENT_TOL * abs(qd[0])


@pytest.mark.parametrize("line,message", [
    ("rtol = 1e-16", "machine.rtol: must be between 1e-13 and 1e-06 (the integration's relative tolerance), got 1e-16"),
    ("rtol = 0.01", "machine.rtol: must be between 1e-13 and 1e-06 (the integration's relative tolerance), got 0.01"),
    ('tables = "no"', "machine.tables: must be true or false, got 'no'"),
])
def test_the_integration_keys_are_checked(tmp_path, line, message):
    path = tmp_path / "squeezer.toml"
    path.write_text(SQUEEZER.read_text(encoding="utf-8").replace("duration = 0.03", f"duration = 0.03\n{line}"),
                    encoding="utf-8")
    with pytest.raises(DescriptionError, match=re.escape(message)):
        load_machine(path)


def test_the_pendulum_follows_its_elliptic_motion(capsys):
    """IFToMM A01: a 1 kg lumped mass on a massless 1 m link released from the horizontal;
    θ = 2·asin(k·sn(K − √(g/L)·t | k²)) from the downward vertical, k = sin(45°)."""
    out = _dynamics(ROOT / "validation" / "benchmarks" / "iftomm_a01_pendulum.toml", capsys)
    t, k = out["end"]["t"], math.sin(math.pi / 4)
    exact = 2 * math.asin(k * ellipj(ellipk(k * k) - math.sqrt(9.81) * t, k * k)[0]) - math.pi / 2
    assert t == 10.0
    assert abs(out["end"]["phi"] - exact) <= BENCHMARK_TOL * abs(exact)


def test_the_benchmark_table_in_the_docs_is_the_models_run(capsys):
    """docs/machine.md's Andrews row (validation/benchmarks.py --write) holds the crank angle
    this model gives; the figures differ between machines by rounding only, far below 1e-12."""
    doc = (ROOT / "docs" / "machine.md").read_text(encoding="utf-8")
    row = next(line for line in doc.splitlines() if line.startswith("| Andrews, tables") and "| β(0.03 s)" in line)
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert float(cells[2]) == BETA_003
    out = _dynamics(SQUEEZER, capsys)
    assert abs(float(cells[3]) - out["end"]["phi"]) <= 1e-12 * BETA_003


# The two routes on a machine with a spring and a damper (slider_crank_torque over 1 s, 3.6 turns):
# they differ by the tables' interpolation, measured 1.3e-10 on φ, 1.2e-10 of the dampers' work and
# 3.5e-10 of the loads' work; 2e-9 is six times the largest.
ROUTES_TOL = 2e-9


def test_the_closed_form_route_agrees_with_the_tables_and_keeps_the_dampers_work():
    from dataclasses import replace

    from linkgen.machine.machine import run_machine
    from linkgen.machine.reduced import reduce

    asm, machine = load_machine(ROOT / "models" / "slider_crank_torque.toml")
    machine = replace(machine, duration=1.0, turns=None)
    runs = [run_machine(replace(machine, tables=tables), reduce(asm, None, exact=not tables), samples=50)
            for tables in (True, False)]
    tables, exact = runs
    assert exact.energy.ok and exact.energy.dampers[-1] < 0
    assert abs(exact.phi[-1] - tables.phi[-1]) <= ROUTES_TOL * abs(tables.phi[-1])
    assert abs(exact.energy.dampers[-1] - tables.energy.dampers[-1]) <= ROUTES_TOL * abs(tables.energy.dampers[-1])
    assert abs(exact.energy.loads[-1] - tables.energy.loads[-1]) <= ROUTES_TOL * abs(tables.energy.loads[-1])

"""Whether the crank turns fully, and where the chain assembles: planar `structure`, the
assembly error's ranges and its `drive.range` suggestion, checked against the four-bar's own
geometry (the distance between the crank pin and the rocker's pivot must lie between the
difference and the sum of the coupler and the rocker)."""

from __future__ import annotations

import math
import re
import subprocess
import sys

import numpy as np
import pytest

from linkgen.errors import AssemblyError
from linkgen.pipeline.registry import load
from linkgen.model.turn import turn_assembly
from linkgen.families.planar.kinematics import solve

from conftest import ROOT

# A non-Grashof four-bar: ground OC = 1 m, crank OA = 0.8 m, coupler AB = 0.5 m, rocker CB = 0.6 m.
# |AC|² = 0.8² + 1 − 1.6·cos φ must stay below (0.5 + 0.6)², so cos φ >= (1.64 − 1.21)/1.6: the
# chain assembles for |φ| <= acos(0.26875) = 74.41°, and |AC| >= 0.2 > 0.6 − 0.5 everywhere.
EDGE = math.acos((0.8**2 + 1.0 - 1.1**2) / 1.6)
ROCKING = """\
[mechanism]
name = "rocking"
gravity = [0.0, -9.81]

[points]
O = [0.0, 0.0]
A = [0.8, 0.0]
B = [0.625, 0.468375]
C = [1.0, 0.0]

[links.ground]
points = ["O", "C"]

[links.crank]
points = ["O", "A"]
length = 0.8

[links.coupler]
points = ["A", "B"]
length = 0.5

[links.rocker]
points = ["C", "B"]
length = 0.6

[drive]
joint = "O"
omega = 10.0
"""
# The edges are bisected to 1e-12 rad on the solver's own test of reach, whose rounding near
# the edge (|AC| against b + c, a square root of a difference of squares) is ~1e-8 rad of φ.
EDGE_TOL_RAD = 1e-7
# Printed with 6 decimals of a degree.
PRINTED_TOL_DEG = 1e-6 + math.degrees(EDGE_TOL_RAD)


def _cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True, cwd=cwd)


@pytest.fixture
def rocking(tmp_path):
    path = tmp_path / "rocking.toml"
    path.write_text(ROCKING, encoding="utf-8")
    return path


def test_structure_says_the_crank_does_not_turn_fully_and_where_it_assembles(rocking):
    p = _cli("structure", rocking)
    assert p.returncode == 0, p.stderr
    line = next(l for l in p.stdout.splitlines() if l.startswith("crank:"))
    assert line.startswith("crank: does not turn fully — the chain assembles at crank angles ")
    lo, hi = (float(x) for x in re.search(r"assembles at crank angles (-?[\d.]+)°\.\.(-?[\d.]+)°", line).groups())
    assert abs(lo + math.degrees(EDGE)) <= PRINTED_TOL_DEG and abs(hi - math.degrees(EDGE)) <= PRINTED_TOL_DEG
    a, b = (float(x) for x in re.search(r"cannot at ([\d.]+)°\.\.([\d.]+)°", line).groups())
    assert abs(a - math.degrees(EDGE)) <= PRINTED_TOL_DEG and abs(b - (360 - math.degrees(EDGE))) <= PRINTED_TOL_DEG
    assert 'put under [drive]: range = ["-74.410deg", "74.410deg"]' in p.stdout


def test_structure_says_a_crank_rocker_turns_fully():
    p = _cli("structure", ROOT / "models" / "fourbar.toml")
    assert p.returncode == 0, p.stderr
    assert "crank: turns fully — the chain assembles at every crank angle" in p.stdout


def test_structure_says_a_given_range_lies_where_the_chain_is_regular():
    p = _cli("structure", ROOT / "models" / "seven_link.toml")
    assert p.returncode == 0, p.stderr
    assert "crank: does not turn fully" in p.stdout
    assert "the drive's crank-angle range -60°..45° lies where the chain is assembled and regular" in p.stdout


def test_an_assembly_error_lists_where_the_chain_assembles_and_a_range_to_paste(rocking, tmp_path):
    with pytest.raises(AssemblyError) as err:
        solve(load(rocking), np.radians(np.arange(0.0, 360.0, 10.0)))
    (lo, hi), = err.value.assembles
    assert abs(lo + EDGE) <= EDGE_TOL_RAD and abs(hi - EDGE) <= EDGE_TOL_RAD
    assert err.value.suggestion == 'range = ["-74.410deg", "74.410deg"]'
    assert str(err.value).endswith("; the chain assembles at crank angles -74.410°..74.410°; to run over the widest of "
                                   'them where it is regular, put under [drive]: range = ["-74.410deg", "74.410deg"]')
    # the CLI says it too, and the suggestion pasted under [drive] runs
    p = _cli("analyze", rocking, "--samples", "36", "--csv", tmp_path / "a.csv")
    assert p.returncode == 2 and err.value.suggestion in p.stderr
    pasted = tmp_path / "pasted.toml"
    pasted.write_text(ROCKING + err.value.suggestion + "\n", encoding="utf-8")
    p = _cli("forces", pasted, "--samples", "360", "--csv", tmp_path / "f.csv")
    assert p.returncode == 0, p.stderr
    singular = np.loadtxt(tmp_path / "f.csv", delimiter=",", skiprows=1, usecols=1)
    assert not singular.any()


def test_the_turn_scan_bisects_edges_of_a_known_status():
    """The shared scan on a status given in closed form: it fails on (1, 2) rad and on the
    wrap (6.0, 0.3) rad, and is singular on (4, 4.5) rad."""
    def status(phi):
        p = np.mod(phi, 2 * np.pi)
        return ((p > 1.0) & (p < 2.0)) | (p > 6.0) | (p < 0.3), (p > 4.0) & (p < 4.5)

    t = turn_assembly(status)
    assert not t.full
    np.testing.assert_allclose(np.array(t.fails), [[6.0 - 2 * np.pi, 0.3], [1.0, 2.0]], atol=1e-11)  # from before 0
    np.testing.assert_allclose(np.array(t.assembles), [[0.3, 1.0], [2.0, 6.0]], atol=1e-11)
    np.testing.assert_allclose(np.array(t.clean), [[0.3, 1.0], [2.0, 4.0], [4.5, 6.0]], atol=1e-11)
    # the widest clean range, 2..4 rad, rounded inward to 0.001°
    assert t.suggestion() == pytest.approx((math.ceil(math.degrees(2.0) * 1000) / 1000,
                                            math.floor(math.degrees(4.0) * 1000) / 1000), abs=1e-9)

"""The springs' tensions and the torsion springs' moments in ``linkgen forces``' output (JSON and
CSV columns ``spring[i].force [N]``, ``torsion_spring[i].moment [N·m]`` …, named as the design
summary names them), against hand values
at crank angles whose positions are written out here."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from linkgen import assemble, load
from linkgen.families.planar.forces_result import forces
from linkgen.families.planar.kinematics import solve

MODELS = ROOT / "models"
# The closed form computes L, dL/dφ and θ in a few operations each: rounding ~1e-15 of the
# values; 1e-12 of the force's size leaves a margin of 1e3 and catches any wrong term.
HAND_TOL = 1e-12


def _slider_crank_by_hand(phi: float, w: float):
    """models/slider_crank_spring.toml (crank r = 0.1 m, rod l = 0.35 m, the slider's pin B on the
    line through O, the spring from B to S = (0.65, 0), k = 2000 N/m, L₀ = 0.45 m, c = 20 N·s/m):
    x_B = r·cosφ + √(l² − r²·sin²φ), L = 0.65 − x_B, dL/dt = −ω·dx_B/dφ with dx_B/dφ = −r·sinφ −
    r²·sinφ·cosφ/√(l² − r²·sin²φ). Returns (L, k·(L − L₀), c·dL/dt)."""
    r, l, k, l0, c = 0.1, 0.35, 2000.0, 0.45, 20.0
    root = math.sqrt(l * l - (r * math.sin(phi)) ** 2)
    xb = r * math.cos(phi) + root
    dxb = -r * math.sin(phi) - r * r * math.sin(phi) * math.cos(phi) / root
    length = 0.65 - xb
    return length, k * (length - l0), c * (-w * dxb)


@pytest.mark.parametrize("phi", [math.radians(60.0), math.radians(200.0)])
def test_the_spring_tension_in_the_forces_output_by_hand(phi):
    w = 10.0
    length, spring, damper = _slider_crank_by_hand(phi, w)
    f = forces(load(MODELS / "slider_crank_spring.toml"), np.array([phi, phi + 0.1]), w)
    cols = f.columns()
    scale = abs(spring) + abs(damper)
    assert cols["spring[0].length [m]"][0] == pytest.approx(length, abs=HAND_TOL)
    assert cols["spring[0].spring_force [N]"][0] == pytest.approx(spring, abs=HAND_TOL * scale)
    assert cols["spring[0].damper_force [N]"][0] == pytest.approx(damper, abs=HAND_TOL * scale)
    assert cols["spring[0].force [N]"][0] == pytest.approx(spring + damper, abs=HAND_TOL * scale)
    assert f.to_dict()["units"]["length"] == "m" and f.to_dict()["units"]["damper_force"] == "N"
    out = f.to_dict()["springs"]["spring[0]"]
    assert out["points"] == "B-S"
    assert out["force"][0] == pytest.approx(spring + damper, abs=HAND_TOL * scale)
    # a compression spring: the tension is negative (it pushes B away from S)
    assert cols["spring[0].force [N]"][0] < 0


def test_the_torsion_springs_moment_in_the_forces_output_by_hand():
    """models/fourbar_torsion.toml: the moment on the rocker is −k·(θ − 90°) − c·ω·dθ/dφ, θ the
    rocker's angle from the positions of C and B, dθ/dφ by central differences of those positions
    (error ~h²·θ‴/6 + eps·θ/h ≈ 3e-10 rad/rad, times c·ω = 5 N·m·s/rad: 2e-9 N·m; 1e-8 allowed)."""
    asm = assemble(load(MODELS / "fourbar_torsion.toml"))
    phi, h, w = 1.3, 1e-6, 10.0
    kin = solve(asm, np.array([phi - h, phi, phi + h]))
    theta = [math.atan2(*(kin.points["B"].p[i] - kin.points["C"].p[i])[::-1]) for i in range(3)]
    spring = -40.0 * (theta[1] - math.pi / 2)
    damper = -0.5 * w * (theta[2] - theta[0]) / (2 * h)
    cols = forces(asm, np.array([phi]), w).columns()
    assert cols["torsion_spring[0].deflection [rad]"][0] == pytest.approx(theta[1] - math.pi / 2, abs=HAND_TOL)
    assert cols["torsion_spring[0].spring_moment [N·m]"][0] == pytest.approx(spring, abs=HAND_TOL * abs(spring))
    assert cols["torsion_spring[0].moment [N·m]"][0] == pytest.approx(spring + damper, abs=1e-8)


def test_the_cli_writes_the_spring_columns(tmp_path):
    """``linkgen forces --samples N -o FILE.csv`` has the spring's columns; one angle's text names it."""
    out = tmp_path / "f.csv"
    run = subprocess.run([sys.executable, "-m", "linkgen", "forces", str(MODELS / "slider_crank_friction.toml"),
                          "--samples", "5", "-o", str(out)], capture_output=True, text=True, check=True)
    header = out.read_text().splitlines()[0].split(",")
    assert {"spring[0].force [N]", "spring[0].damper_force [N]", "spring[0].length [m]"} <= set(header)
    one = subprocess.run([sys.executable, "-m", "linkgen", "forces", str(MODELS / "slider_crank_friction.toml"),
                          "--angle", "60deg", "--json"], capture_output=True, text=True, check=True)
    length, spring, damper = _slider_crank_by_hand(math.radians(60.0), 10.0)
    assert json.loads(one.stdout)["springs"]["spring[0]"]["force"] == pytest.approx(
        spring + damper, abs=HAND_TOL * (abs(spring) + abs(damper)))
    assert run.returncode == 0

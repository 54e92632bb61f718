"""The planetary gear-lever mechanism: positions against the textbook's closed formula, the tooth
force and balancing torque against hand statics and virtual work, the mobility with a higher
pair, bad gear tables, and MuJoCo's joint coupling against the closed form."""

import math
from pathlib import Path

import numpy as np
import pytest

from linkgen import load
from linkgen.errors import DescriptionError
from linkgen.pipeline.registry import loads
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"

LOADED = """
[mechanism]
name = "planet_loaded"
[points]
O = [0.0, 0.0]
C = [1.0, 0.0]
B = [1.55, 0.0]
[links.ground]
points = ["O"]
[links.crank]
points = ["O", "C"]
length = 1.0
inertial = { mass = 1.0, com = [0.0, 0.0], inertia = 0.1 }
[links.satellite]
points = ["C", "B"]
length = 0.55
inertial = { mass = 1.0, com = [0.0, 0.0], inertia = 0.1 }
[gear.mesh]
planet = "satellite"
kind = "KIND"
module = 0.05
teeth = [Z_FIXED, 20]
[drive]
joint = "O"
omega = 1.0
[[force]]
link = "satellite"
point = "B"
force = [30.0, -100.0]
"""


@pytest.mark.parametrize("name,zr", [("planetary_lever", 60), ("planetary_lever_2", 40)])
def test_b_follows_the_textbook_formula(name, zr):
    """B = O + a·(cos φ, sin φ) + 0.55·(cos kφ, sin kφ), a = 0.5·(z_r − 20)·m, k = 1 − z_r/20."""
    mech = load(MODELS / f"{name}.toml")
    phi = np.linspace(0, 2 * math.pi, 721)
    kin = solve(mech, phi)
    a, k = 0.5 * (zr - 20) * 0.05, 1 - zr / 20
    want = np.column_stack([a * np.cos(phi) + 0.55 * np.cos(k * phi), a * np.sin(phi) + 0.55 * np.sin(k * phi)])
    assert np.abs(kin.points["B"].p - want).max() < 1e-13
    d1 = np.column_stack([-a * np.sin(phi) - 0.55 * k * np.sin(k * phi), a * np.cos(phi) + 0.55 * k * np.cos(k * phi)])
    assert np.abs(kin.points["B"].d1 - d1).max() < 1e-13


@pytest.mark.parametrize("kind,z_fixed", [("internal", 60), ("external", 20)])
def test_tooth_force_and_torque_by_hand(kind, z_fixed):
    """At rest (ω = 0: no inertia loads, no gravity) with a force F at B: the planet's moments about
    C give the tangential tooth force, its radial part is |F_t|·tan 20°, and the crank torque is
    −F·dB/dφ (virtual work)."""
    text = LOADED.replace("KIND", kind).replace("Z_FIXED", str(z_fixed))
    mech = loads(text)  # a sun of 20 teeth and the planet of 20: the centre distance is 1.0 m as well
    phi = np.linspace(0.1, 6.0, 13)
    f = forces(mech, phi, 0.0)
    kin = solve(mech, phi)
    force = np.array([30.0, -100.0])
    c, b = kin.points["C"].p, kin.points["B"].p
    radial = c / np.hypot(*c.T)[:, None]
    tangent = np.column_stack([-radial[:, 1], radial[:, 0]])
    r_p = 0.5 * 0.05 * 20
    side = 1.0 if kind == "internal" else -1.0
    moment_b = (b - c)[:, 0] * force[1] - (b - c)[:, 1] * force[0]
    f_t = -moment_b / (side * r_p)
    tooth = f.tooth["mesh"]
    assert np.abs(np.sum(tooth * tangent, axis=1) - f_t).max() < 1e-12 * np.abs(f_t).max()
    assert np.abs(np.sum(tooth * -side * radial, axis=1) - np.abs(f_t) * math.tan(math.radians(20))).max() < 1e-12 * 100
    torque = -(kin.points["B"].d1 @ force)  # T·δφ + F·δB = 0
    assert np.abs(f.balancing_torque - torque).max() < 1e-12 * np.abs(torque).max()


def test_mobility_counts_the_gear_pair():
    mech = load(MODELS / "planetary_lever_rrr.toml")
    from linkgen.families.planar.structure import analyze

    s = analyze(mech)
    assert s.mobility == 1 and s.moving_links == 4 and s.lower_pairs == 5 and len(s.groups) == 1


@pytest.mark.parametrize("change,words", [
    ("teeth = [60, 20]", None),
    ("teeth = [50, 20]", "centre distance"),
    ("teeth = [10, 20]", "more teeth"),
    ('planet = "crank"', "other than the crank"),
    ('kind = "bevel"', "internal"),
])
def test_bad_gear_tables(change, words):
    text = (MODELS / "planetary_lever.toml").read_text(encoding="utf-8")
    key = change.split(" = ")[0]
    lines = [change if line.startswith(key + " =") else line for line in text.splitlines()]
    if words is None:
        loads("\n".join(lines))
        return
    with pytest.raises(DescriptionError, match=words):
        loads("\n".join(lines))


@pytest.mark.parametrize("name", ["planetary_lever", "planetary_lever_2", "planetary_lever_rrr"])
def test_gear_models_validate_against_mujoco(name):
    from linkgen.crosscheck.run import crosscheck
    from linkgen.families.planar.assembly import assemble

    cc = crosscheck(assemble(load(MODELS / f"{name}.toml")), practical=False)
    assert cc.ok, cc.to_json()["diagnosis"]

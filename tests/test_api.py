"""The top-level API: every function takes a Mechanism; scalar in, scalar-shaped out; plain
data for JSON and pandas; short reprs."""

import json
from pathlib import Path

import numpy as np
import pytest

import linkgen

ROOT = Path(__file__).resolve().parents[1]
MECH = linkgen.load(ROOT / "models" / "seven_link.toml")
# Central differences (step 1e-6 rad) of positions against the transfer functions.
FD_TOL = 1e-8


def test_scalar_in_scalar_shaped_out():
    k = linkgen.kinematics(MECH, 0.3, omega=2.0)
    assert k.points["B"].position.shape == (2,) and isinstance(k.links["rocker"].angle, float)
    assert isinstance(k.sliders["block"].displacement, float) and k.phi == 0.3 and k.omega == 2.0
    f = linkgen.forces(MECH, 0.3)
    assert isinstance(f.balancing_torque, float) and all(r.shape == (2,) for r in f.reactions.values())
    ka = linkgen.kinematics(MECH, np.linspace(-0.5, 0.5, 7))
    assert ka.points["B"].position.shape == (7, 2) and ka.links["rocker"].angle.shape == (7,)
    assert ka.points["B"].velocity[3] == pytest.approx(linkgen.kinematics(MECH, 0.0).points["B"].velocity, rel=1e-14)


def test_transfer_functions_against_central_differences():
    h, phi = 1e-6, np.array([-0.4, 0.1, 0.6])
    k, kp, km = (linkgen.kinematics(MECH, phi + d) for d in (0.0, h, -h))
    for name in k.points:
        fd = (kp.points[name].position - km.points[name].position) / (2 * h)
        assert np.abs(fd - k.points[name].d1).max() < FD_TOL
    for name in k.links:
        fd = (kp.links[name].angle - km.links[name].angle) / (2 * h)
        assert np.abs(fd - k.links[name].d1).max() < FD_TOL


def test_plain_data_for_json_and_pandas():
    k = linkgen.kinematics(MECH, np.linspace(-0.5, 0.5, 11))
    text = json.dumps(k.to_dict(), allow_nan=False)
    assert '"units"' in text and json.loads(text)["model"] == "seven_link"
    cols = k.columns()
    assert {len(v) for v in cols.values()} == {11} and "B.velocity.x [m/s]" in cols
    f = linkgen.forces(MECH, np.linspace(-0.5, 0.5, 11), omega=3.0)
    json.dumps(f.to_dict(), allow_nan=False)
    assert {len(v) for v in f.columns().values()} == {11} and "balancing_torque [N·m]" in f.columns()


def test_reprs_are_short():
    big = np.linspace(-1.0, 0.7, 100_000)
    for obj in (MECH, linkgen.assemble(MECH), linkgen.solve(MECH, big), linkgen.solve(MECH, big).motion(1.0),
                linkgen.kinematics(MECH, big), linkgen.forces(MECH, big[:1000])):
        assert len(repr(obj)) < 200, repr(obj)[:300]


def test_mujoco_functions_take_a_mechanism():
    four = linkgen.load(ROOT / "models" / "fourbar.toml")
    assert linkgen.write_mjcf(four).startswith("<mujoco")
    run = linkgen.simulate(four, samples=10)
    assert run.samples.time.shape == (10,)
    triad = linkgen.load(ROOT / "tests" / "data" / "triad_sixbar.toml")  # class III: no closed form
    assert linkgen.write_mjcf(triad).startswith("<mujoco")
    assert linkgen.validate(four, practical=False).ok
    assert "I(0,1)" in linkgen.structure(four).formula

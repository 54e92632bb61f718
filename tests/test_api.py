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
    assert isinstance(f.balancing_torque, float) and all(r.force.shape == (2,) for r in f.reactions.values())
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


# The API reads angles and rates as the CLI does (linkgen.model.arguments): a unit string gives
# the same float as the number in SI it stands for, to float64 rounding of the conversion.
UNIT_REL = 1e-15


def test_angles_and_rates_as_unit_strings():
    k = linkgen.kinematics(MECH, "30deg", omega="120rpm", epsilon="60rpm/s")
    ref = linkgen.kinematics(MECH, np.radians(30.0), omega=4 * np.pi, epsilon=2 * np.pi)
    assert k.phi == pytest.approx(np.pi / 6, rel=UNIT_REL) and k.omega == pytest.approx(4 * np.pi, rel=UNIT_REL)
    np.testing.assert_allclose(k.points["B"].velocity, ref.points["B"].velocity, rtol=UNIT_REL)
    ka = linkgen.kinematics(MECH, ["-10deg", "0.2rad", 0.3], omega="10rad/s")
    np.testing.assert_allclose(ka.phi, [np.radians(-10.0), 0.2, 0.3], rtol=UNIT_REL)
    f = linkgen.forces(MECH, "0.5rad", omega="10rad/s")
    assert f.balancing_torque == pytest.approx(linkgen.forces(MECH, 0.5, omega=10.0).balancing_torque, rel=UNIT_REL)


@pytest.mark.parametrize("call,message", [
    (lambda: linkgen.kinematics(MECH, "30"), "phi: an angle needs its unit: write 30deg or 30rad (or 30°), got '30'"),
    (lambda: linkgen.kinematics(MECH, "thirty"), "phi: expected an angle like 30deg, 30° or 0.52rad, got 'thirty'"),
    (lambda: linkgen.forces(MECH, 0.1, omega="fast"),
     "omega: expected a number in rad/s or one with its unit (e.g. 100rpm), got 'fast'"),
    (lambda: linkgen.kinematics(MECH, [0.1, "1e9rad"]),
     "phi[1]: expected an angle within ±10000 rad (linkgen's limits, see the README), got '1e9rad'"),
    (lambda: linkgen.kinematics(MECH, float("nan")), "phi: expected a finite number, got nan"),
])
def test_a_bad_angle_or_rate_names_the_argument_and_what_is_allowed(call, message):
    with pytest.raises(linkgen.ArgumentError) as info:
        call()
    assert str(info.value) == message


def test_the_cli_and_the_api_say_the_same_about_a_bad_angle():
    from linkgen.cli.common import _angle_arg
    import argparse

    with pytest.raises(argparse.ArgumentTypeError) as cli:
        _angle_arg("30")
    with pytest.raises(linkgen.ArgumentError) as api:
        linkgen.kinematics(MECH, "30")
    assert str(api.value) == f"phi: {cli.value}"


@pytest.mark.parametrize("model", ["fourbar", "cam_translating", "rssr"])
def test_every_family_through_one_api(model):
    """load → kinematics and summary for a planar linkage, a stand-alone cam and a spatial
    four-bar alike (forces and structure where the family has them)."""
    desc = linkgen.load(ROOT / "models" / f"{model}.toml")
    k = linkgen.kinematics(desc, "20deg")
    assert k.phi == pytest.approx(np.radians(20.0), rel=UNIT_REL) and k.text()
    json.dumps(k.to_dict(), allow_nan=False)
    s = linkgen.summary(desc)
    assert s.text() and json.dumps(s.to_dict(), allow_nan=False)
    if model != "cam_translating":
        assert linkgen.structure(desc).text() and linkgen.forces(desc, "20deg").text()
    else:
        with pytest.raises(linkgen.ArgumentError, match="stand-alone cams have no forces stage"):
            linkgen.forces(desc, 0.1)

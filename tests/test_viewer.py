"""The MJCF as a viewer opens it: a keyframe at the sketch moving at ω, the crank turning with no
control input, a floor and a camera sized to the mechanism, and a servo that linkgen's own runs
switch off."""

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from linkgen import assemble, load
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.scene import KEY, SERVO
from linkgen.mujoco.simulate import simulate

ROOT = Path(__file__).resolve().parents[1]
from conftest import MODELS, every_model  # linkages (cam files have tests of their own)
# The acceptance: the crank turns by ω·t within 1 % over one second.
TURN_TOL = 0.01
# ... or over this many turns if they take less than a second: a fast, stiff model's one second is
# millions of steps (Andrews' squeezer at 1000 rad/s: 2e6 steps of 0.5 µs, four minutes), and two
# turns reach the end of any partial range.
TURNS = 2
# How far the soft range limit lets the servo push the crank past the range's end [rad]
# (measured 0.0016 rad on the seven-link).
LIMIT_OVERSHOOT = 0.01


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(MODELS), ids=lambda p: p.stem)
def test_from_the_keyframe_the_crank_turns_at_omega(path):
    """The committed model's keyframe turns the crank at ω. On one model per family and feature
    (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo` runs."""
    mech = load(path)
    m = mujoco.MjModel.from_xml_path(str(path.with_suffix(".xml")))
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key(KEY).id)
    assert not d.ctrl.any()
    j = m.joint(mech.drive.joint)
    q0 = float(d.qpos[j.qposadr[0]])
    duration = min(1.0, TURNS * 2 * math.pi / mech.drive.omega)
    for _ in range(int(round(duration / m.opt.timestep))):  # a fixed count: MuJoCo resets time if unstable
        mujoco.mj_step(m, d)
    assert d.time == pytest.approx(duration, abs=2 * m.opt.timestep) and not d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number
    turned = float(d.qpos[j.qposadr[0]]) - q0
    if m.jnt_limited[j.id]:  # a partial range: the crank turns at ω up to the range's end and stops there
        expected = min(mech.drive.omega * d.time, float(j.range[1]) - q0)
        assert turned == pytest.approx(expected, rel=TURN_TOL, abs=LIMIT_OVERSHOOT)
    else:
        assert turned == pytest.approx(mech.drive.omega * d.time, rel=TURN_TOL)


def test_scene_scales_with_the_mechanism():
    text = (ROOT / "models" / "fourbar.toml").read_text()
    models = []
    for k in (1.0, 1000.0):
        big = text
        for a, b in (("A = [0.3, 0.0]", f"A = [{0.3 * k}, 0.0]"), ("B = [1.0143, 0.6999]", f"B = [{1.0143 * k}, {0.6999 * k}]"),
                     ("C = [1.0, 0.0]", f"C = [{1.0 * k}, 0.0]"), ("length = 0.3\n", f"length = {0.3 * k}\n"),
                     ("length = 1.0\n", f"length = {1.0 * k}\n"), ("length = 0.7\n", f"length = {0.7 * k}\n")):
            big = big.replace(a, b)
        from linkgen.pipeline.registry import loads

        models.append(mujoco.MjModel.from_xml_string(write_mjcf(assemble(loads(big)))))
    small, large = models
    assert large.geom("floor:plane").size[0] == pytest.approx(1000 * small.geom("floor:plane").size[0], rel=1e-9)
    assert large.cam("overview").pos0[2] == pytest.approx(1000 * small.cam("overview").pos0[2], rel=1e-9)
    bars = [i for i in range(small.ngeom) if ":bar:" in small.geom(i).name]
    assert bars and all(large.geom_size[i][0] == pytest.approx(1000 * small.geom_size[i][0], rel=1e-9) for i in bars)


def test_linkgen_runs_switch_the_servo_off():
    run = simulate(assemble(load(ROOT / "models" / "fourbar.toml")), samples=5)
    act = run.model.actuator(SERVO)
    assert not act.biasprm.any() and not act.gainprm.any()


def test_practical_build_writes_mujoco_defaults(tmp_path):
    from linkgen.cli.main import main

    out = tmp_path / "f.xml"
    assert main(["build", str(ROOT / "models" / "fourbar.toml"), "--practical", "-o", str(out)]) == 0
    m = mujoco.MjModel.from_xml_path(str(out))
    assert m.opt.timestep == 0.002 and m.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER
    assert m.eq_solref[0].tolist() == [0.02, 1.0] and math.isclose(m.eq_solimp[0][0], 0.9)

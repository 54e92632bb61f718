"""The cam's roller in MuJoCo is a sphere (linkgen.mujoco.cam.ROLLER_GEOM): a cylinder as thick
as the extruded profile puts its flat ends in the planes of the mesh's caps, and the roller then
left the cam in about a quarter of the steps (validation/cam_contact.py, docs/cams-mujoco.md).
The written model starts with the roller on the cam at every size."""

from __future__ import annotations

import mujoco
import numpy as np

from conftest import ROOT
from linkgen.families.cam.kinetics import state
from linkgen.mujoco.cam_run import run_cam
from linkgen.mujoco.log import no_log_file
from linkgen.pipeline.registry import load
from test_build_scales import FEW_PROFILE_POINTS, scale_description

MODELS = ROOT / "models"
# Over a quarter turn of cam_translating from the closed-form state, measured on mujoco 4.0:
# the sphere 8.1e-6 of the stroke, the cylinder 5.4e-5; the bound is twice the sphere's.
DISPLACEMENT_BOUND = 1.6e-5
# Steps with the roller off the cam over that quarter turn: the sphere 6 %, the cylinder 27 %.
OFF_BOUND = 0.12
# Steps of the written model from its initial state: the scale test's own count
# (tests/test_build_scales.py, _loads_and_steps); MuJoCo flagged BADQACC at the first.
STEPS = 20
# The z part of a contact normal in the cam's plane: 0 but for rounding; out through a cap it is ±1.
IN_PLANE = 1e-6


def test_the_roller_follows_the_profile_over_a_quarter_turn():
    cm = load(MODELS / "cam_translating.toml")
    run = run_cam(cm, revolutions=0.25)
    ref = state(cm, run.theta, float(np.mean(run.omega)))  # the closed form at MuJoCo's own angles
    stroke = float(np.ptp(cm.follower.output(np.linspace(0, 2 * np.pi, 3600, endpoint=False))[0]))
    assert np.abs(run.displacement - ref.displacement).max() / stroke <= DISPLACEMENT_BOUND
    assert 1.0 - float(np.mean(run.touching)) <= OFF_BOUND


@no_log_file()
def test_a_small_cam_starts_with_its_roller_on_the_cam(tmp_path, monkeypatch):
    # cam_oscillating at 1e-2 of its size (masses ∝ s³): its model started at the follower's
    # lowest position, the roller inside the cam (the lift at θ = 0 is 18°); the convex collision
    # pushed the sphere out through the extrusion's flat faces, along z, with ~1e18 N, and MuJoCo
    # flagged BADQACC at the first step
    import linkgen.mujoco.cam as cam

    monkeypatch.setattr(cam, "PROFILE_POINTS", FEW_PROFILE_POINTS)
    cm = load(scale_description(MODELS / "cam_oscillating.toml", tmp_path / "small.toml", 1e-2))
    model = mujoco.MjModel.from_xml_string(cam.cam_mjcf(cm))
    data = mujoco.MjData(model)
    lift = float(state(cm, [0.0]).displacement[0])  # closed form, 18° = π/10 (models/cam_oscillating.toml)
    assert model.qpos0[model.joint(cam.FOLLOWER).qposadr[0]] == -lift  # q = −(ψ − ψ0)
    for _ in range(STEPS):
        mujoco.mj_step(model, data)
    warned = {mujoco.mjtWarning(i).name: int(w.number) for i, w in enumerate(data.warning) if w.number}
    assert not warned
    mujoco.mj_forward(model, data)
    assert all(abs(data.contact[c].frame[2]) <= IN_PLANE for c in range(data.ncon))  # not out through a cap


def test_a_cam_linkage_roller_is_the_same_geom(monkeypatch):
    import linkgen.mujoco.cam_pair as cam_pair
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.mjcf import write_mjcf

    monkeypatch.setattr(cam_pair, "PROFILE_POINTS", FEW_PROFILE_POINTS)
    with no_log_file():
        m = mujoco.MjModel.from_xml_string(write_mjcf(assemble(load(MODELS / "cam_rocker_slider.toml"))))
    rollers = [m.geom(i) for i in range(m.ngeom) if m.geom(i).contype[0] == 2]
    assert rollers and all(g.type[0] == mujoco.mjtGeom.mjGEOM_SPHERE for g in rollers)


def test_the_cam_line_gives_the_contact_force_at_every_step():
    # before: only the 5° means, though the JSON carried the error at every step
    from linkgen.crosscheck.cam import CamCheck

    r = CamCheck("cam", {"errors_relative": {"displacement": 1e-5, "contact_force": 0.007, "cam_torque": 0.005,
                                             "contact_force_instantaneous": 1.0},
                         "profile_points": 4000, "windows": 72, "steps": 100},
                 {"displacement": 2e-4, "contact_force": 0.07, "cam_torque": 0.08})
    assert ("of their peaks as 5° means (at every step 1: not held, the follower leaves the faceted profile at some "
            "steps; docs/cams-mujoco.md), 100 steps") in r.summary()


def test_a_run_that_blows_up_is_an_error_not_a_comparison(tmp_path, monkeypatch):
    # cam_oscillating's lengths at 1e-2, its masses kept: a 5e-6 kg·m² arm under a 638 N·m spring
    # torque, thrown through the cam within a step. MuJoCo flagged BADQACC, restarted the model
    # from its initial state and ran on; validate compared the result: "displacement 3e299 of
    # the stroke", blamed on penetration
    import pytest

    import linkgen.mujoco.cam as cam
    from linkgen.errors import SimulationError

    monkeypatch.setattr(cam, "PROFILE_POINTS", FEW_PROFILE_POINTS)
    cm = load(scale_description(MODELS / "cam_oscillating.toml", tmp_path / "small.toml", 1e-2, masses=False))
    with no_log_file(), pytest.raises(SimulationError, match=r"diverged in MuJoCo at t = \S+ s: MuJoCo flagged "
                                                             r"BADQACC and restarted the model from its initial state"):
        run_cam(cm, revolutions=0.25)


def test_a_cam_linkage_run_that_blows_up_is_an_error(tmp_path, monkeypatch):
    # cam_rocker_slider's lengths at 1e-3, its masses kept: MuJoCo flags BADQACC at the first
    # step (with either roller) and restarts the model; validate compared the rest ("the roller
    # sank 3.31e-05 m into the profile … 1.1e+12 of the roller's travel")
    import pytest

    import linkgen.mujoco.cam_pair as cam_pair
    from linkgen.errors import SimulationError
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.cam_linkage import check_cam_linkage

    monkeypatch.setattr(cam_pair, "PROFILE_POINTS", FEW_PROFILE_POINTS)
    desc = scale_description(MODELS / "cam_rocker_slider.toml", tmp_path / "small.toml", 1e-3, masses=False)
    with pytest.raises(SimulationError, match=r"MuJoCo diverged at t = \S+ s \(step 0\): MuJoCo flagged BADQACC"):
        check_cam_linkage(assemble(load(desc)))

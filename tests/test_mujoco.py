"""MJCF generation and MuJoCo cross-validation with real MuJoCo (no mocks)."""

import json

import mujoco
import numpy as np
import pytest

from conftest import MODELS, RIGID_MODELS, ROOT, every_model
from linkgen import SimulationError, assemble, load
from linkgen.cli.main import main
from linkgen.crosscheck.compare import FORCE_TOL, GAP_TOL, INVERSE_TOL, REL_TOL, compare
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import Settings
from linkgen.mujoco.simulate import simulate

# Constraints at qpos0: the reference pose is the closed-form assembly, so only rounding of
# the %.17g-printed body placements remains.
QPOS0_TOL = 1e-12


def test_committed_xml_equals_the_writer_output(model_path):
    committed = model_path.with_suffix(".xml")
    assert committed.is_file(), f"missing {committed.name}: run `linkgen build models/`"
    assert committed.read_text() == write_mjcf(assemble(load(model_path))), (
        f"{committed.name} is stale: regenerate with `linkgen build models/`")


def test_compiles_with_constraints_satisfied_at_qpos0(model_path):
    from linkgen.mujoco.tree import spanning_tree

    asm = assemble(load(model_path))
    m = mujoco.MjModel.from_xml_string(write_mjcf(asm))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    # a connect has 3 rows, a gear coupling 1; a crank alone none
    assert d.ne == 3 * len(spanning_tree(asm).closures) + len(asm.mechanism.gears)
    assert d.ne == 0 or np.abs(d.efc_pos[: d.ne]).max() < QPOS0_TOL
    mech = load(model_path)
    tip = mech.link(mech.crank).points[-1]  # the crank's pin, a site of every model
    kind = mujoco.mjtJoint.mjJNT_SLIDE if mech.slide_drive else mujoco.mjtJoint.mjJNT_HINGE  # a prismatic drive's slide
    assert m.site(tip).id >= 0 and m.joint(mech.drive.joint).type == kind


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(RIGID_MODELS), ids=lambda p: p.stem)
def test_mujoco_matches_the_closed_form(path):
    """MuJoCo's run agrees with the closed form (`make demo` validates every model besides). On one model per
    family and feature (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make
    demo` runs."""
    asm = assemble(load(path))
    mech = asm.mechanism
    cmp = compare(asm, simulate(asm))
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad
    assert cmp.gap.max_abs_error < GAP_TOL * cmp.size
    # every pair's force is compared by both routes, each against its named tolerance
    for prefix, tol in (("", FORCE_TOL), ("inverse.", INVERSE_TOL)):
        names = [f"{prefix}balancing_torque"] + [f"{prefix}reactions.{j.name}.force" for j in mech.revolutes]
        names += [f"{prefix}prismatic.{p.name}.{q}" for p in mech.prismatics for q in ("normal_force", "moment")]
        for name in names:
            assert cmp.quantities[name].tolerance == tol, name
    kinematic = [k for k in cmp.quantities if k.startswith(("points.", "links.", "sliders."))]
    assert kinematic and all(cmp.quantities[k].tolerance == REL_TOL for k in kinematic)
    assert cmp.quantities["reduced_inertia"].tolerance == FORCE_TOL


def test_validate_json_shape(capsys):
    assert main(["validate", str(ROOT / "models" / "fourbar.toml"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "fourbar" and out["ok"] is True
    q = out["quantities"]["points.B.velocity"]
    assert set(q) == {"max_abs_error", "peak", "scale", "relative_error", "tolerance", "ok"}
    assert "links.rocker.angular_acceleration" in out["quantities"]
    assert out["loop_gap"]["ok"] is True and out["loop_gap"]["relative"] < GAP_TOL
    assert out["settings"]["timestep"] > 0 and out["diagnosis"] == [] and out["left_out"] == []


# One bundled model of each kind the report writes rows and sections for: a planar linkage, a
# stand-alone cam, a cam on a linkage's crank, a spatial chain. Every other model is run in
# MuJoCo by its own test (test_mujoco_matches_the_closed_form, test_spatial_mujoco, the cam
# tests); the whole folder is ``make demo``'s job (several minutes on two cores).
REPORT_MODELS = ("fourbar", "cam_translating", "cam_rocker_slider", "spherical_fourbar")


def test_report_is_written(tmp_path):
    models, out = tmp_path / "models", tmp_path / "report"
    models.mkdir()
    for name in REPORT_MODELS:
        (models / f"{name}.toml").write_bytes((ROOT / "models" / f"{name}.toml").read_bytes())
    assert main(["validate", str(models), "--report", str(out)]) == 0
    text = (out / "README.md").read_text()
    assert "| fourbar | yes |" in text
    assert (out / "fourbar_kinematics.png").stat().st_size > 10_000
    for name in REPORT_MODELS:
        assert f"| {name} | yes |" in text, name
    assert "## cam_rocker_slider (a cam on the crank)" in text and "## spherical_fourbar (spatial " in text


def test_constant_angular_acceleration_is_followed():
    asm = assemble(load(ROOT / "models" / "fourbar.toml"))
    run = simulate(asm, epsilon=5.0)
    eps = run.samples.crank[2]
    assert np.abs(eps - 5.0).max() < 0.05  # the rotor inertia (armature) keeps ε within 1%
    cmp = compare(asm, run)  # kinematics and forces at the measured (φ, ω, ε), every quantity on target
    bad = {k: q.relative_error for k, q in cmp.quantities.items() if not q.ok}
    assert not bad, bad


def test_a_run_whose_loops_come_apart_is_an_error():
    asm = assemble(load(ROOT / "models" / "fourbar.toml"))
    # loose loops: impedance 0.5 lets half the loop acceleration a0 ~ 25 m/s² through, gap ~ 0.25·τ²·a0 ~ 0.016 m
    coarse = Settings(timestep=0.001, timeconst=0.05, impedance=0.5, armature=1e4)
    with pytest.raises(SimulationError, match=r"the loop gap reached .* m \(.* of the mechanism's size, limit 0.0001\) "
                                              r"at crank angle .*° \(t = .* s\) with timestep 0.001 s and loop time "
                                              r"constant 0.05 s"):
        simulate(asm, settings=coarse)


def test_cli_errors(tmp_path, capsys):
    assert main(["build", str(tmp_path / "none.toml")]) == 2
    assert "no such description file" in capsys.readouterr().err
    assert main(["simulate", str(ROOT / "models" / "fourbar.toml"), "--omega", "-1"]) == 2
    assert "omega: must be > 0 rad/s for a MuJoCo run" in capsys.readouterr().err


def test_simulate_writes_every_quantity(tmp_path):
    npz, csv_path = tmp_path / "run.npz", tmp_path / "run.csv"
    model = str(ROOT / "models" / "seven_link.toml")
    assert main(["simulate", model, "--out", str(npz)]) == 0
    data = np.load(npz)
    assert data["qpos"].shape[0] == data["t"].shape[0] == data["phi"].shape[0] == 360
    assert data["B:rocker-rod.force"].shape == (data["phi"].shape[0], 2)
    assert {"block.normal_force", "slider.moment", "drive_torque", "balancing_torque",
            "reduced_inertia"} <= set(data.files)
    assert data["loop_gap"].max() < GAP_TOL
    assert main(["simulate", model, "--out", str(csv_path)]) == 0
    header = csv_path.read_text().splitlines()[0].split(",")
    assert "C.force.x [N]" in header and "slider.normal_force [N]" in header
    assert main(["simulate", model, "--out", str(tmp_path / "run.txt")]) == 2

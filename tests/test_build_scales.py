"""`build` makes a MuJoCo model of any description within linkgen's limits: the bundled models
scaled down and up, spatial four-bars standing still or turning backwards; `build DIR` builds
every file and reports each failure."""

import math
import re
import shutil
from pathlib import Path

import mujoco
import numpy as np
import pytest
import tomlkit

from conftest import ROOT
from linkgen.cli.main import main
from linkgen.mujoco.log import no_log_file

MODELS = ROOT / "models"
ALL_MODELS = sorted(MODELS.glob("*.toml"))
SPATIAL = ["rssr.toml", "rssp.toml", "bennett.toml", "spherical_fourbar.toml"]

# Keys holding a length [m] (besides [points] and plate shapes): a number, or text with a unit.
_LENGTH_KEYS = {"length", "offset", "base_radius", "roller_radius", "arm_length", "pivot_distance", "module",
                "height", "com", "pin_radius", "block_length", "start", "stop"}  # start, stop: a slider drive's range
_LENGTH_UNITS = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}
# A prismatic drive's keys, each ∝ s (the angular speeds kept, so its speed and acceleration scale
# with the lengths); given as numbers in the bundled models.
_SLIDE_DRIVE_KEYS = {"start", "stop", "velocity", "acceleration"}
# Exponent of the length scale s in each other dimensional key, the material (density in kg/m³)
# kept: masses ∝ s³, so kg/m ∝ s², kg/m² ∝ s, kg·m² ∝ s⁵; forces ∝ s³ (weights), torques and
# powers ∝ s⁴ (the speeds kept), spring rates ∝ s².
_EXPONENT = {"density": 2, "areal_density": 1, "mass": 3, "inertia": 5, "flywheel_inertia": 5, "rotor_inertia": 5,
             "spring_rate": 2, "spring_preload": 3, "force": 3, "torque": 4, "stall_torque": 4,
             "torque_constant": 4, "rated_power": 4, "stiffness": 4, "damping": 4,
             "velocity": 1, "acceleration": 1}  # a slider drive's m/s and m/s², the times kept


def _length(value) -> float:
    if isinstance(value, str):
        for unit in sorted(_LENGTH_UNITS, key=len, reverse=True):
            if value.endswith(unit):
                return float(value[:-len(unit)]) * _LENGTH_UNITS[unit]
        raise ValueError(value)
    return float(value)


def _scaled(value, key: str, parents: tuple, s: float, mass_exponent_shift: int):
    if isinstance(value, list):
        return [_scaled(v, key, parents, s, mass_exponent_shift) for v in value]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        return value
    if parents[:1] == ("points",) or "shape" in parents or key in _LENGTH_KEYS:
        return _length(value) * s
    if parents == ("drive",) and key in _SLIDE_DRIVE_KEYS:  # a prismatic drive's stroke and its rates
        return _length(value) * s
    if key in _EXPONENT and not isinstance(value, str):
        return float(value) * s ** (_EXPONENT[key] - mass_exponent_shift)
    return value


def _walk(table, parents: tuple, s: float, shift: int) -> None:
    for key in list(table.keys()):
        value = table[key]
        if isinstance(value, dict):
            _walk(value, parents + (key,), s, shift)
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for item in value:
                _walk(item, parents + (key,), s, shift)
        else:
            table[key] = _scaled(value.unwrap() if hasattr(value, "unwrap") else value, key, parents, s, shift)


def scale_description(src: Path, dst: Path, s: float, *, masses: bool = True) -> Path:
    """``src`` with every length times ``s`` and, with ``masses``, every mass times s³ (the same
    material), the other quantities consistently; without, the masses (and inertias ∝ s²) kept."""
    doc = tomlkit.parse(src.read_text(encoding="utf-8"))
    _walk(doc, (), s, 0 if masses else 3)
    dst.write_text(tomlkit.dumps(doc), encoding="utf-8")
    return dst


@no_log_file()
def _loads(xml: Path) -> mujoco.MjData:
    """Load ``xml`` in MuJoCo and evaluate its first keyframe: finite, no warning."""
    model = mujoco.MjModel.from_xml_path(str(xml))
    data = mujoco.MjData(model)
    if model.nkey:
        mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    assert not any(w.number for w in data.warning), xml.name
    assert np.all(np.isfinite(data.qacc)), xml.name
    return data


@no_log_file()
def _loads_and_steps(xml: Path, steps: int = 20) -> mujoco.MjData:
    """Load ``xml`` in MuJoCo and step it from its first keyframe: no warning (MuJoCo resets a
    diverging state and only counts a warning, so finite values alone prove nothing)."""
    model = mujoco.MjModel.from_xml_path(str(xml))
    data = mujoco.MjData(model)
    if model.nkey:
        mujoco.mj_resetDataKeyframe(model, data, 0)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    warned = {mujoco.mjtWarning(i).name: int(w.number) for i, w in enumerate(data.warning) if w.number}
    assert not warned, (xml.name, warned)
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel)), xml.name
    return data


# Vertices of a cam's profile mesh in these tests: MuJoCo's compiler takes 4 s per cam at the
# writer's 4000 (14 s for a linkage's two-cam disc); the sizes under test (mesh thickness,
# capsule lengths) do not depend on the count.
FEW_PROFILE_POINTS = 400


@pytest.fixture
def quick_cams(monkeypatch):
    import linkgen.mujoco.cam as cam
    import linkgen.mujoco.cam_pair as cam_pair

    monkeypatch.setattr(cam, "PROFILE_POINTS", FEW_PROFILE_POINTS)
    monkeypatch.setattr(cam_pair, "PROFILE_POINTS", FEW_PROFILE_POINTS)


@pytest.mark.parametrize("s", [1e-3, 1e3], ids=["1e-3", "1e3"])
def test_every_bundled_model_builds_scaled(tmp_path, capsys, quick_cams, s):
    for src in ALL_MODELS:
        scale_description(src, tmp_path / src.name, s)
    assert main(["build", str(tmp_path)]) == 0, capsys.readouterr().err
    for src in ALL_MODELS:
        _loads_and_steps((tmp_path / src.name).with_suffix(".xml"))


# The tests below scale lengths only (masses kept, so the mechanism is not a similar one): they
# check that the model is written, compiles and evaluates; a run's settings are not under test.
@pytest.mark.parametrize("name,s", [("fourbar.toml", 1e9), ("press.toml", 1e9), ("ga1.toml", 1e9),
                                    ("planetary_lever.toml", 1e6), ("machine_press.toml", 1e-20)])
def test_planar_pose_does_not_depend_on_the_scale(tmp_path, capsys, name, s):
    # The numeric pose's Jacobian mixed metres and radians: at 1e9 m its condition number passed
    # the singularity bound everywhere and build crashed; the masses kept (within the limits).
    desc = scale_description(MODELS / name, tmp_path / name, s, masses=False)
    assert main(["build", str(desc)]) == 0, capsys.readouterr().err
    _loads(desc.with_suffix(".xml"))


@pytest.mark.parametrize("name", SPATIAL)
@pytest.mark.parametrize("s", [1e-6, 1e12], ids=["1e-6", "1e12"])
def test_spatial_inertia_stays_positive_definite_at_any_size(tmp_path, capsys, name, s):
    desc = scale_description(MODELS / name, tmp_path / name, s, masses=False)
    assert main(["build", str(desc)]) == 0, capsys.readouterr().err
    _loads(desc.with_suffix(".xml"))


@pytest.mark.parametrize("name", ["cam_translating.toml", "cam_flat_face.toml", "cam_oscillating.toml",
                                  "cam_rocker_slider.toml", "g123.toml", "ga31.toml"])
def test_meshes_of_a_micrometre_mechanism_are_thick_enough_for_mujoco(tmp_path, capsys, quick_cams, name):
    # At 1e-6 of the size (masses kept) the cam's profile and the plates enclosed less than
    # MuJoCo's least mesh volume (1e-15 m³) and the follower's stem was shorter than MuJoCo's
    # least capsule: build raised MuJoCo's ValueError.
    desc = scale_description(MODELS / name, tmp_path / name, 1e-6, masses=False)
    assert main(["build", str(desc)]) == 0, capsys.readouterr().err
    _loads(desc.with_suffix(".xml"))


def test_a_cam_too_small_for_any_mesh_is_a_clear_error(tmp_path, capsys, quick_cams):
    # 1e-20 m: no extrusion gives MuJoCo's least mesh volume with a hull its qhull can build
    desc = scale_description(MODELS / "cam_translating.toml", tmp_path / "tiny.toml", 1e-20, masses=False)
    assert main(["build", str(desc)]) == 2
    err = capsys.readouterr().err
    assert re.fullmatch(rf"linkgen: error: {re.escape(str(desc))}: the cam's profile \(size \S+ m, area \S+ m²\) is "
                        r"too small for MuJoCo: a mesh must enclose at least 1e-15 m³, which would take a disc \S+ "
                        r"times thicker than wide, beyond what MuJoCo's convex hull resolves; MuJoCo cannot model "
                        r"this cam\n", err), err
    assert "Traceback" not in err and not desc.with_suffix(".xml").exists()


# Loop gap allowed after the short run, as a fraction of the size: the validation's own bound
# (linkgen.crosscheck.spatial.GAP_TOL is 1e-6), not reached in 200 steps from the sketch.
GAP_FRACTION = 1e-6


@pytest.mark.parametrize("omega", [0.0, -10.0])
@pytest.mark.parametrize("name", SPATIAL)
def test_spatial_build_at_zero_or_negative_omega(tmp_path, capsys, name, omega):
    text = (MODELS / name).read_text(encoding="utf-8")
    doc = tomlkit.parse(text)
    doc["drive"]["omega"] = omega
    desc = tmp_path / name
    desc.write_text(tomlkit.dumps(doc), encoding="utf-8")
    assert main(["build", str(desc)]) == 0, capsys.readouterr().err
    model = mujoco.MjModel.from_xml_path(str(desc.with_suffix(".xml")))
    assert model.opt.timestep > 0 and math.isfinite(model.opt.timestep)
    data = _loads_and_steps(desc.with_suffix(".xml"), steps=200)
    crank = model.joint(0)
    assert math.copysign(1.0, data.qvel[crank.dofadr[0]]) == math.copysign(1.0, omega) or omega == 0.0
    eq = model.equality(0)
    b1 = data.xpos[eq.obj1id] + data.xmat[eq.obj1id].reshape(3, 3) @ model.eq_data[eq.id, 0:3]
    b2 = data.xpos[eq.obj2id] + data.xmat[eq.obj2id].reshape(3, 3) @ model.eq_data[eq.id, 3:6]
    size = float(np.ptp(np.array([model.site_pos[i] for i in range(model.nsite)]), axis=0).max())
    assert np.linalg.norm(b1 - b2) <= GAP_FRACTION * max(size, 1.0)


def test_build_folder_goes_on_past_a_crash(tmp_path, capsys, monkeypatch):
    import linkgen.cli.mujoco as cli_mujoco

    for name in ("a.toml", "b.toml", "c.toml"):
        shutil.copy(MODELS / "fourbar.toml", tmp_path / name)
    real = cli_mujoco._build_one

    def flaky(path, out, *options):
        if path.name == "b.toml":
            raise ValueError("Error: fromto points too close in geom")  # what MuJoCo raised unguarded
        return real(path, out, *options)

    monkeypatch.setattr(cli_mujoco, "_build_one", flaky)
    assert main(["build", str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [f"wrote {tmp_path / 'a.xml'}",
                   f"linkgen: error: {tmp_path / 'b.toml'}: internal error (ValueError: Error: fromto points too close "
                   "in geom); please report it with this file",
                   f"wrote {tmp_path / 'c.xml'}",
                   "linkgen: 1 of 3 descriptions failed"]
    assert (tmp_path / "c.xml").exists() and not (tmp_path / "b.xml").exists()


def test_a_short_link_in_a_large_spatial_chain_has_a_valid_inertia(tmp_path):
    """rssp with its crank pin moved 150 km out (fuzz campaign seed 2028): the 0.2 m rocker's
    inertia along its line, from a rod as thick as the 150 km chain, broke the triangle
    inequality of principal moments that MuJoCo's compiler checks (A + B >= C)."""
    import re

    import mujoco

    import linkgen
    from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf

    text = (MODELS / "rssp.toml").read_text()
    text, n = re.subn(r"(?m)^A = \[0\.15,", "A = [150000.0,", text)
    assert n == 1
    (tmp_path / "big.toml").write_text(text)
    mech = linkgen.load(tmp_path / "big.toml")
    mujoco.MjModel.from_xml_string(write_spatial_mjcf(mech))  # raised ValueError before

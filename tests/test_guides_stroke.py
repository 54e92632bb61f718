"""Guides along the stroke: in the MJCF, every prismatic pair's guide spans the slider point's
travel over the drive's range (as the closed form gives it), plus the block and a named overhang
at each end, and nothing more; the guides are drawings only (the dynamics ignore them)."""

import math
import tomllib

import mujoco
import numpy as np
import pytest
from lxml import etree

from conftest import CAM_MODELS, MODELS, ROOT, SPATIAL_MODELS
from linkgen import assemble, from_dict, load
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.pose import mechanism_size
from linkgen.families.spatial.kinematics import assembled_chain
from linkgen.families.spatial.kinematics import solve as spatial_solve
from linkgen.mujoco.cam import CONTACT, FOLLOWER, cam_mjcf
from linkgen.mujoco.guides import GUIDE_OVERHANG, GUIDE_SIZE
from linkgen.mujoco.mjcf import BLOCK_SIZE, write_mjcf
from linkgen.mujoco.options import PLACEHOLDER
from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf

SLIDER_MODELS = [p for p in MODELS if load(p).prismatics]
# Crank angles at which the slider's travel is taken: every 0.1° of a turn, ten times finer than
# the writer's own sampling, so a guide sized from a coarser or a wrong set of angles shows.
DENSE = 3601
# The guide's centre lies on the guide line: the slider's point, solved in closed form, is off the
# box's axis only by the rounding of %.17g placements and of the frame change (~1e-16 of the size);
# 1e-9 of the size leaves a wide margin and still catches a guide placed beside its line.
ON_LINE_TOL = 1e-9
# Lengths compared to rounding: the box half-length is printed with %.17g (1 ulp), the travel is
# recomputed here from other floating-point operations (~1e-15 of the size).
LENGTH_TOL = 1e-12


def _local_travel(asm, pair) -> np.ndarray:
    """The slider point's positions (n, 2) [m] over DENSE angles of the drive range, in the guide
    link's frame (the frame of the MJCF body that carries the guide geom)."""
    mech = asm.mechanism
    pj = next(p for p in mech.prismatics if p.name == pair)
    kin = solve(asm, np.linspace(mech.drive.start, mech.drive.stop, DENSE), on_singular="mark")
    p = np.asarray(kin.points[pj.point].p)
    if pj.guide == GROUND:
        return p
    pose = kin.links[pj.guide]
    d = p - np.asarray(pose.origin.p)
    th = np.asarray(pose.angle.v)
    c, s = np.cos(th), np.sin(th)
    return np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=-1)


def _guide_box(model, link: str, pair: str) -> tuple[np.ndarray, np.ndarray, float]:
    """The guide geom's centre (2,) [m] and axis (2,) in its body's frame, and its half-length [m]."""
    g = model.geom(f"{link}:guide:{pair}")
    rot = np.zeros(9)
    mujoco.mju_quat2Mat(rot, g.quat)
    return np.asarray(g.pos[:2]), rot.reshape(3, 3)[:2, 0], float(g.size[0])


def _checked_guides(asm) -> dict[str, tuple[float, float]]:
    """For every prismatic pair: (the guide's length, the slider's stroke) [m], after checking that
    the guide lies on the slider's line and covers every position the slider reaches."""
    mech = asm.mechanism
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    size = mechanism_size(mech)
    out = {}
    for pj in mech.prismatics:
        centre, axis, half = _guide_box(model, pj.guide, pj.name)
        r = _local_travel(asm, pj.name) - centre
        along = r @ axis
        across = r @ np.array([-axis[1], axis[0]])
        assert np.abs(across).max() <= ON_LINE_TOL * size, f"{mech.name}: guide {pj.name} is beside its line"
        assert -half <= along.min() and along.max() <= half, (
            f"{mech.name}: guide {pj.name} spans ±{half:.6g} m about its centre; the slider reaches "
            f"{along.min():.6g} to {along.max():.6g} m")
        out[pj.name] = (2 * half, float(np.ptp(along)))
    return out


@pytest.mark.parametrize("path", SLIDER_MODELS, ids=[p.stem for p in SLIDER_MODELS])
def test_guide_spans_the_stroke_and_no_more(path):
    asm = assemble(load(path))
    size = mechanism_size(asm.mechanism)
    block = 2 * BLOCK_SIZE[0] * size
    least = 2 * GUIDE_SIZE[0] * size
    for pair, (length, stroke) in _checked_guides(asm).items():
        longest = max(stroke + 2 * GUIDE_OVERHANG * block + block, least)
        assert length <= longest + LENGTH_TOL * size, (
            f"{path.stem}: guide {pair} is {length:.6g} m long for a {stroke:.6g} m stroke (at most {longest:.6g} m)")
        assert length >= least - LENGTH_TOL * size


def test_press_guide_runs_along_the_ram_stroke():
    """The issue's case: the press's ram runs at x = 0.3–0.5 m on a guide through O."""
    asm = assemble(load(ROOT / "models" / "press.toml"))
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    centre, axis, half = _guide_box(model, GROUND, "ram")
    np.testing.assert_allclose(axis, [1.0, 0.0], atol=1e-15)
    lo, hi = centre[0] - half, centre[0] + half
    assert lo < 0.3 and hi > 0.5 and lo > 0.2 and hi < 0.6, (lo, hi)


def test_a_slider_that_hardly_moves_keeps_a_visible_guide():
    """A 1 mm crank on a 0.4 m rod moves its slider 2 mm: the guide keeps its least length."""
    data = tomllib.loads((ROOT / "models" / "press.toml").read_text())
    data["points"] |= {"A": [0.001, 0.0], "B": [0.401, 0.0]}
    data["links"]["crank"]["length"] = 0.001
    asm = assemble(from_dict(data))
    (length, stroke), = _checked_guides(asm).values()
    np.testing.assert_allclose(stroke, 0.002, rtol=1e-6)
    assert length == pytest.approx(2 * GUIDE_SIZE[0] * mechanism_size(asm.mechanism), rel=LENGTH_TOL)


def _assert_guides_are_drawings_only(text: str, steps: int) -> None:
    """The model ``text`` and the same with its guide geoms removed step bit for bit alike."""
    root = etree.fromstring(text.encode())
    guides = [g for g in root.iter("geom") if ":guide:" in g.get("name", "")]
    assert guides
    for g in guides:
        g.getparent().remove(g)
    runs = []
    for xml in (text, etree.tostring(root, encoding="unicode")):
        model = mujoco.MjModel.from_xml_string(xml)
        data = mujoco.MjData(model)
        if model.nkey:
            mujoco.mj_resetDataKeyframe(model, data, 0)
        data.ctrl[:] = 1.0
        mujoco.mj_step(model, data, steps)
        runs.append(np.concatenate([data.qpos, data.qvel, data.efc_force[: data.nefc]]))
    np.testing.assert_array_equal(runs[0], runs[1])
    assert np.isfinite(runs[0]).all()


@pytest.mark.parametrize("name", ["press", "seven_link"])
def test_guides_are_drawings_only(name):
    _assert_guides_are_drawings_only(write_mjcf(assemble(load(ROOT / "models" / f"{name}.toml"))), steps=200)


def test_a_range_that_cannot_be_traced_gets_guides_at_the_sketch():
    """The seven-link over a whole turn (it assembles over -76°..61° only): the MJCF is still
    written, each guide centred on its slider's sketch position with the least length."""
    data = tomllib.loads((ROOT / "models" / "seven_link.toml").read_text())
    data["drive"] = {k: v for k, v in data["drive"].items() if k not in ("range", "start", "stop")}
    asm = assemble(from_dict(data))
    mech = asm.mechanism
    assert mech.drive.stop - mech.drive.start == pytest.approx(2 * math.pi)
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    size = mechanism_size(mech)
    kin = solve(asm, np.array([asm.sketch_phi]))
    for pj in mech.prismatics:
        centre, axis, half = _guide_box(model, pj.guide, pj.name)
        p = np.asarray(kin.points[pj.point].p[0])
        if pj.guide != GROUND:
            pose = kin.links[pj.guide]
            d, th = p - np.asarray(pose.origin.p[0]), float(pose.angle.v[0])
            p = np.array([math.cos(th) * d[0] + math.sin(th) * d[1], -math.sin(th) * d[0] + math.cos(th) * d[1]])
        along = float((p - centre) @ axis)
        assert abs(along) <= LENGTH_TOL * size, (pj.name, along)
        assert half == pytest.approx(GUIDE_SIZE[0] * size, rel=LENGTH_TOL)


SPATIAL_SLIDERS = [p for p in SPATIAL_MODELS if load(p).slides]


@pytest.mark.parametrize("path", SPATIAL_SLIDERS, ids=[p.stem for p in SPATIAL_SLIDERS])
def test_spatial_guide_spans_the_stroke_and_no_more(path):
    """A spatial slider's fixed guide (RSSP; PSSR and PSSP's input): along its line, over the
    slider's stroke in a turn (over the input's range)."""
    mech = load(path)
    chain = assembled_chain(mech)
    text = write_spatial_mjcf(mech)
    model = mujoco.MjModel.from_xml_string(text)
    block = 2 * model.geom(f"{mech.slides[0].slider}:block").size[0]
    for sl in mech.slides:
        g = model.geom(f"{GROUND}:guide:{sl.name}")
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, g.quat)
        axis, half = rot.reshape(3, 3)[:, 2], float(g.size[2])  # the box's long axis is its z
        r = spatial_solve(mech, np.linspace(*chain.input_range, DENSE), chain).points[sl.point].d[0] - g.pos
        along = r @ axis
        assert np.linalg.norm(r - np.outer(along, axis), axis=1).max() <= ON_LINE_TOL * chain.size
        assert -half <= along.min() and along.max() <= half, (half, along.min(), along.max())
        stroke = float(np.ptp(along))
        longest = max(stroke + 2 * GUIDE_OVERHANG * block + block, 2 * GUIDE_SIZE[0] * chain.size)
        assert 2 * half <= longest + LENGTH_TOL * chain.size, (2 * half, stroke, longest)
    _assert_guides_are_drawings_only(text, steps=500)


TRANSLATING_CAMS = [p for p in CAM_MODELS if load(p).follower.kind == "translating"]


@pytest.mark.parametrize("path", TRANSLATING_CAMS, ids=[p.stem for p in TRANSLATING_CAMS])
def test_cam_follower_guide_spans_the_stroke_and_no_more(path):
    """A translating follower's fixed guide runs along its line over the lift of a whole turn."""
    cm = load(path)
    f = cm.follower
    text = cam_mjcf(cm)
    model = mujoco.MjModel.from_xml_string(text)
    size = 2 * float(np.hypot(*f.pitch_curve(np.linspace(0, 2 * math.pi, 73))[0].T).max())  # the writer's scale
    g = model.geom(f"{GROUND}:guide:{FOLLOWER}")
    np.testing.assert_array_equal(g.quat, [1.0, 0.0, 0.0, 0.0])  # along y, the follower's slide axis
    assert model.jnt_axis[model.joint(FOLLOWER).id].tolist() == [0.0, 1.0, 0.0]
    assert abs(g.pos[0] - f.offset) <= ON_LINE_TOL * size
    y = f.lift_origin + f.output(np.linspace(0.0, 2 * math.pi, DENSE))[0]  # the follower's origin
    half = float(g.size[1])
    assert g.pos[1] - half <= y.min() and y.max() <= g.pos[1] + half, (g.pos[1], half, y.min(), y.max())
    contact = model.geom(CONTACT)  # a flat face's half-thickness along y, else the roller's radius
    block = 2 * float(contact.size[1] if f.flat else contact.size[0])
    longest = max(float(np.ptp(y)) + 2 * GUIDE_OVERHANG * block + block, 2 * GUIDE_SIZE[0] * size)
    assert 2 * half <= longest + LENGTH_TOL * size, (2 * half, longest)
    _assert_guides_are_drawings_only(text, steps=2000)

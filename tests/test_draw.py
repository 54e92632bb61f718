"""Pictures of the mechanism: skeleton drawings and position plans, animations, MuJoCo offscreen
frames, through the console script and the API. Each picture is checked for what it must be
(format, size, frame count), and the MuJoCo frame against the closed form: the crank's pixels
sit where the camera projects the closed-form crank."""

import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import mujoco
import numpy as np
import pytest
from PIL import Image

from linkgen import assemble, load
from linkgen.cli.draw import angles_arg
from linkgen.draw.animate import drawn_frames, frame_angles, save_animation
from linkgen.draw.plan import DPI, FIGSIZE, plan_figure, skeleton_figure
from linkgen.draw.render import render_mechanism
from linkgen.mujoco.scene import CAMERA_ASPECT
from linkgen.families.planar.positions import drive_angles, positions

ROOT = Path(__file__).resolve().parents[1]
from conftest import MODELS, every_model  # linkages (cam files have tests of their own)
SCRIPT = shutil.which("linkgen", path=str(Path(sys.executable).parent))
FIG_PX = (round(FIGSIZE[0] * DPI), round(FIGSIZE[1] * DPI))
# The crank's pixels against the projected closed-form crank: within the capsule's projected
# radius plus this many pixels (rounding of the projection, antialiased edges).
CRANK_PIXELS = 4.0


def run(*args, env=None):
    return subprocess.run([SCRIPT, *map(str, args)], capture_output=True, text=True, timeout=300, env=env)


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(MODELS), ids=lambda p: p.stem)
def test_draw_and_position_plan_of_every_bundled_model(path, tmp_path):
    """A skeleton and a position plan, PNGs of the stated size with something drawn. On one model per family
    and feature (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo`
    runs."""
    mech = load(path)
    paths = positions(mech, drive_angles(mech))
    skeleton_figure(mech, mech.drive.start, tmp_path / "one.png", paths=paths)
    plan_figure(mech, drive_angles(mech, 7)[:-1], tmp_path / "plan.png", paths=paths)
    for name in ("one.png", "plan.png"):
        with Image.open(tmp_path / name) as im:
            assert im.format == "PNG" and im.size == FIG_PX
            px = np.asarray(im.convert("RGB"), dtype=float)
            assert px.std() > 10.0  # something is drawn


def test_draw_cli_formats_and_plan(tmp_path):
    fourbar = ROOT / "models" / "fourbar.toml"
    for suffix, magic in ((".png", b"\x89PNG"), (".svg", b"<?xml"), (".pdf", b"%PDF")):
        out = tmp_path / f"f{suffix}"
        p = run("draw", fourbar, "--angle", "30deg", "-o", out)
        assert p.returncode == 0, p.stderr
        assert out.read_bytes()[:len(magic)] == magic
    p = run("draw", fourbar, "--angles", "0:360:30", "-o", tmp_path / "plan.png")
    assert p.returncode == 0 and "12 positions" in p.stdout, p.stdout + p.stderr


def test_draw_cli_errors_are_one_line():
    seven = ROOT / "models" / "seven_link.toml"
    for args, words in ((("--angles", "0:360:30", "-o", "/tmp/x.png"), "outside the drive's range"),
                        (("--angle", "0deg", "-o", "/tmp/x.jpg"), ".png, .svg or .pdf"),
                        (("--angles", "0:360", "-o", "/tmp/x.png"), "START:STOP:STEP"),
                        (("--angle", "0deg", "--angles", "-60:40:10", "-o", "/tmp/x.png"), "cannot be combined")):
        p = run("draw", seven, *args)
        assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, p.stderr


def test_angles_spec():
    assert np.allclose(np.degrees(angles_arg("0:360:30")), np.arange(0, 360, 30))  # 360 repeats 0
    assert np.allclose(np.degrees(angles_arg("-60:40:10")), np.arange(-60, 41, 10))
    assert np.allclose(angles_arg("0:1:0.5rad"), [0.0, 0.5, 1.0])
    assert np.allclose(np.degrees(angles_arg("0deg:90deg:45deg")), [0, 45, 90])


def test_animation_gif_has_its_frames(tmp_path):
    out = tmp_path / "m.gif"
    p = run("animate", ROOT / "models" / "slider_crank_offset.toml", "--frames", "10", "-o", out)
    assert p.returncode == 0, p.stderr
    with Image.open(out) as im:
        assert im.format == "GIF" and im.n_frames == 10 and im.is_animated
        assert im.size == (480, 360)


def test_animation_mp4_has_its_frames(tmp_path):
    imageio = pytest.importorskip("imageio.v2")  # the test extra installs it; a plain install may not
    mech = load(ROOT / "models" / "fourbar.toml")
    frames = drawn_frames(mech, frame_angles(mech, 8))
    save_animation(frames, tmp_path / "m.mp4")
    reader = imageio.get_reader(tmp_path / "m.mp4")
    assert reader.count_frames() == 8


def test_frame_angles_cover_the_range():
    fourbar = load(ROOT / "models" / "fourbar.toml")
    assert np.allclose(frame_angles(fourbar, 4), [0, math.pi / 2, math.pi, 3 * math.pi / 2])  # no repeat of 0
    seven = load(ROOT / "models" / "seven_link.toml")
    a = frame_angles(seven, 5)
    assert a[0] == seven.drive.start and a[-1] == seven.drive.stop


def test_animation_beside_mujoco(tmp_path):
    out = tmp_path / "m.gif"
    p = run("animate", ROOT / "models" / "fourbar.toml", "--frames", "6", "--mujoco", "-o", out)
    assert p.returncode == 0, p.stderr
    with Image.open(out) as im:
        assert im.n_frames == 6 and im.size == (960, 360)  # two panels


def _projected(model, data, xy: np.ndarray, width: int, height: int) -> np.ndarray:
    """Pixel (column, row) of world points (k, 2) on z = 0 through the ``overview`` camera."""
    cam = model.camera("overview").id
    pos = data.cam_xpos[cam]
    f = 0.5 * height / math.tan(math.radians(0.5 * model.cam_fovy[cam]))
    depth = pos[2]
    col = 0.5 * width + (xy[:, 0] - pos[0]) * f / depth
    row = 0.5 * height - (xy[:, 1] - pos[1]) * f / depth
    return np.column_stack([col, row])


@pytest.mark.parametrize("name", ["fourbar", "g123", "slider_crank_offset", "seven_link"])
def test_render_puts_the_crank_where_the_closed_form_does(name, tmp_path):
    mech = load(ROOT / "models" / f"{name}.toml")
    phi = 0.5 * (mech.drive.start + mech.drive.stop) + 0.3
    width, height = 800, 600
    model, frames = render_mechanism(mech, phi, width, height)
    img = frames[0].astype(float)
    assert img.shape == (height, width, 3)
    red = (img[:, :, 0] > 170) & (img[:, :, 1] < 120) & (img[:, :, 2] < 110)  # the crank's material
    assert red.sum() > 20
    rows, cols = np.nonzero(red)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    crank = mech.link(mech.crank).points[:2]
    pts = positions(mech, [phi])
    ends = np.array([pts.points[crank[0]][0], pts.points[crank[1]][0]])
    a, b = _projected(model, data, ends, width, height)
    u = (b - a) / np.hypot(*(b - a))
    rel = np.column_stack([cols, rows]) - a
    along, across = rel @ u, np.abs(rel @ np.array([-u[1], u[0]]))
    radius_px = model.geom_size[model.geom(f"{mech.crank}:bar:{crank[0]}-{crank[1]}").id][0] * \
        (0.5 * height / math.tan(math.radians(0.5 * model.cam_fovy[0]))) / data.cam_xpos[0][2]
    # every crank pixel on the projected closed-form crank, and the crank seen along most of it
    assert across.max() < radius_px + CRANK_PIXELS
    length = float(np.hypot(*(b - a)))
    assert along.min() > -radius_px - CRANK_PIXELS and along.max() < length + radius_px + CRANK_PIXELS
    assert along.max() - along.min() > 0.6 * length


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_the_camera_frames_the_whole_motion(path):
    mech = load(path)
    model = mujoco.MjModel.from_xml_path(str(path.with_suffix(".xml")))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    height = 600
    width = round(CAMERA_ASPECT * height)
    xy = np.concatenate(list(positions(mech, drive_angles(mech, 145)).points.values()))
    px = _projected(model, data, xy, width, height)
    assert px[:, 0].min() > 0 and px[:, 0].max() < width and px[:, 1].min() > 0 and px[:, 1].max() < height


def test_render_cli_and_no_opengl(tmp_path):
    out = tmp_path / "f.png"
    p = run("render", ROOT / "models" / "press.toml", "--angle", "90deg", "-o", out)
    assert p.returncode == 0, p.stderr
    with Image.open(out) as im:
        assert im.size == (800, 600)
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["MUJOCO_GL"] = "glfw"  # a display backend with no display: no context can open
    p = run("render", ROOT / "models" / "press.toml", "-o", tmp_path / "g.png", env=env)
    assert p.returncode == 2 and "OpenGL" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert not (tmp_path / "g.png").exists()


def test_plates_in_the_mjcf_are_their_points_hull():
    from linkgen.families.planar.plate import convex_hull

    mech = load(ROOT / "models" / "g123.toml")
    model = mujoco.MjModel.from_xml_path(str(ROOT / "models" / "g123.xml"))
    plates = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) for g in range(model.ngeom)
              if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH]
    ternary = [link.name for link in mech.links if len(link.points) >= 3 and link.name != "ground"]
    assert sorted(p.split(":")[0] for p in plates) == sorted(ternary)
    asm = assemble(mech)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    for link in ternary:
        hull = convex_hull([asm.shapes[link].local[p] for p in mech.link(link).points])
        mesh = model.mesh(f"mesh:{link}").id
        first = model.mesh_vertadr[mesh]
        # MuJoCo moves a mesh to its principal frame and the geom's frame with it: in the world
        # the plate lies in the mechanism's plane, its top face the hull moved rigidly.
        geom = model.geom(f"{link}:plate").id
        verts = model.mesh_vert[first:first + model.mesh_vertnum[mesh]]
        world = data.geom_xpos[geom] + verts @ data.geom_xmat[geom].reshape(3, 3).T
        top = world[world[:, 2] > 0][:, :2]
        area = lambda h: 0.5 * abs(np.sum(h[:, 0] * np.roll(h[:, 1], -1) - np.roll(h[:, 0], -1) * h[:, 1]))  # noqa: E731
        assert area(convex_hull(top)) == pytest.approx(area(hull), rel=1e-6)

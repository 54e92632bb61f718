"""Pictures of spatial four-bars: the drawing (3-D view and three projections, skeleton or
position plan) of every bundled spatial model, its formats by suffix, and the report figures of
a real MuJoCo check. Each picture is checked for what it must be: its format, its pixel size
from matplotlib's figure size and dpi, and the crank and coupler drawn in their colours."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from conftest import SPATIAL_MODELS, every_model, input_values

from linkgen.draw.plan import DPI
from linkgen.draw.skeleton import CRANK, LINK
from linkgen.draw.spatial import FIGSIZE, draw_spatial, plot_spatial_check
from linkgen.pipeline.registry import load

ROOT = Path(__file__).resolve().parents[1]
RSSR = ROOT / "models" / "rssr.toml"
FIG_PX = (round(FIGSIZE[0] * DPI), round(FIGSIZE[1] * DPI))
PLAN = np.radians(np.arange(0.0, 360.0, 30.0))  # 0:360:30, as `linkgen draw --angles 0:360:30`
# A bar's colour, within antialiasing: pixels within this distance (0..255 per channel) count.
COLOUR_TOL = 12.0


SPATIAL = SPATIAL_MODELS  # every bundled spatial model, as the registry tells them apart


def _pixels(path: Path, size: tuple[int, int] | None = None) -> np.ndarray:
    """The RGB pixels of a well-formed PNG (of ``size`` when given), with something drawn on it."""
    with Image.open(path) as im:
        im.verify()
    with Image.open(path) as im:
        assert im.format == "PNG"
        if size is not None:
            assert im.size == size
        px = np.asarray(im.convert("RGB"), dtype=float)
    assert px.std() > 10.0
    return px


def _count(px: np.ndarray, colour) -> int:
    return int((np.abs(px - 255.0 * np.asarray(colour)).max(axis=2) < COLOUR_TOL).sum())


def test_the_spatial_models_are_found():
    assert RSSR in SPATIAL


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(SPATIAL), ids=lambda p: p.stem)
def test_skeleton_and_position_plan_of_every_spatial_model(path, tmp_path):
    """A spatial skeleton and position plan, the crank and coupler in their colours. On one model per family
    and feature (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo`
    runs."""
    mech = load(path)
    one = draw_spatial(mech, input_values(mech, [np.radians(30.0)]), tmp_path / "one.png")
    plan = draw_spatial(mech, input_values(mech, PLAN), tmp_path / "plan.png")
    assert (one, plan) == (tmp_path / "one.png", tmp_path / "plan.png")
    px_one, px_plan = _pixels(one, FIG_PX), _pixels(plan, FIG_PX)
    for px in (px_one, px_plan):  # the crank and the coupler are drawn, in four views, in their colours
        assert _count(px, CRANK) > 50 and _count(px, LINK) > 50
    assert not np.array_equal(px_one, px_plan)


def test_one_angle_as_a_float_and_formats_by_suffix(tmp_path):
    mech = load(RSSR)
    for suffix, magic in ((".png", b"\x89PNG\r\n\x1a\n"), (".svg", b"<?xml"), (".pdf", b"%PDF")):
        out = draw_spatial(mech, 0.0, tmp_path / f"rssr{suffix}")
        assert out.read_bytes()[:len(magic)] == magic, suffix
    assert b"<svg" in (tmp_path / "rssr.svg").read_bytes()[:2000]
    _pixels(tmp_path / "rssr.png", FIG_PX)
    draw_spatial(mech, PLAN, tmp_path / "plan.pdf")
    assert (tmp_path / "plan.pdf").read_bytes()[:4] == b"%PDF"


@pytest.fixture(scope="module")
def rssr_check(validated):
    """The RSSR's MuJoCo check (``check_spatial``, what ``linkgen validate`` runs), made once a session."""
    return load(RSSR), validated("rssr")


def test_report_figures_of_a_mujoco_check(rssr_check, tmp_path):
    mech, check = rssr_check
    names = plot_spatial_check(check, tmp_path, mech)
    assert names == [f"{check.model}_{kind}.png" for kind in ("coordinates", "velocities", "accelerations", "torque",
                                                               "loop_gap")]
    widths = {}
    for name in names:
        px = _pixels(tmp_path / name)
        assert px.shape[0] >= 300 and px.shape[1] >= 600
        widths[name] = px.shape[1]
    # without the mechanism the output's column is left out; the rest is drawn the same
    bare = tmp_path / "bare"
    bare.mkdir()
    assert plot_spatial_check(check, bare) == names
    for name in names:
        _pixels(bare / name)
    assert _pixels(bare / names[0]).shape[1] < widths[names[0]]
    assert sorted(p.name for p in tmp_path.iterdir() if p.is_file()) == sorted(names)

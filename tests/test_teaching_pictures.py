"""Every bundled model gives a skeleton with vectors, a velocity plan, an acceleration plan and an
interactive page; and what a student would misread in the pictures stays fixed: the cam's O on its
angle mark and its missing ω arrow, a default pose at a dead centre or folded in line, plate fills
stacking in a position plan, two blocks on one pin drawn alike."""

import math
from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

from conftest import CAM_MODELS, MODELS, ROOT, SPATIAL_MODELS, every_model
from linkgen.draw.plan import plan_figure, plt_module
from linkgen.draw.skeleton import LINK
from linkgen.families.planar.positions import positions
from linkgen.pipeline.registry import load, stage

ALL = MODELS + CAM_MODELS + SPATIAL_MODELS
PAGE_FRAMES = 6
# A dead centre or a folded pose: two lines within this angle [°] of each other read as one line.
IN_LINE_DEG = 10.0


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(ALL), ids=lambda p: p.stem)
def test_every_model_gives_vectors_plans_and_a_page(path, tmp_path):
    """Vectors, both plans and a page. On one model per family and feature (conftest.REPRESENTATIVE); on every
    bundled model in `make every-model`, which `make demo` runs."""
    desc = load(path)
    draw = stage(desc, "draw")
    for name, kw in (("vectors.png", dict(vectors="velocity")), ("velocity.png", dict(plan="velocity")),
                     ("acceleration.png", dict(plan="acceleration"))):
        _, data = draw(desc, None, tmp_path / name, **kw)
        assert data is not None
        with Image.open(tmp_path / name) as im:
            assert np.asarray(im.convert("L"), dtype=float).std() > 10.0  # something is drawn
    stage(desc, "page")(desc, tmp_path / "page.html", PAGE_FRAMES)
    html = (tmp_path / "page.html").read_text(encoding="utf-8")
    assert html.count('"name":"') >= PAGE_FRAMES and "Plotly.newPlot" in html


def test_cli_draw_vectors_plan_and_page(tmp_path, capsys):
    from linkgen.cli.main import main

    press = str(ROOT / "models" / "press.toml")
    for args, said in ((["--vectors", "forces", "--angle", "120deg"], "skeleton at φ = 120°, forces at"),
                       (["--plan", "acceleration", "--angle", "30deg"], "acceleration plan at φ = 30° (closes to")):
        assert main(["draw", press, *args, "-o", str(tmp_path / "x.png")]) == 0
        assert said in capsys.readouterr().out
    assert main(["page", press, "--frames", "4", "-o", str(tmp_path / "p.html")]) == 0
    assert capsys.readouterr().out.startswith(f"wrote {tmp_path / 'p.html'}: press, 4 crank angles")
    for args, message in ((["--parts", "--vectors", "velocity"], "--parts splits accelerations: it needs --vectors "
                           "acceleration"), (["--plan", "velocity", "--angles", "0:90:30"], "--plan draws at one crank "
                           "angle (--angle); it cannot be combined with --angles"),
                          (["--free-body", "7,8"], "--free-body '7,8': no such Assur group in press")):
        assert main(["draw", press, *args, "-o", str(tmp_path / "y.png")]) == 2
        err = capsys.readouterr().err
        assert message in err and "Traceback" not in err, err
        assert not (tmp_path / "y.png").exists()


def _segment_hits_box(p0, p1, box, n=400) -> bool:
    t = np.linspace(0.0, 1.0, n)[:, None]
    pts = p0 + t * (p1 - p0)
    return bool(np.any((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1) & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)))


@pytest.mark.parametrize("path", CAM_MODELS, ids=[p.stem for p in CAM_MODELS])
def test_cam_drawing_keeps_O_off_its_angle_mark_and_shows_omega(path):
    from linkgen.draw.cam import cam_figure

    plt = plt_module()
    cm = load(path)
    for deg in [*range(0, 360, 30), 56]:  # 56°: where O's old place sat on the mark
        th = math.radians(deg)
        fig = cam_figure(cm, th)
        ax = fig.axes[0]
        fig.canvas.draw()
        texts = {t.get_text(): t for t in ax.texts}
        assert "ω" in texts, f"{path.stem}: no ω arrow at {deg}°"
        box = texts["O"].get_window_extent()
        mark = ax.transData.transform([[0.0, 0.0], [0.9 * cm.follower.base_radius * math.cos(th),
                                                    0.9 * cm.follower.base_radius * math.sin(th)]])
        assert not _segment_hits_box(mark[0], mark[1], box), f"{path.stem}: O on the angle mark at {deg}°"
        plt.close(fig)


def _sin_between(u, v) -> float:
    return abs(float(u[0] * v[1] - u[1] * v[0])) / (float(np.linalg.norm(u)) * float(np.linalg.norm(v)))


@pytest.mark.parametrize("name", ["press", "slider_crank_offset", "fourbar", "g123", "scotch_yoke"])
def test_default_drawing_is_not_at_a_dead_centre(name, tmp_path):
    desc = load(ROOT / "models" / f"{name}.toml")
    what, _ = stage(desc, "draw")(desc, None, tmp_path / "d.png")
    phi = math.radians(float(what.split("φ = ")[1].split("°")[0]))
    mech = getattr(desc, "mechanism", desc)
    pos = positions(mech, [phi])
    pivot, pin = mech.link(mech.crank).points[:2]
    crank = pos.points[pin][0] - pos.points[pivot][0]
    for link in mech.links:
        if link.name != mech.crank and pin in link.points:
            for q in link.points:
                if q != pin:
                    rod = pos.points[q][0] - pos.points[pin][0]
                    assert _sin_between(crank, rod) >= math.sin(math.radians(IN_LINE_DEG)), (name, link.name, what)


def test_spatial_report_drawing_is_not_folded(monkeypatch, tmp_path):
    """Bennett at φ = 0 has its four joints on one line (stacked in the side view): the report's
    single drawing shows a pose whose joints span a plane."""
    import linkgen.draw.spatial as spatial
    from linkgen.pipeline.spatial_mujoco import figures

    drawn = []
    monkeypatch.setattr(spatial, "draw_spatial", lambda mech, angles, out, arrows=None: drawn.append(np.asarray(angles)))
    monkeypatch.setattr(spatial, "plot_spatial_check", lambda check, out, mech=None: [])
    desc = load(ROOT / "models" / "bennett.toml")
    figures(desc, SimpleNamespace(model="bennett"), tmp_path)
    one = next(a for a in drawn if a.size == 1)
    from linkgen.families.spatial.kinematics import solve

    pts = np.array([j.d[0][0] for j in solve(desc, one).points.values()])
    sv = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False)
    assert sv[1] >= math.sin(math.radians(IN_LINE_DEG)) * sv[0], (np.degrees(one), sv)


def test_position_plan_fills_no_plate_and_draws_a_guide_link_as_bars():
    plt = plt_module()
    mech = load(ROOT / "models" / "ga31.toml")
    fig = plan_figure(mech, np.radians(np.arange(0.0, 360.0, 45.0)))
    hulls = [p for p in fig.axes[0].patches if hasattr(p, "get_xy") and len(p.get_xy()) == 4
             and tuple(np.round(p.get_edgecolor()[:3], 3)) == tuple(np.round(LINK, 3))]
    plt.close(fig)
    assert hulls == []  # the coulisse (B, D, C) carries the slot: bars, not a filled triangle per position


def test_two_blocks_on_one_pin_are_told_apart():
    from linkgen.draw.plan import skeleton_figure

    plt = plt_module()
    mech = load(ROOT / "models" / "g123.toml")
    fig = skeleton_figure(mech, math.radians(30.0))
    blocks = [p.get_xy()[:4] for p in fig.axes[0].patches if hasattr(p, "get_xy") and len(p.get_xy()) == 5]
    plt.close(fig)
    areas = sorted(0.5 * abs(float(np.dot(b[:, 0], np.roll(b[:, 1], 1)) - np.dot(b[:, 1], np.roll(b[:, 0], 1))))
                   for b in blocks)
    assert len(areas) == 2 and areas[0] < 0.6 * areas[1], areas


# MuJoCo's curve on the page against the closed form's: one pixel of a 300-px plot is 1/300 of its
# range; MuJoCo agrees with the closed form far below that (validate: ~1e-6), so a curve off by a
# unit, a sign or a whole turn fails and a right one passes with room to spare.
MUJOCO_CURVE = 1.0 / 300.0


def test_page_draws_mujocos_curves_on_the_closed_forms(tmp_path):
    from dataclasses import replace

    from linkgen.draw.page_planar import mujoco_curves, planar_page
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.simulate import simulate

    asm = assemble(load(ROOT / "models" / "fourbar.toml"))
    data = planar_page(asm, 24)
    data = replace(data, mujoco=mujoco_curves(data, simulate(asm, samples=90).samples))
    assert set(data.mujoco) == set(data.curves) == {"rocker angle [°]", "balancing torque [N·m]"}
    fine = planar_page(asm, 720)
    for label, (phi, theirs) in data.mujoco.items():
        ours = np.interp(phi, fine.phi, fine.curves[label])
        span = float(np.ptp(fine.curves[label]))
        assert float(np.max(np.abs(theirs - ours))) <= MUJOCO_CURVE * span, label


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


@pytest.mark.parametrize("name", ["ga31", "fourbar", "press"])
def test_position_numbers_keep_clear_of_the_pins_name(name):
    """"0" drawn against "A" read "A0", a point's name."""
    plt = plt_module()
    mech = load(ROOT / "models" / f"{name}.toml")
    fig = plan_figure(mech, np.radians(np.arange(0.0, 360.0, 45.0)))
    fig.canvas.draw()
    texts = fig.axes[0].texts
    pin = mech.link(mech.crank).points[1]
    names = [t.get_window_extent() for t in texts if t.get_text() == pin]
    numbers = [t.get_window_extent() for t in texts if t.get_text().isdigit()]
    plt.close(fig)
    assert names and len(numbers) == 8
    assert not any(_overlap(n, b) for n in names for b in numbers)


@pytest.mark.parametrize("path", CAM_MODELS, ids=[p.stem for p in CAM_MODELS])
def test_default_cam_drawing_shows_the_follower_moving(path, tmp_path):
    cm = load(path)
    what, arrows = stage(cm, "draw")(cm, None, tmp_path / "c.png", vectors="velocity")
    v_b = next(a.vector for a in arrows.arrows if a.label == "v_B")
    th = np.radians(np.arange(0.0, 360.0, 1.0))
    fastest = float(np.max(np.linalg.norm(cm.follower.centre(th)[1], axis=1))) * cm.omega
    assert float(np.linalg.norm(v_b)) >= 0.25 * fastest, what

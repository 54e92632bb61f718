"""Teaching pictures: velocity and acceleration plans, vectors on the skeleton, free-body views.

The plans are checked from the vertex coordinates the drawing returns (not from pixels): every
chain of relative vectors, built from the relative-motion formulas, ends on the vertex the closed
form gives its point (each polygon closes), and in a planar velocity plan each rigid relative vector
is square to the link's line between its two points and each sliding vector lies along its guide.
The skeleton's arrows are the points' velocities, checked against central differences of their
positions; a free-body view's forces sum to zero."""

import math

import numpy as np
import pytest

from conftest import CAM_MODELS, MODELS, ROOT, SPATIAL_MODELS, input_values
from linkgen.draw.vectors import force_arrows, motion_arrows
from linkgen.errors import ArgumentError
from linkgen.families.planar.assembly import assemble
from linkgen.families.planar.positions import positions
from linkgen.pipeline.registry import load

# A chain's end against its vertex, a fraction of the plan's size: both are sums of a few products of
# closed-form terms of order the plan's size, exact to a few ulps (~1e-15); 1e-9 is the bar.
PLAN_CLOSURE = 1e-9
# |cos| of the angle between a rigid relative velocity and its link's line, and |sin| between a
# sliding velocity and its guide: rounding only (~1e-15).
SQUARE = 1e-9
# A free-body view's resultant against its largest force: the kinetostatics solves each group's
# equations exactly; rounding only.
BALANCE = 1e-9
# Velocity arrows against central differences of positions with step H: truncation (H²·x‴/6 ~ 1e-12)
# and rounding (eps·x/H ~ 1e-10) relative to the mechanism's speeds.
H, FD_REL = 1e-5, 1e-6


def _angles(mech):
    d = mech.drive
    return (d.start + 0.37 * (d.stop - d.start), d.start + 0.81 * (d.stop - d.start))


def _plans(path):
    desc = load(path)
    if path in CAM_MODELS:
        from linkgen.families.cam.plans import cam_plan

        return [cam_plan(desc, t, k) for t in (0.6, 2.9) for k in ("velocity", "acceleration")]
    if path in SPATIAL_MODELS:
        from linkgen.families.spatial.plans import spatial_plan

        return [spatial_plan(desc, float(t), k) for t in input_values(desc, (0.6, 2.9))  # a slider input: its range
                for k in ("velocity", "acceleration")]
    from linkgen.families.planar.vector_plan import vector_plan

    mech = getattr(desc, "mechanism", desc)
    asm = assemble(mech)
    return [vector_plan(asm, t, k) for t in _angles(mech) for k in ("velocity", "acceleration")]


ALL = MODELS + CAM_MODELS + SPATIAL_MODELS


@pytest.mark.parametrize("path", ALL, ids=[p.stem for p in ALL])
def test_every_polygon_of_every_plan_closes(path):
    for plan in _plans(path):
        assert plan.chains, f"{path.stem}: an empty plan"
        for c in plan.chains:
            miss = float(np.linalg.norm(c.xy[-1] - plan.vertices[c.target]))
            assert miss <= PLAN_CLOSURE * plan.size, (path.stem, plan.kind, c.link, c.names, miss / plan.size)
            np.testing.assert_array_equal(c.xy[0], 0.0 * c.xy[0])  # every chain starts at the pole


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_planar_velocity_plan_edges_are_square_to_their_links_and_along_their_guides(path):
    from linkgen.families.planar.vector_plan import vector_plan

    mech = getattr(load(path), "mechanism", load(path))
    asm = assemble(mech)
    phi = _angles(mech)[0]
    pos = positions(mech, [phi])
    upper = {p.lower(): p for p in mech.points}
    plan = vector_plan(asm, phi, "velocity")
    checked = 0
    for c in plan.chains:
        for (a, b), (pa, pb), kind in zip(zip(c.names, c.names[1:]), zip(c.xy, c.xy[1:]), c.kinds):
            edge = pb - pa
            n = float(np.linalg.norm(edge))
            if n <= 1e-12 * plan.size:
                continue
            if kind == "relative" and a in upper and b in upper:
                r = pos.points[upper[b]][0] - pos.points[upper[a]][0]
                assert abs(float(edge @ r)) <= SQUARE * n * float(np.linalg.norm(r)), (path.stem, a, b)
                checked += 1
            if kind == "sliding":
                u = pos.guide_line(c.link, 0)[1]
                assert abs(float(edge[0] * u[1] - edge[1] * u[0])) <= SQUARE * n, (path.stem, c.link)
                checked += 1
    assert checked or len(mech.moving_links) == 1


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_velocity_arrows_are_the_points_velocities(path):
    mech = getattr(load(path), "mechanism", load(path))
    asm = assemble(mech)
    phi = _angles(mech)[1]
    arrows = motion_arrows(asm, phi, "velocity")
    around = positions(mech, [phi - H, phi + H])
    w = mech.drive.omega
    scale = max(float(np.linalg.norm(a.vector)) for a in arrows.arrows) or 1.0
    for a in arrows.arrows:
        name = a.label.removeprefix("v_")
        fd = (around.points[name][1] - around.points[name][0]) / (2 * H) * w
        np.testing.assert_allclose(a.vector, fd, atol=FD_REL * scale, err_msg=f"{path.stem} {name}")


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_acceleration_parts_add_up_and_lie_along_and_across_the_velocity(path):
    mech = getattr(load(path), "mechanism", load(path))
    asm = assemble(mech)
    phi = _angles(mech)[0]
    whole = {a.label: a.vector for a in motion_arrows(asm, phi, "acceleration").arrows}
    parts = motion_arrows(asm, phi, "acceleration", parts=True).arrows
    vel = {a.label.removeprefix("v_"): a.vector for a in motion_arrows(asm, phi, "velocity").arrows}
    by = {}
    for a in parts:
        by.setdefault(a.label.split("^")[0], {})[a.kind] = a.vector
    for label, p in by.items():
        if len(p) < 2:
            continue
        np.testing.assert_allclose(p["tangential"] + p["normal"], whole[label], atol=SQUARE * np.linalg.norm(whole[label]))
        v = vel[label.removeprefix("a_")]
        assert abs(float(p["normal"] @ v)) <= SQUARE * np.linalg.norm(v) * max(np.linalg.norm(whole[label]), 1e-300)


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_free_body_view_of_every_group_balances(path):
    mech = getattr(load(path), "mechanism", load(path))
    asm = assemble(mech)
    phi = _angles(mech)[0]
    for g in asm.structure.groups:
        view = force_arrows(asm, phi, f"{g.numbers[0]},{g.numbers[1]}")
        assert set(view.group_links) == set(g.links)
        assert {a.link for a in view.arrows} <= set(g.links)
        largest = max(float(np.linalg.norm(a.vector)) for a in view.arrows)
        assert float(np.linalg.norm(view.resultant())) <= BALANCE * largest, (path.stem, g.label)


def test_free_body_names_the_groups_there_are():
    asm = assemble(load(ROOT / "models" / "g123.toml"))
    with pytest.raises(ArgumentError, match=r"--free-body '9,9': no such Assur group in g123; its groups are "
                                            r"2,3 \(coupler, rocker\); 4,5"):
        force_arrows(asm, 0.5, "9,9")
    assert force_arrows(asm, 0.5, "rocker").group == force_arrows(asm, 0.5, "II(2,3)").group == "II(2,3) RRR"


def test_press_load_is_drawn_with_its_crank_angle_range_and_off_outside_it():
    asm = assemble(load(ROOT / "models" / "press.toml"))
    on, off = (next(a for a in force_arrows(asm, math.radians(d)).arrows if a.kind == "load") for d in (120.0, 30.0))
    assert on.label == off.label == "F (ram, φ ∈ 100°..170°)"
    assert on.active and not off.active
    np.testing.assert_array_equal(on.vector, [3000.0, 0.0])

"""A link's mass properties from a uniform plate over its points: exact formulas, a fan of
triangles computed another way, the loader's errors, and MuJoCo's compiled body."""

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

from linkgen import DescriptionError, assemble
from linkgen.families.planar.geometry import effective_mass_properties, link_shapes
from linkgen.families.planar.plate import hull_area, plate_properties
from linkgen.pipeline.registry import loads
from linkgen.mujoco.mjcf import write_mjcf

ROOT = Path(__file__).resolve().parents[1]
TOL = 1e-12


def test_rectangle_and_right_triangle():
    a, b, rho = 0.6, 0.2, 7.85
    m, com, i = plate_properties([(0, 0), (a, 0), (a, b), (0, b)], rho)
    assert m == pytest.approx(rho * a * b, rel=TOL) and com == pytest.approx((a / 2, b / 2), rel=TOL)
    assert i == pytest.approx(m * (a * a + b * b) / 12, rel=TOL)
    m, com, i = plate_properties([(0, 0), (a, 0), (0, b)], rho)
    assert m == pytest.approx(rho * a * b / 2, rel=TOL) and com == pytest.approx((a / 3, b / 3), rel=TOL)
    assert i == pytest.approx(m * (a * a + b * b) / 18, rel=TOL)


def test_order_and_inner_points_do_not_matter():
    square = [(0, 0), (1, 1), (1, 0), (0, 1), (0.5, 0.5), (0.2, 0.7)]  # shuffled, two inside
    m, com, i = plate_properties(square, 1.0)
    assert (m, i) == pytest.approx((1.0, 1.0 / 6.0), rel=TOL) and com == pytest.approx((0.5, 0.5), rel=TOL)


@pytest.mark.parametrize("seed", range(20))
def test_random_convex_polygons_against_a_fan_of_triangles(seed):
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * math.pi, rng.integers(3, 9)))
    pts = np.column_stack([np.cos(ang), np.sin(ang)]) * rng.uniform(0.5, 2.0) + rng.normal(size=2)
    m, com, i = plate_properties(pts, 3.0)
    # fan from the first vertex; triangle: I_g = m·(a² + b² + c²)/36 with its side lengths
    tm, tc, ti = [], [], []
    for k in range(1, len(pts) - 1):
        p, q, r = pts[0], pts[k], pts[k + 1]
        area = 0.5 * abs((q - p)[0] * (r - p)[1] - (q - p)[1] * (r - p)[0])
        sides = sum(np.sum((u - v) ** 2) for u, v in ((p, q), (q, r), (r, p)))
        tm.append(3.0 * area), tc.append((p + q + r) / 3), ti.append(3.0 * area * sides / 36)
    tm, tc = np.array(tm), np.array(tc)
    g = (tm[:, None] * tc).sum(0) / tm.sum()
    total = sum(t + mm * np.sum((c - g) ** 2) for t, mm, c in zip(ti, tm, tc))
    assert m == pytest.approx(tm.sum(), rel=1e-12) and com == pytest.approx(tuple(g), rel=1e-10, abs=1e-12)
    assert i == pytest.approx(total, rel=1e-10)


def _coupler_plate(extra: str = "") -> str:
    text = (ROOT / "models" / "fourbar.toml").read_text()
    text = text.replace("C = [1.0, 0.0]\n", "C = [1.0, 0.0]\nP = [0.8, 0.1]\n")
    return text.replace('[links.coupler]\npoints = ["A", "B"]\nlength = 1.0\ndensity = 10.0\n',
                        f'[links.coupler]\npoints = ["A", "B", "P"]\nareal_density = 12.0\n{extra}')


def test_a_ternary_plate_reaches_mujoco():
    mech = loads(_coupler_plate())
    shapes = link_shapes(mech)
    mp = effective_mass_properties(mech, shapes, "coupler")
    pts = [mech.points[p] for p in ("A", "B", "P")]
    assert mp.mass == pytest.approx(12.0 * hull_area(pts), rel=TOL)
    model = mujoco.MjModel.from_xml_string(write_mjcf(assemble(mech)))
    body = model.body("coupler")
    assert body.mass[0] == pytest.approx(mp.mass, rel=1e-12)
    assert body.inertia.max() == pytest.approx(mp.inertia, rel=1e-9)  # diaginertia (I/2, I/2, I)


@pytest.mark.parametrize("extra,text", [("density = 1.0\n", "give one of areal_density, density"),
                                        ("", None)])
def test_errors_name_the_field(extra, text):
    if text is None:  # two points only: a plate needs three
        bad = (ROOT / "models" / "fourbar.toml").read_text().replace("length = 1.0\ndensity = 10.0\n",
                                                                     "length = 1.0\nareal_density = 10.0\n")
        with pytest.raises(DescriptionError) as info:
            loads(bad)
        assert "links.coupler.areal_density" in str(info.value) and "density [kg/m]" in str(info.value)
        return
    with pytest.raises(DescriptionError) as info:
        loads(_coupler_plate(extra))
    assert "links.coupler.areal_density" in str(info.value) and text in str(info.value)

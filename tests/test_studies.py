"""Design studies (``linkgen.studies``): the four-bar kernel against the general per-variant
route, failing variants as rows with their reasons, the same table whatever the chunking and
the executor, the fields' paths and their messages."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from linkgen.errors import ArgumentError
from linkgen.model.toml_file import parse_toml, read_toml
from linkgen.pipeline.registry import from_dict, load
from linkgen.studies.engine import run_study
from linkgen.studies.fields import override
from linkgen.studies.fourbar import solve
from linkgen.studies.fourbar_params import fourbar_of, params, takes
from linkgen.studies.general import variant
from linkgen.studies.metrics import angles
from linkgen.studies.sweep import make_study, write_outputs

FOURBAR = "models/fourbar.toml"
# The kernel and the general route compute the same formulas in another order: they round
# differently at ~1e-16 per operation, amplified near a dead centre by at most 1/|D| ≤
# 1/SINGULAR_TOL = 1e4 (linkgen.families.planar.groups): ≲ 1e-11. Measured ≤ 5e-15 on random
# variants; 1e-9 still catches any wrong term, which shows at the size of the value itself.
KERNEL_RTOL = 1e-9
# Absolute floor for values that vanish (a zero reaction without gravity) [SI].
KERNEL_ATOL = 1e-9
# Two grid samples that differ by less than the routes' rounding can swap as the extremum: a
# limit position is then one grid step (2π/360) away ...
LIMIT_TOL = 2 * math.pi / 360 * 1.000001
# ... and the time ratio, from the two limits, moves by at most two steps in a stroke of at least
# π/2 for these variants: 2·(2π/360)/(π/2) = 2.3 % relative.
RATIO_RTOL = 0.023

# A four-bar with explicit mass properties, the rocker's points listed from B and a coupler
# written B → A: the kernel's frames follow the description's point order.
INERTIAL = """
[mechanism]
name = "fb_inertial"
gravity = [0.5, -9.81]
[points]
O = [0.0, 0.0]
A = [0.0, 0.25]
B = [0.9, 0.8]
C = [1.1, 0.0]
[links.ground]
points = ["O", "C"]
[links.crank]
points = ["O", "A"]
length = 0.25
inertial = { mass = 2.0, com = [0.1, 0.02], inertia = 0.03 }
[links.coupler]
points = ["B", "A"]
length = 1.0
inertial = { mass = 4.0, com = [0.4, -0.05], inertia = 0.4 }
[links.rocker]
points = ["B", "C"]
length = 0.8
inertial = { mass = 3.0, com = [0.3, 0.0], inertia = 0.2 }
[drive]
joint = "O"
omega = 12.0
epsilon = 3.0
"""


def _compare(text: str, source: str, paths: list[str], values: np.ndarray) -> int:
    """Kernel against the general route, row by row; the number of rows compared."""
    data = parse_toml(text, source)
    mech = from_dict(data, source)
    fb = fourbar_of(mech)
    assert fb is not None and takes(fb, paths)
    phi, full = angles(mech.drive.start, mech.drive.stop)
    cols, failures, general = solve(fb, mech, params(fb, mech, paths, values), phi, full)
    failed = {r: (kind, text) for r, kind, text in failures}
    for r in range(values.shape[0]):
        want, kind, why = variant(override(data, dict(zip(paths, values[r].tolist()))), source, phi, full, fb.layout)
        if general[r]:
            continue
        if want is None:
            assert failed.get(r) == (kind, why), f"row {r}"
            continue
        assert r not in failed, f"row {r}: the kernel says {failed.get(r)}, the general route computes it"
        for k, v in want.items():
            got = cols[k][r]
            if k.startswith("limit_"):
                if math.isnan(v):
                    assert math.isnan(got), k
                else:
                    d = abs(math.remainder(got - v, 2 * math.pi))
                    assert d <= LIMIT_TOL, f"row {r} {k}: {got} vs {v}"
            elif k.startswith("time_ratio"):
                np.testing.assert_allclose(got, v, rtol=RATIO_RTOL, err_msg=f"row {r} {k}")
            else:
                np.testing.assert_allclose(got, v, rtol=KERNEL_RTOL, atol=KERNEL_ATOL, err_msg=f"row {r} {k}")
    return values.shape[0]


COMMON = dict(deadline=None, derandomize=True, phases=[Phase.explicit, Phase.generate],
              suppress_health_check=[HealthCheck.too_slow])
FOURBAR_FIELDS = ["links.crank.length", "links.coupler.length", "links.rocker.length", "points.C.x", "points.C.y",
                  "points.B.y", "drive.omega", "drive.epsilon", "links.coupler.density", "mechanism.gravity.x",
                  "points.O.x", "points.A.y"]
_RANGES = [(0.1, 0.5), (0.5, 1.5), (0.4, 1.2), (0.5, 1.5), (-0.4, 0.4), (-0.8, 0.8), (-30.0, 30.0), (-50.0, 50.0),
           (0.5, 30.0), (-5.0, 5.0), (-0.3, 0.3), (-0.3, 0.3)]


@settings(max_examples=25, **COMMON)
@given(st.lists(st.tuples(*[st.floats(lo, hi) for lo, hi in _RANGES]), min_size=1, max_size=12))
# a sketch on a dead centre (B on the line A–C): the two modes tie, and both routes keep m = +1
# (found by this test: the kernel's rocker limit 2.2166 rad against the general route's 0.6632)
@example([(0.15, 0.5, 0.4, 0.5, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0)])
def test_kernel_agrees_with_the_general_route(rows):
    """Random four-bar variants: the same metrics, the same failures and messages."""
    _compare(open(FOURBAR, encoding="utf-8").read(), FOURBAR, FOURBAR_FIELDS, np.array(rows))


INERTIAL_FIELDS = ["links.coupler.length", "links.rocker.inertial.mass", "links.coupler.inertial.com.y",
                   "links.crank.inertial.inertia", "points.C.x", "drive.omega"]


@settings(max_examples=15, **COMMON)
@given(st.lists(st.tuples(st.floats(0.6, 1.4), st.floats(0.5, 5.0), st.floats(-0.2, 0.2), st.floats(0.0, 0.1),
                          st.floats(0.7, 1.5), st.floats(-20, 20)), min_size=1, max_size=10))
def test_kernel_agrees_with_explicit_mass_properties_and_reversed_points(rows):
    _compare(INERTIAL, "fb_inertial.toml", INERTIAL_FIELDS, np.array(rows))


def test_failing_variants_are_rows_with_their_reason(tmp_path):
    """A coupler too short to reach, one that folds flat and a negative density: each row stays,
    with its error's class and the loader's or the closed form's message."""
    study = make_study(FOURBAR, ["links.coupler.length=0.2:1.0:3", "links.rocker.density=-1:10:2"])
    table = run_study(study, tmp_path, workers=1, progress=False)
    rows = table.to_pylist()
    assert len(rows) == 6
    short = rows[0]  # coupler 0.2 m: O–C is 1 m, crank 0.3 m, rocker 0.7 m
    assert (short["status"], short["error"]) == ("failed", "DescriptionError")
    assert "links.rocker.density: must be > 0 kg/m, got -1.0" in short["reason"]
    cannot = rows[1]
    assert (cannot["status"], cannot["error"]) == ("failed", "AssemblyError")
    assert cannot["reason"].startswith("group II(2,3) RRR [coupler, rocker] cannot be assembled at crank angles ")
    assert "the two links cannot reach each other" in cannot["reason"]
    assert cannot["min_transmission_angle [rad]"] is None
    fine = rows[5]
    assert fine["status"] == "ok" and fine["error"] is None and fine["reason"] is None
    assert fine["min_transmission_angle [rad]"] > 0


def _bytes(study, out, **how) -> bytes:
    table = run_study(study, out, progress=False, **how)
    return write_outputs(table, study, out)["parquet"].read_bytes()


def test_same_table_whatever_the_chunking_and_executor(tmp_path):
    """Kernel rows, general-route rows (a non-positive density) and failures: the same bytes
    in one chunk, in chunks of 7 and on two local processes."""
    study = make_study(FOURBAR, ["links.coupler.length=0.5:1.5:9", "points.C.x=0.6:1.4:5",
                                 "links.rocker.density=-2:10:3"])
    one = _bytes(study, tmp_path / "one", workers=1, chunk=1000)
    sevens = _bytes(study, tmp_path / "sevens", workers=1, chunk=7)
    pool = _bytes(study, tmp_path / "pool", workers=2, chunk=40)
    assert one == sevens == pool


def test_a_general_route_study_is_chunk_independent(tmp_path):
    """A slider-crank (no kernel): the general route per variant, the same bytes in any chunking."""
    study = make_study("models/slider_crank_offset.toml", ["drive.omega=1:30:4", "links.rod.length=0.03:0.2:4"])
    assert _bytes(study, tmp_path / "a", workers=1, chunk=3) == _bytes(study, tmp_path / "b", workers=1, chunk=100)


@pytest.mark.parametrize("spec, message", [
    ("links.coupler.lenth=1:2:3", "--vary links.coupler.lenth: links.coupler has no 'lenth' (it has points, length, "
                                  "density)"),
    ("links.coupler.points=1:2:3", "--vary links.coupler.points: the description has ['A', 'B'] there; only a number "
                                   "can be varied"),
    ("drive.omega=1:2", "--vary 'drive.omega=1:2': expected FIELD=START:STOP:N"),
    ("drive.omega=1:2:0", "--vary drive.omega N: expected a whole number of values from 1 to 100000, got '0'"),
    ("drive.omega=1:fast:3", "--vary drive.omega STOP: expected a number, optionally with a unit"),
])
def test_bad_fields_are_named(spec, message):
    with pytest.raises(ArgumentError) as exc:
        make_study(FOURBAR, [spec])
    assert message in str(exc.value)


def test_units_in_a_range_and_the_points_coordinates():
    study = make_study(FOURBAR, ["drive.omega=60rpm:120rpm:2", "points.C.y=-5mm:5mm:2"])
    np.testing.assert_allclose(study.values[:, 0], [2 * math.pi, 2 * math.pi, 4 * math.pi, 4 * math.pi])
    np.testing.assert_allclose(study.values[:, 1], [-0.005, 0.005, -0.005, 0.005])
    data = override(read_toml(FOURBAR), {"points.C.y": 0.25, "drive.omega": 3.0})
    mech = load(FOURBAR)
    assert data["points"]["C"] == [1.0, 0.25] and data["drive"]["omega"] == 3.0 and mech.points["C"] == (1.0, 0.0)


def test_plots_for_two_and_for_more_fields(tmp_path):
    from linkgen.studies.plots import plot_study

    two = make_study(FOURBAR, ["links.coupler.length=0.5:1.5:4", "points.C.x=0.6:1.4:3"])
    names = [p.name for p in plot_study(run_study(two, tmp_path / "a", workers=1, progress=False), two, tmp_path)]
    assert names == ["map_min_transmission_angle.png", "map_peak_balancing_torque.png"]
    three = make_study(FOURBAR, ["links.coupler.length=0.5:1.5", "points.C.x=0.6:1.4", "drive.omega=5:15"], lhs=20)
    got = plot_study(run_study(three, tmp_path / "b", workers=1, progress=False), three, tmp_path)
    assert [p.name for p in got] == ["parallel.png"] and got[0].stat().st_size > 10_000


def test_validate_picks_the_extremes_of_working_variants_and_runs_mujoco(tmp_path):
    from linkgen.studies.validate import choose, validate_sample

    study = make_study(FOURBAR, ["links.coupler.length=0.5:1.5:6", "points.C.x=0.8:1.2:3"])
    table = run_study(study, tmp_path, workers=1, progress=False)
    rows = table.to_pylist()
    mu = {r["variant"]: r["min_transmission_angle [rad]"] for r in rows if r["status"] == "ok"}
    picked = choose(table, 6)
    assert picked[0] == (min(mu, key=mu.get), "least min_transmission_angle")
    assert picked[1] == (max(mu, key=mu.get), "greatest min_transmission_angle")
    assert len(picked) == 6 and all(rows[r]["status"] == "ok" for r, _ in picked)
    report = validate_sample(study, table, 1, tmp_path)
    assert report.ok and report.rows[0][0] == picked[0][0]
    assert (tmp_path / "validation.json").exists()


def test_provenance_in_the_parquet_metadata_and_the_sidecar(tmp_path):
    import hashlib
    import json

    import pyarrow.parquet as pq

    study = make_study(FOURBAR, ["links.coupler.length=0.8:1.2", "drive.omega=5:15"], lhs=7, seed=11)
    paths = write_outputs(run_study(study, tmp_path, workers=1, progress=False), study, tmp_path)
    meta = json.loads(pq.read_schema(paths["parquet"]).metadata[b"linkgen"])
    side = json.loads(paths["json"].read_text(encoding="utf-8"))
    digest = hashlib.sha256(open(FOURBAR, "rb").read()).hexdigest()
    for prov in (meta, side):
        assert prov["description_sha256"] == digest
        assert prov["sampling"] == {"method": "lhs", "n": 7, "seed": 11}
        assert prov["numpy"] == np.__version__ and prov["linkgen"] and prov["mujoco"]
        assert [f["path"] for f in prov["fields"]] == ["links.coupler.length", "drive.omega"]
    assert side["columns"]["peak_balancing_torque [N·m]"] == "N·m" and side["rows"] == 7
    assert paths["csv"].read_text(encoding="utf-8").splitlines()[0].startswith(
        '"variant","links.coupler.length [m]","drive.omega [rad/s]","status","error","reason"')

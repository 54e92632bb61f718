"""``linkgen optimize``: differential evolution over a four-bar's fields honours its
constraint (checked by the general route on the written file), is deterministic for a seed,
and writes the design back keeping the user's comments, its sketch re-assembled."""

from __future__ import annotations

import math

import pytest

import linkgen
from linkgen.errors import ArgumentError
from linkgen.model.toml_file import read_toml
from linkgen.studies.general import layout_of, variant
from linkgen.studies.metrics import angles
from linkgen.studies.optimize import optimize, parse_constraint, write_design
from linkgen.studies.sweep import make_study

FOURBAR = "models/fourbar.toml"
VARY = ["links.coupler.length=0.8:1.3", "points.C.x=0.8:1.3", "links.rocker.length=0.5:0.9"]
# 50° binds: without it the least peak torque over these ranges has μ_min ≈ 47.6°.
LEAST = math.radians(50.0)
# Generations for a test: enough to reach the feasible region from a seeded population.
GENERATIONS = 15


@pytest.fixture(scope="module")
def best(tmp_path_factory):
    study = make_study(FOURBAR, VARY, lhs=1)
    cols = layout_of(linkgen.load(FOURBAR)).columns
    c = parse_constraint("min_transmission_angle >= 50deg", cols)
    got = optimize(study, "peak_balancing_torque [N·m]", (c,), seed=3, maxiter=GENERATIONS)
    path = tmp_path_factory.mktemp("opt") / "best.toml"
    write_design(study, got.values, path)
    return study, got, path


def test_the_constraint_is_honoured_by_the_general_route_on_the_written_file(best):
    study, got, path = best
    assert got.feasible
    mech = linkgen.load(path)  # the default sketch tolerance: the sketch was re-assembled
    phi, full = angles(mech.drive.start, mech.drive.stop)
    metrics, error, reason = variant(read_toml(path), str(path), phi, full, layout_of(mech))
    assert error == "", reason
    assert metrics["min_transmission_angle [rad]"] >= LEAST
    assert metrics["peak_balancing_torque [N·m]"] == pytest.approx(got.metrics["peak_balancing_torque [N·m]"],
                                                                   rel=1e-9)


def test_the_written_design_keeps_the_comments_and_the_search_is_seeded(best, tmp_path):
    study, got, path = best
    text = path.read_text(encoding="utf-8")
    assert text.startswith("# Crank–rocker four-bar: OA = 0.3 m")
    assert "omega = 10.0      # rad/s" in text and "density = 10.0    # uniform bar, kg/m" in text
    assert "[points]          # sketch pose at φ = 0" in text
    again = optimize(study, "peak_balancing_torque [N·m]", (parse_constraint("min_transmission_angle >= 50deg",
                     layout_of(linkgen.load(FOURBAR)).columns),), seed=3, maxiter=GENERATIONS)
    assert again.values == got.values


def test_bad_metric_and_constraint_are_named():
    cols = layout_of(linkgen.load(FOURBAR)).columns
    with pytest.raises(ArgumentError, match="'stroke' is not a metric of this mechanism; its metrics are swing.rocker"):
        parse_constraint("stroke >= 1", cols)
    with pytest.raises(ArgumentError, match="expected METRIC >= VALUE or METRIC <= VALUE"):
        parse_constraint("min_transmission_angle > 40deg", cols)

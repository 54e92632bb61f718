"""Optimisation over the varied fields: scipy's ``differential_evolution`` (a population
search that needs no gradient: the metrics are maxima over a grid of crank angles, not smooth,
and a variant may fail to assemble), seeded and deterministic, each generation evaluated as one
batch of variants (``vectorized``) through the same chunk code as a sweep. Constraints
(``min_transmission_angle >= 40deg``) are scipy's ``NonlinearConstraint``s, and a failing
variant violates them all: a feasible design always wins over an infeasible one.

The best design is written back into a copy of the description (tomlkit: the user's comments
and layout kept), its sketch re-assembled from the new lengths (``families.planar.sketch``)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from linkgen.errors import ArgumentError
from linkgen.studies.chunk import Task, run
from linkgen.studies.engine import Study
from linkgen.studies.fields import bound

_CONSTRAINT = re.compile(r"^\s*([A-Za-z_][\w.:\-]*)\s*(>=|<=)\s*(\S+)\s*$")
# Generations at most, and the population per field (scipy's defaults are 1000 and 15: a
# four-bar's fields settle in well under 100 generations).
MAXITER = 100
POPSIZE = 15
# Relative spread of the population's objective at which the search stops (scipy's ``tol``).
TOL = 1e-6


@dataclass(frozen=True)
class Constraint:
    """``metric`` (a table column) ``>=`` or ``<=`` ``value`` [SI]."""

    metric: str
    op: str
    value: float

    def text(self) -> str:
        unit = self.metric.rsplit(" [", 1)[1][:-1]
        shown = f"{math.degrees(self.value):.6g}°" if unit == "rad" else f"{self.value:.6g} {unit}"
        return f"{self.metric.split(' [')[0]} {self.op} {shown}"


def metric_column(name: str, columns: tuple[str, ...]) -> str:
    """The table column a metric's name (with or without its unit) names."""
    for c in columns:
        if name in (c, c.split(" [")[0]):
            return c
    names = ", ".join(c.split(" [")[0] for c in columns)
    raise ArgumentError(f"{name!r} is not a metric of this mechanism; its metrics are {names}")


def parse_constraint(text: str, columns: tuple[str, ...]) -> Constraint:
    """``METRIC >= VALUE`` or ``METRIC <= VALUE``, the value in SI or with a unit (40deg)."""
    m = _CONSTRAINT.match(text)
    if not m:
        raise ArgumentError(f"--subject-to {text!r}: expected METRIC >= VALUE or METRIC <= VALUE, e.g. "
                            f"\"min_transmission_angle >= 40deg\"")
    return Constraint(metric_column(m.group(1), columns), m.group(2), bound(m.group(3), f"--subject-to {text!r}"))


@dataclass(frozen=True)
class Optimum:
    """The best variant: its fields' values [SI], its metrics, how many variants were tried,
    whether it meets the constraints, scipy's message."""

    values: tuple[float, ...]
    metrics: dict
    evaluations: int
    feasible: bool
    message: str


def optimize(study: Study, objective: str, constraints: tuple[Constraint, ...], *, seed: int = 0,
             maxiter: int = MAXITER, progress=None) -> Optimum:
    """Minimise the metric ``objective`` over the study's fields' ranges subject to
    ``constraints``, at most ``maxiter`` generations; ``progress(variants tried, best)`` after
    each generation."""
    from scipy.optimize import Bounds, NonlinearConstraint, differential_evolution

    paths = tuple(f.path for f in study.fields)
    seen = {"count": 0}
    cache: dict = {}

    def evaluate(x: np.ndarray) -> dict:
        x = np.atleast_2d(np.asarray(x, dtype=float).T if np.ndim(x) == 2 else x)  # (S, n_fields)
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = run(Task(study.source, study.text, paths, 0, x, study.angles))
            seen["count"] += x.shape[0]
        return cache[key]

    def energy(x):
        got = evaluate(x)
        v = np.asarray(got["metrics"][objective], dtype=float)
        return np.where(np.isfinite(v), v, np.inf)

    def margins(x):
        got = evaluate(x)
        out = []
        for c in constraints:
            v = np.asarray(got["metrics"][c.metric], dtype=float)
            d = v - c.value if c.op == ">=" else c.value - v
            out.append(np.where(np.isfinite(d), d, -np.inf))
        ok = np.array([s == "ok" for s in got["status"]], dtype=float) * 2.0 - 1.0
        return np.vstack(out + [ok])

    lo = [min(f.start, f.stop) for f in study.fields]
    hi = [max(f.start, f.stop) for f in study.fields]
    nlc = NonlinearConstraint(margins, 0.0, np.inf)

    def callback(intermediate_result):
        if progress is not None:
            progress(seen["count"], float(intermediate_result.fun))

    res = differential_evolution(energy, Bounds(lo, hi), constraints=(nlc,), seed=np.random.default_rng(seed),
                                 maxiter=maxiter, popsize=POPSIZE, tol=TOL, polish=False, vectorized=True,
                                 updating="deferred", callback=callback)
    best = evaluate(np.asarray(res.x)[:, None])
    metrics = {k: float(v[0]) for k, v in best["metrics"].items()}
    feasible = best["status"][0] == "ok" and bool(np.all(margins(np.asarray(res.x)[:, None]) >= 0))
    return Optimum(tuple(float(v) for v in res.x), metrics, seen["count"], feasible, str(res.message))


def write_design(study: Study, values: tuple[float, ...], path: Path) -> None:
    """The description with the fields at ``values`` and its sketch re-assembled, written to
    ``path``, the user's comments and layout kept (tomlkit)."""
    import tomlkit

    from linkgen.model.toml_file import parse_toml
    from linkgen.outputs import atomic_write_text
    from linkgen.studies.design import moved_points
    from linkgen.studies.fields import walk

    doc = tomlkit.parse(study.text)
    given = dict(zip((f.path for f in study.fields), values))
    for p, v in given.items():
        node, key = walk(doc, p, create=True)
        node[key] = float(v)
    for name, xy in moved_points(parse_toml(study.text, study.source), str(path), given).items():
        doc["points"][name] = xy
    atomic_write_text(path, tomlkit.dumps(doc))


__all__ = ["Constraint", "Optimum", "metric_column", "optimize", "parse_constraint", "write_design"]

"""The four-bar kernel's inputs for many variants at once: which descriptions it takes
(``FourBar``: a crank and one RRR group, two-point bars, gravity and inertia as the only loads)
and each variant's lengths, mass properties, speed and gravity (``params``) from the base
description and the varied fields' values.

A variant the kernel would not vouch for — a magnitude outside ``ORDINARY`` — is left to the
general route (``Params.ordinary`` False), so a row's verdict on an extreme value is always the
loader's and the closed form's own."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from linkgen.studies.metrics import Layout

# Magnitudes the kernel takes [SI]: lengths (and the sketch's size) and masses well inside
# linkgen's limits (linkgen.model.limits), speeds and gravity of machines. Outside them the
# loader's checks or the closed form's overflow guards may speak: the general route decides.
ORDINARY = {"length": (1e-6, 1e6), "mass": (1e-6, 1e9), "inertia": (0.0, 1e12), "omega": 1e6, "epsilon": 1e9,
            "gravity": 1e6}


@dataclass(frozen=True)
class FourBar:
    """A four-bar's names: links crank (O→A), coupler (A–B), rocker (B–C, pivoted at C); the
    points of the drive pivot O, the joints A, B and the rocker's pivot C; each link's first
    and second point (its local x axis); the RRR group's label and its two links in the group's
    order."""

    crank: str
    coupler: str
    rocker: str
    points: tuple[str, str, str, str]
    ends: dict
    group: str
    group_links: tuple[str, str]
    layout: Layout


def fourbar_of(mech) -> FourBar | None:
    """The four-bar names of ``mech`` if the kernel takes it, else None."""
    from linkgen.families.planar.structure import GroupKind, analyze
    from linkgen.model.names import GROUND
    from linkgen.studies.general import layout_of

    if (mech.prismatics or mech.gears or mech.cams or mech.springs or mech.torsion_springs or mech.frictions
            or mech.forces or mech.torques or len(mech.links) != 4 or len(mech.revolutes) != 4):
        return None
    if any(link.shape is not None or link.areal_density is not None or len(link.points) != 2 for link in mech.links):
        return None
    structure = analyze(mech)
    if len(structure.groups) != 1 or structure.groups[0].kind is not GroupKind.RRR:
        return None
    group = structure.groups[0]
    crank = mech.link(structure.crank)
    o = mech.revolute(mech.drive.joint).point
    l1, l2 = group.links
    coupler, rocker = (l1, l2) if group.known[0] == structure.crank else (l2, l1)
    a = next(p for p in crank.points if p != o)
    b = next(p for p in mech.link(coupler).points if p != a)
    c = next(p for p in mech.link(rocker).points if p != b)
    if crank.points[0] != o or set(mech.link(GROUND).points) != {o, c}:
        return None
    ends = {link.name: tuple(link.points) for link in mech.links}
    return FourBar(crank.name, coupler, rocker, (o, a, b, c), ends, group.label, (l1, l2), layout_of(mech))


def canonical(path: str) -> tuple:
    """A field path as a tuple, coordinates as indices: ``points.C.x`` → ("points", "C", 0)."""
    from linkgen.studies.fields import steps

    out: list = []
    for step in steps(path):
        if step in ("x", "y") and ((len(out) == 2 and out[0] == "points") or (out and out[-1] in ("gravity", "com"))):
            step = 0 if step == "x" else 1
        out.append(step)
    return tuple(out)


@dataclass(frozen=True)
class Params:
    """Each quantity (V,) [SI] of V variants: ``points`` name → (x, y) sketch coordinates;
    per link ``length``, ``mass``, ``com`` (x, y) local, ``inertia``; ``omega``, ``epsilon``,
    ``gravity`` (x, y); ``ordinary`` the rows the kernel takes."""

    points: dict
    length: dict
    mass: dict
    com: dict
    inertia: dict
    omega: np.ndarray
    epsilon: np.ndarray
    gravity: tuple
    ordinary: np.ndarray


def takes(fb: FourBar, paths: list[str]) -> bool:
    """Whether every varied field is one the kernel reads."""
    return all(_slot(fb, canonical(p)) is not None for p in paths)


def _slot(fb: FourBar, key: tuple):
    links = (fb.crank, fb.coupler, fb.rocker)
    if len(key) == 3 and key[0] == "points" and key[1] in fb.points and key[2] in (0, 1):
        return key
    if len(key) == 3 and key[0] == "links" and key[1] in links and key[2] in ("length", "density"):
        return key
    if len(key) >= 4 and key[0] == "links" and key[1] in links and key[2] == "inertial" and (
            key[3:] in (("mass",), ("inertia",), ("com", 0), ("com", 1))):
        return key
    if key in (("drive", "omega"), ("drive", "epsilon"), ("mechanism", "gravity", 0), ("mechanism", "gravity", 1)):
        return key
    return None


def params(fb: FourBar, mech, paths: list[str], values: np.ndarray) -> Params:
    """The kernel's inputs for the variants ``values`` (V, n_fields) of the fields ``paths``
    over the base description ``mech``."""
    from linkgen.model.defaults import DEFAULT_DENSITY

    rows = values.shape[0]
    given = {canonical(p): values[:, i].astype(float) for i, p in enumerate(paths)}

    def value(key, base):
        return given[key] if key in given else np.full(rows, float(base))

    pts = {p: (value(("points", p, 0), mech.points[p][0]), value(("points", p, 1), mech.points[p][1]))
           for p in mech.points}
    length, mass, com, inertia = {}, {}, {}, {}
    ok = np.ones(rows, dtype=bool)
    lo, hi = ORDINARY["length"]
    for name in (fb.crank, fb.coupler, fb.rocker):
        link = mech.link(name)
        p, q = fb.ends[name]
        sketch = np.hypot(pts[q][0] - pts[p][0], pts[q][1] - pts[p][1])
        length[name] = value(("links", name, "length"), link.length) if link.length is not None or \
            ("links", name, "length") in given else sketch
        if link.inertial is not None:
            m0 = link.inertial
            mass[name] = value(("links", name, "inertial", "mass"), m0.mass)
            com[name] = (value(("links", name, "inertial", "com", 0), m0.com[0]),
                         value(("links", name, "inertial", "com", 1), m0.com[1]))
            inertia[name] = value(("links", name, "inertial", "inertia"), m0.inertia)
        else:
            rho = value(("links", name, "density"), link.density if link.density is not None else DEFAULT_DENSITY)
            ok &= rho > 0
            mass[name] = rho * length[name]
            com[name] = (0.5 * length[name], np.zeros(rows))
            inertia[name] = mass[name] * length[name] * length[name] / 12.0
        ok &= (length[name] >= lo) & (length[name] <= hi) & (sketch >= lo) & (sketch <= hi)
        ok &= (mass[name] >= ORDINARY["mass"][0]) & (mass[name] <= ORDINARY["mass"][1])
        ok &= (inertia[name] >= ORDINARY["inertia"][0]) & (inertia[name] <= ORDINARY["inertia"][1])
        ok &= (np.abs(com[name][0]) <= hi) & (np.abs(com[name][1]) <= hi)
    xs = np.stack([xy[0] for xy in pts.values()])
    ys = np.stack([xy[1] for xy in pts.values()])
    size = np.hypot(xs.max(axis=0) - xs.min(axis=0), ys.max(axis=0) - ys.min(axis=0))
    ok &= (size >= lo) & (size <= hi)
    omega, epsilon = value(("drive", "omega"), mech.drive.omega), value(("drive", "epsilon"), mech.drive.epsilon)
    gravity = (value(("mechanism", "gravity", 0), mech.gravity[0]), value(("mechanism", "gravity", 1), mech.gravity[1]))
    ok &= (np.abs(omega) <= ORDINARY["omega"]) & (np.abs(epsilon) <= ORDINARY["epsilon"])
    ok &= (np.abs(gravity[0]) <= ORDINARY["gravity"]) & (np.abs(gravity[1]) <= ORDINARY["gravity"])
    with np.errstate(invalid="ignore"):
        ok &= np.all(np.isfinite(values), axis=1)
    return Params(pts, length, mass, com, inertia, omega, epsilon, gravity, ok)


__all__ = ["FourBar", "ORDINARY", "Params", "canonical", "fourbar_of", "params", "takes"]

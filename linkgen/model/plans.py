"""Velocity and acceleration plans, the same in every family: the vertices (every point's vector
from one pole, named by the point's lower-case letter) and the chains of relative vectors that
reach them from the pole, built by the relative-motion formulas alone (``families.*``), so that
``VectorPlan.closure`` — how far a chain's end misses its vertex — checks the closed form. Planar
plans are 2-D; a spatial chain's plan is 3-D (its drawing shows projections)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from linkgen.errors import ArgumentError

KINDS = ("velocity", "acceleration")
UNITS = {"velocity": "m/s", "acceleration": "m/s²"}
# The pole's name in each plan (textbooks: p for velocities, π for accelerations).
POLES = {"velocity": "p", "acceleration": "π"}


def pole_name(kind: str, points) -> str:
    """The pole's name in a ``kind`` plan of a mechanism with these ``points``: POLES[kind], unless
    a point's vertex (its lower-case name) is already called so (a crank pin P's ``p``): then with
    a subscript ₀ (``p₀``), as many as it takes to be free."""
    taken = {str(p).lower() for p in points}
    name = POLES[kind]
    while name in taken:
        name += "₀"
    return name


def check_kind(kind: str) -> str:
    """``kind`` if it is one of KINDS, else an ArgumentError naming them."""
    if kind not in KINDS:
        raise ArgumentError(f"plan kind must be one of {list(KINDS)}, got {kind!r}")
    return kind


@dataclass(frozen=True)
class Chain:
    """One path of the plan from the pole to a named point's vertex.

    names: the vertex names along the path (the pole first, ``target`` last; intermediate vertices
        are the coincident point of a guide, ``a3``, or the end of a normal or Coriolis part,
        ``n_ba``, ``k_a``).
    xy: (k, 2) or (k, 3) the vertices' coordinates [m/s or m/s²]: xy[0] the pole (0, 0), xy[1] the closed
        form's vector of the reference point, each later one the previous plus a relative vector.
    kinds: the k − 1 edges: "absolute", "relative", "normal", "tangential", "coriolis", "sliding".
    link: the link (or, for a sliding chain, the prismatic pair) the relative vectors belong to.
    """

    link: str
    target: str
    names: tuple[str, ...]
    xy: np.ndarray
    kinds: tuple[str, ...]


@dataclass(frozen=True)
class VectorPlan:
    """A velocity or acceleration plan at crank angle ``phi`` [rad], crank speed ``omega`` [rad/s]
    and acceleration ``epsilon`` [rad/s²]: ``vertices`` name → the closed form's vector (2,) or (3,) of
    that point (the pole (0, 0) under ``pole``), ``chains`` the relative vectors reaching them."""

    kind: str
    phi: float
    omega: float
    epsilon: float
    pole: str
    vertices: Mapping[str, np.ndarray]
    chains: tuple[Chain, ...]
    ground: tuple[str, ...]

    @property
    def unit(self) -> str:
        return UNITS[self.kind]

    @property
    def size(self) -> float:
        """The largest vertex's or chain vertex's distance from the pole [unit] (> 0 for a moving crank)."""
        pts = [np.linalg.norm(v) for v in self.vertices.values()]
        pts += [float(np.max(np.linalg.norm(c.xy, axis=1))) for c in self.chains]
        return float(max(pts))

    def closure(self) -> float:
        """The largest miss of a chain's end from its target's vertex, a fraction of ``size``."""
        size = self.size or 1.0
        return max((float(np.linalg.norm(c.xy[-1] - self.vertices[c.target])) / size for c in self.chains),
                   default=0.0)


def projected(plan: VectorPlan, basis: np.ndarray) -> VectorPlan:
    """``plan`` seen along a view: every vector times ``basis`` (2, d)ᵀ, the view's right and up."""
    b = np.asarray(basis, dtype=float).T
    return VectorPlan(plan.kind, plan.phi, plan.omega, plan.epsilon, plan.pole,
                      {k: np.asarray(v) @ b for k, v in plan.vertices.items()},
                      tuple(Chain(c.link, c.target, c.names, c.xy @ b, c.kinds) for c in plan.chains), plan.ground)


__all__ = ["Chain", "KINDS", "POLES", "UNITS", "VectorPlan", "check_kind", "pole_name", "projected"]

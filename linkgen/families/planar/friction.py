"""Coulomb friction in a linkage's lower pairs (``[[friction]]``, ``Friction``): the checks, and the
friction loads and losses the kinetostatics adds for given reactions.

At a revolute J between links (a, b) (the description's order) of pin radius r and coefficient μ,
the pin's friction couple on a is τ = −μ·r·|R|·sgn(θ̇_a − θ̇_b), R the reaction, and −τ on b: it
opposes the links' relative rotation. At a prismatic pair of coefficient μ whose block (centred on
the slider's point, ``block_length`` L along the guide) carries the normal force N and the moment M
about that point, the block bears on the guide at its two ends with N₁ = N/2 − M/L and
N₂ = N/2 + M/L (N₁ + N₂ = N, (L/2)·(N₂ − N₁) = M), so the friction force on the slider,
along the guide at its point, is −μ·(|N₁| + |N₂|)·sgn(ṡ) = −μ·max(|N|, 2|M|/L)·sgn(ṡ), ṡ the
slider's speed along its guide (in the guide's frame), and its opposite on the guide.

Where the relative motion stops (ω = 0, a dwell, a dead centre: |relative rate| ≤ STILL_TOL per
unit crank rate) the Coulomb force is indeterminate (anything up to the limit holds the pair);
linkgen then takes it as zero: the kinetostatics at rest is the frictionless one.

The power the friction takes out, P = Σ μ·r·|R|·|θ̇_a − θ̇_b| + Σ μ·(|N₁| + |N₂|)·|ṡ| ≥ 0, is
computed here from the pairs' relative rates alone, independently of how the loads are spread on
the links, for the kinetostatics' power balance.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.names import GROUND
from linkgen.model.units import bounded, shown

if TYPE_CHECKING:
    from linkgen.families.planar.description import Mechanism

# Largest friction coefficient: dry metal pairs are 0.1 … 0.8, rubber on steel ~1–2; 10 is far past
# any pair and keeps μ·|R| within linkgen's force limit for every reaction it allows.
MAX_COEFFICIENT = 10.0

# A pair whose relative rate per unit crank rate is at most this (rad/rad at a revolute; m/rad over
# the mechanism's size at a prismatic pair) is taken as still (its friction is zero). The rates are
# computed to ~1e-15 of their scale, so 1e-9 is far above their rounding and far below any motion
# the pair makes away from a dead centre or dwell.
STILL_TOL = 1e-9


@dataclass(frozen=True)
class Friction:
    """Coulomb friction in the lower pair ``pair`` (a revolute's or a prismatic pair's name):
    ``coefficient`` μ ≥ 0; a revolute's ``pin_radius`` r [m] > 0; a prismatic pair's
    ``block_length`` L [m] > 0 (module docstring)."""

    pair: str
    coefficient: float
    pin_radius: float | None = None
    block_length: float | None = None


def check_friction(m: Mechanism) -> None:
    """Raise DescriptionError for the first bad ``[[friction]]`` entry of ``m``."""
    revolutes = {r.name for r in m.revolutes}
    prismatics = {p.name for p in m.prismatics}
    seen: dict[str, int] = {}
    for i, f in enumerate(m.frictions):
        where = f"friction[{i}]"
        if f.pair not in revolutes | prismatics:
            raise DescriptionError(f"{where}.pair", f"unknown pair {f.pair!r}; revolutes: {sorted(revolutes)}, "
                                                    f"prismatic pairs: {sorted(prismatics)}")
        if f.pair in seen:
            raise DescriptionError(f"{where}.pair", f"pair {f.pair!r} already has friction in friction[{seen[f.pair]}]")
        seen[f.pair] = i
        bounded(f.coefficient, f"{where}.coefficient", MAX_COEFFICIENT, "")
        if f.coefficient < 0:
            raise DescriptionError(f"{where}.coefficient", f"must be >= 0, got {shown(f.coefficient)}")
        need, other = ("pin_radius", "block_length") if f.pair in revolutes else ("block_length", "pin_radius")
        kind = "revolute" if f.pair in revolutes else "prismatic pair"
        if getattr(f, other) is not None:
            raise DescriptionError(f"{where}.{other}", f"does not apply to the {kind} {f.pair!r}; give {need}")
        value = getattr(f, need)
        if value is None:
            raise DescriptionError(f"{where}.{need}", f"is required for the {kind} {f.pair!r}")
        bounded(value, f"{where}.{need}", limits.MAX_LENGTH, "m")
        if not value > 0:
            raise DescriptionError(f"{where}.{need}", f"must be > 0 m, got {shown(value)}")


@dataclass(frozen=True)
class FrictionLoads:
    """For given reactions: ``link`` → [force (n, 2) N, moment about its centre of mass (n,) N·m]
    of every pair's friction; ``pair`` → the friction couple on a revolute's first link [N·m] or the
    friction force on a slider along its guide's direction [N], (n,); ``loss`` the power the
    friction takes out per unit crank rate, Σ |friction·relative rate| (n,) [N·m] (≥ 0; times |ω|
    it is the power lost [W])."""

    link: dict[str, list[np.ndarray]]
    pair: dict[str, np.ndarray]
    loss: np.ndarray


def friction_loads(asm, kin, omega: np.ndarray, com: dict[str, np.ndarray], reactions: dict[str, np.ndarray],
                   normal: dict[str, np.ndarray], moment: dict[str, np.ndarray]) -> FrictionLoads:
    """The friction loads for the reactions (``kinetostatics``' conventions) at crank speed
    ``omega`` (n,), on the moving links whose centres of mass are ``com``."""
    mech = asm.mechanism
    n = kin.phi.shape[0]
    link: dict[str, list[np.ndarray]] = {}
    pair: dict[str, np.ndarray] = {}
    loss = np.zeros(n)
    for fr in mech.frictions:
        rel, moving = relative_rate(asm, kin, fr)
        if fr.pin_radius is not None:
            limit = fr.coefficient * fr.pin_radius * np.hypot(*reactions[fr.pair].T)
        else:
            limit = fr.coefficient * np.maximum(np.abs(normal[fr.pair]), 2.0 * np.abs(moment[fr.pair]) / fr.block_length)
        value = np.where(moving, -limit * np.sign(omega * rel), 0.0)
        for name, (f, m) in pair_loads(asm, kin, com, fr, value).items():
            total = link.setdefault(name, [np.zeros((n, 2)), np.zeros(n)])
            total[0] += f
            total[1] += m
        pair[fr.pair] = value
        loss += np.where(moving, limit * np.abs(rel), 0.0)
    return FrictionLoads(link, pair, loss)


def relative_rate(asm, kin, fr: Friction) -> tuple[np.ndarray, np.ndarray]:
    """The pair's relative rate per unit crank rate (n,) (θ̇_a − θ̇_b [rad/rad] at a revolute, the
    slider's ṡ [m/rad] at a prismatic pair) and where it moves (beyond STILL_TOL)."""
    n = kin.phi.shape[0]
    if fr.pin_radius is not None:
        a, b = asm.mechanism.revolute(fr.pair).links
        rel = np.broadcast_to((0.0 if a == GROUND else kin.links[a].angle.d1)
                              - (0.0 if b == GROUND else kin.links[b].angle.d1), (n,))
        return rel, np.abs(rel) > STILL_TOL
    rel = kin.sliders[fr.pair].d1
    return rel, np.abs(rel) > STILL_TOL * max(asm_size(asm), np.finfo(float).tiny)


def pair_loads(asm, kin, com: dict[str, np.ndarray], fr: Friction, value: np.ndarray) -> dict[str, list[np.ndarray]]:
    """The loads on the pair's moving links (force (n, 2) [N], moment about the centre of mass
    (n,) [N·m]) of its friction ``value`` (n,): the couple on a revolute's first link (its opposite
    on the second), the force on a slider along its guide (its opposite on the guide, both at the
    slider's point)."""
    n = kin.phi.shape[0]
    out: dict[str, list[np.ndarray]] = {}
    if fr.pin_radius is not None:
        for name, sign in zip(asm.mechanism.revolute(fr.pair).links, (1.0, -1.0)):
            if name != GROUND:
                out[name] = [np.zeros((n, 2)), sign * value]
        return out
    g = asm.guides[fr.pair]
    u = kin.links[g.guide].direction(g.alpha).p
    at = kin.links[g.slider].point(g.point).p
    for name, sign in ((g.slider, 1.0), (g.guide, -1.0)):
        if name != GROUND:
            force = sign * value[:, None] * u
            arm = at - com[name]
            out[name] = [force, arm[:, 0] * force[:, 1] - arm[:, 1] * force[:, 0]]
    return out


def asm_size(asm) -> float:
    """The mechanism's size [m]: the sketch's larger extent (x or y)."""
    xy = np.array(list(asm.mechanism.points.values()), dtype=float).reshape(-1, 2)
    return float(np.max(np.ptp(xy, axis=0))) if xy.shape[0] > 1 else 0.0


__all__ = ["MAX_COEFFICIENT", "STILL_TOL", "Friction", "FrictionLoads", "asm_size", "check_friction",
           "friction_loads", "pair_loads", "relative_rate"]

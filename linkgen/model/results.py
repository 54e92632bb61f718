"""The result vocabulary every family shares: one name per quantity in Python attributes, in
``to_dict()`` keys (JSON) and in CSV headers ("name.quantity[.x|.y|.z] [unit]").

A point moves with ``position``, ``velocity``, ``acceleration``, ``jerk`` [m, m/s, m/s², m/s³]; a
turning link or joint with ``angle``, ``angular_velocity``, ``angular_acceleration``,
``angular_jerk`` [rad, rad/s, rad/s², rad/s³]; a slider with ``displacement``, ``velocity``,
``acceleration``, ``jerk`` [m, ...]. Each also carries its transfer functions ``d1``, ``d2``,
``d3``: the first three derivatives of its value with respect to the drive angle φ [unit/rad,
unit/rad², unit/rad³]. A pair's reaction is a ``Reaction`` (``force`` [N], and ``moment`` [N·m]
where the pair carries one, acting ``on`` one link ``by`` another); every other pair's force says
``on`` and ``by`` alike (a prismatic pair's normal force, a gear's tooth force, a cam's contact
force, ``ContactForce``).

Values are shaped as the drive angle was given: a scalar φ gives a point's position (2,) or (3,)
and an angle a float; φ of shape (n,) gives (n, 2|3) and (n,)."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import ClassVar

import numpy as np

TRANSFER = ("d1", "d2", "d3")
AXES = "xyz"


def plain(x):
    """A number or an array as JSON-ready floats and lists."""
    if x is None or isinstance(x, (str, bool, int)) and not isinstance(x, np.generic):
        return x
    a = np.asarray(x)
    if a.dtype == bool:
        return bool(a) if a.ndim == 0 else a.tolist()
    return float(a) if a.ndim == 0 else a.astype(float).tolist()


def shaped(x, scalar: bool):
    """``x`` of shape (n, ...) as the caller gave φ: its first row for a scalar φ."""
    x = np.asarray(x)
    return (float(x[0]) if x.ndim == 1 else x[0].copy()) if scalar else x


def column(x, width: int | None = None) -> np.ndarray:
    """A value as CSV column(s): (n,) for a scalar quantity, (n, width) for a vector."""
    x = np.asarray(x, dtype=float)
    return np.atleast_1d(x) if width is None else x.reshape(-1, width)


def at_sample(result, i: int):
    """A sampled result (``phi`` of shape (n,)) at its ``i``-th drive angle, as if computed at that
    one angle: every per-sample value (an array whose first axis has the n samples, in the result
    and in its records and tables) indexed; words, inputs and non-sampled values kept."""
    n = np.size(result.phi)

    def pick(x):
        if isinstance(x, Record) or x is result:
            return replace(x, **{f.name: pick(getattr(x, f.name)) for f in fields(x) if f.init and f.compare})
        if isinstance(x, Mapping):
            return {k: pick(v) for k, v in x.items()}
        if isinstance(x, np.ndarray) and x.ndim >= 1 and x.shape[0] == n:
            v = x[i]
            return (bool(v) if v.dtype == bool else float(v)) if np.ndim(v) == 0 else v.copy()
        return x

    return pick(result)


def per_sample(text):
    """A result's ``text()`` (written for one drive angle) made to work on samples as well: a
    sampled result prints each angle's block, one after the other, separated by a blank line."""

    @functools.wraps(text)
    def each(self, *args, **kwargs):
        if np.ndim(self.phi) == 0:
            return text(self, *args, **kwargs)
        return "\n\n".join(text(at_sample(self, i), *args, **kwargs) for i in range(np.size(self.phi)))

    return each


class Record:
    """A frozen record of named quantities: ``to_dict()`` gives every field under its own name
    (None fields left out, the transfer functions only with ``transfer``), ``columns(name)`` one
    CSV column per field and axis, headed "name.field[.x|.y|.z] [unit]"."""

    UNIT: ClassVar[str] = ""  # the value's unit; the others follow from it (UNITS)
    UNITS: ClassVar[dict[str, str]] = {}

    def unit(self, name: str) -> str:
        if name in TRANSFER:
            return f"{self.UNIT}/rad" + {"d1": "", "d2": "²", "d3": "³"}[name]
        return self.UNITS.get(name, self.UNIT)

    def names(self, transfer: bool = True) -> list[str]:
        return [f.name for f in fields(self) if getattr(self, f.name) is not None
                and (transfer or f.name not in TRANSFER)]

    def to_dict(self, transfer: bool = True) -> dict:
        return {n: plain(getattr(self, n)) for n in self.names(transfer)}

    def columns(self, name: str, quantities=None, transfer: bool = True) -> dict[str, np.ndarray]:
        out = {}
        for q in quantities or self.names(transfer):
            x = getattr(self, q)
            if isinstance(x, str):
                continue
            x = np.asarray(x, dtype=float)
            width = x.shape[-1] if x.ndim == 2 or (x.ndim == 1 and getattr(self, "VECTOR", False)) else None
            x = column(x, width)
            if width is None:
                out[f"{name}.{q} [{self.unit(q)}]"] = x
            else:
                for i in range(width):
                    out[f"{name}.{q}.{AXES[i]} [{self.unit(q)}]"] = x[:, i]
        return out


@dataclass(frozen=True, repr=False)
class PointMotion(Record):
    """A point: position [m] (2,) or (3,) per angle, its time derivatives and transfer functions."""

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    d1: np.ndarray | None = None
    d2: np.ndarray | None = None
    d3: np.ndarray | None = None
    UNIT: ClassVar[str] = "m"
    UNITS: ClassVar[dict[str, str]] = {"velocity": "m/s", "acceleration": "m/s²", "jerk": "m/s³"}
    VECTOR: ClassVar[bool] = True

    def __repr__(self) -> str:
        return f"PointMotion(shape {np.shape(self.position)})"


@dataclass(frozen=True, repr=False)
class AngleMotion(Record):
    """A link's (or a turning joint's) angle [rad], its time derivatives and transfer functions."""

    angle: np.ndarray | float
    angular_velocity: np.ndarray | float
    angular_acceleration: np.ndarray | float
    angular_jerk: np.ndarray | float
    d1: np.ndarray | float | None = None
    d2: np.ndarray | float | None = None
    d3: np.ndarray | float | None = None
    UNIT: ClassVar[str] = "rad"
    UNITS: ClassVar[dict[str, str]] = {"angular_velocity": "rad/s", "angular_acceleration": "rad/s²",
                                       "angular_jerk": "rad/s³"}

    def __repr__(self) -> str:
        return f"AngleMotion(shape {np.shape(self.angle)})"


@dataclass(frozen=True, repr=False)
class SlideMotion(Record):
    """A slider's (or a sliding joint's) displacement [m], its time derivatives and transfer functions."""

    displacement: np.ndarray | float
    velocity: np.ndarray | float
    acceleration: np.ndarray | float
    jerk: np.ndarray | float
    d1: np.ndarray | float | None = None
    d2: np.ndarray | float | None = None
    d3: np.ndarray | float | None = None
    UNIT: ClassVar[str] = "m"
    UNITS: ClassVar[dict[str, str]] = {"velocity": "m/s", "acceleration": "m/s²", "jerk": "m/s³"}

    def __repr__(self) -> str:
        return f"SlideMotion(shape {np.shape(self.displacement)})"


@dataclass(frozen=True, repr=False)
class Reaction(Record):
    """The reaction in a pair: the ``force`` [N] (and ``moment`` [N·m] where the pair carries one)
    acting on link ``on``, exerted by link ``by``, world frame."""

    force: np.ndarray
    on: str
    by: str
    moment: np.ndarray | None = None
    UNIT: ClassVar[str] = "N"
    UNITS: ClassVar[dict[str, str]] = {"moment": "N·m"}
    VECTOR: ClassVar[bool] = True

    def __repr__(self) -> str:
        return f"Reaction(on {self.on!r} by {self.by!r}, shape {np.shape(self.force)})"


@dataclass(frozen=True, repr=False)
class ContactForce(Record):
    """A cam pair's contact force ``normal_force`` [N] along the profile's normal, acting on the
    follower ``on``, exerted by the cam's link ``by`` (< 0 where the follower would leave the cam)."""

    normal_force: np.ndarray | float
    on: str
    by: str
    UNIT: ClassVar[str] = "N"


# Units of the quantities a result names at its top level.
UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "position": "m", "velocity": "m/s",
         "acceleration": "m/s²", "jerk": "m/s³", "angle": "rad", "angular_velocity": "rad/s",
         "angular_acceleration": "rad/s²", "angular_jerk": "rad/s³", "displacement": "m",
         "d1": "unit/rad", "d2": "unit/rad²", "d3": "unit/rad³"}

__all__ = ["AngleMotion", "ContactForce", "PointMotion", "Reaction", "Record", "SlideMotion", "TRANSFER", "UNITS", "at_sample", "column",
           "per_sample", "plain", "shaped"]

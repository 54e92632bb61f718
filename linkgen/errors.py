"""One exception hierarchy for everything linkgen reports to a user."""

from __future__ import annotations

import re

import numpy as np

_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f]")


def printable(text: str) -> str:
    """``text`` with every control character (a line end, a terminal escape) shown by its code:
    a message names files and values a hostile user chose, and reaches a terminal."""
    return _CONTROL.sub(lambda m: f"\\x{ord(m.group()):02x}", text)


class LinkgenError(Exception):
    """Base class of every error linkgen raises on purpose."""


class DescriptionError(LinkgenError):
    """A mechanism description is malformed: names the field, the value and what is allowed.

    ``source`` is the description file (None for one built in Python); the message starts
    with it when known. File-level problems (unreadable, not TOML) have an empty ``field``.
    """

    def __init__(self, field: str, problem: str, source: str | None = None):
        self.field = field
        self.problem = problem
        self.source = source
        # a hostile key may hold control characters (a terminal escape): the message shows their codes
        shown = printable(field)
        super().__init__(": ".join(part for part in (source, shown, problem) if part))

    def in_file(self, source: str) -> "DescriptionError":
        """The same error attributed to the file ``source``."""
        return DescriptionError(self.field, self.problem, str(source))


class ArgumentError(LinkgenError, ValueError):
    """A function was given an argument outside what it accepts (crank angles, rates): the
    message names the argument, what it got and what is allowed."""


class UnsupportedError(ArgumentError):
    """A command or stage that the description's family does not take (the message names the
    families and commands that do apply)."""


class CouplingError(LinkgenError):
    """A loop-free export (``build --loops coupling``) that would miss its bound: the message
    gives the figure and a drive range that holds."""


class StructureError(LinkgenError):
    """The mechanism's structure is outside what linkgen solves (e.g. a class-III group)."""


def angle_ranges(phi: np.ndarray, mask: np.ndarray) -> list[tuple[float, float]]:
    """Contiguous runs of ``mask`` over ``phi`` as (first, last) crank angles [rad].

    Args:
        phi: crank angles [rad], shape (n,), in the order the caller evaluated them.
        mask: shape (n,), True where something failed.
    """
    phi = np.asarray(phi, dtype=float).reshape(-1)
    mask = np.asarray(mask, dtype=bool).reshape(-1)
    runs: list[tuple[float, float]] = []
    start = None
    for i, bad in enumerate(mask):
        if bad and start is None:
            start = i
        if start is not None and (not bad or i == len(mask) - 1):
            stop = i if bad else i - 1
            runs.append((float(phi[start]), float(phi[stop])))
            start = None
    return runs


def format_ranges(runs: list[tuple[float, float]], limit: int = 6) -> str:
    """Human-readable list of crank-angle ranges in degrees."""
    parts = []
    for lo, hi in runs[:limit]:
        lo_d, hi_d = np.degrees(lo), np.degrees(hi)
        parts.append(f"{lo_d:.3f}°" if lo == hi else f"{lo_d:.3f}°..{hi_d:.3f}°")
    more = f" and {len(runs) - limit} more" if len(runs) > limit else ""
    return ", ".join(parts) + more


def where_text(runs: list[tuple[float, float]], stroke: bool = False) -> str:
    """``crank angles 10.000°..20.000°``, or for a prismatic drive ``strokes s = 0.1..0.2 m``."""
    if not stroke:
        return f"crank angles {format_ranges(runs)}"
    parts = [f"{lo:.6g} m" if lo == hi else f"{lo:.6g}..{hi:.6g} m" for lo, hi in runs[:6]]
    return "strokes s = " + ", ".join(parts) + (f" and {len(runs) - 6} more" if len(runs) > 6 else "")


class AssemblyError(LinkgenError):
    """An Assur group cannot be assembled at some crank angles.

    Attributes:
        group: the group's label, e.g. ``"II(2,3) RRR [coupler, rocker]"``.
        ranges: list of (first, last) crank angles [rad] where assembly fails.
        assembles: (lo, hi) crank angles [rad] where the whole chain does assemble over a turn
            (exact edges), or None when not known.
        suggestion: TOML text for ``[drive]`` (``range = [...]``) running over the widest range
            where the chain is assembled and regular, or None.

    ``where``, if given, is called for (assembles, suggestion) the first time either or the
    message is asked for: a caller that catches the error to try other angles pays nothing.
    """

    def __init__(self, group: str, ranges: list[tuple[float, float]], reason: str, where=None, stroke: bool = False):
        self.group = group
        self.ranges = ranges  # strokes [m] for a prismatic drive (``stroke``)
        self.reason = reason
        self.stroke = stroke
        self._where = where
        self._found: tuple | None = None
        super().__init__(f"group {group} cannot be assembled at {where_text(ranges, stroke)}: {reason}")

    def _lookup(self) -> tuple:
        if self._found is None:
            self._found = (None, None) if self._where is None else tuple(self._where())
        return self._found

    @property
    def assembles(self) -> list[tuple[float, float]] | None:
        return self._lookup()[0]

    @property
    def suggestion(self) -> str | None:
        return self._lookup()[1]

    def __str__(self) -> str:
        assembles, suggestion = self._lookup()
        text = super().__str__()
        if assembles is not None:
            text += (f"; the chain assembles at crank angles {format_ranges(assembles)}" if assembles
                     else "; the chain assembles at no crank angle")
        if suggestion:
            text += f"; to run over the widest of them where it is regular, put under [drive]: {suggestion}"
        return text

    def __reduce__(self):  # pickled with what it found, not the function that finds it
        assembles, suggestion = self._lookup()
        return (_assembly_error, (self.group, self.ranges, self.reason, assembles, suggestion, self.stroke))


def _assembly_error(group, ranges, reason, assembles, suggestion, stroke=False) -> AssemblyError:
    return AssemblyError(group, ranges, reason, lambda: (assembles, suggestion), stroke)


class SingularityError(LinkgenError):
    """An Assur group is at or too near a dead centre (its normalised transfer-function
    denominator is below ``linkgen.families.planar.kinematics.SINGULAR_TOL``), or its guides are parallel.

    Attributes:
        group: the group's label; ranges: (first, last) crank angles [rad]; reason: in words.
    """

    def __init__(self, group: str, ranges: list[tuple[float, float]], reason: str, stroke: bool = False):
        self.group = group
        self.ranges = ranges
        self.reason = reason
        super().__init__(f"group {group} is singular at {where_text(ranges, stroke)}: {reason}")

    def __reduce__(self):
        return (type(self), (self.group, self.ranges, self.reason, "strokes" in str(self)))


class MagnitudeError(LinkgenError, ArithmeticError):
    """Values left the range float64 carries (about 1e-308 to 1.8e308) in the middle of a
    computation: the inputs' magnitudes (lengths, rates, loads) are too large or too small.

    Attributes:
        what: the quantity that overflowed; ranges: (first, last) crank angles [rad].
    """

    def __init__(self, what: str, ranges: list[tuple[float, float]]):
        self.what = what
        self.ranges = ranges
        super().__init__(
            f"{what} overflows float64 (magnitudes beyond ~1.8e308) at crank angles {format_ranges(ranges)}: "
            f"the description's lengths or the crank rates are too large for the computation"
        )


class BalanceError(LinkgenError):
    """The group-by-group balancing torque and the power balance disagree beyond the stated
    tolerance: a result linkgen cannot vouch for. Attributes: ranges, worst (relative)."""

    def __init__(self, ranges: list[tuple[float, float]], worst: float, tol: float):
        self.ranges = ranges
        self.worst = worst
        super().__init__(
            f"the balancing torque from the group-by-group solution and from the power balance disagree "
            f"by up to {worst:.3g} of the torque scale (allowed {tol:g}) at crank angles {format_ranges(ranges)}"
        )


class FrictionError(LinkgenError):
    """The kinetostatics with Coulomb friction has no solution (self-locking: no finite balancing
    torque moves the mechanism) or its iteration does not converge. Attributes: ranges."""

    def __init__(self, ranges: list[tuple[float, float]]):
        self.ranges = ranges
        super().__init__(
            f"the kinetostatics with friction finds no solution at crank angles {format_ranges(ranges)}: the friction "
            f"the pairs' reactions call for changes faster than the reactions themselves, so the mechanism self-locks "
            f"there (no finite balancing torque moves it) or is close to it; lower the friction coefficients or pin "
            f"radii, or lengthen the sliders' blocks"
        )


class SimulationError(LinkgenError):
    """MuJoCo warned, diverged or broke a constraint; names the step and the time."""


class ValidationError(LinkgenError):
    """A comparison was asked for that cannot be made (e.g. a timestep too coarse)."""


class RenderError(LinkgenError):
    """No OpenGL context could be opened for MuJoCo's offscreen rendering, or a frame size is
    outside what the model's offscreen buffer holds."""

"""The design summary's vocabulary, the same in every family (docs/format.md, "Conventions").

Every family's summary is a frozen dataclass whose attributes are its ``to_dict()`` keys
(``as_dict`` walks them), with these keys in common:

    model, omega [rad/s], epsilon [rad/s²], drive_range [rad, rad]: the drive angles summarised;
    units: the unit of each quantity below;
    outputs: output name → ``Output`` (kind "slider" [m] or "rocker" [rad], travel, limits,
             strokes, time_ratio): a slider under its prismatic pair's name, a turning output
             under its link's name (a stand-alone cam's follower under "follower"; a name both
             outputs have, each as "NAME (kind)": ``output_table``);
    peak_balancing_torque: ``Extreme`` (largest |torque| on the driving link [N·m], its φ);
    peak_reactions: pair name → ``Extreme`` (largest |force| [N], its φ), where the family
             computes pair reactions, with forces_note saying why when they are missing.

A drive angle is always ``phi`` [rad] (a crank's or a cam's angle, as ``analyze`` takes it).
Family-specific quantities (a planar group's least transmission angle, a cam's pressure angle
and curvature, a spatial chain's static indeterminacy) come after these, under their own
names."""

from __future__ import annotations

import math

from collections.abc import Mapping
from dataclasses import dataclass, fields, is_dataclass

from linkgen.model.results import plain

# The keys every family's summary has (``peak_reactions`` and ``forces_note`` only where the
# family computes pair reactions: not a stand-alone cam, whose one force is its contact force).
COMMON = ("model", "omega", "epsilon", "drive_range", "units", "outputs", "peak_balancing_torque")
REACTION_KEYS = ("peak_reactions", "forces_note")


@dataclass(frozen=True)
class Extreme:
    """The largest (or least) value of a quantity over the drive range and the drive angle φ [rad]
    where it occurs."""

    value: float
    phi: float


@dataclass(frozen=True)
class Limit:
    """An extreme position of an output: the drive angle φ [rad], the output's value there (m or
    rad, as ``analyze`` gives it) and whether it is the least ("min") or the greatest ("max")."""

    phi: float
    value: float
    kind: str


@dataclass(frozen=True)
class Output:
    """A slider (kind "slider", displacement [m]) or a turning output (kind "rocker", angle [rad]).
    ``travel``: its stroke [m] or swing [rad] (max − min; None for a link that turns fully round);
    ``limits``: its interior extremes in drive-angle order (None where the family does not locate
    them: a cam's follower rests at its extremes over the program's dwells); ``strokes``: the
    drive's turn [rad] of the min → max and the max → min stroke and ``time_ratio`` K = the longer
    over the shorter (≥ 1 at constant speed), where there are exactly two limits over a turn."""

    kind: str
    travel: float | None
    limits: tuple[Limit, ...] | None
    strokes: tuple[float, float] | None = None
    time_ratio: float | None = None


def output_table(outputs) -> dict[str, Output]:
    """(name, Output) pairs → ``outputs``: each under its name, or, where a prismatic pair and a
    ground-pivoted link share a name (both outputs, a slider and a rocker), under "NAME (slider)"
    and "NAME (rocker)", so that neither hides the other."""
    outputs = list(outputs)
    names = [n for n, _ in outputs]
    return {(n if names.count(n) == 1 else f"{n} ({o.kind})"): o for n, o in outputs}


def as_dict(x):
    """A summary (or any of its parts) as JSON-ready data: a dataclass → its attributes by name,
    a mapping → the same keys, a tuple → a list, numbers → floats."""
    if is_dataclass(x) and not isinstance(x, type):
        return {f.name: as_dict(getattr(x, f.name)) for f in fields(x)}
    if isinstance(x, Mapping):
        return {k: as_dict(v) for k, v in x.items()}
    if isinstance(x, (tuple, list)):
        return [as_dict(v) for v in x]
    return plain(x)


def summary_dict(s) -> dict:
    """``s``'s attributes by name, ``units`` after ``drive_range`` (the keys of ``COMMON`` first)."""
    d = as_dict(s)
    out = {k: d.pop(k) for k in ("model", "omega", "epsilon", "drive_range")}
    return out | {"units": dict(s.units)} | d


def _degrees(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


def summary_text(s, what: str = "") -> str:
    """The design summary as the terminal shows it (``linkgen analyze --summary``), the same for
    every family: the header (``what`` names the mechanism's kind), each output's travel, limit
    positions and time ratio, the least transmission angles where the family has them, the peak
    balancing torque and reactions. Angles in degrees."""
    start, stop = s.drive_range
    lines = [f"{s.model}: design summary{what} over φ = {_degrees(start)}..{_degrees(stop)} at ω = {s.omega:g} rad/s, "
             f"ε = {s.epsilon:g} rad/s²"]
    for key, o in s.outputs.items():
        name = key.removesuffix(f" ({o.kind})")
        if o.travel is None:
            lines.append(f"  {o.kind} {name}: turns fully round (no swing, no limit positions)")
            continue
        travel = f"stroke {o.travel:.6g} m" if o.kind == "slider" else f"swing {_degrees(o.travel)} ({o.travel:.6g} rad)"
        lines.append(f"  {o.kind} {name}: {travel}")
        for lim in o.limits:
            value = f"{lim.value:.6g} m" if o.kind == "slider" else f"{_degrees(lim.value)}"
            lines.append(f"    limit position ({lim.kind}) at φ = {_degrees(lim.phi)}: {value}")
        if not o.limits:
            lines.append("    no limit position inside the range (its extremes are at the range's ends)")
        if o.time_ratio is not None:
            lines.append(f"    min→max over {_degrees(o.strokes[0])} of crank turn, max→min over {_degrees(o.strokes[1])}: "
                         f"time ratio K = {o.time_ratio:.6g} (at constant ω)")
    lines += force_lines(s, lambda phi: f"φ = {_degrees(phi)}")
    return "\n".join(lines)


def force_lines(s, at, balancing: str = "peak balancing torque: {:.6g} N·m") -> list[str]:
    """The summary's lines on transmission angles, the peak balancing load (``balancing``, its
    value's format), the peak reactions and the forces' note, each position written by ``at``
    (the drive's coordinate, [rad] or [m], to text)."""
    lines = [f"  transmission angle of {group}: least {_degrees(t.value)} at {at(t.phi)}"
             for group, t in (getattr(s, "min_transmission_angle", None) or {}).items()]
    if s.peak_balancing_torque is not None:
        t = s.peak_balancing_torque
        lines.append(f"  {balancing.format(t.value)} at {at(t.phi)}")
        lines += [f"  peak reaction at {name}: {p.value:.6g} N at {at(p.phi)}"
                  for name, p in sorted(s.peak_reactions.items(), key=lambda kv: -kv[1].value)]
    if s.forces_note:
        lines.append(f"  {s.forces_note}")
    return lines


__all__ = ["summary_text", "COMMON", "REACTION_KEYS", "Extreme", "Limit", "Output", "as_dict", "output_table", "summary_dict"]

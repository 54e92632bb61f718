"""The planar family's ``structure`` stage as a result with ``to_dict()`` and ``text()``
(``linkgen structure``), and the design summary's text (``linkgen analyze --summary``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkgen.model.names import GROUND
from linkgen.model.summary import force_lines



def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


@dataclass(frozen=True)
class StructureGroup:
    """A class-II Assur group: its label ("II(2,3) RRR [coupler, rocker]"), kind (RRR, RRP, RPR,
    PRP, RPP), its two links, its three pairs (outer, inner, outer), the known links it attaches
    to and its assembly mode m (+1 or -1)."""

    label: str
    kind: str
    links: tuple[str, str]
    pairs: tuple[str, str, str]
    known: tuple[str, str]
    assembly_mode: int


@dataclass(frozen=True)
class PlanarStructure:
    """Mobility (Chebyshev–Grübler), the crank and its drive pair, the Assur groups with their
    assembly modes in attachment order, the structure formula, and the lines ``text()`` prints
    (with where the crank turns); the attributes are the ``to_dict()`` keys."""

    model: str
    mobility: int
    crank: str
    drive: str
    formula: str
    groups: tuple[StructureGroup, ...]
    lines: tuple[str, ...]

    def to_dict(self) -> dict:
        from linkgen.model.summary import as_dict

        return as_dict(self)

    def text(self) -> str:
        return "\n".join(self.lines)


def structure(source) -> PlanarStructure:
    """The planar family's ``structure`` stage: the chain assembled, its groups and turn."""
    from linkgen.families.planar.assembly import Assembly, assemble
    from linkgen.families.planar.cam_pair import oscillating
    from linkgen.families.planar.checks import mobility_formula

    asm = source if isinstance(source, Assembly) else assemble(source)
    s, mech = asm.structure, asm.mechanism
    lines = [f"mechanism: {mech.name}",
             f"mobility {mobility_formula(s.moving_links, s.lower_pairs, len(mech.gears) + len(mech.cams))}"]
    for g in mech.gears:
        lines.append(f"gear pair {g.name!r}: planet {g.planet!r} on the crank, {g.kind} mesh {g.teeth[0]}/"
                     f"{g.teeth[1]} teeth, module {g.module:g} m: the planet turns {g.ratio:+g} times the crank")
    for c in mech.cams:
        kind = "oscillating about its pivot" if oscillating(mech, c) else "translating on its guide"
        lines.append(f"cam pair {c.name!r}: the cam on the crank drives the follower {c.follower!r} ({kind}) through "
                     f"its roller at {c.roller!r} (radius {c.roller_radius:g} m), a higher pair")
    if mech.slide_drive and GROUND not in s.drive.links:
        pj = mech.prismatic(s.drive.name)
        lines.append(f"input: the stroke s [m] of the prismatic pair {s.drive.name!r} between the cylinder "
                     f"{pj.guide!r} and its rod {pj.slider!r} (a linear actuator); with the rocker they form the "
                     f"first group, a triangle whose side from the cylinder's pivot to the rod's pin the stroke sets")
    elif mech.slide_drive:
        lines.append(f"input link: I(0,1) slider {s.crank!r}, driven along the prismatic pair {s.drive.name!r} "
                     f"(a linear actuator: the input is its stroke s [m])")
    else:
        lines.append(f"input link: I(0,1) crank {s.crank!r}, driven at {s.drive.name!r}")
    for g, m in zip(s.groups, asm.branches):
        pairs = ", ".join(f"{p.kind} {p.name}" for p in g.pairs)
        lines.append(f"group {g.label}: pairs {pairs}; attached to {list(g.known)}; assembly mode m = {m:+d}")
    lines.append(f"structure formula: {s.formula}")
    groups = tuple(StructureGroup(g.label, g.kind.value, g.links, tuple(p.name for p in g.pairs), g.known, int(m))
                   for g, m in zip(s.groups, asm.branches))
    return PlanarStructure(mech.name, s.mobility, s.crank, s.drive.name, s.formula, groups,
                           tuple(lines + (stroke_lines(asm) if mech.slide_drive else turn_lines(asm))))


# Strokes over a prismatic drive's range at which ``stroke_lines`` checks the chain.
STROKE_SAMPLES = 1001


def stroke_lines(asm) -> list[str]:
    """Whether a prismatic drive's stroke range lies where the chain is assembled and regular, checked
    at STROKE_SAMPLES strokes by the block solver's own failure and dead-centre masks."""
    import numpy as np

    from linkgen.errors import angle_ranges, where_text
    from linkgen.families.planar.kinematics import solve_block

    d = asm.mechanism.drive
    s = np.linspace(d.start, d.stop, STROKE_SAMPLES)
    report: list = []
    with np.errstate(all="ignore"):
        solve_block(asm, s, True, report)
    fails = np.zeros(s.shape[0], dtype=bool)
    rough = np.zeros(s.shape[0], dtype=bool)
    for _, fail, overflow, singular in report:
        fails |= fail
        rough |= overflow | singular
    given = f"the drive's stroke s = {d.start:.6g}..{d.stop:.6g} m (drive.start, drive.stop)"
    if not fails.any() and not rough.any():
        return [f"{given} lies where the chain is assembled and regular (checked at {STROKE_SAMPLES} strokes)"]
    lines = []
    if fails.any():
        lines.append(f"{given}: the chain cannot be assembled at {where_text(angle_ranges(s, fails), True)}")
    if (rough & ~fails).any():
        lines.append(f"{given}: the chain is at or near a dead centre at "
                     f"{where_text(angle_ranges(s, rough & ~fails), True)}")
    return lines


def turn_lines(asm) -> list[str]:
    """Whether the crank turns fully and where the chain assembles (``linkgen.model.turn``)."""
    from linkgen.families.planar.kinematics import planar_turn
    from linkgen.model.turn import EDGE_TOL, degrees_text, drive_range_text

    t = planar_turn(asm)
    how = f"scanned every 0.1°, edges bisected to {EDGE_TOL:g} rad"
    if t.full:
        lines = [f"crank: turns fully — the chain assembles at every crank angle ({how})"]
        if not t.regular:
            lines.append(f"regular at crank angles {degrees_text(t.clean)}; dead centres in between")
        return lines
    lines = [f"crank: does not turn fully — the chain assembles at crank angles {degrees_text(t.assembles)} "
             f"and cannot at {degrees_text(t.fails)} ({how}); it rocks between dead centres"]
    d = asm.mechanism.drive
    given = f"the drive's crank-angle range {math.degrees(d.start):.6g}°..{math.degrees(d.stop):.6g}°"
    turns = [(lo + k * 2 * math.pi, hi + k * 2 * math.pi) for lo, hi in t.clean for k in (-1, 0, 1)]
    if any(lo - 1e-12 <= d.start and d.stop <= hi + 1e-12 for lo, hi in turns):
        lines.append(f"{given} lies where the chain is assembled and regular")
        return lines
    best = t.suggestion()
    if best is not None:
        lines.append(f"{given} leaves where the chain is regular; to run over the widest range where it is, put "
                     f"under [drive]: {drive_range_text(best)}")
    return lines


def summary_text(s) -> str:
    """The design summary as the terminal shows it (``linkgen analyze --summary``): the text every
    family shares (``model.summary.summary_text``)."""
    from linkgen.model.summary import summary_text as common

    lines = [stroke_summary_text(s) if s.stroke else common(s)]
    for name, p in s.peak_spring_forces.items():
        what, unit = ("torque", "N·m") if name.startswith("torsion") else ("force", "N")
        where = f"s = {p.phi:.6g} m" if s.stroke else f"φ = {math.degrees(p.phi):.6g}°"
        lines.append(f"  peak {what} of {name}: {p.value:.6g} {unit} at {where}")
    if s.peak_friction_power is not None:
        p = s.peak_friction_power
        where = f"s = {p.phi:.6g} m" if s.stroke else f"φ = {math.degrees(p.phi):.6g}°"
        lines.append(f"  power lost to friction: peak {p.value:.6g} W at {where}, mean "
                     f"{s.mean_friction_power:.6g} W")
    return "\n".join(lines)


def stroke_summary_text(s) -> str:
    """The design summary of a linkage with a prismatic drive: each output's travel, its limit
    positions and its travel per unit input stroke (the mean transmission ratio), strokes in m."""
    start, stop = s.drive_range
    span = stop - start
    at = "s = {:.6g} m".format
    lines = [f"{s.model}: design summary over the stroke s = {start:.6g}..{stop:.6g} m ({span:.6g} m) at "
             f"ṡ = {s.omega:g} m/s, s̈ = {s.epsilon:g} m/s²"]
    for key, o in s.outputs.items():
        name = key.removesuffix(f" ({o.kind})")
        if o.kind == "slider" and name == s.drive_joint:
            lines.append(f"  slider {name}: stroke {o.travel:.6g} m (the drive's own)")
        elif o.kind == "slider":
            lines.append(f"  slider {name}: stroke {o.travel:.6g} m, {o.travel / span:.6g} m per m of input stroke")
        else:
            lines.append(f"  rocker {name}: swing {_deg(o.travel)} ({o.travel:.6g} rad), {math.degrees(o.travel / span):.6g}°"
                         f" ({o.travel / span:.6g} rad) per m of input stroke")
        for lim in o.limits:
            value = f"{lim.value:.6g} m" if o.kind == "slider" else _deg(lim.value)
            lines.append(f"    limit position ({lim.kind}) at {at(lim.phi)}: {value}")
        if not o.limits:
            lines.append("    no limit position inside the stroke (its extremes are at the stroke's ends)")
    lines += force_lines(s, at, "peak balancing force along the drive's guide: {:.6g} N")
    return "\n".join(lines)


__all__ = ["PlanarStructure", "StructureGroup", "stroke_lines", "structure", "summary_text", "turn_lines"]

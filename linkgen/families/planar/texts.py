"""The planar family's ``structure`` stage as a result with ``to_dict()`` and ``text()``
(``linkgen structure``), and the design summary's text (``linkgen analyze --summary``)."""

from __future__ import annotations

import math
from dataclasses import dataclass



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
    lines.append(f"input link: I(0,1) crank {s.crank!r}, driven at {s.drive.name!r}")
    for g, m in zip(s.groups, asm.branches):
        pairs = ", ".join(f"{p.kind} {p.name}" for p in g.pairs)
        lines.append(f"group {g.label}: pairs {pairs}; attached to {list(g.known)}; assembly mode m = {m:+d}")
    lines.append(f"structure formula: {s.formula}")
    groups = tuple(StructureGroup(g.label, g.kind.value, g.links, tuple(p.name for p in g.pairs), g.known, int(m))
                   for g, m in zip(s.groups, asm.branches))
    return PlanarStructure(mech.name, s.mobility, s.crank, s.drive.name, s.formula, groups,
                           tuple(lines + turn_lines(asm)))


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

    lines = [common(s)]
    for name, p in s.peak_spring_forces.items():
        what, unit = ("torque", "N·m") if name.startswith("torsion") else ("force", "N")
        lines.append(f"  peak {what} of {name}: {p.value:.6g} {unit} at φ = {math.degrees(p.phi):.6g}°")
    if s.peak_friction_power is not None:
        p = s.peak_friction_power
        lines.append(f"  power lost to friction: peak {p.value:.6g} W at φ = {math.degrees(p.phi):.6g}°, mean "
                     f"{s.mean_friction_power:.6g} W")
    return "\n".join(lines)


__all__ = ["PlanarStructure", "StructureGroup", "structure", "summary_text", "turn_lines"]

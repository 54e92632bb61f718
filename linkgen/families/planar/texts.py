"""The planar family's ``structure`` and ``summary`` stages as results with ``to_dict()`` and
``text()`` (``linkgen structure``, ``linkgen analyze --summary``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from linkgen.families.planar.summary import DesignSummary


def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


@dataclass(frozen=True, repr=False)
class PlanarStructure:
    """Mobility, the Assur groups with their assembly modes, the structure formula and where the
    crank turns; ``structure``: the ``Structure`` (its attributes are this result's too)."""

    model: str
    structure: object
    lines: tuple[str, ...]
    branches: tuple[int, ...] = field(default=())

    def __getattr__(self, name):  # the Structure's attributes (groups, formula, ...)
        if name.startswith("__") or name in ("structure", "lines", "model", "branches"):
            raise AttributeError(name)
        return getattr(self.structure, name)

    def to_dict(self) -> dict:
        s = self.structure
        return {"model": self.model, "crank": s.crank, "formula": s.formula,
                "groups": [{"label": g.label, "kind": g.kind.name, "links": list(g.links),
                            "pairs": [p.name for p in g.pairs], "known": list(g.known), "assembly_mode": m}
                           for g, m in zip(s.groups, self.branches or (None,) * len(s.groups))],
                "lines": list(self.lines)}

    def text(self) -> str:
        return "\n".join(self.lines)

    def __repr__(self) -> str:
        return f"PlanarStructure({self.model!r}, {self.structure.formula!r})"


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
    return PlanarStructure(mech.name, s, tuple(lines + turn_lines(asm)), tuple(asm.branches))


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


@dataclass(frozen=True, repr=False)
class PlanarSummary:
    """The design summary over the drive range ``start``..``stop`` [rad] (``summary``: the
    ``DesignSummary``, whose attributes are this result's too)."""

    summary: DesignSummary
    start: float
    stop: float

    def __getattr__(self, name):
        if name.startswith("__") or name in ("summary", "start", "stop"):
            raise AttributeError(name)
        return getattr(self.summary, name)

    def to_dict(self) -> dict:
        return self.summary.to_dict()

    def text(self) -> str:
        s = self.summary
        lines = [f"{s.model}: design summary over φ = {_deg(self.start)}..{_deg(self.stop)} at ω = {s.omega:g} rad/s, "
                 f"ε = {s.epsilon:g} rad/s²"]
        for o in s.outputs:
            if o.travel is None:
                lines.append(f"  {o.kind} {o.name}: turns fully round (no swing, no limit positions)")
                continue
            travel = f"stroke {o.travel:.6g} m" if o.kind == "slider" else f"swing {_deg(o.travel)} ({o.travel:.6g} rad)"
            lines.append(f"  {o.kind} {o.name}: {travel}")
            for lim in o.limits:
                value = f"{lim.value:.6g} m" if o.kind == "slider" else f"{_deg(lim.value)}"
                lines.append(f"    limit position ({lim.kind}) at φ = {_deg(lim.phi)}: {value}")
            if not o.limits:
                lines.append("    no limit position inside the range (its extremes are at the range's ends)")
            if o.time_ratio is not None:
                lines.append(f"    min→max over {_deg(o.strokes[0])} of crank turn, max→min over {_deg(o.strokes[1])}: "
                             f"time ratio K = {o.time_ratio:.6g} (at constant ω)")
        for t in s.transmission:
            lines.append(f"  transmission angle of {t.group}: least {_deg(t.minimum)} at φ = {_deg(t.at)}")
        if s.torque is not None:
            lines.append(f"  peak balancing torque: {s.torque.value:.6g} N·m at φ = {_deg(s.torque.at)}")
            for p in sorted(s.reactions, key=lambda p: -p.value):
                lines.append(f"  peak reaction at {p.name}: {p.value:.6g} N at φ = {_deg(p.at)}")
        else:
            lines.append(f"  {s.forces_note}")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"PlanarSummary({self.summary.model!r})"


def summary(source, omega=None, epsilon=None) -> PlanarSummary:
    """The planar family's ``summary`` stage (``families.planar.summary.summarize``)."""
    from linkgen.families.planar.assembly import Assembly, assemble
    from linkgen.families.planar.summary import summarize

    asm = source if isinstance(source, Assembly) else assemble(source)
    d = asm.mechanism.drive
    return PlanarSummary(summarize(asm, d.omega if omega is None else omega, d.epsilon if epsilon is None else epsilon),
                         d.start, d.stop)


__all__ = ["PlanarStructure", "PlanarSummary", "structure", "summary", "turn_lines"]

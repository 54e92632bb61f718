"""The spatial four-bar's ``structure`` stage as a result with ``to_dict()`` and ``text()``
(``linkgen structure``), and the design summary's text (``linkgen analyze --summary``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SpatialStructure:
    """The chain's mobility (the true one: the spatial formula's, less an idle freedom, or the
    planar/spherical/Bennett one of an overconstrained chain), its kind (RSSR, RSSP, ...), its
    links (crank, coupler, output), the drive pair and the output pair, and the lines ``text()``
    prints (the formula, the pairs, where it assembles); the attributes are the ``to_dict()``
    keys."""

    model: str
    mobility: int
    crank: str
    drive: str
    kind: str
    coupler: str
    output: str
    pair_out: str
    lines: tuple[str, ...]

    def to_dict(self) -> dict:
        from linkgen.model.summary import as_dict

        return as_dict(self)

    def text(self) -> str:
        return "\n".join(self.lines)


def structure(mech) -> SpatialStructure:
    """The spatial family's ``structure`` stage."""
    from linkgen.families.spatial.kinematics import assembled_chain

    c = assembled_chain(mech)
    lines = [f"{mech.name}: spatial {c.kind} four-bar — {'input slider' if c.input_slides else 'crank'} {c.crank!r} "
             f"(driven at {c.drive!r}), coupler "
             f"{c.coupler!r}, output {c.output!r} ({'sliding on' if c.output_slides else 'turning about'} its pair "
             f"{c.pair_out!r})"]
    spherical = sum(1 for j in mech.joints if j.kind == "spherical")
    cylindrical = sum(1 for j in mech.joints if j.kind == "cylindrical")
    lower = len(mech.joints) + len(mech.slides) - spherical - cylindrical
    lines.append(f"mobility by the spatial formula W = 6·n − 5·p5 − 4·p4 − 3·p3 = 6·3 − 5·{lower} − 4·{cylindrical} − "
                 f"3·{spherical} = {c.mobility_formula}")
    if c.kind == "RCCC":
        lines.append("no idle freedom and no repeated constraint: the coupler keeps the twist and the distance of its "
                     "two axes, which fix the output's turn and slide")
    elif c.idle:
        lines.append(f"idle freedom: {c.idle} (moves no other point); the mechanism's mobility is {c.mobility}")
    else:
        why = {"spherical": "all axes meet at one point: the spherical family, W = 3·n − 2·p5 = 3·3 − 2·4 = 1",
               "planar": "all axes are parallel: the planar family, W = 3·n − 2·p5 = 3·3 − 2·4 = 1",
               "Bennett": "Bennett's conditions hold (opposite links equal in length and twist, zero offsets, "
                          "a1·sin α2 = a2·sin α1): three constraints repeat, W = 1"}[c.kind]
        lines.append(f"overconstrained: {why}")
    lines.append("pairs: " + ", ".join(f"{j.kind} {j.name} [{j.links[0]}, {j.links[1]}]" for j in mech.joints)
                 + "".join(f", prismatic {s.name} [{s.guide}, {s.slider}]" for s in mech.slides))
    if c.kind == "RCCC":
        lines.append("a cylindrical pair's point belongs to its first link (A: the crank's, B: the coupler's); the later "
                     "link's copy, which slides along the axis, is named POINT:LINK")
    lines.append(_assembly_range(mech, c))
    return SpatialStructure(mech.name, int(c.mobility), c.crank, c.drive, c.kind, c.coupler, c.output, c.pair_out,
                            tuple(lines))


def _status(mech, chain):
    """Crank angles (n,) [rad] → (fails, singular) masks of the spatial chain, for
    ``linkgen.model.turn`` (the scan and bisection planar linkages use as well)."""
    from linkgen.errors import AssemblyError, SingularityError
    from linkgen.families.spatial.kinematics import solve

    def within(phi, ranges):
        return np.any([(phi >= lo) & (phi <= hi) for lo, hi in ranges], axis=0)

    def at(phi):
        fails, singular = np.zeros(phi.shape[0], bool), np.zeros(phi.shape[0], bool)
        try:
            solve(mech, phi, chain)
        except AssemblyError as exc:
            fails = within(phi, exc.ranges)
            if not fails.all():
                try:
                    solve(mech, phi[~fails], chain)
                except SingularityError as sing:
                    singular[~fails] = within(phi[~fails], sing.ranges)
        except SingularityError as exc:
            singular = within(phi, exc.ranges)
        return fails, singular

    return at


def _assembly_range(mech, chain) -> str:
    """Whether the chain assembles over the whole turn of its crank, or where it does not."""
    from linkgen.model.turn import EDGE_TOL, degrees_text, turn_assembly

    if chain.input_slides:  # assembled_chain has checked the range; a dead centre is found by solve
        from linkgen.errors import SingularityError
        from linkgen.families.spatial.kinematics import RANGE_SAMPLES, solve

        lo, hi = chain.input_range
        try:
            solve(mech, np.linspace(lo, hi, RANGE_SAMPLES), chain)
        except SingularityError as exc:
            return f"assembly: over the input's range {lo:.6g}..{hi:.6g} m, with {exc}"
        return (f"assembly: over the input's range {lo:.6g}..{hi:.6g} m (checked at {RANGE_SAMPLES} displacements), "
                "no dead centre")
    t = turn_assembly(_status(mech, chain))
    if not t.full:
        return (f"assembly: not over the whole turn — the coupler cannot reach the output at crank angles "
                f"{degrees_text(t.fails)}; the crank can only rock in the rest ({degrees_text(t.assembles)}; edges "
                f"bisected to {EDGE_TOL:g} rad)")
    if not t.regular:
        return (f"assembly: over the whole turn, regular at crank angles {degrees_text(t.clean)} "
                "(dead centres in between)")
    return "assembly: over the whole turn of the crank (checked every 0.1°)"


def summary_text(sm) -> str:
    """The design summary as the terminal shows it (``linkgen analyze --summary``): the text every
    family shares (``model.summary.summary_text``), naming the chain's kind."""
    from linkgen.model.summary import summary_text as common

    if sm.input_slides:
        return _slide_summary_text(sm)
    return common(sm, f" of the spatial {sm.kind}")


def _slide_summary_text(sm) -> str:
    """The design summary of a chain driven by a slider: the input's displacement s [m] where
    a crank has φ, the balancing force [N] where it has the torque."""
    import math

    start, stop = sm.drive_range
    lines = [f"{sm.model}: design summary of the spatial {sm.kind} over s = {start:.6g}..{stop:.6g} m at "
             f"v = {sm.omega:g} m/s, a = {sm.epsilon:g} m/s²"]
    for name, o in sm.outputs.items():
        slider = o.kind == "slider"
        lines.append(f"  {o.kind} {name}: " + (f"stroke {o.travel:.6g} m" if slider else
                                                f"swing {math.degrees(o.travel):.6g}° ({o.travel:.6g} rad)"))
        for lim in o.limits:
            value = f"{lim.value:.6g} m" if slider else f"{math.degrees(lim.value):.6g}°"
            lines.append(f"    limit position ({lim.kind}) at s = {lim.phi:.6g} m: {value}")
    t = sm.peak_balancing_torque
    lines.append(f"  peak balancing force: {t.value:.6g} N at s = {t.phi:.6g} m")
    for name, p in sorted(sm.peak_reactions.items(), key=lambda kv: -kv[1].value):
        lines.append(f"  peak reaction at {name}: {p.value:.6g} N at s = {p.phi:.6g} m")
    if sm.forces_note:
        lines.append(f"  {sm.forces_note}")
    return "\n".join(lines)


__all__ = ["SpatialStructure", "structure", "summary_text"]

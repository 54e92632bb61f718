"""The spatial four-bar's ``structure`` and ``summary`` stages as results with ``to_dict()`` and
``text()`` (``linkgen structure``, ``linkgen analyze --summary``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.spatial.summary import SpatialSummary


@dataclass(frozen=True, repr=False)
class SpatialStructure:
    """The chain's kind and links, its mobility by the spatial formula (and why a lower one
    holds), its pairs and where it assembles; ``chain``: the assembled ``Chain``."""

    model: str
    chain: object
    lines: tuple[str, ...]

    def __getattr__(self, name):  # the chain's attributes (kind, crank, coupler, output, ...)
        if name.startswith("__") or name in ("model", "chain", "lines"):
            raise AttributeError(name)
        return getattr(self.chain, name)

    def to_dict(self) -> dict:
        c = self.chain
        return {"model": self.model, "kind": c.kind, "crank": c.crank, "coupler": c.coupler, "output": c.output,
                "drive": c.drive, "pair_out": c.pair_out, "mobility": c.mobility, "lines": list(self.lines)}

    def text(self) -> str:
        return "\n".join(self.lines)

    def __repr__(self) -> str:
        return f"SpatialStructure({self.model!r}, {self.chain.kind})"


def structure(mech) -> SpatialStructure:
    """The spatial family's ``structure`` stage."""
    from linkgen.families.spatial.kinematics import assembled_chain

    c = assembled_chain(mech)
    lines = [f"{mech.name}: spatial {c.kind} four-bar — crank {c.crank!r} (driven at {c.drive!r}), coupler "
             f"{c.coupler!r}, output {c.output!r} ({'sliding on' if c.output_slides else 'turning about'} its pair "
             f"{c.pair_out!r})"]
    spherical = sum(1 for j in mech.joints if j.kind == "spherical")
    lower = len(mech.joints) + len(mech.slides) - spherical
    lines.append(f"mobility by the spatial formula W = 6·n − 5·p5 − 3·p3 = 6·3 − 5·{lower} − 3·{spherical} = "
                 f"{c.mobility_formula}")
    if c.idle:
        lines.append(f"idle freedom: {c.idle} (moves no other point); the mechanism's mobility is {c.mobility}")
    else:
        why = {"spherical": "all axes meet at one point: the spherical family, W = 3·n − 2·p5 = 3·3 − 2·4 = 1",
               "planar": "all axes are parallel: the planar family, W = 3·n − 2·p5 = 3·3 − 2·4 = 1",
               "Bennett": "Bennett's conditions hold (opposite links equal in length and twist, zero offsets, "
                          "a1·sin α2 = a2·sin α1): three constraints repeat, W = 1"}[c.kind]
        lines.append(f"overconstrained: {why}")
    lines.append("pairs: " + ", ".join(f"{j.kind} {j.name} [{j.links[0]}, {j.links[1]}]" for j in mech.joints)
                 + "".join(f", prismatic {s.name} [{s.guide}, {s.slider}]" for s in mech.slides))
    lines.append(_assembly_range(mech, c))
    return SpatialStructure(mech.name, c, tuple(lines))


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

    t = turn_assembly(_status(mech, chain))
    if not t.full:
        return (f"assembly: not over the whole turn — the coupler cannot reach the output at crank angles "
                f"{degrees_text(t.fails)}; the crank can only rock in the rest ({degrees_text(t.assembles)}; edges "
                f"bisected to {EDGE_TOL:g} rad)")
    if not t.regular:
        return (f"assembly: over the whole turn, regular at crank angles {degrees_text(t.clean)} "
                "(dead centres in between)")
    return "assembly: over the whole turn of the crank (checked every 0.1°)"


@dataclass(frozen=True, repr=False)
class SpatialSummaryResult:
    """The design summary over one turn (``summary``: the ``SpatialSummary``, whose attributes
    are this result's too)."""

    summary: SpatialSummary

    def __getattr__(self, name):
        if name.startswith("__") or name == "summary":
            raise AttributeError(name)
        return getattr(self.summary, name)

    def to_dict(self) -> dict:
        return self.summary.to_dict()

    def text(self) -> str:
        sm = self.summary
        rad = sm.unit != "m"
        show = (lambda v: f"{math.degrees(v):.6g}°") if rad else (lambda v: f"{v:.6g} m")
        if sm.swing is None:
            lines = [f"{sm.model}: spatial {sm.kind}, output {sm.output!r} turns fully with the crank (no limit "
                     "positions)"]
        else:
            lines = [f"{sm.model}: spatial {sm.kind}, output {sm.output!r}: {'swing' if rad else 'stroke'} "
                     f"{show(sm.swing)} (positions measured from the sketch)"]
        for kind, a, v in sm.limits:
            lines.append(f"  limit position ({kind}) at φ = {math.degrees(a):.6g}°: {show(v)}")
        if sm.time_ratio is not None:
            work = 360.0 * sm.time_ratio / (1.0 + sm.time_ratio)
            lines.append(f"  min→max over {work:.6g}° of crank turn, max→min over {360.0 - work:.6g}°: time ratio "
                         f"K = {sm.time_ratio:.6g} (at constant ω)")
        t, a = sm.peak_torque
        lines.append(f"  peak balancing torque: {t:.6g} N·m at φ = {math.degrees(a):.4g}°")
        for name, (v, a) in sm.peak_pair_forces.items():
            lines.append(f"  peak force at pair {name}: {v:.6g} N at φ = {math.degrees(a):.4g}°")
        if sm.indeterminate:
            lines.append(f"  pair forces: statically indeterminate by {sm.indeterminate}, not summarised")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"SpatialSummaryResult({self.summary.model!r})"


def summary(mech, omega=None, epsilon=None) -> SpatialSummaryResult:
    """The spatial family's ``summary`` stage over one turn at ω and ε (default the drive's;
    ``families.spatial.summary`` reads them from the description's drive)."""
    from dataclasses import replace

    from linkgen.families.spatial.summary import summarize

    d = mech.drive
    drive = replace(d, omega=d.omega if omega is None else float(omega),
                    epsilon=d.epsilon if epsilon is None else float(epsilon))
    return SpatialSummaryResult(summarize(mech if drive == d else replace(mech, drive=drive)))


__all__ = ["SpatialStructure", "SpatialSummaryResult", "structure", "summary"]

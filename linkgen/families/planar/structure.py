"""Structural analysis: mobility, decomposition into the input link and class-II Assur groups.

The input link (``crank``) is the crank of a revolute drive, or the slider of a prismatic drive
(a linear actuator on a guide fixed to the ground): it and the ground are known first.

A prismatic drive between two moving links (a hydraulic cylinder pivoted on the ground, its rod
pinned to a rocker) has no input link: for a given stroke the cylinder and its rod are one rigid
body whose pivot-to-pin distance the stroke sets, and with the rocker they form the first group,
the ``ACTUATOR`` (links cylinder, rocker; ``third`` the rod): a triangle pivot–pin–rocker pivot,
an RRR dyad whose first side changes with the stroke. The other groups follow as usual."""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import TYPE_CHECKING

from linkgen.errors import StructureError
from linkgen.model.names import GROUND
from linkgen.families.planar.decompose import Conn, decompose

if TYPE_CHECKING:
    from linkgen.families.planar.description import Mechanism


class GroupKind(enum.Enum):
    """The five class-II groups (dyads), named by their joints: outer, inner, outer."""

    RRR = "RRR"
    RRP = "RRP"
    RPR = "RPR"
    PRP = "PRP"
    RPP = "RPP"
    ACTUATOR = "R(P)R-R"  # a driven cylinder and rod with a rocker (module docstring)


@dataclass(frozen=True)
class Pair:
    """A kinematic pair as the structure sees it: kind 'R' or 'P', name, the two links."""

    kind: str
    name: str
    links: tuple[str, str]

    def other(self, link: str) -> str:
        return self.links[1] if self.links[0] == link else self.links[0]


@dataclass(frozen=True)
class Group:
    """A class-II Assur group, oriented so that its kind is one of GroupKind.

    Attributes:
        links: (L1, L2); L1 is attached to the known link ``known[0]`` by ``pairs[0]``,
            L2 to ``known[1]`` by ``pairs[2]``; ``pairs[1]`` joins L1 and L2.
        numbers: the links' numbers in the structure formula.
    """

    kind: GroupKind
    links: tuple[str, str]
    pairs: tuple[Pair, Pair, Pair]
    known: tuple[str, str]
    numbers: tuple[int, int]
    third: str | None = None  # an ACTUATOR's rod (the driven pair joins it to links[0], pairs[1] to links[1])

    @property
    def label(self) -> str:
        if self.kind is GroupKind.ACTUATOR:
            return (f"actuator({self.numbers[0]},{self.numbers[1]},{self.numbers[1] + 1}) {self.kind.value} "
                    f"[{self.links[0]}, {self.third}, {self.links[1]}]")
        return f"II({self.numbers[0]},{self.numbers[1]}) {self.kind.value} [{self.links[0]}, {self.links[1]}]"


@dataclass(frozen=True)
class Structure:
    """Mobility and the Assur-group decomposition, groups in attachment order."""

    mobility: int
    moving_links: int
    lower_pairs: int
    crank: str
    drive: Pair
    groups: tuple[Group, ...]

    @property
    def formula(self) -> str:
        """E.g. ``I(0,1) → II(2,3) → II(4,5)``; with a driven cylinder ``A(1,2,3) → II(4,5)``."""
        parts = [] if self.groups and self.groups[0].kind is GroupKind.ACTUATOR else ["I(0,1)"]
        parts += [f"A({g.numbers[0]},{g.numbers[1]},{g.numbers[1] + 1})" if g.kind is GroupKind.ACTUATOR
                  else f"II({g.numbers[0]},{g.numbers[1]})" for g in self.groups]
        return " → ".join(parts)


_KINDS = {k.value for k in GroupKind}

def pairs_of(mech: Mechanism) -> list[Pair]:
    """All lower pairs of the mechanism, revolutes then prismatics, in description order."""
    out = [Pair("R", j.name, j.links) for j in mech.revolutes]
    out += [Pair("P", j.name, (j.slider, j.guide)) for j in mech.prismatics]
    return out


def drive_pair(mech: Mechanism, pairs: list[Pair] | None = None) -> Pair:
    """The driven pair: the crank's revolute with ground, or a prismatic drive's pair."""
    kind = "P" if mech.slide_drive else "R"
    return next(p for p in (pairs_of(mech) if pairs is None else pairs) if p.kind == kind and p.name == mech.drive.joint)


def actuator(mech: Mechanism, pairs: list[Pair], drive: Pair) -> Group:
    """The ACTUATOR group of a prismatic drive between two moving links (module docstring): the
    guide (the cylinder) pivoted on the ground, the slider (the rod) pinned to a rocker that is
    pivoted on the ground, each by a revolute. StructureError saying what is needed otherwise."""
    pj = mech.prismatic(drive.name)
    cyl, rod = pj.guide, pj.slider
    revs = [p for p in pairs if p.kind == "R"]

    def grounded(link: str) -> list[Pair]:
        return [p for p in revs if set(p.links) == {link, GROUND}]

    need = (f"the driven prismatic pair {pj.name!r} joins two moving links: its guide {cyl!r} (the cylinder) must "
            f"be pivoted on {GROUND!r} and its slider {rod!r} (the rod) pinned to one rocker pivoted on {GROUND!r}")
    a = grounded(cyl)
    b = [p for p in revs if rod in p.links and p.other(rod) not in (GROUND, cyl) and len(grounded(p.other(rod))) == 1]
    if len(a) != 1 or len(b) != 1:
        raise StructureError(f"{need}; {cyl!r} has {len(a)} revolutes with {GROUND!r} and {rod!r} is pinned to "
                             f"{len(b)} links pivoted on {GROUND!r}")
    rocker = b[0].other(rod)
    return Group(GroupKind.ACTUATOR, (cyl, rocker), (a[0], b[0], grounded(rocker)[0]), (GROUND, GROUND), (1, 2), rod)


def analyze(mech: Mechanism) -> Structure:
    """Mobility (Chebyshev–Grübler) and the decomposition into class-II groups (``decompose``).

    Raises:
        StructureError: a link is not connected, or some links form a group of a class
            higher than II (not supported), naming the links.
    """
    pairs = pairs_of(mech)
    n = len(mech.moving_links)
    drive = drive_pair(mech, pairs)
    crank = mech.crank
    first: list[Group] = []
    if GROUND not in drive.links:
        first = [actuator(mech, pairs, drive)]
        known = (first[0].third, first[0].links[1])
    else:
        extra = [p for p in pairs if p is not drive and set(p.links) == {GROUND, crank}]
        if extra:
            raise StructureError(f"the crank {crank!r} has another pair with ground ({extra[0].name!r})")
        known = mech.planets
    raw, rest = decompose({l.name: l.points for l in mech.links},
                          [(j.name, j.slider, j.guide) for j in mech.prismatics if j.name != drive.name or not first],
                          crank, known)
    if rest:
        raise StructureError(
            f"links {rest} do not decompose into class-II Assur groups attached to the "
            f"{'actuator' if first else 'crank'}; groups of class III and higher are not supported"
        )
    revolute = {(j.point, frozenset(j.links)): Pair("R", j.name, j.links) for j in mech.revolutes}
    prismatic = {p.name: p for p in pairs if p.kind == "P"}

    def pair(conn: Conn) -> Pair:
        kind, name, links = conn
        return revolute[(name, frozenset(links))] if kind == "R" else prismatic[name]

    groups = first
    for i, ((l1, l2), conns) in enumerate(raw, start=len(first)):
        o1, inner, o2 = (pair(c) for c in conns)
        kind = o1.kind + inner.kind + o2.kind
        if kind not in _KINDS:  # PRR -> RRP, PPR -> RPP
            l1, l2, o1, o2 = l2, l1, o2, o1
            kind = o1.kind + inner.kind + o2.kind
        if kind not in _KINDS:
            raise StructureError(f"links {[l1, l2]} form a PPP group, which has no defined position")
        groups.append(Group(GroupKind(kind), (l1, l2), (o1, inner, o2), (o1.other(l1), o2.other(l2)),
                            (2 + 2 * i, 3 + 2 * i)))
    return Structure(
        mobility=3 * n - 2 * len(pairs) - len(mech.gears) - len(mech.cams),
        moving_links=n,
        lower_pairs=len(pairs),
        crank=crank,
        drive=drive,
        groups=tuple(groups),
    )


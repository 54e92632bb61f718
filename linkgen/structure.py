"""Structural analysis: mobility, decomposition into the input link and class-II Assur groups."""

from __future__ import annotations

import enum
import heapq
from collections import defaultdict
from dataclasses import dataclass

from .description import GROUND, Mechanism
from .errors import StructureError


class GroupKind(enum.Enum):
    """The five class-II groups (dyads), named by their joints: outer, inner, outer."""

    RRR = "RRR"
    RRP = "RRP"
    RPR = "RPR"
    PRP = "PRP"
    RPP = "RPP"


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

    @property
    def label(self) -> str:
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
        """E.g. ``I(0,1) → II(2,3) → II(4,5)``."""
        parts = ["I(0,1)"] + [f"II({g.numbers[0]},{g.numbers[1]})" for g in self.groups]
        return " → ".join(parts)


_KINDS = {k.value for k in GroupKind}

# A connection as the decomposition sees it: ("R", point, (link, link)) for a revolute at a
# point, ("P", name, (slider, guide)) for a prismatic pair.
Conn = tuple[str, str, tuple[str, str]]


def pairs_of(mech: Mechanism) -> list[Pair]:
    """All lower pairs of the mechanism, revolutes then prismatics, in description order."""
    out = [Pair("R", j.name, j.links) for j in mech.revolutes]
    out += [Pair("P", j.name, (j.slider, j.guide)) for j in mech.prismatics]
    return out


def decompose(link_points: dict[str, tuple[str, ...]], prismatics: list[tuple[str, str, str]],
              crank: str) -> tuple[list[tuple[tuple[str, str], tuple[Conn, Conn, Conn]]], list[str]]:
    """Class-II groups from the links' points and prismatic pairs, in attachment order.

    Works on points, not on revolutes: at a point carried by k links (a compound hinge) each
    link is joined to the carrier that became known first (of a group's two links, the one
    whose name sorts first), or, for a group's inner pair, to the group's other link; the
    decomposition thus chooses the k - 1 revolutes and the result does not depend on the
    order of the links or of their points. Among groups ready at the
    same time the one whose links come first in ``link_points`` is taken (this only numbers
    them). Time: each link is visited when it or a neighbour becomes known, so close to
    linear in the number of links for bounded numbers of pairs per link.

    Args:
        link_points: link name → its points, in description order (ground included).
        prismatics: (name, slider, guide) per prismatic pair.
        crank: the driven link; it and ground are known from the start.

    Returns:
        ([((link1, link2), (outer1, inner, outer2)), ...], links left over): outer1 joins
        link1 to a known link, inner joins the two links, outer2 joins link2; link1 is the
        one listed first.
    """
    order = {name: i for i, name in enumerate(link_points)}
    carriers: dict[str, list[str]] = defaultdict(list)
    for name, pts in link_points.items():
        for p in dict.fromkeys(pts):
            carriers[p].append(name)
    slides: dict[str, list[tuple[str, str, str]]] = defaultdict(list)
    for pr in prismatics:
        slides[pr[1]].append(pr)
        if pr[2] != pr[1]:
            slides[pr[2]].append(pr)
    known: set[str] = set()
    anchor: dict[str, str] = {}  # point -> its first known carrier
    ext = dict.fromkeys(link_points, 0)  # connections of each unknown link to the known ones
    heap: list[tuple[int, int, str, str]] = []

    def between(a: str, b: str) -> list[Conn]:
        out: list[Conn] = [("R", p, (a, b)) for p in dict.fromkeys(link_points[a])
                           if p not in anchor and b in carriers[p]]
        return out + [("P", pr[0], (pr[1], pr[2])) for pr in slides[a] if b in (pr[1], pr[2]) and pr[1] != pr[2]]

    def outer(link: str) -> Conn:
        for p in dict.fromkeys(link_points[link]):
            if p in anchor:
                return ("R", p, (anchor[p], link))
        pr = next(pr for pr in slides[link] if (pr[2] if pr[1] == link else pr[1]) in known)
        return ("P", pr[0], (pr[1], pr[2]))

    def look(link: str) -> None:
        """Queue every group ``link`` can form now."""
        if link in known or ext.get(link) != 1:
            return
        partners = {m for p in link_points[link] if p not in anchor for m in carriers[p]}
        partners |= {m for pr in slides[link] for m in pr[1:]}
        for m in partners:
            if m != link and m not in known and ext.get(m) == 1 and len(between(link, m)) == 1:
                a, b = sorted((order[link], order[m]))
                heapq.heappush(heap, (b, a, link, m))

    def make_known(link: str) -> list[str]:
        known.add(link)
        touched = []
        for p in dict.fromkeys(link_points[link]):
            if p in anchor:
                continue
            anchor[p] = link
            for other in carriers[p]:
                if other not in known:
                    ext[other] += 1
                    touched.append(other)
        for pr in slides[link]:
            other = pr[2] if pr[1] == link else pr[1]
            if other not in known and other in ext:
                ext[other] += 1
                touched.append(other)
        return touched

    touched = make_known(GROUND) + make_known(crank) if crank in link_points and GROUND in link_points else []
    groups: list[tuple[tuple[str, str], tuple[Conn, Conn, Conn]]] = []
    while True:
        for link in dict.fromkeys(touched):
            look(link)
        touched = []
        while heap:
            _, _, l1, l2 = heapq.heappop(heap)
            if l1 in known or l2 in known or ext[l1] != 1 or ext[l2] != 1:
                continue
            inner = between(l1, l2)
            if len(inner) != 1:
                continue
            if order[l2] < order[l1]:
                l1, l2 = l2, l1
            groups.append(((l1, l2), (outer(l1), inner[0], outer(l2))))
            first, second = sorted((l1, l2))  # by name: a compound hinge's pairs ignore table order
            touched = make_known(first) + make_known(second)
            break
        if not touched:
            break
    return groups, [name for name in link_points if name not in known]


def analyze(mech: Mechanism) -> Structure:
    """Mobility (Chebyshev–Grübler) and the decomposition into class-II groups (``decompose``).

    Raises:
        StructureError: a link is not connected, or some links form a group of a class
            higher than II (not supported), naming the links.
    """
    pairs = pairs_of(mech)
    n = len(mech.moving_links)
    drive = next(p for p in pairs if p.kind == "R" and p.name == mech.drive.joint)
    crank = mech.crank
    extra = [p for p in pairs if p is not drive and set(p.links) == {GROUND, crank}]
    if extra:
        raise StructureError(f"the crank {crank!r} has another pair with ground ({extra[0].name!r})")
    raw, rest = decompose({l.name: l.points for l in mech.links},
                          [(j.name, j.slider, j.guide) for j in mech.prismatics], crank)
    if rest:
        raise StructureError(
            f"links {rest} do not decompose into class-II Assur groups attached to the crank; "
            f"groups of class III and higher are not supported"
        )
    revolute = {(j.point, frozenset(j.links)): Pair("R", j.name, j.links) for j in mech.revolutes}
    prismatic = {p.name: p for p in pairs if p.kind == "P"}

    def pair(conn: Conn) -> Pair:
        kind, name, links = conn
        return revolute[(name, frozenset(links))] if kind == "R" else prismatic[name]

    groups = []
    for i, ((l1, l2), conns) in enumerate(raw):
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
        mobility=3 * n - 2 * len(pairs),
        moving_links=n,
        lower_pairs=len(pairs),
        crank=crank,
        drive=drive,
        groups=tuple(groups),
    )


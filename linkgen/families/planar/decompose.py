"""The decomposition of a linkage into the input link and class-II Assur groups, on link
names and points alone (the description uses it to pair the links of compound hinges)."""

from __future__ import annotations

import heapq
from collections import defaultdict

from linkgen.model.names import GROUND

# A connection as the decomposition sees it: ("R", point, (link, link)) for a revolute at a
# point, ("P", name, (slider, guide)) for a prismatic pair.
Conn = tuple[str, str, tuple[str, str]]



def decompose(link_points: dict[str, tuple[str, ...]], prismatics: list[tuple[str, str, str]],
              crank: str, planets: tuple[str, ...] = ()) -> tuple[list[tuple[tuple[str, str], tuple[Conn, Conn, Conn]]], list[str]]:
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
        planets: links a gear pair ties to the crank (their first point on it): known next.

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
    for planet in planets:
        if planet in link_points and planet not in known:
            touched += make_known(planet)
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

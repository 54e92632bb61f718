"""The structure of a spatial four-bar: which link is the crank, the coupler and the output, the
kind of chain, its mobility, and its exact geometry at the sketch.

Kinds (the crank is the driven revolute with the ground, or for PSSR and PSSP the input slider
on its driven prismatic pair with the ground):
    RSSR       spherical pairs at both ends of the coupler, the output turns on a revolute;
    RSSP       spherical pairs at both ends of the coupler, the output slides on a line;
    PSSR       RSSR with a slider as the input;
    PSSP       RSSP with a slider as the input;
    RCCC       three cylindrical pairs (each turning about and sliding along its axis) after the
               crank, on any axes (``rccc``);
    spherical  four revolutes whose axes meet at one point (the centre);
    planar     four revolutes with parallel axes;
    Bennett    four revolutes on skew axes with Bennett's conditions (opposite links equal in
               length and twist, zero offsets, a1·sin α2 = a2·sin α1).

Mobility by the spatial structure formula W = 6n − 5p5 − 3p3 (n moving links; p5 revolute or
prismatic, p4 cylindrical, p3 spherical pairs: W = 6n − 5p5 − 4p4 − 3p3). RCCC gives 1.
RSSR, RSSP, PSSR and PSSP give 2: one is the idle spin of the coupler about
the line through its two spherical pairs, which moves nothing else (a slender coupler's inertia
about that line is zero). The 4R chains give −2: three constraints repeat themselves, by the
common centre (spherical: W = 3n − 2p5 = 1 in the spherical family), the parallel axes (planar:
W = 3n − 2p5 = 1) or Bennett's conditions (W = 1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.errors import DescriptionError, StructureError, format_ranges
from linkgen.model.names import GROUND
from linkgen.families.spatial.description import SpatialMechanism

KINDS = ("RSSR", "RSSP", "PSSR", "PSSP", "RCCC", "spherical", "planar", "Bennett")
# Geometric conditions (axes meeting, parallel, Bennett's equalities) hold to this fraction of
# the mechanism's size (or in radians): a description written to 9 significant digits passes.
GEOMETRY_TOL = 1e-8


@dataclass(frozen=True)
class Chain:
    """A spatial four-bar at its sketch: link names, pair names, kind, mobility figures and the
    exact geometry (world frame, m; unit axes).

    ``a0``/``ka``: the drive pivot and axis (a prismatic input: the slider's point at the sketch
    and its line's direction); ``ref``: the direction φ is measured from; ``phi_s``: the crank
    angle of the sketch [rad] (0 for a prismatic input, whose coordinate s is the displacement
    from the sketch); ``input_slides``: the input is a slider; ``input_range``: the input's
    range, a full turn (0, 2π) [rad] for a crank, (start, stop) [m] for a slider; ``A``, ``B``: the coupler's pair points at
    the sketch (B as described, before assembly); ``length``: the coupler's |AB| [m];
    ``b0``/``kb``: the output's pivot and axis (revolute) or the line's point and direction
    (prismatic); ``centre``: the common point of a spherical chain; ``ua``/``ub``: the axes of
    the coupler's revolutes at the sketch (4R chains)."""

    kind: str
    crank: str
    coupler: str
    output: str
    drive: str
    pair_a: str
    pair_b: str
    pair_out: str
    a0: np.ndarray
    ka: np.ndarray
    ref: np.ndarray
    phi_s: float
    A: np.ndarray
    B: np.ndarray
    length: float
    b0: np.ndarray
    kb: np.ndarray
    output_slides: bool
    centre: np.ndarray | None
    ua: np.ndarray | None
    ub: np.ndarray | None
    size: float
    mobility_formula: int
    mobility: int
    idle: str
    input_slides: bool = False
    input_range: tuple[float, float] = (0.0, 2 * math.pi)
    drive_point: str = ""

    def input_samples(self, n: int) -> np.ndarray:
        """``n`` input values: over a crank's turn (its end excluded), or over a slider's range
        (both ends)."""
        lo, hi = self.input_range
        return np.linspace(lo, hi, n, endpoint=self.input_slides)

    def worded(self, exc, verb: str):
        """``exc`` (AssemblyError or SingularityError) with its input values worded for this
        chain's input (crank angles in degrees, a slider's displacements in metres)."""
        Exception.__init__(exc, f"group {exc.group} {verb} at {self.input_text(exc.ranges)}: {exc.reason}")
        return exc

    def input_text(self, runs) -> str:
        """(first, last) input values as the user reads them: crank angles in degrees, or a
        slider's displacements in metres."""
        if not self.input_slides:
            return "crank angles " + format_ranges(runs)
        return "input displacements " + ", ".join(f"{lo:.6g} m" if lo == hi else f"{lo:.6g}..{hi:.6g} m"
                                                  for lo, hi in runs)

    @property
    def input_unit(self) -> float:
        """The input's natural unit: 1 rad for a crank, the size [m] for a slider (a point of
        the chain moves by about the size when the input moves by this much)."""
        return self.size if self.input_slides else 1.0

    @property
    def output_variable(self) -> str:
        return "displacement" if self.output_slides else "angle"


def reference_direction(axis: np.ndarray) -> np.ndarray:
    """The unit direction φ is measured from for a revolute with ``axis``: the world axis least
    aligned with it (x, then y, then z on ties), projected onto the plane square to it."""
    k = int(np.argmin(np.abs(axis) + np.array([0.0, 1e-12, 2e-12])))
    e = np.zeros(3)
    e[k] = 1.0
    e = e - axis * float(axis @ e)
    return e / np.linalg.norm(e)


def angle_about(axis: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angle [rad] of v (…, 3) about ``axis`` from ``reference_direction(axis)``."""
    ref = reference_direction(axis)
    side = np.cross(axis, ref)
    return np.arctan2(v @ side, v @ ref)


def _line_distance(p1, u1, p2, u2) -> float:
    n = np.cross(u1, u2)
    if np.linalg.norm(n) < 1e-12:
        d = p2 - p1
        return float(np.linalg.norm(d - u1 * (d @ u1)))
    return float(abs((p2 - p1) @ n) / np.linalg.norm(n))


def build_chain(mech: SpatialMechanism) -> Chain:
    """Recognise the four-bar and fix its geometry; StructureError for anything else."""
    moving = [l for l in mech.links if l.name != GROUND]
    if len(moving) != 3:
        raise StructureError(f"{mech.name}: a spatial mechanism is solved as a four-bar (three moving links: crank, "
                             f"coupler, output); this one has {len(moving)} moving link(s)")
    slide_in = mech.drive.slides
    drive = next(s for s in mech.slides if s.name == mech.drive.joint) if slide_in else mech.joint(mech.drive.joint)
    crank = drive.slider if slide_in else (drive.links[1] if drive.links[0] == GROUND else drive.links[0])
    pairs = list(mech.joints) + list(mech.slides)
    if len(pairs) != 4:
        raise StructureError(f"{mech.name}: a four-bar has four pairs; this one has {len(pairs)} "
                             f"({', '.join(p.name for p in pairs)})")

    def other(j, name):
        return j.links[1] if j.links[0] == name else j.links[0]

    at_crank = [j for j in mech.joints if crank in j.links and j is not drive]
    if len(at_crank) != 1 or GROUND in at_crank[0].links:
        raise StructureError(f"{mech.name}: the crank {crank} must join the ground (pair {drive.name}) and one coupler")
    ja = at_crank[0]
    coupler = other(ja, crank)
    at_coupler = [j for j in mech.joints if coupler in j.links and j is not ja]
    if len(at_coupler) != 1 or GROUND in at_coupler[0].links:
        raise StructureError(f"{mech.name}: the coupler {coupler} must join the crank and an output link, with one pair each")
    jb = at_coupler[0]
    output = other(jb, coupler)
    ground_pairs = [j for j in mech.joints if GROUND in j.links and output in j.links]
    slides = [s for s in mech.slides if {s.slider, s.guide} == {output, GROUND} and s is not drive]
    if len(ground_pairs) + len(slides) != 1:
        raise StructureError(f"{mech.name}: the output link {output} must join the ground by one revolute or one prismatic pair")
    slides_out = bool(slides)
    pts = [p for l in mech.links for p in l.points]
    size = max(math.dist(mech.points[p], mech.points[q]) for p in pts for q in pts) or 1.0

    a0 = mech.point(drive.point if slide_in else drive.name)
    ka = np.array(drive.direction if slide_in else drive.axis)
    ref = reference_direction(ka)
    A = mech.point(ja.name)
    crank_link = mech.link(crank)
    if slide_in:
        phi_s = 0.0  # the input's coordinate: the slider's displacement from its sketch position
    else:
        if crank_link.length is not None:  # the crank's length is exact: scale A about the pivot
            A = a0 + (A - a0) * (crank_link.length / np.linalg.norm(A - a0))
        ra = A - a0
        if np.linalg.norm(ra - ka * (ka @ ra)) < GEOMETRY_TOL * size:
            raise DescriptionError(f"joints.{ja.name}", f"point {ja.name} lies on the drive axis: the crank moves nothing")
        phi_s = float(angle_about(ka, ra))
    B = mech.point(jb.name)
    if slides_out:
        s = slides[0]
        if s.point != jb.name:
            raise StructureError(f"{mech.name}: prismatic.{s.name}.point must be the coupler's pair {jb.name}")
        b0, kb, pair_out = B.copy(), np.array(s.direction), s.name
    else:
        jo = ground_pairs[0]
        if jo.kind not in ("revolute", "cylindrical"):
            raise StructureError(f"{mech.name}: the output's pair with the ground, {jo.name}, must be revolute, "
                                 "cylindrical or prismatic")
        b0, kb, pair_out = mech.point(jo.name), np.array(jo.axis), jo.name
        out_link = mech.link(output)
        if out_link.length is not None and jo.kind == "revolute":
            B = b0 + (B - b0) * (out_link.length / np.linalg.norm(B - b0))
    coupler_link = mech.link(coupler)
    L = coupler_link.length if coupler_link.length is not None else float(np.linalg.norm(B - A))

    kinds = (ja.kind, jb.kind)
    centre = ua = ub = None
    out_kind = "prismatic" if slides_out else ground_pairs[0].kind
    if "cylindrical" in (*kinds, out_kind) and (kinds, out_kind, slide_in) != (("cylindrical",) * 2, "cylindrical", False):
        raise StructureError(
            f"{mech.name}: the chain's pairs after the crank are {ja.kind} {ja.name}, {jb.kind} {jb.name}, {out_kind} "
            f"{pair_out}; with cylindrical pairs linkgen solves the RCCC chain: a crank on a revolute, then three "
            "cylindrical pairs")
    if kinds == ("cylindrical", "cylindrical"):
        ua, ub = np.array(ja.axis), np.array(jb.axis)
        kind, formula, idle = "RCCC", 6 * 3 - 5 * 1 - 4 * 3, ""
        _check_rccc(mech, (drive.name, ka), (ja.name, ua), (jb.name, ub), (pair_out, kb))
    elif kinds == ("spherical", "spherical"):
        kind = ("P" if slide_in else "R") + ("SSP" if slides_out else "SSR")
        formula, idle = 6 * 3 - 5 * 2 - 3 * 2, f"the coupler {coupler!r} spins about the line {ja.name}{jb.name}"
    elif kinds == ("revolute", "revolute") and not slides_out and not slide_in:
        formula, idle = 6 * 3 - 5 * 4, ""
        ua, ub = np.array(ja.axis), np.array(jb.axis)
        axes = [(a0, ka), (A, ua), (B, ub), (b0, kb)]
        kind, centre = _four_revolutes(mech, axes, size, (drive.name, ja.name, jb.name, pair_out))
    else:
        raise StructureError(
            f"{mech.name}: the coupler {coupler} has a {ja.kind} pair at {ja.name} and a {jb.kind} pair at {jb.name}"
            f"{' and the output slides' if slides_out else ''}{' and the input slides' if slide_in else ''}; linkgen "
            "solves RSSR, RSSP, PSSR and PSSP (spherical pairs at both ends) and the 4R chains (spherical, planar, "
            "Bennett) driven by a crank")
    span = mech.drive.range if slide_in else (0.0, 2 * math.pi)
    return Chain(kind, crank, coupler, output, drive.name, ja.name, jb.name, pair_out, a0, ka, ref, phi_s, A, B, L,
                 b0, kb, slides_out, centre, ua, ub, size, formula, 1, idle, slide_in, span,
                 drive.point if slide_in else drive.name)


def _check_rccc(mech, drive, pa, pb, pout) -> None:
    """No two successive axes of an RCCC may be parallel: the crank would not turn A's axis, or
    the coupler's twist would not fix the output's turn."""
    pairs = [drive, pa, pb, pout]
    for (n1, u1), (n2, u2) in zip(pairs, pairs[1:] + pairs[:1]):
        if np.linalg.norm(np.cross(u1, u2)) < GEOMETRY_TOL:
            raise StructureError(f"{mech.name}: the axes of {n1} and {n2} are parallel; an RCCC needs skew successive "
                                 "axes (with parallel ones the coupler's twist does not fix the output's turn)")


def _four_revolutes(mech, axes, size: float, names) -> tuple[str, np.ndarray | None]:
    """Classify a loop of four revolutes (point, unit axis): planar, spherical or Bennett."""
    us = [u for _, u in axes]
    if all(np.linalg.norm(np.cross(us[0], u)) < GEOMETRY_TOL for u in us):
        return "planar", None
    # spherical: the least-squares common point of the four axis lines lies on every one
    m = sum(np.eye(3) - np.outer(u, u) for u in us)
    rhs = sum((np.eye(3) - np.outer(u, u)) @ p for p, u in axes)
    try:
        c = np.linalg.solve(m, rhs)
        off = max(float(np.linalg.norm((np.eye(3) - np.outer(u, u)) @ (c - p))) for p, u in axes)
    except np.linalg.LinAlgError:
        off = math.inf
    if off < GEOMETRY_TOL * size:
        return "spherical", c
    bad = bennett_defects(axes)
    worst = max(bad.values())
    if worst < GEOMETRY_TOL:
        return "Bennett", None
    what = ", ".join(f"{k} {v:.3g}{' rad' if 'twists' in k else ''}" for k, v in bad.items() if v >= GEOMETRY_TOL)
    raise StructureError(
        f"{mech.name}: the four revolutes {', '.join(names)} are neither parallel, nor meet at one point, nor make a "
        f"Bennett linkage — Bennett's conditions miss by: {what} (lengths and offsets as fractions of the longest "
        f"link's common normal, {max(l[0] for l in (common_normal(*axes[i], *axes[(i + 1) % 4]) for i in range(4))):.6g} m; "
        f"each must be below {GEOMETRY_TOL:g}); a general 4R loop cannot move (W = 6·3 − 5·4 = −2)")


def common_normal(p1, u1, p2, u2) -> tuple[float, float, np.ndarray, np.ndarray]:
    """Length a ≥ 0 and twist α of the common normal from line 1 to line 2 (α in (−π, π], about
    the normal's direction), and its feet on line 1 and line 2."""
    n = np.cross(u1, u2)
    d = p2 - p1
    if np.linalg.norm(n) < 1e-12:
        foot1 = p1
        foot2 = p2 - u2 * float(u2 @ d)
        return float(np.linalg.norm(foot2 - foot1)), 0.0, foot1, foot2
    # feet: p1 + t1·u1, p2 + t2·u2 with the joining vector square to both lines, from n = u1 × u2
    # itself (not a 2×2 system whose determinant 1 − (u1·u2)² rounds to 0 for nearly parallel axes)
    nn = float(n @ n)
    t1, t2 = float(np.cross(d, u2) @ n) / nn, float(np.cross(d, u1) @ n) / nn
    f1, f2 = p1 + t1 * u1, p2 + t2 * u2
    a = float(np.linalg.norm(f2 - f1))
    x = (f2 - f1) / a if a > 0 else n / np.linalg.norm(n)
    alpha = math.atan2(float(np.cross(u1, u2) @ x), float(u1 @ u2))
    return a, alpha, f1, f2


def bennett_defects(axes) -> dict[str, float]:
    """How far four revolute axes (point, unit axis) in loop order are from Bennett's
    conditions, each as a fraction of the largest link length (or in radians for twists):
    opposite lengths and twists equal, zero offsets, a1·sin α2 = a2·sin α1."""
    links = [common_normal(*axes[i], *axes[(i + 1) % 4]) for i in range(4)]
    a = [l[0] for l in links]
    al = [l[1] for l in links]
    scale = max(a) or 1.0
    offsets = []
    for i in range(4):  # the two feet on axis i+1: of the normal arriving and of the one leaving
        arriving = links[i][3]
        leaving = links[(i + 1) % 4][2]
        offsets.append(float(np.linalg.norm(arriving - leaving)) / scale)

    def twist_gap(x, y):  # twists equal up to the sense of the normals and of the axes (a turned-over axis adds π)
        return min(abs(math.remainder(x - y, math.pi)), abs(math.remainder(x + y, math.pi)))

    return {"opposite lengths": max(abs(a[0] - a[2]), abs(a[1] - a[3])) / scale,
            "opposite twists": max(twist_gap(al[0], al[2]), twist_gap(al[1], al[3])),
            "offsets": max(offsets),
            "a1·sin α2 − a2·sin α1": abs(a[0] * abs(math.sin(al[1])) - a[1] * abs(math.sin(al[0]))) / scale}


__all__ = ["Chain", "KINDS", "angle_about", "bennett_defects", "build_chain", "common_normal", "reference_direction"]

"""Assembly: the structure, the link shapes and each Assur group's assembly mode.

``assemble`` analyses the structure and takes each group's assembly mode (m = ±1 of the closed-form group formulas)
from the sketch pose: the branch whose points land nearest the sketch *and* whose links lie at
their sketch angles (a link's x axis points from its first point to its second; a one-point
link's x axis is the world x axis in the sketch, and a slider keeps its sketch angle to its
guide, so the guide line's direction counts too). Positions alone cannot tell the modes apart
when each link of an RPR group carries a single point: both modes put the points at the same
places and differ only in the links' angles (and so in the slot's direction, the centres of
mass and every load). The mode is then kept over every crank angle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.description import Mechanism
from linkgen.errors import AssemblyError, DescriptionError, MagnitudeError
from linkgen.families.planar.geometry import GuideShape, LinkPose, LinkShape, guide_shapes, link_shapes, sketch_input
from linkgen.families.planar.groups import SINGULAR_TOL, input_poses, place, solve_group
from linkgen.families.planar.structure import Group, GroupKind, Structure, analyze

# The sketch must agree with the assembled pose to this fraction of the mechanism's size:
# loose enough for a sketch drawn to three digits, tight enough to catch a wrong branch or typo.
SKETCH_TOLERANCE = 0.02
_BRANCHED = (GroupKind.RRR, GroupKind.RRP, GroupKind.RPR, GroupKind.ACTUATOR)


@dataclass(frozen=True)
class Assembly:
    """A mechanism with its structure, shapes and each group's assembly mode."""

    mechanism: Mechanism
    structure: Structure
    shapes: dict[str, LinkShape]
    guides: dict[str, GuideShape]
    branches: tuple[int, ...]
    sketch_phi: float

    def __repr__(self) -> str:
        return f"Assembly({self.mechanism.name!r}, {self.structure.formula})"


def assemble(mech: Mechanism, *, sketch_tolerance: float | None = SKETCH_TOLERANCE) -> Assembly:
    """Analyse the structure and take each group's assembly mode from the sketch pose.

    ``sketch_tolerance``: how far [fraction of the sketch's size] the sketch may be from the
    assembled pose; None skips the check (a rough sketch that only chooses the modes, as
    ``linkgen assemble`` takes it).

    Raises:
        AssemblyError: a group cannot be assembled at the sketch's crank angle.
        MagnitudeError: intermediate values overflow float64 (coordinates too large).
        DescriptionError: the assembled pose is far from the sketch on every branch.
    """
    structure = analyze(mech)
    shapes = link_shapes(mech)
    guides = guide_shapes(mech, shapes)
    phi0 = np.array([sketch_input(mech, shapes)])
    size = max(_sketch_size(mech), np.finfo(float).tiny)
    poses = input_poses(mech, structure, shapes, phi0)
    branches = []
    for group in structure.groups:
        best = None
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            trials = [(m, *solve_group(group, m, poses, shapes, guides, mech, phi0))
                      for m in ((1, -1) if group.kind in _BRANCHED else (1,))]
        if not all(res.fail[0] or np.isfinite(res.denominator[0]) for *_, res in trials):
            raise MagnitudeError(f"group {group.label}'s solution at the sketch pose", [(float(phi0[0]),) * 2])
        _check_guides(group, trials[0][3])
        for m, p1, p2, res in trials:
            if res.fail[0]:
                continue
            trial = {group.links[0]: p1, group.links[1]: p2} | ({group.third: res.value} if group.third else {})
            err = _sketch_error(mech, shapes, trial, size)
            if best is None or err < best[0] - SKETCH_TIE:  # a tie (a sketch on a dead centre) keeps m = +1
                best = (err, m, p1, p2, res)
        if best is None:
            raise AssemblyError(
                group.label, [(float(phi0[0]), float(phi0[0]))], "the sketch pose cannot be assembled"
            )
        branches.append(best[1])
        place(group, poses, best[2], best[3], best[4])
    if sketch_tolerance is not None:
        _check_sketch(mech, shapes, poses, sketch_tolerance)
    return Assembly(mech, structure, shapes, guides, tuple(branches), float(phi0[0]))


def _check_guides(group: Group, res) -> None:
    """Two guides of a PRP or RPP group that are parallel in the sketch leave the group without
    a position (no intersection, or a whole line of them): a description error, not a pose."""
    if group.kind not in (GroupKind.PRP, GroupKind.RPP):
        return
    sine = float(np.abs(res.denominator[0]))
    if not sine >= SINGULAR_TOL:
        names = [p.name for p in group.pairs if p.kind == "P"]
        raise DescriptionError(
            ", ".join(f"prismatic.{n}" for n in names),
            f"the guides of group {group.label} are parallel in the sketch (sine of the angle between them "
            f"{sine:.3g}, needs at least {SINGULAR_TOL:g}), so the group has no defined position; turn one "
            f"of the guide lines ('angle')",
        )


# Two branches whose sketch errors (dimensionless, ``_sketch_error``) differ by less than this are
# a tie: the sketch lies on a dead centre (its two modes mirror each other there) and the first
# mode, m = +1, is kept whatever the last bits of the two errors. The sketch's own branch has an
# error of rounding's order (~1e-15) and the other one of order one, so only true ties fall in.
SKETCH_TIE = 1e-9


def _sketch_size(mech: Mechanism) -> float:
    """The diagonal of the sketch's bounding box [m]."""
    xy = np.array(list(mech.points.values()))
    return float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))


def _sketch_error(mech: Mechanism, shapes: dict[str, LinkShape], poses: dict[str, LinkPose], size: float) -> float:
    """How far a trial pose of some links is from the sketch: the distances of their points
    over the sketch's size plus their angles' differences from the sketch angles [rad]. Both
    are dimensionless and zero on the sketch's own branch; on the other branch at least one
    of them is of order one unless the group is at a dead centre."""
    err = 0.0
    for name, pose in poses.items():
        for p, local in shapes[name].local.items():
            err += float(np.hypot(*(pose.point(local).p[0] - np.asarray(mech.points[p])))) / size
        turn = float(pose.angle.v[0]) - shapes[name].sketch_angle
        err += abs(math.remainder(turn, 2.0 * math.pi))
    return err


def _check_sketch(mech: Mechanism, shapes: dict[str, LinkShape], poses: dict[str, LinkPose],
                  fraction: float = SKETCH_TOLERANCE) -> None:
    tol = fraction * _sketch_size(mech)
    for link in mech.links:
        for p in link.points:
            got = poses[link.name].point(shapes[link.name].local[p]).p[0]
            want = np.asarray(mech.points[p])
            dev = float(np.hypot(*(got - want)))
            if dev > tol:
                raise DescriptionError(
                    f"points.{p}",
                    f"the sketch puts it at ({want[0]:.6g}, {want[1]:.6g}) m but link {link.name!r} assembles it at "
                    f"({got[0]:.6g}, {got[1]:.6g}) m on the nearest branch, {dev:.3g} m away (allowed {tol:.3g} m = "
                    f"{fraction:g} of the sketch's size); correct the sketch or the link lengths, or let "
                    f"`linkgen assemble --write` place the points",
                )

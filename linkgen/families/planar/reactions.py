"""The group-by-group solution of a linkage's reactions for given total loads on its links (the
kinetostatics' core, ``kinetostatics``: its conventions): each class-II group's six equations from
the last group attached back to the first (``equilibrium``), each cam follower's and planet gear's,
then the crank's three, which give the drive pair's reaction and the balancing torque (a prismatic
drive's: the balancing force along its guide, on the slider)."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import MagnitudeError, SingularityError, angle_ranges
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.cam_pair import contact as cam_contact, ground_pair
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.equilibrium import Column, dyad, three
from linkgen.families.planar.kinematics import Kinematics
from linkgen.families.planar.structure import GroupKind, Pair


@np.errstate(invalid="ignore", divide="ignore", over="ignore")  # found and named by angle (``_checked``)
def solve_reactions(asm: Assembly, kin: Kinematics, given_load: dict, com: dict, marked: np.ndarray, extra: dict | None = None):
    """The group-by-group solution for the links' total loads ``given_load`` plus ``extra`` (the
    friction's): (torque, reactions, normal forces, moments, tooth and contact forces, the torque
    scale the reactions on the crank add)."""
    mech = asm.mechanism
    n = kin.phi.shape[0]
    scale = np.zeros(n)
    load = {k: [f + extra[k][0], m + extra[k][1]] if extra and k in extra else [f, m] for k, (f, m) in given_load.items()}
    reactions: dict[str, np.ndarray] = {}
    normal: dict[str, np.ndarray] = {}
    moment: dict[str, np.ndarray] = {}

    def columns(pair: Pair, link: str) -> list[tuple[np.ndarray, np.ndarray]]:
        """The load on ``link`` per unit value of each of ``pair``'s two unknowns."""
        if pair.kind == "R":
            joint = mech.revolute(pair.name)
            sign = 1.0 if link == joint.links[0] else -1.0
            d = kin.points[joint.point].p - com[link]
            ex, ey = np.zeros((n, 2)), np.zeros((n, 2))
            ex[:, 0], ey[:, 1] = sign, sign
            return [(ex, -sign * d[:, 1]), (ey, sign * d[:, 0])]
        g = asm.guides[pair.name]
        sign = 1.0 if link == g.slider else -1.0
        u = kin.links[g.guide].direction(g.alpha).p
        nrm = np.stack([-u[:, 1], u[:, 0]], axis=1)
        d = kin.links[g.slider].point(g.point).p - com[link]
        return [(sign * nrm, sign * (d[:, 0] * nrm[:, 1] - d[:, 1] * nrm[:, 0])),
                (np.zeros((n, 2)), np.full(n, sign))]

    def store(pair: Pair, x: np.ndarray) -> None:
        if pair.kind == "R":
            reactions[pair.name] = x.copy()
        else:
            normal[pair.name], moment[pair.name] = x[:, 0].copy(), x[:, 1].copy()

    def transmit(pair: Pair, link: str, x: np.ndarray) -> None:
        """Add the solved pair's load on ``link`` (a link solved later) to its given load."""
        if link == GROUND:
            return
        for k, (f, m) in enumerate(columns(pair, link)):
            load[link][0] = load[link][0] + f * x[:, k:k + 1]
            load[link][1] = load[link][1] + m * x[:, k]

    def column3(pair: Pair, link: str) -> tuple[Column, Column]:
        """``columns`` as (x force, y force, moment) triples (``equilibrium``); ±1 and 0 stay scalars."""
        if pair.kind == "R":
            joint = mech.revolute(pair.name)
            sign = 1.0 if link == joint.links[0] else -1.0
            d = kin.points[joint.point].p - com[link]
            return (sign, 0.0, -sign * d[:, 1]), (0.0, sign, sign * d[:, 0])
        (f0, m0), _ = columns(pair, link)
        sign = 1.0 if link == asm.guides[pair.name].slider else -1.0
        return (f0[:, 0], f0[:, 1], m0), (0.0, 0.0, sign)

    def given3(link: str) -> Column:
        """−(the link's total load), the right side of its three equations."""
        f, m = load[link]
        return -f[:, 0], -f[:, 1], -m

    def moved(cols, src: str, dst: str):
        """Columns of ``src``'s equations with their moments taken about ``dst``'s centre of mass."""
        r = com[src] - com[dst]
        return tuple((fx, fy, m + r[:, 0] * fy - r[:, 1] * fx) for fx, fy, m in cols)

    def merged(b1: Column, b2: Column, src: str, dst: str) -> Column:
        """Right sides of ``dst`` and ``src`` as one body, moments about ``dst``'s centre of mass."""
        (fx, fy, m), = moved((b2,), src, dst)
        return b1[0] + fx, b1[1] + fy, b1[2] + m

    crank, drive = asm.structure.crank, asm.structure.drive
    span = asm.shapes[crank].span()
    for group in reversed(asm.structure.groups):
        (l1, l2), (o1, inner, o2) = group.links, group.pairs
        if group.kind is GroupKind.ACTUATOR:
            # the cylinder and its rod as one body (their loads about the cylinder's centre of mass)
            # with the rocker: a dyad; the rod's own equations give the drive's pair and force below
            rod = group.third
            x, singular = dyad(column3(o1, l1), moved(column3(inner, rod), rod, l1), column3(inner, l2),
                               column3(o2, l2), merged(given3(l1), given3(rod), rod, l1), given3(l2))
            x = _checked(x, singular, kin.phi, marked, f"{group.label} (equilibrium equations)", True)
            for col, pair in ((0, o1), (2, inner), (4, o2)):
                store(pair, x[:, col:col + 2])
            transmit(inner, rod, x[:, 2:4])
            crank = rod  # the drive's force: from the rod's equations
            continue
        x, singular = dyad(column3(o1, l1), column3(inner, l1), column3(inner, l2), column3(o2, l2), given3(l1),
                           given3(l2))
        x = _checked(x, singular, kin.phi, marked, f"{group.label} (equilibrium equations)")
        for col, pair in ((0, o1), (2, inner), (4, o2)):
            store(pair, x[:, col:col + 2])
            if crank in pair.links:
                scale += span * np.hypot(*x[:, col:col + 2].T)
        transmit(o1, group.known[0], x[:, 0:2])
        transmit(o2, group.known[1], x[:, 4:6])

    contact: dict[str, np.ndarray] = {}
    for cam in mech.cams:  # each follower: the contact force along the cam's normal and its pair with the ground
        follower = cam.follower
        kind, gp = ground_pair(mech, cam)
        pair = Pair(kind, gp.name, gp.links if kind == "R" else (gp.slider, gp.guide))
        c, nrm, _ = cam_contact(kin, cam)
        d = c - com[follower]
        x, singular = three((nrm[:, 0], nrm[:, 1], d[:, 0] * nrm[:, 1] - d[:, 1] * nrm[:, 0]),
                            *column3(pair, follower), given3(follower))
        x = _checked(x, singular, kin.phi, marked,
                     f"the follower {follower!r} of cam {cam.name!r} (equilibrium equations)")
        contact[cam.name] = x[:, 0].copy()
        store(pair, x[:, 1:3])
        on_cam = -x[:, :1] * nrm  # through C, on the line of the contact
        dc = c - com[crank]
        load[crank][0] = load[crank][0] + on_cam
        load[crank][1] = load[crank][1] + dc[:, 0] * on_cam[:, 1] - dc[:, 1] * on_cam[:, 0]
        scale += np.abs(x[:, 0]) * np.hypot(*(c - kin.points[mech.revolute(drive.name).point].p).T)

    tooth: dict[str, np.ndarray] = {}
    for g in mech.gears:  # each planet: its tooth force from the moment about its centre, then its pin
        planet, centre = g.planet, mech.link(g.planet).points[0]
        pin = next(Pair("R", r.name, r.links) for r in mech.revolutes
                   if r.point == centre and set(r.links) == {crank, planet})
        c = kin.points[centre].p
        pivot = kin.points[mech.revolute(drive.name).point].p
        radial = (c - pivot) / np.hypot(*(c - pivot).T)[:, None]
        tangent = np.stack([-radial[:, 1], radial[:, 0]], axis=1)
        side = 1.0 if g.kind == "internal" else -1.0  # the pitch point beyond the centre, or before it
        f_load, m_load = load[planet]
        d = com[planet] - c
        m_centre = m_load + d[:, 0] * f_load[:, 1] - d[:, 1] * f_load[:, 0]
        f_t = -m_centre / (side * g.planet_radius)
        f_tooth = f_t[:, None] * tangent + (np.abs(f_t) * math.tan(g.pressure_angle))[:, None] * (-side * radial)
        tooth[g.name] = f_tooth
        r = -(f_load + f_tooth)  # on the planet from the crank
        x = r if planet == pin.links[0] else -r
        store(pin, x)
        transmit(pin, crank, x)
        scale += span * np.hypot(*x.T)

    x, singular = three(*column3(drive, crank), _input_column(asm, kin, com, crank), given3(crank))
    x = _checked(x, singular, kin.phi, marked, f"I(0,1) {'slider' if mech.slide_drive else 'crank'} "
                                               f"(equilibrium equations)", mech.slide_drive)
    store(drive, x[:, 0:2])
    return x[:, 2].copy(), reactions, normal, moment, tooth, contact, scale


def _input_column(asm: Assembly, kin: Kinematics, com: dict, link: str) -> Column:
    """What the drive's unknown puts into ``link``'s equations: a torque about +z on the crank, or a
    prismatic drive's force along its guide line (+u on the slider, −u on the guide, through the
    slider's point)."""
    mech = asm.mechanism
    if not mech.slide_drive:
        return (0.0, 0.0, 1.0)
    g = asm.guides[mech.drive.joint]
    sign = 1.0 if link == g.slider else -1.0
    u = sign * kin.links[g.guide].direction(g.alpha).p
    d = kin.links[g.slider].point(g.point).p - com[link]
    return (u[:, 0], u[:, 1], d[:, 0] * u[:, 1] - d[:, 1] * u[:, 0])


def _checked(x: tuple[np.ndarray, ...], singular: np.ndarray, phi: np.ndarray, marked: np.ndarray,
             label: str, stroke: bool = False) -> np.ndarray:
    """The unknowns of one system (``equilibrium``) as (n, k), zero at the ``marked`` (singular)
    angles. A system that is exactly singular elsewhere raises SingularityError naming the
    angles; a non-finite solution, MagnitudeError."""
    n = phi.shape[0]
    out = np.empty((n, len(x)))
    for k, v in enumerate(x):
        out[:, k] = v
    out[marked] = 0.0
    bad = np.broadcast_to(singular, (n,)) & ~marked
    if np.any(bad):
        raise SingularityError(label, angle_ranges(phi, bad), "the equilibrium equations are singular", stroke)
    bad = ~np.all(np.isfinite(out), axis=1)
    if np.any(bad):
        raise MagnitudeError(f"the solution of {label}", angle_ranges(phi, bad))
    return out


__all__ = ["solve_reactions"]

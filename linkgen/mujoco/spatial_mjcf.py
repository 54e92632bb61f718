"""MJCF of a spatial four-bar: hinges and slides along their axes, ball joints for spherical
pairs, and one ``connect`` closing the loop at the coupler's pair with the output.

Bodies are written at the assembled sketch with world-aligned frames: the crank on its hinge at
the drive pivot, the coupler its child on a ball (RSSR, RSSP) or a hinge (4R chains) at A, the
output on a hinge or slide. The ``connect`` at B holds B on both bodies: for a 4R chain that is
the hinge at B as well, since the coupler and the output already share a second point on B's
axis (the centre of a spherical chain, the parallel axes of a planar one, and for Bennett's the
one-parameter motion the three hinges leave). A coupler on two ball joints keeps the idle spin
about its line, which moves nothing: its slender-rod inertia about that line is zero and its
initial spin is zero, so the spin stays zero.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np
from lxml import etree

from linkgen.mujoco.guides import GUIDE_SIZE, guide_span
from linkgen.mujoco.options import MUJOCO_MIN_BAR
from linkgen.mujoco.options import PLACEHOLDER, Settings
from linkgen.mujoco.scene import KEY, SERVO, SERVO_TIME, add_scene_assets
from linkgen.model.names import GROUND
from linkgen.families.spatial.chain import Chain
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.kinematics import assembled_chain
from linkgen.families.spatial.mass import ROD_RADIUS, rod_inertia
from linkgen.families.spatial.travel import full_turn, slide_travel
from linkgen.mujoco.spatial_names import closing_body, slide_joint

DRIVE_ACTUATOR = "drive:motor"
# Geom sizes as fractions of the mechanism's size.
BAR_RADIUS = ROD_RADIUS
SITE_SIZE = 0.01
# The share of an RCCC output's mass and inertia on its body on the ground's pair (the rest on
# its half carried by the coupler, welded to it).
OUTPUT_SHARE = 0.5


def _v(x) -> str:
    return " ".join("0" if float(c) == 0.0 else repr(float(c)) for c in np.ravel(x))


def sketch_points(mech: SpatialMechanism, chain: Chain) -> dict[str, np.ndarray]:
    """Every point at the assembled sketch (the output's pair point placed on the loop)."""
    pts = {p: mech.point(p) for p in mech.points}
    pts[chain.pair_a] = chain.A.copy()
    pts[chain.pair_b] = chain.B.copy()
    return pts


def link_inertial(mech: SpatialMechanism, link: str, pts: dict, origin: np.ndarray, size: float,
                  share: float = 1.0) -> tuple:
    """COM (3,) relative to ``origin`` and the full inertia (Ixx Iyy Izz Ixy Ixz Iyz) about it,
    world-aligned (``linkgen.families.spatial.mass``); ``share``: the fraction of the link's mass
    and inertia this body carries (an RCCC output is two welded bodies, half each)."""
    l = mech.link(link)
    p0 = pts[l.points[0]]
    if len(l.points) == 1:
        com, x, span2 = p0, np.array([1.0, 0.0, 0.0]), 0.0
    else:
        p1 = pts[l.points[1]]
        com, d = (p0 + p1) / 2, p1 - p0
        span2 = float(d @ d)
        x = d / math.sqrt(span2)
    full = rod_inertia(l.mass, x[None], np.array([span2]), size)[0] * share
    return com - origin, (full[0, 0], full[1, 1], full[2, 2], full[0, 1], full[0, 2], full[1, 2])


def write_spatial_mjcf(mech: SpatialMechanism, settings: Settings | None = None, chain: Chain | None = None) -> str:
    """The MJCF text of the spatial four-bar with ``settings`` (default: the placeholder)."""
    settings = PLACEHOLDER if settings is None else settings
    chain = assembled_chain(mech) if chain is None else chain
    pts = sketch_points(mech, chain)
    size = chain.size
    root = etree.Element("mujoco", model=mech.name)
    root.append(etree.Comment(
        f" linkgen spatial four-bar ({chain.kind}): timestep {settings.timestep:g} s (RK4), loop-closing "
        f"{'weld' if chain.kind == 'RCCC' else 'connect'} with "
        f"time constant {settings.timeconst:g} s, " + (f"rotor inertia {settings.armature:g} kg·m² on the drive joint "
        "that keeps the crank speed constant" if not chain.input_slides else f"drive mass {settings.armature:g} kg "
        "(armature) on the input's slide that keeps its speed constant") + ". " + _loads_note(mech)))
    etree.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true")
    etree.SubElement(root, "option", timestep=repr(settings.timestep), integrator=settings.integrator,
                     solver="Newton", iterations=str(settings.iterations), tolerance=repr(settings.tolerance),
                     gravity=_v(mech.gravity))
    default = etree.SubElement(root, "default")
    etree.SubElement(default, "geom", contype="0", conaffinity="0")
    visual = etree.SubElement(root, "visual")
    etree.SubElement(visual, "global", offwidth="1280", offheight="960")
    asset = etree.SubElement(root, "asset")
    add_scene_assets(asset)
    world = etree.SubElement(root, "worldbody")
    centre = np.mean([pts[p] for p in pts], axis=0)
    etree.SubElement(world, "light", name="light:sun", pos=_v(centre + [0, 0, 4 * size]), dir="0 0 -1",
                     directional="true", diffuse="0.5 0.5 0.5")
    low = min(p[2] for p in pts.values()) - 0.3 * size
    etree.SubElement(world, "geom", name="floor:plane", type="plane", pos=_v([centre[0], centre[1], low]),
                     size=_v([3 * size, 3 * size, 0.1 * size]), material="mat:floor")
    eye = centre + np.array([1.6, -2.2, 1.4]) * size
    fwd = centre - eye
    right = np.cross(fwd, [0, 0, 1.0])
    up = np.cross(right, fwd)
    etree.SubElement(world, "camera", name="overview", pos=_v(eye),
                     xyaxes=_v(np.r_[right / np.linalg.norm(right), up / np.linalg.norm(up)]))
    r_bar, r_site = BAR_RADIUS * size, SITE_SIZE * size
    named: set[str] = set()
    for p in mech.link(GROUND).points:
        etree.SubElement(world, "geom", name=f"ground:pivot:{p}", type="sphere", size=repr(2 * r_bar), pos=_v(pts[p]),
                         material="mat:ground")
        etree.SubElement(world, "site", name=p, pos=_v(pts[p]), size=repr(r_site))
        named.add(p)
    _guides(world, mech, chain, 2 * r_bar)

    def body(parent, link, origin, parent_origin, material, share=1.0):
        b = etree.SubElement(parent, "body", name=link, pos=_v(origin - parent_origin))
        com, inertia = link_inertial(mech, link, pts, origin, size, share)
        etree.SubElement(b, "inertial", pos=_v(com), mass=repr(mech.link(link).mass * share), fullinertia=_v(inertia))
        lp = mech.link(link).points
        for i in range(len(lp) - 1):
            if np.linalg.norm(pts[lp[i + 1]] - pts[lp[i]]) < MUJOCO_MIN_BAR:  # MuJoCo refuses it; a drawing only
                continue
            etree.SubElement(b, "geom", name=f"{link}:bar:{lp[i]}-{lp[i + 1]}", type="capsule", size=repr(r_bar),
                             fromto=_v(np.r_[pts[lp[i]] - origin, pts[lp[i + 1]] - origin]), material=material)
        if len(lp) == 1:
            etree.SubElement(b, "geom", name=f"{link}:block", type="box", size=_v([2 * r_bar] * 3), material=material)
        for p in lp:  # a point's first site carries its bare name, later copies "POINT:LINK"
            name = p if p not in named else f"{p}:{link}"
            named.add(name)
            etree.SubElement(b, "site", name=name, pos=_v(pts[p] - origin), size=repr(r_site))
        return b

    zero = np.zeros(3)
    crank = body(world, chain.crank, chain.a0, zero, "mat:crank")
    etree.SubElement(crank, "joint", name=chain.drive, type="slide" if chain.input_slides else "hinge", pos="0 0 0",
                     axis=_v(chain.ka), armature=repr(settings.armature))
    coupler = body(crank, chain.coupler, chain.A, chain.a0, "mat:link")
    cyl = chain.kind == "RCCC"  # a cylindrical pair: a hinge and a slide on one axis
    if chain.ua is None:
        etree.SubElement(coupler, "joint", name=chain.pair_a, type="ball", pos="0 0 0")
    else:
        etree.SubElement(coupler, "joint", name=chain.pair_a, type="hinge", pos="0 0 0", axis=_v(chain.ua))
    if cyl:
        etree.SubElement(coupler, "joint", name=slide_joint(chain.pair_a), type="slide", pos="0 0 0", axis=_v(chain.ua))
        # the loop closes by welding the output to its second half, carried by the coupler on B's pair
        half = etree.SubElement(coupler, "body", name=closing_body(chain), pos=_v(chain.B - chain.A))
        com, inertia = link_inertial(mech, chain.output, pts, chain.B, size, 1.0 - OUTPUT_SHARE)
        etree.SubElement(half, "inertial", pos=_v(com), mass=repr(mech.link(chain.output).mass * (1.0 - OUTPUT_SHARE)),
                         fullinertia=_v(inertia))
        etree.SubElement(half, "joint", name=chain.pair_b, type="hinge", pos="0 0 0", axis=_v(chain.ub))
        etree.SubElement(half, "joint", name=slide_joint(chain.pair_b), type="slide", pos="0 0 0", axis=_v(chain.ub))
        out = body(world, chain.output, chain.b0, zero, "mat:link", OUTPUT_SHARE)
        etree.SubElement(out, "joint", name=chain.pair_out, type="hinge", pos="0 0 0", axis=_v(chain.kb))
        etree.SubElement(out, "joint", name=slide_joint(chain.pair_out), type="slide", pos="0 0 0", axis=_v(chain.kb))
    elif chain.output_slides:
        out = body(world, chain.output, chain.B, zero, "mat:slider")
        etree.SubElement(out, "joint", name=chain.pair_out, type="slide", pos="0 0 0", axis=_v(chain.kb))
    else:
        out = body(world, chain.output, chain.b0, zero, "mat:link")
        etree.SubElement(out, "joint", name=chain.pair_out, type="hinge", pos="0 0 0", axis=_v(chain.kb))
    eq = etree.SubElement(root, "equality")
    if cyl:
        etree.SubElement(eq, "weld", name=closing_body(chain), body1=closing_body(chain), body2=chain.output,
                         relpose=_v(np.r_[chain.b0 - chain.B, 1.0, 0.0, 0.0, 0.0]), solref=settings.solref,
                         solimp=settings.solimp_text)
    else:
        etree.SubElement(eq, "connect", name=chain.pair_b, body1=chain.coupler, body2=chain.output,
                         anchor=_v(chain.B - chain.A), solref=settings.solref, solimp=settings.solimp_text)
    act = etree.SubElement(root, "actuator")
    etree.SubElement(act, "motor", name=DRIVE_ACTUATOR, joint=chain.drive, gear="1")
    kv = settings.armature / SERVO_TIME
    etree.SubElement(act, "general", name=SERVO, joint=chain.drive, gainprm="0", biastype="affine",
                     biasprm=_v([kv * mech.drive.omega, 0.0, -kv]))
    _keyframe(root, mech, chain)
    etree.indent(root, space="  ")
    return etree.tostring(root, pretty_print=True, encoding="unicode")


def _guides(world, mech: SpatialMechanism, chain: Chain, block_half: float) -> None:
    """Each fixed guide as a bar along its slider's stroke over the turn (``linkgen.mujoco.guides``;
    ``block_half`` [m]: the slider block's half-size)."""
    travel = slide_travel(mech, full_turn(mech, chain))
    for sl in mech.slides:
        if sl.guide != GROUND:
            continue
        mid, half = guide_span(*travel[sl.name], block_half, chain.size)
        u = np.array(sl.direction, dtype=float)
        thick = GUIDE_SIZE[1] * chain.size
        etree.SubElement(world, "geom", name=f"{GROUND}:guide:{sl.name}", type="box", size=_v([thick, thick, half]),
                         pos=_v(mech.point(sl.point) + mid * u), zaxis=_v(u), material="mat:ground")


def _loads_note(mech: SpatialMechanism) -> str:
    """What the file leaves out: the description's [[force]]/[[torque]] loads."""
    n_f, n_t = len(mech.forces), len(mech.torques)
    if not n_f + n_t:
        return ""
    return (f"Not in this file: the description's {n_f} [[force]] and {n_t} [[torque]] load(s); linkgen applies "
            "them as body wrenches (xfrc_applied) before every step. ")


def _keyframe(root, mech: SpatialMechanism, chain: Chain) -> None:
    """Keyframe ``sketch``: the assembled sketch moving at the drive's ω (a plain viewer then
    turns the crank, its speed servo holding ω; a slider input moves at its velocity)."""
    from linkgen.families.spatial.kinematics import solve

    k = solve(mech, np.array([chain.phi_s]), chain)
    w = mech.drive.omega
    if chain.kind == "RCCC":
        from linkgen.mujoco.spatial_state import cylinder_state

        model = mujoco.MjModel.from_xml_string(etree.tostring(root, encoding="unicode"))
        qpos, qvel, _ = cylinder_state(model, chain, k, 0, w)
        key = etree.SubElement(root, "keyframe")
        etree.SubElement(key, "key", name=KEY, qpos=_v(qpos), qvel=_v(qvel))
        return
    w_rel = (k.spin[chain.coupler][0][0] - k.spin[chain.crank][0][0]) * w  # body frames are world-aligned here
    if chain.ua is None:
        qpos, qvel = [0.0, 1.0, 0.0, 0.0, 0.0], [w, *w_rel]
    else:
        qpos, qvel = [0.0, 0.0], [w, float(w_rel @ chain.ua)]
    qpos.append(0.0)
    qvel.append(float(k.turn.d[1][0]) * w)
    key = etree.SubElement(root, "keyframe")
    etree.SubElement(key, "key", name=KEY, qpos=_v(qpos), qvel=_v(qvel))


__all__ = ["DRIVE_ACTUATOR", "sketch_points", "write_spatial_mjcf"]

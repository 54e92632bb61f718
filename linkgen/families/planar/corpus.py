"""Random valid mechanism descriptions, for test corpora and fidelity campaigns.

``random_description(rng)`` returns a TOML-shaped dict that ``linkgen.from_dict`` accepts;
``to_toml(desc)`` writes it out so that a failure can be replayed with the CLI.

What the generator covers:
    * A crank on ground followed by 1..``max_groups`` class-II groups, each of a kind drawn
      uniformly from RRR, RRP, RPR, PRP and RPP, attached to two distinct known links (the
      crank, ground or a link of an earlier group; at least one of them moving).
    * Outer revolutes on new points of the known link (which makes it a ternary link) or on
      one of its existing points, which makes compound hinges (a point on three links),
      the drive pivot included. A moving link's point that is also on ground is not reused:
      a group pinned there and to ground would not move.
    * Slots and guides at any angle, through a point of the guide link on the line or off it
      (an offset), in either direction; RPR slots on either link; one-point blocks and
      sliders, and blocks that carry a second (tracer) point.
    * Two-point links given by ``length`` or by the sketch, links of three or more points by
      ``shape`` (in an arbitrary rigid placement) or by the sketch; in one draw in five, a
      tracer point placed on top of another point of the same link.
    * Sizes from 1 cm to 30 m (log-uniform when ``size`` is None), ω from 0.1 to 300 rad/s
      (log-uniform when ``omega`` is None); mass properties by default, by linear density
      (1e-3..1e3 kg/m) or explicit (1e-4..1e3 kg, inertia from none to a large radius of
      gyration); gravity on or off and in any direction; point forces with and without a
      stroke, link torques.

The sketch is exact: every group is built by construction at the sketch crank angle (the
joints are placed first and the lengths, angles and offsets computed from them), so the
sketch satisfies every constraint to rounding. Groups are well conditioned on average (the
transmission angles at the sketch are 25°..155°, guides at least 30° from parallel), but one
group in ten is drawn from the hard end (down to 5° and 8°).

The crank range: the mechanism is solved with ``linkgen.solve`` on a 0.25° grid round the
turn (the scan that finds where it assembles; it uses linkgen's own solver). If every group
assembles and none is near a dead centre (``Kinematics.near_singular``) everywhere, the range
is the full turn. Otherwise it is the run of good samples containing the sketch angle, shrunk
by ``margin_deg`` from its last good samples (each limit lies within one grid step beyond
them), so that it stays at least ``margin_deg`` clear of the assembly limits and dead
centres; a draw whose sketch angle falls outside that range, or whose range is under 10°,
is discarded and drawn again from the same generator; so is a draw that linkgen cannot
assemble at its own sketch (the scan needs linkgen's solver), which with a solver that takes
assembly modes from point positions alone drops some chains hanging from an RPR group of two
one-point links. Features narrower than the grid step are not seen. For a given linkgen, the
result is a deterministic function of the generator's state.
"""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import LinkgenError
from linkgen.model.toml_text import to_toml

GROUND = "ground"
KINDS = ("RRR", "RRP", "RPR", "PRP", "RPP")
SCAN_STEP_DEG = 0.25  # grid of the range scan: 1440 samples a turn, one solve of a few ms
MIN_RANGE_DEG = 10.0  # narrower usable ranges are drawn again
HARD_FRACTION = 0.1  # share of groups drawn from the badly conditioned end
_MAX_DRAWS = 500


def _e(a: float) -> np.ndarray:
    return np.array([math.cos(a), math.sin(a)])


class _Builder:
    """The mechanism in world coordinates at the sketch crank angle, at unit scale."""

    def __init__(self, rng: np.random.Generator):
        self.rng = rng
        self.pos: dict[str, np.ndarray] = {}
        self.links: dict[str, list[str]] = {GROUND: []}
        self.prism: list[dict] = []  # slider, guide, point, through, line point, line angle (world)
        self.phi0 = float(rng.uniform(-math.pi, math.pi))
        o = self.point(GROUND, rng.normal(0.0, 0.3, 2))
        self.links["crank"] = [o]
        self.point("crank", self.pos[o] + rng.uniform(0.15, 0.6) * _e(self.phi0))
        self.pivot = o

    def new(self, xy) -> str:
        name = f"P{len(self.pos)}"
        self.pos[name] = np.asarray(xy, dtype=float)
        return name

    def point(self, link: str, xy) -> str:
        name = self.new(xy)
        self.links[link].append(name)
        return name

    def carriers(self, p: str) -> int:
        return sum(p in pts for pts in self.links.values())

    def link(self, *points: str) -> str:
        name = f"L{len(self.links) - 1}"
        self.links[name] = list(points)
        return name

    def any_point(self, link: str) -> np.ndarray:
        pts = self.links[link]
        return self.pos[pts[self.rng.integers(len(pts))]] if pts else np.zeros(2)

    def pin(self, link: str, near: np.ndarray, spread: float):
        """A proposed revolute site on ``link``: (link, existing point or None, xy)."""
        rng = self.rng
        if link != GROUND:
            # not a point on ground: a group pinned there and to ground would not move
            reuse = [p for p in self.links[link] if self.carriers(p) < 3 and p not in self.links[GROUND]]
            if reuse and rng.random() < 0.3:
                p = reuse[rng.integers(len(reuse))]
                return (link, p, self.pos[p])
            return (link, None, self.any_point(link) + rng.uniform(0.3, 1.0) * _e(rng.uniform(0, 2 * math.pi)))
        if rng.random() < 0.15:
            p = self.links[GROUND][rng.integers(len(self.links[GROUND]))]
            if self.carriers(p) < 3:
                return (GROUND, p, self.pos[p])
        return (GROUND, None, near + spread * _e(rng.uniform(0, 2 * math.pi)))

    def commit(self, proposal) -> str:
        link, existing, xy = proposal
        return existing if existing is not None else self.point(link, xy)

    def guide(self, slider: str, guide: str, point: str, line_point: np.ndarray, angle: float) -> None:
        """A prismatic pair whose line passes through ``line_point`` at world ``angle`` in the
        sketch; the guide's ``through`` point is an existing point or a new one, on or off it."""
        rng = self.rng
        if guide != GROUND and not self.links[guide]:
            raise AssertionError("a guide link always has a point")
        if rng.random() < 0.5 and self.links[guide]:
            pts = [p for p in self.links[guide] if p != point] or self.links[guide]
            through = pts[rng.integers(len(pts))]
        else:
            off = 0.0 if rng.random() < 0.5 else rng.uniform(-0.3, 0.3)
            xy = line_point + rng.uniform(-1.0, 1.0) * _e(angle) + off * _e(angle + math.pi / 2)
            through = self.point(guide, xy)
        self.prism.append(dict(slider=slider, guide=guide, point=point, through=through,
                               line=np.asarray(line_point, dtype=float), angle=angle))

    def maybe_tracer(self, link: str, p: float = 0.3) -> None:
        if self.rng.random() < p:
            self.point(link, self.any_point(link) + self.rng.uniform(0.2, 0.8) * _e(self.rng.uniform(0, 2 * math.pi)))


def _group(b: _Builder, kind: str, k1: str, k2: str, hard: bool) -> bool:
    """Add one group of ``kind`` hanging from k1 and k2. False if no well-placed one was found."""
    rng = b.rng
    gmin = math.radians(5.0 if hard else 25.0)  # least transmission angle at the sketch
    pmin = math.radians(8.0 if hard else 30.0)  # least angle between two guide lines
    for _ in range(30):
        p = b.pin(k1, b.any_point(k1), 1.0)
        if kind in ("RRR", "RPR"):
            q = b.pin(k2, p[2], rng.uniform(0.6, 2.0))
            d = float(np.hypot(*(q[2] - p[2])))
            if not 0.3 < d < 4.0:
                continue
            u = math.atan2(*(q[2] - p[2])[::-1])
            if kind == "RRR":
                l1, l2 = d * rng.uniform(0.4, 1.4), d * rng.uniform(0.4, 1.4)
                cg = (l1 * l1 + l2 * l2 - d * d) / (2 * l1 * l2)
                if abs(cg) > math.cos(gmin):
                    continue
                beta = math.acos(max(-1.0, min(1.0, (l1 * l1 + d * d - l2 * l2) / (2 * l1 * d))))
                pp, qq = b.commit(p), b.commit(q)
                rr = b.new(b.pos[pp] + l1 * _e(u + rng.choice((-1, 1)) * beta))
                b.link(*((pp, rr) if rng.random() < 0.5 else (rr, pp)))
                b.link(*((qq, rr) if rng.random() < 0.5 else (rr, qq)))
            else:
                eta = rng.uniform(-1, 1) * (math.radians(70) if hard else math.radians(35))
                pp, qq = b.commit(p), b.commit(q)
                a, c = b.link(pp), b.link(qq)
                if rng.random() < 0.5:  # the block on k1's pin slides in a slot of c
                    b.guide(a, c, pp, b.pos[pp], u + eta + math.pi * rng.integers(2))
                else:  # the rod pinned at p slides through a block pivoted at q
                    b.guide(c, a, qq, b.pos[qq], u + math.pi + eta + math.pi * rng.integers(2))
                b.maybe_tracer(a)
                b.maybe_tracer(c)
            return True
        if kind == "RRP":
            pp = b.commit(p)
            psi = rng.uniform(0, 2 * math.pi)
            r = b.pos[pp] + rng.uniform(0.5, 1.5) * _e(psi)
            delta = rng.uniform(-1, 1) * (math.radians(85) if hard else math.radians(60))
            a = b.link(pp)
            rr = b.point(a, r)
            if rng.random() < 0.5:
                b.links[a].reverse()
            c = b.link(rr)
            b.guide(c, k2, rr, r, psi + delta + math.pi * rng.integers(2))
            b.maybe_tracer(c, 0.2)
            return True
        th1 = rng.uniform(0, 2 * math.pi)
        th2 = th1 + rng.choice((-1, 1)) * rng.uniform(pmin, math.pi - pmin)
        if kind == "PRP":
            r = b.any_point(k1) + rng.uniform(0.5, 1.5) * _e(rng.uniform(0, 2 * math.pi))
            a = b.link()
            rr = b.point(a, r)
            c = b.link(rr)
            b.guide(a, k1, rr, r, th1)
            b.guide(c, k2, rr, r, th2)
            b.maybe_tracer(a, 0.2)
            b.maybe_tracer(c, 0.2)
            return True
        pp = b.commit(p)  # RPP: block pinned at p slides in a yoke, the yoke slides on k2
        a = b.link(pp)
        c = b.link()
        yy = b.point(c, b.pos[pp] + rng.uniform(0.3, 1.0) * _e(rng.uniform(0, 2 * math.pi)))
        b.guide(a, c, pp, b.pos[pp], th1)
        b.guide(c, k2, yy, b.pos[yy], th2)
        return True
    return False


def _build(rng: np.random.Generator, max_groups: int) -> _Builder | None:
    b = _Builder(rng)
    moving = ["crank"]
    for _ in range(int(rng.integers(1, max_groups + 1))):
        kind = KINDS[rng.integers(len(KINDS))]
        k1 = moving[-1] if rng.random() < 0.5 else moving[rng.integers(len(moving))]
        others = [GROUND] + [m for m in moving if m != k1]
        k2 = GROUND if rng.random() < 0.5 else others[rng.integers(len(others))]
        if not _group(b, kind, k1, k2, rng.random() < HARD_FRACTION):
            return None
        moving += list(b.links)[len(moving) + 1:]
    if rng.random() < 0.2:  # a tracer on top of another point of the same link
        cands = [n for n in moving if len(b.links[n]) >= 2]
        if cands:
            n = cands[rng.integers(len(cands))]
            b.point(n, b.pos[b.links[n][rng.integers(len(b.links[n]))]].copy())
    return b


def _frame(b: _Builder, link: str) -> float:
    pts = b.links[link]
    if link == GROUND or len(pts) < 2:
        return 0.0
    d = b.pos[pts[1]] - b.pos[pts[0]]
    return math.atan2(d[1], d[0])


def _wrap(a: float) -> float:
    return math.remainder(a, 2 * math.pi)


def _emit(b: _Builder, rng: np.random.Generator, size: float | None, omega: float | None) -> dict:
    xy = np.array(list(b.pos.values()))
    extent = float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))
    size = float(10 ** rng.uniform(-2, math.log10(30.0))) if size is None else float(size)
    omega = float(10 ** rng.uniform(-1, math.log10(300.0))) if omega is None else float(omega)
    s = size / extent
    pos = {p: v * s for p, v in b.pos.items()}
    links: dict[str, dict] = {}
    for name, pts in b.links.items():
        spec: dict = {"points": list(pts)}
        links[name] = spec
        if name == GROUND:
            continue
        if len(pts) == 2 and rng.random() < 0.5:
            spec["length"] = float(np.hypot(*(pos[pts[1]] - pos[pts[0]])))
        elif len(pts) >= 3 and rng.random() < 0.6:
            rho, t = rng.uniform(-math.pi, math.pi), rng.normal(0.0, size, 2)
            c, sn = math.cos(rho), math.sin(rho)
            spec["shape"] = {p: [float(c * w[0] - sn * w[1] + t[0]), float(sn * w[0] + c * w[1] + t[1])]
                             for p in pts for w in [pos[p] - pos[pts[0]]]}
        span = max(float(np.hypot(*(pos[p] - pos[q]))) for p in pts for q in pts) or 0.1 * size
        pick = rng.random()
        if pick < 0.3 and len(pts) == 2:
            spec["density"] = float(10 ** rng.uniform(-3, 3))
        elif pick < 0.75:
            mass = float(10 ** rng.uniform(-4, 3))
            com = rng.uniform(-0.5, 1.0, 2) * span
            gyr = 0.0 if (len(pts) == 1 and rng.random() < 0.3) else rng.uniform(0.05, 0.6) * span
            spec["inertial"] = {"mass": mass, "com": [float(com[0]), float(com[1])], "inertia": mass * gyr * gyr}
    prismatic = {}
    for i, pj in enumerate(b.prism):
        th, thr = pj["angle"], pj["through"]
        normal = _e(th + math.pi / 2)
        spec = {"slider": pj["slider"], "guide": pj["guide"], "point": pj["point"], "through": thr,
                "angle": _wrap(th - _frame(b, pj["guide"]))}
        off = float(np.dot(pj["line"] * s - pos[thr], normal))
        if off != 0.0 or rng.random() < 0.5:
            spec["offset"] = off
        prismatic[f"S{i}"] = spec
    carriers = [n for n in b.links if b.pivot in b.links[n]]
    joint = b.pivot if len(carriers) == 2 else f"{b.pivot}:{GROUND}-crank"
    desc: dict = {
        "mechanism": {"name": "corpus", "title": "generated by linkgen.corpus"},
        "points": {p: [float(v[0]), float(v[1])] for p, v in pos.items()},
        "links": links,
        "drive": {"joint": joint, "omega": omega},
    }
    if prismatic:
        desc["prismatic"] = prismatic
    if rng.random() < 0.5:
        g = 9.81 * _e(-math.pi / 2 if rng.random() < 0.7 else rng.uniform(0, 2 * math.pi))
        desc["mechanism"]["gravity"] = [float(g[0]), float(g[1])]
    moving = [n for n in b.links if n != GROUND]
    forces = []
    for _ in range(int(rng.integers(0, 3))):
        n = moving[rng.integers(len(moving))]
        f = float(10 ** rng.uniform(-2, 3)) * _e(rng.uniform(0, 2 * math.pi))
        spec = {"link": n, "point": b.links[n][rng.integers(len(b.links[n]))], "force": [float(f[0]), float(f[1])]}
        if rng.random() < 0.5:
            lo = float(rng.uniform(0, 360))
            spec["stroke"] = [f"{lo:.3f}deg", f"{lo + rng.uniform(30, 300):.3f}deg"]
        forces.append(spec)
    if forces:
        desc["force"] = forces
    if rng.random() < 0.3:
        n = moving[rng.integers(len(moving))]
        desc["torque"] = [{"link": n, "torque": float(rng.choice((-1, 1)) * 10 ** rng.uniform(-2, 2))}]
    return desc


def denominator_crossings(asm, phi: np.ndarray) -> np.ndarray:
    """(n,) True on both sides of a sign change of some group's transfer-function denominator
    between neighbouring angles: a dead centre narrower than the grid step lies there."""
    from linkgen.families.planar.groups import input_poses, place, solve_group

    mech = asm.mechanism
    poses = input_poses(mech, asm.structure, asm.shapes, phi)
    out = np.zeros(phi.shape[0], dtype=bool)
    with np.errstate(all="ignore"):
        for group, m in zip(asm.structure.groups, asm.branches):
            p1, p2, res = solve_group(group, m, poses, asm.shapes, asm.guides, mech, phi)
            den = np.broadcast_to(res.denominator, phi.shape)
            flip = np.sign(den[1:]) * np.sign(den[:-1]) < 0
            out[1:] |= flip
            out[:-1] |= flip
            place(group, poses, p1, p2, res)
    return out


def _usable_range(desc: dict, phi0: float, margin: float) -> tuple[float, float] | None:
    """(start, stop) [rad] around ``phi0``, or None when the draw must be discarded."""
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.reader import from_dict

    try:
        from linkgen.families.planar.assembly import assemble

        asm = assemble(from_dict(desc))
    except LinkgenError:
        return None
    step = math.radians(SCAN_STEP_DEG)
    n = int(round(360.0 / SCAN_STEP_DEG))
    grid = phi0 - math.pi + step * np.arange(n)
    good = np.ones(n, dtype=bool)
    for _ in range(64):  # each pass drops the samples where the first failing group fails
        idx = np.flatnonzero(good)
        if idx.size == 0:
            return None
        try:
            kin = solve(asm, grid[idx])
        except LinkgenError as exc:
            ranges = getattr(exc, "ranges", None)
            if not ranges:
                return None
            for lo, hi in ranges:
                good[(grid >= lo) & (grid <= hi)] = False
            continue
        for mask in kin.near_singular.values():
            good[idx[np.asarray(mask, dtype=bool)]] = False
        good[idx] &= ~denominator_crossings(asm, grid[idx])
        break
    else:
        return None
    if good.all():
        return (0.0, 2 * math.pi)
    k0 = n // 2
    if not good[k0]:
        return None
    lo = k0
    while good[(lo - 1) % n]:
        lo -= 1
    hi = k0
    while good[(hi + 1) % n]:
        hi += 1
    start, stop = phi0 + (lo - k0) * step + margin, phi0 + (hi - k0) * step - margin
    if not start < phi0 < stop or stop - start < math.radians(MIN_RANGE_DEG):
        return None
    return (start, stop)


def random_description(rng: np.random.Generator, *, max_groups: int = 4, margin_deg: float = 5.0,
                       size: float | None = None, omega: float | None = None) -> dict:
    """A random valid mechanism description (see the module docstring for what it covers).

    Args:
        rng: the source of randomness; the result is a deterministic function of its state.
        max_groups: the most class-II groups after the crank (at least 1).
        margin_deg: the crank range keeps this far [deg] from assembly limits and dead centres.
        size: the sketch's diagonal extent [m], or None for log-uniform 1 cm..30 m.
        omega: crank speed [rad/s], or None for log-uniform 0.1..300 rad/s.

    Returns:
        A TOML-shaped dict for ``linkgen.from_dict``.
    """
    if max_groups < 1:
        raise ValueError(f"max_groups must be >= 1, got {max_groups!r}")
    margin = math.radians(margin_deg)
    for _ in range(_MAX_DRAWS):
        b = _build(rng, max_groups)
        if b is None:
            continue
        desc = _emit(b, rng, size, omega)
        rng_range = _usable_range(desc, b.phi0, margin)
        if rng_range is None:
            continue
        if rng_range != (0.0, 2 * math.pi) or rng.random() < 0.5:
            desc["drive"]["range"] = [rng_range[0], rng_range[1]]
        return desc
    raise RuntimeError(f"no usable mechanism in {_MAX_DRAWS} draws (max_groups={max_groups}, margin={margin_deg}°)")


__all__ = ["KINDS", "random_description", "to_toml"]


def scaled(desc: dict, factor: float, omega: float | None = None, gravity: bool = True) -> dict:
    """A copy of a TOML-shaped description with every length multiplied by ``factor`` (points,
    ``length``, ``shape``, guide offsets, centres of mass; explicit inertias by factor², masses
    and linear densities kept), the crank speed set to ``omega`` if given, and gravity off
    unless ``gravity``: the same mechanism at another size or speed, for scaling studies."""
    import copy

    out = copy.deepcopy(desc)
    out["points"] = {k: [factor * x for x in v] for k, v in out["points"].items()}
    for link in out["links"].values():
        if "length" in link:
            link["length"] *= factor
        if "shape" in link:
            link["shape"] = {k: [factor * x for x in v] for k, v in link["shape"].items()}
        if "inertial" in link:
            link["inertial"] = dict(link["inertial"], com=[factor * x for x in link["inertial"]["com"]],
                                    inertia=link["inertial"]["inertia"] * factor**2)
    for pj in out.get("prismatic", {}).values():
        if "offset" in pj:
            pj["offset"] *= factor
    if omega is not None:
        out["drive"]["omega"] = omega
    if not gravity:
        out["mechanism"]["gravity"] = [0.0, 0.0]
    return out

"""Checks of linkgen's results written from first principles, independent of its solvers.

Everything here reads the TOML-shaped description (the dict) for the geometry, the mass
properties and the loads, and linkgen's reported results only as the numbers under test:
positions, angles and transfer functions (``Kinematics``) and reactions (``Forces``). The
expected relations are rigid-body geometry, finite differences and Newton–Euler balance
with d'Alembert loads, coded here without calling linkgen's solvers. Each check returns the
worst error as a dimensionless figure (relative to a stated scale) so that the tests and the
fuzz script can compare it with a named tolerance.
"""

from __future__ import annotations

import math

import numpy as np

GROUND = "ground"
# Link defaults stated in the README ("links without mass properties get the stated defaults"):
# a uniform bar of 1 kg/m over the first two points, or a 0.1 kg block of 1e-4 kg·m².
DEFAULT_DENSITY = 1.0
DEFAULT_BLOCK_MASS = 0.1
DEFAULT_BLOCK_INERTIA = 1e-4


def wrap(a):
    return np.remainder(np.asarray(a) + np.pi, 2 * np.pi) - np.pi


def angle_value(x) -> float:
    """An angle field of the description (radians, or '<x>deg' / '<x>rad') [rad]."""
    if isinstance(x, str):
        v = float(x[:-3])
        return math.radians(v) if x.endswith("deg") else v
    return float(x)


def sketch(desc: dict) -> dict[str, np.ndarray]:
    return {p: np.asarray(xy, dtype=float) for p, xy in desc["points"].items()}


def size(desc: dict) -> float:
    """The sketch's diagonal extent [m]: the length scale of every position check."""
    xy = np.array(list(desc["points"].values()), dtype=float)
    return float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))


def local_coordinates(desc: dict, link: str) -> dict[str, np.ndarray]:
    """The link's points in its own frame (origin at the first point, x to the second) [m]."""
    spec = desc["links"][link]
    pts = spec["points"]
    if "length" in spec:
        return {pts[0]: np.zeros(2), pts[1]: np.array([float(spec["length"]), 0.0])}
    src = {p: np.asarray(v, dtype=float) for p, v in spec.get("shape", {}).items()} or sketch(desc)
    o = src[pts[0]]
    a = 0.0 if len(pts) < 2 or link == GROUND else math.atan2(*(src[pts[1]] - o)[::-1])
    if link == GROUND:
        return {p: src[p] for p in pts}
    c, s = math.cos(a), math.sin(a)
    return {p: np.array([c * (src[p] - o)[0] + s * (src[p] - o)[1], -s * (src[p] - o)[0] + c * (src[p] - o)[1]])
            for p in pts}


def sketch_frame_angle(desc: dict, link: str) -> float:
    """The link's frame angle in the sketch [rad]: towards its second point, 0 for one point."""
    pts = desc["links"][link]["points"]
    if link == GROUND or len(pts) < 2:
        return 0.0
    xy = sketch(desc)
    return math.atan2(*(xy[pts[1]] - xy[pts[0]])[::-1])


def sketch_phi(desc: dict) -> float:
    return sketch_frame_angle(desc, crank_name(desc))


def crank_name(desc: dict) -> str:
    joint = desc["drive"]["joint"]
    point = joint.split(":")[0]
    if ":" in joint:
        a, b = joint.split(":")[1].split("-")
        return b if a == GROUND else a
    return next(n for n, s in desc["links"].items() if n != GROUND and point in s["points"])


def crank_range(desc: dict) -> tuple[float, float]:
    r = desc["drive"].get("range")
    return (0.0, 2 * math.pi) if r is None else (angle_value(r[0]), angle_value(r[1]))


def line(desc: dict, kin, name: str, k=slice(None)):
    """World base point (n, 2) and unit direction (n, 2) of a prismatic pair's guide line."""
    pj = desc["prismatic"][name]
    th = kin.links[pj["guide"]].angle.v[k] + angle_value(pj.get("angle", 0.0))
    u = np.stack([np.cos(th), np.sin(th)], axis=-1)
    nrm = np.stack([-u[..., 1], u[..., 0]], axis=-1)
    base = kin.points[pj["through"]].p[k] + float(pj.get("offset", 0.0)) * nrm
    return base, u, nrm


def geometry_errors(desc: dict, kin) -> dict[str, float]:
    """Worst violations over kin.phi: link point distances and frame angles, slider points
    off their guide lines, relative slider/guide angles, ground points moved, the crank's
    angle, and (at the sketch angle, if sampled) the pose against the sketch. Lengths are
    relative to ``size(desc)``, angles in rad."""
    L = size(desc)
    xy = sketch(desc)
    out = dict(distance=0.0, frame=0.0, guide=0.0, relative_angle=0.0, ground=0.0, crank=0.0,
               sketch_point=0.0, sketch_angle=0.0)
    P = {p: kin.points[p].p for p in desc["points"]}
    for name, spec in desc["links"].items():
        pts, loc = spec["points"], local_coordinates(desc, name)
        for i, a in enumerate(pts):
            for b in pts[i + 1:]:
                want = float(np.hypot(*(loc[a] - loc[b])))
                got = np.hypot(*(P[a] - P[b]).T)
                out["distance"] = max(out["distance"], float(np.max(np.abs(got - want))) / L)
        if name == GROUND:
            for p in pts:
                out["ground"] = max(out["ground"], float(np.max(np.hypot(*(P[p] - xy[p]).T))) / L)
        elif len(pts) >= 2:
            th = np.arctan2(*(P[pts[1]] - P[pts[0]]).T[::-1])
            out["frame"] = max(out["frame"], float(np.max(np.abs(wrap(kin.links[name].angle.v - th)))))
    crank = crank_name(desc)
    out["crank"] = float(np.max(np.abs(wrap(kin.links[crank].angle.v - kin.phi))))
    for name, pj in desc.get("prismatic", {}).items():
        base, u, nrm = line(desc, kin, name)
        off = np.einsum("ij,ij->i", P[pj["point"]] - base, nrm)
        out["guide"] = max(out["guide"], float(np.max(np.abs(off))) / L)
        rel = kin.links[pj["slider"]].angle.v - kin.links[pj["guide"]].angle.v
        rel0 = sketch_frame_angle(desc, pj["slider"]) - sketch_frame_angle(desc, pj["guide"])
        out["relative_angle"] = max(out["relative_angle"], float(np.max(np.abs(wrap(rel - rel0)))))
    at = np.flatnonzero(np.abs(wrap(kin.phi - sketch_phi(desc))) < 1e-12)
    for k in at:
        for p in desc["points"]:
            out["sketch_point"] = max(out["sketch_point"], float(np.hypot(*(P[p][k] - xy[p]))) / L)
        for name in desc["links"]:
            if name != GROUND:
                d = wrap(kin.links[name].angle.v[k] - sketch_frame_angle(desc, name))
                out["sketch_angle"] = max(out["sketch_angle"], abs(float(d)))
    return out


def _fd_first(f_minus, f_plus, h):
    return (f_plus - f_minus) / (2 * h)


def transfer_errors(desc: dict, solve_at, phi: np.ndarray, steps=(1e-4, 1e-3)) -> dict[str, float]:
    """First transfer functions against central differences of positions (and link angles),
    second ones against central differences of the first.

    ``solve_at(angles)`` returns linkgen's Kinematics. At a step h the figure is
    |reported − FD(h/2)| / (|FD(h) − FD(h/2)| + floor): where the central difference's h²
    truncation dominates, its error at h/2 is a quarter of that at h, so the reported value
    is about a third of |FD(h) − FD(h/2)| from FD(h/2); a wrong transfer function gives a
    figure of order scale/truncation, far above 1. The floor is rounding: 1e-13·scale/h,
    scale = the sketch size plus the quantity's own peak. Each sample takes the smaller
    figure over ``steps``: a small step is noisy where the mechanism is badly conditioned
    (rounding ∝ 1/h), a large one leaves the asymptotic regime near a limit; a correct value
    is consistent at one of them at least, a wrong one at neither.
    """
    k = solve_at(phi)
    L = size(desc)
    figs: dict[str, dict] = {"d1": {}, "d2": {}}

    def fig(key, name, rep, pick, scale, h, near):
        (km, kp), (km2, kp2) = near
        fd, fd2 = _fd_first(pick(km), pick(kp), h), _fd_first(pick(km2), pick(kp2), h / 2)
        ratio = np.abs(rep - fd2) / (np.abs(fd - fd2) + 1e-13 * scale / h)
        old = figs[key].get(name)
        figs[key][name] = ratio if old is None else np.minimum(old, ratio)

    for h in steps:
        near = ((solve_at(phi - h), solve_at(phi + h)), (solve_at(phi - h / 2), solve_at(phi + h / 2)))
        for p in desc["points"]:
            v = k.points[p]
            fig("d1", p, v.d1, lambda x: x.points[p].p, L + np.max(np.abs(v.d1)), h, near)
            fig("d2", p, v.d2, lambda x: x.points[p].d1, L + np.max(np.abs(v.d2)), h, near)
        for n in desc["links"]:
            if n == GROUND:
                continue
            a = k.links[n].angle
            # unwrap each neighbour next to the centre
            fig("d1", n, a.d1, lambda x: a.v + wrap(x.links[n].angle.v - a.v), 1.0 + np.max(np.abs(a.d1)), h, near)
            fig("d2", n, a.d2, lambda x: x.links[n].angle.d1, 1.0 + np.max(np.abs(a.d2)), h, near)
    return {key: max(float(np.max(r)) for r in v.values()) for key, v in figs.items()}


def mass_properties(desc: dict, link: str) -> tuple[float, np.ndarray, float]:
    """(mass [kg], centre of mass in the link frame [m], inertia about it [kg·m²])."""
    spec = desc["links"][link]
    pts = spec["points"]
    if "inertial" in spec:
        t = spec["inertial"]
        return float(t["mass"]), np.asarray(t["com"], dtype=float), float(t["inertia"])
    if len(pts) == 1:
        return DEFAULT_BLOCK_MASS, np.zeros(2), DEFAULT_BLOCK_INERTIA
    loc = local_coordinates(desc, link)
    length = float(np.hypot(*(loc[pts[1]] - loc[pts[0]])))
    rho = float(spec["density"]) if "density" in spec else DEFAULT_DENSITY
    m = rho * length
    return m, 0.5 * (loc[pts[0]] + loc[pts[1]]), m * length * length / 12.0


def _rot(th, w):
    c, s = np.cos(th), np.sin(th)
    return np.stack([c * w[0] - s * w[1], s * w[0] + c * w[1]], axis=-1)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def stroke_on(spec: dict, phi: np.ndarray) -> np.ndarray:
    if "stroke" not in spec:
        return np.ones(phi.shape, dtype=bool)
    lo, hi = (angle_value(x) for x in spec["stroke"])
    return (hi - lo >= 2 * np.pi) | (np.remainder(phi - lo, 2 * np.pi) <= hi - lo)


def link_loads(desc: dict, kin, omega: float, eps: float):
    """Per moving link: com S (n,2), S' (n,2), θ' (n,), and the given + d'Alembert load as
    a list of (force (n,2), point of application (n,2)) and pure moments (n,), plus a
    force scale and the list of 'power' terms of virtual work."""
    g = np.asarray(desc["mechanism"].get("gravity", [0.0, 0.0]), dtype=float)
    out = {}
    for name, spec in desc["links"].items():
        if name == GROUND:
            continue
        m, c, inertia = mass_properties(desc, name)
        o, th = kin.points[spec["points"][0]], kin.links[name].angle
        rc = _rot(th.v, c)
        perp = np.stack([-rc[:, 1], rc[:, 0]], axis=1)
        S = o.p + rc
        S1 = o.d1 + th.d1[:, None] * perp
        S2 = o.d2 + th.d2[:, None] * perp - (th.d1**2)[:, None] * rc
        acc = S2 * omega**2 + S1 * eps
        alpha = th.d2 * omega**2 + th.d1 * eps
        forces = [(np.broadcast_to(m * g, S.shape), S), (-m * acc, S)]
        moments = [-inertia * alpha]
        out[name] = dict(S=S, S1=S1, th1=th.d1, forces=forces, moments=moments)
    for spec in desc.get("force", []):
        if spec["link"] == GROUND:
            continue
        on = stroke_on(spec, kin.phi)[:, None]
        F = np.where(on, np.asarray(spec["force"], dtype=float), 0.0)
        out[spec["link"]]["forces"].append((F, kin.points[spec["point"]].p))
    for spec in desc.get("torque", []):
        if spec["link"] != GROUND:
            out[spec["link"]]["moments"].append(np.full(kin.phi.shape, float(spec["torque"])))
    return out


# Residuals are relative to the sum of the magnitudes of their own terms plus this share of
# the whole mechanism's: a group's rounding (~1e-16 of the loads it carries, times its
# conditioning) reaches the light links it also loads, whose own terms may be far smaller,
# and the crank of a chain whose groups hang from ground alone, whose terms are all ~0.
GLOBAL_SHARE = 1e-3


def revolutes(desc: dict) -> list[tuple[str, str, tuple[str, str]]]:
    """(name, point, (first, second)) of every revolute: a point on two links is a revolute
    named after it. A point on k > 2 links (a compound hinge) carries k − 1 revolutes whose
    pairing linkgen chooses in its decomposition (README, "Conventions"); they are taken from
    linkgen, and every check that uses them (each link's balance, the net force a link gets at
    a point) holds for any pairing."""
    import linkgen

    carriers: dict[str, list[str]] = {}
    for name, spec in desc["links"].items():
        for p in spec["points"]:
            carriers.setdefault(p, []).append(name)
    out = [(p, p, (names[0], names[1])) for p, names in carriers.items() if len(names) == 2]
    compound = {p for p, names in carriers.items() if len(names) > 2}
    if compound:
        out += [(j.name, j.point, j.links) for j in linkgen.from_dict(desc).revolutes if j.point in compound]
    return out


def balance_errors(desc: dict, kin, f, omega: float, eps: float) -> dict[str, float]:
    """Each moving link's force and moment balance from the reported reactions, normal
    forces, moments and the balancing torque, with given and d'Alembert loads; and the
    balancing torque against virtual work. Each residual is relative to the sum of the
    magnitudes of its own terms plus GLOBAL_SHARE of the mechanism's (so that rounding, not
    the load level, sets the figure)."""
    loads = link_loads(desc, kin, omega, eps)
    vw = np.zeros(kin.phi.shape)
    vw_scale = np.zeros(kin.phi.shape)
    for name, d in loads.items():
        for F, at in d["forces"]:
            term = np.einsum("ij,ij->i", F, d["S1"]) + _cross(at - d["S"], F) * d["th1"]
            vw += term
            vw_scale += np.abs(np.einsum("ij,ij->i", F, d["S1"])) + np.abs(_cross(at - d["S"], F) * d["th1"])
        for M in d["moments"]:
            vw += M * d["th1"]
            vw_scale += np.abs(M * d["th1"])
    T = np.asarray(f.balancing_torque)
    # reactions onto the links
    for jname, point, links in revolutes(desc):
        R = np.asarray(f.reactions[jname])
        at = kin.points[point].p
        for link, sign in ((links[0], 1.0), (links[1], -1.0)):
            if link != GROUND:
                loads[link]["forces"].append((sign * R, at))
    for name, pj in desc.get("prismatic", {}).items():
        _, _, nrm = line(desc, kin, name)
        N, M = np.asarray(f.normal_force[name]), np.asarray(f.moment[name])
        at = kin.points[pj["point"]].p
        for link, sign in ((pj["slider"], 1.0), (pj["guide"], -1.0)):
            if link != GROUND:
                loads[link]["forces"].append((sign * N[:, None] * nrm, at))
                loads[link]["moments"].append(sign * M)
    loads[crank_name(desc)]["moments"].append(T)
    rows = []
    for name, d in loads.items():
        Fs = sum(F for F, _ in d["forces"])
        Fscale = sum(np.hypot(*F.T) for F, _ in d["forces"])
        Ms = sum(_cross(at - d["S"], F) for F, at in d["forces"]) + sum(d["moments"])
        Mscale = sum(np.abs(_cross(at - d["S"], F)) for F, at in d["forces"]) + sum(np.abs(M) for M in d["moments"])
        rows.append((np.hypot(*Fs.T), Fscale, np.abs(Ms), Mscale))
    # the mechanism's load level: every load and reaction (ground's side too) and every moment
    f_all = sum(r[1] for r in rows) + sum(np.hypot(*np.asarray(R).T) for R in f.reactions.values())
    f_glob = GLOBAL_SHARE * f_all + 1e-300
    m_glob = GLOBAL_SHARE * (f_all * size(desc) + sum(r[3] for r in rows)) + 1e-300
    return {
        "force_balance": max(float(np.max(r[0] / (r[1] + f_glob))) for r in rows),
        "moment_balance": max(float(np.max(r[2] / (r[3] + m_glob))) for r in rows),
        "virtual_work": float(np.max(np.abs(T + vw) / (np.abs(T) + vw_scale + m_glob))),
    }


def net_joint_forces(desc: dict, f) -> dict[tuple[str, str], np.ndarray]:
    """(point, link) → the sum of the revolute reactions acting on that link at that point:
    invariant under how a compound hinge is split into revolutes."""
    out: dict[tuple[str, str], np.ndarray] = {}
    for jname, point, links in revolutes(desc):
        R = np.asarray(f.reactions[jname])
        for link, sign in ((links[0], 1.0), (links[1], -1.0)):
            key = (point, link)
            out[key] = out.get(key, 0.0) + sign * R
    return out


def zoomed_peak(fun, phi: np.ndarray, values: np.ndarray) -> float:
    """The largest value of ``fun`` (vectorised over angles), sampled as ``values`` at the
    increasing angles ``phi`` (dense: 200 000 over a turn): the best sample, then three rounds of 1001 samples between the best one's neighbours (spacing down
    to 2e-13 rad: the value is then exact to rounding at a smooth top, and at a kink or jump)."""
    k = int(np.argmax(values))
    best = float(values[k])
    a, b = phi[max(k - 1, 0)], phi[min(k + 1, len(phi) - 1)]
    for _ in range(3):
        x = np.linspace(a, b, 1001)
        y = fun(x)
        j = int(np.argmax(y))
        best = max(best, float(y[j]))
        a, b = x[max(j - 1, 0)], x[min(j + 1, len(x) - 1)]
    return best

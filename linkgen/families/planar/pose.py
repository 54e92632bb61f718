"""Assembled poses and velocities found numerically from the pair constraints, for any structure.

The closed form (``linkgen.kinematics``) needs the mechanism to decompose into class-II Assur
groups. MuJoCo needs no groups, only a reference pose where every pair holds and an initial
state: this module finds both for any mechanism, class III included, by Newton's method
(Gauss–Newton steps, least squares) on the pair constraints, starting from the sketch.

Unknowns: every moving link's frame origin (its first point) [m] and angle [rad], q (3·n,).
Equations, F(q, φ) = 0 (3·n of them for a mechanism of mobility 1):
    * a revolute at point P between links a and b: P on a − P on b = 0 (2 rows, m);
    * a prismatic pair: the slider's point on the guide line (1 row, m) and the slider's angle
      minus the guide's equal to their sketch difference (1 row, rad);
    * the drive: the crank's angle − φ = 0 (1 row, rad), or a prismatic drive's slider point
      along its guide line minus the stroke s (1 row, m; φ then stands for s).
Velocities solve J·q̇ = e·ω, e the drive row's unit vector (only that row depends on φ).

Other crank angles are reached by continuation from the sketch's crank angle in steps of at
most ``MAX_STEP`` (predictor q + q′·Δφ, then Newton), which keeps the sketch's assembly mode;
so this is a sequential path over the requested angles, not a vectorised solver.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.errors import ArgumentError, AssemblyError, DescriptionError, SingularityError
from linkgen.families.planar.geometry import guide_shapes, link_shapes, sketch_input
from linkgen.families.planar.cam_pair import ground_pair, lift, sense

# Newton stops when every position row is below POSE_TOL × the mechanism's size [m] and every
# angle row below POSE_TOL [rad]: ~1e4 ulp of double precision, so reachable, and far below the
# 1e-12 (relative) the MJCF's %.17g reference pose and the closed form agree to.
POSE_TOL = 1e-12
MAX_ITER = 40
# Continuation step in crank angle: 2° keeps the predictor within a few percent of the next pose
# on the bundled models, so Newton converges in 3–4 iterations and cannot jump to another branch.
MAX_STEP = math.radians(2.0)
# Halvings of a continuation step before giving up (2° / 2^12 ≈ 0.0005°).
MAX_HALVINGS = 12
# The sketch must agree with the assembled pose to this fraction of the mechanism's size (the
# same figure as linkgen.families.planar.assembly.SKETCH_TOLERANCE).
SKETCH_TOLERANCE = 0.02
# J·q̇ = e·ω is not solved where J's condition number exceeds this: beyond ~1e12 the velocities
# lose more than 4 of double precision's 16 digits (a dead centre or lock-up position).
MAX_CONDITION = 1e12


def mechanism_size(mech: Mechanism) -> float:
    """Diagonal of the sketch points' bounding box [m] (> 0: the crank's two points differ)."""
    xy = np.array(list(mech.points.values()), dtype=float)
    return float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))


@dataclass(frozen=True)
class LinkStates:
    """Every link's frame at m crank angles: origin (m, 2) [m], angle (m,) [rad], origin velocity
    (m, 2) [m/s], angular velocity (m,) [rad/s]; ground included (fixed, world frame)."""

    phi: np.ndarray
    omega: np.ndarray
    origin: dict[str, np.ndarray]
    angle: dict[str, np.ndarray]
    velocity: dict[str, np.ndarray]
    angular_velocity: dict[str, np.ndarray]

    def point(self, link: str, local) -> np.ndarray:
        """World position (m, 2) [m] of a point given in the link's frame."""
        c, s = np.cos(self.angle[link]), np.sin(self.angle[link])
        x, y = float(local[0]), float(local[1])
        return self.origin[link] + np.column_stack([c * x - s * y, s * x + c * y])

    def point_velocity(self, link: str, local) -> np.ndarray:
        """World velocity (m, 2) [m/s] of a point given in the link's frame."""
        r = self.point(link, local) - self.origin[link]
        w = self.angular_velocity[link]
        return self.velocity[link] + np.column_stack([-w * r[:, 1], w * r[:, 0]])


class _Constraints:
    """F(q, φ) and its Jacobian for one mechanism (see the module docstring)."""

    def __init__(self, mech: Mechanism):
        self.mech = mech
        self.shapes = link_shapes(mech)
        self.guides = guide_shapes(mech, self.shapes)
        self.links = mech.moving_links
        self.index = {name: 3 * k for k, name in enumerate(self.links)}
        self.size = mechanism_size(mech)
        self.rev = [(j.links[0], self.shapes[j.links[0]].local[j.point], j.links[1], self.shapes[j.links[1]].local[j.point])
                    for j in mech.revolutes]
        self.pri = list(self.guides.values())
        crank = self.shapes[mech.crank].sketch_angle
        # a gear pair: θ_planet − k·θ_crank stays at its sketch value
        self.gears = [(g.planet, g.ratio, self.shapes[g.planet].sketch_angle - g.ratio * crank) for g in mech.gears]
        # a cam pair: the follower's angle (or its roller centre along the guide) is the program's δ
        # of the crank's angle from the sketch (linkgen.families.planar.cam_pair)
        self.cams = [(cam, sense(mech, self.shapes, cam), self._guide_direction(cam)) for cam in mech.cams]
        self.n = 3 * len(self.links)
        rows = 2 * len(self.rev) + 2 * len(self.pri) + len(self.gears) + len(self.cams) + 1
        if rows != self.n:  # validate() enforces mobility 1, so this is a programming error
            raise ArgumentError(f"{rows} constraint rows for {self.n} unknowns")
        self.length_row = np.zeros(self.n, dtype=bool)  # rows measured in metres (others in radians)
        self.length_row[:2 * len(self.rev)] = True
        self.length_row[2 * len(self.rev):2 * len(self.rev) + 2 * len(self.pri):2] = True
        first_cam = 2 * len(self.rev) + 2 * len(self.pri) + len(self.gears)
        for k, (_, _, u) in enumerate(self.cams):
            self.length_row[first_cam + k] = u is not None  # a translating follower's lift [m]
        self.length_row[-1] = mech.slide_drive  # a prismatic drive's stroke [m]
        # continuation steps: MAX_STEP of a turn, or of the size along a stroke
        self.max_step = MAX_STEP * self.size if mech.slide_drive else MAX_STEP
        # Newton and J·q′ = e work on the dimensionless system (lengths over the size): rows in
        # metres divided by it, origin columns multiplied by it, so that J's conditioning and
        # the steps do not depend on the mechanism's scale (1e-9 m or 1e9 m alike).
        self.row_scale = np.where(self.length_row, 1.0 / self.size, 1.0)
        self.col_scale = np.tile([self.size, self.size, 1.0], len(self.links))

    def _guide_direction(self, cam) -> np.ndarray | None:
        """A translating follower's guide direction (2,) in the world; None for an oscillating one."""
        kind, pair = ground_pair(self.mech, cam)
        if kind == "R":
            return None
        alpha = self.guides[pair.name].alpha
        return np.array([math.cos(alpha), math.sin(alpha)])

    def sketch(self) -> tuple[np.ndarray, float]:
        """q at the sketch (link origins at their first points, sketch angles) and the crank angle."""
        q = np.zeros(self.n)
        for name in self.links:
            i, sh = self.index[name], self.shapes[name]
            q[i:i + 2], q[i + 2] = sh.sketch_origin, sh.sketch_angle
        return q, sketch_input(self.mech, self.shapes)

    def _frame(self, q: np.ndarray, link: str) -> tuple[np.ndarray, float]:
        if link == GROUND:
            return np.zeros(2), 0.0
        i = self.index[link]
        return q[i:i + 2], q[i + 2]

    def _place(self, q, link, local) -> tuple[np.ndarray, np.ndarray]:
        """World point and its derivative in the link's angle."""
        o, th = self._frame(q, link)
        c, s = math.cos(th), math.sin(th)
        r = np.array([c * local[0] - s * local[1], s * local[0] + c * local[1]])
        return o + r, np.array([-r[1], r[0]])

    def residual(self, q: np.ndarray, phi: float) -> np.ndarray:
        return self._evaluate(q, phi, jacobian=False)[0]

    def _evaluate(self, q: np.ndarray, phi: float, jacobian: bool = True):
        f = np.zeros(self.n)
        jac = np.zeros((self.n, self.n)) if jacobian else None

        def put(row, link, cols):  # cols: d/d(x, y, θ) of this row for one link
            if jacobian and link != GROUND:
                jac[row, self.index[link]:self.index[link] + 3] += cols

        r = 0
        for a, la, b, lb in self.rev:
            pa, da = self._place(q, a, la)
            pb, db = self._place(q, b, lb)
            f[r:r + 2] = pa - pb
            for k in range(2):
                e = np.eye(2)[k]
                put(r + k, a, [e[0], e[1], da[k]])
                put(r + k, b, [-e[0], -e[1], -db[k]])
            r += 2
        for g in self.pri:
            ps, ds = self._place(q, g.slider, g.point)
            pg, dg = self._place(q, g.guide, g.base)
            th_g = self._frame(q, g.guide)[1] + g.alpha
            u = np.array([math.cos(th_g), math.sin(th_g)])
            nrm = np.array([-u[1], u[0]])
            d = ps - pg
            f[r] = nrm @ d
            put(r, g.slider, [nrm[0], nrm[1], nrm @ ds])
            put(r, g.guide, [-nrm[0], -nrm[1], -(nrm @ dg) - u @ d])
            f[r + 1] = self._frame(q, g.slider)[1] - self._frame(q, g.guide)[1] - g.relative_angle
            put(r + 1, g.slider, [0.0, 0.0, 1.0])
            put(r + 1, g.guide, [0.0, 0.0, -1.0])
            r += 2
        for planet, k, c0 in self.gears:
            f[r] = self._frame(q, planet)[1] - k * self._frame(q, self.mech.crank)[1] - c0
            put(r, planet, [0.0, 0.0, 1.0])
            put(r, self.mech.crank, [0.0, 0.0, -k])
            r += 1
        crank, phi_s = self.mech.crank, self.shapes[self.mech.crank].sketch_angle
        for cam, sig, u in self.cams:
            d = lift(cam, np.array([self._frame(q, crank)[1] - phi_s]))
            fol = self.shapes[cam.follower]
            if u is None:  # turning about its pivot
                f[r] = self._frame(q, cam.follower)[1] - fol.sketch_angle - sig * d[0][0]
                put(r, cam.follower, [0.0, 0.0, 1.0])
            else:  # along the guide line, fixed to the ground
                pc, dc = self._place(q, cam.follower, fol.local[cam.roller])
                f[r] = u @ (pc - np.asarray(self.mech.points[cam.roller], dtype=float)) - sig * d[0][0]
                put(r, cam.follower, [u[0], u[1], u @ dc])
            put(r, crank, [0.0, 0.0, -sig * d[1][0]])
            r += 1
        if self.mech.slide_drive:  # the slider's point along the guide line from its base − s
            g = self.guides[self.mech.drive.joint]
            ps, ds = self._place(q, g.slider, g.point)
            pg, dg = self._place(q, g.guide, g.base)
            th_g = self._frame(q, g.guide)[1] + g.alpha
            u = np.array([math.cos(th_g), math.sin(th_g)])
            d = ps - pg
            f[r] = u @ d - phi
            put(r, g.slider, [u[0], u[1], u @ ds])
            put(r, g.guide, [-u[0], -u[1], -(u @ dg) + np.array([-u[1], u[0]]) @ d])
            return f, jac
        f[r] = self._frame(q, self.mech.crank)[1] - phi
        put(r, self.mech.crank, [0.0, 0.0, 1.0])
        return f, jac

    def error(self, f: np.ndarray) -> float:
        """The largest residual row, lengths relative to the mechanism's size."""
        return float(np.max(np.abs(np.where(self.length_row, f / self.size, f))))

    def newton(self, q: np.ndarray, phi: float) -> tuple[np.ndarray, bool]:
        f, jac = self._evaluate(q, phi)
        err = self.error(f)
        for _ in range(MAX_ITER):
            if err <= POSE_TOL:
                return q, True
            step = self.col_scale * np.linalg.lstsq(self._dimensionless(jac), -self.row_scale * f, rcond=None)[0]
            t = 1.0
            while True:  # backtracking keeps a far start from diverging
                trial = q + t * step
                f_t, jac_t = self._evaluate(trial, phi)
                err_t = self.error(f_t)
                if err_t < err or t < 1e-3:
                    break
                t *= 0.5
            q, f, jac, err = trial, f_t, jac_t, err_t
        return q, err <= POSE_TOL

    def rates(self, q: np.ndarray, phi: float) -> np.ndarray:
        """q′ = dq/dφ at a solved pose (J·q′ = e)."""
        jac = self._dimensionless(self._evaluate(q, phi)[1])
        cond = np.linalg.cond(jac)
        if not cond < MAX_CONDITION:
            raise SingularityError(self.label, [(phi, phi)],
                                   f"the pair constraints' Jacobian has condition number {cond:.3g}, beyond "
                                   f"MAX_CONDITION = {MAX_CONDITION:g}: a dead centre or lock-up position, where "
                                   "the velocities are not determined")
        e = np.zeros(self.n)
        e[-1] = self.row_scale[-1]  # the drive row: unscaled in radians, over the size in metres
        return self.col_scale * np.linalg.solve(jac, e)

    def _dimensionless(self, jac: np.ndarray) -> np.ndarray:
        return self.row_scale[:, None] * jac * self.col_scale[None, :]

    @property
    def label(self) -> str:
        return "[" + ", ".join(l for l in self.links if l != self.mech.crank) + "] (numeric)"


def _assembled_sketch(con: _Constraints) -> tuple[np.ndarray, float]:
    q, phi0 = con.sketch()
    q, ok = con.newton(q, phi0)
    if not ok:
        raise DescriptionError(
            "points", f"no assembled pose near the sketch at crank angle {math.degrees(phi0):.6g}°: Newton's method "
            f"on the pair constraints stopped at a residual of {con.error(con.residual(q, phi0)):.3g} (relative to the "
            f"size {con.size:.6g} m, needed {POSE_TOL:g}); correct the sketch or the link lengths")
    tol = SKETCH_TOLERANCE * con.size
    for link in con.links:
        for p, local in con.shapes[link].local.items():
            got = con._place(q, link, local)[0]
            want = np.asarray(con.mech.points[p], dtype=float)
            dev = float(np.hypot(*(got - want)))
            if dev > tol:
                raise DescriptionError(
                    f"points.{p}", f"the sketch puts it at ({want[0]:.6g}, {want[1]:.6g}) m but link {link!r} assembles "
                    f"it at ({got[0]:.6g}, {got[1]:.6g}) m, {dev:.3g} m away (allowed {tol:.3g} m = {SKETCH_TOLERANCE:g} "
                    f"of the sketch's size); correct the sketch or the link lengths")
    return q, phi0


def _track(con: _Constraints, q: np.ndarray, phi: float, target: float) -> np.ndarray:
    """Continue the solved pose q at crank angle φ to ``target``."""
    while phi != target:
        step = max(-con.max_step, min(con.max_step, target - phi))
        for _ in range(MAX_HALVINGS + 1):
            nxt = target if abs(target - phi) <= abs(step) else phi + step
            trial, ok = con.newton(q + con.rates(q, phi) * (nxt - phi), nxt)
            if ok:
                break
            step *= 0.5
        else:
            raise AssemblyError(con.label, [(nxt, nxt)],
                                f"the loop equations have no solution continuing from {math.degrees(phi):.6g}° "
                                f"(Newton's method on the pair constraints does not converge)")
        q, phi = trial, nxt
    return q


def state(mech: Mechanism, phi, omega=0.0) -> LinkStates:
    """Link poses and velocities at crank angles φ (m,) [rad] and speeds ω (scalar or (m,)) [rad/s],
    on the sketch's assembly mode, reached by continuation in the order given.

    Raises:
        DescriptionError: no assembled pose near the sketch.
        AssemblyError: the path from the sketch's crank angle to some φ leaves the assembled range.
        SingularityError: J is singular at some φ (dead centre), so velocities are undefined.
    """
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    if phi.ndim != 1 or phi.shape[0] == 0 or not np.all(np.isfinite(phi)):
        raise ArgumentError(f"phi must be a non-empty, finite 1-D array of crank angles [rad], got {phi!r}")
    omega = np.asarray(omega, dtype=float)
    if omega.shape not in ((), phi.shape) or not np.all(np.isfinite(omega)):
        raise ArgumentError(f"omega must be a finite scalar or one per crank angle {phi.shape} [rad/s], got {omega!r}")
    omega = np.broadcast_to(omega, phi.shape)
    con = _Constraints(mech)
    q, at = _assembled_sketch(con)
    qs, rates = np.zeros((phi.shape[0], con.n)), np.zeros((phi.shape[0], con.n))
    for k, target in enumerate(phi):
        q = _track(con, q, at, float(target))
        at = float(target)
        qs[k], rates[k] = q, con.rates(q, at)
    qd = rates * omega[:, None]
    m = phi.shape[0]
    origin, angle = {GROUND: np.zeros((m, 2))}, {GROUND: np.zeros(m)}
    vel, avel = {GROUND: np.zeros((m, 2))}, {GROUND: np.zeros(m)}
    for name in con.links:
        i = con.index[name]
        origin[name], angle[name] = qs[:, i:i + 2], qs[:, i + 2]
        vel[name], avel[name] = qd[:, i:i + 2], qd[:, i + 2]
    return LinkStates(phi, np.array(omega), origin, angle, vel, avel)


def reference_pose(mech: Mechanism) -> LinkStates:
    """The assembled pose at the sketch's crank angle (at rest): the MJCF's reference pose."""
    return state(mech, sketch_input(mech, link_shapes(mech)), 0.0)


__all__ = ["LinkStates", "MAX_STEP", "POSE_TOL", "mechanism_size", "reference_pose", "state"]

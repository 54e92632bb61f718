"""A solver that is not linkgen, for the referee's tests: a plain vector-loop Newton solver of
the Watt six-bar in tests/data/referee_sixbar.toml, numpy and tomllib only (it reads the sketch
and the lengths from the TOML itself, and shares no code with linkgen).

Unknowns: the angles θ2 (coupler A→B), θ3 (rocker C→B), θ4 (link4 D→E), θ5 (link5 F→E).
Loops:  A(φ) + L2·e(θ2) − C − L3·e(θ3) = 0
        C + LCD·e(θ3 + β) + L4·e(θ4) − F − L5·e(θ5) = 0,   e(θ) = (cos θ, sin θ)
Positions by Newton from the sketch, continued angle by angle (which keeps the assembly mode);
velocities from J·q̇ = −∂F/∂φ·ω; accelerations from J·q̈ = −(∂F/∂φ·ε + the θ̇² and ω² terms).

``solve(phi, omega, epsilon, centripetal=True, flip_from=None)``: ``centripetal`` False drops the
θ̇² and ω² terms (a classic mistake); ``flip_from`` an angle [rad] from which the Newton
iteration restarts from the mirror image of the second dyad (E reflected in the line D–F): the
solver lands on its other assembly mode there."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np

TOML = Path(__file__).resolve().parent / "data" / "referee_sixbar.toml"


def _e(t):
    return np.array([math.cos(t), math.sin(t)])


def _n(t):  # d e(θ)/dθ
    return np.array([-math.sin(t), math.cos(t)])


class SixBar:
    def __init__(self, path: Path = TOML) -> None:
        d = tomllib.loads(path.read_text(encoding="utf-8"))
        p = {k: np.array(v, dtype=float) for k, v in d["points"].items()}
        links = d["links"]
        self.O, self.C, self.F = p["O"], p["C"], p["F"]
        self.L1 = links["crank"]["length"]
        self.L2 = links["coupler"]["length"]
        self.L3 = float(np.linalg.norm(p["B"] - p["C"]))
        self.LCD = float(np.linalg.norm(p["D"] - p["C"]))
        self.beta = math.atan2(*(p["D"] - p["C"])[::-1]) - math.atan2(*(p["B"] - p["C"])[::-1])
        self.L4 = float(np.linalg.norm(p["E"] - p["D"]))
        self.L5 = float(np.linalg.norm(p["E"] - p["F"]))
        self.sketch = p
        self.q0 = np.array([math.atan2(*(p[b] - p[a])[::-1]) for a, b in (("A", "B"), ("C", "B"), ("D", "E"),
                                                                            ("F", "E"))])

    def residual(self, q, phi):
        t2, t3, t4, t5 = q
        a = self.O + self.L1 * _e(phi)
        r1 = a + self.L2 * _e(t2) - self.C - self.L3 * _e(t3)
        r2 = self.C + self.LCD * _e(t3 + self.beta) + self.L4 * _e(t4) - self.F - self.L5 * _e(t5)
        return np.concatenate([r1, r2])

    def jacobian(self, q):
        t2, t3, t4, t5 = q
        j = np.zeros((4, 4))
        j[:2, 0] = self.L2 * _n(t2)
        j[:2, 1] = -self.L3 * _n(t3)
        j[2:, 1] = self.LCD * _n(t3 + self.beta)
        j[2:, 2] = self.L4 * _n(t4)
        j[2:, 3] = -self.L5 * _n(t5)
        return j

    def newton(self, q, phi):
        for _ in range(50):
            dq = np.linalg.solve(self.jacobian(q), -self.residual(q, phi))
            q = q + dq
            if np.max(np.abs(dq)) < 1e-15:
                break
        return q

    def mirrored(self, q, phi):
        """The second dyad's other mode: E reflected in the line D–F."""
        t2, t3, t4, t5 = q
        d = self.C + self.LCD * _e(t3 + self.beta)
        e = self.F + self.L5 * _e(t5)
        u = (self.F - d) / np.linalg.norm(self.F - d)
        m = d + 2 * np.dot(e - d, u) * u - (e - d)
        return np.array([t2, t3, math.atan2(*(m - d)[::-1]), math.atan2(*(m - self.F)[::-1])])

    def solve(self, phi, omega, epsilon=0.0, centripetal=True, flip_from=None) -> dict[str, np.ndarray]:
        out: dict[str, list] = {}
        q = self.newton(self.q0, float(phi[0]))
        flipped = False
        for f in phi:
            q = self.newton(q, float(f))
            if flip_from is not None and f >= flip_from and not flipped:
                q = self.newton(self.mirrored(q, float(f)), float(f))
                flipped = True
            j = self.jacobian(q)
            dphi = np.concatenate([self.L1 * _n(f), np.zeros(2)])  # ∂F/∂φ
            w = np.linalg.solve(j, -dphi * omega)
            t2, t3, t4, t5 = q
            w2, w3, w4, w5 = w
            k = 1.0 if centripetal else 0.0
            sq = np.concatenate([
                -self.L1 * omega**2 * _e(f) - self.L2 * w2**2 * _e(t2) + self.L3 * w3**2 * _e(t3),
                -self.LCD * w3**2 * _e(t3 + self.beta) - self.L4 * w4**2 * _e(t4) + self.L5 * w5**2 * _e(t5)])
            acc = np.linalg.solve(j, -(dphi * epsilon + k * sq))
            pts = self._points(f, q, w, acc, omega, epsilon, k)
            for name, v in pts.items():
                out.setdefault(name, []).append(v)
            for i, link in enumerate(("coupler", "rocker", "link4", "link5")):
                for qty, val in (("angle [rad]", q[i]), ("angular_velocity [rad/s]", w[i]),
                                 ("angular_acceleration [rad/s²]", acc[i])):
                    out.setdefault(f"{link}.{qty}", []).append(val)
        return {"phi [rad]": np.asarray(phi, dtype=float)} | {k: np.array(v) for k, v in out.items()}

    def _points(self, f, q, w, a, omega, epsilon, k):
        t2, t3, t4, t5 = q
        res = {}
        # B, D on the rocker about C; E on link5 about F
        for name, base, length, t, wi, ai in (("B", self.C, self.L3, t3, w[1], a[1]),
                                              ("D", self.C, self.LCD, t3 + self.beta, w[1], a[1]),
                                              ("E", self.F, self.L5, t5, w[3], a[3])):
            pos = base + length * _e(t)
            vel = length * wi * _n(t)
            acc = length * (ai * _n(t) - k * wi**2 * _e(t))
            for qty, v, unit in (("position", pos, "m"), ("velocity", vel, "m/s"), ("acceleration", acc, "m/s²")):
                res[f"{name}.{qty}.x [{unit}]"], res[f"{name}.{qty}.y [{unit}]"] = v[0], v[1]
        return res

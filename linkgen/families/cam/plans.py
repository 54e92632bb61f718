"""The velocity and acceleration plans of a cam and its follower (``model.plans``), at constant
cam speed ω, of the follower's point B: the roller's centre (for a flat face, the contact point on
the face). Through the cam: B₁, the cam's point under B, turns about O, and B moves along the pitch
curve relative to the cam,

    v_B = ω × OB + ω·R(θ)P′,            a_B = −ω² OB + 2 ω × v_BB₁ + ω²·R(θ)P″

(P the pitch curve in the cam's frame, R(θ) the cam's turn: normal part, Coriolis part, relative
part); through the follower, for a roller: v_B = ṡ u along the stem (translating), or
ψ̇ × O₁B turning about the arm's pivot O₁ (oscillating, with the normal part −ψ̇² O₁B and the
tangential part ψ̈ × O₁B). Both chains end at the closed form's C′ω and C″ω² (``Follower.centre``)."""

from __future__ import annotations

import numpy as np

from linkgen.model.plans import POLES, Chain, VectorPlan, check_kind


def _j(v: np.ndarray) -> np.ndarray:
    """A quarter turn counter-clockwise: ẑ × v."""
    return np.array([-v[1], v[0]])


def cam_plan(cm, theta: float, kind: str) -> VectorPlan:
    """The ``kind`` ("velocity" or "acceleration") plan of the cam mechanism ``cm`` at cam angle θ [rad]."""
    check_kind(kind)
    f = cm.follower
    w = cm.omega
    th = np.array([float(theta)])
    c, c1, c2, u = (x[0] for x in f.centre(th))
    _, p1, p2 = (x[0] for x in f.pitch_curve(th))
    cs, sn = np.cos(theta), np.sin(theta)
    rot = np.array([[cs, -sn], [sn, cs]])  # R(θ): the cam's frame to the fixed one
    rel_v, rel_a = w * (rot @ p1), w * w * (rot @ p2)
    pole = POLES[kind]
    acc = kind == "acceleration"
    target = c2 * w * w if acc else c1 * w
    if acc:
        n = -w * w * c
        k = n + 2.0 * w * _j(rel_v)
        chains = [Chain("cam", "b", (pole, "b1", "k_b", "b"), np.array([np.zeros(2), n, k, k + rel_a]),
                        ("normal", "coriolis", "sliding"))]
    else:
        b1 = w * _j(c)
        chains = [Chain("cam", "b", (pole, "b1", "b"), np.array([np.zeros(2), b1, b1 + rel_v]), ("relative", "sliding"))]
    q, q1, q2, _ = (x[0] for x in f.output(th))
    if not f.flat and f.kind == "translating":
        s_v, s_a = q1 * w, q2 * w * w
        chains.append(Chain("follower", "b", (pole, "b"), np.array([np.zeros(2), (s_a if acc else s_v) * u]),
                            ("sliding",)))
    elif not f.flat:
        r = c - np.array([f.pivot_distance, 0.0])  # O₁B
        sign = float(np.sign(r[0] * u[1] - r[1] * u[0])) or 1.0  # ψ grows along u: turning sense about +z
        psi_v, psi_a = sign * q1 * w, sign * q2 * w * w
        if acc:
            nrm = -psi_v * psi_v * r
            chains.append(Chain("follower", "b", (pole, "n_bo1", "b"), np.array([np.zeros(2), nrm, nrm + psi_a * _j(r)]),
                                ("normal", "tangential")))
        else:
            chains.append(Chain("follower", "b", (pole, "b"), np.array([np.zeros(2), psi_v * _j(r)]), ("relative",)))
    vertices = {pole: np.zeros(2), "b": target}
    return VectorPlan(kind, float(theta), float(w), 0.0, pole, vertices, tuple(chains), ("O",))


__all__ = ["cam_plan"]

"""The equilibrium systems of the kinetostatics, solved in closed form over arrays of angles.

A column is what one unknown of a pair (a force component, a normal force, a moment) puts into a
link's three equilibrium equations: a triple (x force, y force, moment about the link's centre
of mass), each an array over the angles or a constant. Every equation here is elementwise, so a
result at one angle does not depend on the others, the block size or the threads.

A class-II group (``dyad``) has the block structure of its pairs: the outer pair o1 loads
only L1, o2 only L2, the inner pair both,

    | P1  Q1  0  | |x1|   |b1|
    | 0   Q2  P2 | |y | = |b2|       (each block 3 × 2)
                   |x2|

so n_i = P_i[:, 0] × P_i[:, 1], normal to both columns of P_i, removes x_i from L_i's three
equations: n_i·Q_i y = n_i·b_i, two equations in the inner pair's two unknowns (Cramer). Each
outer pair's unknowns then follow from P_i x_i = b_i − Q_i y, whose right side lies in the plane
of P_i's columns: for c = α·a + β·b, α = (c × b)·n / n·n and β = (a × c)·n / n·n with n = a × b.
This is the textbook's order (the inner pair first, from each link's own equations) and costs
about 80 multiplications per angle, against ~330 ns per angle for a batched 6 × 6 LU (measured:
``np.linalg.solve`` was 48 % of ``forces``'s time on the four-bar at 10^6 angles).

A 3 × 3 system (the crank, a cam's follower) is solved by Cramer's rule with triple products.

Where a system is exactly singular (a zero determinant, or an outer pair whose columns are
parallel) the result is not finite; the caller names those angles (``SingularityError``).
"""

from __future__ import annotations

from typing import Union

import numpy as np

Component = Union[np.ndarray, float]
Column = tuple[Component, Component, Component]


def dot(a: Column, b: Column) -> np.ndarray:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Column, b: Column) -> Column:
    return a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]


def _minus(c: Column, a: Column, y0: np.ndarray, b: Column, y1: np.ndarray) -> Column:
    """c − a·y0 − b·y1."""
    return c[0] - a[0] * y0 - b[0] * y1, c[1] - a[1] * y0 - b[1] * y1, c[2] - a[2] * y0 - b[2] * y1


def in_plane(c: Column, a: Column, b: Column, n: Column) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray]:
    """((α, β), n·n) with c = α·a + β·b, for c in the plane of a and b, n = a × b."""
    nn = dot(n, n)
    return (dot(cross(c, b), n) / nn, dot(cross(a, c), n) / nn), nn


def dyad(p1: tuple[Column, Column], q1: tuple[Column, Column], q2: tuple[Column, Column],
         p2: tuple[Column, Column], b1: Column, b2: Column) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Solve a class-II group's six equations (see the module's docstring): (the unknowns of o1
    (two), of the inner pair (two) and of o2 (two), each an array over the angles; where the
    system is exactly singular)."""
    n1, n2 = cross(*p1), cross(*p2)
    m00, m01, m10, m11 = dot(n1, q1[0]), dot(n1, q1[1]), dot(n2, q2[0]), dot(n2, q2[1])
    r0, r1 = dot(n1, b1), dot(n2, b2)
    det = m00 * m11 - m01 * m10
    y0, y1 = (r0 * m11 - m01 * r1) / det, (m00 * r1 - m10 * r0) / det
    x1, nn1 = in_plane(_minus(b1, q1[0], y0, q1[1], y1), *p1, n1)
    x2, nn2 = in_plane(_minus(b2, q2[0], y0, q2[1], y1), *p2, n2)
    return (*x1, y0, y1, *x2), (det == 0.0) | (nn1 == 0.0) | (nn2 == 0.0)


def three(c0: Column, c1: Column, c2: Column, b: Column) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Solve x0·c0 + x1·c1 + x2·c2 = b by Cramer's rule: ((x0, x1, x2), where det = 0)."""
    n12 = cross(c1, c2)
    det = dot(c0, n12)
    return (dot(b, n12) / det, dot(c0, cross(b, c2)) / det, dot(c0, cross(c1, b)) / det), det == 0.0


__all__ = ["Column", "cross", "dot", "dyad", "in_plane", "three"]

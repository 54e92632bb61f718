"""The Bennett linkage of models/bennett.toml, built by Denavit–Hartenberg transforms so that its
numbers can be reproduced: four revolutes on skew axes, opposite links equal in length and twist
(crank and rocker a, α; coupler and ground b, β), zero offsets, and a·sin β = b·sin α.

Each link is the common normal between its two joint axes. With the frame of joint i at its point
P_i (z along the axis, x along the link's normal towards the next axis), the next joint's frame
is F_i·Tx(a_i)·Rx(α_i)·Rz(θ_{i+1}). The world frame sits at the crank pivot A0 with z along the
drive axis and x along the ground's normal arriving from B0, so B0 = (−b, 0, 0), the ground axis
is (0, sin β, cos β), and the crank angle φ (A about z from +x) is the joint angle θ1. Bennett's
closure: θ3 = −θ1, θ4 = −θ2, tan(θ1/2)·tan(θ2/2) = sin((β + α)/2) / sin((β − α)/2), so every θ1
has its θ2: the crank turns fully. ``frames`` asserts that the four transforms close the loop.

    python validation/make_bennett.py                      # print the description
    python validation/make_bennett.py -o models/bennett.toml
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

# Crank and rocker: length A [m], twist ALPHA [deg]; coupler and ground: twist BETA [deg], length
# from Bennett's condition a·sin β = b·sin α (0.4 m here).
A = 0.2
ALPHA = 30.0
BETA = 90.0
PHI_SKETCH = 60.0  # the crank angle of the sketch [deg]
DENSITY = 2.0  # kg/m on every moving link
OMEGA = 10.0  # rad/s
# The four transforms close the loop but for rounding: a few eps of the metre-sized lengths.
CLOSURE_TOL = 1e-12
# Components below this are rounding (cos 90° = 6e-17) and are written as 0.
ROUNDING = 1e-15


def coupler_length(a: float = A, alpha: float = ALPHA, beta: float = BETA) -> float:
    """b from Bennett's condition a·sin β = b·sin α [m] (twists in degrees)."""
    return a * math.sin(math.radians(beta)) / math.sin(math.radians(alpha))


def tx(a: float) -> np.ndarray:
    t = np.eye(4)
    t[0, 3] = a
    return t


def rx(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    t = np.eye(4)
    t[1:3, 1:3] = [[c, -s], [s, c]]
    return t


def rz(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    t = np.eye(4)
    t[0:2, 0:2] = [[c, -s], [s, c]]
    return t


def link(a: float, alpha: float, theta_next: float) -> np.ndarray:
    """From a joint's frame along the link's normal (length a, twist α [rad]) to the next joint's
    frame turned by its joint angle."""
    return tx(a) @ rx(alpha) @ rz(theta_next)


def frames(phi: float, a: float = A, alpha: float = ALPHA, beta: float = BETA) -> list[np.ndarray]:
    """The frames (4, 4) of the joints A0, A, B, B0 at crank angle ``phi`` [rad] (twists in
    degrees); the origin of each is its joint point, its z column the joint's axis."""
    al, be = math.radians(alpha), math.radians(beta)
    b = coupler_length(a, alpha, beta)
    k = math.sin((be + al) / 2) / math.sin((be - al) / 2)
    th2 = 2 * math.atan2(k * math.cos(phi / 2), math.sin(phi / 2))
    f1 = rz(phi)
    f2 = f1 @ link(a, al, th2)
    f3 = f2 @ link(b, be, -phi)
    f4 = f3 @ link(a, al, -th2)
    closure = f4 @ link(b, be, phi)
    assert np.abs(closure - f1).max() < CLOSURE_TOL, closure - f1
    return [f1, f2, f3, f4]


def vec(v) -> str:
    return "[" + ", ".join(repr(float(x) if abs(x) > ROUNDING else 0.0) for x in v) + "]"


def description(a: float = A, alpha: float = ALPHA, beta: float = BETA, phi_sketch: float = PHI_SKETCH) -> str:
    """The TOML description (the defaults are models/bennett.toml's)."""
    b = coupler_length(a, alpha, beta)
    be = math.radians(beta)
    names = ("A0", "A", "B", "B0")
    f = frames(math.radians(phi_sketch), a, alpha, beta)
    pts = {n: fr[:3, 3] for n, fr in zip(names, f)}
    axes = {n: fr[:3, 2] for n, fr in zip(names, f)}
    # the ground's pair points and axes exactly (the transforms agree to rounding)
    pts["A0"], axes["A0"] = np.zeros(3), np.array([0.0, 0.0, 1.0])
    pts["B0"], axes["B0"] = np.array([-b, 0.0, 0.0]), np.array([0.0, math.sin(be), math.cos(be)])
    lines = [
        "# Bennett linkage: four revolutes on skew axes, opposite links equal, zero offsets. Crank A0A and",
        f"# rocker B0B: length a = {a:g} m, twist α = {alpha:g}°; coupler AB and ground B0A0: length",
        f"# b = {b:.9g} m, twist β = {beta:g}° (Bennett's condition a·sin β = b·sin α). Each link is the",
        "# common normal of its two joint axes, and each point the foot of the normals at its joint.",
        "# The crank turns about z through A0 = (0, 0, 0); the ground's normal runs from B0 = (−b, 0, 0)",
        f"# along +x to A0, and the ground axis through B0 is (0, sin β, cos β). The sketch is at φ = {phi_sketch:g}°",
        "# (A about z from +x). Every link turns fully: at φ = 0 and 180° the four joints lie on the x",
        "# axis, and the linkage folds through. Coordinates from validation/make_bennett.py",
        "# (Denavit–Hartenberg transforms), written in full.",
        "[mechanism]",
        'name = "bennett"',
        f'title = "Bennett linkage: crank and rocker {a:g} m twisted {alpha:g}°, coupler and ground {b:.4g} m '
        f'twisted {beta:g}°"',
        'space = "spatial"',
        "gravity = [0.0, 0.0, -9.81]",
        "",
        f"[points]          # the sketch at φ = {phi_sketch:g}°",
        *(f"{n} = {vec(pts[n])}" for n in names),
        "",
        "[links.ground]",
        'points = ["A0", "B0"]',
        "",
    ]
    for lname, (p, q) in (("crank", ("A0", "A")), ("coupler", ("A", "B")), ("rocker", ("B0", "B"))):
        lines += [f"[links.{lname}]", f'points = ["{p}", "{q}"]', f"density = {DENSITY!r}" + ("     # kg/m, a uniform rod" if lname == "crank" else ""), ""]
    for n in names:
        lines += [f"[joints.{n}]", 'kind = "revolute"', f"axis = {vec(axes[n])}", ""]
    lines += ["[drive]", 'joint = "A0"', f"omega = {OMEGA!r}      # rad/s"]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", type=Path, help="write the description here (default: print it)")
    args = p.parse_args(argv)
    text = description()
    if args.output:
        args.output.write_text(text, encoding="utf-8")
    else:
        print(text, end="")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Measure the magnitudes the closed-form pipeline carries: every bundled model rescaled in
length (s), mass (mu) and time (w = 1/time scale), solved, and checked against the unscaled
solution by the scaling laws of rigid-body mechanics (positions ×s, velocities ×s·w, forces
×mu·s·w², torques and reduced moments ×mu·s²·w², reduced inertia ×mu·s²). Prints one row per
scale: the worst relative error over all models, or the first error raised.

    .venv/bin/python validation/limits_scan.py               # with linkgen.limits enforced
    .venv/bin/python validation/limits_scan.py --unlimited   # where the pipeline itself breaks
"""

from __future__ import annotations

import copy
import sys
import tomllib
from pathlib import Path

import numpy as np

from linkgen import LinkgenError, from_dict, solve
from linkgen.families.planar.kinetostatics import forces
from linkgen.cli.common import crank_grid

MODELS = Path(__file__).resolve().parent.parent / "models"
SAMPLES = 24


def scaled(data: dict, s: float = 1.0, mu: float = 1.0, w: float = 1.0) -> dict:
    """The description with lengths ×s, masses ×mu and rates ×w (time ×1/w)."""
    d = copy.deepcopy(data)
    d["points"] = {k: [x * s for x in v] for k, v in d["points"].items()}
    for link in d["links"].values():
        if "length" in link:
            link["length"] *= s
        if "shape" in link:
            link["shape"] = {k: [x * s for x in v] for k, v in link["shape"].items()}
        if "density" in link:
            link["density"] *= mu / s
        if "inertial" in link:
            i = link["inertial"]
            link["inertial"] = {"mass": i["mass"] * mu, "com": [x * s for x in i["com"]],
                                "inertia": i["inertia"] * mu * s * s}
        elif "density" not in link:
            # the defaults (1 kg/m bars, 0.1 kg blocks) do not scale: make them explicit
            pts = link["points"]
            if link is not d["links"]["ground"]:
                if len(pts) == 1:
                    link["inertial"] = {"mass": 0.1 * mu, "com": [0.0, 0.0], "inertia": 1e-4 * mu * s * s}
                elif len(pts) == 2:
                    link["density"] = mu / s
                else:  # the default bar over the first two points, made explicit
                    xy = link.get("shape", d["points"])
                    length = float(np.hypot(*np.subtract(xy[pts[1]], xy[pts[0]])))
                    link["inertial"] = {"mass": length / s * mu, "com": [length / 2, 0.0],
                                        "inertia": length**3 / s * mu / 12}
    for p in d.get("prismatic", {}).values():
        if "offset" in p:
            p["offset"] *= s
    mech = d["mechanism"]
    if "gravity" in mech:
        mech["gravity"] = [g * s * w * w for g in mech["gravity"]]
    d["drive"]["omega"] *= w
    if "epsilon" in d["drive"]:
        d["drive"]["epsilon"] *= w * w
    for f in d.get("force", []):
        f["force"] = [x * mu * s * w * w for x in f["force"]]
    for t in d.get("torque", []):
        t["torque"] *= mu * s * s * w * w
    return d


def _quantities(data: dict) -> dict[str, tuple[np.ndarray, float]]:
    """(values, unit exponents in s, mu, w) of every output."""
    mech = from_dict(data)
    phi = crank_grid(mech, SAMPLES)
    f = forces(mech, phi, mech.drive.omega, mech.drive.epsilon)

    out = {"balancing_torque": (f.balancing_torque, (2, 1, 2)),
           "reduced_inertia": (f.reduced.inertia, (2, 1, 0)),
           "reduced_moment": (f.reduced.moment, (2, 1, 2))}
    out |= {f"reaction {k}": (v, (1, 1, 2)) for k, v in f.reactions.items()}
    out |= {f"normal {k}": (v, (1, 1, 2)) for k, v in f.normal_force.items()}
    out |= {f"moment {k}": (v, (2, 1, 2)) for k, v in f.moment.items()}


    mo = solve(mech, phi).motion(mech.drive.omega, mech.drive.epsilon)
    for k, (p, v, a) in mo.points.items():
        out |= {f"{k}.p": (p, (1, 0, 0)), f"{k}.v": (v, (1, 0, 1)), f"{k}.a": (a, (1, 0, 2))}
    return out


def worst(data: dict, ref: dict, s: float, mu: float, w: float) -> float:
    got = _quantities(scaled(data, s, mu, w))
    err = 0.0
    for k, (v, (es, em, ew)) in got.items():
        r = ref[k][0]
        # the exponents may exceed the float range when multiplied out: scale back step by step
        back = v / s**es if es else v
        back = back / mu**em if em else back
        back = back / w**ew if ew else back
        peak = float(np.max(np.abs(r)))
        if not np.all(np.isfinite(back)):
            return float("inf")
        if peak > 0:
            err = max(err, float(np.max(np.abs(back - r))) / peak)
    return err


def main() -> int:
    if "--unlimited" in sys.argv[1:]:
        from linkgen import limits

        for name in limits.__all__:
            setattr(limits, name, 0.0 if name.startswith("MIN") else float("inf"))
    models = {p.stem: tomllib.loads(p.read_text()) for p in sorted(MODELS.glob("*.toml"))}
    refs = {k: _quantities(scaled(d)) for k, d in models.items()}
    # every 10 decades, and every decade where the closed form stops holding (1e-104, 1e17)
    fine = set(range(-110, -95)) | set(range(10, 20))
    scans = [("s", {"s": 10.0**k}) for k in sorted(set(range(-300, 301, 10)) | fine)]
    scans += [("w", {"w": 10.0**k}) for k in range(-300, 301, 10)]
    scans += [("mu", {"mu": 10.0**k}) for k in range(-300, 301, 10)]
    # corners inside linkgen.limits: sizes 0.3-1.5 m ×1e11, masses ≤ 10 kg ×1e29, ω ≤ 10 rad/s ×1e29
    scans += [("s,mu,w", {"s": s, "mu": mu, "w": w}) for s, mu, w in
              [(1e11, 1e29, 1e29), (1e11, 1e-13, 1e29), (1e-88, 1e-13, 1.0), (1e-88, 1e29, 1e29)]]
    for label, kw in scans:
        row = []
        for name, d in models.items():
            try:
                row.append(worst(d, refs[name], kw.get("s", 1.0), kw.get("mu", 1.0), kw.get("w", 1.0)))
            except (LinkgenError, ArithmeticError, ValueError, RecursionError) as exc:
                row.append(f"{name}: {type(exc).__name__}: {str(exc)[:80]}")
                break
        value = ", ".join(f"{v:.0e}" for v in kw.values())
        bad = [r for r in row if isinstance(r, str)]
        print(f"{label} = {value}: " + (bad[0] if bad else f"worst relative error {max(row):.2e}"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

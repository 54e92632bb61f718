"""Hypothesis strategies and description transforms for the property tests.

Mechanisms come from ``linkgen.families.planar.corpus.random_description`` seeded by hypothesis; the
transforms below rewrite a description into an equivalent one (the same physical mechanism
said differently) or into a hostile file. They work on the TOML-shaped dict with their own
geometry (the sketch), not with linkgen's.
"""

from __future__ import annotations

import copy
import math

import numpy as np
from hypothesis import strategies as st

from independent_checks import GROUND, angle_value, crank_name, sketch, sketch_frame_angle
from linkgen.families.planar.corpus import random_description, to_toml

seeds = st.integers(min_value=0, max_value=2**63 - 1)


def _described(seed: int, max_groups: int) -> tuple[int, dict]:
    return seed, random_description(np.random.default_rng(seed), max_groups=1 + seed % max_groups)


def mechanisms(max_groups: int = 4):
    """(seed, description): one draw per example, so that no two examples share a mechanism
    (hypothesis avoids repeating a whole example, not a part of one); the number of groups
    and any further randomness of a test derive from the seed."""
    return seeds.map(lambda s: _described(s, max_groups))


def _drive_joint(desc: dict) -> str:
    """The drive revolute's name under the description's current table order."""
    pivot = desc["drive"]["joint"].split(":")[0]
    carriers = [n for n, s in desc["links"].items() if pivot in s["points"]]
    if len(carriers) == 2:
        return pivot
    crank = crank_name(desc)
    first = carriers[0]
    return f"{pivot}:{first}-{crank if first == GROUND else GROUND}"


def reorder_tables(desc: dict, rng: np.random.Generator) -> dict:
    """The same mechanism with its points, links, prismatic pairs and forces listed in
    another order (the drive pivot's first carrier kept on ground or the crank, so that a
    ground–crank revolute still exists)."""
    out = copy.deepcopy(desc)
    crank = crank_name(desc)
    pivot = desc["drive"]["joint"].split(":")[0]
    names = list(desc["links"])
    for _ in range(100):
        order = [names[i] for i in rng.permutation(len(names))]
        first = next(n for n in order if pivot in desc["links"][n]["points"])
        if first in (GROUND, crank):
            break
    else:
        order = names
    out["links"] = {n: desc["links"][n] for n in order}
    pts = list(desc["points"])
    out["points"] = {p: desc["points"][p] for p in (pts[i] for i in rng.permutation(len(pts)))}
    if "prismatic" in desc:
        pr = list(desc["prismatic"])
        out["prismatic"] = {k: desc["prismatic"][k] for k in (pr[i] for i in rng.permutation(len(pr)))}
    if "force" in desc:
        out["force"] = [desc["force"][i] for i in rng.permutation(len(desc["force"]))]
    out["drive"]["joint"] = _drive_joint(out)
    out["mechanism"]["name"] = "reordered"
    return copy.deepcopy(out)


def _rot(a: float, w) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([c * w[0] - s * w[1], s * w[0] + c * w[1]])


def reorder_link_points(desc: dict, rng: np.random.Generator) -> dict | None:
    """The same mechanism with one link's points listed in another order: its frame moves,
    so its explicit centre of mass and the angles of guides on it are re-expressed. Only
    orders that keep the physics: the crank keeps its first two points (they define φ), a
    link with default mass keeps its first two as a set (the default bar), and the first
    two points never coincide. None if no link qualifies."""
    out = copy.deepcopy(desc)
    xy = sketch(desc)
    crank = crank_name(desc)
    for _ in range(50):
        names = [n for n, s in desc["links"].items() if len(s["points"]) >= 2]
        name = names[rng.integers(len(names))]
        spec = desc["links"][name]
        pts = list(spec["points"])
        perm = [pts[i] for i in rng.permutation(len(pts))]
        if name == crank:
            perm = pts[:2] + [p for p in perm if p not in pts[:2]]
        elif name != GROUND and "inertial" not in spec and "density" not in spec and set(perm[:2]) != set(pts[:2]):
            continue
        if perm == pts or (name != GROUND and np.hypot(*(xy[perm[1]] - xy[perm[0]])) == 0.0):
            continue
        break
    else:
        return None
    out["links"][name]["points"] = perm
    if name == GROUND:
        return out
    th_old, th_new = sketch_frame_angle(desc, name), sketch_frame_angle(out, name)
    o_old, o_new = xy[pts[0]], xy[perm[0]]
    if "inertial" in spec:
        world = o_old + _rot(th_old, spec["inertial"]["com"])
        c = _rot(-th_new, world - o_new)
        out["links"][name]["inertial"]["com"] = [float(c[0]), float(c[1])]
    for pj in out.get("prismatic", {}).values():
        if pj["guide"] == name:
            pj["angle"] = angle_value(pj.get("angle", 0.0)) + th_old - th_new
    out["mechanism"]["name"] = "points_reordered"
    return out


def reverse_slot(desc: dict, name: str) -> dict:
    """The prismatic pair ``name`` with its line's direction reversed: angle + 180°, and
    the offset's sign flipped (it is measured along the line's left normal)."""
    out = copy.deepcopy(desc)
    pj = out["prismatic"][name]
    pj["angle"] = angle_value(pj.get("angle", 0.0)) + math.pi
    pj["offset"] = -float(pj.get("offset", 0.0))
    return out


def through_other(desc: dict, name: str, rng: np.random.Generator) -> dict | None:
    """The prismatic pair ``name`` with its line given through another point of the guide
    link, the offset recomputed from the sketch so that the line is the same. None if the
    guide has one point."""
    pj = desc["prismatic"][name]
    others = [p for p in desc["links"][pj["guide"]]["points"] if p != pj["through"]]
    if not others:
        return None
    q = others[rng.integers(len(others))]
    xy = sketch(desc)
    th = sketch_frame_angle(desc, pj["guide"]) + angle_value(pj.get("angle", 0.0))
    nrm = np.array([-math.sin(th), math.cos(th)])
    out = copy.deepcopy(desc)
    out["prismatic"][name]["through"] = q
    out["prismatic"][name]["offset"] = float(pj.get("offset", 0.0) + np.dot(xy[pj["through"]] - xy[q], nrm))
    return out


# ---------------------------------------------------------------- hostile files

_EXTREMES = [0.0, -0.0, 1e308, -1e308, 1e-308, 5e-324, 1e300, 1e-300, 1e154, float("nan"), float("inf"),
             -float("inf"), 2**63 - 1, -(2**63)]
_WRONG = ["x", "", True, [], [1.0], [1.0, 2.0, 3.0], {}, {"a": 1}, 3, "30deg", "1e999deg"]


def _leaves(obj, path=()):
    """Every (container, key) pair in a nested dict/list structure."""
    items = obj.items() if isinstance(obj, dict) else enumerate(obj)
    for k, v in list(items):
        yield obj, k, path + (k,)
        if isinstance(v, (dict, list)):
            yield from _leaves(v, path + (k,))


def _scaled(obj, s):
    if isinstance(obj, float):
        return obj * s
    if isinstance(obj, list):
        return [_scaled(x, s) for x in obj]
    if isinstance(obj, dict):
        return {k: _scaled(v, s) for k, v in obj.items()}
    return obj


def mutate(desc: dict, rng: np.random.Generator) -> bytes:
    """A hostile variant of a valid description, as file bytes: a deleted key, a wrong
    type, an extreme or non-finite number, deep nesting, a geometry scaled to the ends of
    float64, or damaged text (truncated, a byte flipped or inserted)."""
    d = copy.deepcopy(desc)
    kind = int(rng.integers(8))
    slots = list(_leaves(d))
    parent, key, _ = slots[rng.integers(len(slots))]
    if kind == 0:
        del parent[key]
    elif kind == 1:
        parent[key] = copy.deepcopy(_WRONG[rng.integers(len(_WRONG))])
    elif kind == 2:
        nums = [(p, k) for p, k, _ in slots if isinstance(p[k], float)]
        p, k = nums[rng.integers(len(nums))]
        p[k] = _EXTREMES[rng.integers(len(_EXTREMES))]
    elif kind == 3:
        depth = int(rng.choice([50, 1000, 5000, 50000]))
        if rng.random() < 0.5:
            return (to_toml(d) + "\nx = " + "[" * depth + "]" * depth + "\n").encode()
        return (to_toml(d) + "\n[" + ".".join(["t"] * depth) + "]\n").encode()
    elif kind == 4:
        key2 = rng.choice(["points", "links", "prismatic"]) if "prismatic" in d else rng.choice(["points", "links"])
        s = float(rng.choice([1e-300, 1e300, 1e-200, 1e200, 1e-160, 1e160]))
        if key2 != "prismatic":
            d[key2] = _scaled(d[key2], s)
        if key2 != "links":  # with the points: the whole geometry rescaled, still consistent
            for name, spec in d.get("prismatic", {}).items():
                spec["offset"] = float(spec.get("offset", 0.0)) * s
            if key2 == "points":
                for spec in d["links"].values():
                    for k in ("length", "shape"):
                        if k in spec:
                            spec[k] = _scaled(spec[k], s)
    text = to_toml(d).encode()
    if kind == 5 and text:
        return text[: int(rng.integers(len(text)))]
    if kind == 6 and text:
        i = int(rng.integers(len(text)))
        return text[:i] + bytes([int(rng.integers(256))]) + text[i + 1:]
    if kind == 7 and text:
        i = int(rng.integers(len(text)))
        return text[:i] + bytes(rng.integers(0, 256, int(rng.integers(1, 8))).astype(np.uint8)) + text[i:]
    return text

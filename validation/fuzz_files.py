"""Mutate the bundled descriptions at random and check that every mutant either loads and
solves or fails with a LinkgenError (a DescriptionError naming the file when loading fails):
never another exception, never a NaN in the results.

    .venv/bin/python validation/fuzz_files.py [COUNT] [SEED]
"""

from __future__ import annotations

import re
import sys
import tempfile
import traceback
from collections import Counter
from pathlib import Path

import numpy as np

from linkgen import DescriptionError, LinkgenError, load, solve
from linkgen.families.planar.kinetostatics import forces
from linkgen.families.cam.kinetics import state as cam_state
from linkgen.families.spatial.forces import forces as spatial_forces
from linkgen.families.spatial.kinematics import solve as spatial_solve
from linkgen.pipeline.registry import family_of

MODELS = sorted((Path(__file__).resolve().parent.parent / "models").glob("*.toml"))
_NUMBER = re.compile(rb"-?\d+\.?\d*(?:e-?\d+)?")
EXTREMES = [b"1e308", b"-1e308", b"1e-320", b"0", b"-0.0", b"nan", b"inf", b"-inf", b"1e13", b"1e-91",
            b"9" * 30, b"1e31", b"1e-16", b'"30deg"', b'"1e400deg"', b"[]", b"{}", b'"x"', b"true"]
ALPHABET = b"[]{}=,.\"'#\n -+0123456789abcdefxyz_\xff\xfe\x00\xef\xbb\xbf"


def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    for _ in range(int(rng.integers(1, 4))):
        kind = int(rng.integers(0, 6))
        n = len(data)
        i, j = sorted(int(x) for x in rng.integers(0, max(n, 1), 2))
        if kind == 0:  # a number replaced by an extreme or ill-typed value
            nums = list(_NUMBER.finditer(data))
            if nums:
                m = nums[int(rng.integers(0, len(nums)))]
                data = data[:m.start()] + EXTREMES[int(rng.integers(0, len(EXTREMES)))] + data[m.end():]
        elif kind == 1:  # random bytes inserted
            k = int(rng.integers(1, 8))
            data = data[:i] + bytes(ALPHABET[int(x)] for x in rng.integers(0, len(ALPHABET), k)) + data[i:]
        elif kind == 2:  # a span deleted
            data = data[:i] + data[j:]
        elif kind == 3:  # a span duplicated
            data = data[:j] + data[i:j] + data[j:]
        elif kind == 4:  # two lines swapped
            lines = data.split(b"\n")
            a, b = (int(x) for x in rng.integers(0, len(lines), 2))
            lines[a], lines[b] = lines[b], lines[a]
            data = b"\n".join(lines)
        else:  # one byte flipped
            if n:
                data = data[:i] + bytes([int(rng.integers(0, 256))]) + data[i + 1:]
    return data


def check(path: Path) -> str:
    """The outcome class of one file; raises AssertionError for a wrong kind of failure."""
    try:
        mech = load(path)
    except DescriptionError as exc:
        assert str(exc).startswith(f"{path}: "), f"message does not name the file: {exc}"
        return "DescriptionError on load"
    return CHECKS[family_of(mech).name](mech)


def _check_planar(mech) -> str:
    """A planar linkage over its drive range: finite forces, or a LinkgenError."""
    phi = np.linspace(mech.drive.start, mech.drive.stop, 16)
    try:
        f = forces(mech, phi, mech.drive.omega, mech.drive.epsilon)
    except LinkgenError as exc:
        return type(exc).__name__ + " on solve"
    for name, v in [("balancing_torque", f.balancing_torque), *f.reactions.items()]:
        assert np.all(np.isfinite(v)), f"non-finite {name}"
    solve(mech, phi)
    return "solved"


def _check_cam(cm) -> str:
    """A stand-alone cam over a whole turn: finite follower motion and forces, or a LinkgenError."""
    theta = np.linspace(0.0, 2 * np.pi, 16)
    try:
        st = cam_state(cm, theta)
    except LinkgenError as exc:
        return type(exc).__name__ + " on solve"
    for name in ("displacement", "velocity", "acceleration", "contact_force", "cam_torque"):
        assert np.all(np.isfinite(getattr(st, name))), f"non-finite {name}"
    return "solved"


def _check_spatial(mech) -> str:
    """A spatial four-bar over a whole turn of its crank: finite motion and forces, or a LinkgenError."""
    phi = np.linspace(0.0, 2 * np.pi, 16)
    try:
        motion = spatial_solve(mech, phi)
        f = spatial_forces(mech, phi, motion=motion)
    except LinkgenError as exc:
        return type(exc).__name__ + " on solve"
    assert np.all(np.isfinite(f.balancing_torque)), "non-finite balancing_torque"
    for name, r in f.reactions.items():
        assert np.all(np.isfinite(r.force)) and np.all(np.isfinite(r.moment)), f"non-finite {name}"
    return "solved"


# The check of each family (by the registry's name for it).
CHECKS = {"planar": _check_planar, "cam": _check_cam, "spatial": _check_spatial}


def main(count: int = 2000, seed: int = 1) -> int:
    rng = np.random.default_rng(seed)
    originals = [p.read_bytes() for p in MODELS]
    outcomes: Counter[str] = Counter()
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "mutant.toml"
        for k in range(count):
            data = mutate(originals[k % len(originals)], rng)
            path.write_bytes(data)
            try:
                outcomes[check(path)] += 1
            except Exception as exc:  # the point of the run: anything else is a finding
                outcomes["FAILED: " + type(exc).__name__] += 1
                failures.append((k, data, "".join(traceback.format_exception_only(exc)).strip()))
    for kind, n in sorted(outcomes.items()):
        print(f"{n:6d}  {kind}")
    for k, data, msg in failures[:10]:
        print(f"--- mutant {k}: {msg[:300]}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(*(int(a) for a in sys.argv[1:3])))

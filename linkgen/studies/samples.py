"""The variants of a study: a full grid over the varied fields (the last field varying
fastest) or a Latin-hypercube sample of N variants over their ranges, seeded (scipy's
``qmc.LatinHypercube``: the same seed gives the same variants on every machine)."""

from __future__ import annotations

import numpy as np

from linkgen.errors import ArgumentError
from linkgen.studies.fields import Field

# The most variants one study takes (the table and its chunks stay within a few hundred MB).
MAX_VARIANTS = 10_000_000


def grid(fields: tuple[Field, ...]) -> np.ndarray:
    """Every combination of the fields' values, shape (Π N_i, n_fields) [SI]."""
    total = int(np.prod([f.count for f in fields], dtype=np.int64))
    if total > MAX_VARIANTS:
        raise ArgumentError(f"--vary: the grid has {total} variants, more than {MAX_VARIANTS}")
    axes = [np.linspace(f.start, f.stop, f.count) for f in fields]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=1)


def latin_hypercube(fields: tuple[Field, ...], n: int, seed: int) -> np.ndarray:
    """``n`` variants, one in each of n equal slices of every field's range, shape (n, n_fields)."""
    from scipy.stats import qmc

    if not 1 <= n <= MAX_VARIANTS:
        raise ArgumentError(f"--lhs: expected a number of variants from 1 to {MAX_VARIANTS}, got {n}")
    unit = qmc.LatinHypercube(d=len(fields), seed=np.random.default_rng(seed)).random(n)
    lo = np.array([f.start for f in fields])
    hi = np.array([f.stop for f in fields])
    return lo + unit * (hi - lo)


__all__ = ["MAX_VARIANTS", "grid", "latin_hypercube"]

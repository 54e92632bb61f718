"""Running a vectorised solver over a long array of crank angles in cache-sized blocks.

A solve over n angles makes a few hundred temporaries of n or 2n floats. Over 10^6 angles
each one is 8-16 MB: every operation then streams from main memory and every temporary is
fresh pages from the kernel. In blocks of ``BLOCK`` angles the temporaries stay in the CPU's
cache and are recycled by the allocator; only the results are written to full-length arrays.
NumPy releases the GIL inside its loops, so blocks also spread over threads.

Results are trees of ``Vec``, ``Scalar``, ``LinkPose``, dicts, tuples and arrays whose first
axis is the angle; arrays that are constant along φ (zero-stride views) stay views.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable

import numpy as np

from linkgen.families.planar.geometry import LinkPose
from linkgen.families.planar.primitives import Scalar, Vec, constant_along

# Angles per block. Measured with validation/bench_kinematics.py's job (four-bar, 10^6 angles,
# solve_motion), best of 5, ms, on this machine's 2 cores (1 MiB L2 each, 32 MiB L3 shared):
#   block      4096  8192  16384  32768  65536  131072  262144
#   1 thread    193   146    126    123    124     135     145
#   2 threads   263   160    110    100     86      88     156
# Small blocks lose to per-block Python overhead and, on two threads, to handing the GIL back
# and forth between NumPy calls. Large blocks grow each thread's heap of temporaries (about
# 40 arrays of a block's size), which a fresh process pays for in page faults: first call in
# a fresh process after 10 s idle, 16384 → 0.31-0.39 s, 32768 → 0.40-0.43 s, 65536 → 0.52 s
# (peak memory 201, 220, 258 MB). 32768 keeps both the warm time and the cold one in target.
BLOCK = 32768


# glibc gives freed memory at the top of its heap back to the kernel once it passes a trim
# threshold; that threshold starts at 256 KB and follows twice the size of the largest block
# freed so far, up to 64 MB (mallopt(3), "dynamic mmap threshold"). Until a process has freed
# something large, every block's temporaries come back as fresh pages. Measured: circle_circle
# over 16384 angles, 110 ns/angle so and 27 ns/angle after one large free; a fresh process's
# solve_motion over 10^6 angles, 55k page faults and 0.26-0.30 s so, 22.6k and 0.21-0.23 s after.
# ``in_blocks`` therefore frees one untouched 30 MB allocation first, once per process.
_WARM_ALLOCATOR_BYTES = 30 * 2**20
_allocator_warmed = False


def _warm_allocator() -> None:
    global _allocator_warmed
    if not _allocator_warmed:
        np.empty(_WARM_ALLOCATOR_BYTES, dtype=np.uint8)  # mapped, never touched, freed at once
        _allocator_warmed = True


def default_threads() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def leaves(tree: Any, out: list[np.ndarray] | None = None, seen: set[int] | None = None) -> list[np.ndarray]:
    """The per-angle arrays of ``tree`` in a fixed order, each shared object (array or not) once."""
    out = [] if out is None else out
    seen = set() if seen is None else seen
    if id(tree) in seen:
        return out
    seen.add(id(tree))
    if isinstance(tree, np.ndarray):
        out.append(tree)
    elif isinstance(tree, (Vec, Scalar)):
        for a in (tree.p if isinstance(tree, Vec) else tree.v, tree.d1, tree.d2, tree.d3):
            leaves(a, out, seen)
    elif isinstance(tree, LinkPose):
        leaves(tree.angle, out, seen)
        for _, vec in tree.known:
            leaves(vec, out, seen)
    elif isinstance(tree, dict):
        for v in tree.values():
            leaves(v, out, seen)
    elif isinstance(tree, (tuple, list)):
        for v in tree:
            leaves(v, out, seen)
    else:
        raise TypeError(f"cannot split a {type(tree).__name__} into per-angle arrays")
    return out


def rebuild(tree: Any, new: Callable[[np.ndarray], np.ndarray], memo: dict[int, Any] | None = None) -> Any:
    """``tree`` with every per-angle array replaced by ``new(array)``, sharing preserved.
    Cached cos/sin pairs of angles are dropped (recomputed on demand)."""
    memo = {} if memo is None else memo
    key = id(tree)
    if key in memo:
        return memo[key]
    if isinstance(tree, np.ndarray):
        out = new(tree)
    elif isinstance(tree, Vec):
        out = Vec(new(tree.p), new(tree.d1), new(tree.d2), new(tree.d3))
    elif isinstance(tree, Scalar):
        out = Scalar(new(tree.v), new(tree.d1), new(tree.d2), new(tree.d3))
    elif isinstance(tree, LinkPose):
        out = LinkPose(rebuild(tree.angle, new, memo), tuple((loc, rebuild(v, new, memo)) for loc, v in tree.known))
    elif isinstance(tree, dict):
        out = {k: rebuild(v, new, memo) for k, v in tree.items()}
    elif isinstance(tree, (tuple, list)):
        out = type(tree)(rebuild(v, new, memo) for v in tree)
    else:
        raise TypeError(f"cannot split a {type(tree).__name__} into per-angle arrays")
    memo[key] = out
    return out


def carve(n: int, like: list[np.ndarray]) -> list[np.ndarray]:
    """New arrays of n rows, shaped, typed and ordered like each of ``like``, all views into
    one allocation. One large allocation is mapped with huge pages where the kernel allows
    (NumPy advises it for arrays over 4 MB): measured here, 80 MB as one array took 625 page
    faults and 18 ms to fill, as ten 8 MB arrays 5232 faults and 145 ms. The memory is
    released when the last of the views is."""
    sizes = [-(-n * int(np.prod(a.shape[1:], dtype=int)) * a.itemsize // 64) * 64 for a in like]
    buf = np.empty(sum(sizes), dtype=np.uint8)
    out, at = [], 0
    for a, size in zip(like, sizes):
        count = n * int(np.prod(a.shape[1:], dtype=int))
        flat = buf[at:at + count * a.itemsize].view(a.dtype)
        order = "F" if a.ndim > 1 and a.flags.f_contiguous and not a.flags.c_contiguous else "C"
        out.append(flat.reshape((n, *a.shape[1:]), order=order))
        at += size
    return out


def in_blocks(solve: Callable[[slice], tuple[Any, Any]], n: int, threads: int | None = None,
              block: int | None = None) -> tuple[Any, list[Any]]:
    """Run ``solve(rows) -> (tree, info)`` over the rows 0..n-1, ``block`` rows at a time.

    Returns the trees joined along the first axis and the list of each block's ``info``
    (small per-block findings, e.g. flags), in row order. With n ≤ ``block`` this is just
    ``solve(slice(0, n))``.
    """
    block = BLOCK if block is None else block
    if n <= block:
        tree, info = solve(slice(0, n))
        return tree, [info]
    _warm_allocator()
    first, info0 = solve(slice(0, block))
    srcs = leaves(first)
    keep = [not constant_along(a) for a in srcs]
    fresh = iter(carve(n, [a for a, k in zip(srcs, keep) if k]))
    full = {id(a): next(fresh) if k else np.broadcast_to(a[0], (n, *a.shape[1:])) for a, k in zip(srcs, keep)}
    out = rebuild(first, lambda a: full[id(a)])
    dsts = leaves(out)

    def write(tree: Any, rows: slice) -> None:
        srcs = leaves(tree)
        if len(srcs) != len(dsts):
            raise RuntimeError("a block's result has a different structure from the first block's")
        for dst, src, k in zip(dsts, srcs, keep):
            if k:
                dst[rows] = src

    def run(start: int) -> Any:
        rows = slice(start, min(start + block, n))
        tree, info = solve(rows)
        write(tree, rows)
        return info

    write(first, slice(0, block))
    rest = range(block, n, block)
    threads = default_threads() if threads is None else threads
    if threads > 1:
        with ThreadPoolExecutor(min(threads, len(rest))) as pool:
            infos = list(pool.map(run, rest))
    else:
        infos = [run(s) for s in rest]
    return out, [info0, *infos]

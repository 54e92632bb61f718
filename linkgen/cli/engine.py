"""``linkgen validate --engine mjwarp``: a planar linkage's MuJoCo run in float32 through MuJoCo
Warp against float64 MuJoCo and the closed form (``mujoco.float32``), one line or one JSON entry
per file."""

from __future__ import annotations

import json
import sys
from pathlib import Path


def _one(path: Path, progress: bool) -> dict:
    from linkgen.cli.files import message_for
    from linkgen.errors import ArgumentError, LinkgenError
    from linkgen.pipeline.registry import family_of, load

    try:
        desc = load(path)
        family = family_of(desc)
        if family.name != "planar":
            raise ArgumentError(f"--engine mjwarp runs planar linkages (their loops are what float32 puts at risk); "
                                f"this is a {family.title}: validate it without --engine")
        from linkgen.families.planar.assembly import assemble
        from linkgen.mujoco.float32 import float32_check

        def report(fraction: float, seconds: float) -> None:
            print(f"{desc.name}: float32 run {fraction:6.1%} ({seconds:.1f} s)", file=sys.stderr, flush=True)

        check = float32_check(assemble(desc), progress=report if progress else None)
    except LinkgenError as exc:
        return {"model": path.stem, "file": str(path), "ok": False, "error": message_for(path, exc)}
    return {"file": str(path), "family": "planar"} | check.to_json() | {"line": f"{check.name:<22} {check.summary()}"}


def validate_float32(args, paths: list[Path]) -> int:
    """The float32 validation of ``paths`` (``args.model``'s files), printed; 0 when every file
    holds its float32 tolerances, 1 when one misses, 2 when one could not be run."""
    from linkgen.cli.common import OptionError

    if args.out is not None:
        raise OptionError("-o/--out: --engine mjwarp prints its comparison (add --json for JSON); it writes no report")
    results = []
    for path in paths:
        r = _one(path, progress=not args.json)
        results.append(r)
        if not args.json:
            print(r["line"] if "line" in r else f"linkgen: error: {r['error']}", file=sys.stdout if "line" in r
                  else sys.stderr, flush=True)
    if args.json:
        print(json.dumps(results[0] if len(results) == 1 else results, indent=2, allow_nan=False))
    if any("error" in r for r in results):
        return 2
    return 0 if all(r["ok"] for r in results) else 1


__all__ = ["validate_float32"]

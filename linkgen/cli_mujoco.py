"""CLI commands that need MuJoCo: build, simulate, validate."""

from __future__ import annotations

import json
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from .errors import DescriptionError, LinkgenError

REPORT_DIR = Path("validation/report")


def _models(path: Path) -> list[Path]:
    """The description files a command runs on: ``path`` itself, or a folder's ``*.toml`` in
    name order."""
    if path.is_dir():
        found = sorted(p for p in path.glob("*.toml") if not p.is_dir())
        if not found:
            raise DescriptionError("", "no *.toml descriptions in this folder", str(path))
        return found
    return [path]


def _build_one(path: Path, out: Path) -> Path:
    """Compile ``path``'s MJCF in MuJoCo and write it atomically to ``out``."""
    import mujoco

    from .assembly import assemble
    from .files import atomic_write_text
    from .load import load
    from .mjcf import write_mjcf

    xml = write_mjcf(assemble(load(path)))
    try:
        mujoco.MjModel.from_xml_string(xml)  # always compile what we write
    except ValueError as exc:
        raise LinkgenError(f"MuJoCo rejects the generated model: {str(exc).strip()}") from None
    atomic_write_text(out, xml)
    print(f"wrote {out}", file=sys.stderr)
    return out


def cmd_build(args) -> int:
    """One file (to -o or next to it), or every *.toml of a folder next to itself: a bad file
    is reported as ``FILE: message`` and the others are still built; status 2 if any failed."""
    from .cli import OptionError
    from .files import run_each

    if args.output is not None and args.model.is_dir():
        raise OptionError(f"-o/--output writes one model, but {str(args.model)!r} is a folder (a folder's models "
                          "are written next to their descriptions)")
    paths = _models(args.model)
    if len(paths) == 1 and not args.model.is_dir():
        _build_one(paths[0], args.output or paths[0].with_suffix(".xml"))
        return 0
    outcomes = run_each(paths, lambda p: _build_one(p, p.with_suffix(".xml")))
    bad = [o for o in outcomes if not o.ok]
    if bad:
        print(f"linkgen: {len(bad)} of {len(outcomes)} descriptions failed", file=sys.stderr)
    return 2 if bad else 0


def cmd_simulate(args) -> int:
    from .assembly import assemble
    from .load import load
    from .simulate import simulate

    asm = assemble(load(args.model))
    t = time.perf_counter()
    run = simulate(asm, revolutions=args.revolutions, omega=args.omega, epsilon=args.epsilon, timestep=args.timestep)
    elapsed = time.perf_counter() - t
    s = run.samples
    arrays = {"time": run.time, "qpos": run.qpos, "qvel": run.qvel, "constraint_violation": run.violation,
              "sample_time": s.time, "phi": s.crank[0], "omega": s.crank[1], "epsilon": s.crank[2],
              "drive_torque": s.drive_torque}
    for p, (x, v, a) in s.points.items():
        arrays |= {f"points.{p}.position": x, f"points.{p}.velocity": v, f"points.{p}.acceleration": a}
    for l, (x, v, a) in s.links.items():
        arrays |= {f"links.{l}.angle": x, f"links.{l}.angular_velocity": v, f"links.{l}.angular_acceleration": a}
    for n, (x, v, a) in s.sliders.items():
        arrays |= {f"sliders.{n}.displacement": x, f"sliders.{n}.velocity": v, f"sliders.{n}.acceleration": a}
    f = s.forces  # forward route, linkgen.kinetostatics' sign conventions
    arrays |= {f"reactions.{k}.force": v for k, v in f.reactions.items()}
    arrays |= {f"prismatic.{k}.normal_force": v for k, v in f.normal_force.items()}
    arrays |= {f"prismatic.{k}.moment": v for k, v in f.moment.items()}
    arrays["reduced_inertia"] = s.reduced_inertia
    if args.out is None:
        pass
    elif args.out.suffix == ".npz":
        np.savez(args.out, **arrays)
    elif args.out.suffix == ".csv":
        cols = [k for k, v in arrays.items() if k.startswith(("sample_time", "phi", "omega", "epsilon", "drive",
                                                              "points.", "links.", "sliders.", "reactions.",
                                                              "prismatic.", "reduced_"))]
        header, data = [], []
        for k in cols:
            v = arrays[k]
            if v.ndim == 2:
                header += [f"{k}.x", f"{k}.y"]
                data += [v[:, 0], v[:, 1]]
            else:
                header.append(k)
                data.append(v)
        np.savetxt(args.out, np.column_stack(data), delimiter=",", header=",".join(header), comments="", fmt="%.17g")
    else:
        raise DescriptionError("--out", f"must end in .npz or .csv, got {str(args.out)!r}")
    print(f"{asm.mechanism.name}: {len(run.time)} steps in {elapsed:.3f} s ({len(run.time) / elapsed:,.0f} steps/s); "
          f"max constraint violation {run.violation.max():.3g} m" + (f"; wrote {args.out}" if args.out else ""))
    return 0


def _validate_one(path: Path, timestep: float):
    from .assembly import assemble
    from .compare import compare
    from .load import load
    from .simulate import simulate

    asm = assemble(load(path))
    t = time.perf_counter()
    run = simulate(asm, timestep=timestep)
    return compare(asm, run), time.perf_counter() - t


def cmd_validate(args) -> int:
    from .report import write_report

    paths = _models(args.model)
    with ThreadPoolExecutor(max_workers=2) as pool:  # two cores: rollout releases the GIL
        results = list(pool.map(lambda p: _validate_one(p, args.timestep), paths))
    comparisons = [c for c, _ in results]
    if args.json:
        payload = [c.to_json() for c in comparisons]
        print(json.dumps(payload[0] if len(payload) == 1 else payload, indent=2))
    else:
        for c, elapsed in results:
            worst = max((k for k in c.quantities if k != "constraint_violation"),
                        key=lambda k: c.quantities[k].relative_error)
            print(f"{c.model:<22} {'ok  ' if c.ok else 'FAIL'} worst {worst} {c.quantities[worst].relative_error:.2e}"
                  f", constraint violation {c.quantities['constraint_violation'].max_abs_error:.2e} m, {elapsed:.2f} s")
    if args.model.is_dir():
        path = write_report(comparisons, {c.model: t for c, t in results}, args.report)
        print(f"report: {path}", file=sys.stderr)
    return 0 if all(c.ok for c in comparisons) else 1


def add_commands(sub) -> None:
    from .cli import _float_arg
    from .mjcf import TIMESTEP

    b = sub.add_parser("build", help="write the MJCF of a model, or of every model in a folder")
    b.add_argument("model", type=Path)
    b.add_argument("-o", "--output", type=Path, help="output file (one model file only, not a folder)")
    b.set_defaults(func=cmd_build)

    s = sub.add_parser("simulate", help="run the driven crank in MuJoCo")
    s.add_argument("model", type=Path)
    s.add_argument("--revolutions", type=_float_arg, default=1.0)
    s.add_argument("--omega", type=_float_arg)
    s.add_argument("--epsilon", type=_float_arg)
    s.add_argument("--timestep", type=_float_arg, default=TIMESTEP)
    s.add_argument("--out", type=Path, help="FILE.npz or FILE.csv")
    s.set_defaults(func=cmd_simulate)

    v = sub.add_parser("validate", help="closed form against MuJoCo; a folder also writes the report")
    v.add_argument("model", type=Path)
    v.add_argument("--json", action="store_true")
    v.add_argument("--timestep", type=_float_arg, default=TIMESTEP)
    v.add_argument("--report", type=Path, default=REPORT_DIR)
    v.set_defaults(func=cmd_validate)


__all__ = ["add_commands", "LinkgenError"]

"""``linkgen assemble``: the exactly assembled sketch, printed or written back into the file."""

from __future__ import annotations

import math
from pathlib import Path


def cmd_assemble(args) -> int:
    from linkgen.cli.files import atomic_write_text
    from linkgen.pipeline.registry import load
    from linkgen.families.planar.sketch import exact_sketch

    from linkgen.model.arguments import input_kind

    mech = load(args.model)
    sk = exact_sketch(mech, input_kind(args.angle, mech.slide_drive, "--angle"))
    at = f"s = {sk.phi:.9g} m" if mech.slide_drive else f"φ = {math.degrees(sk.phi):.9g}°"  # a prismatic drive's stroke
    if args.write:
        import tomlkit

        doc = tomlkit.parse(Path(args.model).read_text(encoding="utf-8-sig"))
        table = doc["points"]
        for name, (x, y) in sk.points.items():
            if sk.moved[name] > 0.0:
                table[name] = [x, y]
        # in place: a symlinked description is updated at its target, its mode kept
        atomic_write_text(Path(args.model), tomlkit.dumps(doc), follow_symlink=True)
        load(args.model)  # the written file loads, its sketch now within the tolerance
        worst = max(sk.moved.values())
        print(f"wrote the assembled sketch at {at} into {args.model} "
              f"(points moved by up to {worst:.6g} m)")
        return 0
    print(f"# {mech.name}: assembled at {at} from the link lengths")
    print("[points]")
    width = max(len(n) for n in sk.points)
    for name, (x, y) in sk.points.items():
        note = f"  # moved {sk.moved[name]:.3g} m" if sk.moved[name] > 0.0 else ""
        print(f"{name:<{width}} = [{x!r}, {y!r}]{note}")
    return 0


def add_command(sub) -> None:
    from linkgen.cli.common import _angle_arg

    a = sub.add_parser("assemble", help="place the sketch's points exactly from the link lengths (the rough "
                                        "sketch only chooses each group's assembly mode)")
    a.add_argument("model", type=Path, help="description file (.toml)")
    a.add_argument("--angle", type=_angle_arg, help="crank angle with its unit, e.g. 30deg (default: the sketch's)")
    a.add_argument("--write", action="store_true", help="write the points back into the file, keeping its "
                                                        "comments and layout (default: print them)")
    a.set_defaults(func=cmd_assemble)


__all__ = ["add_command", "cmd_assemble"]

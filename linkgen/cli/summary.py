"""``linkgen analyze MODEL --summary``: the design summary (``planar.summary``) as text or JSON."""

from __future__ import annotations

import math

from linkgen.cli.common import OptionError, check_finite, drive_rates, print_json


def _deg(x: float) -> str:
    return f"{math.degrees(x):.6g}°"


def cmd_summary(args) -> int:
    from linkgen.pipeline.registry import load
    from linkgen.families.planar.assembly import assemble
    from linkgen.families.planar.summary import summarize

    used = [o for o, v in (("--angle", args.angle), ("--samples", args.samples), ("--csv", args.csv),
                           ("--transfer", args.transfer or None), ("--keep-singular", args.keep_singular or None))
            if v is not None]
    if used:
        raise OptionError(f"--summary covers the whole drive range; it cannot be combined with {used[0]}")
    mech = load(args.model)
    omega, epsilon = drive_rates(mech, args)
    s = summarize(assemble(mech), omega, epsilon)
    result = s.to_dict()
    check_finite(result)
    if args.json:
        print_json(result)
        return 0
    d = mech.drive
    print(f"{mech.name}: design summary over φ = {_deg(d.start)}..{_deg(d.stop)} at ω = {omega:g} rad/s, "
          f"ε = {epsilon:g} rad/s²")
    for o in s.outputs:
        if o.travel is None:
            print(f"  {o.kind} {o.name}: turns fully round (no swing, no limit positions)")
            continue
        travel = f"stroke {o.travel:.6g} m" if o.kind == "slider" else \
            f"swing {_deg(o.travel)} ({o.travel:.6g} rad)"
        print(f"  {o.kind} {o.name}: {travel}")
        for lim in o.limits:
            value = f"{lim.value:.6g} m" if o.kind == "slider" else f"{_deg(lim.value)}"
            print(f"    limit position ({lim.kind}) at φ = {_deg(lim.phi)}: {value}")
        if not o.limits:
            print("    no limit position inside the range (its extremes are at the range's ends)")
        if o.time_ratio is not None:
            print(f"    min→max over {_deg(o.strokes[0])} of crank turn, max→min over {_deg(o.strokes[1])}: "
                  f"time ratio K = {o.time_ratio:.6g} (at constant ω)")
    for t in s.transmission:
        print(f"  transmission angle of {t.group}: least {_deg(t.minimum)} at φ = {_deg(t.at)}")
    if s.torque is not None:
        print(f"  peak balancing torque: {s.torque.value:.6g} N·m at φ = {_deg(s.torque.at)}")
        for p in sorted(s.reactions, key=lambda p: -p.value):
            print(f"  peak reaction at {p.name}: {p.value:.6g} N at φ = {_deg(p.at)}")
    else:
        print(f"  {s.forces_note}")
    return 0


__all__ = ["cmd_summary"]

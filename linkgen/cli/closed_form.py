"""``linkgen structure`` and ``linkgen analyze``: the closed form from the command line."""

from __future__ import annotations

import math

import numpy as np

from linkgen.cli.common import (check_crank_options, check_finite, crank_grid, drive_rates, print_json,
                                write_rows)
from linkgen.cli.singular import report_singular
from linkgen.families.planar.checks import mobility_formula
from linkgen.pipeline.registry import load
from linkgen.families.planar.assembly import assemble
from linkgen.families.planar.cam_pair import above_lowest, contact, lift, oscillating
from linkgen.families.planar.kinematics import Kinematics, solve


UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "position": "m", "velocity": "m/s",
         "acceleration": "m/s²", "angle": "rad", "angular_velocity": "rad/s", "angular_acceleration": "rad/s²",
         "jerk": "m/s³", "angular_jerk": "rad/s³", "displacement": "m", "d/dphi": "per rad", "d2/dphi2": "per rad²",
         "d3/dphi3": "per rad³"}

# Names of each kind's value and time derivatives, in the JSON and the CSV columns.
_NAMES = {"points": ("position", "velocity", "acceleration", "jerk"),
          "links": ("angle", "angular_velocity", "angular_acceleration", "angular_jerk"),
          "sliders": ("displacement", "velocity", "acceleration", "jerk")}


def _motion_json(kin: Kinematics, omega: float, epsilon: float, i: int = 0, model: str = "") -> dict:
    """The state at angle ``kin.phi[i]``; jerks take ε constant in time (x‴ω³ + 3x″ωε)."""
    mo = kin.motion(omega, epsilon)
    out = {"model": model, "phi": float(kin.phi[i]), "omega": float(omega), "epsilon": float(epsilon), "units": UNITS}
    for kind in ("points", "links", "sliders"):
        out[kind] = {n: dict(zip(_NAMES[kind], (a[i].tolist() for a in (*t, mo.jerk[kind][n]))))
                     for n, t in getattr(mo, kind).items()}
    if kin.assembly.mechanism.cams:
        out["followers"] = followers_json(kin, omega, epsilon, i)
    return out


def followers_json(kin: Kinematics, omega: float, epsilon: float, i: int = 0) -> dict:
    """Each cam pair's follower: its coordinate from the program's lowest position (rad or m) with
    velocity, acceleration and jerk (ε constant), and the pressure angle [rad]."""
    out = {}
    for cam in kin.assembly.mechanism.cams:
        theta = kin.phi[i:i + 1] - kin.assembly.sketch_phi
        q = above_lowest(cam, theta)[0]
        _, d1, d2, d3 = lift(cam, theta)
        alpha = contact(kin, cam)[2][i]
        out[cam.follower] = {"cam": cam.name, "displacement": float(q), "velocity": float(d1[0] * omega),
                             "acceleration": float(d2[0] * omega**2 + d1[0] * epsilon),
                             "jerk": float(d3[0] * omega**3 + 3 * d2[0] * omega * epsilon),
                             "pressure_angle": float(alpha),
                             "unit": "rad" if oscillating(kin.assembly.mechanism, cam) else "m"}
    return out


def cmd_structure(args) -> int:
    asm = assemble(load(args.model))
    s = asm.structure
    print(f"mechanism: {asm.mechanism.name}")
    p4 = len(asm.mechanism.gears) + len(asm.mechanism.cams)
    print(f"mobility {mobility_formula(s.moving_links, s.lower_pairs, p4)}")
    for g in asm.mechanism.gears:
        print(f"gear pair {g.name!r}: planet {g.planet!r} on the crank, {g.kind} mesh {g.teeth[0]}/{g.teeth[1]} "
              f"teeth, module {g.module:g} m: the planet turns {g.ratio:+g} times the crank")
    for c in asm.mechanism.cams:
        kind = "oscillating about its pivot" if oscillating(asm.mechanism, c) else "translating on its guide"
        print(f"cam pair {c.name!r}: the cam on the crank drives the follower {c.follower!r} ({kind}) through "
              f"its roller at {c.roller!r} (radius {c.roller_radius:g} m), a higher pair")
    print(f"input link: I(0,1) crank {s.crank!r}, driven at {s.drive.name!r}")
    for g, m in zip(s.groups, asm.branches):
        pairs = ", ".join(f"{p.kind} {p.name}" for p in g.pairs)
        print(f"group {g.label}: pairs {pairs}; attached to {list(g.known)}; assembly mode m = {m:+d}")
    print(f"structure formula: {s.formula}")
    for line in turn_lines(asm):
        print(line)
    return 0


def turn_lines(asm) -> list[str]:
    """Whether the crank turns fully and where the chain assembles (``linkgen.model.turn``)."""
    from linkgen.model.turn import EDGE_TOL, degrees_text, drive_range_text
    from linkgen.families.planar.kinematics import planar_turn

    t = planar_turn(asm)
    how = f"scanned every 0.1°, edges bisected to {EDGE_TOL:g} rad"
    if t.full:
        lines = [f"crank: turns fully — the chain assembles at every crank angle ({how})"]
        if not t.regular:
            lines.append(f"regular at crank angles {degrees_text(t.clean)}; dead centres in between")
        return lines
    lines = [f"crank: does not turn fully — the chain assembles at crank angles {degrees_text(t.assembles)} "
             f"and cannot at {degrees_text(t.fails)} ({how}); it rocks between dead centres"]
    d = asm.mechanism.drive
    given = f"the drive's crank-angle range {math.degrees(d.start):.6g}°..{math.degrees(d.stop):.6g}°"
    if any(lo - 1e-12 <= d.start and d.stop <= hi + 1e-12 for lo, hi in _turns(t.clean)):
        lines.append(f"{given} lies where the chain is assembled and regular")
        return lines
    best = t.suggestion()
    if best is not None:
        lines.append(f"{given} leaves where the chain is regular; to run over the widest range where it is, put "
                     f"under [drive]: {drive_range_text(best)}")
    return lines


def _turns(ranges):
    """Each range [rad] and its copies one turn either side."""
    return [(lo + k * 2 * math.pi, hi + k * 2 * math.pi) for lo, hi in ranges for k in (-1, 0, 1)]


def cmd_analyze(args) -> int:
    from linkgen.families.cam.description import is_cam_file

    if is_cam_file(args.model):
        from linkgen.cli.cams import cmd_analyze_cam

        return cmd_analyze_cam(args)
    if args.summary:
        from linkgen.cli.summary import cmd_summary

        return cmd_summary(args)
    check_crank_options(args)
    mech = load(args.model)
    omega, epsilon = drive_rates(mech, args)
    if args.samples is not None or args.csv is not None:
        phi = crank_grid(mech, args.samples or 360)
        kin = solve(mech, phi, on_singular="mark")
        mo = kin.motion(omega, epsilon)
        cols, data = ["phi", "singular"], [phi, kin.singular]
        for kind in ("points", "links", "sliders"):
            for n, arrays in getattr(mo, kind).items():
                for qname, arr in zip(_NAMES[kind], (*arrays, mo.jerk[kind][n])):
                    if arr.ndim == 2:
                        cols += [f"{n}.{qname}.x", f"{n}.{qname}.y"]
                        data += [arr[:, 0], arr[:, 1]]
                    else:
                        cols.append(f"{n}.{qname}")
                        data.append(arr)
        if args.transfer:
            c2, d2 = _transfer_columns(kin)
            cols, data = cols + c2, data + d2
        write_rows(cols, data, args.csv, units=True)
        return report_singular(args.model, kin, args.keep_singular)
    phi = mech.drive.start if args.angle is None else args.angle
    kin = solve(mech, np.array([phi]))
    result = _motion_json(kin, omega, epsilon, model=mech.name)
    if args.transfer:
        result["transfer"] = _transfer_json(kin)
    check_finite(result)
    if args.json:
        print_json(result)
        return 0
    print(f"{mech.name}: φ = {math.degrees(phi):.6g}° ({phi:.9g} rad), ω = {omega:g} rad/s, ε = {epsilon:g} rad/s²")
    _print_state(result)
    if args.transfer:
        _print_transfer(result["transfer"])
    return 0


def _print_state(result: dict) -> None:
    heads = ("x [m]", "y [m]", "vx [m/s]", "vy [m/s]", "ax [m/s²]", "ay [m/s²]", "jx [m/s³]", "jy [m/s³]")
    print(f"{'point':<10}" + "".join(f"{h:>14}" for h in heads))
    for n, q in result["points"].items():
        print(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["position"] + q["velocity"] + q["acceleration"] + q["jerk"]))
    print(f"{'link':<10}{'angle [rad]':>14}{'ω [rad/s]':>14}{'ε [rad/s²]':>14}{'jerk [rad/s³]':>14}")
    for n, q in result["links"].items():
        print(f"{n:<10}" + "".join(f"{q[k]:>14.6g}" for k in _NAMES["links"]))
    if result["sliders"]:
        print(f"{'slider':<10}{'s [m]':>14}{'v [m/s]':>14}{'a [m/s²]':>14}{'j [m/s³]':>14}")
        for n, q in result["sliders"].items():
            print(f"{n:<10}" + "".join(f"{q[k]:>14.6g}" for k in _NAMES["sliders"]))


def _print_transfer(tr: dict) -> None:
    print("transfer functions (derivatives with respect to the crank angle φ)")
    heads = ("dx/dφ [m]", "dy/dφ [m]", "d²x/dφ² [m]", "d²y/dφ² [m]", "d³x/dφ³ [m]", "d³y/dφ³ [m]")
    print(f"{'point':<10}" + "".join(f"{h:>14}" for h in heads))
    for n, q in tr["points"].items():
        print(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["d/dphi"] + q["d2/dphi2"] + q["d3/dphi3"]))
    for kind, unit in (("links", "rad/rad"), ("sliders", "m/rad")):
        if tr[kind]:
            print(f"{kind[:-1]:<10}" + "".join(f"{h + ' [' + unit + ']':>18}" for h in ("d/dφ", "d²/dφ²", "d³/dφ³")))
            for n, q in tr[kind].items():
                print(f"{n:<10}{q['d/dphi']:>18.6g}{q['d2/dphi2']:>18.6g}{q['d3/dphi3']:>18.6g}")


def _transfer_json(kin: Kinematics, i: int = 0) -> dict:
    """First, second and third derivatives with respect to φ: points [m/rad, m/rad², m/rad³],
    link angles [rad/rad, rad/rad², rad/rad³], slider displacements [m/rad, m/rad², m/rad³]."""
    keys = ("d/dphi", "d2/dphi2", "d3/dphi3")

    def row(q) -> dict:
        return dict(zip(keys, (a[i].tolist() for a in (q.d1, q.d2, q.d3))))

    return {"points": {n: row(v) for n, v in kin.points.items()},
            "links": {n: row(lp.angle) for n, lp in kin.links.items()},
            "sliders": {n: row(s) for n, s in kin.sliders.items()}}


def _transfer_columns(kin: Kinematics) -> tuple[list[str], list[np.ndarray]]:
    cols, data = [], []
    n_phi = kin.phi.shape[0]
    for n, v in kin.points.items():
        for tag, arr in (("d1", v.d1), ("d2", v.d2), ("d3", v.d3)):
            arr = np.broadcast_to(arr, (n_phi, 2))
            cols += [f"{n}.position.{tag}.x", f"{n}.position.{tag}.y"]
            data += [arr[:, 0], arr[:, 1]]
    for kind, table in (("angle", {n: lp.angle for n, lp in kin.links.items()}), ("displacement", kin.sliders)):
        for n, s in table.items():
            for tag, arr in (("d1", s.d1), ("d2", s.d2), ("d3", s.d3)):
                cols.append(f"{n}.{kind}.{tag}")
                data.append(np.broadcast_to(arr, (n_phi,)))
    return cols, data


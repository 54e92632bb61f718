"""``linkgen structure`` and ``linkgen analyze``: the closed form from the command line."""

from __future__ import annotations

import math

import numpy as np

from linkgen.cli.common import (check_crank_options, check_finite, crank_grid, drive_rates, print_json,
                                write_rows)
from linkgen.cli.singular import report_singular
from linkgen.model.reader import load
from linkgen.planar.assembly import assemble
from linkgen.planar.kinematics import Kinematics, solve


UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "position": "m", "velocity": "m/s",
         "acceleration": "m/s²", "angle": "rad", "angular_velocity": "rad/s", "angular_acceleration": "rad/s²",
         "displacement": "m", "d/dphi": "per rad", "d2/dphi2": "per rad²"}


def _motion_json(kin: Kinematics, omega: float, epsilon: float, i: int = 0, model: str = "") -> dict:
    mo = kin.motion(omega, epsilon)
    return {
        "model": model, "phi": float(kin.phi[i]), "omega": float(omega), "epsilon": float(epsilon), "units": UNITS,
        "points": {n: {"position": p[i].tolist(), "velocity": v[i].tolist(), "acceleration": a[i].tolist()}
                   for n, (p, v, a) in mo.points.items()},
        "links": {n: {"angle": float(p[i]), "angular_velocity": float(v[i]), "angular_acceleration": float(a[i])}
                  for n, (p, v, a) in mo.links.items()},
        "sliders": {n: {"displacement": float(p[i]), "velocity": float(v[i]), "acceleration": float(a[i])}
                    for n, (p, v, a) in mo.sliders.items()},
    }


def cmd_structure(args) -> int:
    asm = assemble(load(args.model))
    s = asm.structure
    print(f"mechanism: {asm.mechanism.name}")
    p4 = len(asm.mechanism.gears)
    if p4:
        print(f"mobility W = 3·n - 2·p5 - p4 = 3·{s.moving_links} - 2·{s.lower_pairs} - {p4} = {s.mobility}")
        for g in asm.mechanism.gears:
            print(f"gear pair {g.name!r}: planet {g.planet!r} on the crank, {g.kind} mesh {g.teeth[0]}/{g.teeth[1]} "
                  f"teeth, module {g.module:g} m: the planet turns {g.ratio:+g} times the crank")
    else:
        print(f"mobility W = 3·n - 2·p5 = 3·{s.moving_links} - 2·{s.lower_pairs} = {s.mobility}")
    print(f"input link: I(0,1) crank {s.crank!r}, driven at {s.drive.name!r}")
    for g, m in zip(s.groups, asm.branches):
        pairs = ", ".join(f"{p.kind} {p.name}" for p in g.pairs)
        print(f"group {g.label}: pairs {pairs}; attached to {list(g.known)}; assembly mode m = {m:+d}")
    print(f"structure formula: {s.formula}")
    return 0


def cmd_analyze(args) -> int:
    from linkgen.cams.description import is_cam_file

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
        for kind, table in (("point", mo.points), ("link", mo.links), ("slider", mo.sliders)):
            names = ("position", "velocity", "acceleration") if kind == "point" else (
                ("angle", "angular_velocity", "angular_acceleration") if kind == "link"
                else ("displacement", "velocity", "acceleration"))
            for n, arrays in table.items():
                for qname, arr in zip(names, arrays):
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
    print(f"{'point':<10}{'x [m]':>14}{'y [m]':>14}{'vx [m/s]':>14}{'vy [m/s]':>14}{'ax [m/s²]':>14}{'ay [m/s²]':>14}")
    for n, q in result["points"].items():
        print(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["position"] + q["velocity"] + q["acceleration"]))
    print(f"{'link':<10}{'angle [rad]':>14}{'ω [rad/s]':>14}{'ε [rad/s²]':>14}")
    for n, q in result["links"].items():
        print(f"{n:<10}{q['angle']:>14.6g}{q['angular_velocity']:>14.6g}{q['angular_acceleration']:>14.6g}")
    if result["sliders"]:
        print(f"{'slider':<10}{'s [m]':>14}{'v [m/s]':>14}{'a [m/s²]':>14}")
        for n, q in result["sliders"].items():
            print(f"{n:<10}{q['displacement']:>14.6g}{q['velocity']:>14.6g}{q['acceleration']:>14.6g}")
    if args.transfer:
        tr = result["transfer"]
        print("transfer functions (derivatives with respect to the crank angle φ)")
        print(f"{'point':<10}{'dx/dφ [m]':>14}{'dy/dφ [m]':>14}{'d²x/dφ² [m]':>14}{'d²y/dφ² [m]':>14}")
        for n, q in tr["points"].items():
            print(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["d/dphi"] + q["d2/dphi2"]))
        for kind, unit in (("links", "rad/rad"), ("sliders", "m/rad")):
            if tr[kind]:
                print(f"{kind[:-1]:<10}{'d/dφ [' + unit + ']':>18}{'d²/dφ² [' + unit + ']':>18}")
                for n, q in tr[kind].items():
                    print(f"{n:<10}{q['d/dphi']:>18.6g}{q['d2/dphi2']:>18.6g}")
    return 0


def _transfer_json(kin: Kinematics, i: int = 0) -> dict:
    """First and second derivatives with respect to φ: points [m/rad, m/rad²], link angles
    [rad/rad, rad/rad²], slider displacements [m/rad, m/rad²]."""
    return {"points": {n: {"d/dphi": v.d1[i].tolist(), "d2/dphi2": v.d2[i].tolist()} for n, v in kin.points.items()},
            "links": {n: {"d/dphi": float(lp.angle.d1[i]), "d2/dphi2": float(lp.angle.d2[i])}
                      for n, lp in kin.links.items()},
            "sliders": {n: {"d/dphi": float(s.d1[i]), "d2/dphi2": float(s.d2[i])} for n, s in kin.sliders.items()}}


def _transfer_columns(kin: Kinematics) -> tuple[list[str], list[np.ndarray]]:
    cols, data = [], []
    n_phi = kin.phi.shape[0]
    for n, v in kin.points.items():
        for tag, arr in (("d1", v.d1), ("d2", v.d2)):
            arr = np.broadcast_to(arr, (n_phi, 2))
            cols += [f"{n}.position.{tag}.x", f"{n}.position.{tag}.y"]
            data += [arr[:, 0], arr[:, 1]]
    for kind, table in (("angle", {n: lp.angle for n, lp in kin.links.items()}), ("displacement", kin.sliders)):
        for n, s in table.items():
            for tag, arr in (("d1", s.d1), ("d2", s.d2)):
                cols.append(f"{n}.{kind}.{tag}")
                data.append(np.broadcast_to(arr, (n_phi,)))
    return cols, data


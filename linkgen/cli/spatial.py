"""The closed-form commands for a spatial description (``[mechanism] space = "spatial"``):
structure, analyze and forces (build, validate and the pictures go through the family's stages,
``pipeline.spatial_mujoco``); the others say in one line that they are for planar linkages."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.spatial.description import is_spatial_file
from linkgen.cli.common import check_crank_options, check_finite, drive_rates, print_json, write_rows
from linkgen.families.spatial.jets import motion as jet_motion

def route(args):
    """The handler for a spatial model's closed-form command, or None for a planar (or no) model
    (the registry has refused the commands spatial four-bars do not take)."""
    model = getattr(args, "model", None)
    if model is None or not is_spatial_file(model):
        return None
    handlers = {"structure": cmd_structure, "analyze": cmd_analyze, "forces": cmd_forces}
    return handlers.get(args.command)


def _load(path):
    from linkgen.pipeline.registry import load

    return load(path)


def cmd_structure(args) -> int:
    from linkgen.families.spatial.kinematics import assembled_chain

    mech = _load(args.model)
    c = assembled_chain(mech)
    print(f"{mech.name}: spatial {c.kind} four-bar — crank {c.crank!r} (driven at {c.drive!r}), coupler {c.coupler!r}, "
          f"output {c.output!r} ({'sliding on' if c.output_slides else 'turning about'} its pair {c.pair_out!r})")
    spherical = sum(1 for j in mech.joints if j.kind == "spherical")
    lower = len(mech.joints) + len(mech.slides) - spherical
    print(f"mobility by the spatial formula W = 6·n − 5·p5 − 3·p3 = 6·3 − 5·{lower} − 3·{spherical} = {c.mobility_formula}")
    if c.idle:
        print(f"idle freedom: {c.idle} (moves no other point); the mechanism's mobility is {c.mobility}")
    else:
        why = {"spherical": "all axes meet at one point: the spherical family, W = 3·n − 2·p5 = 3·3 − 2·4 = 1",
               "planar": "all axes are parallel: the planar family, W = 3·n − 2·p5 = 3·3 − 2·4 = 1",
               "Bennett": "Bennett's conditions hold (opposite links equal in length and twist, zero offsets, "
                          "a1·sin α2 = a2·sin α1): three constraints repeat, W = 1"}[c.kind]
        print(f"overconstrained: {why}")
    print(f"pairs: " + ", ".join(f"{j.kind} {j.name} [{j.links[0]}, {j.links[1]}]" for j in mech.joints)
          + "".join(f", prismatic {s.name} [{s.guide}, {s.slider}]" for s in mech.slides))
    print(_assembly_range(mech, c))
    return 0


def _status(mech, chain):
    """Crank angles (n,) [rad] → (fails, singular) masks of the spatial chain, for
    ``linkgen.model.turn`` (the scan and bisection planar linkages use as well)."""
    from linkgen.errors import AssemblyError, SingularityError
    from linkgen.families.spatial.kinematics import solve

    def within(phi, ranges):
        return np.any([(phi >= lo) & (phi <= hi) for lo, hi in ranges], axis=0)

    def at(phi):
        fails, singular = np.zeros(phi.shape[0], bool), np.zeros(phi.shape[0], bool)
        try:
            solve(mech, phi, chain)
        except AssemblyError as exc:
            fails = within(phi, exc.ranges)
            if not fails.all():
                try:
                    solve(mech, phi[~fails], chain)
                except SingularityError as sing:
                    singular[~fails] = within(phi[~fails], sing.ranges)
        except SingularityError as exc:
            singular = within(phi, exc.ranges)
        return fails, singular

    return at


def _assembly_range(mech, chain) -> str:
    """Whether the chain assembles over the whole turn of its crank, or where it does not."""
    from linkgen.model.turn import EDGE_TOL, degrees_text, turn_assembly

    t = turn_assembly(_status(mech, chain))
    if not t.full:
        return (f"assembly: not over the whole turn — the coupler cannot reach the output at crank angles "
                f"{degrees_text(t.fails)}; the crank can only rock in the rest ({degrees_text(t.assembles)}; edges "
                f"bisected to {EDGE_TOL:g} rad)")
    if not t.regular:
        return (f"assembly: over the whole turn, regular at crank angles {degrees_text(t.clean)} "
                "(dead centres in between)")
    return "assembly: over the whole turn of the crank (checked every 0.1°)"


def _output_name(chain) -> str:
    return chain.pair_out


def state_json(mech, phi: float, omega: float, epsilon: float, transfer: bool = False) -> dict:
    """Points (position, velocity, acceleration, jerk) and joint variables at one crank state."""
    from linkgen.families.spatial.kinematics import solve

    k = solve(mech, np.array([phi]))
    c = k.chain
    pts = {}
    for name, jet in k.points.items():
        p, v, a, j = jet_motion(jet, omega, epsilon)
        pts[name] = {"position": p[0].tolist(), "velocity": v[0].tolist(), "acceleration": a[0].tolist(),
                     "jerk": j[0].tolist()}
    out_jet = k.output
    x, v, a, j = (float(q[0]) for q in jet_motion(out_jet, omega, epsilon))
    if c.output_slides:
        out = {"displacement": x, "velocity": v, "acceleration": a, "jerk": j}
    else:
        out = {"angle": x, "angular_velocity": v, "angular_acceleration": a, "angular_jerk": j}
    joints = {c.drive: {"angle": phi, "angular_velocity": omega, "angular_acceleration": epsilon, "angular_jerk": 0.0},
              c.pair_out: out}
    result = {"model": mech.name, "kind": c.kind, "phi": phi, "omega": omega, "epsilon": epsilon,
              "units": {"position": "m", "velocity": "m/s", "acceleration": "m/s²", "jerk": "m/s³", "angle": "rad",
                        "angular_velocity": "rad/s", "angular_acceleration": "rad/s²", "angular_jerk": "rad/s³",
                        "displacement": "m"},
              "points": pts, "joints": joints}
    if transfer:
        result["transfer"] = {
            "points": {n: {"d/dphi": jet.d[1][0].tolist(), "d2/dphi2": jet.d[2][0].tolist(),
                           "d3/dphi3": jet.d[3][0].tolist()} for n, jet in k.points.items()},
            "joints": {c.pair_out: {"d/dphi": float(out_jet.d[1][0]), "d2/dphi2": float(out_jet.d[2][0]),
                                    "d3/dphi3": float(out_jet.d[3][0])}}}
    return result


def _summary(args) -> int:
    """`analyze --summary` of a spatial four-bar (linkgen.families.spatial.summary)."""
    from linkgen.families.spatial.summary import summarize

    sm = summarize(_load(args.model))
    if args.json:
        print_json(sm.to_dict())
        return 0
    unit = "m" if sm.unit == "m" else "°"
    show = (lambda v: f"{v:.6g} m") if sm.unit == "m" else (lambda v: f"{math.degrees(v):.6g}°")
    if sm.swing is None:
        print(f"{sm.model}: spatial {sm.kind}, output {sm.output!r} turns fully with the crank (no limit positions)")
    else:
        print(f"{sm.model}: spatial {sm.kind}, output {sm.output!r}: {'stroke' if unit == 'm' else 'swing'} "
              f"{show(sm.swing)}")
    for kind, a, v in sm.limits:
        print(f"  limit position ({kind}) at φ = {math.degrees(a):.6g}°: {show(v)}")
    if sm.time_ratio is not None:
        out, back = (math.degrees(a) for a in sm.strokes)
        print(f"  min→max over {out:.6g}° of crank turn, max→min over {back:.6g}°: time ratio "
              f"K = {sm.time_ratio:.6g} (at constant ω)")
    t, a = sm.peak_torque
    print(f"  peak balancing torque: {t:.6g} N·m at φ = {math.degrees(a):.4g}°")
    for name, (v, a) in sm.peak_pair_forces.items():
        print(f"  peak force at pair {name}: {v:.6g} N at φ = {math.degrees(a):.4g}°")
    if sm.indeterminate:
        print(f"  pair forces: statically indeterminate by {sm.indeterminate}, not summarised")
    return 0


def cmd_analyze(args) -> int:
    from linkgen.families.spatial.kinematics import solve

    if getattr(args, "summary", False):
        return _summary(args)
    check_crank_options(args)
    mech = _load(args.model)
    omega, epsilon = drive_rates(mech, args)
    if args.samples is not None or args.csv is not None:
        phi = np.linspace(0.0, 2 * math.pi, args.samples or 360, endpoint=False)
        k = solve(mech, phi)
        cols, data = ["phi"], [phi]
        for name, jet in k.points.items():
            for q, arr in zip(("position", "velocity", "acceleration", "jerk"), jet_motion(jet, omega, epsilon)):
                for i, axis in enumerate("xyz"):
                    cols.append(f"{name}.{q}.{axis}")
                    data.append(arr[:, i])
            if args.transfer:
                for tag in (1, 2, 3):
                    for i, axis in enumerate("xyz"):
                        cols.append(f"{name}.position.d{tag}.{axis}")
                        data.append(jet.d[tag][:, i])
        names = (("displacement", "velocity", "acceleration", "jerk") if k.chain.output_slides else
                 ("angle", "angular_velocity", "angular_acceleration", "angular_jerk"))
        for q, arr in zip(names, jet_motion(k.output, omega, epsilon)):
            cols.append(f"{k.chain.pair_out}.{q}")
            data.append(arr)
        write_rows(cols, data, args.csv, units=True)
        return 0
    phi = 0.0 if args.angle is None else args.angle
    result = state_json(mech, phi, omega, epsilon, transfer=args.transfer)
    check_finite(result)
    if args.json:
        print_json(result)
        return 0
    print(f"{mech.name} ({result['kind']}): φ = {math.degrees(phi):.6g}° ({phi:.9g} rad), ω = {omega:g} rad/s, "
          f"ε = {epsilon:g} rad/s²")
    head = "".join(f"{h:>13}" for h in ("x [m]", "y [m]", "z [m]", "vx [m/s]", "vy [m/s]", "vz [m/s]", "ax [m/s²]",
                                          "ay [m/s²]", "az [m/s²]", "jx [m/s³]", "jy [m/s³]", "jz [m/s³]"))
    print(f"{'point':<8}{head}")
    for n, q in result["points"].items():
        print(f"{n:<8}" + "".join(f"{x:>13.6g}" for x in q["position"] + q["velocity"] + q["acceleration"] + q["jerk"]))
    for n, q in result["joints"].items():
        print(f"joint {n}: " + ", ".join(f"{k} {v:.9g}" for k, v in q.items()))
    if args.transfer:
        print("transfer functions (derivatives with respect to φ) of the output: "
              + ", ".join(f"{k} {v:.9g}" for k, v in next(iter(result["transfer"]["joints"].values())).items()))
    return 0


def cmd_forces(args) -> int:
    from linkgen.families.spatial.forces import forces

    check_crank_options(args)
    mech = _load(args.model)
    omega, epsilon = drive_rates(mech, args)
    if args.samples is not None or args.csv is not None:
        phi = np.linspace(0.0, 2 * math.pi, args.samples or 360, endpoint=False)
        f = forces(mech, phi, omega, epsilon)
        cols = ["phi", "balancing_torque", "power_balance_torque"]
        data = [phi, f.balancing_torque, f.power_balance_torque]
        for name, r in f.reactions.items():
            for q, arr in (("force", r.force), ("moment", r.moment)):
                for i, axis in enumerate("xyz"):
                    cols.append(f"{name}.{q}.{axis}")
                    data.append(arr[:, i])
        write_rows(cols, data, args.csv, units=True)
        return 0
    phi = 0.0 if args.angle is None else args.angle
    f = forces(mech, np.array([phi]), omega, epsilon)
    result = {"model": mech.name, "phi": phi, "omega": omega, "epsilon": epsilon,
              "units": {"force": "N", "moment": "N·m", "balancing_torque": "N·m"},
              "balancing_torque": float(f.balancing_torque[0]), "statically_indeterminate": f.indeterminate,
              "reactions": {n: {"on": r.on, "by": r.by, "force": r.force[0].tolist(), "moment": r.moment[0].tolist()}
                            for n, r in f.reactions.items()}}
    check_finite(dict(result, power_balance_torque=float(f.power_balance_torque[0])))
    if args.json:
        print_json(result)
        return 0
    print(f"{mech.name}: φ = {math.degrees(phi):.6g}°, ω = {omega:g} rad/s, ε = {epsilon:g} rad/s²: balancing torque "
          f"{result['balancing_torque']:.6g} N·m (power balance: {f.power_balance_torque[0]:.6g} N·m)")
    for n, r in result["reactions"].items():
        print(f"pair {n}: on {r['on']} by {r['by']}: force [{', '.join(f'{x:.6g}' for x in r['force'])}] N, "
              f"moment [{', '.join(f'{x:.6g}' for x in r['moment'])}] N·m")
    if f.indeterminate:
        print(f"statically indeterminate by {f.indeterminate}: the reactions shown are the least-squares (minimum-norm) "
              "ones; the balancing torque is determined")
    return 0


__all__ = ["route", "state_json"]

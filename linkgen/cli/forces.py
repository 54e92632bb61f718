"""``linkgen forces``: closed-form kinetostatics and reduced dynamics from the command line.

Conventions (see ``linkgen.kinetostatics``): ``reactions[J].force`` is the force [N] the
second link of pair J (in the description's order) exerts on the first, world frame;
``prismatic[P].normal_force`` [N] is the guide's force on the slider along the guide's left
normal and ``moment`` [N·m] the couple it carries about the slider's point;
``balancing_torque`` [N·m] is the torque the drive applies to the crank, about +z.
"""

from __future__ import annotations

# The command's --help: the conventions above in plain words.
HELP = ("Closed-form joint reactions, balancing torque and reduced inertia. Conventions: reactions[J].force is the "
        "force [N] the second link of pair J (in the description's order) exerts on the first, in the world frame; "
        "prismatic[P].normal_force [N] is the guide's force on the slider along the guide's left normal, and moment "
        "[N·m] the couple it carries about the slider's point; balancing_torque [N·m] is the torque the drive applies "
        "to the crank, about +z.")

import math

import numpy as np

from linkgen.families.planar.kinetostatics import Forces, forces
from linkgen.pipeline.registry import load


def forces_json(f: Forces, mech, i: int = 0) -> dict:
    """One crank angle's forces as the JSON object ``linkgen forces --json`` prints."""
    first = {r.name: r.links for r in mech.revolutes}
    return {
        "balancing_torque": float(f.balancing_torque[i]),
        "reactions": {k: {"force": v[i].tolist(), "on": first[k][0], "by": first[k][1]} for k, v in f.reactions.items()},
        "prismatic": {k: {"normal_force": float(f.normal_force[k][i]), "moment": float(f.moment[k][i])}
                      for k in f.normal_force},
        "reduced_inertia": float(f.reduced.inertia[i]),
        "reduced_inertia_derivative": float(f.reduced.inertia_derivative[i]),
        "reduced_moment": float(f.reduced.moment[i]),
        **({"tooth": {k: {"force": v[i].tolist(), "on": g}
                      for (k, v), g in zip(f.tooth.items(), (g.planet for g in mech.gears))}} if f.tooth else {}),
        **({"contact": {c.name: {"normal_force": float(f.contact[c.name][i]), "on": c.follower}
                        for c in mech.cams}} if f.contact else {}),
    }


def _columns(f: Forces) -> tuple[list[str], list[np.ndarray]]:
    cols = ["phi", "singular", "balancing_torque", "power_balance_torque", "reduced_inertia",
            "reduced_inertia_derivative", "reduced_moment"]
    data = [f.phi, f.singular, f.balancing_torque, f.power_balance_torque, f.reduced.inertia,
            f.reduced.inertia_derivative, f.reduced.moment]
    for k, v in f.reactions.items():
        cols += [f"{k}.force.x", f"{k}.force.y"]
        data += [v[:, 0], v[:, 1]]
    for k in f.normal_force:
        cols += [f"{k}.normal_force", f"{k}.moment"]
        data += [f.normal_force[k], f.moment[k]]
    for k, v in f.tooth.items():
        cols += [f"{k}.tooth_force.x", f"{k}.tooth_force.y"]
        data += [v[:, 0], v[:, 1]]
    for k, v in f.contact.items():
        cols += [f"{k}.contact_force"]
        data += [v]
    return cols, data


def cmd_forces(args) -> int:
    from linkgen.cli.common import check_crank_options, check_finite, crank_grid, drive_rates, print_json, write_rows
    from linkgen.cli.singular import report_singular
    from linkgen.families.planar.kinematics import solve

    check_crank_options(args)
    mech = load(args.model)
    omega, epsilon = drive_rates(mech, args)
    if args.samples is not None or args.csv is not None:
        phi = crank_grid(mech, args.samples or 360)
        f = forces(mech, phi, omega, epsilon, on_singular="mark")
        write_rows(*_columns(f), args.csv, units=True)
        # which groups: a second kinematic pass, only when some sample is marked
        kin = solve(mech, phi, on_singular="mark") if f.singular.any() else None
        return report_singular(args.model, kin, args.keep_singular)
    phi = mech.drive.start if args.angle is None else args.angle
    f = forces(mech, np.array([phi]), omega, epsilon)
    result = {"model": mech.name, "phi": float(phi), "omega": float(omega), "epsilon": float(epsilon),
              "units": {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "force": "N", "torque": "N·m",
                        "moment": "N·m", "reduced_inertia": "kg·m²", "reduced_inertia_derivative": "kg·m²/rad",
                        "reduced_moment": "N·m"}} | forces_json(f, mech)
    check_finite(dict(result, power_balance_torque=float(f.power_balance_torque[0])))
    if args.json:
        print_json(result)
        return 0
    print(f"{mech.name}: φ = {math.degrees(phi):.6g}°, ω = {omega:g} rad/s, ε = {epsilon:g} rad/s²")
    print(f"balancing torque on the crank: {result['balancing_torque']:.6g} N·m "
          f"(power balance: {f.power_balance_torque[0]:.6g} N·m)")
    print(f"reduced inertia J = {result['reduced_inertia']:.6g} kg·m², dJ/dφ = "
          f"{result['reduced_inertia_derivative']:.6g} kg·m²/rad, reduced moment of loads = "
          f"{result['reduced_moment']:.6g} N·m")
    print(f"{'pair':<18}{'on':>10}{'by':>10}{'Fx [N]':>14}{'Fy [N]':>14}{'|F| [N]':>14}")
    for k, q in result["reactions"].items():
        fx, fy = q["force"]
        print(f"{k:<18}{q['on']:>10}{q['by']:>10}{fx:>14.6g}{fy:>14.6g}{math.hypot(fx, fy):>14.6g}")
    if result["prismatic"]:
        print(f"{'prismatic':<18}{'N [N]':>14}{'M [N·m]':>14}")
        for k, q in result["prismatic"].items():
            print(f"{k:<18}{q['normal_force']:>14.6g}{q['moment']:>14.6g}")
    for k, q in result.get("tooth", {}).items():
        fx, fy = q["force"]
        print(f"tooth force of gear {k!r} on {q['on']!r}: ({fx:.6g}, {fy:.6g}) N, |F| = {math.hypot(fx, fy):.6g} N")
    for k, q in result.get("contact", {}).items():
        n = q["normal_force"]
        print(f"contact force of cam {k!r} on its follower {q['on']!r}: {n:.6g} N along the profile's normal"
              + ("" if n >= 0 else " — negative: the follower would leave the cam here (a stronger spring keeps it on)"))
    return 0


def add_command(sub) -> None:
    from linkgen.cli.common import add_crank_arguments

    f = sub.add_parser("forces", help="joint reactions, balancing torque and reduced inertia (closed form)",
                       description=HELP)
    add_crank_arguments(f, "30deg")
    f.set_defaults(func=cmd_forces)

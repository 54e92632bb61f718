"""Cam mechanisms on the command line: ``analyze`` (one angle, samples or the design summary),
``profile`` (the profile as point coordinates) and ``draw`` for a description with a ``[cam]``
table."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from linkgen.families.cam.summary import cam_summary
from linkgen.errors import DescriptionError
from linkgen.cli.common import OptionError, check_finite, print_json, write_rows

UNITS = {"theta": "rad", "omega": "rad/s", "translating": "m, m/s, m/s², m/s³", "oscillating": "rad, rad/s, rad/s², rad/s³",
         "pressure_angle": "rad", "contact_force": "N", "cam_torque": "N·m"}


def _follower_json(st, i: int) -> dict:
    return {"displacement": float(st.displacement[i]), "velocity": float(st.velocity[i]),
            "acceleration": float(st.acceleration[i]), "jerk": float(st.jerk[i]),
            "pressure_angle": float(st.pressure_angle[i]), "contact_force": float(st.contact_force[i]),
            "cam_torque": float(st.cam_torque[i])}


def cmd_analyze_cam(args) -> int:
    from linkgen.families.cam.description import load_cam
    from linkgen.families.cam.kinetics import state

    if args.transfer or args.keep_singular:
        raise OptionError("--transfer and --keep-singular are for linkages; a cam's derivatives come with --json")
    if args.epsilon not in (None, 0.0):
        raise OptionError("a cam turns at a constant speed here: --epsilon must be 0 or left out")
    cm = load_cam(args.model)
    omega = cm.omega if args.omega is None else args.omega
    if not omega > 0:
        raise OptionError(f"--omega must be > 0 (the cam turns counter-clockwise), got {omega:g} rad/s")
    if args.summary:
        return _summary(cm, omega, args.json)
    if args.samples is not None or args.csv is not None:
        if args.angle is not None or args.json:
            raise OptionError("--angle/--json are for one cam angle; --samples/--csv for samples over the turn")
        theta = np.linspace(0.0, 2 * math.pi, args.samples or 360, endpoint=False)
        st = state(cm, theta, omega)
        unit = "m" if cm.follower.kind == "translating" else "rad"
        cols = ["theta [rad]", f"displacement [{unit}]", f"velocity [{unit}/s]", f"acceleration [{unit}/s²]",
                f"jerk [{unit}/s³]", "pressure_angle [rad]", "contact_force [N]", "cam_torque [N·m]"]
        write_rows(cols, [theta, st.displacement, st.velocity, st.acceleration, st.jerk, st.pressure_angle,
                          st.contact_force, st.cam_torque], args.csv, rows="cam angles")
        return 0
    theta = 0.0 if args.angle is None else args.angle
    st = state(cm, [theta], omega)
    out = {"model": cm.name, "theta": theta, "phi": theta, "omega": omega, "units": UNITS,
           "followers": {"follower": _follower_json(st, 0)}}
    check_finite(out)
    if args.json:
        print_json(out)
        return 0
    f = out["followers"]["follower"]
    unit = "m" if cm.follower.kind == "translating" else "rad"
    print(f"{cm.name}: {cm.follower.kind} follower at cam angle θ = {math.degrees(theta):.6g}°, ω = {omega:g} rad/s")
    print(f"  displacement {f['displacement']:.6g} {unit} (from the lowest position), velocity {f['velocity']:.6g} "
          f"{unit}/s, acceleration {f['acceleration']:.6g} {unit}/s², jerk {f['jerk']:.6g} {unit}/s³")
    print(f"  pressure angle {math.degrees(f['pressure_angle']):.6g}°, contact force {f['contact_force']:.6g} N, "
          f"cam torque {f['cam_torque']:.6g} N·m")
    return 0


def _summary(cm, omega: float, as_json: bool) -> int:
    s = cam_summary(cm, omega)
    if as_json:
        s = dict(s, leave_speed=None if math.isinf(s["leave_speed"]) else s["leave_speed"])
        print_json(s)
        return 0
    unit = "m" if s["kind"] == "translating" else "rad"
    deg = math.degrees
    print(f"{cm.name}: {s['kind']} follower, base circle {s['base_radius']:.6g} m, at ω = {omega:g} rad/s")
    print(f"  stroke {s['stroke']:.6g} {unit}" + (f" ({deg(s['stroke']):.4g}°)" if unit == "rad" else ""))
    a = s["max_pressure_angle"]
    print(f"  largest pressure angle {deg(a['value']):.4g}° at θ = {deg(a['at']):.4g}°")
    r = s["min_profile_curvature_radius"]
    shape = "convex" if s["convex"] else "concave in places"
    print(f"  profile {shape}; least radius of curvature {r['value']:.6g} m at θ = {deg(r['at']):.4g}°"
          + ("; UNDERCUT: the roller is larger than the pitch curve's radius there" if s["undercut"] else ""))
    print(f"  contact force {s['min_contact_force']:.6g}..{s['peak_contact_force']['value']:.6g} N; peak cam torque "
          f"{s['peak_cam_torque']['value']:.6g} N·m at θ = {deg(s['peak_cam_torque']['at']):.4g}°")
    if s["smallest_base_radius_for_30deg"] is not None:
        print(f"  the smallest base circle keeping the pressure angle within 30°: {s['smallest_base_radius_for_30deg']:.6g} m")
    lv = s["leave_speed"]
    print("  the follower never leaves the cam" if math.isinf(lv) else
          f"  the follower leaves the cam above ω = {lv:.6g} rad/s" + (" — it does at this speed" if omega > lv else ""))
    return 0


def cmd_profile(args) -> int:
    from linkgen.families.cam.description import cam_from_dict, is_cam_data
    from linkgen.model.toml_file import read_toml

    data = read_toml(args.model)  # a file that is no description is refused as such
    if not is_cam_data(data):
        what = ("a linkage whose crank carries a cam ([cam.NAME] pair tables beside [links])"
                if isinstance(data, dict) and "links" in data and "cam" in data else "not a cam description")
        raise OptionError(f"{args.model}: {what}; `linkgen profile` takes a cam file: a [cam] table and no [links] "
                          "(docs/cams.md)")
    try:
        cm = cam_from_dict(data)
    except DescriptionError as exc:
        raise exc.in_file(str(args.model)) from None
    theta = np.linspace(0.0, 2 * math.pi, args.points, endpoint=False)
    prof, pitch = cm.follower.profile(theta), cm.follower.pitch_curve(theta)[0]
    write_rows(["theta [rad]", "profile.x [m]", "profile.y [m]", "pitch.x [m]", "pitch.y [m]"],
               [theta, prof[:, 0], prof[:, 1], pitch[:, 0], pitch[:, 1]], args.output, rows="cam angles")
    return 0


def add_command(sub) -> None:
    from linkgen.cli.common import _positive_int

    p = sub.add_parser("profile", help="a cam's profile and pitch curve as point coordinates (CSV)")
    p.add_argument("model", type=Path, help="cam description file (.toml)")
    p.add_argument("-o", "--output", type=Path, help="CSV file (default: print)")
    p.add_argument("--points", type=_positive_int, default=720, help="points over the turn (no unit; default 720)")
    p.set_defaults(func=cmd_profile)


__all__ = ["add_command", "cam_summary", "cmd_analyze_cam", "cmd_profile"]

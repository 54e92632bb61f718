"""``linkgen dynamics`` and ``linkgen flywheel``: the machine driven by its motor."""

from __future__ import annotations

import argparse
import sys
import math
from pathlib import Path

import numpy as np

from linkgen.cli.common import _float_arg, print_json, write_rows
from linkgen.outputs import output_folder


def _positive(text: str) -> float:
    x = _float_arg(text)
    if not x > 0:
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, got {text!r}")
    return x


def _samples(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if not 2 <= n <= 10**6:
        raise argparse.ArgumentTypeError(f"expected 2 to 1000000 samples, got {n}")
    return n


def integration_progress(name: str):
    """progress(fraction, elapsed) for a long machine run (the ODE's or MuJoCo's), on stderr."""
    def report(fraction: float, elapsed: float) -> None:
        eta = elapsed * (1 - fraction) / max(fraction, 1e-9)
        print(f"{name}: machine run {100 * fraction:5.1f}% of its time ({elapsed:.1f} s, about {eta:.0f} s left)",
              file=sys.stderr, flush=True)
    return report


# What ``-o/--out`` writes, told by the path: (key, what it is, how it is recognised).
_OUT_KINDS = (("csv", "the time samples", ".csv"), ("mjcf", "the machine's MuJoCo file", ".xml"),
              ("report", "the figure's folder", "a folder"))


def _outputs(args, kinds: tuple[str, ...]) -> dict:
    """The files and folder ``-o/--out`` names (each told by its extension: .csv the samples, .xml
    the MJCF, a folder — existing or without an extension — the figure), with the earlier
    spellings (--csv, --mjcf, --report) kept as hidden aliases: key → Path or None."""
    from linkgen.cli.common import OptionError

    out = {k: getattr(args, f"old_{k}", None) for k in kinds}
    allowed = " or ".join(w for k, _, w in _OUT_KINDS if k in kinds)
    for path in args.out or []:
        suffix = path.suffix.lower()
        key = ("csv" if suffix == ".csv" else "mjcf" if suffix == ".xml" else
               "report" if path.is_dir() or not suffix else None)
        if key not in kinds:
            raise OptionError(f"-o/--out: {str(path)!r} is not {allowed}; `linkgen {args.command}` writes "
                              + ", ".join(f"{what} ({w})" for k, what, w in _OUT_KINDS if k in kinds))
        if out[key] is not None:
            what = next(what for k, what, _ in _OUT_KINDS if k == key)
            raise OptionError(f"-o/--out: {what} given twice ({out[key]} and {path})")
        out[key] = path
    return out


def cmd_dynamics(args) -> int:
    from linkgen.machine.machine import run_machine
    from linkgen.machine.plots import plot_run
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import cycle_forces, load_machine

    outs = _outputs(args, ("csv", "report", "mjcf"))
    asm, machine = load_machine(args.model)
    name = asm.mechanism.name
    duration = args.duration if args.duration is not None else machine.duration
    run = run_machine(machine, reduce(asm, machine.process_load), samples=args.samples, duration=duration,
                      progress=integration_progress(name))
    forces = cycle_forces(asm, run)
    mj = compared = mj_run = None
    if args.mujoco:
        from linkgen.crosscheck.machine import compare_machine_run

        what = (f"the start-up and {args.cycles} steady cycles" if run.steady is not None else
                f"its duration of {machine.duration:g} s (no steady cycle)")
        print(f"{name}: running the full linkage in MuJoCo over {what} …", file=sys.stderr, flush=True)
        compared, mj, mj_run = compare_machine_run(asm, machine, args.cycles, native=True,
                                                   progress=integration_progress(name))
    out = {"model": name, "duration": duration, "samples": args.samples, "motor": machine.motor.kind,
           "units": {"t": "s", "phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "motor_torque": "N·m (motor shaft)",
                     "current": "A", "twist": "rad", "inertia": "kg·m²"},
           "added_inertia": machine.added_inertia,
           "steady": run.steady.to_json() if run.steady else None, "startup_time": run.startup_time,
           "peak_motor_torque": run.peak_motor_torque, "peak_motor_torque_at": run.peak_motor_torque_at,
           "integrator": run.method,
           "forces_over_steady_cycle": forces.to_json() if forces else None}
    if compared is not None:
        out["mujoco"] = compared
    if outs["mjcf"] is not None:
        from linkgen.cli.files import atomic_write_text
        from linkgen.mujoco.machine_mjcf import machine_mjcf

        atomic_write_text(outs["mjcf"], machine_mjcf(asm, machine))
        out["mjcf"] = str(outs["mjcf"])
    if outs["report"] is not None:
        output_folder(outs["report"])
        fig = outs["report"] / f"{name}_machine.png"
        plot_run(name, mj_run if mj_run is not None else run, fig, mj)
        out["figure"] = str(fig)
    if outs["csv"] is not None:
        cols = ["t [s]", "phi [rad]", "omega [rad/s]", "epsilon [rad/s²]", "motor_torque [N·m]"]
        data = [run.t, run.phi, run.omega, run.epsilon, run.motor_torque]
        for c, arr in (("current [A]", run.current), ("twist [rad]", run.twist),
                       ("shaft_torque [N·m]", run.shaft_torque)):
            if arr is not None:
                cols.append(c)
                data.append(arr)
        write_rows(cols, data, outs["csv"], rows="time samples")
    if args.json:
        print_json(out)
        return 0
    print(f"{name}: {machine.motor.kind} motor, {duration:g} s from {machine.start_speed:g} rad/s, "
          f"rotor + flywheel {machine.added_inertia:.6g} kg·m² at the crank")
    if run.steady is None:
        print("  no steady cycle within the duration (two successive turns never repeated): give a longer "
              "--duration or [machine] duration")
    else:
        s = run.steady
        print(f"  steady cycle from t = {s.t_start:.4g} s: period {s.period:.6g} s, ω_mean {s.omega_mean:.6g} rad/s, "
              f"ω_min {s.omega_min:.6g}, ω_max {s.omega_max:.6g}, δ = {s.delta:.4g}")
        print(f"  start-up time {run.startup_time:.4g} s (ω within the steady band ±1 % of ω_mean from then on)"
              if run.startup_time is not None else "  start-up: ω had not settled into the steady band by the end")
    print(f"  peak motor torque {out['peak_motor_torque']:.6g} N·m at t = {out['peak_motor_torque_at']:.4g} s")
    if forces:
        t = forces.peak_balancing_torque
        print(f"  along the real motion: peak balancing torque {t.value:.6g} N·m at {math.degrees(t.phi):.1f}°")
        for k, r in forces.peak_reactions.items():
            print(f"    reaction {k}: {r.value:.6g} N at {math.degrees(r.phi):.1f}°")
    if compared is not None:
        m = compared
        e = {k: v for k, v in m["errors_relative"].items() if v is not None}
        window = (f"start-up and {m['cycles']} steady cycles, {m['duration_s']:.4g} s" if "cycles" in m
                  else f"{m['duration_s']:.4g} s, the whole duration: no steady cycle" if m.get("no_steady_cycle")
                  else f"{m['duration_s']:.4g} s")
        print(f"  MuJoCo's full linkage ({window}; {m['steps']} steps of {m['timestep']:.3g} s), relative to each "
              f"peak: " + ", ".join(f"{k} {v:.2e}" for k, v in e.items())
              + f"; φ within {m['phi_error_rad']:.2e} rad — {'ok' if m['ok'] else 'OVER'} the tolerance "
              f"{m['tolerance']:g}" + ("" if m["ok"] else f" ({m['worst']})"))
        if "dcmotor" in m:
            d = m["dcmotor"]
            print(f"  MuJoCo's own dcmotor element (the -o FILE.xml file), first {d['duration_s']:.3g} s: ω within "
                  f"{d['omega_error_relative']:.2e} at {d['timestep']:.3g} s steps, {d['omega_error_relative_half_step']:.2e} "
                  f"at half of it (order {d['order']:.2f} in the timestep)")
    if "figure" in out:
        print(f"  figure: {out['figure']}")
    if "mjcf" in out:
        print(f"  MuJoCo file of the machine: {out['mjcf']} (keyframe 'start'; the motor is machine:motor)")
    return 0


def cmd_flywheel(args) -> int:
    from linkgen.machine.flywheel import fluctuation
    from linkgen.machine.plots import plot_flywheel
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import flywheel_study, load_machine

    outs = _outputs(args, ("report",))
    asm, machine = load_machine(args.model)
    fw, delta_check = flywheel_study(asm, machine, args.delta, args.omega)
    out = {"model": asm.mechanism.name, "delta": args.delta, "omega_mean": fw.omega_mean,
           "inertia_required": fw.inertia, "driving_torque": fw.driving_torque, "energy_swing": fw.energy_swing,
           "delta_integrated": delta_check,
           "units": {"inertia_required": "kg·m² at the crank, beyond the mechanism and the rotor",
                     "driving_torque": "N·m", "energy_swing": "J", "omega_mean": "rad/s"}}
    if outs["report"] is not None:
        output_folder(outs["report"])
        red = reduce(asm, machine.process_load)
        added = machine.rotor_inertia * machine.gear_ratio**2
        js = np.geomspace(max(fw.inertia, 1e-6) / 30, max(fw.inertia, 1e-6) * 30, 40)
        ds = np.array([fluctuation(red, j, fw.omega_mean, added) for j in js])
        fig = outs["report"] / f"{asm.mechanism.name}_flywheel.png"
        plot_flywheel(asm.mechanism.name, js, ds, (fw.inertia, args.delta), fig)
        out["figure"] = str(fig)
    if args.json:
        print_json(out)
        return 0
    print(f"{out['model']}: flywheel for δ = {args.delta:g} at ω_mean = {fw.omega_mean:g} rad/s: "
          f"{fw.inertia:.6g} kg·m² at the crank (beyond the mechanism and the rotor)")
    print(f"  driving torque (mean resisting) {fw.driving_torque:.6g} N·m, largest energy swing {fw.energy_swing:.6g} J")
    print(f"  integrated with it: δ = {delta_check:.6g}")
    return 0


def add_command(sub) -> None:
    d = sub.add_parser("dynamics", help="the machine driven by its motor ([machine] table): start-up, steady "
                                        "cycle, speed fluctuation, forces along the real motion")
    d.add_argument("model", type=Path, help="description with a [machine] table")
    d.add_argument("--duration", type=_positive, help="seconds of machine time (default: [machine] duration)")
    d.add_argument("--samples", type=_samples, default=2000, help="time samples in the output (no unit; default 2000)")
    d.add_argument("-o", "--out", type=Path, action="append",
                   help="an output, told by its extension (give -o once per output): FILE.csv the time samples — "
                        "t [s], phi [rad], omega [rad/s], epsilon [rad/s²], motor_torque [N·m] (and current [A], "
                        "twist [rad], shaft_torque [N·m]); FILE.xml the machine as a MuJoCo file (the linkage, rotor, "
                        "flywheel, shaft and the motor as MuJoCo's own element where it has one); a folder for the "
                        "figure ω(t), M(t), ω(M)")
    d.add_argument("--csv", dest="old_csv", type=Path, help=argparse.SUPPRESS)
    d.add_argument("--json", action="store_true", help="print one JSON object")
    d.add_argument("--report", dest="old_report", type=Path, help=argparse.SUPPRESS)
    d.add_argument("--mujoco", action="store_true",
                   help="also run the full linkage in MuJoCo over the start-up and --cycles steady cycles and compare "
                        "ω(t), φ(t), the motor torque and the shaft twist")
    d.add_argument("--mjcf", dest="old_mjcf", type=Path, help=argparse.SUPPRESS)
    d.add_argument("--cycles", type=_samples, default=10,
                   help="steady cycles compared with --mujoco (no unit; default 10)")
    d.set_defaults(func=cmd_dynamics)
    f = sub.add_parser("flywheel", help="the flywheel inertia for a speed fluctuation δ (energy method), "
                                        "checked by integration")
    f.add_argument("model", type=Path, help="description with a [machine] table")
    f.add_argument("--delta", type=_positive, required=True, help="coefficient of speed fluctuation (no unit), e.g. 0.02")
    f.add_argument("--omega", type=_positive, help="mean crank speed [rad/s] (default: the drive's omega)")
    f.add_argument("--json", action="store_true", help="print one JSON object")
    f.add_argument("-o", "--out", type=Path, action="append", help="folder for the figure δ against flywheel inertia")
    f.add_argument("--report", dest="old_report", type=Path, help=argparse.SUPPRESS)
    f.set_defaults(func=cmd_flywheel)


__all__ = ["add_command", "cmd_dynamics", "cmd_flywheel"]

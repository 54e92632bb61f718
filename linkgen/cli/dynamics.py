"""``linkgen dynamics`` and ``linkgen flywheel``: the machine driven by its motor."""

from __future__ import annotations

import argparse
import sys
import math
from pathlib import Path

import numpy as np

from linkgen.cli.common import FOLDER, _float_arg, add_out_argument, print_json, rate_arg, write_rows
from linkgen.model import limits
from linkgen.outputs import output_folder


def _positive(text: str) -> float:
    x = _float_arg(text)
    if not x > 0:
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, got {text!r}")
    return x


def _positive_rate(text: str) -> float:
    """A crank speed > 0 [rad/s], or with its unit (120rpm): the parser of every --omega."""
    x = rate_arg(limits.MAX_OMEGA, "rad/s")(text)
    if not x > 0:
        raise argparse.ArgumentTypeError(f"expected a speed > 0, got {text!r}")
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


# What -o/--out writes, by extension (``common.output_kind``): a figure is a file by its
# extension, or a folder that receives it as NAME_machine.png / NAME_flywheel.png.
FIGURE = {".png": "the figure", ".svg": "the figure", ".pdf": "the figure"}
DYNAMICS = {".csv": "the time samples", ".xml": "the machine's MuJoCo file", **FIGURE,
            FOLDER: "the figure, as NAME_machine.png"}
FLYWHEEL = {**FIGURE, FOLDER: "the figure, as NAME_flywheel.png"}


def _outputs(args, kinds: dict[str, str]) -> dict:
    """What each -o/--out (or a hidden earlier spelling: --csv, --mjcf, --report) names, told by
    its extension (``common.output_kind``): "csv", "mjcf", "figure" → Path or None; a folder
    gives the figure's file inside it (named by ``_figure``)."""
    from linkgen.cli.common import OptionError, output_kind

    out: dict = {"csv": None, "mjcf": None, "figure": None}
    for path in args.out or []:
        kind = output_kind(args, path, kinds)
        key = {".csv": "csv", ".xml": "mjcf"}.get(kind, "figure")
        if out[key] is not None:
            raise OptionError(f"-o/--out: {kinds[kind].split(',')[0]} given twice ({out[key]} and {path})")
        out[key] = path
    return out


def _figure(path: Path, name: str) -> Path:
    """The figure's file: ``path`` itself (its format from the extension), or inside the folder
    ``path`` (made if missing) as ``name``.png."""
    if path.suffix.lower() in FIGURE and not path.is_dir():
        return path
    return output_folder(path) / f"{name}.png"


def _equation_source(machine) -> str:
    """Where the machine's equation reads J(φ), J′(φ) and M(φ) from (``[machine] tables``)."""
    from linkgen.machine.reduced import GRID, MOMENT_GRID

    if machine.tables:
        return f"tables over a turn (J at {GRID} angles, M at {MOMENT_GRID})"
    return "the closed form at every step"


def cmd_dynamics(args) -> int:
    from linkgen.machine.machine import run_machine
    from linkgen.machine.plots import plot_run
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import cycle_forces, load_machine

    outs = _outputs(args, DYNAMICS)
    asm, machine = load_machine(args.model)
    name = asm.mechanism.name
    duration = args.duration if args.duration is not None else machine.duration
    run = run_machine(machine, reduce(asm, machine.process_load, exact=not machine.tables), samples=args.samples,
                      duration=duration, progress=integration_progress(name))
    forces = cycle_forces(asm, run)
    kinds = [k for k in ("links", "points", "reactions") if getattr(args, k, False)]
    extra = {}
    if kinds:
        from linkgen.machine.along import along_time

        extra = along_time(asm, run.phi, run.omega, run.epsilon, kinds)
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
           "integrator": {"method": run.method, "rtol": run.rtol, "atol": run.rtol * 1e-3,
                          "equation": _equation_source(machine)},
           "start": {"phi": float(run.phi[0]), "omega": float(run.omega[0])},
           "end": {"t": float(run.t[-1]), "phi": float(run.phi[-1]), "omega": float(run.omega[-1]),
                   "turns": float((run.phi[-1] - run.phi[0]) / (2 * math.pi))},
           "energy_balance": run.energy.to_json(),
           "forces_over_steady_cycle": forces.to_json() if forces else None}
    if run.stopping is not None:  # [machine.schedule] / [machine.brake]
        out |= {"run_down_time": run.stopping.run_down_time, "braking_angle": run.stopping.braking_angle,
                "stopping": run.stopping.to_json()}
        out["units"] |= {"run_down_time": "s", "braking_angle": "rad"}
    if extra:
        out["along_time"] = {"t [s]": run.t.tolist()} | {k: np.asarray(v, dtype=float).tolist() for k, v in extra.items()}
    if compared is not None:
        out["mujoco"] = compared
    if outs["mjcf"] is not None:
        from linkgen.cli.files import atomic_write_text
        from linkgen.mujoco.machine_mjcf import machine_mjcf

        atomic_write_text(outs["mjcf"], machine_mjcf(asm, machine))
        out["mjcf"] = str(outs["mjcf"])
    if outs["figure"] is not None:
        fig = _figure(outs["figure"], f"{name}_machine")
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
        cols += list(extra)
        data += list(extra.values())
        write_rows(cols, data, outs["csv"], rows="time samples")
    e = run.energy
    if args.json:
        print_json(out)
        return 0 if e.ok else 1
    drive = "free motion (no motor)" if machine.free else f"{machine.motor.kind} motor"
    print(f"{name}: {drive}, {run.t[-1]:.6g} s from φ = {math.degrees(run.phi[0]):.6g}°, ω = {run.omega[0]:.6g} rad/s, "
          f"rotor + flywheel {machine.added_inertia:.6g} kg·m² at the crank")
    print(f"  at the end: φ = {float(run.phi[-1])!r} rad = {math.degrees(run.phi[-1]):.10g}° ({out['end']['turns']:.6g} "
          f"turns), ω = {float(run.omega[-1])!r} rad/s; integrated by {run.method} at rtol {run.rtol:g}, atol "
          f"{run.rtol * 1e-3:g} (rad, rad/s), J, J′ and M from {_equation_source(machine)}")
    what = ("drive, loads, springs, dampers" + (", friction" if e.friction is not None else "")
            + (", brake" if e.brake is not None else ""))
    print(f"  energy balance (ΔT = work of the {what}) at every sample: worst residual "
          f"{e.worst:.2e} of the run's energy scale {e.scale:.6g} J — "
          + ("ok" if e.ok else "VIOLATED") + f" (tolerance {e.tolerance:g})")
    if e.friction is not None:
        from linkgen.machine.friction import STICK_SPEED

        print(f"  friction in the pairs: {-e.friction[-1]:.6g} J lost over the run (Coulomb's law, ramped from zero "
              f"at rest to its full value at |ω| = {STICK_SPEED:g} rad/s)")
    if run.steady is None:
        stopped = (f"the run stopped after its {machine.turns:g} turns ([machine] turns)" if machine.turns is not None
                   and run.t[-1] < duration else "the run ended with the crank at rest under the brake"
                   if run.stopping is not None and run.stopping.held else "give a longer --duration or [machine] duration")
        print(f"  no steady cycle within the run (two successive turns never repeated): {stopped}")
    else:
        s = run.steady
        print(f"  steady cycle from t = {s.t_start:.4g} s: period {s.period:.6g} s, ω_mean {s.omega_mean:.6g} rad/s, "
              f"ω_min {s.omega_min:.6g}, ω_max {s.omega_max:.6g}, δ = {s.delta:.4g}")
        print(f"  start-up time {run.startup_time:.4g} s (ω within the steady band ±1 % of ω_mean from then on)"
              if run.startup_time is not None else "  start-up: ω had not settled into the steady band by the end")
    if run.stopping is not None:
        _print_stopping(run.stopping)
    if not machine.free:
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
    if not e.ok:
        print(f"{name}: the energy balance is violated: {e.worst:.2e} of the energy scale, over its tolerance "
              f"{e.tolerance:g}; the integration cannot be trusted", file=sys.stderr)
    return 0 if e.ok else 1


def _print_stopping(s) -> None:
    """The schedule's and the brake's lines of ``dynamics`` (``machine.schedule.Stopping``)."""
    off = f", off at {s.motor_off:.6g} s" if s.motor_off is not None else ", not switched off within the run"
    print(f"  motor on at {s.motor_on:.6g} s{off}" + (f"; brake applied at t = {s.brake_at:.6g} s, φ = "
          f"{math.degrees(s.brake_angle):.6g}°" if s.brake_at is not None else "; no brake applied in the run"))
    if s.rest_at is None:
        if s.motor_off is not None or s.brake_at is not None:
            print("  the crank did not come to rest within the run (ω never reached 0)")
        return
    print(f"  at rest at t = {s.rest_at:.6g} s" + (" (the run ends there: the brake holds the crank)" if s.held else ""))
    if s.run_down_time is not None:
        print(f"  run-down time (motor off → rest) {s.run_down_time:.6g} s")
    if s.braking_angle is not None:
        print(f"  braking angle (brake applied → rest) {math.degrees(s.braking_angle):.6g}° ({s.braking_angle:.6g} rad) "
              f"in {s.braking_time:.6g} s")


def cmd_flywheel(args) -> int:
    from linkgen.machine.flywheel import fluctuation
    from linkgen.machine.plots import plot_flywheel
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import flywheel_study, load_machine

    outs = _outputs(args, FLYWHEEL)
    asm, machine = load_machine(args.model)
    fw, delta_check = flywheel_study(asm, machine, args.delta, args.omega)
    out = {"model": asm.mechanism.name, "delta": args.delta, "omega_mean": fw.omega_mean,
           "inertia_required": fw.inertia, "driving_torque": fw.driving_torque, "energy_swing": fw.energy_swing,
           "delta_integrated": delta_check,
           "units": {"inertia_required": "kg·m² at the crank, beyond the mechanism and the rotor",
                     "driving_torque": "N·m", "energy_swing": "J", "omega_mean": "rad/s"}}
    if outs["figure"] is not None:
        fig = _figure(outs["figure"], f"{asm.mechanism.name}_flywheel")
        red = reduce(asm, machine.process_load)
        added = machine.rotor_inertia * machine.gear_ratio**2
        js = np.geomspace(max(fw.inertia, 1e-6) / 30, max(fw.inertia, 1e-6) * 30, 40)
        ds = np.array([fluctuation(red, j, fw.omega_mean, added) for j in js])
        plot_flywheel(asm.mechanism.name, js, ds, (fw.inertia, args.delta), fig)
        out["figure"] = str(fig)
    if args.json:
        print_json(out)
        return 0
    print(f"{out['model']}: flywheel for δ = {args.delta:g} at ω_mean = {fw.omega_mean:g} rad/s: "
          f"{fw.inertia:.6g} kg·m² at the crank (beyond the mechanism and the rotor)")
    print(f"  driving torque (mean resisting) {fw.driving_torque:.6g} N·m, largest energy swing {fw.energy_swing:.6g} J")
    print(f"  integrated with it: δ = {delta_check:.6g}")
    if "figure" in out:
        print(f"  figure: {out['figure']}")
    return 0


def add_command(sub) -> None:
    d = sub.add_parser("dynamics", help="the machine driven by its motor ([machine] table): start-up, steady "
                                        "cycle, speed fluctuation, forces along the real motion")
    d.add_argument("model", type=Path, help="description with a [machine] table")
    d.add_argument("--duration", type=_positive, help="seconds of machine time (default: [machine] duration)")
    d.add_argument("--samples", type=_samples, default=2000, help="time samples in the output (no unit; default 2000)")
    add_out_argument(d, "an output, told by its extension (give -o once per output): FILE.csv the time samples — "
                        "t [s], phi [rad], omega [rad/s], epsilon [rad/s²], motor_torque [N·m] (and current [A], "
                        "twist [rad], shaft_torque [N·m]); FILE.xml the machine as a MuJoCo file (the linkage, rotor, "
                        "flywheel, shaft and the motor as MuJoCo's own element where it has one); FILE.png, .svg or "
                        ".pdf the figure ω(t), M(t), ω(M), or a folder for it (NAME_machine.png)",
                     old=("--csv", "--report", "--mjcf"), append=True)
    d.add_argument("--json", action="store_true", help="print one JSON object")
    from linkgen.machine.along import KINDS

    for k, what in KINDS.items():
        d.add_argument(f"--{k}", action="store_true",
                       help=f"add to the time samples (-o FILE.csv, and --json's along_time) {what}")
    d.add_argument("--mujoco", action="store_true",
                   help="also run the full linkage in MuJoCo over the start-up and --cycles steady cycles and compare "
                        "ω(t), φ(t), the motor torque and the shaft twist")
    d.add_argument("--cycles", type=_samples, default=10,
                   help="steady cycles compared with --mujoco (no unit; default 10)")
    d.set_defaults(func=cmd_dynamics)
    f = sub.add_parser("flywheel", help="the flywheel inertia for a speed fluctuation δ (energy method), "
                                        "checked by integration")
    f.add_argument("model", type=Path, help="description with a [machine] table")
    f.add_argument("--delta", type=_positive, required=True, help="coefficient of speed fluctuation (no unit), e.g. 0.02")
    f.add_argument("--omega", type=_positive_rate,
                   help="mean crank speed [rad/s], or with a unit, e.g. 120rpm (default: the drive's omega)")
    f.add_argument("--json", action="store_true", help="print one JSON object")
    add_out_argument(f, "the figure δ against flywheel inertia: FILE.png, .svg or .pdf, or a folder for it "
                        "(NAME_flywheel.png)", old=("--report",), append=True)
    f.set_defaults(func=cmd_flywheel)


__all__ = ["add_command", "cmd_dynamics", "cmd_flywheel"]

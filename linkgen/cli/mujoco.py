"""CLI commands that need MuJoCo: build, simulate, validate — written once against the family
stages (``pipeline.registry.stage``): mjcf, simulate, validate and the report's figures."""

from __future__ import annotations

import json
import math
import multiprocessing
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from linkgen.errors import DescriptionError, LinkgenError

# Diagnosis lines printed per model (the JSON has them all).
DIAGNOSIS_LINES = 5


def _models(path: Path) -> list[Path]:
    """The description files a command runs on: ``path`` itself, or a folder's ``*.toml`` in
    name order."""
    if path.is_dir():
        found = sorted(p for p in path.glob("*.toml") if not p.is_dir())
        if not found:
            raise DescriptionError("", "no *.toml descriptions in this folder", str(path))
        return found
    return [path]


def _build_one(path: Path, out: Path, practical: bool = False, robot=None, loops: str = "closed") -> Path:
    """Compile ``path``'s MJCF (its family's ``mjcf`` stage; with ``robot``, a
    ``mujoco.robot.RobotOptions``, the robot-ready one with the rotor of the file's [machine]; with
    ``loops`` "coupling", its ``coupling`` stage, whose errors are printed) in MuJoCo and write it
    atomically to ``out``; a model MuJoCo's compiler refuses is a LinkgenError saying what it
    refused."""
    import mujoco

    from linkgen.cli.files import atomic_write_text
    from linkgen.mujoco.log import no_log_file
    from linkgen.pipeline.registry import load, stage

    desc = load(path)
    coupled = None
    if robot is not None:
        from dataclasses import replace

        from linkgen.model.machine import machine_from_dict
        from linkgen.model.toml_file import read_toml

        machine = machine_from_dict(read_toml(path))
        if machine is not None:
            robot = replace(robot, rotor_inertia=machine.added_inertia, machine=machine)
        xml = stage(desc, "mjcf")(desc, robot=robot)
    elif loops == "coupling":
        xml, coupled = stage(desc, "coupling")(desc, practical=practical)
    else:
        xml = stage(desc, "mjcf")(desc, practical=practical)  # any structure class: the MJCF needs no Assur groups
    try:
        with no_log_file():
            mujoco.MjModel.from_xml_string(xml)  # always compile what we write
    except ValueError as exc:
        text = str(exc).strip()
        if not text.startswith(("Error", "XML Error")):  # not MuJoCo's compiler: a bug, reported as such
            raise
        raise LinkgenError(f"MuJoCo cannot represent this mechanism as described (its compiler refuses the "
                           f"generated model: {' '.join(text.split())})") from None
    atomic_write_text(out, xml)
    said = ""
    if robot is not None:  # what a robot scene needs from the file (docs/robotics.md)
        p = robot.prefix if robot.prefix is not None else f"{desc.name}/"
        said = f" (robot model: attach body {p}mount, actuator {p}drive:{robot.actuator}, sensors {p}reaction:*)"
    if coupled is not None:
        print(coupled.line())
    print(f"wrote {out}{said}", file=sys.stderr)  # with the errors, in order, as for every family
    return out


# What -o/--out writes, by extension (``common.output_kind``).
BUILD = {".xml": "the MJCF of one description", "folder": "each description's MJCF, NAME.xml (NAME.coupled.xml "
                                                            "with --loops coupling)"}
SIMULATE = {".npz": "the sampled arrays", ".csv": "the samples as columns with their units"}
VALIDATE = {"folder": "the report: README.md and the figures"}


def cmd_build(args) -> int:
    """One file (to -o FILE.xml, into -o DIR, or next to it), or every *.toml of a folder (into -o
    DIR, or each next to itself): a bad file is reported as ``FILE: message`` and the others are
    still built; status 2 if any failed."""
    from linkgen.cli.common import FOLDER, OptionError, output_kind
    from linkgen.cli.files import output_folder, run_each

    kind = None if args.out is None else output_kind(args, args.out, BUILD)
    if kind is not None and kind != FOLDER and args.model.is_dir():
        raise OptionError(f"-o/--out {args.out}: {str(args.model)!r} is a folder of descriptions; its models are "
                          "written into a folder (-o DIR), or each beside its description (no -o)")
    robot = _robot_options(args)
    paths = _models(args.model)
    folder = output_folder(args.out) if kind == FOLDER else None

    # the loop-free model never takes the loop model's name (models/NAME.xml is the validated one)
    suffix = ".coupled.xml" if args.loops == "coupling" else ".xml"

    def target(p: Path) -> Path:
        return folder / f"{p.stem}{suffix}" if folder is not None else p.with_name(p.stem + suffix)

    if len(paths) == 1 and not args.model.is_dir():
        _build_one(paths[0], args.out if kind == ".xml" else target(paths[0]), args.practical, robot, args.loops)
        return 0
    from linkgen.pipeline.registry import check_command

    def build(p: Path) -> Path:  # each file of a folder refused as a file given alone would be
        check_command("build", p, tuple(o for o, on in (("--practical", args.practical), ("--robot", args.robot)) if on))
        return _build_one(p, target(p), args.practical, robot, args.loops)

    outcomes = run_each(paths, build)
    bad = [o for o in outcomes if not o.ok]
    if bad:
        print(f"linkgen: {len(bad)} of {len(outcomes)} descriptions failed", file=sys.stderr)
    return 2 if bad else 0


# build's options of the robot-ready model, each refused without --robot.
ROBOT_OPTIONS = ("--prefix", "--actuator", "--gear", "--kp", "--kv", "--plane", "--scene")


def _robot_options(args):
    """The ``RobotOptions`` of ``build --robot`` (None without it); an OptionError in one line for
    a robot option given without --robot, or with --practical."""
    from linkgen.cli.common import OptionError

    given = [o for o in ROBOT_OPTIONS if getattr(args, o[2:]) not in (None, False)]
    if not args.robot:
        if given:
            raise OptionError(f"{', '.join(given)} {'is an option' if len(given) == 1 else 'are options'} of the "
                              "robot-ready model: add --robot")
        return None
    if args.practical:
        raise OptionError("--practical and --robot: the robot-ready model states MuJoCo's own settings (timestep "
                          "2 ms, implicitfast); give one of them")
    if args.loops != "closed":
        raise OptionError("--loops coupling and --robot: the robot-ready model keeps its loops closed (its reaction "
                          "sensors read the loop forces); the loop-free model is written without --robot")
    from linkgen.errors import ArgumentError
    from linkgen.mujoco.robot import RobotOptions

    try:
        return RobotOptions(prefix=args.prefix, actuator=args.actuator or "motor",
                            gear=1.0 if args.gear is None else args.gear, kp=args.kp, kv=args.kv, plane=args.plane,
                            scene=args.scene)
    except ArgumentError as exc:  # about the options, not the file
        raise OptionError(str(exc)) from None


def _progress(name: str):
    def report(fraction: float, elapsed: float, what: str = "MuJoCo run") -> None:
        left = f", about {elapsed * (1 - fraction) / fraction:.0f} s left" if fraction > 0 else ""
        print(f"{name}: {what} {100 * fraction:5.1f}% ({elapsed:.1f} s{left})", file=sys.stderr, flush=True)
    return report


def cmd_simulate(args) -> int:
    from linkgen.cli.common import check_finite_columns, output_kind
    from linkgen.mujoco.simulate import steps_per_revolution
    from linkgen.pipeline.registry import load, stage

    if args.out is not None:
        output_kind(args, args.out, SIMULATE)  # about the option, not the file
    if args.out is not None:  # a symlink or a folder refused before the run, not after it
        from linkgen.outputs import check_output

        check_output(args.out)
    desc = load(args.model)
    run = stage(desc, "simulate")(desc, revolutions=args.revolutions, omega=args.omega, epsilon=args.epsilon,
                                  samples=args.samples, progress=_progress(desc.name),
                                  notice=lambda text: print(f"{args.model}: {text}", file=sys.stderr))
    arrays = run.samples.arrays()
    if args.out is not None:
        check_finite_columns(list(arrays), list(arrays.values()))  # nothing non-finite is written
        _write_samples(args.out, run.samples)
    st = run.settings
    # a prismatic drive's stroke is no revolution: steps per metre of it (2π rad of a crank's, in the same units)
    rate = (f"{steps_per_revolution(run) / (2 * math.pi):.0f} per m of stroke" if getattr(desc, "slide_drive", False)
            else f"{steps_per_revolution(run):.0f} per revolution")
    print(f"{desc.name}: {run.steps} steps ({rate}) in {run.wall:.2f} s "
          f"on {run.segments} thread(s); timestep {st.timestep:g} s, loop time constant {st.timeconst:g} s; "
          f"largest loop gap {run.gap_max:.3g} m; {run.samples.time.shape[0]} samples"
          + (f"; wrote {args.out}" if args.out else ""))
    return 0


def _write_samples(out: Path, samples) -> None:
    """``simulate -o``: the sampled arrays as NPZ (``Samples.arrays``), or as CSV with the names
    and units of ``analyze`` and ``forces`` (``Samples.columns``), written atomically and never
    through a symlink."""
    from linkgen.cli.common import _write_csv
    from linkgen.outputs import atomic_open, atomic_output

    if out.suffix.lower() == ".npz":
        with atomic_output(out) as tmp:
            np.savez(tmp, **samples.arrays())
        return
    cols = samples.columns()
    with atomic_open(out) as f:
        _write_csv(f, list(cols), list(cols.values()))


def wall_text(seconds: float) -> str:
    """The wall time of one file's validation, as the CLI line and the report table give it."""
    return f"validated in {seconds:.2f} s"


def _check_one(path: Path, report: Path | None, practical: bool, nthread: int | None, progress: bool,
               max_steps: int | None = None) -> dict:
    """Validate one file (in a worker process for folders) through its family's ``validate``
    stage; with ``report``, its ``figures`` stage draws into that folder. Returns the file's
    JSON entry: ``file``, ``family``, the result's ``to_dict()``, its figures, ``total_wall_s`` and
    ``line`` (the result's ``summary``), or ``error`` when it could not be validated."""
    from linkgen.cli.dynamics import integration_progress
    from linkgen.cli.files import message_for
    from linkgen.pipeline.registry import family_of, load, stage

    t0 = time.perf_counter()
    try:
        desc = load(path)
        check = stage(desc, "validate")(desc, practical=practical, nthread=nthread, max_steps=max_steps,
                                        progress=_progress(desc.name) if progress else None, source=path,
                                        machine_progress=integration_progress(desc.name) if progress else None)
    except LinkgenError as exc:
        return {"model": path.stem, "file": str(path), "ok": False, "error": message_for(path, exc)}
    out = {"file": str(path), "family": family_of(desc).name} | check.to_dict()
    if report is not None:
        from linkgen.outputs import output_folder

        output_folder(report)
        out |= stage(desc, "figures")(desc, check, report)
    out["total_wall_s"] = time.perf_counter() - t0
    out["line"] = check.summary(wall_text(out["total_wall_s"]))
    return out


def _summary(r: dict) -> str:
    """What the CLI prints of one file's validation (its JSON entry, ``_check_one``): the model
    and its result's line, a machine's comparison, the diagnosis and the runs tried."""
    from linkgen.report.report import number as _num

    if "error" in r:
        return f"{r['model']:<22} FAIL {r['error']}"
    lines = [f"{r['model']:<22} {r['line']}"]
    dyn = r.get("dynamics")
    if dyn is not None:
        lines.append(f"    machine: {dyn['skipped']}" if "skipped" in dyn else
                     f"    machine ({'free motion' if dyn.get('free') else 'driven by its motor'}), {dyn['duration_s']:g} s"
                     + (f" (its first {dyn['window']['step_budget']} MuJoCo steps: friction in the pairs)"
                        if "window" in dyn else "")
                     + (" to its rest under the brake" if (dyn.get("stopping") or {}).get("held_by_brake") else "") + ": "
                     f"MuJoCo's worst {dyn['worst']} "
                     f"{dyn['worst_error_relative']:.2e} of its scale (tolerance {dyn['tolerance']:g})"
                     + ("" if dyn["ok"] else " — over the tolerance"))
    from linkgen.crosscheck.diagnose import finding_line

    shown = r.get("diagnosis", [])[:DIAGNOSIS_LINES]
    pred = r.get("prediction") or {}
    if not r.get("ok", True) and "text" in pred:  # what was foreseen before the run, and how the run compares
        factor = pred.get("worst_factor") if pred.get("measured_over_predicted") else None  # none held to it
        apart = "measured" in pred and pred["measured"] is None  # the run stopped before any comparison
        lines.append(f"    {pred['text']}" + (("; it left nothing to compare, as predicted" if pred.get("unsettled") else
                                                "; it came apart, as predicted" if pred.get("apart") else
                                                "; it stopped before any comparison, which the prediction did not foresee")
                                               if apart else
                                               "" if factor is None else f"; measured within {factor:.2g}× of the prediction"))
    lines += [f"    {finding_line(d)}" for d in shown]
    if len(r.get("diagnosis", [])) > len(shown):
        lines.append(f"    … and {len(r['diagnosis']) - len(shown)} more quantities (see --json)")
    if r.get("diagnosis") and r.get("attempts"):
        said = {d["detail"] for d in shown}
        tried = "; ".join((f"timestep {a['settings']['timestep']:.3g} s, loop τ {a['settings']['timeconst']:.3g} s"
                           if a["settings"] else "derived settings")
                          + ((" → failed as above" if a["error"] in said else f" → failed: {a['error']}") if a["error"] else
                             f" → worst {a['worst']} at {_num(a['worst_error_over_tolerance'], '.2g')}× its tolerance")
                          for a in r.get("attempts", []))
        lines.append(f"    tried: {tried}")
    return "\n".join(lines)


def cmd_validate(args) -> int:
    if args.engine == "mjwarp":  # float32 through MuJoCo Warp (docs/float32.md)
        from linkgen.cli.engine import validate_float32

        return validate_float32(args, _models(args.model))
    from linkgen.families.planar.blocks import default_threads
    from linkgen.pipeline.registry import report_parts
    from linkgen.report.report import write_index

    paths = _models(args.model)
    report = args.out  # a report only where the user asks for one: never relative to the working folder
    if report is not None:  # refused before the runs (a symlink, a file), not after them
        from linkgen.outputs import output_folder

        from linkgen.cli.common import OptionError, output_kind
        from linkgen.cli.files import same_name

        twins = same_name(paths)  # the report names figures and sections after the mechanism: one would overwrite the other's
        if twins:
            raise OptionError(f"{twins[1]} and {twins[2]} both name their mechanism {twins[0]!r}: the report names its "
                              "figures and sections after it, so one would overwrite the other's; give them different "
                              "[mechanism] names, or validate them into separate -o/--out folders")
        output_kind(args, report, VALIDATE)  # a folder: "rep.md" is a file's name
        output_folder(report)
    practical = not args.no_practical
    t0 = time.perf_counter()
    cpu0 = os.times()
    if len(paths) == 1:
        results = [_check_one(paths[0], report, practical, None, True, args.max_steps)]
    else:  # models side by side in processes (each draws its own figures), one thread each
        ctx = multiprocessing.get_context("spawn")
        with ProcessPoolExecutor(max_workers=min(len(paths), default_threads()), mp_context=ctx) as pool:
            futures = [pool.submit(_check_one, p, report, practical, 1, False, args.max_steps) for p in paths]
            results = []
            for fut in futures:
                r = fut.result()
                results.append(r)
                if not args.json:
                    print(_summary(r), flush=True)
    wall = time.perf_counter() - t0
    cpu1 = os.times()
    cores = (cpu1.children_user + cpu1.children_system + cpu1.user + cpu1.system
             - cpu0.children_user - cpu0.children_system - cpu0.user - cpu0.system) / max(wall, 1e-9)
    if args.json:
        print(json.dumps(results[0] if len(results) == 1 else results, indent=2, allow_nan=False,
                         default=_json_default))
    elif len(paths) == 1 and "error" in results[0]:
        print(f"linkgen: error: {results[0]['error']}", file=sys.stderr)
    elif len(paths) == 1:
        print(_summary(results[0]))
    if report is not None:
        path = write_index(results, report, wall, cores, report_parts)
        print(f"report: {path} ({len(paths)} model(s) in {wall:.1f} s, {cores:.2f} cores busy)", file=sys.stderr)
    elif args.model.is_dir():
        print(f"{len(paths)} model(s) in {wall:.1f} s, {cores:.2f} cores busy; no report written (-o DIR writes one, "
              f"with the figures)", file=sys.stderr)
    if any("error" in r for r in results):
        return 2  # a file that could not be validated at all
    return 0 if all(r["ok"] for r in results) else 1


def _json_default(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    raise TypeError(f"not JSON serialisable: {type(x).__name__}")


def add_commands(sub) -> None:
    from linkgen.model import limits
    from linkgen.cli.common import _float_arg, _positive_int, add_out_argument, allowed_text, rate_arg
    from linkgen.mujoco.options import MAX_STEPS

    b = sub.add_parser("build", help="write the MJCF of a model, or of every model in a folder")
    b.add_argument("model", type=Path, help="description file (.toml), or a folder whose every description is "
                                            "written beside itself as .xml (or into -o DIR)")
    add_out_argument(b, f"write {allowed_text(BUILD)} (default: beside the description)", old=("--output",))
    b.add_argument("--practical", action="store_true",
                   help="write MuJoCo's usual settings (timestep 2 ms, Euler, default solref/solimp) instead of "
                        "the validation's; validate reports what they cost in accuracy")
    r = b.add_argument_group("robot-ready model (docs/robotics.md)")
    r.add_argument("--robot", action="store_true",
                   help="write a model to drive, attach to a robot and read (one actuator, reaction sensors, MuJoCo's "
                        "own settings, no servo, no scene); default: the validation model")
    r.add_argument("--prefix", help="every name in the file begins with it (default: the mechanism's name and '/')")
    r.add_argument("--actuator", choices=("motor", "position", "velocity"),
                   help="the driven joint's actuator (default motor)")
    r.add_argument("--gear", type=_float_arg, help="the actuator's gear: joint torque = gear × actuator force (default 1)")
    r.add_argument("--kp", type=_float_arg, help="the position servo's stiffness at the joint [N·m/rad], whatever the "
                                                 "gear (the file holds kp/gear²; default: from the reduced inertia and "
                                                 "a 5 Hz bandwidth)")
    r.add_argument("--kv", type=_float_arg, help="the position servo's damping or the velocity servo's gain at the joint "
                                                 "[N·m·s/rad], whatever the gear (the file holds kv/gear²; default: "
                                                 "critically damped / from the reduced inertia)")
    r.add_argument("--plane", choices=("xz", "yz", "xy"),
                   help="the world plane the mechanism's plane lies in, z up (default xz; planar linkages)")
    r.add_argument("--scene", action="store_true",
                   help="add a floor, sky, light and camera (default: none, the robot's scene has its own)")
    b.add_argument("--loops", choices=("closed", "coupling"), default="closed",
                   help="closed (default): the loops closed by constraints, as linkgen validates them; coupling: a "
                        "loop-free model for robot learning, every joint tied to the crank by a quartic fitted over "
                        "the drive range (its largest error printed and in the file; refused where it misses 1e-3 of "
                        "the travel)")
    b.set_defaults(func=cmd_build)

    s = sub.add_parser("simulate", help="run the driven crank in MuJoCo with settings derived from the mechanism")
    s.add_argument("model", type=Path, help="description file (.toml)")
    s.add_argument("--revolutions", type=_float_arg, default=1.0,
                   help="turns of the crank for a full-turn range (default 1)")
    s.add_argument("--omega", type=rate_arg(limits.MAX_OMEGA, "rad/s"),
                   help="crank speed at the start [rad/s], or with a unit, e.g. 120rpm (default: the description's)")
    s.add_argument("--epsilon", type=rate_arg(limits.MAX_EPSILON, "rad/s²"),
                   help="crank acceleration [rad/s²], or with a unit, e.g. 60rpm/s (default: the description's)")
    s.add_argument("--samples", type=_positive_int, default=360, help="sampled states over the range (no unit; default 360)")
    add_out_argument(s, f"write {allowed_text(SIMULATE)}; the names and units of analyze and forces",
                     metavar="FILE")
    s.set_defaults(func=cmd_simulate)

    v = sub.add_parser("validate", help="closed form against MuJoCo, for a file or every file of a folder")
    v.add_argument("model", type=Path, help="description file (.toml) or a folder of them")
    v.add_argument("--json", action="store_true", help="print the results as JSON")
    add_out_argument(v, f"write {allowed_text(VALIDATE)} (default: no report)", old=("--report",), metavar="DIR")
    v.add_argument("--no-practical", action="store_true",
                   help="skip the runs at MuJoCo's usual settings (the practical-settings table)")
    v.add_argument("--engine", choices=("mujoco", "mjwarp"), default="mujoco",
                   help="mujoco (default): MuJoCo in float64; mjwarp: a planar linkage's run in float32 through MuJoCo "
                        "Warp against float64 and the closed form (docs/float32.md; pip install 'linkgen[mjwarp]')")
    v.add_argument("--max-steps", type=_positive_int, default=MAX_STEPS,
                   help=f"step budget of each MuJoCo run, per segment (no unit; default {MAX_STEPS}); a planar "
                        f"linkage whose loops need more is run at the budget and reported against its prediction "
                        f"(docs/fidelity.md); a cam or a spatial chain over it is not started")
    v.set_defaults(func=cmd_validate)


__all__ = ["add_commands", "wall_text", "LinkgenError"]

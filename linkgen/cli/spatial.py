"""The MuJoCo and drawing commands for a spatial description (``[mechanism] space = "spatial"``):
build, validate and draw (structure, analyze and forces go through the registry:
``cli.closed_form``)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from linkgen.families.spatial.description import is_spatial_file
from linkgen.cli.common import OptionError

def route(args):
    """The spatial drawing's handler for ``draw`` of a spatial model, else None (the closed-form
    commands go through the registry, ``cli.closed_form``; the registry has refused the commands
    spatial four-bars do not take)."""
    model = getattr(args, "model", None)
    if args.command != "draw" or model is None or not is_spatial_file(model):
        return None
    return cmd_draw


def _load(path):
    from linkgen.pipeline.registry import load

    return load(path)


def cmd_draw(args) -> int:
    from linkgen.cli.draw import FIGURE_FORMATS, _suffix
    from linkgen.cli.files import atomic_output
    from linkgen.draw.spatial import draw_spatial

    _suffix(args.output, FIGURE_FORMATS, "a drawing")
    if args.angle is not None and args.angles is not None:
        raise OptionError("--angle cannot be combined with --angles: --angle draws one position, --angles a plan")
    mech = _load(args.model)
    if args.angles is None and args.angle is None:  # the sketch's own pose
        from linkgen.families.spatial.kinematics import assembled_chain

        angles = np.array([assembled_chain(mech).phi_s])
    else:
        angles = np.atleast_1d(args.angles if args.angles is not None else [args.angle])
    with atomic_output(args.output) as tmp:
        draw_spatial(mech, np.asarray(angles, dtype=float), tmp)
    what = (f"position plan of {len(angles)} positions" if len(angles) > 1
            else f"skeleton at φ = {math.degrees(float(angles[0])):.6g}°")
    print(f"wrote {args.output}: {mech.name}, {what}")
    return 0


def build_spatial(path: Path, out: Path, practical: bool = False) -> Path:
    import mujoco

    from linkgen.cli.files import atomic_write_text
    from linkgen.errors import DescriptionError
    from linkgen.mujoco.log import no_log_file
    from linkgen.crosscheck.spatial import derived_settings
    from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf

    if practical:
        raise DescriptionError("--practical", "is for planar linkages", str(path))
    mech = _load(path)
    xml = write_spatial_mjcf(mech, derived_settings(mech)[0])
    with no_log_file():
        mujoco.MjModel.from_xml_string(xml)
    atomic_write_text(out, xml)
    print(f"wrote {out}", file=sys.stderr)  # with the errors, in order, as for every family
    return out


def check_spatial_file(path: Path, t0: float, report: Path | None = None, progress=None,
                       max_steps: int | None = None) -> dict:
    """A spatial model in MuJoCo against its closed form; with ``report``, its figures there."""
    import time

    from linkgen.cli.files import message_for
    from linkgen.errors import LinkgenError
    from linkgen.crosscheck.spatial import check_spatial

    try:
        mech = _load(path)
        r = check_spatial(mech, progress=progress, max_steps=max_steps)
    except LinkgenError as exc:
        return {"model": path.stem, "file": str(path), "ok": False, "error": message_for(path, exc)}
    out = {"file": str(path), "spatial": r.to_json(), "model": r.model, "ok": r.ok, "line": r.summary()}
    if report is not None:
        from linkgen.draw.spatial import draw_spatial, plot_spatial_check

        from linkgen.outputs import output_folder

        output_folder(report)
        draw_spatial(mech, np.array([0.0]), report / f"{r.model}_drawing.png")
        draw_spatial(mech, np.radians(np.arange(0.0, 360.0, 30.0)), report / f"{r.model}_plan.png")
        out["figures"] = [f"{r.model}_drawing.png", f"{r.model}_plan.png"] + plot_spatial_check(r, report, mech)
    from linkgen.cli.cams import wall_text

    out["total_wall_s"] = time.perf_counter() - t0
    out["line"] = r.summary(wall_text(out["total_wall_s"]))
    return out


__all__ = ["build_spatial", "check_spatial_file", "is_spatial_file", "route"]

"""The float32 table of docs/float32.md: every bundled planar linkage (models/*.toml of the planar
family) run in float32 through MuJoCo Warp against MuJoCo's float64 and the closed form
(``mujoco.float32.float32_check``: 64 stretches tiling one turn, each from the closed-form
state, as the worlds of one batch), at linkgen's derived validation settings and at MuJoCo's
usual settings (``crosscheck.practical.USER``: 2 ms, Euler, solref 0.02, solimp 0.9) with the
derived rotor armature. Mechanisms without a closed loop and cam linkages are left out.
Prints a Markdown table.

Run: PYTHONPATH=. nice -n 10 .venv/bin/python validation/float32.py [model ...]   (~10 min on a busy CPU)
"""

from __future__ import annotations

import math
import sys
from dataclasses import replace
from pathlib import Path

import mujoco

from linkgen.crosscheck.practical import USER
from linkgen.errors import LinkgenError
from linkgen.families.planar.assembly import assemble
from linkgen.mujoco.float32 import float32_check
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import PLACEHOLDER
from linkgen.mujoco.settings import derive
from linkgen.mujoco.tree import spanning_tree
from linkgen.pipeline.registry import family_of, load

ROOT = Path(__file__).resolve().parents[1]


def _user(asm):
    w = asm.mechanism.drive.omega
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    derived, _ = derive(asm, model, omega=w, epsilon=0.0, duration=2 * math.pi / w)
    return replace(USER, armature=derived.armature)


def main(names: list[str]) -> None:
    paths = [ROOT / "models" / f"{n}.toml" for n in names] or sorted((ROOT / "models").glob("*.toml"))
    print("| model | settings | steps × worlds | loop gap / size: float32 (float64) | tolerance | loop forces / peak "
          "vs closed form: float32 (float64) | float32 vs float64 | tolerance | ok |")
    print("|---|---|---|---|---|---|---|---|---|")
    for p in paths:
        desc = load(p)
        if family_of(desc).name != "planar" or getattr(desc, "cams", None):
            continue
        asm = assemble(desc)
        if not spanning_tree(asm).closures:  # no loop: nothing float32 could open
            continue
        for label, settings in (("derived", None), ("MuJoCo's usual", _user(asm))):
            try:
                r = float32_check(asm, settings=settings)
            except LinkgenError as exc:
                print(f"| {desc.name} | {label} | | {type(exc).__name__}: {exc} | | | | | |", flush=True)
                continue
            t = r.tolerances
            print(f"| {desc.name} | {label} ({r.timestep:.2g} s) | {r.steps} × {r.worlds} | {r.gap32:.1e} ({r.gap64:.1e}) | "
                  f"{t['loop_gap']:.1e} | {r.force32_vs_closed:.1e} ({r.force64_vs_closed:.1e}) | {r.force32_vs_64:.1e} | "
                  f"{t['constraint_force']:.1e} | {'yes' if r.ok else 'no'} |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])

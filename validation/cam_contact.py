"""Which MuJoCo modelling of a cam's contact makes the instantaneous contact force follow the
closed form: each choice changed on its own from linkgen's cam MJCF (``mujoco.cam.cam_mjcf``),
the bundled stand-alone cams run over a part of a turn from the closed-form state
(``mujoco.cam_run.run_cam``), and a table printed of, per variant and cam: the follower's
displacement error at every step relative to the stroke, the contact force's error at every
step relative to its peak, the share of the steps with the roller off the cam, and the wall time.

The choices: the roller's geom (linkgen's sphere; a cylinder, as used before, or a capsule), the
profile's tessellation (PROFILE_POINTS), the contact's time constant (solref) and impedance (solimp), a contact margin, the
integrator, noslip iterations, the cone, the timestep, the convex collision's tolerance.

Run: PYTHONPATH=. .venv/bin/python validation/cam_contact.py [--turn FRACTION] [variant ...]
(about 1 s a variant and cam at a quarter of a turn on an idle core)
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from lxml import etree

import linkgen.mujoco.cam as mc
import linkgen.mujoco.cam_run as mr
from linkgen.families.cam.kinetics import state
from linkgen.pipeline.registry import load

ROOT = Path(__file__).resolve().parents[1]
MODELS = ("cam_translating", "cam_oscillating", "cam_flat_face")


def _contact_geoms(root):
    return [g for g in root.iter("geom") if g.get("name") in ("cam:profile", mc.CONTACT)]


def _set(attr, value):
    def edit(root, dt):
        for g in _contact_geoms(root):
            g.set(attr, value(dt) if callable(value) else value)
    return edit


def _option(attr, value):
    def edit(root, dt):
        root.find("option").set(attr, value)
    return edit


def _roller(kind):
    """The roller's geom as ``kind`` in place of linkgen's sphere: a cylinder (the geom used
    before) or a capsule along z, as thick as the extruded profile."""
    def edit(root, dt):
        g = root.find(".//geom[@name='follower:contact']")
        if g.get("type") != "sphere":  # a flat face's box: not a roller
            return
        half = abs(float(root.find(".//mesh[@name='cam:profile']").get("vertex").split()[2]))
        g.set("type", kind)
        g.set("size", f"{g.get('size')} {half!r}")
    return edit


def _half_step(root, dt):
    root.find("option").set("timestep", repr(dt / 2))


# name -> (constants changed in mujoco.cam, edits of the written MJCF (root, timestep))
VARIANTS = {
    "baseline": ({}, []),
    "roller cylinder": ({}, [_roller("cylinder")]),
    "roller capsule": ({}, [_roller("capsule")]),
    "points 1000": ({"PROFILE_POINTS": 1000}, []),
    "points 16000": ({"PROFILE_POINTS": 16000}, []),
    "points 64000": ({"PROFILE_POINTS": 64000}, []),
    "solref 2 dt": ({"CONTACT_TIME": 2}, []),
    "solref 20 dt": ({"CONTACT_TIME": 20}, []),
    "solref 50 dt": ({"CONTACT_TIME": 50}, []),
    "solref 200 dt": ({"CONTACT_TIME": 200}, []),
    "solimp 0.99": ({}, [_set("solimp", "0.99 0.99 0.001 0.5 2")]),
    "solimp 0.9 (default)": ({}, [_set("solimp", "0.9 0.95 0.001 0.5 2")]),
    "margin 1e-3 size": ({}, [_set("margin", lambda dt: "5e-4")]),
    "implicitfast": ({}, [_option("integrator", "implicitfast")]),
    "RK4": ({}, [_option("integrator", "RK4")]),
    "noslip 10": ({}, [_option("noslip_iterations", "10")]),
    "cone elliptic": ({}, [_option("cone", "elliptic")]),
    "timestep / 2": ({}, [_half_step]),
    "ccd default": ({}, [_option("ccd_tolerance", "1e-6"), _option("ccd_iterations", "50")]),
    # the two that each helped one figure, together
    "solimp 0.9 + solref 2 dt": ({"CONTACT_TIME": 2}, [_set("solimp", "0.9 0.95 0.001 0.5 2")]),
    "solimp 0.9 + solref 20 dt": ({"CONTACT_TIME": 20}, [_set("solimp", "0.9 0.95 0.001 0.5 2")]),
    "solimp 0.9 + points 16000": ({"PROFILE_POINTS": 16000}, [_set("solimp", "0.9 0.95 0.001 0.5 2")]),
}


def run_variant(cm, name: str, turn: float) -> dict:
    consts, edits = VARIANTS[name]
    saved = {k: getattr(mc, k) for k in consts}
    try:
        for k, v in consts.items():
            setattr(mc, k, v)
        root = etree.fromstring(mc.cam_mjcf(cm).encode())
        dt = float(root.find("option").get("timestep"))
        for e in edits:
            e(root, dt)
        text = etree.tostring(root, encoding="unicode")
        t0 = time.perf_counter()
        run = mr.run_cam(cm, revolutions=turn, mjcf_text=text, max_steps=10**8)
        wall = time.perf_counter() - t0
    finally:
        for k, v in saved.items():
            setattr(mc, k, v)
    ref = state(cm, run.theta, float(np.mean(run.omega)))
    q_all = cm.follower.output(np.linspace(0, 2 * np.pi, 3600, endpoint=False))[0]
    f_peak = float(np.abs(state(cm, np.linspace(0, 2 * np.pi, 3600, endpoint=False)).contact_force).max())
    return {"displacement": float(np.abs(run.displacement - ref.displacement).max() / np.ptp(q_all)),
            "force": float(np.abs(run.contact_force - ref.contact_force).max() / f_peak),
            "force_rms": float(np.sqrt(np.mean((run.contact_force - ref.contact_force) ** 2)) / f_peak),
            "off": float(1.0 - np.mean(run.touching)), "steps": run.steps, "wall": wall}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variants", nargs="*", default=list(VARIANTS))
    ap.add_argument("--turn", type=float, default=0.25, help="the part of a turn compared (after an eighth settling)")
    ap.add_argument("--models", nargs="*", default=list(MODELS))
    args = ap.parse_args(argv)
    cams = [load(ROOT / "models" / f"{m}.toml") for m in args.models]
    print(f"errors over {args.turn:g} turn from the closed-form state: displacement / stroke, contact force / peak "
          "(every step: max | rms), steps off the cam")
    print(f"| variant | {' | '.join(cm.name for cm in cams)} |")
    print("|---|" + "---|" * len(cams))
    for name in args.variants:
        cells = []
        for cm in cams:
            try:
                r = run_variant(cm, name, args.turn)
                cells.append(f"{r['displacement']:.1e}, {r['force']:.1e} \\| {r['force_rms']:.1e}, {r['off']:.0%} "
                             f"({r['wall']:.1f} s)")
            except Exception as e:  # a variant MuJoCo refuses is a finding too
                cells.append(f"{type(e).__name__}: {str(e)[:60]}")
        print(f"| {name} | {' | '.join(cells)} |", flush=True)


if __name__ == "__main__":
    main()

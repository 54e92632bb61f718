"""The loop-free export (``build --loops coupling``) against the loop model, on the four-bar, the
seven-link, the offset slider-crank and the models with an oscillating drive (tangent_prp):

* the fit: each model's worst coupled coordinate (minimax, as written) over its drive range — or,
  where the quartics miss 1e-3 of the travel there (a full turn), over the widest range about its
  middle that holds (``coupling.holding_range``) —, with least squares' worst for comparison;
* speed: MuJoCo steps per wall second of the coupled and the loop model at the same settings (the
  derived ones with the coupled file's Newton tolerance 1e-10, and MuJoCo's defaults at 2 ms:
  Euler, solref 0.02, tolerance 1e-8), each driven
  over its range from the same state, one thread, ``mujoco.rollout``;
* torque: the crank held at the drive's ω by a heavy rotor (as linkgen's runs do: armature 1e6×
  the largest reduced inertia), the torque the rotor gives, −armature·q̈, against the closed
  form's balancing torque at the angles and speeds reached, for the coupled model (its own run
  here, the description's loads applied through xfrc_applied) and the loop model (linkgen's
  ``simulate``).

Run: PYTHONPATH=. .venv/bin/python validation/coupling_study.py [model ...]   (~1 min)
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np
from mujoco import rollout

from linkgen.crosscheck.practical import USER
from linkgen.families.planar.assembly import assemble
from linkgen.families.planar.kinetostatics import forces
from linkgen.families.planar.polyfit import fit, grid, least_squares
from linkgen.mujoco.coupling import TOLERANCE, coordinate, coupled_tree, couple, holding_range, link_poses
from linkgen.mujoco.coupling_mjcf import MIN_TOLERANCE, write_coupled
from linkgen.mujoco.forces import apply_loads
from linkgen.mujoco.mjcf import settings_for, write_mjcf
from linkgen.mujoco.simulate import simulate
from linkgen.pipeline.registry import load

ROOT = Path(__file__).resolve().parents[1]
MODELS = ("fourbar", "seven_link", "slider_crank_offset", "tangent_prp")
REPEATS = 3
# The torque error is also given over this middle fraction of the range: a quartic's slope and
# curvature err most at the range's ends, where the torque (which needs both) errs most.
INNER = 0.8


def _range_that_holds(mech):
    tree, _ = coupled_tree(mech)
    asm = assemble(mech)
    try:
        couple(asm)
        return mech, "its drive range"
    except Exception:  # CouplingError: narrow it
        lo, hi = holding_range(asm, mech, tree)
        return replace(mech, drive=replace(mech.drive, start=lo, stop=hi)), "narrowed"


def _lsq_worst(asm, c) -> float:
    """Least squares' worst relative error of the outputs, each against the crank (no chain)."""
    mech = asm.mechanism
    phi = grid(*c.drive_range)
    origin, angle = link_poses(asm, phi)
    worst = 0.0
    for parent, child, pair in c.tree[1:]:
        if parent != "ground":
            continue
        y = coordinate(mech, pair, parent, child, origin, angle)
        f = fit(phi, y, float(phi[len(phi) // 2]), float(y[len(y) // 2]), least_squares)
        worst = max(worst, f.relative)
    return worst


def _steps_per_second(asm, c, settings) -> tuple[float, float]:
    """MuJoCo steps per wall second (coupled, loop) at ``settings``: both models written with
    them, the crank on the same heavy rotor, from the closed-form state at the range's start at
    the drive's ω, over the range (one thread, ``mujoco.rollout``, the best of REPEATS)."""
    from linkgen.mujoco.state import initial_state

    mech = asm.mechanism
    w = mech.drive.omega
    out = []
    for xml, coupled in ((write_coupled(asm, c, settings), True), (write_mjcf(asm, settings), False)):
        m = mujoco.MjModel.from_xml_string(xml)
        crank = m.joint(mech.drive.joint)
        m.dof_armature[crank.dofadr[0]] = settings_for(asm).armature
        d = mujoco.MjData(m)
        if coupled:
            chain = c.chain(np.array([c.drive_range[0]]))
            for name, (q, d1, _) in chain.items():
                d.qpos[m.joint(name).qposadr[0]], d.qvel[m.joint(name).dofadr[0]] = q[0], d1[0] * w
        else:
            d.qpos[:], d.qvel[:] = initial_state(asm, m, c.drive_range[0], w)
        for name in ("drive:servo",):  # the loop model's viewer servo off, as linkgen's runs do
            try:
                m.actuator_gainprm[m.actuator(name).id] = m.actuator_biasprm[m.actuator(name).id] = 0.0
            except KeyError:
                pass
        state = np.zeros((1, mujoco.mj_stateSize(m, mujoco.mjtState.mjSTATE_FULLPHYSICS)))
        mujoco.mj_getState(m, d, state[0], mujoco.mjtState.mjSTATE_FULLPHYSICS)
        nstep = max(int((c.drive_range[1] - c.drive_range[0]) / w / m.opt.timestep), 100)
        best = math.inf
        for _ in range(REPEATS):
            t0 = time.perf_counter()
            rollout.rollout(m, d, state, nstep=nstep)
            best = min(best, time.perf_counter() - t0)
        out.append(nstep / best)
    return out[0], out[1]


def _coupled_torque(asm, c, xml: str, settings) -> tuple[float, float]:
    """The coupled model driven by its rotor at ω over the range from the chain's state: largest |rotor torque − closed form's balancing torque| [N·m] over the range at ω, the
    same over the middle INNER of the range, and the closed form's largest |torque| there."""
    mech = asm.mechanism
    w = mech.drive.omega
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    crank = m.joint(mech.drive.joint)
    m.dof_armature[crank.dofadr[0]] = settings.armature
    m.jnt_limited[crank.id] = 0
    start, stop = c.drive_range
    for name, (q, d1, _) in c.chain(np.array([start])).items():  # a consistent start
        d.qpos[m.joint(name).qposadr[0]], d.qvel[m.joint(name).dofadr[0]] = q[0], d1[0] * w
    mujoco.mj_forward(m, d)
    phis, ws, taus, gap = [], [], [], 0.0
    steps = int((stop - start) / w / m.opt.timestep)
    for k in range(steps):
        apply_loads(asm, m, d, float(d.qpos[crank.qposadr[0]]))
        mujoco.mj_step(m, d)
        if k % 20 == 0 and k > steps // 50:  # past a short start
            phis.append(d.qpos[crank.qposadr[0]])
            ws.append(d.qvel[crank.dofadr[0]])
            taus.append(-settings.armature * d.qacc[crank.dofadr[0]])
            gap = max(gap, float(np.abs(d.efc_pos[:d.nefc]).max()))
    phis, ws, taus = map(np.array, (phis, ws, taus))
    keep = (phis >= start) & (phis <= stop)
    cf = forces(asm, phis[keep], ws[keep], 0.0).balancing_torque
    err = np.abs(taus[keep] - cf)
    mid, half = 0.5 * (start + stop), 0.5 * (stop - start)
    inner = np.abs(phis[keep] - mid) <= INNER * half
    return float(err.max()), float(err[inner].max()), float(np.abs(cf).max()), gap


def study(name: str) -> dict:
    desc = load(ROOT / "models" / f"{name}.toml")
    mech, which = _range_that_holds(getattr(desc, "mechanism", desc))
    asm = assemble(mech)
    settings = settings_for(asm)
    from linkgen.mujoco.coupling_torque import lag, torque_error

    c = couple(asm)
    c = replace(c, torque=torque_error(asm, c, mujoco.MjModel.from_xml_string(write_coupled(asm, c, settings))))
    coupled_xml = write_coupled(asm, c, settings)
    lo, hi = (math.degrees(a) for a in c.drive_range)
    out = {"model": name, "range": f"{lo:.4g}..{hi:.4g}° ({which})", "worst": c.worst.describe(),
           "worst_relative": c.worst.fit.relative, "outputs": [j.describe() for j in c.outputs],
           "lsq_outputs_worst_relative": _lsq_worst(asm, c)}
    same = replace(settings, tolerance=max(settings.tolerance, MIN_TOLERANCE))  # as the coupled file writes it
    for label, st in (("derived", same), ("MuJoCo defaults, 2 ms Euler", USER)):
        out[f"steps/s coupled ({label})"], out[f"steps/s loop ({label})"] = _steps_per_second(asm, c, st)
    t0 = time.perf_counter()
    err, inner, peak, gap = _coupled_torque(asm, c, coupled_xml, settings)
    out["lag measured"] = gap
    out["lag stated"] = max(lag(c, settings.timeconst, mech.drive.omega).values())
    out["torque error stated"] = c.torque.max_error if c.torque is not None else None
    out["torque error coupled"] = err
    out["torque error coupled inner"] = inner
    out["peak torque"] = peak
    out["coupled run wall s"] = time.perf_counter() - t0
    run = simulate(asm, settings=settings, nthread=1)
    s = run.samples
    cf = forces(asm, s.crank[0], s.crank[1], s.crank[2]).balancing_torque
    out["torque error loop"] = float(np.abs(s.drive_torque - cf).max())
    return out


def main(names) -> None:
    for name in names or MODELS:
        r = study(name)
        print(f"{r['model']}: over {r['range']}; worst coupled joint {r['worst']} "
              f"(outputs by least squares, unchained: {r['lsq_outputs_worst_relative']:.2g} of the travel)")
        for o in r["outputs"]:
            print(f"    output {o}")
        print("    steps/s: " + "; ".join(f"{k[8:]} {v:,.0f}" for k, v in r.items() if k.startswith("steps/s")))
        print(f"    crank torque at ω, against the closed form (peak {r['peak torque']:.3g} N·m): coupled "
              f"{r['torque error coupled']:.3g} N·m ({r['torque error coupled inner']:.3g} over the middle "
              f"{INNER:.0%}; the file states {r['torque error stated']:.3g}), loop model {r['torque error loop']:.3g} N·m; "
              f"the couplings' lag: {r['lag measured']:.2g} measured, {r['lag stated']:.2g} stated", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])

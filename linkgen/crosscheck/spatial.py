"""A spatial four-bar run in MuJoCo against the closed form: every point's position, velocity and
acceleration, the balancing torque and (where the statics determine them) the pair reactions,
over a full revolution of the crank.

MuJoCo drives the crank by a rotor inertia (``state.derive_settings``) from the closed-form
state a lead-in before the compared revolution; at every sample the closed form is evaluated at
MuJoCo's own crank angle, speed and acceleration, so the comparison measures the loop, not the
rotor. Errors are relative to the scale of each kind of quantity: the size L for positions,
L·ω for velocities, L·(ω² + |ε|) + |g| for accelerations, the peak closed-form torque and pair
force for forces. Tolerances are the planar ones (``linkgen.mujoco.tolerances``). The
description's loads are set on MuJoCo's bodies before every step and every read-out, at
MuJoCo's own positions and crank angle (``spatial.mjloads``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import mujoco
import numpy as np

from linkgen.mujoco.tolerances import FORCE_TOL, GAP_TOL, INVERSE_TOL, REL_TOL
from linkgen.errors import SimulationError
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.scene import SERVO
from linkgen.mujoco.settings import Scales
from linkgen.mujoco.timing import SETTLE_TARGET, settle_window, switch_angles
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.forces import forces
from linkgen.mujoco.spatial_inverse import inverse_torque
from linkgen.families.spatial.jets import motion as jet_motion
from linkgen.families.spatial.kinematics import assembled_chain, solve
from linkgen.mujoco.spatial_mjcf import DRIVE_ACTUATOR, write_spatial_mjcf
from linkgen.mujoco.spatial_loads import loads_at_state, loads_while_stepping
from linkgen.mujoco.spatial_names import closing_body
from linkgen.mujoco.spatial_state import SCAN, derive_settings, joint_state, loop_name

# The run starts this many crank radians before the compared revolution, from the closed-form
# state: the loop's transient from the start (a few time constants τ = PHASE/ω, i.e. a few
# hundredths of a radian) has died out by the first sample.
LEAD = 0.2
# A slider input's run starts at its range's start; the samples compared begin this fraction of
# the range later (PHASE of the input unit per τ: the transient has died out many times over).
LEAD_RANGE = 0.05
# Chains whose coupler turns on two ball joints and so has an idle spin about its own line.
IDLE_SPIN = ("RSSR", "RSSP", "PSSR", "PSSP")
# Closed-form states at which MuJoCo's inverse dynamics is compared (every 10°).
INVERSE_SAMPLES = 36


@dataclass(frozen=True)
class SpatialCheck:
    """Worst relative errors by quantity (``errors``: name → (error, tolerance)), the largest loop
    gap over the size, the steps, the wall time [s], the settings used and what they came from,
    and the reactions left out (statically indeterminate chains)."""

    model: str
    kind: str
    errors: dict
    gap: float
    steps: int
    wall: float
    settings: object
    scales: dict
    note: str = ""
    samples: dict = field(default_factory=dict, repr=False)

    @property
    def ok(self) -> bool:
        return self.gap <= GAP_TOL and all(e <= tol for e, tol in self.errors.values())

    def worst(self) -> tuple[str, float, float]:
        """The worst quantity relative to its tolerance, the loop gap included."""
        errors = self.errors | {"loop gap": (self.gap, GAP_TOL)}
        name = max(errors, key=lambda k: errors[k][0] / errors[k][1])
        return (name, *errors[name])

    def summary(self, wall: str | None = None) -> str:
        """One line; ``wall``: the wall time as the caller measured it (default: this check's)."""
        name, err, tol = self.worst()
        gap = name == "loop gap"  # worded as the planar line: the gap once, relative to the size
        return (f"{'ok  ' if self.ok else 'FAIL'} {self.kind}: worst {name} {err:.2e} " + ("of the size " if gap else "")
                + f"(tolerance {tol:g}), "
                + ("" if gap else f"loop gap {self.gap:.1e} of the size (tolerance {GAP_TOL:g}), ")
                + f"{self.steps} steps, {wall or f'{self.wall:.2f} s'}" + (f"; {self.note}" if self.note else ""))

    @property
    def diagnosis(self) -> tuple:
        """What missed, where and why: none is worked out for spatial chains yet (the errors name
        the quantities)."""
        return ()

    @property
    def quantities(self) -> dict:
        """Each compared quantity as ``mujoco.result_shape`` gives it."""
        from linkgen.mujoco.result_shape import quantity

        return {k: quantity(e, t) for k, (e, t) in self.errors.items()}

    @property
    def loop_gap(self) -> dict:
        """The largest loop gap relative to the size, its tolerance, and whether it holds."""
        from linkgen.mujoco.result_shape import loop_gap

        return loop_gap(self.gap, GAP_TOL)

    def to_dict(self) -> dict:
        """The result as ``linkgen validate --json`` gives it (``mujoco.result_shape``)."""
        from linkgen.mujoco.result_shape import validation

        return validation(self.model, self.ok, settings=self.settings.to_json(), quantities=self.quantities,
                          loop_gap=self.loop_gap, diagnosis=self.diagnosis, kind=self.kind,
                          steps=self.steps, wall_s=self.wall, scales=self.scales, note=self.note)

    def to_json(self) -> dict:
        return self.to_dict()


# Steps between progress reports (a few thousand steps take about a second here).
PROGRESS_STEPS = 5000


@no_log_file()
def derived_settings(mech: SpatialMechanism, omega: float | None = None, chain=None):
    """The MuJoCo settings derived for the mechanism at crank speed ω (default the drive's)."""
    chain = assembled_chain(mech) if chain is None else chain
    w0 = mech.drive.omega if omega is None else float(omega)
    model = mujoco.MjModel.from_xml_string(write_spatial_mjcf(mech, chain=chain))
    scan = solve(mech, chain.input_samples(SCAN), chain)
    return derive_settings(mech, chain, scan, model, w0)


@no_log_file()
def check_spatial(mech: SpatialMechanism, samples: int = 360, omega: float | None = None,
                  progress=None, max_steps: int | None = None) -> SpatialCheck:
    """Run the mechanism over one revolution in MuJoCo and compare it with the closed form.
    ``progress(fraction, elapsed seconds)`` is called about every second once the run has lasted
    PROGRESS_AFTER seconds (a heavy chain under strong gravity needs 3e5 steps: a minute). A run
    past ``max_steps`` steps (default ``mujoco.options.MAX_STEPS``) is refused before it starts."""
    from linkgen.mujoco.options import MAX_STEPS, PROGRESS_AFTER, within_budget

    wall0 = time.perf_counter()
    w0 = mech.drive.omega if omega is None else float(omega)
    if not (math.isfinite(w0) and w0 > 0):
        if mech.drive.slides:
            raise SimulationError(f"{'drive.velocity' if omega is None else 'velocity'}: must be > 0 m/s for a MuJoCo "
                                  f"run (it drives the input slider forwards over its range), got {w0!r}")
        raise SimulationError(f"{'drive.omega' if omega is None else 'omega'}: must be > 0 rad/s for a MuJoCo run "
                              f"(it drives the crank forwards through a turn), got {w0!r}")
    chain = assembled_chain(mech)
    scan = solve(mech, chain.input_samples(SCAN), chain)
    settings, scales = derived_settings(mech, w0, chain)
    model = mujoco.MjModel.from_xml_string(write_spatial_mjcf(mech, settings, chain))
    model.actuator(SERVO).biasprm[:] = 0.0  # the viewer's speed servo is off: the rotor holds the speed
    data = mujoco.MjData(model)
    lo, hi = chain.input_range
    if chain.input_slides:  # from the range's start; the compared samples after a lead inside it
        lead = LEAD_RANGE * (hi - lo)
        phi_start, spacing = lo, (hi - lo - lead) / (samples - 1)
    else:
        lead, phi_start, spacing = LEAD, -LEAD, 2 * np.pi / samples
    start = solve(mech, np.array([phi_start]), chain)
    data.qpos[:], data.qvel[:] = joint_state(model, chain, start, 0, w0)
    mean_torque = float(np.mean(forces(mech, scan.phi, w0, 0.0, motion=scan).balancing_torque))
    data.ctrl[model.actuator(DRIVE_ACTUATOR).id] = mean_torque
    dt = settings.timestep
    t_samples = (lead + np.arange(samples) * spacing) / w0
    steps_at = np.rint(t_samples / dt).astype(int)
    within_budget(mech.name, int(steps_at[-1]), dt, MAX_STEPS if max_steps is None else max_steps)
    states = []
    step = 0
    with loads_while_stepping(mech, model, data, model.joint(chain.drive).qposadr[0], chain.phi_s):
        for target in steps_at:
            while step < target:
                mujoco.mj_step(model, data)
                step += 1
                if progress is not None and step % PROGRESS_STEPS == 0:
                    elapsed = time.perf_counter() - wall0
                    if elapsed > PROGRESS_AFTER:
                        progress(step / steps_at[-1], elapsed)
                if not np.all(np.isfinite(data.qacc)):
                    raise SimulationError(f"{mech.name}: MuJoCo diverged at t = {data.time:.6g} s (step {step})")
            states.append((data.time, data.qpos.copy(), data.qvel.copy()))
    states, left = _after_switches(mech, chain, model, states, settings, scales, w0)
    result = _compare(mech, chain, model, states, w0, settings)
    note = "; ".join(x for x in (left, result[2]) if x)
    return SpatialCheck(mech.name, chain.kind, result[0], result[1], step, time.perf_counter() - wall0, settings,
                        scales, note, result[3])


def _after_switches(mech, chain, model, states, settings, scales, w0) -> tuple[list, str]:
    """The samples outside the loop's settling window after a load switches on or off (the
    planar rule, ``mujoco.timing.settle_window``: a soft loop answers a step in its load with a
    transient of a few τ), and a note on those left out."""
    crank = model.joint(chain.drive).qposadr[0]
    phi = np.array([q[crank] for _, q, _ in states]) + chain.phi_s
    edges = switch_angles(mech, float(phi[0]), float(phi[-1]))
    if not edges:
        return states, ""
    # The spatial settings do not measure the loop's conditioning: σ = 1 (a well-conditioned loop).
    sc = Scales(chain.size, w0, scales["loop_acceleration"], 1.0, math.nan, scales["reduced_inertia"],
                scales["tau_gap"], scales["tau_phase"], math.nan, False)
    reach = w0 * settle_window(settings, sc, mech.drive.epsilon, SETTLE_TARGET, float(np.linalg.norm(mech.gravity)))
    hit = np.zeros(phi.shape[0], dtype=bool)
    for edge in edges:
        hit |= (phi >= edge) & (phi <= edge + reach)
    if hit.all():
        raise SimulationError(f"{mech.name}: every sample lies within {math.degrees(reach):.3g}° after a load switch, "
                              "where the loop still settles; nothing is left to compare")
    note = (f"{int(hit.sum())} samples within {math.degrees(reach):.3g}° after {len(edges)} load switch(es) left out "
            "(the loop's transient)")
    return [s for s, h in zip(states, hit) if not h], note


def _halves_apart(mech, chain, model, d) -> float:
    """The largest distance [m] between an RCCC output's points as its two welded halves carry
    them (the half on the ground's pair from B0, the coupler's from B)."""
    g, o = model.body(closing_body(chain)).id, model.body(chain.output).id
    return max(float(np.linalg.norm(d.xpos[g] + d.xmat[g].reshape(3, 3) @ (x - chain.B)
                                    - d.xpos[o] - d.xmat[o].reshape(3, 3) @ (x - chain.b0)))
               for x in [mech.point(p) for p in mech.link(chain.output).points if p != chain.pair_b] + [chain.B])


def _compare(mech, chain, model, states, w0, settings):
    d = mujoco.MjData(model)
    m = len(states)
    crank = model.joint(chain.drive)
    eq = model.equality(loop_name(chain)).id
    cyl = chain.kind == "RCCC"  # the loop closes by a weld: 3 translation rows, then 3 rotation rows
    g = np.array(mech.gravity)
    names = [p for p in mech.points if p not in mech.link("ground").points]
    cf0 = solve(mech, np.array([chain.phi_s]), chain)
    copies = {f"{p}:{link}": (link, p) for link, p in cf0.own}  # a cylindrical pair's later copy (RCCC)
    names += list(copies)
    mj = {p: np.zeros((m, 3, 3)) for p in names}
    phi, om, ep, gap, torque = (np.zeros(m) for _ in range(5))
    react = {k: np.zeros((m, 3)) for k in (chain.drive, chain.pair_a, chain.pair_b, chain.pair_out)}
    moving = (chain.crank, chain.coupler, chain.output)
    spin = {link: np.zeros((m, 3)) for link in moving}
    r6 = np.zeros(6)
    for k, (t, qpos, qvel) in enumerate(states):
        d.time, d.qpos[:], d.qvel[:] = t, qpos, qvel
        d.ctrl[:] = 0.0
        d.ctrl[model.actuator(DRIVE_ACTUATOR).id] = 0.0
        loads_at_state(mech, model, d, float(qpos[crank.qposadr[0]]) + chain.phi_s)
        mujoco.mj_forward(model, d)
        mujoco.mj_rnePostConstraint(model, d)
        phi[k] = qpos[crank.qposadr[0]] + chain.phi_s
        om[k], ep[k] = qvel[crank.dofadr[0]], d.qacc[crank.dofadr[0]]
        torque[k] = d.actuator(DRIVE_ACTUATOR).force[0] - settings.armature * ep[k]
        rows = np.flatnonzero((d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY) & (d.efc_id == eq))
        # the gap across the closing pair: the connect's distance, or (an RCCC's weld) the farthest apart
        # the output's two halves put its points
        gap[k] = _halves_apart(mech, chain, model, d) if cyl else float(np.linalg.norm(d.efc_pos[rows]))
        for p in names:
            sid = model.site(p).id
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_SITE, sid, r6, 0)
            v = r6[3:].copy()
            mujoco.mj_objectAcceleration(model, d, mujoco.mjtObj.mjOBJ_SITE, sid, r6, 0)
            mj[p][k] = (d.site(p).xpos, v, r6[3:] + g)  # MuJoCo reports a − g
        for link in moving:
            mujoco.mj_objectVelocity(model, d, mujoco.mjtObj.mjOBJ_BODY, model.body(link).id, r6, 0)
            spin[link][k] = r6[:3]
        react[chain.drive][k] = d.cfrc_int[model.body(chain.crank).id, 3:]
        if chain.input_slides:  # a slide passes the drive's force along its line: the pair's reaction is the rest
            react[chain.drive][k] -= torque[k] * chain.ka
        react[chain.pair_a][k] = d.cfrc_int[model.body(chain.coupler).id, 3:]
        if cyl:  # the coupler's force on the output's half it carries, through B's hinge and slide
            react[chain.pair_b][k] = d.cfrc_int[model.body(closing_body(chain)).id, 3:]
        else:
            react[chain.pair_b][k] = -d.efc_force[rows]  # the connect's force on the coupler, reversed
        react[chain.pair_out][k] = d.cfrc_int[model.body(chain.output).id, 3:]
    cf = solve(mech, phi, chain)
    size, unit = chain.size, chain.input_unit
    rate = w0 / unit  # the input's rate in its own unit per second: ω, or a slider's v / size
    acc_scale = size * (rate**2 + float(np.abs(ep).max()) / unit) + float(np.linalg.norm(g))
    errors = {}
    def jet_of(p):
        return cf.at(*copies[p]) if p in copies else cf.points[p]

    for p in names:
        pos, vel, acc, _ = jet_motion(jet_of(p), om, ep)
        for i, (what, ref, scale) in enumerate((("position", pos, size), ("velocity", vel, size * rate),
                                                ("acceleration", acc, acc_scale))):
            errors[f"points.{p}.{what}"] = (float(np.abs(mj[p][:, i] - ref).max()) / scale, REL_TOL)
    for link in moving:
        ref = cf.spin[link][0] * om[:, None]
        errors[f"links.{link}.angular_velocity"] = (float(np.abs(spin[link] - ref).max()) / rate, REL_TOL)
    if chain.kind in IDLE_SPIN:  # the coupler's spin about its own line, which nothing drives
        ends = [cf.points[q].d[0] for q in mech.link(chain.coupler).points[:2]]
        axis = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0], axis=1)[:, None]
        errors[f"links.{chain.coupler}.idle_spin"] = (
            float(np.abs(np.einsum("ij,ij->i", spin[chain.coupler], axis)).max()) / rate, REL_TOL)
    fc = forces(mech, phi, om, ep, motion=cf)
    t_scale = float(np.abs(fc.balancing_torque).max()) or 1.0
    drive = "balancing_force" if chain.input_slides else "balancing_torque"  # a slider input's is a force [N]
    errors[drive] = (float(np.abs(torque - fc.balancing_torque).max()) / t_scale, FORCE_TOL)
    note = ""
    if fc.indeterminate == 0:
        f_scale = max(float(np.abs(r.force).max()) for r in fc.reactions.values()) or 1.0
        read_on = {chain.drive: chain.crank, chain.pair_a: chain.coupler, chain.pair_b: chain.output,
                   chain.pair_out: chain.output}  # the body whose force MuJoCo reports above
        for name, r in fc.reactions.items():
            errors[f"reactions.{name}.force"] = (float(np.abs(react[name] - r.force_on(read_on[name])).max()) / f_scale,
                                           FORCE_TOL)
    else:
        note = (f"pair reactions not compared: the {chain.kind} chain is statically indeterminate by {fc.indeterminate} "
                "(its redundant constraints share the load in a way rigid-body statics does not fix)")
    # the inverse route: MuJoCo's inverse dynamics at closed-form states (no integration)
    phi_i = chain.input_samples(INVERSE_SAMPLES)
    t_inv, lam_inv = inverse_torque(mech, phi_i, w0, mech.drive.epsilon, settings)
    fi = forces(mech, phi_i, w0, mech.drive.epsilon)
    ti_scale = float(np.abs(fi.balancing_torque).max()) or 1.0
    errors[f"inverse.{drive}"] = (float(np.abs(t_inv - fi.balancing_torque).max()) / ti_scale, INVERSE_TOL)
    if fc.indeterminate == 0 and not cyl:  # an RCCC's weld carries half the output's inertia as well: not B's force
        fb = fi.reactions[chain.pair_b].force_on(chain.output)
        errors[f"inverse.reactions.{chain.pair_b}.force"] = (
            float(np.abs(lam_inv - fb).max()) / (float(np.abs(fb).max()) or 1.0), INVERSE_TOL)
    samples = {"phi": phi, "omega": om, "epsilon": ep, "gap": gap, "torque": torque, "closed_torque": fc.balancing_torque,
               "points": mj, "closed": {p: jet_motion(jet_of(p), om, ep) for p in names}}
    return errors, float(gap.max()) / size, note, samples


__all__ = ["SpatialCheck", "check_spatial", "derived_settings"]

"""The general route: one variant at a time through the loader and the planar closed form
(``families.planar``: assemble from the lengths — the sketch only chooses each group's mode —,
kinematics, kinetostatics), reduced by ``metrics``. It takes every planar linkage the closed
form takes, and is the reference the four-bar kernel (``fourbar``) is checked against."""

from __future__ import annotations

import numpy as np

from linkgen.errors import LinkgenError
from linkgen.studies.metrics import Layout, reduce


def layout_of(mech) -> Layout:
    """The metric columns of a planar mechanism: its outputs and its joints."""
    from linkgen.model.names import GROUND

    pivoted = {p for r in mech.revolutes if GROUND in r.links for p in r.links if p != GROUND}
    outputs = [(p.name, "slider") for p in mech.prismatics if p.guide == GROUND]
    outputs += [(link.name, "rocker") for link in mech.links if link.name in pivoted and link.name != mech.crank]
    return Layout(tuple(outputs), tuple(r.name for r in mech.revolutes) + tuple(p.name for p in mech.prismatics))


def reason_of(exc: LinkgenError) -> tuple[str, str]:
    """(the error's class name, its message without the costlier look-ups some errors add when
    printed — where the chain does assemble, ``AssemblyError.__str__``)."""
    return type(exc).__name__, Exception.__str__(exc)


def arrays(asm, phi: np.ndarray, layout: Layout) -> dict:
    """The values ``metrics.reduce`` takes, for one assembled variant (each (1, N)).

    Raises:
        LinkgenError: the closed form's (assembly, singular position, balance).
    """
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.kinetostatics import forces
    from linkgen.families.planar.summary import transmission_angles

    mech = asm.mechanism
    f = forces(asm, phi, mech.drive.omega, mech.drive.epsilon)
    kin = solve(asm, phi)
    outputs = {name: (kin.sliders[name].v if kind == "slider" else kin.links[name].angle.v)[None, :]
               for name, kind in layout.outputs}
    mu = transmission_angles(asm, phi)
    least = np.min(np.stack([np.sin(m) for m in mu.values()]), axis=0) if mu else np.ones_like(phi)
    reactions = {j: (np.hypot(*np.asarray(f.reactions[j]).T) if j in f.reactions  # a prismatic: its normal force
                     else np.abs(np.asarray(f.normal_force[j])))[None, :] for j in layout.joints}
    return {"outputs": outputs, "least_d": least[None, :], "torque": np.asarray(f.balancing_torque)[None, :],
            "reactions": reactions, "inertia": np.asarray(f.reduced.inertia)[None, :]}


def variant(data: dict, source: str, phi: np.ndarray, full: bool, layout: Layout) -> tuple[dict | None, str, str]:
    """One variant's metrics (column → float), or None with its failure's class and message."""
    from linkgen.families.planar.assembly import assemble
    from linkgen.pipeline.registry import from_dict

    try:
        mech = from_dict(data, source)
        asm = assemble(mech, sketch_tolerance=None)
        got = arrays(asm, phi, layout)
    except LinkgenError as exc:
        return (None, *reason_of(exc))
    cols = reduce(layout, phi, full, got["outputs"], got["least_d"], got["torque"], got["reactions"], got["inertia"])
    return {k: float(v[0]) for k, v in cols.items()}, "", ""


__all__ = ["arrays", "layout_of", "reason_of", "variant"]

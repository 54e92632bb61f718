"""Published multibody benchmarks against linkgen's machine route (the closed form reduced to the
crank, integrated in time: ``linkgen dynamics``), each quantity with its reference, linkgen's value,
the relative error, the tolerance asked for and the wall time of the run.

- Andrews' squeezing mechanism (models/andrews_squeezer.toml): the IVP test set's reference
  solution at t = 0.03 s (Mazzia & Magherini, problem "andrews", subroutine SOLN: PSIDE on a Cray
  C90 at rtol = atol = 1e-14), the seven angles and the crank's speed; the issue asks for 1e-8 on
  the crank angle. Run twice: as the model is written (the equation's J, M tables, rtol 1e-10) and
  with ``[machine] tables = false, rtol = 1e-12`` (the closed form at every step).
- IFToMM A01, the simple pendulum (validation/benchmarks/iftomm_a01_pendulum.toml): the exact
  motion, Jacobi's elliptic sine, at t = 10 s.
- IFToMM A02, the N-four-bar with N = 2 (validation/benchmarks/iftomm_a02_nfourbar.toml): until the
  bars reach the ground line, the exact motion of the parallelogram (J = 3 kg·m² constant,
  M = −3.5·g·cos φ) by quadrature; there linkgen stops (the rows say how).

    python validation/benchmarks.py            # prints the table (Markdown)
    python validation/benchmarks.py --write    # and puts it into docs/machine.md between its markers

The Andrews rows of the table in docs/machine.md are checked against a run by tests/test_benchmarks.py.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import tempfile
import time
from pathlib import Path


ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from linkgen.errors import LinkgenError  # noqa: E402
from linkgen.machine.along import along_time  # noqa: E402
from linkgen.machine.machine import run_machine  # noqa: E402
from linkgen.machine.reduced import reduce  # noqa: E402
from linkgen.machine.study import load_machine  # noqa: E402

DOC = ROOT / "docs" / "machine.md"
BEGIN, END = "<!-- benchmarks:begin -->", "<!-- benchmarks:end -->"
# The bound on the crank angle after several turns, relative.
CRANK_TOL = 1e-8
# The tight route: the closed form at every step, at this relative tolerance.
TIGHT_RTOL = 1e-12

# IVP test set, problem "andrews", SOLN at t = 0.03 s: β, Θ, γ, Φ, δ, Ω, ε [rad] and β′ [rad/s].
ANDREWS_T = 0.03
ANDREWS = {"β": 15.81077119629904, "Θ": -15.75637105984298, "γ": 0.04082224013073101,
           "Φ": -0.5347301163226948, "δ": 0.5244099658805304, "Ω": 0.5347301163226948,
           "ε": 1.048080741042263, "β′ [rad/s]": 1139.920302151208}


def andrews_angles(links: dict[str, float]) -> dict[str, float]:
    """The benchmark's coordinates from linkgen's link angles [rad] (models/andrews_squeezer.toml's
    frames: each link's x axis from its first point to its second): β the crank's angle, Θ the
    coupler's relative to it (its x axis P → E points along −(cos(β+Θ), sin(β+Θ))), γ the lever's
    (x axis B → E = (sin γ, −cos γ)), δ and ε the rockers' (A → F at δ, A → G = (sin ε, −cos ε)),
    Φ and Ω the rods' relative to them (F → E = (sin(Φ+δ), −cos(Φ+δ)), G → E at Ω + ε)."""
    beta, delta = links["crank.angle"], links["rocker_5.angle"]
    eps = links["rocker_7.angle"] + math.pi / 2
    return {"β": beta, "Θ": links["coupler.angle"] - beta - math.pi, "γ": links["lever.angle"] + math.pi / 2,
            "Φ": links["rod_4.angle"] - delta + math.pi / 2, "δ": delta, "Ω": links["rod_6.angle"] - eps, "ε": eps}


def same_turn(value: float, reference: float) -> float:
    """``value`` moved by whole turns to the turn of ``reference`` (a link angle is known modulo 2π)."""
    return value + 2 * math.pi * round((reference - value) / (2 * math.pi))


@dataclasses.dataclass(frozen=True)
class Row:
    benchmark: str
    quantity: str
    reference: float
    linkgen: float | str
    tolerance: float | None
    seconds: float

    @property
    def error(self) -> float | None:
        return None if isinstance(self.linkgen, str) else abs(self.linkgen - self.reference) / abs(self.reference)

    def cells(self) -> list[str]:
        err = "–" if self.error is None else f"{self.error:.1e}"
        tol = "–" if self.tolerance is None else f"{self.tolerance:g}"
        val = self.linkgen if isinstance(self.linkgen, str) else repr(float(self.linkgen))
        return [self.benchmark, self.quantity, f"{self.reference:.16g}", val, err, tol, f"{self.seconds:.1f}"]


def _run(path: Path, **machine_keys):
    """(assembly, machine, run, wall seconds) of a model's machine, with ``machine_keys`` replacing
    its [machine] keys (``tables``, ``rtol``, ``duration``, …)."""
    asm, machine = load_machine(path)
    machine = dataclasses.replace(machine, **machine_keys)
    t0 = time.perf_counter()
    run = run_machine(machine, reduce(asm, machine.process_load, exact=not machine.tables), samples=2)
    return asm, machine, run, time.perf_counter() - t0


def andrews(tight: bool) -> list[Row]:
    """Andrews' squeezer at t = 0.03 s, as written or by the tight route."""
    keys = {"tables": False, "rtol": TIGHT_RTOL} if tight else {}
    asm, machine, run, wall = _run(ROOT / "models" / "andrews_squeezer.toml", **keys)
    name = (f"Andrews, closed form at every step, rtol {TIGHT_RTOL:g}" if tight else
            f"Andrews, tables, rtol {machine.rtol:g} (the model as written)")
    cols = along_time(asm, run.phi[-1:], run.omega[-1:], run.epsilon[-1:], ("links",))
    links = {k.split(" ")[0]: float(v[0]) for k, v in cols.items()}
    got = andrews_angles(links)
    rows = []
    for q, ref in ANDREWS.items():
        if q == "β′ [rad/s]":
            value = float(run.omega[-1])
        else:
            value = float(run.phi[-1]) if q == "β" else same_turn(got[q], ref)
        label = f"{q.split(' ')[0]}(0.03 s)" + (" [rad/s]" if "rad/s" in q else " [rad]")
        rows.append(Row(name, label, ref, value, CRANK_TOL if q in ("β", "β′ [rad/s]") else None, wall))
    return rows


def pendulum_exact(t: float, g: float = 9.81, length: float = 1.0, theta0: float = math.pi / 2) -> float:
    """The crank angle φ [rad] (from +x, the pendulum released at rest at φ = θ0 − π/2 … here from the
    horizontal, φ = 0) of a lumped-mass pendulum at time t [s]: θ = 2·asin(k·sn(K − √(g/L)·t | k²)),
    k = sin(θ0/2), θ measured from the downward vertical; φ = θ − π/2."""
    from scipy.special import ellipj, ellipk

    k = math.sin(theta0 / 2)
    sn = ellipj(ellipk(k * k) - math.sqrt(g / length) * t, k * k)[0]
    return 2 * math.asin(k * sn) - math.pi / 2


def pendulum(tight: bool) -> list[Row]:
    keys = {"tables": False, "rtol": TIGHT_RTOL} if tight else {}
    _, machine, run, wall = _run(ROOT / "validation" / "benchmarks" / "iftomm_a01_pendulum.toml", **keys)
    name = (f"IFToMM A01 pendulum, closed form at every step, rtol {TIGHT_RTOL:g}" if tight else
            f"IFToMM A01 pendulum, tables, rtol {machine.rtol:g}")
    return [Row(name, f"φ({machine.duration:g} s) [rad], exact: elliptic sine", pendulum_exact(machine.duration),
                float(run.phi[-1]), CRANK_TOL, wall)]


# A02 with N = 2: five bars of 1 kg, 1 m; on the parallelogram branch J = 3·(1/3) + 2·1 = 3 kg·m²
# (the three hinged bars about their pivots, the two couplers translating with the crank pin) and
# the loads' moment M = −g·(3·0.5 + 2·1)·cos φ.
A02_J, A02_ARM = 3.0, 3.5
# Before the bars reach the ground line (φ = 0 at 0.714 s).
A02_T = 0.4


def nfourbar_exact(t: float, g: float = 9.81) -> float:
    """φ [rad] at time t [s] of the A02 parallelogram from φ = 90° at ω = −1 rad/s, falling toward
    φ = 0: t(φ) = ∫_φ^{π/2} dψ / √(1 + 2·3.5·g·(1 − sin ψ)/J) by quadrature, inverted by Brent."""
    from scipy.integrate import quad
    from scipy.optimize import brentq

    def time_at(phi: float) -> float:
        return quad(lambda p: 1.0 / math.sqrt(1.0 + 2 * A02_ARM * g * (1.0 - math.sin(p)) / A02_J), phi, math.pi / 2,
                    epsabs=1e-14, epsrel=1e-13, limit=200)[0]

    return brentq(lambda p: time_at(p) - t, 1e-9, math.pi / 2, xtol=1e-15, rtol=1e-15)


def nfourbar() -> list[Row]:
    path = ROOT / "validation" / "benchmarks" / "iftomm_a02_nfourbar.toml"
    rows = []
    try:
        _run(path)
        what = "ran its 10 s"
    except LinkgenError as exc:
        what = "refused: " + str(exc).split(": ", 1)[-1].split(";")[0]
    rows.append(Row("IFToMM A02 N-four-bar (N = 2), 10 s", "runs through the ground line?", math.nan, what, None, 0.0))
    with tempfile.TemporaryDirectory() as tmp:  # the range above the ground line, as the error suggests
        above = Path(tmp) / path.name
        above.write_text(path.read_text(encoding="utf-8").replace(
            "omega = 1.0", 'omega = 1.0\nrange = ["0.006deg", "179.994deg"]'), encoding="utf-8")
        _, _, run, wall = _run(above, tables=False, rtol=TIGHT_RTOL, duration=A02_T)
    rows.append(Row(f"IFToMM A02, up to {A02_T:g} s (before the ground line), closed form, rtol {TIGHT_RTOL:g}",
                    f"φ({A02_T:g} s) [rad], exact: parallelogram, quadrature", nfourbar_exact(A02_T),
                    float(run.phi[-1]), CRANK_TOL, wall))
    return rows


def table(rows: list[Row]) -> str:
    head = ["benchmark", "quantity", "reference", "linkgen", "relative error", "tolerance", "time [s]"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r.cells()).replace("nan", "–") + " |" for r in rows]
    return "\n".join(lines)


def all_rows() -> list[Row]:
    return andrews(False) + andrews(True) + pendulum(False) + pendulum(True) + nfourbar()


def write_doc(text: str, doc: Path = DOC) -> None:
    """Put ``text`` between the markers of ``doc``."""
    src = doc.read_text(encoding="utf-8")
    a, b = src.index(BEGIN) + len(BEGIN), src.index(END)
    doc.write_text(src[:a] + "\n" + text + "\n" + src[b:], encoding="utf-8")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--write", action="store_true", help=f"also write the table into {DOC.relative_to(ROOT)}")
    args = ap.parse_args(argv)
    rows = all_rows()
    text = table(rows)
    print(text)
    if args.write:
        write_doc(text)
    bad = [r for r in rows if r.tolerance is not None and not (r.error is not None and r.error <= r.tolerance)]
    for r in bad:
        print(f"over its tolerance: {r.benchmark}: {r.quantity}", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

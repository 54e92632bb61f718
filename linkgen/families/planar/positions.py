"""Where every point and link is at a set of crank angles: the input of every drawing.

Class-II mechanisms come from the closed-form Assur-group solution; mechanisms with groups of
class III and higher from the numeric pose (``planar.pose.state``). Singular poses (dead centres)
are drawn like any other: only positions are needed."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.errors import StructureError
from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.geometry import GuideShape, LinkShape, guide_shapes, link_shapes

# Crank angles along a traced point path over a full revolution: one every 0.5°, so that the
# polyline's chord error on a path of curvature radius r is below r·(1 - cos 0.25°) ≈ 1e-5·r.
PATH_SAMPLES = 721


@dataclass(frozen=True)
class Positions:
    """Positions at crank angles ``phi`` (n,) [rad].

    Attributes:
        points: every named point's world position, (n, 2) [m].
        angles: every link's angle (its x axis against the world x axis), (n,) [rad].
        shapes, guides: the links' local shapes and the prismatic pairs (``model.geometry``).
    """

    mechanism: Mechanism
    phi: np.ndarray
    points: dict[str, np.ndarray]
    angles: dict[str, np.ndarray]
    shapes: dict[str, LinkShape]
    guides: dict[str, GuideShape]

    def __len__(self) -> int:
        return int(self.phi.shape[0])

    def local_to_world(self, link: str, local, i: int) -> np.ndarray:
        """World position (2,) [m] at angle index ``i`` of a point given in ``link``'s frame."""
        first = self.mechanism.link(link).points[0]
        th = float(self.angles[link][i])
        w = np.asarray(local, dtype=float) - self.shapes[link].local[first]
        c, s = math.cos(th), math.sin(th)
        return self.points[first][i] + np.array([c * w[0] - s * w[1], s * w[0] + c * w[1]])

    def guide_line(self, pair: str, i: int) -> tuple[np.ndarray, np.ndarray]:
        """The guide line of prismatic ``pair`` at index ``i``: base point (2,) [m], unit direction (2,)."""
        g = self.guides[pair]
        th = float(self.angles[g.guide][i]) + g.alpha
        return self.local_to_world(g.guide, g.base, i), np.array([math.cos(th), math.sin(th)])

    def _world(self, link: str, local) -> np.ndarray:
        """World positions (n, 2) [m] at every angle of a point given in ``link``'s frame."""
        first = self.mechanism.link(link).points[0]
        th = np.asarray(self.angles[link], dtype=float)
        w = np.asarray(local, dtype=float) - self.shapes[link].local[first]
        c, s = np.cos(th), np.sin(th)
        return self.points[first] + np.stack([c * w[0] - s * w[1], s * w[0] + c * w[1]], axis=-1)

    def slider_travel(self, pair: str) -> np.ndarray:
        """The slider point's displacement along its guide from the guide's base, (n,) [m]."""
        g = self.guides[pair]
        th = np.asarray(self.angles[g.guide], dtype=float) + g.alpha
        d = self._world(g.slider, g.point) - self._world(g.guide, g.base)
        return d[:, 0] * np.cos(th) + d[:, 1] * np.sin(th)

    def travel(self, pair: str) -> tuple[float, float]:
        """The least and greatest of ``slider_travel`` [m]: the stroke's ends on the guide line,
        in the guide's frame, which every drawn guide (``linkgen draw``, the MJCF) spans."""
        t = self.slider_travel(pair)
        return float(t.min()), float(t.max())

    def bounds(self) -> tuple[float, float, float, float]:
        """xmin, xmax, ymin, ymax [m] of every point over every angle."""
        xy = np.concatenate([p for p in self.points.values()])
        return float(xy[:, 0].min()), float(xy[:, 0].max()), float(xy[:, 1].min()), float(xy[:, 1].max())

    def size(self) -> float:
        """Diagonal of ``bounds`` [m] (> 0: the crank's two points differ)."""
        x0, x1, y0, y1 = self.bounds()
        return float(math.hypot(x1 - x0, y1 - y0))


def drive_angles(mech: Mechanism, n: int = PATH_SAMPLES) -> np.ndarray:
    """``n`` crank angles [rad] spanning the drive's range (its ends included)."""
    return np.linspace(mech.drive.start, mech.drive.stop, n)


def guide_travel(mech: Mechanism, n: int = PATH_SAMPLES) -> dict[str, tuple[float, float]]:
    """Each prismatic pair's ``Positions.travel`` over the drive's range (``n`` angles).

    Raises:
        AssemblyError: the mechanism cannot be assembled at some angle of the range.
    """
    paths = positions(mech, drive_angles(mech, n))
    return {pair: paths.travel(pair) for pair in paths.guides}


def positions(mech: Mechanism, phi) -> Positions:
    """Positions at crank angles ``phi`` [rad] (scalar or (n,)).

    Raises:
        AssemblyError: the mechanism cannot be assembled at some of the angles (names them).
    """
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    shapes = link_shapes(mech)
    guides = guide_shapes(mech, shapes)
    try:
        from linkgen.families.planar.kinematics import solve

        kin = solve(mech, phi, on_singular="mark")
        points = {k: np.asarray(v.p) for k, v in kin.points.items()}
        angles = {k: np.asarray(p.angle.v) for k, p in kin.links.items()}
    except StructureError:  # class III and higher: the numeric pose
        from linkgen.families.planar.pose import state

        order = np.argsort(phi, kind="stable")
        st = state(mech, phi[order])
        back = np.empty_like(order)
        back[order] = np.arange(order.shape[0])
        angles = {k: np.asarray(st.angle[k])[back] for k in st.angle}
        points = {}
        for link in mech.links:
            for p in link.points:
                points.setdefault(p, st.point(link.name, shapes[link.name].local[p])[back])
    angles.setdefault(GROUND, np.zeros(phi.shape[0]))
    return Positions(mech, phi, points, {k: np.broadcast_to(v, phi.shape) for k, v in angles.items()},
                     shapes, guides)


__all__ = ["PATH_SAMPLES", "Positions", "drive_angles", "guide_travel", "positions"]

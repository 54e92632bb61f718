"""The plots a designer looks at first (matplotlib, PNG), into the study's folder:

* one field: ``metrics.png``, the main metrics against it, the failing stretches shaded;
* two fields: ``map_<metric>.png``, each main metric over the two fields (a grid as cells, a
  Latin hypercube as points), the failing variants shaded grey;
* more: ``parallel.png``, parallel coordinates of the fields and the main metrics (each axis
  scaled to its range), the failing variants in grey.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

# The metrics plotted, when the table has them: what a designer reads first.
MAIN = ("min_transmission_angle [rad]", "peak_balancing_torque [N·m]")
# Lines drawn at most on parallel coordinates (a random subset beyond, seeded: the same plot).
MAX_LINES = 600
# Each parallel axis spans these percentiles of its values.
AXIS_RANGE = (1.0, 99.0)
_FAILED = "#bbbbbb"


def _column(table, name: str) -> np.ndarray:
    return np.array([np.nan if x is None else x for x in table.column(name).to_pylist()], dtype=float)


def _label(name: str) -> str:
    if name.endswith("[rad]"):
        return name.replace("[rad]", "[deg]")
    return name


def _shown(name: str, v: np.ndarray) -> np.ndarray:
    return np.degrees(v) if name.endswith("[rad]") else v


def plot_study(table, study, out: Path) -> list[Path]:
    """The plots of a study's table into ``out``; the paths written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fields = [f.column for f in study.fields]
    metrics = [m for m in MAIN if m in table.column_names]
    failed = np.array([s != "ok" for s in table.column("status").to_pylist()])
    x = [_column(table, f) for f in fields]
    paths = []
    if len(fields) == 1:
        fig, axes = plt.subplots(len(metrics), 1, figsize=(6, 2.6 * len(metrics)), sharex=True, squeeze=False)
        order = np.argsort(x[0], kind="stable")
        for ax, m in zip(axes[:, 0], metrics):
            ax.plot(x[0][order], _shown(m, _column(table, m))[order], ".-", color="C0")
            for xi in x[0][failed]:
                ax.axvspan(xi, xi, color=_FAILED)
            if failed.any():
                ax.scatter(x[0][failed], np.zeros(failed.sum()), marker="x", color="grey", label="fails")
                ax.legend(loc="best")
            ax.set_ylabel(_label(m))
            ax.grid(alpha=0.3)
        axes[-1, 0].set_xlabel(fields[0])
        paths.append(_save(fig, out / "metrics.png"))
    elif len(fields) == 2:
        for m in metrics:
            fig, ax = plt.subplots(figsize=(6.4, 5))
            v = _shown(m, _column(table, m))
            grid = study.sampling["method"] == "grid"
            if grid:
                n0, n1 = study.fields[0].count, study.fields[1].count
                X, Y = x[0].reshape(n0, n1), x[1].reshape(n0, n1)
                ax.pcolormesh(X, Y, failed.reshape(n0, n1).astype(float), cmap="Greys", vmin=0, vmax=4,
                              shading="nearest")
                mesh = ax.pcolormesh(X, Y, np.ma.masked_invalid(v.reshape(n0, n1)), cmap="viridis",
                                     shading="nearest")
            else:
                ax.scatter(x[0][failed], x[1][failed], marker="x", color=_FAILED, s=12)
                mesh = ax.scatter(x[0][~failed], x[1][~failed], c=v[~failed], cmap="viridis", s=12)
            fig.colorbar(mesh, ax=ax, label=_label(m))
            ax.set_xlabel(fields[0])
            ax.set_ylabel(fields[1])
            ax.set_title(f"{_label(m)}; grey: the variant fails ({int(failed.sum())} of {failed.size})", fontsize=9)
            slug = m.split(" [")[0]
            paths.append(_save(fig, out / f"map_{slug}.png"))
    else:
        names = fields + metrics
        cols = [_shown(n, _column(table, n)) for n in names]
        rows = np.arange(failed.size)
        if rows.size > MAX_LINES:
            rows = np.sort(np.random.default_rng(0).choice(rows, MAX_LINES, replace=False))
        fig, ax = plt.subplots(figsize=(1.6 * len(names) + 2, 4.5))
        scaled, ranges = [], []
        for c in cols:  # each axis over its 1–99 % range: one extreme variant does not flatten the rest
            fin = c[np.isfinite(c)]
            lo, hi = (np.percentile(fin, AXIS_RANGE) if fin.size else (0.0, 1.0))
            ranges.append((lo, hi))
            scaled.append(np.clip((c - lo) / (hi - lo), -0.02, 1.02) if hi > lo else np.full_like(c, 0.5))
        s = np.stack(scaled, axis=1)
        colour = np.clip(scaled[len(fields)], 0.0, 1.0) if metrics else np.zeros(failed.size)
        cmap = plt.get_cmap("viridis")
        for r in rows[~failed[rows]]:
            ax.plot(range(len(names)), s[r], color=cmap(float(colour[r])), lw=0.6, alpha=0.5)
        for r in rows[failed[rows]]:
            ax.plot(range(len(fields)), s[r, :len(fields)], color="0.35", lw=0.8, alpha=0.6)
        for k, (lo, hi) in enumerate(ranges):
            ax.axvline(k, color="k", lw=0.8)
            ax.text(k, -0.06, f"{lo:.3g}", ha="center", va="top", fontsize=7)
            ax.text(k, 1.06, f"{hi:.3g}", ha="center", va="bottom", fontsize=7)
        ax.set_ylim(-0.15, 1.15)
        ax.set_xticks(range(len(names)), [_label(n) for n in names], rotation=20, ha="right", fontsize=8)
        ax.set_yticks([])
        ax.set_title(f"{rows.size} of {failed.size} variants, each axis over its 1–99 % range, coloured by "
                     f"{_label(metrics[0]) if metrics else 'nothing'}; dark grey: fails", fontsize=9)
        paths.append(_save(fig, out / "parallel.png"))
    return paths


def _save(fig, path: Path) -> Path:
    import matplotlib.pyplot as plt

    from linkgen.outputs import save_figure

    fig.tight_layout()
    save_figure(fig, path, dpi=90)
    plt.close(fig)
    return path


__all__ = ["MAIN", "plot_study"]

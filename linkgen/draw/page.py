"""One self-contained interactive HTML page of a mechanism (``linkgen page``), written with plotly
(plotly.js inline: no server, no network): the mechanism moving under a slider of its input (a
crank angle φ, or a prismatic input's stroke s) with a play button, its vectors as traces the legend turns on and off, the curves of chosen quantities
with a cursor at the current angle, and the design summary. Every family gives the same
``PageData``; this module only lays it out."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

# Plotly trace names the page and its browser test look up.
PIN_TRACE = "crank pin"
SLIDER_TRACE = "driven slider"  # the pin's trace of a prismatic input: the driven slider's point
CURSOR_TRACE = "cursor"
MECHANISM_COLOR, PIN_COLOR = "rgb(64,115,204)", "rgb(217,77,51)"
VECTOR_COLORS = {"velocity": "rgb(26,140,51)", "acceleration": "rgb(153,26,153)", "forces": "rgb(204,26,26)"}


@dataclass(frozen=True)
class PageData:
    """What the page shows, at input values ``phi`` (n,): crank angles [rad], or with ``stroke`` a
    prismatic input's strokes s [m] (the slider, the curves' axis and their cursor say which).

    lines: (n, k, 2) [m] the mechanism's polylines at each angle, NaN rows breaking them.
    points: name → (n, 2) [m] the named points (drawn with their names).
    pin: (n, 2) [m] the crank pin (its own trace, PIN_TRACE), or a prismatic input's slider point
        (SLIDER_TRACE).
    vectors: what → (n, m, 2) [m] arrow segments on the drawing (tail, tip, NaN), to the scale in
        ``vector_scales`` (what → "1 m of drawing = X unit").
    curves: label → (n,) values, each label with its unit in brackets.
    fixed: (k, 2) [m] what does not move (the ground, a cam's base circle), NaN-broken.
    axes: the drawing's axis names (e.g. "x [m]", "y [m]").
    mujoco: label → (φ (m,) [rad] or s (m,) [m], values (m,)): MuJoCo's run of a curve, drawn beside it.
    """

    title: str
    phi: np.ndarray
    lines: np.ndarray
    points: Mapping[str, np.ndarray]
    pin: np.ndarray
    vectors: Mapping[str, np.ndarray] = field(default_factory=dict)
    vector_scales: Mapping[str, str] = field(default_factory=dict)
    curves: Mapping[str, np.ndarray] = field(default_factory=dict)
    summary: tuple[str, ...] = ()
    fixed: np.ndarray | None = None
    axes: tuple[str, str] = ("x [m]", "y [m]")
    mujoco: Mapping[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    start: int = 0  # the frame the page opens at (the drawing's default pose)
    stroke: bool = False  # the input is a stroke s [m], not a crank angle φ [rad]

    def input_axis(self) -> np.ndarray:
        """The input values as the curves' axis shows them: degrees of φ, or metres of s."""
        return np.asarray(self.phi, dtype=float) if self.stroke else np.degrees(self.phi)

    @property
    def input_title(self) -> str:
        return "s [m]" if self.stroke else "φ [°]"

    @property
    def inputs_text(self) -> str:
        """How many input values the page shows, worded for the input (``72 crank angles``)."""
        return f"{len(self.phi)} {'stroke positions s [m]' if self.stroke else 'crank angles'}"

    def input_text(self, i: int) -> str:
        """The slider's label of frame ``i``."""
        return f"{float(self.phi[i]):.4g} m" if self.stroke else f"{math.degrees(float(self.phi[i])):.0f}°"


def arrow_segments(at: np.ndarray, vec: np.ndarray, scale: float) -> np.ndarray:
    """(n, 3m, 2): for m arrows at (n, m, 2) with vectors (n, m, 2) drawn at ``scale`` [unit per m]:
    tail, tip and a NaN break each, with a head of two strokes folded into the tip."""
    n, m = at.shape[:2]
    tip = at + vec / scale
    d = tip - at
    back = -0.18 * d
    side = 0.08 * np.stack([-d[..., 1], d[..., 0]], axis=-1)
    nan = np.full((n, m, 2), np.nan)
    rows = [at, tip, tip + back + side, tip, tip + back - side, nan]
    return np.stack(rows, axis=2).reshape(n, 6 * m, 2)


def _xy(a: np.ndarray) -> tuple[list, list]:
    return [None if not math.isfinite(v) else float(v) for v in a[:, 0]], \
           [None if not math.isfinite(v) else float(v) for v in a[:, 1]]


def _moving(data: PageData, i: int) -> list[dict]:
    """The traces that change with the angle, in a fixed order (frames replace them by index)."""
    import plotly.graph_objects as go

    names = list(data.points)
    px = np.array([data.points[n][i] for n in names]) if names else np.zeros((0, 2))
    out = [go.Scatter(x=_xy(data.lines[i])[0], y=_xy(data.lines[i])[1], mode="lines", name="mechanism",
                      line=dict(color=MECHANISM_COLOR, width=4), xaxis="x", yaxis="y", hoverinfo="skip"),
           go.Scatter(x=list(px[:, 0]), y=list(px[:, 1]), mode="markers+text", text=names, textposition="top right",
                      name="points", marker=dict(color="white", size=9, line=dict(color="black", width=1.5)),
                      xaxis="x", yaxis="y"),
           go.Scatter(x=[float(data.pin[i, 0])], y=[float(data.pin[i, 1])], mode="markers",
                      name=SLIDER_TRACE if data.stroke else PIN_TRACE,
                      marker=dict(color=PIN_COLOR, size=12, line=dict(color="black", width=1)), xaxis="x", yaxis="y")]
    for what, seg in data.vectors.items():
        x, y = _xy(seg[i])
        out.append(go.Scatter(x=x, y=y, mode="lines", name=f"{what} ({data.vector_scales.get(what, '')})",
                              line=dict(color=VECTOR_COLORS.get(what, "black"), width=2), xaxis="x", yaxis="y",
                              visible=True if what == "velocity" else "legendonly", hoverinfo="skip"))
    deg = float(data.input_axis()[i])
    for k, (label, ys) in enumerate(data.curves.items()):
        out.append(go.Scatter(x=[deg], y=[float(ys[i])], mode="markers", name=f"{CURSOR_TRACE}: {label}",
                              marker=dict(color="black", size=9), xaxis="x2", yaxis=f"y{k + 2}", showlegend=False))
    return out


def page_figure(data: PageData):
    """The plotly figure of ``data``: the drawing on the left, the curves stacked on the right."""
    import plotly.graph_objects as go

    deg = data.input_axis()
    ncurves = len(data.curves)
    moving = _moving(data, data.start)
    fixed = []
    if data.fixed is not None:
        x, y = _xy(data.fixed)
        fixed.append(go.Scatter(x=x, y=y, mode="lines", name="frame", line=dict(color="gray", width=1.5, dash="dot"),
                                xaxis="x", yaxis="y", hoverinfo="skip"))
    curves = []
    for k, (label, ys) in enumerate(data.curves.items()):
        curves.append(go.Scatter(x=list(deg), y=list(map(float, ys)), mode="lines", name=label, xaxis="x2",
                                 yaxis=f"y{k + 2}", line=dict(width=2)))
        if label in data.mujoco:
            mx, my = data.mujoco[label]
            curves.append(go.Scatter(x=list(np.asarray(mx, dtype=float) if data.stroke else np.degrees(mx)), y=list(map(float, my)), mode="lines",
                                     name=f"{label}, MuJoCo", xaxis="x2", yaxis=f"y{k + 2}",
                                     line=dict(width=1.5, dash="dash")))
    fig = go.Figure(data=moving + fixed + curves)
    parts = [data.lines.reshape(-1, 2), data.pin] + [v.reshape(-1, 2) for v in data.vectors.values()]
    parts += [data.fixed] if data.fixed is not None else []
    allxy = np.concatenate(parts)
    allx, ally = allxy[:, 0], allxy[:, 1]
    x0, x1, y0, y1 = np.nanmin(allx), np.nanmax(allx), np.nanmin(ally), np.nanmax(ally)
    pad = 0.15 * max(x1 - x0, y1 - y0)
    layout = dict(title=dict(text=data.title, font=dict(size=14)), height=860, width=1240, template="plotly_white",
                  xaxis=dict(domain=[0.0, 0.55], range=[x0 - pad, x1 + pad], title=data.axes[0], constrain="domain"),
                  yaxis=dict(domain=[0.36, 1.0], range=[y0 - pad, y1 + pad], title=data.axes[1], scaleanchor="x",
                             scaleratio=1.0),
                  legend=dict(x=0.9, y=1.0, yanchor="top", font=dict(size=10)), margin=dict(t=70, b=40))
    h = 0.76 / max(ncurves, 1)
    layout["xaxis2"] = dict(domain=[0.62, 0.88], title=data.input_title, anchor=f"y{ncurves + 1}")
    for k, label in enumerate(data.curves):
        layout[f"yaxis{k + 2}"] = dict(domain=[1.0 - (k + 1) * h + 0.06, 1.0 - k * h], title=dict(text=label, font=dict(size=10)),
                                       anchor="x2")
    frames, steps = [], []
    ids = list(range(len(moving)))
    for i, d in enumerate(deg):
        name = f"{d:.6g}"
        frames.append(go.Frame(data=_moving(data, i), traces=ids, name=name))
        steps.append(dict(method="animate", label=data.input_text(i), args=[[name], dict(mode="immediate", frame=dict(
            duration=0, redraw=False), transition=dict(duration=0))]))
    layout["sliders"] = [dict(active=data.start, steps=steps, x=0.07, y=0.27, len=0.48, yanchor="top",
                              currentvalue=dict(prefix="s = " if data.stroke else "φ = "), pad=dict(t=40))]
    layout["updatemenus"] = [dict(type="buttons", x=0.0, y=0.27, yanchor="top", pad=dict(t=40), showactive=False,
                                  buttons=[dict(label="▶ play", method="animate", args=[None, dict(
                                      frame=dict(duration=60, redraw=False), fromcurrent=True, transition=dict(duration=0))]),
                                           dict(label="❚❚", method="animate", args=[[None], dict(
                                               mode="immediate", frame=dict(duration=0, redraw=False))])])]
    if data.summary:
        layout["annotations"] = [dict(text="<b>design summary</b><br>" + "<br>".join(data.summary), xref="paper",
                                      yref="paper", x=0.0, y=0.1, xanchor="left", yanchor="top", align="left",
                                      showarrow=False, bgcolor="rgb(248,248,235)", bordercolor="gray", font=dict(size=11))]
    fig.update_layout(**layout)
    fig.frames = frames
    return fig


def write_page(data: PageData, out: Path) -> None:
    """Write the page of ``data`` to ``out`` (.html): one file, plotly.js inline, no network."""
    fig = page_figure(data)
    html = fig.to_html(include_plotlyjs=True, full_html=True, auto_play=False,
                       config=dict(displaylogo=False, responsive=False), div_id="linkgen-page")
    Path(out).write_text(html, encoding="utf-8")


__all__ = ["CURSOR_TRACE", "PIN_TRACE", "SLIDER_TRACE", "PageData", "arrow_segments", "page_figure", "write_page"]

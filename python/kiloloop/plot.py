"""PNG plots of SIL logs (matplotlib, headless Agg backend).

One panel per entry of `panels`, all against log["t"]: a Panel, or the tuple
(title, signal, reference or None, unit or None). Legends name components as the log describes
them (SignalLog.describe: joint names, x/y/z, roll/pitch, feet), else `signal[i]`; the y label is
the signal and its unit (the panel's, else the log's). A reference is drawn dashed in its
component's colour, wide and translucent under the signal so that it shows even where the
signal tracks it, with one legend entry "reference (dashed): NAME". Thresholds (a criterion's
bound) are horizontal dotted lines: `thresholds={signal: [(op, value, label[, t0]), ...]}`, value
in the signal's plotted unit (op: the side that passes, "<" below; t0 [s]: the bound holds from
then on, default the whole run), drawn on every panel that shows that signal, one legend entry
"criterion: LABEL" per label (default "signal op value"; each its own dash pattern);
scenarios/plots.py builds them from a scenario's criteria. Panels with the same `group` share
their y range (e.g. the same signal with a feed-forward on and off).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

THRESHOLD_COLOUR = "tab:red"
THRESHOLD_STYLES = [":", "-.", (0, (5, 3))]  # one per criterion on a panel, in turn
REFERENCE_COLOUR = "0.35"  # grey of the reference's legend entry
# A wide translucent dashed band under the signal's thin solid line: it shows even where the
# signal tracks it exactly.
REFERENCE_STYLE = {"ls": (0, (3, 2)), "lw": 3.6, "alpha": 0.4}


@dataclass(frozen=True)
class Panel:
    title: str
    signal: str
    ref: str | None = None      # a signal of the same shape, drawn dashed
    unit: str | None = None     # None: the log's unit for the signal
    group: str | None = None    # panels of one group share their y range


def as_panel(entry) -> Panel:
    """A Panel from a Panel or a tuple (title, signal, ref, unit[, group])."""
    return entry if isinstance(entry, Panel) else Panel(*entry)


def _columns(log, name: str) -> np.ndarray:
    y = np.asarray(log[name], dtype=float)
    return y[:, None] if y.ndim == 1 else y.reshape(len(y), -1)


def _describe(log, name: str, what: str):
    """log.unit / components / label when the log is a SignalLog, None for a plain dict."""
    fn = getattr(log, what, None)
    return fn(name) if callable(fn) else None


def component_labels(log, name: str) -> list[str]:
    """Legend labels of a signal's columns: the log's component names when they fit, else
    name[i] (a scalar signal: its label, else its name)."""
    y = _columns(log, name)
    names = _describe(log, name, "components")
    if names is not None and len(names) == y.shape[1]:
        return list(names)
    if np.asarray(log[name]).ndim == 1:
        return [_describe(log, name, "label") or name]
    return [f"{name}[{i}]" for i in range(y.shape[1])]


def y_label(log, panel: Panel) -> str:
    unit = panel.unit if panel.unit is not None else (_describe(log, panel.signal, "unit") or "")
    return f"{panel.signal} [{unit}]" if unit else panel.signal


def figure(log, panels, title: str = "", thresholds: dict | None = None):
    """The matplotlib Figure of plot_log (not saved; no pyplot state is kept)."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    panels = [as_panel(p) for p in panels]
    thresholds = thresholds or {}
    t = np.asarray(log["t"], dtype=float)
    height = 3.0 if len(panels) <= 5 else 2.4
    fig = Figure(figsize=(12, height * len(panels)), layout="constrained")
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for ax, p in zip(axes, panels):
        y = _columns(log, p.signal)
        labels = component_labels(log, p.signal)
        ref = _columns(log, p.ref) if p.ref is not None else None
        for i in range(y.shape[1]):
            line, = ax.plot(t, y[:, i], lw=1.1, label=labels[i], zorder=2)
            if ref is not None and i < ref.shape[1]:
                ax.plot(t, ref[:, i], ls=REFERENCE_STYLE["ls"], lw=REFERENCE_STYLE["lw"],
                        alpha=REFERENCE_STYLE["alpha"], color=line.get_color(), zorder=1)
        handles, names = ax.get_legend_handles_labels()
        if ref is not None:
            handles.append(Line2D([], [], color=REFERENCE_COLOUR, **REFERENCE_STYLE))
            names.append(f"reference (dashed): {p.ref}")
        styles: dict[str, object] = {}  # legend text -> its line style (one per criterion)
        for entry in thresholds.get(p.signal, ()):
            op, value, label = entry[:3]
            t0 = entry[3] if len(entry) > 3 else None
            text = label or f"{p.signal} {op} {value:g}"
            if text not in styles:
                styles[text] = THRESHOLD_STYLES[len(styles) % len(THRESHOLD_STYLES)]
                handles.append(Line2D([], [], ls=styles[text], lw=1.4, color=THRESHOLD_COLOUR))
                names.append(f"criterion: {text}")
            style = dict(ls=styles[text], lw=1.4, color=THRESHOLD_COLOUR, zorder=4)
            if t0 is None:
                ax.axhline(value, **style)
            else:
                # A run shorter than t0 is judged on its last tick (as the scenarios do).
                ax.hlines(value, min(t0, t[-1]), t[-1], **style)
        ax.set_title(p.title, loc="left", fontsize=9)
        ax.set_ylabel(y_label(log, p))
        ax.grid(True, alpha=0.3)
        if handles:
            ax.legend(handles, names, loc="upper left", bbox_to_anchor=(1.005, 1.0), fontsize=7,
                      ncol=1 if len(names) <= 10 else 2, frameon=False, handlelength=3.5)
    groups: dict[str, list] = {}
    for ax, p in zip(axes, panels):
        if p.group is not None:
            groups.setdefault(p.group, []).append(ax)
    for members in groups.values():
        lo = min(ax.get_ylim()[0] for ax in members)
        hi = max(ax.get_ylim()[1] for ax in members)
        for ax in members:
            ax.set_ylim(lo, hi)
    axes[-1].set_xlabel("time [s]")
    if title:
        fig.suptitle(title)
    return fig


def legend_labels(fig) -> list[list[str]]:
    """The legend texts of each panel of a figure(), top to bottom."""
    out = []
    for ax in fig.axes:
        legend = ax.get_legend()
        out.append([] if legend is None else [x.get_text() for x in legend.get_texts()])
    return out


def plot_log(log, panels, path, title: str = "", thresholds: dict | None = None) -> Path:
    """Writes figure(log, panels, title, thresholds) as a PNG; returns the path written."""
    fig = figure(log, panels, title, thresholds)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    return path

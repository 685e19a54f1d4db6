"""PNG plots of SIL logs (matplotlib, headless Agg backend)."""
from __future__ import annotations

from pathlib import Path

import numpy as np


def plot_log(log, panels, path, title: str = "") -> Path:
    """Draws one panel per (title, signal, reference or None, unit) against log["t"].

    Each component of a vector signal gets its own colour; its reference is dashed in the same
    colour. Returns the path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = log["t"]
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 3.0 * len(panels)), sharex=True,
                             squeeze=False)
    for ax, (panel_title, name, ref, unit) in zip(axes[:, 0], panels):
        y = log[name] if log[name].ndim > 1 else log[name][:, None]
        for i in range(y.shape[1]):
            line, = ax.plot(t, y[:, i], lw=1.2, label=f"{name}[{i}]")
            if ref is not None:
                r = log[ref] if log[ref].ndim > 1 else log[ref][:, None]
                ax.plot(t, r[:, i], ls="--", lw=1.0, color=line.get_color())
        ax.set_ylabel(f"{panel_title} [{unit}]")
        ax.grid(True, alpha=0.3)
        if y.shape[1] <= 8:
            ax.legend(loc="upper right", fontsize=7, ncol=min(y.shape[1], 6))
    axes[-1, 0].set_xlabel("time [s]")
    if title:
        fig.suptitle(title + ("   (dashed: reference)" if any(p[2] for p in panels) else ""))
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

"""Figures for the exploration experiments (matplotlib, Agg backend).

* :func:`box_plot` — mission time per team size and method, as in seed 000 Figures 6 and 8.
* :func:`snapshots` — panels of one mission at its key moments (task found, gossip, completion, end), as in
  Figures 5 and 7: true obstacles, area covered so far (recomputed from the recorded trajectories with the
  same lidar), trails, robots, their common-belief particles (hollow), the comm range, tasks and home.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from sim.explore import METHODS, MissionHistory  # noqa: E402
from sim.grid import LidarModel  # noqa: E402

__all__ = ["box_plot", "snapshots", "key_frames"]

_COLOURS = {"epistemic": "tab:green", "flock": "tab:red", "ideal": "tab:blue"}


def box_plot(rows: Sequence[dict], path: str | Path, *, case: int, title: str | None = None) -> Path:
    """Box plot of mission time [s] vs team size, one box per method (Figures 6/8)."""
    rows = [r for r in rows if r["case"] == case]
    sizes = sorted({r["n_robots"] for r in rows})
    methods = [m for m in METHODS if any(r["method"] == m for r in rows)]
    fig, ax = plt.subplots(figsize=(7, 4))
    width = 0.8 / max(len(methods), 1)
    for k, m in enumerate(methods):
        data = [[r["mission_time"] for r in rows if r["method"] == m and r["n_robots"] == n] for n in sizes]
        pos = np.arange(len(sizes)) + (k - (len(methods) - 1) / 2) * width
        bp = ax.boxplot(data, positions=pos, widths=width * 0.9, patch_artist=True, manage_ticks=False)
        for patch in bp["boxes"]:
            patch.set_facecolor(_COLOURS.get(m, "grey"))
            patch.set_alpha(0.6)
        ax.plot([], [], color=_COLOURS.get(m, "grey"), lw=6, alpha=0.6, label=m)
    ax.set_xticks(np.arange(len(sizes)), [str(n) for n in sizes])
    ax.set_xlabel("number of robots")
    ax.set_ylabel("mission time [s]")
    ax.set_title(title or f"Case Study {'I' if case == 1 else 'II'}: mission time")
    ax.legend()
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def key_frames(hist: MissionHistory, k: int = 4) -> list[int]:
    """Indices of up to ``k`` frames: after the split, first discovery, first completion, the end."""
    times = hist.times
    if len(times) == 0:
        return []
    wanted = []
    for kind in ("disconnect", "discover", "allocate", "complete"):
        ev = next((e for e in hist.events if e[1] == kind), None)
        if ev is not None:
            wanted.append(ev[0] + (4.0 if kind in ("disconnect", "allocate") else 0.0))
    wanted.append(times[-1])
    idx = sorted({int(np.clip(np.searchsorted(times, t), 0, len(times) - 1)) for t in wanted})
    while len(idx) > k:
        idx.pop(len(idx) // 2 if len(idx) > 2 else 0)
    return idx


def _coverage(hist: MissionHistory, upto: int, lidar: LidarModel) -> np.ndarray:
    seen = np.zeros(hist.world.shape, dtype=bool)
    flat = seen.ravel()
    for t in range(0, upto + 1, 2):
        for xy in hist.positions[t]:
            free, hit = lidar.scan(hist.world.occupied, xy)
            flat[free] = True
            flat[hit] = True
    return seen


def snapshots(hist: MissionHistory, path: str | Path, *, frames: Sequence[int] | None = None,
              comm_range: float = 10.0, lidar_range: float = 5.0, title: str = "") -> Path:
    """A row of panels of one mission (Figures 5 and 7)."""
    frames = list(frames) if frames is not None else key_frames(hist)
    if not frames:
        frames = [0]
    lidar = LidarModel(lidar_range, 90, hist.world.resolution)
    n = hist.positions.shape[1] if hist.positions.ndim == 3 else 0
    cmap = plt.get_cmap("tab10")
    w, h = hist.world.size
    fig, axes = plt.subplots(1, len(frames), figsize=(3.6 * len(frames), 3.8), squeeze=False)
    for ax, f in zip(axes[0], frames, strict=True):
        cov = _coverage(hist, f, lidar) if len(hist.times) else np.zeros(hist.world.shape, bool)
        img = np.ones((*hist.world.shape, 3)) * 0.75
        img[cov] = 1.0
        img[hist.world.occupied] = 0.0
        ax.imshow(img, origin="lower", extent=(0, w, 0, h), interpolation="nearest")
        t_now = hist.times[f] if len(hist.times) else 0.0
        for spec in hist.tasks:
            done = any(e[1] == "complete" and f"task {spec.id} " in e[2] and e[0] <= t_now for e in hist.events)
            ax.plot(*spec.xy, marker="*", ms=14, color="gold" if not done else "grey", mec="k")
            ax.annotate(str(spec.n_required), spec.xy, xytext=(4, 4), textcoords="offset points", fontsize=8)
        ax.plot(*hist.home, marker="s", ms=9, color="k")
        for i in range(n):
            c = cmap(i % 10)
            trail = hist.positions[:f + 1, i]
            ax.plot(trail[:, 0], trail[:, 1], color=c, lw=0.8, alpha=0.8)
            x, y = hist.positions[f, i]
            ax.plot(x, y, "o", color=c, mec="k", ms=7)
            ax.add_patch(plt.Circle((x, y), comm_range, color=c, fill=False, ls=":", lw=0.6))
            px, py = hist.particles[f, i]
            if np.isfinite(px):
                ax.plot(px, py, "o", mfc="none", mec=c, ms=9, mew=1.5)
        ax.set_xlim(0, w)
        ax.set_ylim(0, h)
        ax.set_aspect("equal")
        ax.set_title(f"t = {t_now:.1f} s", fontsize=10)
        ax.set_xticks([])
        ax.set_yticks([])
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path

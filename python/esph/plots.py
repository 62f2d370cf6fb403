"""Every plot of the package: each function takes data already computed
(rows, time series, snapshots) and writes one PNG; none runs LAMMPS."""
from __future__ import annotations

from pathlib import Path

import numpy as np


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_convergence(rows, png: Path) -> None:
    """log-log |error| against dx for Tables 2 and 4 (rows of esph.validate),
    ours and the paper's."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, table, title in [(axes[0], "2", "beam, tip dv"), (axes[1], "4", "truss, tip dh")]:
        sel = [r for r in rows if r.table == table]
        for key in sorted({(r.variant, r.load) for r in sel}):
            pts = sorted((r.dx, abs(r.error)) for r in sel if (r.variant, r.load) == key)
            line, = ax.loglog([p[0] * 1e3 for p in pts], [100 * p[1] for p in pts], "o-",
                              label=f"{key[0]}, {key[1]:g} N")
            cont = sorted((r.dx, abs(r.error_continuum)) for r in sel
                          if (r.variant, r.load) == key and r.error_continuum == r.error_continuum)
            if cont:
                ax.loglog([p[0] * 1e3 for p in cont], [100 * p[1] for p in cont], "--",
                          color=line.get_color(), label=f"{key[0]}, {key[1]:g} N, vs continuum")
        for load in sorted({r.load for r in sel}):
            paper = sorted({(r.dx, r.paper) for r in sel if r.load == load and r.paper > 0})
            if paper:
                ax.loglog([p[0] * 1e3 for p in paper], [p[1] for p in paper], "k:", marker="x",
                          label=f"paper (against its theory), {load:g} N")
        ax.set_xlabel("dx [mm]")
        ax.set_ylabel("|error| [%]")
        ax.set_title(title)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def plot_speed(rows, png: Path) -> None:
    """log-log |error| against wall time, one panel per problem and load
    (rows of esph.speed)."""
    plt = _pyplot()
    cases = sorted({(r.problem, r.load) for r in rows})
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4), squeeze=False)
    for ax, case in zip(axes[0], cases):
        for method in dict.fromkeys(r.method for r in rows):
            pts = sorted((r.wall, abs(r.error), r.dx) for r in rows
                         if (r.problem, r.load) == case and r.method == method
                         and r.status == "ok" and r.error == r.error)
            if pts:
                ax.loglog([p[0] for p in pts], [100 * p[1] for p in pts], "o-", label=method)
                for w, e, dx in pts:
                    ax.annotate(f"{dx * 1e3:g}", (w, 100 * e), fontsize=6)
        ax.set_xlabel("wall time to equilibrium [s]")
        ax.set_ylabel("|error| [%]")
        ax.set_title(f"{case[0]}, {case[1]:g} N (labels: dx in mm)")
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def plot_energies(t_ms: np.ndarray, series: dict, title: str, png: Path) -> None:
    """Kinetic, strain, contact and total energy of a collision against time
    (series: the columns of the rings time series, by name)."""
    plt = _pyplot()
    ke = series["etotal"] - series["estrain"] - series["econtact"]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for y, label in [(ke, "kinetic"), (series["estrain"], "strain"),
                     (series["econtact"], "contact"), (series["etotal"], "total")]:
        ax.plot(t_ms, y, label=label)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("energy [J]")
    ax.set_title(title)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)


def plot_snapshots(frames: list[tuple[float, np.ndarray]], png: Path, title: str,
                   ncols: int = 3) -> None:
    """Particles coloured by von Mises stress, one panel per snapshot (time,
    rows of id mol x y vonmises, as runner.read_dump gives them), all on
    the same axes; the colour scale ends at the 99.5th percentile so that a
    few loaded or clamped particles do not wash out the body."""
    plt = _pyplot()
    frames = sorted(frames, key=lambda f: f[0])
    if not frames:
        return
    every = np.concatenate([f[1] for f in frames])
    vmax = float(np.percentile(every[:, 4], 99.5)) or 1.0
    lo, hi = every[:, 2:4].min(axis=0), every[:, 2:4].max(axis=0)
    pad = 0.03 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    aspect = (hi[1] - lo[1]) / (hi[0] - lo[0])
    ncols = min(ncols, len(frames))
    nrows = -(-len(frames) // ncols)
    width = 3.6
    fig, axes = plt.subplots(nrows, ncols, figsize=(width * ncols + 1.2,
                                                    (width * aspect + 0.35) * nrows + 0.5),
                             squeeze=False, constrained_layout=True)
    for ax in axes.flat[len(frames):]:
        ax.set_visible(False)
    for ax, (time, rows) in zip(axes.flat, frames):
        sc = ax.scatter(rows[:, 2], rows[:, 3], c=rows[:, 4] / 1e6, s=1.0, cmap="jet",
                        vmin=0.0, vmax=vmax / 1e6)
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_title(f"t = {time * 1e3:.2f} ms", fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(sc, ax=axes.ravel().tolist(), label="von Mises stress [MPa]", shrink=0.8)
    fig.suptitle(title, fontsize=10)
    fig.savefig(png, dpi=120)
    plt.close(fig)

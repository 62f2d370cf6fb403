"""Particle snapshots coloured by von Mises stress, like the paper's Figures
2-10: the beam under -250 N for CCB, CCBWAT and ICB, and (esph.rings) the
colliding rings.  Snapshots come from the dumps the example scripts write
when their variable snap is set."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .runner import BEAM, run_mpi


def read_dump(path: Path) -> tuple[float, np.ndarray]:
    """(time, rows of id mol x y vonmises) of one snapshot of in.rings."""
    lines = Path(path).read_text().splitlines()
    time = float(lines[lines.index("ITEM: TIME") + 1])
    start = next(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS")) + 1
    return time, np.array([[float(v) for v in line.split()] for line in lines[start:]])


def plot_snapshots(dumps: list[Path], png: Path, title: str, ncols: int = 3) -> None:
    """Particles coloured by von Mises stress, one panel per snapshot, all on
    the same axes; the colour scale ends at the 99.5th percentile so that a
    few loaded or clamped particles do not wash out the body."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frames = sorted((read_dump(p) for p in dumps), key=lambda f: f[0])
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


def beam_figures(out: Path, load: float = -250.0, dx: float = 0.002, snap: float = 0.001,
                 schemes=("ccb", "ccbwat", "icb"), nprocs: int = 1, progress=print) -> list[Path]:
    """Damped dynamics of the beam for each scheme with snapshots every
    `snap` seconds; a run that fails stops at the failure (in.failure), so
    its last snapshot shows the crack."""
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    pngs = []
    for scheme in schemes:
        tag = f"{scheme}_{load:g}_{dx * 1e3:g}mm"
        progress(f"[esph] beam snapshots {scheme}, Fy = {load:g} N ...")
        for old in out.glob(f"beam_{tag}.*.dump"):
            old.unlink()
        res = run_mpi(BEAM, {"Fy": load, "dx": dx, "scheme": scheme, "route": "dyn",
                             "snap": snap, "outdir": str(out), "tag": tag}, nprocs)
        failed = res.variables.get("failed", 0.0) > 0.5
        status = (f"failed at {res.variables['time'] * 1e3:.2f} ms" if failed
                  else f"intact, tip dv = {res.variables['tip_dv'] * 1e3:.2f} mm")
        png = out / f"beam_{tag}.png"
        plot_snapshots(sorted(out.glob(f"beam_{tag}.*.dump")), png,
                       f"beam, {scheme.upper()}, Fy = {load:g} N, dx = {dx * 1e3:g} mm: {status}",
                       ncols=2)
        print(f"{scheme:>7}: {status}; {png}", flush=True)
        pngs.append(png)
    return pngs

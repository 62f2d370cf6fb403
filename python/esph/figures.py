"""The paper's beam figures (2-4): damped dynamics of the beam under -250 N
for CCB, CCBWAT and ICB, with particle snapshots coloured by von Mises
stress (the rings' are drawn by esph.rings)."""
from __future__ import annotations

from pathlib import Path

from .plots import plot_snapshots
from .problems import BEAM
from .runner import read_dump, run_mpi


def beam_figures(out: Path, load: float = -250.0, dx: float = 0.002, snap: float = 0.001,
                 schemes=("ccb", "ccbwat", "icb"), nprocs: int = 1, progress=print) -> list[Path]:
    """Damped dynamics of the beam for each scheme with snapshots every
    `snap` seconds; a run that fails stops at the failure (in.failure), so
    its last snapshot shows the crack."""
    out = Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    print(f"Beam under Fy = {load:g} N by damped dynamics, dx = {dx * 1e3:g} mm, "
          f"snapshots every {snap * 1e3:g} ms (rings: esph rings)")
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
        frames = [read_dump(p) for p in sorted(out.glob(f"beam_{tag}.*.dump"))]
        plot_snapshots(frames, png,
                       f"beam, {scheme.upper()}, Fy = {load:g} N, dx = {dx * 1e3:g} mm: {status}",
                       ncols=2)
        print(f"{scheme:>7}: {status}; {png}", flush=True)
        pngs.append(png)
    return pngs

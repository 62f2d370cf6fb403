"""Colliding rings (paper section 3.3) through examples/rings/in.rings: run,
read the time series the script writes, and reduce it to the numbers of a
collision (rebound speed, contact duration, energy balance, failure)."""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from .figures import read_dump
from .runner import RINGS, run_mpi, run_script

# columns of rings_<tag>.dat (fix ave/time in in.rings)
COLUMNS = ["step", "v1", "v2", "estrain", "econtact", "etotal", "px", "py", "fcontact",
           "ncontact", "overlap", "symx", "symy", "failed"]


@dataclass
class RingsCase:
    scheme: str = "icb"           # icb, ccb, ccbwat
    v: float = 5.0                # speed of each ring, m/s
    dx: float = 0.002             # m
    tend: float = 0.004           # s
    stress: str = "pk1"           # icb stress measure (corotated: the paper's)
    grad: str = "quadratic"       # icb gradient correction (linear: the paper's)
    volumes: str = "exact"        # set_sph_volumes polar, or cells (the paper's)
    damping: float = 0.0          # contact damping ratio
    every: int = 50               # steps between time-series rows
    snap: float = 0.0             # s between particle snapshots (0 = none)

    @property
    def tag(self) -> str:
        return f"{self.scheme}_{self.v:g}_{self.dx * 1e3:g}mm"

    def variables(self, outdir: Path) -> dict:
        return {"scheme": self.scheme, "v": self.v, "dx": self.dx, "tend": self.tend,
                "stress": self.stress, "grad": self.grad, "volumes": self.volumes,
                "damping": self.damping, "every": self.every,
                "snap": self.snap, "outdir": str(outdir), "tag": self.tag}


@dataclass
class RingsResult:
    case: RingsCase
    atoms: int
    steps: int
    wall: float
    rebound_speed: float          # mean |vx| of the two rings at the end, m/s
    restitution: float            # rebound speed / initial speed
    contact_start: float          # s (nan without contact)
    contact_end: float            # s, last time in contact (nan if still in contact)
    max_contact_force: float      # N, sum of pair force magnitudes
    max_overlap: float            # (dx - d)/dx
    max_strain_share: float       # largest strain energy / initial kinetic energy
    energy_error: float           # max |E - E0| / E0 over the run
    momentum_error: float         # max |p| / (sum m |v0|)
    centroid_asymmetry: float     # max |x1 + x2|, |y1 - y2| of the ring centroids / dx
    t_fail: float                 # s, first failure (nan = intact)
    series_file: str
    mirror_error: float = float("nan")   # particle mirror error / dx, largest over snapshots

    @property
    def contact_duration(self) -> float:
        return self.contact_end - self.contact_start

    def row(self) -> dict:
        out = {k: v for k, v in asdict(self).items() if k != "case"}
        out.update(asdict(self.case))
        out["contact_duration"] = self.contact_duration
        return out


def load_series(path: Path) -> dict:
    data = np.atleast_2d(np.loadtxt(path))
    return {name: data[:, k] for k, name in enumerate(COLUMNS)}


def summarise(case: RingsCase, series: dict, dt: float, atoms: int, steps: int, wall: float,
              series_file: Path) -> RingsResult:
    t = series["step"] * dt
    e0 = series["etotal"][0]
    touching = series["ncontact"] > 0
    start = t[touching][0] if touching.any() else float("nan")
    end = t[touching][-1] if touching.any() and not touching[-1] else float("nan")
    failed = series["failed"] > 0.5
    rebound = 0.5 * (abs(series["v1"][-1]) + abs(series["v2"][-1]))
    mass_speed = 2.0 * e0 / case.v
    return RingsResult(
        case=case, atoms=atoms, steps=steps, wall=wall, rebound_speed=rebound,
        restitution=rebound / case.v, contact_start=start, contact_end=end,
        max_contact_force=float(series["fcontact"].max()),
        max_overlap=float(series["overlap"].max()),
        max_strain_share=float(series["estrain"].max() / e0),
        energy_error=float(np.abs(series["etotal"] - e0).max() / e0),
        momentum_error=float(np.abs(series["px"]).max() / mass_speed),
        centroid_asymmetry=float(max(np.abs(series["symx"]).max(),
                                     np.abs(series["symy"]).max()) / case.dx),
        t_fail=float(t[failed][0]) if failed.any() else float("nan"),
        series_file=str(series_file))


def run_rings(case: RingsCase, outdir: Path, nprocs: int = 1) -> RingsResult:
    """Run one collision (in-process on 1 rank, else mpirun) and summarise it."""
    outdir = Path(outdir).resolve()
    outdir.mkdir(parents=True, exist_ok=True)
    variables = case.variables(outdir)
    if nprocs == 1:
        info = {}
        out = run_script(RINGS, variables, read=["v1"],
                         inspect=lambda lmp: info.update(dt=lmp.extract_global("dt")))
        dt, steps, atoms = info["dt"], out.steps, out.natoms
    else:
        out = run_mpi(RINGS, variables, nprocs)
        steps, atoms = int(out.variables["steps"]), int(out.variables["atoms"])
        dt = out.variables["time"] / steps
    series_file = outdir / f"rings_{case.tag}.dat"
    res = summarise(case, load_series(series_file), dt, atoms, steps, out.wall, series_file)
    dumps = sorted(outdir.glob(f"rings_{case.tag}.*.dump"))
    if dumps:
        res.mirror_error = max(mirror_error(read_dump(p)[1]) for p in dumps) / case.dx
    return res


def mirror_error(rows: np.ndarray) -> float:
    """Largest distance between a particle of ring 1 and the mirror image
    (x -> -x) of the nearest particle of ring 2; rows are id mol x y ..."""
    a = rows[rows[:, 1] == 1][:, 2:4]
    b = rows[rows[:, 1] == 2][:, 2:4] * [-1.0, 1.0]
    worst = 0.0
    for chunk in np.array_split(a, max(1, len(a) // 500)):
        d2 = ((chunk[:, None, :] - b[None, :, :]) ** 2).sum(axis=2)
        worst = max(worst, float(np.sqrt(d2.min(axis=1)).max()))
    return worst


def plot_energies(result: RingsResult, png: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = load_series(Path(result.series_file))
    dt = result.case.tend / max(result.steps, 1)
    t = s["step"] * dt * 1e3
    ke = s["etotal"] - s["estrain"] - s["econtact"]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for y, label in [(ke, "kinetic"), (s["estrain"], "strain"), (s["econtact"], "contact"),
                     (s["etotal"], "total")]:
        ax.plot(t, y, label=label)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("energy [J]")
    ax.set_title(f"rings, {result.case.scheme}, {result.case.v:g} m/s, dx = "
                 f"{result.case.dx * 1e3:g} mm")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)

"""Colliding rings (paper section 3.3) through examples/rings/in.rings: run,
read the time series the script writes, and reduce it to the numbers of a
collision (rebound speed, contact duration, energy balance, failure)."""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from . import plots
from .problems import RINGS
from .report import print_head, write_rows
from .runner import read_dump, run_mpi, run_script

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


def energy_plot(result: RingsResult, png: Path) -> None:
    """The energies of one collision against time, as a PNG."""
    series = load_series(Path(result.series_file))
    dt = result.case.tend / max(result.steps, 1)
    plots.plot_energies(series["step"] * dt * 1e3, series,
                        f"rings, {result.case.scheme}, {result.case.v:g} m/s, dx = "
                        f"{result.case.dx * 1e3:g} mm", png)


def run_table(out: Path, schemes, speeds, dx: float, tend: float, stress: str, grad: str,
              volumes: str, snap: float, nprocs: int, progress=print) -> list[RingsResult]:
    """Each scheme at each speed: one table row per collision, its energy
    plot and (if snap > 0) its snapshots, and the rows as JSON and CSV."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"Colliding rings (outer diameter 0.2 m, wall 1 cm, E = 20 GPa, nu = 0.3, plane "
          f"stress, rho = 1000), dx = {dx * 1e3:g} mm, {tend * 1e3:g} ms, "
          f"{nprocs} MPI rank(s); output in {out}")
    print_head(f"{'scheme':>7} {'v':>4} {'atoms':>6} {'steps':>7} {'wall[s]':>8} {'rebound':>8} "
               f"{'e':>5} {'contact[ms]':>15} {'F_max[N]':>9} {'overlap':>7} {'strain':>6} "
               f"{'dE/E0':>9} {'|p|':>8} {'mirror/dx':>9} {'failed[ms]':>10}")
    results = []
    for scheme in schemes:
        for speed in speeds:
            progress(f"[esph] rings {scheme} {speed:g} m/s ...")
            case = RingsCase(scheme=scheme, v=speed, dx=dx, tend=tend, stress=stress, grad=grad,
                             volumes=volumes, snap=snap)
            res = run_rings(case, out, nprocs=nprocs)
            fail = "-" if res.t_fail != res.t_fail else f"{res.t_fail * 1e3:.3f}"
            print(f"{scheme:>7} {speed:4g} {res.atoms:6d} {res.steps:7d} {res.wall:8.1f} "
                  f"{res.rebound_speed:8.3f} {res.restitution:5.2f} "
                  f"{res.contact_start * 1e3:7.3f}-{res.contact_end * 1e3:7.3f} "
                  f"{res.max_contact_force:9.1f} {res.max_overlap:7.3f} "
                  f"{res.max_strain_share:6.2f} {res.energy_error:9.2e} "
                  f"{res.momentum_error:8.1e} {res.mirror_error:9.1e} {fail:>10}",
                  flush=True)
            results.append(res)
            energy_plot(res, out / f"energy_{case.tag}.png")
            dumps = sorted(out.glob(f"rings_{case.tag}.*.dump"))
            if dumps:
                plots.plot_snapshots([read_dump(p) for p in dumps],
                                     out / f"snapshots_{case.tag}.png",
                                     f"{scheme}, {speed:g} m/s: von Mises stress")
    print("rebound = mean |vx| of the rings at the end; e = rebound/initial speed; contact = "
          "first-last time in contact (nan: still in contact); strain = largest strain energy "
          "/ initial kinetic energy; dE/E0 = largest total-energy error; |p| = largest total "
          "momentum / sum m|v0|; mirror = largest distance of a ring-1 particle from the "
          "mirror image of ring 2, over the snapshots")
    write_rows(out / "rings.json", [r.row() for r in results])
    return results

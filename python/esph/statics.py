"""Time to the static beam: Newton, CG and damped dynamics from one start,
each against the converged answer of the same model (Newton to 1e-10 of the
load) and against the elastica, with the command of every row."""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from .problems import BEAM, exact_tip
from .report import command_line, machine, write_rows
from .runner import run_mpi
from .schemes import STATICS_MODEL, STATICS_ROUTES


@dataclass
class StaticsRow:
    route: str
    dx: float
    nprocs: int
    atoms: int
    iterations: int          # minimiser iterations or time steps
    wall: float              # s, whole run including start-up and partner build
    loop: float              # s, LAMMPS's loop time of all runs and minimisations
    dv: float
    deviation: float         # dv relative to the converged Newton answer
    error: float             # dv relative to the elastica at the same material point
    command: str


def statics(dx: float, nprocs_list, routes, progress=print, out: Path | None = None
            ) -> list[StaticsRow]:
    """Time to the static beam by each route, against its own converged answer
    (Newton to a force norm of 1e-10 of the load)."""
    exact = exact_tip("beam", STATICS_MODEL["Fy"], dx)
    refs = {}
    for stress in sorted({{**STATICS_MODEL, **STATICS_ROUTES[r]}["stress"] for r in routes}):
        progress(f"[esph] converged reference: Newton, stress {stress}, ftol 1e-10, "
                 f"dx = {dx * 1e3:g} mm ...")
        refs[stress] = run_mpi(BEAM, {**STATICS_MODEL, **STATICS_ROUTES["newton"], "dx": dx,
                                      "ftol": 1e-10, "stress": stress}, 1).variables["tip_dv"]
    print(f"Static beam, Fy = {STATICS_MODEL['Fy']:g} N, the defaults (pk1, quadratic gradient, "
          f"mirror clamp, exact volumes, face traction), dx = {dx * 1e3:g} mm; converged dv = "
          + ", ".join(f"{ref * 1e3:.6f} mm ({stress})" for stress, ref in refs.items())
          + f"; 'vs conv' is against the converged answer of the row's stress; machine: {machine()}")
    print(f"{'route':<17} {'ranks':>5} {'atoms':>6} {'iter':>7} {'wall[s]':>8} {'loop[s]':>8} "
          f"{'dv[mm]':>11} {'vs conv':>9} {'vs exact':>9}")
    rows = []
    for nprocs in nprocs_list:
        for route in routes:
            variables = {**STATICS_MODEL, **STATICS_ROUTES[route], "dx": dx}
            ref = refs[variables["stress"]]
            cmd = command_line(BEAM, variables, nprocs)
            progress(f"[esph] {route} on {nprocs} rank(s) ...")
            res = run_mpi(BEAM, variables, nprocs, timeout=7200)
            v = res.variables
            row = StaticsRow(route, dx, nprocs, int(v["atoms"]), int(v["steps"]), res.wall,
                             v.get("loop_total", float("nan")), v["tip_dv"],
                             v["tip_dv"] / ref - 1.0, v["tip_dv"] / exact - 1.0, cmd)
            print(f"{route:<17} {nprocs:5d} {row.atoms:6d} {row.iterations:7d} {row.wall:8.2f} "
                  f"{row.loop:8.2f} {1e3 * row.dv:11.6f} {100 * row.deviation:+8.4f}% "
                  f"{100 * row.error:+8.3f}%", flush=True)
            rows.append(row)
    if out is not None:
        Path(out).mkdir(parents=True, exist_ok=True)
        write_rows(Path(out) / "statics.json", [asdict(r) for r in rows])
        print(f"\nJSON and CSV (with the command of every row) in {Path(out) / 'statics.json'}, .csv")
    return rows

"""Speed against error: for the beam (Fy = -75, -250 N) and the truss
(+3000 N), every scheme and route at several spacings -- the wall time to
equilibrium, the error against the exact answer of the model it runs, and
the throughput in particle-steps per second -- beside LAMMPS's own MACHDYN
smd/tlsph on the same beam.  Each run is one `mpirun lmp` of an example
script; the command is recorded with the numbers."""
from __future__ import annotations

import os
import platform
import re
from dataclasses import asdict, dataclass
from pathlib import Path

from . import theory
from .paths import lmp_binary
from .runner import BEAM, BEAM_TLSPH, TRUSS, run_mpi

PAPER = {"grad": "linear", "clamp": "fixed", "volumes": "cells", "load": "column"}
LAST = {"grad": "quadratic", "clamp": "mirror", "volumes": "cells", "load": "column"}
DEFAULT = {"grad": "quadratic", "clamp": "mirror", "volumes": "exact", "load": "traction"}
# (label, script for the beam, script for the truss or None, variables, truss model)
METHODS = [
    ("ICB min CG, paper (linear/fixed, pk1)", BEAM, TRUSS,
     {"route": "min", "solver": "cg", "stress": "pk1", **PAPER},
     "pk1"),
    ("ICB min CG, quadratic/mirror, pk1", BEAM, TRUSS,
     {"route": "min", "solver": "cg", "stress": "pk1", **LAST},
     "pk1"),
    ("ICB dyn, paper (linear/fixed, corotated)", BEAM, TRUSS,
     {"route": "dyn", "stress": "corotated", **PAPER}, "corotated"),
    ("ICB dyn, quadratic/mirror, pk1", BEAM, TRUSS,
     {"route": "dyn", "stress": "pk1", **LAST, "hg": 0.05},
     "pk1"),
    ("CCBWAT dyn", BEAM, TRUSS, {"scheme": "ccbwat", "route": "dyn"}, "hypo"),
    ("MACHDYN smd/tlsph dyn", BEAM_TLSPH, None, {"route": "dyn"}, None),
    ("ICB min Newton, paper (linear/fixed, pk1)", BEAM, TRUSS,
     {"route": "min", "solver": "newton", "stress": "pk1", **PAPER},
     "pk1"),
    ("ICB min Newton, quadratic/mirror, pk1", BEAM, TRUSS,
     {"route": "min", "solver": "newton", "stress": "pk1", **LAST}, "pk1"),
    ("ICB min Newton, defaults (exact volumes, face traction)", BEAM, TRUSS,
     {"route": "min", "solver": "newton", "stress": "pk1", **DEFAULT}, "pk1"),
]
PROBLEMS = [("beam", -75.0), ("beam", -250.0), ("truss", 3000.0)]
# a damped run has reached equilibrium when the force 2-norm is below this
# share of the load
AT_REST = 1.0e-4


@dataclass
class SpeedRow:
    problem: str
    load: float
    method: str
    dx: float
    atoms: int
    steps: int
    wall: float              # s, whole run (time to solution)
    loop: float              # s, LAMMPS's loop time of all runs
    throughput: float        # particle-steps per second
    value: float             # tip dv (beam) or dh (truss), m
    exact: float
    error: float
    status: str
    command: str
    residual: float = float("nan")   # dyn routes: force 2-norm / load at the end


def exact_answer(problem: str, load: float, dx: float, model: str | None) -> tuple[float, int]:
    """(exact value, component index 1 = dv, 0 = dh)."""
    if problem == "beam":
        beam = theory.Beam()
        return theory.beam_tip(beam, load, s=beam.L - 0.5 * dx)[1], 1
    truss = theory.Truss()
    return truss.displacement(load, model, truss.L - 0.5 * dx), 0


def run_one(problem: str, load: float, method, dx: float, nprocs: int) -> SpeedRow | None:
    label, beam_script, truss_script, variables, model = method
    script = beam_script if problem == "beam" else truss_script
    if script is None:
        return None
    load_var = "Fy" if problem == "beam" else "Fx"
    variables = {**variables, load_var: load, "dx": dx}
    cmd = (f"cd {script.parent.relative_to(script.parents[2])} && mpirun -np {nprocs} lmp -in "
           f"{script.name} " + " ".join(f"-var {k} {v}" for k, v in variables.items()))
    exact, comp = exact_answer(problem, load, dx, model or "pk1")
    try:
        out = run_mpi(script, variables, nprocs, timeout=7200)
    except RuntimeError as err:
        found = re.search(r"^ERROR.*$", str(err), re.M)
        reason = found.group(0) if found else str(err)[-200:]
        return SpeedRow(problem, load, label, dx, 0, 0, float("nan"), float("nan"), float("nan"),
                        float("nan"), exact, float("nan"), f"error: {reason}", cmd)
    v = out.variables
    value = v["tip_dv"] if comp == 1 else v["tip_dh"]
    failed = v.get("failed", 0.0) > 0.5
    residual = v.get("residual", float("nan"))
    status = "failed" if failed else ("not at rest" if residual > AT_REST else "ok")
    atoms, steps, loop = int(v["atoms"]), int(v["steps"]), v.get("loop_total", float("nan"))
    return SpeedRow(problem, load, label, dx, atoms, steps, out.wall, loop,
                    atoms * steps / loop if loop > 0 else float("nan"), value, exact,
                    value / exact - 1.0, status, cmd, residual)


def machine() -> str:
    return (f"{platform.node()}, {os.cpu_count()} cores, "
            f"{platform.processor() or platform.machine()}, {platform.platform()}")


def print_row(r: SpeedRow) -> None:
    err = "-" if r.error != r.error else f"{100 * r.error:+8.2f}%"
    print(f"{r.problem:>5} {r.load:7.0f} {r.method:<42} {r.dx * 1e3:5g} {r.atoms:6d} {r.steps:8d} "
          f"{r.wall:8.1f} {r.throughput / 1e6:8.3f} {err:>9} {r.status}", flush=True)


def plot(rows: list[SpeedRow], png: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

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


def run_all(dxs, nprocs: int, problems=PROBLEMS, methods=METHODS, progress=print,
            truss_dxs=None):
    """dxs for the beam; truss_dxs for the truss, whose height H = 5 cm needs
    a spacing that divides it (default: dxs)."""
    rows = []
    print(f"Speed against error; machine: {machine()}; {nprocs} MPI rank(s); lmp = {lmp_binary()}")
    print(f"{'':>5} {'load':>7} {'method':<42} {'dx':>5} {'atoms':>6} {'steps':>8} {'wall[s]':>8} "
          f"{'Mp-st/s':>8} {'error':>9} status")
    for problem, load in problems:
        for method in methods:
            for dx in (truss_dxs or dxs) if problem == "truss" else dxs:
                progress(f"[esph] {problem} {load:g} N, {method[0]}, dx = {dx * 1e3:g} mm ...")
                row = run_one(problem, load, method, dx, nprocs)
                if row:
                    print_row(row)
                    rows.append(row)
    return rows


def as_dicts(rows):
    return [asdict(r) for r in rows]


# The static beam of the performance issue: Fy = -250 N, our accurate model
STATICS_MODEL = {"Fy": -250.0, "stress": "pk1", "grad": "quadratic", "clamp": "mirror"}
STATICS_ROUTES = {
    "newton": {"route": "min", "solver": "newton"},
    "newton-loose": {"route": "min", "solver": "newton", "ftol": 1.0e-3},
    "cg": {"route": "min", "solver": "cg"},
    # damped dynamics needs hourglass control; its equilibrium moves by ~2e-4
    "dyn": {"route": "dyn", "hg": 0.05},
}


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


def statics(dx: float, nprocs_list, routes, progress=print) -> list[StaticsRow]:
    """Time to the static beam by each route, against its own converged answer
    (Newton to a force norm of 1e-10 of the load)."""
    exact, _ = exact_answer("beam", STATICS_MODEL["Fy"], dx, "pk1")
    progress(f"[esph] converged reference: Newton, ftol 1e-10, dx = {dx * 1e3:g} mm ...")
    ref = run_mpi(BEAM, {**STATICS_MODEL, **STATICS_ROUTES["newton"], "dx": dx, "ftol": 1e-10},
                  1).variables["tip_dv"]
    print(f"Static beam, Fy = {STATICS_MODEL['Fy']:g} N, the defaults (pk1, quadratic gradient, "
          f"mirror clamp, exact volumes, face traction), dx = {dx * 1e3:g} mm; converged dv = "
          f"{ref * 1e3:.6f} mm; machine: {machine()}")
    print(f"{'route':<13} {'ranks':>5} {'atoms':>6} {'iter':>7} {'wall[s]':>8} {'loop[s]':>8} "
          f"{'dv[mm]':>11} {'vs conv':>9} {'vs exact':>9}")
    rows = []
    for nprocs in nprocs_list:
        for route in routes:
            variables = {**STATICS_MODEL, **STATICS_ROUTES[route], "dx": dx}
            cmd = (f"cd examples/beam && mpirun -np {nprocs} lmp -in in.beam " +
                   " ".join(f"-var {k} {v}" for k, v in variables.items()))
            progress(f"[esph] {route} on {nprocs} rank(s) ...")
            out = run_mpi(BEAM, variables, nprocs, timeout=7200)
            v = out.variables
            row = StaticsRow(route, dx, nprocs, int(v["atoms"]), int(v["steps"]), out.wall,
                             v.get("loop_total", float("nan")), v["tip_dv"],
                             v["tip_dv"] / ref - 1.0, v["tip_dv"] / exact - 1.0, cmd)
            print(f"{route:<13} {nprocs:5d} {row.atoms:6d} {row.iterations:7d} {row.wall:8.2f} "
                  f"{row.loop:8.2f} {1e3 * row.dv:11.6f} {100 * row.deviation:+8.4f}% "
                  f"{100 * row.error:+8.3f}%", flush=True)
            rows.append(row)
    return rows

"""Weak scaling of memory: peak resident memory of every MPI rank at a
constant number of particles per rank (1, 2, 4 ranks; 4 oversubscribed on
2 cores), for the 2D beam and the 3D cantilever, in dynamics (route nve) and
in Newton statics (min_style sph/newton, the defaults).  The body grows
along its length with the rank count and its tip load falls as the square
of it (the same deflection over the length), so flat memory per rank is the
target; the Newton bookkeeping (sph_newton_dofs, the mirror pairing, the
direct solver's gathered Hessian on rank 0) is what can break it.

The cases are those of the study studies/weak_scaling (issue 34's baseline,
whose script this replaced), so that `esph bench --suite` runs them and
writes JSON.  Each rank
runs under bench3d's wrapper, which reports the rank's own peak RSS
(getrusage of its lmp child), so the memory of rank 0 is told apart from
the others'."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from .bench3d import run_measured
from .report import command_line, machine, print_head
from .problems import PROBLEMS


@dataclass(frozen=True)
class WeakCase:
    problem: str             # the example that runs it, by name of esph.problems.PROBLEMS
    route: str               # "dyn" (route nve) or "newton" (route min, the defaults)
    variables: dict          # at one rank
    scaled: str = "L"        # the variable multiplied by the rank count
    # the tip load, divided by the square of the rank count: a cantilever's
    # deflection over its length goes as F L^2, so every length solves the
    # same nonlinear problem.  Under one load the 4-rank 2d beam bent 16
    # times further in proportion, took 17 Newton steps against 4, and the
    # heap of its tip ranks grew by 6-8 MB of resident pages during the late
    # steps (not in live bytes: massif stays flat; not glibc's trimming:
    # MALLOC_TRIM_THRESHOLD_=0 left it)
    load: str = "Fy"

    @property
    def dim(self) -> int:
        return PROBLEMS[self.problem].dim


# dx = 1 mm in 2D: 4060 atoms per rank; dx = 2 mm in 3D (L = 0.1): about
# 5300 at one rank, 5075 per rank at four (the clamp layers do not grow)
CASES = {
    "beam-dyn": WeakCase("beam", "dyn", {"dx": 0.001, "L": 0.2, "route": "nve", "nsteps": 200,
                                         "Fy": -10}),
    # the defaults: solver auto, the direct solve on one rank and PETSc's
    # distributed one on more
    "beam-newton": WeakCase("beam", "newton", {"dx": 0.001, "L": 0.2, "route": "min",
                                               "Fy": -10}),
    # PETSc's distributed solver on every rank count, and the direct solve,
    # which gathers the whole system on rank 0
    "beam-newton-petsc": WeakCase("beam", "newton", {"dx": 0.001, "L": 0.2, "route": "min",
                                                     "Fy": -10, "linear": "petsc"}),
    "beam-newton-direct": WeakCase("beam", "newton", {"dx": 0.001, "L": 0.2, "route": "min",
                                                      "Fy": -10, "linear": "direct"}),
    "beam3d-dyn": WeakCase("beam3d", "dyn", {"dx": 0.002, "L": 0.1, "route": "nve",
                                             "nsteps": 200, "Fy": -100}),
    "beam3d-newton": WeakCase("beam3d", "newton", {"dx": 0.002, "L": 0.1, "route": "min",
                                                   "Fy": -100}),
}
RANKS = (1, 2, 4)


@dataclass
class WeakRow:
    case: str
    dim: int
    route: str
    ranks: int
    atoms: int
    per_rank: float          # atoms / ranks
    wall: float              # s, the whole mpirun
    rss_mb: list = field(default_factory=list)    # peak RSS of each rank, by rank, MiB
    max_rss_mb: float = math.nan
    # peak RSS of the largest rank over the particles per rank: the whole
    # footprint (binary, libraries, MPI buffers included), not a marginal cost
    bytes_per_particle: float = math.nan
    command: str = ""


def run_case(name: str, ranks: int, dx: float | None = None, nsteps: int | None = None,
             timeout: float = 3600) -> WeakRow:
    """One case on `ranks` ranks; dx and nsteps override the case's own
    (small bodies for tests)."""
    case = CASES[name]
    variables = dict(case.variables)
    if dx is not None:
        variables["dx"] = dx
    if nsteps is not None and "nsteps" in variables:
        variables["nsteps"] = nsteps
    variables[case.scaled] = variables[case.scaled] * ranks
    variables[case.load] = variables[case.load] / ranks**2
    script = PROBLEMS[case.problem].script
    out = run_measured(variables, ranks, timeout, script=script)
    atoms = int(out["atoms"])
    per_rank = atoms / ranks
    rss = out["rss_mb_ranks"]
    peak = max(rss, default=math.nan)
    return WeakRow(name, case.dim, case.route, ranks, atoms, per_rank, out["wall"], rss, peak,
                   peak * 1024 * 1024 / per_rank, command_line(script, variables, ranks))


def print_row(r: WeakRow) -> None:
    print(f"{r.case:>14} {r.ranks:5d} {r.atoms:7d} {r.per_rank:7.0f} {r.wall:8.1f} "
          f"{r.max_rss_mb:9.1f} {r.bytes_per_particle:12.0f}  "
          + " ".join(f"{v:.1f}" for v in r.rss_mb) + f"  |  {r.command}", flush=True)


def weak(cases=tuple(CASES), ranks=RANKS, dx: float | None = None, nsteps: int | None = None,
         progress=print) -> list[WeakRow]:
    """Every case (by name of CASES) at every rank count, one row each,
    printed as it comes."""
    print(f"Weak scaling of memory (constant particles per rank, the body grows along x); "
          f"machine {machine()}")
    print_head(f"{'case':>14} {'ranks':>5} {'atoms':>7} {'/rank':>7} {'wall[s]':>8} "
               f"{'MB max':>9} {'B/particle':>12}  MB per rank  |  command")
    rows = []
    for name in cases:
        for nprocs in ranks:
            progress(f"[esph] weak {name}, {nprocs} rank(s) ...")
            row = run_case(name, nprocs, dx, nsteps)
            print_row(row)
            rows.append(row)
    return rows

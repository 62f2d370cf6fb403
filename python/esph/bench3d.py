"""3D cantilever statics by min_style sph/newton with each linear solver
(direct on rank 0, MUMPS, matrix-free PETSc CG), per spacing and rank count:
Newton iterations, wall time, peak memory per rank, the ratio to 100 dynamic
steps of the same body on the same ranks, and how the solve scales with N."""

from __future__ import annotations

import math
import re
import sys

from .paths import lmp_binary
from .problems import BEAM3D, PROBLEMS
from .report import command_line, machine, print_head
from .runner import RunError, _var_args, mpirun_command, run_mpirun
from .schemes import LINEAR_SOLVERS

SOLVERS = LINEAR_SOLVERS     # the choices of esph bench3d --solvers

# runs lmp as a child and reports its peak resident memory: one line per rank
_WRAP = ("import os, resource, subprocess, sys\n"
         "code = subprocess.call(sys.argv[1:])\n"
         "peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss\n"
         "print(f\"ESPH_MAXRSS {os.environ.get('OMPI_COMM_WORLD_RANK', '0')} {peak}\", "
         "file=sys.stderr)\n"
         "sys.exit(code)\n")
_RSS_RE = re.compile(r"^ESPH_MAXRSS (\d+) (\d+)$", re.M)
_RESULT_RE = re.compile(r"^RESULT (\S+) (\S+)$", re.M)
_SUMMARY_RE = re.compile(r"^\s+min_style sph/newton: (\d+ (?:solves|MUMPS solves|Hessians).*)$",
                         re.M)


def run_measured(variables: dict, nprocs: int, timeout: float) -> dict:
    """One run of the 3D beam script: its RESULT values, wall time, the
    largest peak memory of a rank (MB) and the solver's summary line."""
    cmd = (mpirun_command(nprocs) + [sys.executable, "-c", _WRAP,
            lmp_binary(), "-in", BEAM3D.name, "-log", "none", "-nocite"] + _var_args(variables))
    launch = run_mpirun(cmd, BEAM3D.parent, timeout)
    text = launch.proc.stdout + launch.proc.stderr
    if launch.proc.returncode != 0:
        raise RunError(f"{' '.join(cmd)} failed", text[-2000:], text)
    row = {k: float(v) for k, v in _RESULT_RE.findall(launch.proc.stdout)}
    row["wall"] = launch.wall
    row["rss_mb"] = max((int(kb) / 1024 for _, kb in _RSS_RE.findall(text)), default=math.nan)
    summaries = _SUMMARY_RE.findall(text)
    row["summary"] = summaries[-1] if summaries else ""
    return row


def bench3d(dxs, nprocs_list, solvers, side: float, timeout: float) -> None:
    """Print one row per (dx, ranks, solver) for one body: a square section
    of the given side (H = W = side, L = 10 H), resolved by each dx (the
    default 0.02 m: 10 k atoms at dx = 2 mm, 81 k at 1 mm)."""
    print(f"3D cantilever statics (square section, L = 10 H, end traction, pk1, quadratic "
          f"gradient, mirror clamp, hourglass control 0.2: the defaults; force tolerance 1e-7 of "
          f"the load); machine {machine()}")
    print_head(f"{'dx[mm]':>6} {'atoms':>7} {'ranks':>5} {'solver':>7} {'iters':>5} "
               f"{'wall[s]':>8} {'MB/rank':>8} {'dyn100[s]':>9} {'ratio':>6}  solver log / command")
    for dx in dxs:
        geometry = {"dx": dx, "H": side, "W": side, "L": 10 * side,
                    "Fy": -1500 * (side / PROBLEMS["beam3d"].H)**2}
        for nprocs in nprocs_list:
            dynamics = run_measured({**geometry, "route": "nve", "nsteps": 100}, nprocs, timeout)
            for solver in solvers:
                variables = {**geometry, "solver": "newton", "linear": solver,
                             "thermo_every": 100}
                cmd = command_line(BEAM3D, variables, nprocs)
                try:
                    row = run_measured(variables, nprocs, timeout)
                except (RunError, TimeoutError, OSError) as failure:
                    print(f"{dx * 1e3:6.2f} {'':>7} {nprocs:5d} {solver:>7} failed: "
                          f"{str(failure).splitlines()[0][:100]}  {cmd}", flush=True)
                    continue
                except Exception as failure:    # subprocess.TimeoutExpired and the like
                    print(f"{dx * 1e3:6.2f} {'':>7} {nprocs:5d} {solver:>7} "
                          f"{type(failure).__name__}  {cmd}", flush=True)
                    continue
                ratio = row["wall"] / dynamics["wall"]
                print(f"{dx * 1e3:6.2f} {int(row['atoms']):7d} {nprocs:5d} {solver:>7} "
                      f"{int(row['steps']):5d} {row['wall']:8.1f} {row['rss_mb']:8.0f} "
                      f"{dynamics['wall']:9.2f} {ratio:6.1f}  {row['summary']}  |  {cmd}",
                      flush=True)

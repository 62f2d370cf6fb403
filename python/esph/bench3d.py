"""3D cantilever statics by min_style sph/newton with each linear solver
(direct on rank 0, MUMPS, matrix-free PETSc CG), per spacing and rank count:
Newton iterations, wall time, peak memory per rank, the ratio to 100 dynamic
steps of the same body on the same ranks, and how the solve scales with N."""

from __future__ import annotations

import math
import re
import sys
import tempfile
from pathlib import Path

from .paths import lmp_binary
from .problems import BEAM3D, PROBLEMS
from .report import command_line, machine, print_head
from .runner import RunError, _var_args, mpirun_command, run_mpirun
from .schemes import LINEAR_SOLVERS

SOLVERS = LINEAR_SOLVERS     # the choices of esph bench3d --solvers

# runs lmp as a child and reports its peak resident memory, one per rank: as
# a file maxrss.RANK in the folder given as its first argument, and as a
# line on stderr.  The file is what counts: Open MPI may stop forwarding a
# rank's output once its MPI process (lmp) has finalised, so a line printed
# after that can be lost (seen on 2 ranks).
_WRAP = ("import os, resource, subprocess, sys\n"
         "code = subprocess.call(sys.argv[2:])\n"
         "peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss\n"
         "rank = os.environ.get('OMPI_COMM_WORLD_RANK', os.environ.get('PMI_RANK', '0'))\n"
         "with open(os.path.join(sys.argv[1], f'maxrss.{rank}'), 'w') as fh:\n"
         "    fh.write(f'{peak}\\n')\n"
         "print(f\"ESPH_MAXRSS {rank} {peak}\", file=sys.stderr)\n"
         "sys.exit(code)\n")
_RSS_RE = re.compile(r"^ESPH_MAXRSS (\d+) (\d+)$", re.M)
_RESULT_RE = re.compile(r"^RESULT (\S+) (\S+)$", re.M)
_SUMMARY_RE = re.compile(r"^\s+min_style sph/newton: (\d+ (?:solves|MUMPS solves|Hessians).*)$",
                         re.M)


def run_measured(variables: dict, nprocs: int, timeout: float, script: Path = BEAM3D) -> dict:
    """One run of an example script (the 3D beam unless told): its RESULT
    values, wall time, the peak memory of each rank by rank (MB,
    rss_mb_ranks), the largest of them (rss_mb) and the solver's summary
    line."""
    with tempfile.TemporaryDirectory(prefix="esph-rss-") as folder:
        cmd = (mpirun_command(nprocs) + [sys.executable, "-c", _WRAP, folder,
                lmp_binary(), "-in", script.name, "-log", "none", "-nocite"]
               + _var_args(variables))
        launch = run_mpirun(cmd, script.parent, timeout)
        peaks = {int(f.suffix[1:]): int(f.read_text()) for f in Path(folder).glob("maxrss.*")}
    text = launch.proc.stdout + launch.proc.stderr
    if launch.proc.returncode != 0:
        raise RunError(f"{' '.join(cmd)} failed", text[-2000:], text)
    row = {k: float(v) for k, v in _RESULT_RE.findall(launch.proc.stdout)}
    row["wall"] = launch.wall
    for rank, kb in _RSS_RE.findall(text):      # a file lost: the line, if it came
        peaks.setdefault(int(rank), int(kb))
    row["rss_mb_ranks"] = [peaks[rank] / 1024 for rank in sorted(peaks)]
    row["rss_mb"] = max(row["rss_mb_ranks"], default=math.nan)
    summaries = _SUMMARY_RE.findall(text)
    row["summary"] = summaries[-1] if summaries else ""
    return row


def bench3d(dxs, nprocs_list, solvers, side: float, timeout: float) -> list[dict]:
    """Print one row per (dx, ranks, solver) for one body: a square section
    of the given side (H = W = side, L = 10 H), resolved by each dx (the
    default 0.02 m: 10 k atoms at dx = 2 mm, 81 k at 1 mm).  Returns the
    rows as dicts with the fields of results_page.parse_bench3d (a failed
    run: dx, ranks, solver, failed, command), so that a caller can write
    them as JSON (esph bench --suite)."""
    rows = []
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
                    reason = f"failed: {str(failure).splitlines()[0][:100]}"
                    print(f"{dx * 1e3:6.2f} {'':>7} {nprocs:5d} {solver:>7} {reason}  {cmd}",
                          flush=True)
                    rows.append({"dx": dx, "ranks": nprocs, "solver": solver, "failed": reason,
                                 "command": cmd})
                    continue
                except Exception as failure:    # subprocess.TimeoutExpired and the like
                    print(f"{dx * 1e3:6.2f} {'':>7} {nprocs:5d} {solver:>7} "
                          f"{type(failure).__name__}  {cmd}", flush=True)
                    rows.append({"dx": dx, "ranks": nprocs, "solver": solver,
                                 "failed": type(failure).__name__, "command": cmd})
                    continue
                ratio = row["wall"] / dynamics["wall"]
                print(f"{dx * 1e3:6.2f} {int(row['atoms']):7d} {nprocs:5d} {solver:>7} "
                      f"{int(row['steps']):5d} {row['wall']:8.1f} {row['rss_mb']:8.0f} "
                      f"{dynamics['wall']:9.2f} {ratio:6.1f}  {row['summary']}  |  {cmd}",
                      flush=True)
                rows.append({"dx": dx, "atoms": int(row["atoms"]), "ranks": nprocs,
                             "solver": solver, "iterations": int(row["steps"]),
                             "wall": row["wall"], "rss_mb": row["rss_mb"],
                             "dyn100": dynamics["wall"], "ratio": ratio,
                             "solver_log": row["summary"], "command": cmd,
                             "rss_mb_ranks": row["rss_mb_ranks"],
                             "dyn100_command": command_line(BEAM3D, {**geometry, "route": "nve",
                                                                     "nsteps": 100}, nprocs)})
    return rows

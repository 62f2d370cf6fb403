"""Weak scaling of memory: peak resident memory per MPI rank at a constant
number of particles per rank (1, 2, 4 ranks; 4 oversubscribed on 2 cores),
for the 2D beam and the 3D cantilever, in dynamics (route nve, 200 steps)
and in Newton statics (min_style sph/newton, the defaults, and in 2D also
the distributed PETSc solver).  The body grows along its length with the
rank count.  Issue 34 item 3: flat per-rank memory is the target; only the
direct solver (the 2D default) gathers the whole system, on rank 0.

    cd studies/weak_scaling && python weak.py [--ranks 1,2,4] [--cases beam-dyn,...]

Needs the environment of scripts/common.sh (esph_env) for lmp and mpirun.
Prints one row per run: case, ranks, atoms, atoms/rank, wall, peak RSS of
each rank (MB) and its maximum, and that maximum per atom of a rank (kB,
the fixed memory of the process included).
"""
from __future__ import annotations

import argparse
import re
import tempfile
import time
from pathlib import Path

from esph.paths import EXAMPLES, lmp_binary
from esph.runner import mpirun_command, run_mpirun

# case: (example, variables at one rank, the variable scaled with the ranks)
CASES = {
    "beam-dyn": ("beam/in.beam", {"dx": 0.001, "L": 0.2, "route": "nve", "nsteps": 200,
                                  "Fy": -10}, "L"),
    "beam-newton": ("beam/in.beam", {"dx": 0.001, "L": 0.2, "route": "min", "Fy": -10}, "L"),
    # the same with PETSc's distributed solver, which gathers nothing on rank 0
    "beam-newton-petsc": ("beam/in.beam", {"dx": 0.001, "L": 0.2, "route": "min", "Fy": -10,
                                           "linear": "petsc"}, "L"),
    "beam3d-dyn": ("beam3d/in.beam3d", {"dx": 0.002, "L": 0.1, "route": "nve", "nsteps": 200,
                                        "Fy": -100}, "L"),
    "beam3d-newton": ("beam3d/in.beam3d", {"dx": 0.002, "L": 0.1, "route": "min", "Fy": -100},
                      "L"),
}
RSS = re.compile(r"^RSS_KB (\d+)$", re.M)
ATOMS = re.compile(r"Created (\d+) atoms")


def run(case: str, ranks: int) -> dict:
    script, variables, scaled = CASES[case]
    variables = dict(variables)
    variables[scaled] = variables[scaled] * ranks
    path = EXAMPLES / script
    args = []
    for name, value in variables.items():
        args += ["-var", name, str(value)]
    with tempfile.TemporaryDirectory() as tmp:
        # each rank's time appends its line to one file: on the shared
        # stdout the ranks' lines can interleave
        rss_file = Path(tmp) / "rss"
        cmd = mpirun_command(ranks) + ["/usr/bin/time", "-a", "-o", str(rss_file), "-f",
                                       "RSS_KB %M", lmp_binary(), "-in", path.name, "-log",
                                       "none", "-nocite"] + args
        start = time.perf_counter()
        launch = run_mpirun(cmd, path.parent, timeout=3600)
        wall = time.perf_counter() - start
        out = launch.proc.stdout + launch.proc.stderr
        if launch.proc.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed:\n{out[-2000:]}")
        rss = sorted(int(k) / 1024.0 for k in RSS.findall(rss_file.read_text()))
    if len(rss) != ranks:
        raise RuntimeError(f"{' '.join(cmd)}: {len(rss)} memory readings for {ranks} ranks")
    atoms = int(ATOMS.findall(out)[0]) if ATOMS.findall(out) else -1
    return {"case": case, "ranks": ranks, "atoms": atoms, "per_rank": atoms // ranks,
            "wall": wall, "rss": rss}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ranks", default="1,2,4")
    parser.add_argument("--cases", default=",".join(CASES))
    args = parser.parse_args()
    print(f"{'case':>14} {'ranks':>5} {'atoms':>7} {'/rank':>6} {'wall[s]':>8} "
          f"{'max RSS/rank [MB]':>17} {'kB/atom':>7}  per rank [MB]")
    for case in args.cases.split(","):
        for ranks in (int(r) for r in args.ranks.split(",")):
            r = run(case, ranks)
            print(f"{r['case']:>14} {r['ranks']:5d} {r['atoms']:7d} {r['per_rank']:6d} "
                  f"{r['wall']:8.1f} {max(r['rss']):17.1f} "
                  f"{1024.0 * max(r['rss']) / r['per_rank']:7.1f}  "
                  + " ".join(f"{v:.1f}" for v in r["rss"]), flush=True)


if __name__ == "__main__":
    main()

"""Speed against error: for the beam (Fy = -75, -250 N) and the truss
(+3000 N), every scheme and route at several spacings -- the wall time to
equilibrium, the error against the exact answer of the model it runs, and
the throughput in particle-steps per second -- beside LAMMPS's own MACHDYN
smd/tlsph on the same beam; and the plain throughput of the dynamics
(`esph bench`).  Each run is one `mpirun lmp` of an example script; the
command is recorded with the numbers."""
from __future__ import annotations

import os
import platform
import shlex
from dataclasses import asdict, dataclass
from pathlib import Path

from . import plots
from .paths import lmp_binary
from .problems import PROBLEMS, exact_tip
from .report import command_line, machine, print_head, write_rows
from .runner import RunError, run_mpi
from .schemes import BENCH_STYLES, METHODS, Method


CASES = {"beam-75": ("beam", -75.0), "beam-250": ("beam", -250.0), "truss3000": ("truss", 3000.0)}
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


def run_one(problem: str, load: float, method: Method, dx: float, nprocs: int) -> SpeedRow | None:
    """One row: `method` on `problem` at spacing dx, None if it cannot run it."""
    runs = method.script_problem(problem)
    if runs is None:
        return None
    script = PROBLEMS[runs].script
    variables = {**method.variables, PROBLEMS[problem].load_var: load, "dx": dx}
    cmd = command_line(script, variables, nprocs)
    exact = exact_tip(problem, load, dx, method.model)
    try:
        out = run_mpi(script, variables, nprocs, timeout=7200)
    except RunError as err:
        return SpeedRow(problem, load, method.label, dx, 0, 0, float("nan"), float("nan"),
                        float("nan"), float("nan"), exact, float("nan"), f"error: {err.error}",
                        cmd)
    v = out.variables
    value = v["tip_" + PROBLEMS[problem].compared]
    failed = v.get("failed", 0.0) > 0.5
    residual = v.get("residual", float("nan"))
    status = "failed" if failed else ("not at rest" if residual > AT_REST else "ok")
    atoms, steps, loop = int(v["atoms"]), int(v["steps"]), v.get("loop_total", float("nan"))
    return SpeedRow(problem, load, method.label, dx, atoms, steps, out.wall, loop,
                    atoms * steps / loop if loop > 0 else float("nan"), value, exact,
                    value / exact - 1.0, status, cmd, residual)


def print_row(r: SpeedRow) -> None:
    err = "-" if r.error != r.error else f"{100 * r.error:+8.2f}%"
    print(f"{r.problem:>5} {r.load:7.0f} {r.method:<42} {r.dx * 1e3:5g} {r.atoms:6d} {r.steps:8d} "
          f"{r.wall:8.1f} {r.throughput / 1e6:8.3f} {err:>9} {r.status}", flush=True)


def run_all(dxs, nprocs: int, cases=tuple(CASES), methods=tuple(METHODS), progress=print,
            truss_dxs=None) -> list[SpeedRow]:
    """Every method (by name) on every case (by name of CASES): dxs for the
    beam; truss_dxs for the truss, whose height H = 5 cm needs a spacing that
    divides it (default: dxs)."""
    rows = []
    print(f"Speed against error; machine: {machine()}; {nprocs} MPI rank(s); lmp = {lmp_binary()}")
    print(f"{'':>5} {'load':>7} {'method':<42} {'dx':>5} {'atoms':>6} {'steps':>8} {'wall[s]':>8} "
          f"{'Mp-st/s':>8} {'error':>9} status")
    for case in cases:
        problem, load = CASES[case]
        for name in methods:
            method = METHODS[name]
            for dx in (truss_dxs or dxs) if problem == "truss" else dxs:
                progress(f"[esph] {problem} {load:g} N, {method.label}, dx = {dx * 1e3:g} mm ...")
                row = run_one(problem, load, method, dx, nprocs)
                if row:
                    print_row(row)
                    rows.append(row)
    return rows


def speed_table(out: Path, dxs, truss_dxs, nprocs: int, cases, methods, progress=print):
    """run_all, then its rows as JSON and CSV, the commands that reproduce
    them and the log-log plot of error against wall time, in `out`."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rows = run_all(dxs, nprocs, cases, methods, progress=progress, truss_dxs=truss_dxs)
    write_rows(out / "speed.json", [asdict(r) for r in rows])
    with open(out / "commands.txt", "w") as fh:
        fh.write(f"# {machine()}\n")
        fh.writelines(f"{r.command}\n" for r in rows)
    plots.plot_speed(rows, out / "speed_vs_error.png")
    print(f"\nJSON, CSV, commands and the log-log plot of error against wall time in {out}")
    return rows


def throughput(dxs, styles, nprocs_list, steps: int) -> None:
    """Particle-steps per second of undamped fix nve dynamics of the beam
    (MACHDYN: its own integrator) for a fixed number of steps, by LAMMPS's
    loop time."""
    print(f"Throughput, beam under -250 N, undamped dynamics, {steps} steps; machine "
          f"{platform.node()} ({os.cpu_count()} cores), {platform.processor() or platform.machine()}")
    print_head(f"{'style':>8} {'dx[mm]':>7} {'atoms':>7} {'ranks':>5} {'loop[s]':>8} "
               f"{'Mpart-steps/s':>14} {'us/part-step':>12}  command")
    for dx in dxs:
        for style in styles:
            name, extra = BENCH_STYLES[style]
            script = PROBLEMS[name].script
            for nprocs in nprocs_list:
                variables = {**extra, "dx": dx, "route": "nve", "nsteps": steps, "Fy": -250}
                out = run_mpi(script, variables, nprocs)
                natoms, loop = int(out.variables["atoms"]), out.variables["loop_time"]
                rate = natoms * steps / loop
                cmd = command_line(script, variables, nprocs, shlex.quote(lmp_binary()))
                print(f"{style:>8} {dx * 1e3:7.2f} {natoms:7d} {nprocs:5d} {loop:8.3f} "
                      f"{rate / 1e6:14.3f} {nprocs * 1e6 / rate:12.3f}  {cmd}", flush=True)


# throughput of a 3D contact problem: the sphere collision of
# examples/spheres3d, particles per radius R/dx
SPHERES_NR = (6, 10)


@dataclass
class SpheresSpeedRow:
    nr: float                # particles per sphere radius, R/dx
    atoms: int
    nprocs: int
    steps: int
    wall: float              # s, the whole mpirun
    loop: float              # s, LAMMPS's loop time of all runs
    throughput: float        # particle-steps per second of the loop time
    duration_error: float    # contact duration against Hertz
    command: str


def spheres_throughput(nrs=SPHERES_NR, nprocs_list=(1, 2), v: float = 20.0,
                       out: Path | None = None, progress=print) -> list[SpheresSpeedRow]:
    """Particle-steps per second of the 3D sphere collision (pair sph/icb
    with fix sph/contact and its own neighbour list, fix nve) from first
    step to separation: the contact problem beside the beam's dynamics.
    Not a speed-against-error case (no equilibrium to reach), so a table of
    its own."""
    from .spheres3d import SPHERES3D, SpheresCase, run_spheres
    print(f"\nThroughput, two spheres colliding in 3d (examples/spheres3d, {v:g} m/s each, to "
          f"separation); machine {platform.node()} ({os.cpu_count()} cores)")
    print_head(f"{'R/dx':>5} {'atoms':>7} {'ranks':>5} {'steps':>6} {'wall[s]':>8} {'loop[s]':>8} "
               f"{'Mpart-steps/s':>14} {'t_c/Hertz-1':>11}  command")
    rows = []
    for nr in nrs:
        for nprocs in nprocs_list:
            progress(f"[esph] spheres3d R/dx = {nr:g}, {nprocs} rank(s) ...")
            case = SpheresCase(nr=nr, v=v)
            res = run_spheres(case, nprocs)
            cmd = command_line(SPHERES3D, case.variables(), nprocs, shlex.quote(lmp_binary()))
            row = SpheresSpeedRow(nr, res.atoms, nprocs, res.steps, res.wall, res.loop,
                                  res.throughput, res.duration_error, cmd)
            print(f"{nr:5g} {row.atoms:7d} {nprocs:5d} {row.steps:6d} {row.wall:8.2f} "
                  f"{row.loop:8.3f} {row.throughput / 1e6:14.3f} "
                  f"{100 * row.duration_error:+10.1f}%  {cmd}", flush=True)
            rows.append(row)
    if out is not None:
        write_rows(Path(out) / "spheres3d_speed.json", [asdict(r) for r in rows])
    return rows

"""Command line: python -m esph {validate,bench} ...  (see --help)."""
from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import shlex
import sys
from dataclasses import asdict
from pathlib import Path

from . import figures, speed, theory
from .beam import BeamCase, run_beam
from .paths import lmp_binary
from .runner import BEAM, BEAM_TLSPH, run_mpi


def _progress(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def write_rows(path: Path, rows: list[dict]) -> None:
    """The rows as JSON at `path` and as CSV beside it (same name, .csv), one
    column per field of any row, for a spreadsheet or pandas."""
    path = Path(path)
    path.write_text(json.dumps(rows, indent=1))
    fields = list(dict.fromkeys(key for row in rows for key in row))
    with open(path.with_suffix(".csv"), "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields, restval="")
        writer.writeheader()
        writer.writerows(rows)


def cmd_validate(args) -> int:
    """The paper's Tables 1-4 for ICB (quick or --full), plus the CCB/CCBWAT
    failure matrix in full mode."""
    from . import validate
    for variant in args.variants.split(","):
        if variant not in validate.VARIANT_LABELS:
            print(f"unknown variant {variant!r}: choose from {', '.join(validate.VARIANT_LABELS)}",
                  file=sys.stderr)
            return 2
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"{'Full' if args.full else 'Quick'} validation of pair_style sph/icb against the exact "
          f"theory and Tran-Duc et al. (2023), {args.np} MPI rank(s); tip = centroid of the last "
          f"column, compared at the same material point.  Output in {out}.")
    run = validate.Runner(nprocs=args.np, stress=args.stress, route=args.route, solver=args.solver,
                          hourglass=args.hourglass, progress=_progress)
    loads = [float(x) for x in args.loads.split(",")]
    rows = validate.run_all(run, args.variants.split(","), args.full, args.tables, args.dx, loads)
    data = validate.rows_as_dicts(rows)
    if args.full and "m" in args.tables:
        from . import matrix
        data += [asdict(r) for r in matrix.beam_table(args.dx, args.np, 10.0, progress=_progress)]
        data += [asdict(r) for r in matrix.truss_table(args.dx, args.np, 10.0, progress=_progress)]
    write_rows(out / "validate.json", data)
    if args.json:
        write_rows(Path(args.json), data)
    if any(r.table in "24" for r in rows):
        validate.plot_convergence(rows, out / "convergence.png")
        print(f"\nconvergence plot: {out / 'convergence.png'}")
    return 0


BENCH_STYLES = {
    "icb": (BEAM, {"scheme": "icb"}),
    "icb-pk1": (BEAM, {"scheme": "icb", "stress": "pk1"}),
    "ccb": (BEAM, {"scheme": "ccb"}),
    "ccbwat": (BEAM, {"scheme": "ccbwat"}),
    "tlsph": (BEAM_TLSPH, {}),
}


def cmd_bench(args) -> int:
    """Throughput on the beam: fix nve dynamics (MACHDYN: its own integrator)
    for a fixed number of steps, LAMMPS's loop time."""
    print(f"Throughput, beam under -250 N, undamped dynamics, {args.steps} steps; machine "
          f"{platform.node()} ({os.cpu_count()} cores), {platform.processor() or platform.machine()}")
    print(f"{'style':>8} {'dx[mm]':>7} {'atoms':>7} {'ranks':>5} {'loop[s]':>8} {'Mpart-steps/s':>14}"
          f" {'us/part-step':>12}  command")
    for dx in [float(x) for x in args.dx.split(",")]:
        for style in args.styles.split(","):
            script, extra = BENCH_STYLES[style]
            for nprocs in [int(x) for x in args.np.split(",")]:
                variables = {**extra, "dx": dx, "route": "nve", "nsteps": args.steps, "Fy": -250}
                out = run_mpi(script, variables, nprocs)
                natoms, loop = int(out.variables["atoms"]), out.variables["loop_time"]
                rate = natoms * args.steps / loop
                cmd = (f"mpirun -np {nprocs} {shlex.quote(lmp_binary())} -in "
                       f"examples/beam/{script.name} "
                       + " ".join(f"-var {k} {v}" for k, v in variables.items()))
                print(f"{style:>8} {dx * 1e3:7.2f} {natoms:7d} {nprocs:5d} {loop:8.3f} "
                      f"{rate / 1e6:14.3f} {nprocs * 1e6 / rate:12.3f}  {cmd}", flush=True)
    return 0


def cmd_matrix(args) -> int:
    """The paper's Tables 1 and 3, ours side by side."""
    from . import matrix
    print(f"Failure matrix: ICB by minimisation (stress pk1), CCB and CCBWAT by damped dynamics "
          f"(fix viscous at 2 omega1 for {args.tdamp:g}/omega1) from a suddenly applied load; "
          f"a run fails when initially adjacent particles are farther apart than 2h; "
          f"{args.np} MPI rank(s).")
    rows = []
    if args.problem in ("beam", "both"):
        rows += matrix.beam_table(args.dx, args.np, args.tdamp, progress=_progress)
    if args.problem in ("truss", "both"):
        rows += matrix.truss_table(args.dx, args.np, args.tdamp, progress=_progress)
    if args.json:
        write_rows(Path(args.json), [asdict(r) for r in rows])
    return 0


def cmd_rings(args) -> int:
    """Colliding rings: each scheme at each speed, with energy and snapshot plots."""
    from . import rings
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"Colliding rings (outer diameter 0.2 m, wall 1 cm, E = 20 GPa, nu = 0.3, plane "
          f"stress, rho = 1000), dx = {args.dx * 1e3:g} mm, {args.tend * 1e3:g} ms, "
          f"{args.np} MPI rank(s); output in {out}")
    head = (f"{'scheme':>7} {'v':>4} {'atoms':>6} {'steps':>7} {'wall[s]':>8} {'rebound':>8} "
            f"{'e':>5} {'contact[ms]':>15} {'F_max[N]':>9} {'overlap':>7} {'strain':>6} "
            f"{'dE/E0':>9} {'|p|':>8} {'mirror/dx':>9} {'failed[ms]':>10}")
    print(head)
    print("-" * len(head))
    rows = []
    for scheme in args.schemes.split(","):
        for speed in (float(v) for v in args.speeds.split(",")):
            _progress(f"[esph] rings {scheme} {speed:g} m/s ...")
            case = rings.RingsCase(scheme=scheme, v=speed, dx=args.dx, tend=args.tend,
                                   stress=args.stress, grad=args.grad, volumes=args.volumes,
                                   snap=args.snap)
            res = rings.run_rings(case, out, nprocs=args.np)
            fail = "-" if res.t_fail != res.t_fail else f"{res.t_fail * 1e3:.3f}"
            print(f"{scheme:>7} {speed:4g} {res.atoms:6d} {res.steps:7d} {res.wall:8.1f} "
                  f"{res.rebound_speed:8.3f} {res.restitution:5.2f} "
                  f"{res.contact_start * 1e3:7.3f}-{res.contact_end * 1e3:7.3f} "
                  f"{res.max_contact_force:9.1f} {res.max_overlap:7.3f} "
                  f"{res.max_strain_share:6.2f} {res.energy_error:9.2e} "
                  f"{res.momentum_error:8.1e} {res.mirror_error:9.1e} {fail:>10}",
                  flush=True)
            rows.append(res.row())
            rings.plot_energies(res, out / f"energy_{case.tag}.png")
            dumps = sorted(out.glob(f"rings_{case.tag}.*.dump"))
            if dumps:
                figures.plot_snapshots(dumps, out / f"snapshots_{case.tag}.png",
                                     f"{scheme}, {speed:g} m/s: von Mises stress")
    print("rebound = mean |vx| of the rings at the end; e = rebound/initial speed; contact = "
          "first-last time in contact (nan: still in contact); strain = largest strain energy "
          "/ initial kinetic energy; dE/E0 = largest total-energy error; |p| = largest total "
          "momentum / sum m|v0|; mirror = largest distance of a ring-1 particle from the "
          "mirror image of ring 2, over the snapshots")
    write_rows(out / "rings.json", rows)
    return 0


def cmd_speed(args) -> int:
    """Speed against error, beside MACHDYN smd/tlsph."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    dxs = [float(x) for x in args.dx.split(",")]
    problems = [p for p in speed.PROBLEMS if f"{p[0]}{p[1]:g}" in args.problems.split(",")]
    methods = [m for k, m in enumerate(speed.METHODS) if str(k) in args.methods]
    truss_dxs = [float(x) for x in args.truss_dx.split(",")]
    rows = speed.run_all(dxs, args.np, problems, methods, progress=_progress, truss_dxs=truss_dxs)
    write_rows(out / "speed.json", speed.as_dicts(rows))
    with open(out / "commands.txt", "w") as fh:
        fh.write(f"# {speed.machine()}\n")
        fh.writelines(f"{r.command}\n" for r in rows)
    speed.plot(rows, out / "speed_vs_error.png")
    print(f"\nJSON, CSV, commands and the log-log plot of error against wall time in {out}")
    return 0


def cmd_statics(args) -> int:
    """Time to the static beam by Newton, CG and damped dynamics."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = speed.statics(args.dx, [int(n) for n in args.np.split(",")], args.routes.split(","),
                         progress=_progress)
    write_rows(out / "statics.json", [asdict(r) for r in rows])
    print(f"\nJSON and CSV (with the command of every row) in {out / 'statics.json'}, .csv")
    return 0


def cmd_figures(args) -> int:
    """The paper's beam figures: snapshots coloured by von Mises stress."""
    print(f"Beam under Fy = {args.load:g} N by damped dynamics, dx = {args.dx * 1e3:g} mm, "
          f"snapshots every {args.snap * 1e3:g} ms (rings: esph rings)")
    figures.beam_figures(Path(args.out), args.load, args.dx, args.snap,
                         args.schemes.split(","), args.np, progress=_progress)
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="esph", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)

    val = sub.add_parser("validate", help="the paper's Tables 1-4 for ICB against exact theory")
    val.add_argument("--full", action="store_true",
                     help="dx down to 0.5 mm, all loads, and the CCB/CCBWAT failure matrix "
                          "(about 70 min on one core); default: quick (about 1 min)")
    val.add_argument("--tables", default="12345m",
                     help="which tables: 1 2 3 4 (ICB, the paper's), 5 (the defaults against "
                          "the finite-element continuum, nu = 0 and 0.3, 3D), m (failure matrix, "
                          "with --full)")
    val.add_argument("--dx", type=float, default=0.002,
                     help="particle spacing of Tables 1 and 3 in m (0.002)")
    val.add_argument("--loads", default=",".join(f"{x:g}" for x in theory.PAPER_BEAM_LOADS),
                     help="comma-separated beam loads of Table 1 in N")
    val.add_argument("--out", default="validate-out", help="folder for JSON and PNG output")
    # pk1 is the exact gradient of the strain energy, which minimisation needs;
    # corotated (the paper's measure) reaches equilibrium through --route dyn
    val.add_argument("--stress", default="pk1", choices=["corotated", "pk1"])
    val.add_argument("--route", default="min", choices=["min", "dyn"])
    val.add_argument("--solver", default="newton", choices=["newton", "cg"],
                     help="minimiser of the min route: newton = min_style sph/newton (stress pk1 "
                          "only), cg = conjugate gradients (default: %(default)s)")
    val.add_argument("--hourglass", type=float, default=0.0)
    val.add_argument("--variants", default="linear/fixed,default",
                     help="comma-separated schemes: linear/fixed (the paper's), default (quadratic "
                          "gradient, mirror clamp, exact volumes, face traction), or a "
                          "gradient/clamp pair with cell volumes and a column load: "
                          "quadratic/mirror, quadratic/fixed, linear/mirror (default: "
                          "%(default)s)")
    val.add_argument("--np", type=int, default=1, help="MPI ranks (1 = in-process)")
    val.add_argument("--json", help="write the rows to this JSON file")
    val.set_defaults(func=cmd_validate)

    ben = sub.add_parser("bench", help="throughput in particle-steps per second, beside MACHDYN")
    ben.add_argument("--dx", default="0.002,0.001", help="comma-separated spacings in m")
    ben.add_argument("--np", default="1,2", help="comma-separated MPI rank counts")
    ben.add_argument("--steps", type=int, default=2000)
    ben.add_argument("--styles", default="icb,ccb,tlsph",
                     help="comma-separated: " + ", ".join(BENCH_STYLES) + " (tlsph = MACHDYN "
                          "smd/tlsph on the same beam)")
    ben.set_defaults(func=cmd_bench)

    mat = sub.add_parser("matrix", help="the paper's failure matrix: Tables 1 and 3, all schemes")
    mat.add_argument("--problem", default="both", choices=["beam", "truss", "both"])
    mat.add_argument("--dx", type=float, default=0.002, help="particle spacing in m (0.002)")
    mat.add_argument("--np", type=int, default=2, help="MPI ranks per run (2)")
    mat.add_argument("--tdamp", type=float, default=10.0,
                     help="damped runs last tdamp/omega1: error ~ exp(-tdamp) (10)")
    mat.add_argument("--json", help="write the rows to this JSON file")
    mat.set_defaults(func=cmd_matrix)

    spd = sub.add_parser("speed", help="wall time, throughput and error of every scheme and "
                                       "route, beside MACHDYN smd/tlsph")
    spd.add_argument("--dx", default="0.004,0.002",
                     help="comma-separated spacings in m (0.004,0.002; add 0.001 for the record)")
    spd.add_argument("--truss-dx", default="0.005,0.0025",
                     help="spacings for the truss, which must divide H = 5 cm (0.005,0.0025)")
    spd.add_argument("--problems", default="beam-75,beam-250,truss3000",
                     help="comma-separated problems: beam-75, beam-250, truss3000")
    spd.add_argument("--methods", default="01234567",
                     help="which methods, by index: " + "; ".join(
                         f"{k} {m[0]}" for k, m in enumerate(speed.METHODS)))
    spd.add_argument("--np", type=int, default=1, help="MPI ranks (1)")
    spd.add_argument("--out", default="speed-out", help="output folder (speed-out)")
    spd.set_defaults(func=cmd_speed)

    sta = sub.add_parser("statics", help="time to the static beam (-250 N) by Newton, CG and "
                                         "damped dynamics, against its converged answer")
    sta.add_argument("--dx", type=float, default=0.001, help="particle spacing in m (0.001)")
    sta.add_argument("--np", default="1,2", help="comma-separated MPI rank counts (1,2)")
    sta.add_argument("--routes", default="newton,newton-loose,cg,dyn",
                     help="comma-separated: " + ", ".join(speed.STATICS_ROUTES))
    sta.add_argument("--out", default="speed-out", help="output folder (speed-out)")
    sta.set_defaults(func=cmd_statics)

    fig = sub.add_parser("figures", help="beam snapshots coloured by von Mises stress (the "
                                         "paper's Figures 2-4)")
    fig.add_argument("--load", type=float, default=-250.0, help="tip load in N (-250)")
    fig.add_argument("--dx", type=float, default=0.002, help="particle spacing in m (0.002)")
    fig.add_argument("--snap", type=float, default=0.001, help="seconds between snapshots")
    fig.add_argument("--schemes", default="ccb,ccbwat,icb", help="comma-separated schemes")
    fig.add_argument("--np", type=int, default=1, help="MPI ranks (1)")
    fig.add_argument("--out", default="figures-out", help="output folder (figures-out)")
    fig.set_defaults(func=cmd_figures)

    rng = sub.add_parser("rings", help="colliding rings: energy, rebound, contact, failure, "
                                       "snapshots")
    rng.add_argument("--schemes", default="icb,ccb,ccbwat", help="comma-separated schemes")
    rng.add_argument("--speeds", default="5,8", help="comma-separated ring speeds in m/s")
    rng.add_argument("--dx", type=float, default=0.002, help="particle spacing in m (0.002)")
    rng.add_argument("--tend", type=float, default=0.004, help="simulated time in s (0.004)")
    rng.add_argument("--stress", default="pk1", choices=["corotated", "pk1"],
                     help="icb stress measure (default %(default)s; corotated is the paper's)")
    rng.add_argument("--grad", default="quadratic", choices=["linear", "quadratic"],
                     help="icb gradient correction (default %(default)s; linear is the paper's)")
    rng.add_argument("--volumes", default="exact", choices=["exact", "cells"],
                     help="particle volumes: exact = set_sph_volumes polar (default), cells = "
                          "plain arc cells (the paper's)")
    rng.add_argument("--snap", type=float, default=0.0005,
                     help="seconds between snapshots for the PNGs (0 = none)")
    rng.add_argument("--np", type=int, default=1, help="MPI ranks (1 = in-process)")
    rng.add_argument("--out", default="rings-out", help="output folder (rings-out)")
    rng.set_defaults(func=cmd_rings)

    args = parser.parse_args(argv)
    return args.func(args)

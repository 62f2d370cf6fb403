"""Command line: python -m esph {validate,bench,bench3d,matrix,speed,statics,figures,rings,
spheres3d} ...
(see --help).  This module only parses arguments and hands them to the
module that does the work."""
from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from . import (bench, bench3d, figures, matrix, rings, speed, spheres3d, statics, theory,
               validate, weak)
from .report import progress


def _floats(text: str) -> list[float]:
    return [float(x) for x in text.split(",")]


def _ints(text: str) -> list[int]:
    return [int(x) for x in text.split(",")]


def _names(text: str, allowed, what: str) -> list[str]:
    """The comma-separated names of an option, each one of `allowed`; exit
    status 2, as for argparse's own usage errors, if one is not."""
    names = text.split(",")
    for name in names:
        if name not in allowed:
            print(f"esph: unknown {what} {name!r}: choose from {', '.join(allowed)}",
                  file=sys.stderr)
            raise SystemExit(2)
    return names


def cmd_validate(args) -> int:
    variants = _names(args.variants, validate.VARIANT_LABELS, "variant")
    validate.validate(Path(args.out), variants, args.full, args.tables, args.dx,
                      _floats(args.loads), nprocs=args.np, stress=args.stress, route=args.route,
                      solver=args.solver, hourglass=args.hourglass,
                      json_path=args.json and Path(args.json), progress=progress)
    return 0


def cmd_bench(args) -> int:
    if args.suite:
        return cmd_bench_suite(args)
    speed.throughput(_floats(args.dx), _names(args.styles, speed.BENCH_STYLES, "style"),
                     _ints(args.np), args.steps)
    return 0


def cmd_bench_suite(args) -> int:
    bodies = _names(args.bodies, bench.BODIES, "body")
    h2h_dx = args.h2h_dx and _floats(args.h2h_dx)
    h2h_steps = args.h2h_steps and _ints(args.h2h_steps)
    if h2h_dx and len(h2h_dx) != len(bodies):
        print(f"esph: --h2h-dx needs one spacing per body ({len(bodies)})", file=sys.stderr)
        raise SystemExit(2)
    if h2h_steps and len(h2h_steps) != 2 * len(bodies):
        print(f"esph: --h2h-steps needs ours,MACHDYN per body ({2 * len(bodies)} numbers)",
              file=sys.stderr)
        raise SystemExit(2)
    options = bench.SuiteOptions(
        only=tuple(_names(args.only, bench.PARTS, "part")), reps=args.reps, bodies=tuple(bodies),
        h2h_dx=h2h_dx and tuple(h2h_dx), h2h_steps=h2h_steps and tuple(h2h_steps),
        statics_dx=tuple(_floats(args.statics_dx)), statics_np=tuple(_ints(args.statics_np)),
        statics_side=args.statics_side, statics_timeout=args.timeout,
        weak_cases=tuple(_names(args.weak_cases, weak.CASES, "case")),
        weak_ranks=tuple(_ints(args.weak_ranks)), weak_dx=args.weak_dx,
        weak_steps=args.weak_steps)
    command = shlex.join(["python", "-m", "esph", *args.argv])
    bench.suite(options, args.json_dir and Path(args.json_dir), command, progress=progress)
    return 0


def cmd_bench3d(args) -> int:
    bench3d.bench3d(_floats(args.dx), _ints(args.np),
                    _names(args.solvers, bench3d.SOLVERS, "solver"), args.side, args.timeout)
    return 0


def cmd_matrix(args) -> int:
    matrix.failure_matrix(args.problem, args.dx, args.np, args.tdamp, progress=progress,
                          json_path=args.json and Path(args.json))
    return 0


def cmd_rings(args) -> int:
    rings.run_table(Path(args.out), args.schemes.split(","), _floats(args.speeds), args.dx,
                    args.tend, args.stress, args.grad, args.volumes, args.snap, args.np,
                    progress=progress)
    return 0


def cmd_speed(args) -> int:
    speed.speed_table(Path(args.out), _floats(args.dx), _floats(args.truss_dx), args.np,
                      _names(args.problems, speed.CASES, "problem"),
                      _names(args.methods, speed.METHODS, "method"), progress=progress)
    if args.spheres != "none":
        speed.spheres_throughput(_floats(args.spheres), [args.np], out=Path(args.out),
                                 progress=progress)
    return 0


def cmd_statics(args) -> int:
    routes = _names(args.routes, statics.STATICS_ROUTES, "route")
    statics.statics(args.dx, _ints(args.np), routes, progress=progress, out=Path(args.out))
    return 0


def cmd_figures(args) -> int:
    figures.beam_figures(Path(args.out), args.load, args.dx, args.snap, args.schemes.split(","),
                         args.np, progress=progress)
    return 0


def cmd_spheres3d(args) -> int:
    spheres3d.run_table(_floats(args.nr), args.v, _ints(args.np), out=Path(args.out),
                        progress=progress, stress=args.stress, volumes=args.volumes)
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="esph", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)

    val = sub.add_parser("validate", help="the paper's Tables 1-4 for ICB against exact theory")
    val.add_argument("--full", action="store_true",
                     help="dx down to 0.5 mm, all loads, and the CCB/CCBWAT failure matrix "
                          "(about 70 min on one core); default: quick (a few minutes, Table 10's "
                          "gate run about 3 of them on one core)")
    val.add_argument("--tables", default="123456789gm",
                     help="which tables: 1 2 3 4 (ICB, the paper's), 5 (the defaults against "
                          "the finite-element continuum, nu = 0 and 0.3, 3D), 6 (two spheres "
                          "colliding in 3D against Hertz), 7 (Lame's thick-walled cylinder, a "
                          "curved body under pressure), 8 (the beam under its own weight "
                          "against the FE continuum), 9 (the hydrostatic plate: RHEO's water on an "
                          "elastic plate against the FE continuum), g (Table 10, the elastic-gate "
                          "dam break against Antoci's experiment), m (failure matrix, with "
                          "--full)")
    val.add_argument("--dx", type=float, default=0.002,
                     help="particle spacing of Tables 1 and 3 in m (0.002)")
    val.add_argument("--loads", default=",".join(f"{x:g}" for x in theory.PAPER_BEAM_LOADS),
                     help="comma-separated beam loads of Table 1 in N")
    val.add_argument("--out", default="validate-out", help="folder for JSON and PNG output")
    # pk1 is the exact gradient of the strain energy; corotated (the paper's
    # measure) has none, and min_style sph/newton treats it by Newton-Krylov
    val.add_argument("--stress", default="pk1", choices=["corotated", "pk1"])
    val.add_argument("--route", default="min", choices=["min", "dyn"])
    val.add_argument("--solver", default="newton", choices=["newton", "cg"],
                     help="minimiser of the min route: newton = min_style sph/newton (Newton-Krylov "
                          "for corotated), cg = conjugate gradients (default: %(default)s)")
    val.add_argument("--hourglass", type=float, default=None,
                     help="hourglass-control coefficient of every variant (default: each "
                          "variant's own, 0.2 for default, 0 for the others)")
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
                     help="comma-separated: " + ", ".join(speed.BENCH_STYLES) + " (tlsph = MACHDYN "
                          "smd/tlsph on the same beam; icb3d and tlsph3d: the 3d cantilever, e.g. "
                          "--dx 0.002 --steps 200)")
    ben.add_argument("--suite", action="store_true",
                     help="the extended benchmark (scripts/bench without arguments) instead: "
                          "head to head with MACHDYN, 3D statics against dynamics, weak scaling "
                          "of memory; --dx, --np, --steps and --styles do not apply")
    ben.add_argument("--only", default=",".join(bench.PARTS),
                     help="--suite: comma-separated parts: " + ", ".join(bench.PARTS))
    ben.add_argument("--reps", type=int, default=3,
                     help="--suite: alternating runs per head-to-head variant, best kept (3)")
    ben.add_argument("--json-dir", help="--suite: write headtohead.json, statics_bench.json and "
                     "weak.json here, each with its entry in sources.json (scripts/bench: "
                     "doc/results)")
    ben.add_argument("--bodies", default=",".join(bench.BODIES),
                     help="--suite: head-to-head bodies: " + ", ".join(
                         f"{k} ({b.label})" for k, b in bench.BODIES.items()))
    ben.add_argument("--h2h-dx", help="--suite: one spacing per body, replacing " + ", ".join(
        f"{b.variables['dx']:g}" for b in bench.BODIES.values()))
    ben.add_argument("--h2h-steps", help="--suite: steps per run, ours,MACHDYN per body, "
                     "replacing " + ",".join(f"{b.steps},{b.machdyn_steps}"
                                             for b in bench.BODIES.values()))
    ben.add_argument("--statics-dx", default="0.002,0.001",
                     help="--suite: spacings of the 3D statics (0.002: 10k particles, 0.001: "
                          "81k)")
    ben.add_argument("--statics-np", default="2", help="--suite: ranks of the 3D statics (2)")
    ben.add_argument("--statics-side", type=float, default=0.02,
                     help="--suite: section side of the 3D statics' body in m, L = 10 side "
                          "(0.02)")
    ben.add_argument("--timeout", type=float, default=3600,
                     help="--suite: seconds per statics run (3600)")
    ben.add_argument("--weak-cases", default=",".join(weak.CASES),
                     help="--suite: weak-scaling cases: " + ", ".join(weak.CASES))
    ben.add_argument("--weak-ranks", default=",".join(map(str, weak.RANKS)),
                     help="--suite: weak-scaling rank counts (1,2,4)")
    ben.add_argument("--weak-dx", type=float,
                     help="--suite: spacing of every weak-scaling case (default: each case's own)")
    ben.add_argument("--weak-steps", type=int,
                     help="--suite: steps of the weak-scaling dynamics (default 200)")
    ben.set_defaults(func=cmd_bench)

    b3d = sub.add_parser("bench3d", help="3D cantilever statics per linear solver: iterations, "
                         "time, memory per rank, ratio to 100 dynamic steps")
    b3d.add_argument("--dx", default="0.002", help="comma-separated spacings in m (0.002: 10k "
                     "atoms; 0.001 is the 81k-atom case)")
    b3d.add_argument("--np", default="1,2", help="comma-separated MPI rank counts (1,2; add 4 "
                     "to oversubscribe for communication volume)")
    b3d.add_argument("--solvers", default=",".join(bench3d.SOLVERS),
                     help="comma-separated min_modify solver values: " + ", ".join(bench3d.SOLVERS))
    b3d.add_argument("--side", type=float, default=0.02,
                     help="side of the square section in m (0.02): H = W = side, L = 10 H")
    b3d.add_argument("--timeout", type=float, default=1800, help="seconds per run (1800)")
    b3d.set_defaults(func=cmd_bench3d)

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
    spd.add_argument("--problems", default=",".join(speed.CASES),
                     help="comma-separated problems: " + ", ".join(speed.CASES))
    spd.add_argument("--methods", default=",".join(speed.METHODS),
                     help="comma-separated methods by name: " + "; ".join(
                         f"{name} = {m.label}" for name, m in speed.METHODS.items()))
    spd.add_argument("--np", type=int, default=1, help="MPI ranks (1)")
    spd.add_argument("--out", default="speed-out", help="output folder (speed-out)")
    spd.add_argument("--spheres", default=",".join(f"{nr:g}" for nr in speed.SPHERES_NR),
                     help="comma-separated R/dx of the 3D sphere collision's throughput rows "
                          "after the table, or none (default: %(default)s)")
    spd.set_defaults(func=cmd_speed)

    sta = sub.add_parser("statics", help="time to the static beam (-250 N) by Newton, CG and "
                                         "damped dynamics, against its converged answer")
    sta.add_argument("--dx", type=float, default=0.001, help="particle spacing in m (0.001)")
    sta.add_argument("--np", default="1,2", help="comma-separated MPI rank counts (1,2)")
    sta.add_argument("--routes", default="newton,newton-loose,cg,dyn,newton-corotated",
                     help="comma-separated: " + ", ".join(statics.STATICS_ROUTES))
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

    sph = sub.add_parser("spheres3d", help="two spheres colliding in 3D (fix sph/contact) against "
                                           "Hertz: contact duration, peak force, restitution, "
                                           "balances, throughput")
    sph.add_argument("--nr", default="6,8", help="comma-separated particles per radius R/dx (6,8)")
    sph.add_argument("--v", type=float, default=20.0, help="speed of each sphere in m/s (20)")
    sph.add_argument("--stress", default="pk1", choices=["corotated", "pk1"],
                     help="icb stress measure (default %(default)s)")
    sph.add_argument("--volumes", default="exact", choices=["exact", "cells"],
                     help="exact = set_sph_volumes lattice (default), cells = plain dx^3")
    sph.add_argument("--np", default="1", help="comma-separated MPI rank counts (1)")
    sph.add_argument("--out", default="spheres3d-out", help="output folder (spheres3d-out)")
    sph.set_defaults(func=cmd_spheres3d)

    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)   # recorded with the results
    return args.func(args)

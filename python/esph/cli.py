"""Command line: python -m esph {validate,bench} ...  (see --help)."""
from __future__ import annotations

import argparse
import json
import os
import platform
import shlex
import sys
from dataclasses import asdict
from pathlib import Path

from . import theory
from .beam import BeamCase, run_beam
from .paths import lmp_binary
from .runner import BEAM, run_mpi


def _progress(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


VARIANT_LABELS = {"linear/fixed": "the paper's scheme: linear gradient correction, fixed clamp",
                  "quadratic/fixed": "gradient exact for quadratic fields, fixed clamp",
                  "quadratic/mirror": "gradient exact for quadratic fields, mirror clamp",
                  "linear/mirror": "linear gradient correction, mirror clamp"}


def _validate_table(args, variant: str, paper: dict) -> tuple[float, list]:
    loads = [float(x) for x in args.loads.split(",")]
    gradient, clamp = variant.split("/")
    print(f"\nCantilever beam, pair_style sph/icb, {VARIANT_LABELS[variant]}, "
          f"dx = {args.dx * 1e3:g} mm, nu = {args.nu:g}, plane {args.plane}, stress {args.stress}, "
          f"route {args.route}, hourglass {args.hourglass:g}")
    head = (f"{'Fy[N]':>7} {'dv[mm]':>9} {'exact':>9} {'paper':>8} {'err_dv':>7} {'paper':>7} | "
            f"{'dh[mm]':>8} {'exact':>8} {'paper':>7} {'err_dh':>7} | {'steps':>6} {'wall[s]':>7}")
    print(head)
    print("-" * len(head))
    rows = []
    worst = 0.0
    for load in loads:
        _progress(f"[esph] beam {variant}, Fy = {load:g} N ...")
        case = BeamCase(load=load, dx=args.dx, nu=args.nu, plane=args.plane, stress=args.stress,
                        route=args.route, hourglass=args.hourglass, gradient=gradient, clamp=clamp)
        res = run_beam(case, nprocs=args.np)
        ex_dh, ex_dv = res.exact
        p_dv, p_dh = paper.get(load, (float("nan"), float("nan")))
        p_err = p_dv * 1e-3 / ex_dv - 1.0
        worst = max(worst, abs(res.error_dv))
        print(f"{load:7.0f} {res.dv * 1e3:9.4f} {ex_dv * 1e3:9.4f} {p_dv:8.2f} "
              f"{100 * res.error_dv:6.2f}% {100 * p_err:6.2f}% | {res.dh * 1e3:8.4f} "
              f"{ex_dh * 1e3:8.4f} {p_dh:7.3f} {100 * res.error_dh:6.2f}% | {res.steps:6d} "
              f"{res.wall:7.2f}", flush=True)
        rows.append({**asdict(case), "dv": res.dv, "dh": res.dh, "exact_dv": ex_dv, "exact_dh": ex_dh,
                     "paper_dv_mm": p_dv, "paper_dh_mm": p_dh, "err_dv": res.error_dv,
                     "paper_err_dv": p_err, "err_dh": res.error_dh, "steps": res.steps,
                     "natoms": res.natoms, "wall": res.wall})
    print(f"largest |error| in dv, {variant}: {100 * worst:.2f}%")
    return worst, rows


def cmd_validate(args) -> int:
    paper = dict(zip(theory.PAPER_BEAM_LOADS, zip(theory.PAPER_BEAM["ICB"]["dv"],
                                                    theory.PAPER_BEAM["ICB"]["dh"])))
    print("Tip = centroid of the last column; exact = elastica at the same material point "
          "(s = L - dx/2);\npaper = Table 1 ICB at dx = 2 mm, its error taken against the same "
          "exact value.")
    rows = []
    for variant in args.variants.split(","):
        if variant not in VARIANT_LABELS:
            print(f"unknown variant {variant!r}: choose from {', '.join(VARIANT_LABELS)}",
                  file=sys.stderr)
            return 2
        rows += _validate_table(args, variant, paper)[1]
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


def cmd_bench(args) -> int:
    """Throughput of sph/icb on the beam: fix nve dynamics for a fixed number of steps."""
    print(f"sph/icb throughput, beam, fix nve, {args.steps} steps; machine {platform.node()} "
          f"({os.cpu_count()} cores), {platform.processor() or platform.machine()}")
    print(f"{'dx[mm]':>7} {'atoms':>7} {'ranks':>5} {'loop[s]':>8} {'Mpart-steps/s':>14}  command")
    for dx in [float(x) for x in args.dx.split(",")]:
        for nprocs in [int(x) for x in args.np.split(",")]:
            variables = {"dx": dx, "route": "nve", "nsteps": args.steps, "Fy": -250}
            out = run_mpi(BEAM, variables, nprocs)
            natoms, loop = int(out.variables["atoms"]), out.variables["loop_time"]
            rate = natoms * args.steps / loop / 1e6
            cmd = (f"mpirun -np {nprocs} {shlex.quote(lmp_binary())} -in examples/beam/in.beam "
                   + " ".join(f"-var {k} {v}" for k, v in variables.items()))
            print(f"{dx * 1e3:7.2f} {natoms:7d} {nprocs:5d} {loop:8.3f} {rate:14.3f}  {cmd}",
                  flush=True)
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
        Path(args.json).write_text(json.dumps([asdict(r) for r in rows], indent=1))
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
                                   stress=args.stress, snap=args.snap)
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
                rings.plot_snapshots(dumps, out / f"snapshots_{case.tag}.png",
                                     f"{scheme}, {speed:g} m/s: von Mises stress")
    print("rebound = mean |vx| of the rings at the end; e = rebound/initial speed; contact = "
          "first-last time in contact (nan: still in contact); strain = largest strain energy "
          "/ initial kinetic energy; dE/E0 = largest total-energy error; |p| = largest total "
          "momentum / sum m|v0|; mirror = largest distance of a ring-1 particle from the "
          "mirror image of ring 2, over the snapshots")
    (out / "rings.json").write_text(json.dumps(rows, indent=1))
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="esph", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)

    val = sub.add_parser("validate", help="beam validation table against the exact elastica")
    val.add_argument("--dx", type=float, default=0.002, help="particle spacing in m (0.002)")
    val.add_argument("--loads", default=",".join(f"{x:g}" for x in theory.PAPER_BEAM_LOADS),
                     help="comma-separated tip loads in N")
    val.add_argument("--nu", type=float, default=0.0)
    val.add_argument("--plane", default="stress", choices=["stress", "strain"])
    # pk1 is the exact gradient of the strain energy, which the CG minimiser needs;
    # corotated (the paper's measure) reaches equilibrium through --route dyn
    val.add_argument("--stress", default="pk1", choices=["corotated", "pk1"])
    val.add_argument("--route", default="min", choices=["min", "dyn"])
    val.add_argument("--hourglass", type=float, default=0.0)
    val.add_argument("--variants", default="linear/fixed,quadratic/mirror",
                     help="comma-separated gradient/clamp pairs: gradient linear (paper) or "
                          "quadratic, clamp fixed (paper) or mirror (default: %(default)s)")
    val.add_argument("--np", type=int, default=1, help="MPI ranks (1 = in-process)")
    val.add_argument("--json", help="write the rows to this JSON file")
    val.set_defaults(func=cmd_validate)

    ben = sub.add_parser("bench", help="sph/icb throughput in particle-steps per second")
    ben.add_argument("--dx", default="0.002,0.001", help="comma-separated spacings in m")
    ben.add_argument("--np", default="1,2", help="comma-separated MPI rank counts")
    ben.add_argument("--steps", type=int, default=2000)
    ben.set_defaults(func=cmd_bench)

    mat = sub.add_parser("matrix", help="the paper's failure matrix: Tables 1 and 3, all schemes")
    mat.add_argument("--problem", default="both", choices=["beam", "truss", "both"])
    mat.add_argument("--dx", type=float, default=0.002, help="particle spacing in m (0.002)")
    mat.add_argument("--np", type=int, default=2, help="MPI ranks per run (2)")
    mat.add_argument("--tdamp", type=float, default=10.0,
                     help="damped runs last tdamp/omega1: error ~ exp(-tdamp) (10)")
    mat.add_argument("--json", help="write the rows to this JSON file")
    mat.set_defaults(func=cmd_matrix)

    rng = sub.add_parser("rings", help="colliding rings: energy, rebound, contact, failure, "
                                       "snapshots")
    rng.add_argument("--schemes", default="icb,ccb,ccbwat", help="comma-separated schemes")
    rng.add_argument("--speeds", default="5,8", help="comma-separated ring speeds in m/s")
    rng.add_argument("--dx", type=float, default=0.002, help="particle spacing in m (0.002)")
    rng.add_argument("--tend", type=float, default=0.004, help="simulated time in s (0.004)")
    rng.add_argument("--stress", default="corotated", choices=["corotated", "pk1"],
                     help="icb stress measure (corotated, the paper's)")
    rng.add_argument("--snap", type=float, default=0.0005,
                     help="seconds between snapshots for the PNGs (0 = none)")
    rng.add_argument("--np", type=int, default=1, help="MPI ranks (1 = in-process)")
    rng.add_argument("--out", default="rings-out", help="output folder (rings-out)")
    rng.set_defaults(func=cmd_rings)

    args = parser.parse_args(argv)
    return args.func(args)

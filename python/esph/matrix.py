"""The paper's failure matrix (Tables 1 and 3): every scheme on the beam and
the truss, survived or failed (with the time of failure), displacement and
error against the exact answer of the model the scheme runs."""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

from . import theory
from .problems import BEAM, PROBLEMS, TRUSS, beam_exact, truss_exact
from .report import print_head, write_rows
from .runner import RunError, run_mpi
from .schemes import PAIR_SCHEMES

SCHEMES = tuple(PAIR_SCHEMES)
PAPER_NAME = {name: s.paper_name for name, s in PAIR_SCHEMES.items()}


@dataclass
class Outcome:
    scheme: str
    load: float
    dh: float = float("nan")
    dv: float = float("nan")
    failed: bool = False
    time: float = float("nan")     # s, end of the run or time of failure
    reason: str = ""
    steps: int = 0
    wall: float = 0.0

    def status(self) -> str:
        if not self.failed:
            return "ok"
        return f"FAILED t={self.time * 1e3:.3f}ms" if self.time == self.time else "FAILED"


def run_case(script, scheme: str, variables: dict, nprocs: int) -> Outcome:
    """ICB by minimisation (pk1: exact energy gradient), CCB and CCBWAT by
    damped dynamics (schemes.PAIR_SCHEMES) with the failure monitor of
    examples/common/in.failure."""
    load = variables.get("Fy", variables.get("Fx"))
    out = Outcome(scheme, load)
    try:
        res = run_mpi(script, {**variables, "scheme": scheme, **PAIR_SCHEMES[scheme].variables},
                      nprocs)
    except RunError as err:      # a LAMMPS error: non-finite state, inverted particle
        out.failed, out.reason = True, err.error
        return out
    v = res.variables
    out.dh, out.dv = v["tip_dh"], v["tip_dv"]
    out.failed = v.get("failed", 0.0) > 0.5
    out.time, out.steps, out.wall = v["time"], int(v["steps"]), res.wall
    if out.failed:
        out.reason = "adjacent particles farther apart than 2h"
    return out


def _geometry(problem: str) -> str:
    p = PROBLEMS[problem]
    return f"L = {p.L:g} m, H = {p.H * 100:g} cm, E = {p.E / 1e9:g} GPa"


def beam_table(dx: float, nprocs: int, tdamp: float, loads=theory.PAPER_BEAM_LOADS,
               progress=print) -> list[Outcome]:
    rows = []
    print(f"\nTable 1: beam ({_geometry('beam')}, nu = 0, plane stress), dx = "
          f"{dx * 1e3:g} mm; tip dv in mm, error against the elastica at s = L - dx/2")
    head = f"{'Fy[N]':>6} {'exact':>8} | " + " | ".join(
        f"{PAPER_NAME[s]:>6} {'ours':>8} {'err':>6} {'paper':>7}" for s in SCHEMES)
    print_head(head)
    for k, load in enumerate(loads):
        exact = beam_exact(load, dx)[1]
        cells = []
        for scheme in SCHEMES:
            progress(f"[esph] beam {scheme} Fy = {load:g} N ...")
            o = run_case(BEAM, scheme, {"Fy": load, "dx": dx, "tdamp": tdamp}, nprocs)
            rows.append(o)
            paper = theory.PAPER_BEAM[PAPER_NAME[scheme]]["dv"][k]
            paper_txt = f"{paper:7.2f}" if paper is not None else f"{'broken':>7}"
            if o.failed:
                cells.append(f"{'':>6} {o.status():>15} {paper_txt}")
            else:
                cells.append(f"{'':>6} {o.dv * 1e3:8.3f} {100 * (o.dv / exact - 1):5.1f}% {paper_txt}")
        print(f"{load:6.0f} {exact * 1e3:8.3f} | " + " | ".join(cells), flush=True)
    return rows


def truss_table(dx: float, nprocs: int, tdamp: float, loads=theory.PAPER_TRUSS_LOADS,
                progress=print) -> list[Outcome]:
    truss = theory.Truss()
    rows = []
    print(f"\nTable 3: truss ({_geometry('truss')}, nu = 0, plane stress), dx = "
          f"{dx * 1e3:g} mm; tip dh in mm.  exact = the scheme's own model at X = L - dx/2 "
          "(ICB: Green strain + SVK, P = F S; CCB: Jaumann rate, E ln(stretch) = F/A); "
          "linear = F L/(A E); lateral = |tip dv| (buckling shows here)")
    head = f"{'Fx[N]':>6} {'linear':>7} | " + " | ".join(
        f"{PAPER_NAME[s]:>6} {'ours':>8} {'exact':>8} {'err':>6} {'lateral':>8} {'paper':>7}"
        for s in SCHEMES)
    print_head(head)
    for k, load in enumerate(loads):
        cells = []
        for scheme in SCHEMES:
            progress(f"[esph] truss {scheme} Fx = {load:g} N ...")
            o = run_case(TRUSS, scheme, {"Fx": load, "dx": dx, "tdamp": tdamp}, nprocs)
            rows.append(o)
            exact = truss_exact(load, dx, PAIR_SCHEMES[scheme].model)
            paper = theory.PAPER_TRUSS[PAPER_NAME[scheme]][k]
            paper_txt = f"{paper:7.2f}" if paper is not None else f"{'broken':>7}"
            if o.failed:
                cells.append(f"{'':>6} {o.status():>33} {paper_txt}")
            else:
                cells.append(f"{'':>6} {o.dh * 1e3:8.3f} {exact * 1e3:8.3f} "
                             f"{100 * (o.dh / exact - 1):5.1f}% {abs(o.dv) * 1e3:8.4f} {paper_txt}")
        print(f"{load:6.0f} {truss.linear(load) * 1e3:7.2f} | " + " | ".join(cells), flush=True)
    return rows


def failure_matrix(problem: str, dx: float, nprocs: int, tdamp: float, progress=print,
                   json_path: Path | None = None) -> list[Outcome]:
    """Tables 1 and/or 3 (problem beam, truss or both), rows optionally
    written as JSON and CSV."""
    print(f"Failure matrix: ICB by minimisation (stress pk1), CCB and CCBWAT by damped dynamics "
          f"(fix viscous at 2 omega1 for {tdamp:g}/omega1) from a suddenly applied load; "
          f"a run fails when initially adjacent particles are farther apart than 2h; "
          f"{nprocs} MPI rank(s).")
    rows = []
    if problem in ("beam", "both"):
        rows += beam_table(dx, nprocs, tdamp, progress=progress)
    if problem in ("truss", "both"):
        rows += truss_table(dx, nprocs, tdamp, progress=progress)
    if json_path:
        write_rows(Path(json_path), [asdict(r) for r in rows])
    return rows

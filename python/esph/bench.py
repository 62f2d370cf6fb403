"""The extended benchmark of `scripts/bench` (`esph bench --suite`, issue 34
item 4), in one command with its JSON for the results page:

- headtohead: throughput of undamped `fix nve` dynamics on one rank, ours
  with the defaults and with hourglass control off, beside LAMMPS's MACHDYN
  smd/tlsph on the same body (2D beam, 3D cantilever).  The variants run
  alternately, rep by rep, and each keeps its best run: the machine's
  speed drifts over minutes, and alternating spreads that drift over all
  variants instead of charging it to whichever ran last.
- statics: the 3D cantilever by min_style sph/newton (the defaults, solver
  auto) against 100 dynamic steps of the same body (esph.bench3d).
- weak: peak memory per rank at constant particles per rank (esph.weak).

Each part writes its JSON (headtohead.json, statics_bench.json, weak.json)
into the folder given, as soon as it is done, and records the command,
date, commit and machine of it in that folder's sources.json, the
provenance python -m esph.results_page prints beside each table."""
from __future__ import annotations

import datetime
import json
import math
import os
import subprocess
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

from . import bench3d as bench3d_module
from . import weak as weak_module
from .paths import ROOT, lmp_binary
from .problems import PROBLEMS
from .report import command_line, machine, print_head
from .runner import run_mpi

PARTS = ("headtohead", "statics", "weak")
# the file each part writes and its kind in sources.json (results_page.SECTIONS)
FILES = {"headtohead": ("headtohead.json", "headtohead"),
         "statics": ("statics_bench.json", "statics_bench"),
         "weak": ("weak.json", "weak")}


# ---------------------------------------------------------------- head to head

@dataclass(frozen=True)
class Body:
    label: str
    ours: str                # problem (esph.problems.PROBLEMS) of our script
    machdyn: str             # problem of MACHDYN's script of the same body
    variables: dict          # geometry and load, both scripts
    ours_variables: dict     # ours only (the defaults: nothing but the scheme)
    machdyn_variables: dict  # MACHDYN only: its kernel radius
    steps: int               # per run of ours
    # per run of MACHDYN: it is about 4-8x slower per particle-step, and the
    # rate is per particle-step, so fewer steps keep its runs as long as ours
    machdyn_steps: int

    @property
    def dim(self) -> int:
        return PROBLEMS[self.ours].dim


# hfac 2.01 is MACHDYN's most accurate kernel radius on the 2D beam; 2.4
# (the support of our sinc5 kernel at h = 1.2 dx) in 3D.  W = 8 mm: 4 layers
# across at dx = 2 mm, 4120 particles like the 2D beam's 4060.
BODIES = {
    "beam": Body("2D beam", "beam", "beam_tlsph", {"dx": 0.001, "Fy": -250}, {"scheme": "icb"},
                 {"hfac": 2.01}, 2000, 250),
    "beam3d": Body("3D cantilever", "beam3d", "beam3d_tlsph", {"W": 0.008, "dx": 0.002}, {},
                   {"hfac": 2.4}, 500, 100),
}
# our variants beside MACHDYN's: the defaults, and hourglass control off
VARIANTS = {"defaults": {}, "hg0": {"hg": 0}}


@dataclass
class Runs:
    """The repeated runs of one variant on one body."""
    command: str
    steps: int
    atoms: int = 0
    loops: list = field(default_factory=list)    # s, LAMMPS's loop time of each run, in order
    rates: list = field(default_factory=list)    # particle-steps/s of each run

    @property
    def best(self) -> float:
        return max(self.rates, default=math.nan)


@dataclass
class HeadToHeadRow:
    body: str
    dim: int
    particles: int           # ours; MACHDYN's is machdyn_particles (the same lattice)
    machdyn_particles: int
    steps: int
    machdyn_steps: int
    reps: int
    rate_defaults: float     # particle-steps/s, best of reps
    rate_hg0: float
    rate_machdyn: float
    ratio_defaults: float    # rate_defaults / rate_machdyn
    ratio_hg0: float
    loops_defaults: list     # s, every run's loop time, in the order run
    loops_hg0: list
    loops_machdyn: list
    command_defaults: str
    command_hg0: str
    command_machdyn: str


def _variant_runs(body: Body) -> dict[str, tuple[Path, dict, Runs]]:
    """script, variables and an empty Runs of every variant of a body; the
    commands name `lmp` (the binary's path is the JSON's "lmp")."""
    out = {}
    for name, extra in VARIANTS.items():
        script = PROBLEMS[body.ours].script
        variables = {**body.variables, "route": "nve", "nsteps": body.steps,
                     **body.ours_variables, **extra}
        out[name] = (script, variables, Runs(command_line(script, variables, 1),
                                             body.steps))
    script = PROBLEMS[body.machdyn].script
    variables = {**body.variables, "route": "nve", "nsteps": body.machdyn_steps,
                 **body.machdyn_variables}
    out["machdyn"] = (script, variables, Runs(command_line(script, variables, 1),
                                              body.machdyn_steps))
    return out


def headtohead(bodies=tuple(BODIES.values()), reps: int = 3, progress=print,
               timeout: float = 1800) -> list[HeadToHeadRow]:
    """One row per body: best-of-reps throughput of each variant on one
    rank, the variants alternating within every rep."""
    print(f"\nHead to head on 1 rank, undamped fix nve dynamics, best of {reps} alternating "
          f"runs, particle-steps per second of LAMMPS's loop time; machine {machine()}")
    print_head(f"{'body':>14} {'particles':>9} {'defaults':>9} {'hg 0':>9} {'MACHDYN':>9} "
               f"{'def/MD':>7} {'hg0/MD':>7}  [M particle-steps/s]")
    rows = []
    for body in bodies:
        variants = _variant_runs(body)
        for rep in range(reps):
            for name, (script, variables, runs) in variants.items():
                progress(f"[esph] {body.label}, {name}, run {rep + 1} of {reps} ...")
                out = run_mpi(script, variables, 1, timeout=timeout)
                atoms, steps = int(out.variables["atoms"]), int(out.variables["steps"])
                loop = out.variables["loop_time"]
                # the loop time is that of the last run, which makes all the
                # steps: the `run 0` the scripts set up with adds none
                if steps != runs.steps:
                    raise RuntimeError(f"{runs.command}: ran {steps} steps, not {runs.steps}")
                runs.atoms = atoms
                runs.loops.append(loop)
                runs.rates.append(atoms * steps / loop)
        d, h, m = (variants[k][2] for k in ("defaults", "hg0", "machdyn"))
        row = HeadToHeadRow(body.label, body.dim, d.atoms, m.atoms, body.steps,
                            body.machdyn_steps, reps, d.best, h.best, m.best,
                            d.best / m.best, h.best / m.best, d.loops, h.loops, m.loops,
                            d.command, h.command, m.command)
        print(f"{row.body:>14} {row.particles:9d} {row.rate_defaults / 1e6:9.3f} "
              f"{row.rate_hg0 / 1e6:9.3f} {row.rate_machdyn / 1e6:9.3f} "
              f"{row.ratio_defaults:7.2f} {row.ratio_hg0:7.2f}", flush=True)
        for k, runs in (("defaults", d), ("hg0", h), ("machdyn", m)):
            print(f"{'':>14} {k}: loop times " + " ".join(f"{t:.3f}" for t in runs.loops)
                  + f" s, {runs.steps} steps  |  {runs.command}", flush=True)
        rows.append(row)
    return rows


def bodies_for(names, dxs=None, steps=None) -> list[Body]:
    """The bodies by name (of BODIES), with optional spacings (one per body)
    and step counts (ours, MACHDYN per body) replacing their own."""
    out = []
    for k, name in enumerate(names):
        body = BODIES[name]
        if dxs:
            body = replace(body, variables={**body.variables, "dx": dxs[k]})
        if steps:
            body = replace(body, steps=steps[2 * k], machdyn_steps=steps[2 * k + 1])
        out.append(body)
    return out


# ---------------------------------------------------------------- provenance

def commit() -> str:
    """The checkout's commit, -dirty when it has uncommitted changes."""
    try:
        return subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty",
                               "--abbrev=7"], capture_output=True, text=True,
                              timeout=30).stdout.strip() or "unknown"
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"


def load_average() -> str:
    try:
        return " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


def record(folder: Path, part: str, data: dict, command: str, load_before: str) -> Path:
    """Write a part's JSON into `folder` and its entry in folder/sources.json
    (created if absent; other entries kept in their order)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    name, kind = FILES[part]
    path = folder / name
    path.write_text(json.dumps(data, indent=1) + "\n")
    sources_path = folder / "sources.json"
    sources = json.loads(sources_path.read_text()) if sources_path.exists() else {}
    entry = {"kind": kind, "command": command, "date": datetime.date.today().isoformat(),
             "commit": commit(),
             "machine": f"{machine()}; load average (1, 5, 15 min) {load_before} before the "
                        f"part, {load_average()} after"}
    sources[name] = entry
    sources_path.write_text(json.dumps(sources, indent=1, ensure_ascii=False) + "\n")
    return path


# ---------------------------------------------------------------- the suite

@dataclass
class SuiteOptions:
    only: tuple = PARTS
    reps: int = 3
    bodies: tuple = tuple(BODIES)
    h2h_dx: tuple | None = None       # one spacing per body (default: each body's own)
    h2h_steps: tuple | None = None    # ours, MACHDYN per body (default: each body's own)
    statics_dx: tuple = (0.002, 0.001)
    statics_np: tuple = (2,)
    statics_side: float = 0.02
    statics_timeout: float = 3600
    weak_cases: tuple = tuple(weak_module.CASES)
    weak_ranks: tuple = weak_module.RANKS
    weak_dx: float | None = None
    weak_steps: int | None = None


def run_part(part: str, options: SuiteOptions, progress=print) -> dict:
    """One part of the suite, printed as it runs; returns its JSON data."""
    if part == "headtohead":
        rows = headtohead(bodies_for(options.bodies, options.h2h_dx, options.h2h_steps),
                          options.reps, progress)
        return {"title": f"Head to head on 1 rank: undamped fix nve dynamics, best of "
                         f"{options.reps} alternating runs per variant",
                "machine": machine(), "lmp": lmp_binary(), "rows": [asdict(r) for r in rows]}
    if part == "statics":
        print()
        rows = bench3d_module.bench3d(options.statics_dx, options.statics_np, ["auto"],
                                      options.statics_side, options.statics_timeout)
        return {"title": f"3D cantilever (square section {options.statics_side:g} m, "
                         f"L = 10 H) statics by min_style sph/newton with the defaults and "
                         f"linear solver auto, against 100 steps of undamped dynamics of the "
                         f"same body on the same ranks",
                "machine": machine(), "lmp": lmp_binary(), "rows": rows}
    if part == "weak":
        print()
        rows = weak_module.weak(options.weak_cases, options.weak_ranks, options.weak_dx,
                                options.weak_steps, progress)
        return {"title": "Weak scaling of memory: peak resident memory per rank at constant "
                         "particles per rank", "machine": machine(), "lmp": lmp_binary(),
                "rows": [asdict(r) for r in rows]}
    raise ValueError(f"unknown part {part!r}: choose from {', '.join(PARTS)}")


def suite(options: SuiteOptions, json_dir: Path | None = None, command: str = "",
          progress=print) -> dict:
    """The parts in options.only, in the order of PARTS; with a json_dir,
    each part's JSON and sources entry are written as soon as it is done,
    so a failure in a later part keeps the earlier ones.  Returns {part:
    its JSON data}."""
    results = {}
    for part in PARTS:
        if part not in options.only:
            continue
        load = load_average()
        results[part] = run_part(part, options, progress)
        if json_dir is not None:
            path = record(json_dir, part, results[part], command, load)
            progress(f"[esph] wrote {path}")
    return results

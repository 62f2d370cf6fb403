#!/usr/bin/env python3
"""Throughput of the coupled elastic gate (issue 35): the fluid's and the
solid's particle-steps per second, and the solid's cost per particle-step
in the coupled run against the same gate alone (in.gate_dry).

Wall times on this shared VM vary by tens of percent, so the solid's share
of a coupled run is counted in instructions (callgrind, the time loop
only: Verlet::run), where it can be told apart by function:

  coupled, the solid: every hook of fix sph/fluid (the gate's sub-steps
      with their elastic forces and clamps, the twins' hand-over, and the
      twins' velocities in the fluid's continuity equation, whose share is
      reported alone too), pair sph/icb as pair hybrid calls it, fix
      sph/mirror as LAMMPS calls it;
  alone: the whole loop, less fix addforce (the water's pressure as an
      atom-style variable, which the coupled run does not have).

Both per particle-step of the gate's body atoms at its sub-step.  Also the
loop's wall time of each run without callgrind, for particle-steps/s.

    python3 throughput.py [--steps 99] [--out out_throughput.json]

Needs valgrind and the in-tree lmp (scripts/setup.sh); about 3 minutes.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
GATE = ROOT / "examples" / "fsi_gate"

FLUID_HOOKS = ("initial_integrate", "post_integrate", "pre_force", "post_force",
               "final_integrate", "end_of_step")


def lmp_binary() -> str:
    sys.path.insert(0, str(ROOT / "python"))
    from esph.runner import lmp_binary as find
    return find()


def run(cmd: list[str], cwd: Path) -> str:
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}")
    return proc.stdout


def callgrind(lmp: str, args: list[str], cwd: Path, out: Path) -> dict:
    """Inclusive instructions by function and by (caller, function) edge."""
    run(["valgrind", "--tool=callgrind", "--collect-atstart=no",
         "--toggle-collect=LAMMPS_NS::Verlet::run(int)", f"--callgrind-out-file={out}",
         lmp, *args, "-log", "none", "-screen", "none"], cwd)
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--tree=caller",
                           "--threshold=100", str(out)], capture_output=True, text=True).stdout
    inclusive, edges, callers = {}, {}, []
    line_re = re.compile(r"^\s*([\d,]+) \([ \d.]+%\)\s+(\*|<)?\s*\?\?\?:(.+?) (\(\d+x\) )?\[")
    for line in text.splitlines():
        m = line_re.match(line)
        if not m:
            callers = [] if not line.strip() else callers
            continue
        cost, mark, name = int(m.group(1).replace(",", "")), m.group(2), m.group(3).strip()
        if mark == "<":
            callers.append((name, cost))
        elif mark == "*":
            inclusive[name] = cost
            for caller, c in callers:
                edges[(caller, name)] = c
            callers = []
    return {"inclusive": inclusive, "edges": edges}


def loop_time(log: str) -> float:
    return float(re.findall(r"Loop time of ([\d.eE+-]+)", log)[-1])


def results(log: str) -> dict:
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^RESULT (\w+) (\S+)", log, re.M)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=99, help="fluid steps of the coupled run")
    ap.add_argument("--out", default=str(HERE / "out_throughput.json"))
    args = ap.parse_args()
    lmp = lmp_binary()
    work = Path(os.environ.get("TMPDIR", "/tmp")) / "esph_throughput"
    work.mkdir(exist_ok=True)

    # the coupled run's step and sub-steps, from a run of it
    probe = run([lmp, "-in", "in.fsi_gate", "-var", "T", "0.0", "-var", "file", "/dev/null",
                 "-log", "none"], GATE)
    r0 = results(probe)
    dt, nsub, nbody, nwater = r0["dt"], int(r0["substeps"]), int(r0["gate"]), int(r0["water"])
    T = f"{args.steps * dt:.17g}"
    coupled_args = ["-in", "in.fsi_gate", "-var", "T", T, "-var", "file", "/dev/null"]
    dry_args = ["-in", "in.gate_dry", "-var", "nsub", str(nsub), "-var", "nfluid", str(args.steps)]

    coupled_log = run([lmp, *coupled_args, "-log", "none"], GATE)
    dry_log = run([lmp, *dry_args, "-log", "none"], HERE)
    steps = int(results(coupled_log)["steps"])
    assert int(results(dry_log)["steps"]) == steps * nsub and int(results(dry_log)["body"]) == nbody

    c = callgrind(lmp, coupled_args, GATE, work / "coupled.cg")
    d = callgrind(lmp, dry_args, HERE, work / "dry.cg")
    ns = "LAMMPS_NS::"
    solid_coupled = sum(c["inclusive"].get(f"{ns}FixSPHFluid::{h}(int)", 0) +
                        c["inclusive"].get(f"{ns}FixSPHFluid::{h}()", 0) for h in FLUID_HOOKS)
    solid_coupled += c["edges"].get((f"{ns}PairHybrid::compute(int, int)",
                                     f"{ns}PairSPHICB::compute(int, int)"), 0)
    for hook in ("pre_force", "post_force"):
        solid_coupled += c["edges"].get((f"{ns}Modify::{hook}(int)",
                                         f"{ns}FixSPHMirror::{hook}(int)"), 0)
    total_coupled = c["inclusive"][f"{ns}Verlet::run(int)"]
    # continuity body: fix sph/fluid's calls of SPHTwinContinuity (another
    # translation unit: not inlined)
    continuity = sum(c["inclusive"].get(f"{ns}SPHTwinContinuity::{m}", 0) for m in (
        "find_pairs(LAMMPS_NS::NeighList*)", "add_differences(bool)", "correct_owned(bool)",
        "correct_ghosts()", "clear()", "save_step_start()"))
    solid_dry = d["inclusive"][f"{ns}Verlet::run(int)"] - \
        d["inclusive"].get(f"{ns}FixAddForce::post_force(int)", 0)
    body_steps = nbody * nsub * steps
    out = {
        "command": "python3 studies/fsi_rheo/probes/throughput.py --steps %d" % args.steps,
        "coupled": " ".join(["lmp", *coupled_args]) + "  (in examples/fsi_gate)",
        "alone": " ".join(["lmp", *dry_args]) + "  (in studies/fsi_rheo/probes)",
        "water": nwater, "body": nbody, "steps": steps, "substeps": nsub, "dt": dt,
        "instructions_coupled": total_coupled,
        "instructions_solid_coupled": solid_coupled,
        "instructions_solid_alone": solid_dry,
        "solid_per_particle_step_coupled": solid_coupled / body_steps,
        "solid_per_particle_step_alone": solid_dry / body_steps,
        "solid_ratio": solid_coupled / solid_dry,
        "instructions_continuity": continuity,
        "continuity_per_particle_step": continuity / body_steps,
        "rest_per_water_particle_step": (total_coupled - solid_coupled) / (nwater * steps),
        "loop_coupled_s": loop_time(coupled_log),
        "loop_alone_s": loop_time(dry_log),
        "water_particle_steps_per_s": nwater * steps / loop_time(coupled_log),
        "solid_particle_steps_per_s_alone": body_steps / loop_time(dry_log),
    }
    # the solid's wall time in the coupled run, estimated from its share of
    # the instructions (an estimate: the fluid's loops need not run at the
    # solid's instructions per cycle)
    out["solid_particle_steps_per_s_coupled_est"] = \
        body_steps / (loop_time(coupled_log) * solid_coupled / total_coupled)
    Path(args.out).write_text(json.dumps(out, indent=1) + "\n")
    for key, value in out.items():
        print(f"{key:40s} {value}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

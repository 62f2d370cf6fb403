"""Every style under valgrind memcheck: short runs that touch each code path
(2d/3d, both stress measures, quadratic gradient, hourglass, CCB/CCBWAT and
its integrator, contact with damping, mirror clamp, set_sph_volumes, fix
sph/traction, sliding and displaced mirrors, minimize, restart, the
diagnostics compute, 2 MPI ranks with atoms migrating) must report no
invalid read or write and no use of uninitialised memory.  About a minute."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from esph.paths import lmp_binary
from esph.runner import mpirun_command, run_mpirun

from conftest import jiggled_block

B2 = jiggled_block(2, "p s p", "sq 0.001 origin 0.5 0.5 0.0", "0 8 0 6 -0.5 0.5", 0.0) + \
    "timestep 2e-8\n"
B3 = jiggled_block(3, "p p p", "sc 0.001 origin 0.5 0.5 0.5", "0 8 0 6 0 6", 5e-5) + \
    "timestep 2e-8\n"

INPUTS = {
    "icb_2d_contact": B2 + """
region upper block INF INF 3 INF INF INF
set region upper mol 2
pair_style sph/icb 0.0012 stress corotated plane stress hourglass 0.05 gradient quadratic
pair_coeff * * 1e9 0.3
fix rot all sph/rotation
fix c all sph/contact 0.001 thickness 0.001 damping 0.2
fix_modify c energy yes
fix nve all nve
compute diag all sph/elastic/atom stress vonmises strain rotation stretch failed
compute top all reduce max c_diag[1] c_diag[7]
thermo_style custom step pe ke f_c c_top[1] c_top[2]
run 30
""",
    "icb_3d_restart": B3 + """
pair_style sph/icb 0.0012 stress corotated hourglass 0.05
pair_coeff * * 1e9 0.3
fix rot all sph/rotation method iterative
fix nve all nve
run 20
write_restart memcheck.restart
clear
read_restart memcheck.restart
fix rot all sph/rotation method polar
fix nve all nve
run 20
""",
    "ccbwat_2d": B2 + """
pair_style sph/ccb 0.0012 plane strain thickness 0.001 viscosity 1.0 0.5 artificial_stress 0.3 4 0.001
pair_coeff * * 1e9 0.3
fix integrate all sph/ccb/nve
compute dtc all pair sph/ccb
compute diag all sph/elastic/atom stress vonmises stretch failed
compute top all reduce max c_diag[7]
thermo_style custom step pe ke c_dtc[1] c_top
run 30
""",
    "icb_mirror_minimize": B2.replace("boundary p s p", "boundary s s p") + """
pair_style sph/icb 0.0012 stress pk1 plane stress gradient quadratic
pair_coeff * * 1e9 0.0
compute diag all sph/elastic/atom stress strain
region left block INF 0.003 INF INF INF INF units box
group mirror region left
fix clamp mirror sph/mirror x 0.003
region right block 0.007 INF INF INF INF INF units box
group tip region right
fix load tip addforce 0.0 -0.5 0.0
fix_modify load energy yes
min_style cg
minimize 0.0 1e-10 30 300
""",
}
# boundary conditions: exact volumes, a sliding mirror plane with a prescribed
# displacement from a variable, a held coordinate, a face traction from a
# variable and a surface pressure, solved by Newton (its probe sees them all)
INPUTS["icb_boundary_newton"] = B2.replace("boundary p s p", "boundary s s p") + """
set_sph_volumes all lattice 0.001 thickness 0.001 density 1000
pair_style sph/icb 0.0012 plane stress
pair_coeff * * 1e9 0.3
region left block INF 0.003 INF INF INF INF units box
group mirror region left
variable u equal -1e-7
fix clamp mirror sph/mirror x 0.003 displace v_u 0.0 slip yes
region pin block 0.004 0.005 0.002 0.003 INF INF units box
group pin region pin
variable ty equal -1e5
fix load all sph/traction x 0.008 traction 0.0 v_ty
fix_modify load energy yes
fix press all sph/traction surface pressure 1e4
fix_modify press energy yes
fix hold pin setforce NULL 0.0 NULL
min_style sph/newton
minimize 0.0 1e-14 30 300
"""
# the Newton minimiser on the same clamped strip, including its probe of the fixes,
# the rank-0 gather of the Hessian (2 ranks) and the round-off stop
INPUTS["icb_mirror_newton"] = INPUTS["icb_mirror_minimize"].replace(
    "min_style cg\nminimize 0.0 1e-10 30 300", "min_style sph/newton\nminimize 0.0 1e-14 30 300")


def valgrind_cmd(nprocs: int) -> list[str]:
    supp = Path(__file__).with_name("openmpi.supp")
    vg = ["valgrind", "--error-exitcode=3", "--leak-check=no", "--track-origins=no", "-q",
          f"--suppressions={supp}"]
    if nprocs == 1:
        return vg
    return mpirun_command(nprocs) + vg


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind not installed")
@pytest.mark.parametrize("name,nprocs", [(k, 1) for k in INPUTS] + [("icb_2d_contact", 2),
                                                                  ("icb_mirror_newton", 2),
                                                                  ("icb_boundary_newton", 2)])
@pytest.mark.slow
def test_no_memory_errors(tmp_path, name, nprocs):
    script = tmp_path / f"in.{name}"
    script.write_text(INPUTS[name])
    # LAMMPS's screen output stays on: its last line is what tells Open MPI's
    # exit race apart; an attempt lost to the race is checked as well
    launch = run_mpirun(valgrind_cmd(nprocs) + [lmp_binary(), "-in", script.name, "-log", "none",
                                               "-nocite"], tmp_path, timeout=900)
    proc = launch.proc
    report = launch.lost_log + proc.stdout + proc.stderr
    assert proc.returncode == 0, report[-4000:]
    assert "Invalid read" not in report and "Invalid write" not in report
    assert "uninitialised" not in report

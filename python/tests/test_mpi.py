"""Periodic boxes on 1, 2 and 4 ranks: a jiggled block drifting through the
periodic boundary, so that every atom changes rank and reference partners
sit on other ranks and across the boundary, must end in the same state to
1e-10 relative."""
from __future__ import annotations

import pytest

from esph.runner import launcher_race, run_mpi, run_mpirun

from conftest import jiggled_block

GEOMETRY = {
    2: ("sq 0.001 origin 0.5 0.5 0.0", "0 10 0 8 -0.5 0.5", 0.0),
    3: ("sc 0.001 origin 0.5 0.5 0.5", "0 8 0 6 0 6", 5e-5),
}
PAIRS = {
    "icb": "pair_style sph/icb 0.0012 stress corotated hourglass 0.05\npair_coeff * * 1e9 0.3\n"
           "fix rot all sph/rotation\nfix nve all nve",
    "ccbwat": "pair_style sph/ccb 0.0012 {thick} viscosity 1.0 0.5 artificial_stress 0.3 4 0.001"
              "\npair_coeff * * 1e9 0.3\nfix nve all sph/ccb/nve",
}


def script(dim: int, scheme: str) -> str:
    lattice, region, dz = GEOMETRY[dim]
    pair = PAIRS[scheme].format(thick="thickness 0.001" if dim == 2 else "")
    return jiggled_block(dim, "p p p", lattice, region, dz) + f"""
# a drift of half the box in x over the run: every atom changes rank
velocity all set 500.0 NULL NULL sum yes units box
{pair}
timestep 2e-8
thermo_style custom step pe ke
run 400
variable x1 equal x[1]
variable y1 equal y[1]
print "RESULT x1 $(v_x1:%.17g)"
print "RESULT y1 $(v_y1:%.17g)"
print "RESULT pe $(pe:%.17g)"
print "RESULT ke $(ke:%.17g)"
"""


@pytest.mark.parametrize("dim,scheme", [(2, "icb"), (3, "icb"), (2, "ccbwat")])
@pytest.mark.slow
def test_periodic_runs_agree_on_1_2_4_ranks(tmp_path, dim, scheme):
    path = tmp_path / "in.periodic"
    path.write_text(script(dim, scheme))
    runs = [run_mpi(path, {}, n).variables for n in (1, 2, 4)]
    assert runs[0]["pe"] > 0.0
    for other in runs[1:]:
        for key in ("x1", "y1", "pe", "ke"):
            assert other[key] == pytest.approx(runs[0][key], rel=1e-10), key


MIGRATING_3D = """
units si
dimension 3
boundary f f f
atom_style sph/elastic
atom_modify map array
lattice sc 0.001 origin 0.5 0.5 0.5
region box block 0 30 0 6 0 6
region body block 0 6 0 6 0 6
create_box 1 box
create_atoms 1 region body
set group all mol 1
set_sph_volumes all lattice 0.001 density 1000
pair_style sph/icb $(v_hfac*0.001)
pair_coeff * * 1e9 0.3
comm_modify cutoff $(4.5*v_hfac*0.001)
neighbor 0.0005 bin
velocity all set 20.0 0 0 units box
velocity all ramp vy -1 1 x 0 0.006 sum yes units box
fix nve all nve
timestep 2e-7
run 4000
variable x1 equal x[1]
variable y1 equal y[1]
print "RESULT xc $(xcm(all,x):%.17g)"
print "RESULT x1 $(v_x1:%.17g)"
print "RESULT y1 $(v_y1:%.17g)"
print "RESULT pe $(pe:%.17g)"
print "RESULT ke $(ke:%.17g)"
"""


@pytest.mark.parametrize("hfac", [1.5, 2.0])
@pytest.mark.slow
def test_migrating_3d_body_with_long_partner_lists(tmp_path, hfac):
    """A 3d block crosses the rank boundaries (x from 0.003 to 0.019 m in a
    0.03 m box) with h = 1.5 and 2 dx: up to 250 partners per atom, whose
    records migrate with it.  The exchange buffer must be sized for them
    (it was not: SIGABRT at h = 2 dx on 2 ranks); 2 and 4 ranks must give
    what 1 rank gives."""
    path = tmp_path / "in.migrate"
    path.write_text(MIGRATING_3D)
    runs = [run_mpi(path, {"hfac": hfac}, n).variables for n in (1, 2, 4)]
    assert runs[0]["xc"] == pytest.approx(0.019, rel=1e-6)     # it did cross the box
    assert runs[0]["pe"] > 0.0                                  # and was deformed
    for other in runs[1:]:
        for key in ("x1", "y1", "pe", "ke"):
            assert other[key] == pytest.approx(runs[0][key], rel=1e-10), key


# What Open MPI 4.1's mpirun printed when it lost the end of a finished run in
# CI, after LAMMPS's last line
RACE_TAIL = """Total wall time: 0:00:00
--------------------------------------------------------------------------
mpirun has exited due to process rank 0 with PID 0 on
node vm exiting improperly. There are three reasons this could occur:
"""


def test_launcher_race_is_told_apart_from_real_failures():
    assert launcher_race(1, RACE_TAIL)
    assert not launcher_race(0, RACE_TAIL)
    # a rank that really died is named by its own PID
    assert not launcher_race(1, RACE_TAIL.replace("PID 0 ", "PID 4242 "))
    # and a LAMMPS error is never put down to the launcher
    assert not launcher_race(1, "ERROR: Illegal pair_style command (src/x.cpp:1)\n" + RACE_TAIL)
    # nor is a run that LAMMPS did not finish
    assert not launcher_race(1, RACE_TAIL.replace("Total wall time: 0:00:00\n", ""))


def _fake_mpirun(tmp_path, races: int) -> list[str]:
    """A command that prints the race `races` times, then succeeds."""
    fake = tmp_path / "fake_mpirun.sh"
    fake.write_text(f"""#!/bin/sh
n=$(cat count 2>/dev/null || echo 0); echo $((n + 1)) > count
if [ "$n" -lt {races} ]; then printf '%s' '{RACE_TAIL}'; exit 1; fi
echo "RESULT ok 1"
""")
    fake.chmod(0o755)
    return [str(fake)]


def test_a_run_lost_by_the_launcher_is_run_once_more(tmp_path):
    with pytest.warns(UserWarning, match="ompi#7833"):
        launch = run_mpirun(_fake_mpirun(tmp_path, races=1), tmp_path, timeout=30)
    assert launch.proc.returncode == 0 and "RESULT ok 1" in launch.proc.stdout
    assert "exiting improperly" in launch.lost_log      # kept for whoever checks all output
    assert (tmp_path / "count").read_text().strip() == "2"


def test_a_second_lost_run_is_a_failure(tmp_path):
    with pytest.warns(UserWarning):
        launch = run_mpirun(_fake_mpirun(tmp_path, races=2), tmp_path, timeout=30)
    assert launch.proc.returncode == 1
    assert (tmp_path / "count").read_text().strip() == "2"


@pytest.mark.parametrize("banner,flavour,oversubscribe", [
    ("mpirun (Open MPI) 4.1.4\n\nReport bugs to http://www.open-mpi.org/community/help/",
     "openmpi", True),
    ("HYDRA build details:\n    Version:                                 4.1.2\n", "mpich", False),
])
def test_mpirun_options_follow_the_mpi_library(tmp_path, monkeypatch, banner, flavour,
                                               oversubscribe):
    """Open MPI needs --oversubscribe for more ranks than cores; MPICH's Hydra
    (the pip route's MPI) rejects it: the flavour is read from the launcher."""
    import esph.runner as runner
    fake = tmp_path / "mpirun"
    fake.write_text(f"#!/bin/sh\ncat <<'END'\n{banner}\nEND\n")
    fake.chmod(0o755)
    assert runner.mpi_flavour(str(fake)) == flavour
    monkeypatch.setattr(runner, "mpi_flavour", lambda launcher="mpirun": flavour)
    cmd = runner.mpirun_command(3)
    assert cmd[0] == "mpirun" and cmd[-2:] == ["-np", "3"]
    assert ("--oversubscribe" in cmd) == oversubscribe


def test_this_machine_runs_open_mpi():
    """Debian's Open MPI, which the in-tree build and PETSc use."""
    from esph.runner import mpi_flavour
    assert mpi_flavour() == "openmpi"

"""Bad input stops with a LAMMPS error that names the problem."""
from __future__ import annotations

import pytest

import subprocess

from conftest import block, make_lammps, sph_header
from esph.paths import lmp_binary
from esph.runner import mpirun_command

BASE = sph_header("0 6 0 4", map_array=False) + """create_atoms 1 box
set group all volume 1e-9
set group all mass 1e-6
set group all mol 1
"""

ICB = "pair_style sph/icb 0.0012 stress pk1 gradient linear\npair_coeff * * 1e9 0.3\n"

NEWTON_MIN = "\nfix hold all setforce 0 0 0\nminimize 0 1e-8 100 1000\n"

CASES = [
    ("pair_style sph/icb 0.0012 colour red", "Unknown pair_style sph/icb keyword: colour"),
    ("pair_style sph/icb -1", "smoothing length h must be > 0"),
    ("pair_style sph/icb", "pair_style sph/icb"),
    ("pair_style sph/icb 0.0012 stress cauchy", "Unknown pair_style sph/icb stress cauchy"),
    ("pair_style sph/icb 0.0012 kernel gauss", "Unknown pair_style sph/icb kernel gauss"),
    ("pair_style sph/icb 0.0012 hourglass -1", "hourglass must be >= 0"),
    ("pair_style sph/icb 0.0012 gradient cubic", "Unknown pair_style sph/icb gradient cubic"),
    ("pair_style sph/icb 0.0012\npair_coeff * * 1e9 0.5", "Poisson's ratio nu must satisfy"),
    ("pair_style sph/icb 0.0012\npair_coeff * * -1e9 0.3", "Young's modulus E must be > 0"),
    ("pair_style sph/icb 0.0012\npair_coeff * * 0.0 0.3", "Young's modulus E must be > 0"),
    ("pair_style sph/icb 0.0012\npair_coeff * * stiff 0.3", "Expected floating point parameter"),
    ("fix i all sph/ccb/nve extra", "it takes no arguments"),
    ("fix m all sph/mirror x 0.0 extra", "Unknown fix sph/mirror keyword extra"),
    ("pair_style sph/icb 0.0012\npair_coeff * * 1e9", "expected I J E nu"),
    ("pair_style sph/icb 0.0012 stress corotated\npair_coeff * * 1e9 0.3\nrun 0",
     "requires fix sph/rotation"),
    ("fix r all sph/rotation method magic", "Unknown fix sph/rotation method magic"),
    ("fix r all sph/rotation tol 0", "tol must be > 0"),
    ("fix r all sph/rotation bogus 1", "Unknown fix sph/rotation keyword: bogus"),
    ("compute c all sph/elastic/atom temperature", "Unknown compute sph/elastic/atom quantity"),
    ("pair_style sph/ccb 0.0012 thickness 0", "thickness must be > 0"),
    ("pair_style sph/ccb 0.0012 viscosity 1", "pair_style sph/ccb viscosity"),
    ("pair_style sph/ccb 0.0012 viscosity -1 0", "viscosity a and b must be >= 0"),
    ("pair_style sph/ccb 0.0012 artificial_stress 0.3 4 0", "dp (initial particle spacing) must be > 0"),
    ("pair_style sph/ccb 0.0012 thickness 1e-3\npair_coeff * * 1e9 0.3\nrun 0",
     "requires fix sph/ccb/nve"),
    ("pair_style sph/ccb 0.0012\npair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\nrun 0",
     "in 2d needs the keyword 'thickness t'"),
    ("pair_style sph/ccb 0.0012 thickness 1e-3\npair_coeff * * 1e9 0.3\n"
     "fix i all sph/ccb/nve\nminimize 0 1e-6 10 10", "is rate based and cannot be minimized"),
    ("pair_style sph/ccb 0.0012 thickness 1e-3 artificial_stress 0.3 4 0.01\n"
     "pair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\nrun 0", "lies outside the kernel support"),
    ("pair_style sph/icb 0.0012 stress pk1\npair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\nrun 0",
     "requires pair style sph/ccb"),
    ("pair_style sph/ccb 0.0012 thickness 1e-3\npair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\n"
     "compute c all sph/elastic/atom strain\nrun 0", "strain needs a total-Lagrangian pair style"),
    ("fix m all sph/mirror x", "Illegal fix sph/mirror command"),
    ("fix m all sph/mirror w 0.0", "the surface must be x|y|z <position>, 'plane px py pz nx ny nz'"),
    ("fix m all sph/mirror z 0.0", "plane normal z is not allowed in a 2d"),
    ("fix m all sph/mirror x zero", "Expected floating point parameter"),
    ("pair_style sph/ccb 0.0012 thickness 1e-3\npair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\n"
     "region r block 0 1 INF INF INF INF units lattice\ngroup g region r\n"
     "fix m g sph/mirror x 0.0\nrun 0", "Fix sph/mirror requires pair_style sph/icb"),
    (ICB + "group g empty\nfix m g sph/mirror x 0.0\nrun 0", "sph/mirror: group g has no atoms"),
    (ICB + "region r block 0 1 INF INF INF INF units lattice\ngroup g region r\n"
     "fix m g sph/mirror x 0.0005\nrun 0", "lies on the plane x = 0.0005"),
    (ICB + "region r block 0 1 INF INF INF INF units lattice\ngroup g region r\n"
     "fix m g sph/mirror x 0.0\nrun 0", "at reference position (0.0005, 0.0005, 0) has no"),
    # clamps on inclined and curved surfaces (issue 32)
    ("fix m all sph/mirror sphere 0 0 0 1", "a sphere is for 3d; in 2d use 'cylinder z cx cy R'"),
    ("fix m all sph/mirror cylinder x 0 0 1", "in 2d a cylinder's axis must be z"),
    ("fix m all sph/mirror cylinder z 0 0 -1", "the cylinder's radius must be > 0"),
    ("fix m all sph/mirror cylinder z 0 0 1 along z", "'along' takes an axis normal to the"),
    ("fix m all sph/mirror cylinder z 0 0 1 along q", "'along' takes an axis normal to the"),
    ("fix m all sph/mirror cylinder z 0 0 1 along x slip yes", "'along' (images along an axis)"),
    ("set_sph_volumes all lattice 0.001 thickness 1e-3 jacobian 2.0",
     "jacobian takes an atom-style variable"),
    ("set_sph_volumes all lattice 0.001 thickness 1e-3 jacobian v_none", "jacobian: no variable"),
    ("variable J equal 2.0\nset_sph_volumes all lattice 0.001 thickness 1e-3 jacobian v_J",
     "variable J is not atom-style"),
    ("variable J atom x-0.003\nset_sph_volumes all lattice 0.001 thickness 1e-3 jacobian v_J",
     "Set_sph_volumes jacobian must be positive"),
    ("fix m all sph/mirror plane 0 0 0 0 0 0", "the plane's normal is zero"),
    ("fix m all sph/mirror plane 0 0 0 1 1 0 slip yes displace 0.001 0",
     "displace with slip yes is for planes normal to x, y or z only"),
    ("create_sph_mirrors all all x 0.0", "the mirror group must be a new group"),
    ("create_sph_mirrors all m x 0.0", "needs 'depth D'"),
    (ICB + "create_sph_mirrors all m x 0.0 depth -1", "depth must be > 0"),
    (ICB + "create_sph_mirrors all m x 0.0 colour red", "Unknown create_sph_mirrors keyword colour"),
    (ICB + "create_sph_mirrors all m cylinder z 0.003 0.002 0.0015 depth 0.001",
     "on both sides of the cylinder about z"),
    (ICB + "create_sph_mirrors all m cylinder z -0.001 0.002 0.001 depth 0.0015",
     "reaches beyond the centre"),
    (ICB + "region r block INF 0.003 INF INF INF INF units box\ngroup left region r\n"
     "create_sph_mirrors left m x 0.003 depth 0.002", "already lie behind the plane x = 0.003"),
    (ICB + "create_sph_mirrors all m plane 0 0 0 1 0.2 0 depth 0.0025\n"
     "fix s m sph/mirror plane 0 0 0 1 0.3 0\nrun 0", "sph/mirror: atom 26 of group m at reference"),
    ("fix c all sph/contact", "Illegal fix sph/contact command"),
    ("fix c all sph/contact -0.001", "contact distance dx must be > 0"),
    ("fix c all sph/contact 0.001 thickness 0", "thickness must be > 0"),
    ("fix c all sph/contact 0.001 damping -1", "damping ratio must be >= 0"),
    ("fix c all sph/contact 0.001 bogus 1", "Unknown fix sph/contact keyword: bogus"),
    ("fix c all sph/contact 0.001 thickness 0.001\nrun 0", "takes the bulk moduli of pair_style"),
    (ICB + "fix c all sph/contact 0.001\nrun 0", "in 2d needs the thickness"),
    ("change_box all boundary p s p\npair_style sph/ccb 0.0012 thickness 1e-3\n"
     "pair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\nfix d all deform 1 x erate 0.01 remap v\n"
     "run 0", "sph/ccb does not support fix deform with remap v"),
    (ICB + "fix c all sph/contact 0.001 thickness 0.001 damping 0.5\nrun 0",
     "damping needs the velocities of ghost atoms"),
    (ICB + "region r block 3 6 INF INF INF INF units lattice\nset region r mol 2\n"
     "fix c all sph/contact 0.01 thickness 0.001\nrun 0", "plus the neighbor skin exceeds the ghost"),
    ("reset_sph_reference", "Illegal reset_sph_reference command: missing argument"),
    ("reset_sph_reference all extra", "takes one group ID, got an extra argument extra"),
    ("reset_sph_reference nogroup", "Could not find reset_sph_reference group ID nogroup"),
    (ICB + "run 0\nreset_sph_reference all", "the reference partners were already built"),
    # partners are found among the current neighbours: not from a perturbed body
    (ICB + "displace_atoms all random 3e-4 3e-4 0 4711 units box\nrun 0",
     "apart since the reference configuration, more than 0.5 of the"),
    # min_style sph/newton
    ("pair_style zero 0.0012\npair_coeff * *\nmin_style sph/newton" + NEWTON_MIN,
     "requires pair_style sph/icb"),
    (ICB + "min_style sph/newton\nfix a all aveforce 0 0 0\nminimize 0 1e-8 100 1000",
     "cannot model how the fixes change the force on atom"),
    (ICB + "min_style sph/newton\ngroup odd id 1:24:2\ndelete_atoms group odd compress no"
     + NEWTON_MIN,
     "requires consecutive atom IDs 1..N"),
    (ICB + "min_style sph/newton\nfix h all setforce 0 0 0\nminimize 0 1e-8 100 1000",
     "every coordinate is held fixed"),
    (ICB + "min_style sph/newton\nmin_modify factor qr",
     "Unknown min_modify factor qr: use auto, cholmod or ldlt"),
    (ICB + "min_style sph/newton\nmin_modify factor",
     "Illegal min_modify factor command: missing argument(s)"),
    # the package's styles find their pair style also as a sub-style of
    # pair_style hybrid (python/tests/test_hybrid_types.py), and say when there is none
    ("pair_style zero 0.0012\npair_coeff * *\ncompute c all sph/elastic/atom stress\nrun 0",
     "Compute sph/elastic/atom requires pair style sph/icb or sph/ccb"),
    ("pair_style zero 0.0012\npair_coeff * *\ncompute c all sph/probe 0.003 0.002\nrun 0",
     "Compute sph/probe requires pair style sph/icb or sph/ccb"),
    ("pair_style zero 0.0012\npair_coeff * *\nfix t all sph/traction x 0.006 traction 1e5 0\n"
     "run 0", "Fix sph/traction requires pair_style sph/icb"),
    ("pair_style hybrid/overlay zero 0.0012 lj/cut 0.001\npair_coeff * * zero\n"
     "pair_coeff * * lj/cut 1e-9 1e-3\nfix c all sph/contact 0.001 thickness 0.001\nrun 0",
     "Fix sph/contact takes the bulk moduli of pair_style sph/icb or sph/ccb"),
    ("pair_style hybrid/overlay sph/ccb 0.0012 thickness 1e-3 zero 0.0012\n"
     "pair_coeff * * sph/ccb 1e9 0.3\npair_coeff * * zero\nfix i all sph/ccb/nve\nrun 0",
     "Pair style sph/ccb cannot be a sub-style of pair_style hybrid/overlay"),
    ("pair_style hybrid/overlay sph/icb 0.0012 sph/icb 0.0012\n"
     "pair_coeff * * sph/icb 1 1e9 0.3\npair_coeff * * sph/icb 2 1e9 0.3\nrun 0",
     "Pair style sph/icb appears more than once in pair_style hybrid/overlay"),
]


def assert_refused(setup, commands, message):
    """After the setup commands, the commands stop with an error that says message."""
    lmp = make_lammps()
    lmp.commands_string(setup)
    with pytest.raises(Exception) as err:
        lmp.commands_string(commands)
    assert message in str(err.value)
    lmp.close()


@pytest.mark.parametrize("commands,message", CASES)
def test_bad_input_names_the_problem(commands, message):
    assert_refused(BASE, commands, message)


def test_write_data_warns_that_ccb_state_is_not_stored(tmp_path):
    """A data file holds the reference state only: read back, a sph/ccb
    body would start unstressed, so write_data says so."""
    from lammps import lammps
    log = tmp_path / "log.lammps"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    lmp.commands_string(BASE + "pair_style sph/ccb 0.0012 thickness 1e-3\n"
                        "pair_coeff * * 1e9 0.3\nfix i all sph/ccb/nve\nrun 0\n"
                        f"write_data {tmp_path / 'ccb.data'}")
    lmp.close()
    assert "Write_data does not store the density and stress that pair style sph/ccb" in (
        log.read_text())


@pytest.mark.parametrize("pairs", ["ii", "ij"])
def test_two_materials_round_trip_through_data_and_coeff_files(tmp_path, pairs):
    """write_data ... pair ii and pair ij, and write_coeff (which lists
    every pair), read back with both materials: the cross pairs, which
    carry no material, are written as 'I J none'."""
    data, coeffs = tmp_path / "body.data", tmp_path / "coeffs.in"
    two_types = BASE.replace("create_box 1 box", "create_box 2 box") + (
        "set group all type/fraction 2 0.5 4711\n"
        "pair_style sph/icb 0.0012 stress pk1 gradient linear\n"
        "pair_coeff 1 1 1e9 0.3\npair_coeff 2 2 2e9 0.25 neohookean\n")
    lmp = make_lammps()
    lmp.commands_string(two_types + f"run 0\nwrite_data {data} pair {pairs}\n"
                        f"write_coeff {coeffs}")
    lmp.close()
    written = coeffs.read_text()
    assert "pair_coeff 1 2 none" in written
    for source in ("data", "coeff"):
        lmp = make_lammps()
        setup = ("units si\ndimension 2\nboundary s s p\natom_style sph/elastic\n"
                 "pair_style sph/icb 0.0012 stress pk1 gradient linear\n")
        if source == "data":
            lmp.commands_string(setup + f"read_data {data}")
        else:
            lmp.commands_string(two_types.replace("pair_coeff 1 1 1e9 0.3\n", "")
                                .replace("pair_coeff 2 2 2e9 0.25 neohookean\n", "")
                                + f"include {coeffs}")
        lmp.commands_string(f"write_coeff {tmp_path / 'again.in'}\nrun 0")
        again = (tmp_path / "again.in").read_text()
        assert "pair_coeff 1 1 1000000000 0.3 svk" in again, source
        assert "pair_coeff 2 2 2000000000 0.25 neohookean" in again, source
        lmp.close()


@pytest.mark.parametrize("commands,message", [
    ("pair_style sph/icb 1.0\npair_coeff * * 1e9 0.3", "requires atom_style sph/elastic"),
    ("fix c all sph/contact 1.0 thickness 0.1", "requires molecule IDs to tell bodies apart"),
])
def test_wrong_atom_style(commands, message):
    assert_refused("units si\ndimension 2\nboundary s s p\natom_style atomic\n"
                   "region box block 0 4 0 4 -0.5 0.5\ncreate_box 1 box\n"
                   "create_atoms 1 single 1 1 0\nmass 1 1.0\n" + commands,
                   "run 0", message)


@pytest.mark.parametrize("command,message", [
    ("pair_style sph/icb 1.0 plane stress", "plane and thickness are only valid for 2d"),
    ("fix c all sph/contact 1.0 thickness 0.1", "keyword thickness is only valid in 2d"),
])
def test_2d_only_keyword_in_3d(command, message):
    assert_refused("units si\ndimension 3\natom_style sph/elastic\n"
                   "region box block 0 4 0 4 0 4\ncreate_box 1 box", command, message)


@pytest.mark.slow
def test_absurd_load_inverts_a_particle_and_stops_the_run():
    """The beam under a billion newtons: the first step throws the tip
    column decimetres away, and the run stops with an error at the next
    neighbour list (reference partners more than ten kernel supports apart)
    instead of going on with NaN or binning a kilometre-wide box."""
    from esph.problems import BEAM
    from esph.runner import run_mpi
    with pytest.raises(RuntimeError) as err:
        run_mpi(BEAM, {"Fy": -1e9, "dx": 0.005, "route": "nve", "nsteps": 200}, 1)
    assert "(more than 10 kernel supports): the run blew up" in str(err.value)
    assert "so the load is too large for this resolution" in str(err.value)


def test_inverted_particle_stops_dynamics():
    lmp = make_lammps()
    block(lmp, n=(6, 5, 1), dim=2, extra_pair="stress pk1")
    lmp.command("run 0")
    x = lmp.numpy.extract_atom("x")
    x0 = lmp.numpy.extract_atom("x0")
    n = lmp.get_natoms()
    x[:n, 0] = -x0[:n, 0]          # mirror: det F = -1 everywhere
    lmp.command("fix nve all nve")
    with pytest.raises(Exception, match="is inverted"):
        lmp.command("run 1")
    lmp.close()


DATA = """# zero volume
4 atoms
1 atom types
0 0.004 xlo xhi
0 0.001 ylo yhi
-0.0005 0.0005 zlo zhi

Atoms # sph/elastic

1 1 1 1e-9 1e-6 0.0005 0.0005 0 0.0005 0.0005 0
2 1 1 0.0 1e-6 0.0015 0.0005 0 0.0015 0.0005 0
3 1 1 1e-9 1e-6 0.0025 0.0005 0 0.0025 0.0005 0
4 1 1 1e-9 1e-6 0.0035 0.0005 0 0.0035 0.0005 0
"""


def test_non_positive_volume_in_data_file(tmp_path):
    data = tmp_path / "data.zero"
    data.write_text(DATA)
    lmp = make_lammps()
    with pytest.raises(Exception, match="Invalid volume 0 for atom 2"):
        lmp.commands_string(f"units si\ndimension 2\nboundary f f p\natom_style sph/elastic\n"
                            f"read_data {data}")
    lmp.close()


LOST_PARTNER = BASE.replace("region box block 0 6 0 4", "region box block 0 16 0 4") + """
pair_style sph/icb 0.0012 stress pk1
pair_coeff * * 1e9 0.3
neighbor 0.0001 bin
run 0
displace_atoms all ramp x 0.0 0.02 x 0.0 0.016 units box
run 0
"""


def test_partner_beyond_ghost_cutoff_is_an_error(tmp_path):
    """On 2 ranks a stretch beyond the ghost cut-off loses partners: the run
    must stop and say what to set, not compute with missing partners."""
    script = tmp_path / "in.lost"
    script.write_text(LOST_PARTNER)
    proc = subprocess.run(mpirun_command(2) + [lmp_binary(), "-in", str(script),
                           "-log", "none", "-nocite"], capture_output=True, text=True, timeout=120,
                          env={**__import__("os").environ, "OMPI_ALLOW_RUN_AS_ROOT": "1",
                               "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"})
    assert proc.returncode != 0
    assert "beyond the ghost cut-off" in proc.stdout + proc.stderr
    assert "comm_modify cutoff" in proc.stdout + proc.stderr


def test_gradient_cannot_change_after_partners_are_built():
    lmp = make_lammps()
    lmp.commands_string(BASE + "pair_style sph/icb 0.0012 stress pk1 gradient linear\n"
                        "pair_coeff * * 1e9 0.3\nrun 0")
    lmp.commands_string("pair_style sph/icb 0.0012 stress pk1 gradient quadratic\n"
                        "pair_coeff * * 1e9 0.3")
    with pytest.raises(Exception, match="gradient quadratic: the reference partners were already"):
        lmp.command("run 0")
    lmp.close()


def test_quadratic_gradient_on_a_single_row_is_refused():
    # two rows of particles cannot tell d^2u/dy^2 from du/dy: the fit is singular
    lmp = make_lammps()
    lmp.commands_string(BASE.replace("0 6 0 4", "0 6 0 2"))
    lmp.commands_string("pair_style sph/icb 0.0012 stress pk1 gradient quadratic\n"
                        "pair_coeff * * 1e9 0.3\nneighbor 0.0003 nsq")
    with pytest.raises(Exception, match="too few for the quadratic kernel gradient"):
        lmp.command("run 0")
    lmp.close()

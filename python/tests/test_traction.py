"""fix sph/traction (consistent surface loads) and the prescribed-displacement
and sliding modes of fix sph/mirror.

Patch tests: a block deformed by a uniform F and loaded on its faces by the
tractions t = P(F) N of the exact uniform first Piola-Kirchhoff stress is in
exact discrete equilibrium (every particle's net force vanishes to
round-off); a block stretched between two prescribed-displacement mirror
planes reaches the exact uniform stress of St. Venant-Kirchhoff's uniaxial
answer at every particle, Poisson contraction included."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import apply_affine, lattice_2d_script, make_lammps, sph_header

DX = 1.0e-3
T = 1.0e-3
E, NU = 2.0e9, 0.3


def lame(dim, plane):
    mu = E / (2 * (1 + NU))
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    if dim == 2 and plane == "stress":
        lam = 2 * lam * mu / (lam + 2 * mu)
    return lam, mu


def pk1(F, dim, plane="stress"):
    lam, mu = lame(dim, plane)
    Fd = F[:dim, :dim]
    G = 0.5 * (Fd.T @ Fd - np.eye(dim))
    S = lam * np.trace(G) * np.eye(dim) + 2 * mu * G
    return Fd @ S


def block(lmp, n, dim, gradient="quadratic", volumes=True):
    box = f"0 {n[0]} 0 {n[1]}" + ("" if dim == 2 else f" 0 {n[2]}")
    lmp.commands_string(sph_header(box, DX, dim) + f"""
        create_atoms 1 box
        set group all mol 1
        set group all volume {DX ** dim * (T if dim == 2 else 1.0)}
        set group all mass {1000 * DX ** dim * (T if dim == 2 else 1.0)}
    """)
    if volumes:
        lmp.command(f"set_sph_volumes all lattice {DX}" + (f" thickness {T}" if dim == 2 else ""))
    lmp.commands_string(f"""
        pair_style sph/icb {1.2 * DX} stress pk1 gradient {gradient} {'plane stress' if dim == 2 else ''}
        pair_coeff * * {E} {NU}
        neighbor {0.5 * DX} bin
    """)


def lattice_2d(lmp, box):
    """A 2d si box 'xlo xhi ylo yhi' (lattice units) filled with particles
    on the cell centres of a square lattice of spacing DX."""
    lmp.commands_string(lattice_2d_script(box, DX))


def uniaxial_plane_stress(stretch):
    """F and P of a uniaxial stretch along x in plane stress, Poisson
    contraction included: P_yy = 0."""
    lam, mu = lame(2, "stress")
    E11 = (stretch ** 2 - 1) / 2
    E22 = -lam / (lam + 2 * mu) * E11
    F = np.diag([stretch, np.sqrt(1 + 2 * E22), 1.0])
    P = pk1(F, 2)
    assert abs(P[1, 1]) < 1e-6 * P[0, 0]
    return F, P


def mirrored_strip(lmp, box, axis):
    """The 2d block `box` (lattice units) whose atoms at negative `axis`
    (x or y) are the mirror atoms of a sliding plane there, its partners
    built (run 0) in the reference configuration."""
    lattice_2d(lmp, box)
    region = {"x": "INF 0.0 INF INF", "y": "INF INF INF 0.0"}[axis]
    lmp.commands_string(f"""
        region mirrored block {region} INF INF units box
        group mirrored region mirrored
        set group all mol 1
        set group all volume {DX * DX * T}
        set group all mass 1.0
        set_sph_volumes all lattice {DX} thickness {T}
        pair_style sph/icb {1.2 * DX} plane stress
        pair_coeff * * {E} {NU}
        neighbor {0.5 * DX} bin
        fix sym mirrored sph/mirror {axis} 0.0 slip yes
        run 0
    """)


def face_loads(lmp, P, n, dim):
    """One fix per face: traction P N on the face with outward normal N."""
    for a in range(dim):
        for side, coord in ((-1, 0.0), (1, n[a] * DX)):
            t = side * P[:, a]
            values = " ".join(f"{v:.17g}" for v in t)
            lmp.command(f"fix f{a}{side + 1} all sph/traction {'xyz'[a]} {coord} traction {values}")
            lmp.command(f"fix_modify f{a}{side + 1} energy yes")


def net_forces(lmp):
    n = lmp.get_natoms()
    return np.array(lmp.numpy.extract_atom("f")[:n], dtype=float)


CASES_2D = {
    "tension": np.diag([1.01, 1.0, 1.0]),
    "compression": np.diag([0.97, 0.995, 1.0]),
    "shear": np.array([[1.0, 0.004, 0], [0.004, 1.0, 0], [0, 0, 1.0]]),
    "large": np.array([[1.2, 0.05, 0], [-0.03, 0.9, 0], [0, 0, 1.0]]),
}


@pytest.mark.parametrize("gradient", ["linear", "quadratic"])
@pytest.mark.parametrize("volumes", [True, False])
@pytest.mark.parametrize("case", list(CASES_2D))
def test_uniform_stress_is_an_exact_equilibrium_2d(case, gradient, volumes):
    F = CASES_2D[case]
    n = (12, 9)
    lmp = make_lammps()
    block(lmp, n, 2, gradient, volumes)
    lmp.command("run 0")
    apply_affine(lmp, F, 2)
    P = pk1(F, 2)
    face_loads(lmp, P, n, 2)
    lmp.command("run 0")
    f = net_forces(lmp)
    scale = np.abs(P).max() * DX * T
    assert np.abs(f).max() < 1e-10 * scale
    # and without the loads the boundary particles are far from equilibrium
    for a in range(2):
        for side in (0, 2):
            lmp.command(f"unfix f{a}{side}")
    lmp.command("run 0")
    assert np.abs(net_forces(lmp)).max() > 0.1 * scale
    lmp.close()


def test_uniform_stress_is_an_exact_equilibrium_3d():
    F = np.array([[1.02, 0.01, 0.0], [0.01, 0.99, 0.003], [0.0, 0.003, 1.01]])
    n = (7, 6, 5)
    lmp = make_lammps()
    block(lmp, n, 3)
    lmp.command("run 0")
    apply_affine(lmp, F, 3)
    P = pk1(F, 3)
    face_loads(lmp, P, n, 3)
    lmp.command("run 0")
    assert np.abs(net_forces(lmp)).max() < 1e-10 * np.abs(P).max() * DX ** 2
    lmp.close()


def test_traction_next_to_a_sliding_mirror_is_an_exact_equilibrium():
    """A half model: slip mirror plane y = 0 (symmetry), tractions on both x
    faces, uniaxial stretch with Poisson contraction.  The face loads of the
    particles near the mirror include what fix sph/mirror hands over from the
    mirror atoms, so the uniform state is still an exact equilibrium."""
    nx, ny = 14, 6
    F, P = uniaxial_plane_stress(1.01)
    lmp = make_lammps()
    mirrored_strip(lmp, f"0 {nx} -3 {ny}", "y")
    apply_affine(lmp, F, 2)
    x0 = lmp.numpy.extract_atom("x0")
    n = lmp.get_natoms()
    for side, coord in ((-1, 0.0), (1, nx * DX)):
        t = side * P[:, 0]
        lmp.command(f"fix f{side + 1} all sph/traction x {coord} traction {t[0]:.17g} {t[1]:.17g}")
    lmp.command("run 0")
    f = net_forces(lmp)
    body = np.array(x0[:n, 1]) > 0
    assert np.abs(f[body]).max() < 1e-10 * np.abs(P).max() * DX * T
    # the mirror atoms keep no force of their own
    assert np.abs(f[~body]).max() == 0.0
    lmp.close()


@pytest.mark.parametrize("nx", [4, 6, 20])
def test_short_body_between_a_mirror_and_a_traction_face_is_an_exact_equilibrium(nx):
    """A block only 4 or 6 spacings long between a sliding mirror plane at
    x = 0 and a traction face at x = L: the face's consistent loads reach
    about 5 spacings deep, past the body's middle.  The uniform stress
    leaves the atoms near a mirror plane in equilibrium by itself, so the
    face takes all of its b_i (splitting them at the middle left the short
    3d bar's stress 0.2 % off)."""
    ny = 6
    F, P = uniaxial_plane_stress(1.01)
    lmp = make_lammps()
    mirrored_strip(lmp, f"-3 {nx} 0 {ny}", "x")
    apply_affine(lmp, F, 2)
    t = P[:, 0]
    lmp.command(f"fix load all sph/traction x {nx * DX} traction {t[0]:.17g} {t[1]:.17g}")
    lmp.command("run 0")
    x0 = lmp.numpy.extract_atom("x0")
    body = np.array(x0[:lmp.get_natoms(), 0]) > 0
    f = net_forces(lmp)
    assert np.abs(f[body]).max() < 1e-10 * np.abs(P).max() * DX * T
    lmp.close()


@pytest.mark.parametrize("hole", [None, "4 7 3 5", "11 14 3 5", "20 23 3 5"])
def test_another_surface_within_the_face_reach_is_warned(tmp_path, hole):
    """A hole whose walls are normal to the loaded face's normal and whose
    own loads' reach (3 supports) overlaps the face's takes part of the
    face's b_i, so the load is not the face's alone: warned (the hole
    4 spacings from the face shifted the resultant by 10 % in 3d).  A hole
    20 spacings away, or none, leaves the face's load exact and silent."""
    from lammps import lammps
    log = tmp_path / "log.lammps"
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    lattice_2d(lmp, "0 30 0 8")
    if hole:
        lmp.commands_string(f"region hole block {hole} INF INF\n"
                            "delete_atoms region hole compress yes")
    lmp.commands_string(f"""
        set group all mol 1
        set group all volume {DX * DX * T}
        set group all mass 1.0
        set_sph_volumes all lattice {DX} thickness {T}
        pair_style sph/icb {1.2 * DX} plane stress
        pair_coeff * * {E} {NU}
        neighbor {0.5 * DX} bin
        fix load all sph/traction x 0.0 traction -1e6 0
        run 0
    """)
    total = lmp.extract_fix("load", 0, 1, 0)
    lmp.close()
    warned = "another surface normal to x (a hole or a step)" in log.read_text()
    near = hole is not None and not hole.startswith("20 ")
    assert warned == near
    if not near:
        assert total == pytest.approx(-1e6 * 8 * DX * T, rel=1e-12)


def test_surface_pressure_next_to_a_mirror_loads_only_the_group():
    """A strip on a sliding mirror plane y = 0, pressure on the surfaces of
    its left third only: the mirror atoms hand their shares to their
    sources where the sources are in the group, so nothing far from the
    group is loaded (every mirror atom's share went to its source before:
    p dx t on the whole row next to the plane), and the left part's load
    is the one of the same strip without the mirror atoms' hand-over."""
    lmp = make_lammps()
    lattice_2d(lmp, "0 30 -3 10")
    lmp.commands_string(f"""
        set group all mol 1
        set_sph_volumes all lattice {DX} thickness {T}
        pair_style sph/icb {1.2 * DX} plane strain
        pair_coeff * * {E} {NU}
        region mir block INF INF INF 0.0 INF INF units box
        group mir region mir
        fix sym mir sph/mirror y 0.0 slip yes
        region left block INF {10 * DX} INF INF INF INF units box
        group left region left
        fix press left sph/traction surface pressure 1.0e5
        run 0
    """)
    x0 = np.array(lmp.numpy.extract_atom("x0")[:lmp.get_natoms()])
    f = net_forces(lmp)
    lmp.close()
    far = (x0[:, 0] > 20 * DX) & (x0[:, 1] > 0)
    # the pair forces of the reference state are round-off: 2e-8 of p dx t
    assert np.abs(f[far]).max() < 1e-6 * 1.0e5 * DX * T
    assert np.abs(f[x0[:, 0] < 10 * DX]).max() > 0.1 * 1.0e5 * DX * T


@pytest.mark.parametrize("nlayer,warned", [(5, True), (20, False)])
def test_pressure_group_mixing_two_surfaces_is_warned(tmp_path, nlayer, warned):
    """A ring pressurised inside, the group ending midway through the wall:
    with 5 particles through the wall the inner and outer surfaces' loads
    overlap and no group separates them (Lame's cylinder came out 8 ... 130 %
    off, depending on where the group ended, without a word); with 20 the
    cut carries nothing and the fix stays silent."""
    from test_volumes import ring_body
    r_in = 0.02
    lmp, _ = ring_body(nlayer, r_in, centre=(0.0, 0.0))
    log = tmp_path / "log.lammps"
    lmp.command(f"log {log}")
    lmp.commands_string(f"""
        set_sph_volumes all polar {DX} 0.0 0.0 thickness {T} density 1000.0
        pair_style sph/icb {1.2 * DX} plane strain
        pair_coeff * * {E} {NU}
        neighbor {0.5 * DX} bin
        region bore cylinder z 0.0 0.0 {r_in + 0.5 * nlayer * DX} INF INF units box
        group bore region bore
        fix inflate bore sph/traction surface pressure 1.0e5
        run 0
    """)
    lmp.close()
    assert ("the group's loads mix those of two surfaces" in log.read_text()) == warned


@pytest.mark.parametrize("volumes", [False, True])
def test_face_load_resultant_is_traction_times_area(volumes):
    """The consistent forces of a face sum to t times the face area, with
    plain and with corrected volumes, when the faces are far enough apart
    (14 spacings here) that their loads do not overlap."""
    n = (16, 9)
    lmp = make_lammps()
    block(lmp, n, 2, volumes=volumes)
    lmp.command("fix load all sph/traction x 0.016 traction 1.5e6 -2.0e6")
    lmp.command("run 0")
    area = n[1] * DX * T
    total = [lmp.extract_fix("load", 0, 1, k) for k in range(3)]
    np.testing.assert_allclose(total, [1.5e6 * area, -2.0e6 * area, 0.0], rtol=1e-12, atol=1e-9)
    lmp.close()


def test_pressure_on_a_whole_surface_is_the_hydrostatic_equilibrium():
    """p on every surface particle (no face given) balances sigma = -p I."""
    J = 0.99
    F = np.diag([J, J, 1.0])
    n = (10, 8)
    lmp = make_lammps()
    block(lmp, n, 2)
    lmp.command("run 0")
    apply_affine(lmp, F, 2)
    P = pk1(F, 2)
    assert abs(P[0, 1]) < 1e-6 and np.isclose(P[0, 0], P[1, 1])
    lmp.command(f"fix p all sph/traction surface pressure {-P[0, 0]:.17g}")
    lmp.command("run 0")
    assert np.abs(net_forces(lmp)).max() < 1e-10 * abs(P[0, 0]) * DX * T
    lmp.close()


def clamped_strip(nu: float, mass: float, load: str) -> str:
    """Commands for the 2d strip of the lattice made before them: mirror
    clamp columns at x < 0 (fix sph/mirror x 0), exact volumes, sph/icb
    (pk1, quadratic gradient, plane stress), and the traction `load`
    (fix sph/traction's arguments) in the energy."""
    return f"""set group all mol 1
set group all volume {DX * DX * T}
set group all mass {mass}
region clampzone block INF 0.0 INF INF INF INF units box
group clamp region clampzone
group body subtract all clamp
set_sph_volumes all lattice {DX} thickness {T}
pair_style sph/icb {1.2 * DX} stress pk1 gradient quadratic plane stress
pair_coeff * * {E} {nu}
neighbor {0.5 * DX} bin
fix hold clamp sph/mirror x 0.0
fix load body sph/traction {load}
fix_modify load energy yes
"""


def truss_tip(solver, Fx, nu=0.0, nx=20, ny=6, ranks_note=""):
    """A bar clamped by a mirror at x = 0, pulled by a traction on x = L."""
    lmp = make_lammps()
    L, H = nx * DX, ny * DX
    lattice_2d(lmp, f"-3 {nx} 0 {ny}")
    lmp.commands_string(clamped_strip(nu, 1000 * DX * DX * T,
                                      f"x {L} traction {Fx / (H * T)} 0.0") + f"""
        compute ref all property/atom x0x
        variable ux atom x-c_ref
        region tipzone block {L - DX} INF INF INF INF INF units box
        group tip region tipzone
    """)
    lmp.commands_string("""
        compute tipx tip reduce ave v_ux
        thermo_style custom step pe fnorm c_tipx
    """)
    if solver == "newton":
        lmp.command("min_style sph/newton")
    else:
        lmp.commands_string(f"min_style cg\nmin_modify dmax {0.1 * DX} line forcezero")
    lmp.command(f"minimize 0 {1e-9 * abs(Fx)} 20000 20000")
    tip = lmp.extract_compute("tipx", 0, 0)
    lmp.close()
    return tip, L, H


@pytest.mark.parametrize("Fx", [300.0, -60.0])
def test_truss_with_traction_is_exact(Fx):
    """nu = 0: uniaxial SVK, P = E lam (lam^2 - 1)/2 = F/A, exact at every
    point; the tip column's mean displacement is (lam - 1)(L - dx/2)."""
    tip, L, H = truss_tip("newton", Fx)
    from scipy.optimize import brentq
    P = Fx / (H * T)
    lam = brentq(lambda l: E * l * (l * l - 1) / 2 - P, 0.6, 1.5)
    assert tip == pytest.approx((lam - 1) * (L - DX / 2), rel=1e-9)


def test_traction_energy_is_seen_by_cg_and_newton_alike():
    a, _, _ = truss_tip("newton", 300.0, nu=0.3)
    b, _, _ = truss_tip("cg", 300.0, nu=0.3)
    assert a == pytest.approx(b, rel=1e-6)


def stretch_between_mirrors(delta, nu, slip, n=(16, 7), solver="newton"):
    """Block on x in (0, L), y in (0, H) between the mirror planes x = 0 and
    x = L, the latter displaced by delta.  With slip the planes are
    symmetry planes and the body contracts freely; one atom's y is held to
    take out the rigid slide (the exact answer is affine about it)."""
    nx, ny = n
    L = nx * DX
    lmp = make_lammps()
    lattice_2d(lmp, f"-3 {nx + 3} 0 {ny}")
    lmp.commands_string(f"""
        region left block -3 0 INF INF INF INF
        region right block {nx} {nx + 3} INF INF INF INF
        region pin block 5 6 3 4 INF INF
        group left region left
        group right region right
        group pin region pin
        group mirrors union left right
        group body subtract all mirrors
        set group all mol 1
        set group all volume {DX * DX * T}
        set group all mass {1000 * DX * DX * T}
        set_sph_volumes all lattice {DX} thickness {T}
        pair_style sph/icb {1.2 * DX} stress pk1 gradient quadratic plane stress
        pair_coeff * * {E} {nu}
        neighbor {0.5 * DX} bin
        fix l left sph/mirror x 0.0 slip {'yes' if slip else 'no'}
        fix r right sph/mirror x {L} displace {delta} 0.0 slip {'yes' if slip else 'no'}
        fix p pin setforce NULL 0.0 NULL
        compute s body sph/elastic/atom stress
    """)
    if solver == "newton":
        lmp.command("min_style sph/newton")
    else:
        lmp.commands_string(f"min_style cg\nmin_modify dmax {0.1 * DX} line forcezero")
    lmp.command("minimize 0 1e-6 2000 20000")
    return lmp, L


def uniaxial_cauchy(stretch, nu):
    """SVK (plane stress lambda*) under uniaxial stress: sigma_xx.  The
    body thins as it narrows (E_zz = E_yy, from S_zz = S_yy = 0 of the 3d
    law), and the Cauchy stress divides by the current volume."""
    mu = E / (2 * (1 + nu))
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    lam = 2 * lam * mu / (lam + 2 * mu)
    E11 = (stretch ** 2 - 1) / 2
    E22 = -lam / (lam + 2 * mu) * E11
    S11 = lam * (E11 + E22) + 2 * mu * E11
    lat = np.sqrt(1 + 2 * E22)
    return stretch * stretch * S11 / (stretch * lat * lat)


@pytest.mark.parametrize("nu, slip, strain", [(0.0, False, 0.02), (0.3, True, 0.02),
                                              (0.0, True, 0.02), (0.3, True, 0.10)])
def test_prescribed_displacement_gives_the_exact_uniform_stress(nu, slip, strain):
    """Also at 10 % from the first run, where the plane moves its mirrors by
    2 u0 = 3.2 spacings, far beyond the neighbor skin: the reference
    partners are found before the plane is displaced (they were not, and
    the body did not deform at all)."""
    delta = strain * 16 * DX
    lmp, L = stretch_between_mirrors(delta, nu, slip)
    n = lmp.get_natoms()
    sigma = np.array(lmp.numpy.extract_compute("s", 1, 2)[:n])
    x0 = np.array(lmp.numpy.extract_atom("x0")[:n])
    inside = (x0[:, 0] > 0) & (x0[:, 0] < L)
    assert np.count_nonzero(inside) == 16 * 7
    expect = uniaxial_cauchy(1.0 + strain, nu)
    np.testing.assert_allclose(sigma[inside, 0], expect, rtol=1e-8)
    np.testing.assert_allclose(sigma[inside, 1], 0.0, atol=1e-8 * expect)
    np.testing.assert_allclose(sigma[inside, 3], 0.0, atol=1e-8 * expect)
    lmp.close()


def test_displacement_from_a_variable_ramps():
    """displace v_name follows an equal-style variable through a run."""
    lmp = make_lammps()
    nx, ny = 10, 5
    L = nx * DX
    lattice_2d(lmp, f"-3 {nx + 3} 0 {ny}")
    lmp.commands_string(f"""
        region right block {nx} INF INF INF INF INF
        group right region right
        set group all mol 1
        set group all volume {DX * DX * T}
        set group all mass {1000 * DX * DX * T}
        pair_style sph/icb {1.2 * DX} stress pk1 gradient quadratic plane stress
        pair_coeff * * {E} 0.0
        fix nve all nve
        variable u equal 1e-6*step
        fix r right sph/mirror x {L} displace v_u 0.0
        compute ref all property/atom x0x
        variable ux atom x-c_ref
        compute um right reduce ave v_ux
        timestep 1e-9
        run 10
    """)
    # mirror atoms at reference x_m sit at x_m + 2 u0 - u_source
    n = lmp.get_natoms()
    x = np.array(lmp.numpy.extract_atom("x")[:n])
    x0 = np.array(lmp.numpy.extract_atom("x0")[:n])
    pos = {(round(a / DX - 0.5), round(b / DX - 0.5)): k for k, (a, b) in enumerate(x0[:, :2])}
    u0 = 1e-6 * 10
    checked = 0
    for (i, j), k in pos.items():
        if i >= nx:
            s = pos[(2 * nx - 1 - i, j)]
            us = x[s, 0] - x0[s, 0]
            assert x[k, 0] - x0[k, 0] == pytest.approx(2 * u0 - us, abs=1e-15)
            checked += 1
    assert checked == 3 * ny
    lmp.close()


BAD = [
    ("fix t all sph/traction q 0.01 traction 1 0", "must be x, y"),
    ("fix t all sph/traction surface traction 1 0", "needs a face"),
    ("fix t all sph/traction x 0.01 traction 1", "takes 2 values"),
    ("fix t all sph/traction x 0.01 push 1 0", "use traction or pressure"),
    ("fix t all sph/traction x 0.01 traction 1 0 5", "no z component"),
    ("fix t all sph/traction x 0.005 traction 1 0\nrun 0", "both sides"),
    ("fix t all sph/traction x 0.5 traction 1 0\nrun 0", "is 0.4905 from the nearest"),
    ("fix t all sph/traction x 0.01 traction v_nope 0\nrun 0", "does not exist"),
    ("fix m all sph/mirror x 0.0 displace 1", "displace takes 2 values"),
    ("fix m all sph/mirror x 0.0 slip yes displace 0 1e-3", "only the normal"),
    ("fix m all sph/mirror x 0.0 wobble 1", "Unknown fix sph/mirror keyword"),
    # the consistent loads reach deeper than a group of the face layers
    ("region r block 0.008 INF INF INF INF INF units box\ngroup face region r\n"
     "fix t face sph/traction x 0.01 traction 1 0\nrun 0", "loads atoms deeper than group face"),
    # a face or mirror plane across which the body is periodic
    ("change_box all boundary p s p\nfix t all sph/traction x 0.01 traction 1 0\nrun 0",
     "normal to x, a periodic dimension"),
    ("region r block INF 0.002 INF INF INF INF units box\ngroup g region r\n"
     "change_box all boundary s p p\nfix m g sph/mirror y 0.0\nrun 0",
     "is not invariant along y, a periodic dimension"),
]


@pytest.mark.parametrize("command, words", BAD)
def test_bad_input_is_a_clear_error(command, words):
    lmp = make_lammps()
    block(lmp, (10, 5), 2)
    with pytest.raises(Exception, match=words):
        for line in command.split("\n"):
            lmp.command(line)
    lmp.close()


@pytest.mark.slow
def test_3d_face_traction_statics_agree_on_1_2_4_ranks():
    """examples/beam3d (exact volumes, mirror clamp, face traction, Newton)
    on a small cantilever: the same tip on 1, 2 and 4 ranks."""
    from esph.problems import BEAM3D
    from esph.runner import run_mpi
    variables = {"L": 0.04, "H": 0.01, "W": 0.01, "dx": 0.0025, "Fy": -2000.0, "nu": 0.3}
    tips = [run_mpi(BEAM3D, variables, n).variables for n in (1, 2, 4)]
    assert tips[0]["load_x"] == pytest.approx(0.04)
    assert tips[0]["tip_dv"] < -1e-5
    for other in tips[1:]:
        for key in ("tip_dh", "tip_dv"):
            assert other[key] == pytest.approx(tips[0][key], rel=1e-9)
        assert abs(other["tip_dz"]) < 1e-12


@pytest.mark.slow
def test_face_loads_with_mirror_shares_across_ranks_agree_on_1_and_2_ranks(tmp_path):
    """Each share of a face's load goes to its atom on the rank that holds
    it (a ghost's share to the owner by reverse communication), with no
    list of the loaded atoms on every rank.  A strip clamped by a mirror at
    x = 0 and sheared on its top face: the mirror atoms' shares go to their
    sources, which on 2 ranks (split at x = 1.5 spacings) are partly the
    other rank's.  Every atom's load and the total are those of 1 rank."""
    from esph.runner import run_mpi
    nx, ny = 6, 10
    head = sph_header(f"-3 {nx} 0 {ny}", DX, 2, extra="processors * 1 1\n")
    script = tmp_path / "in.shared"
    script.write_text(head + "create_atoms 1 box\n"
                      + clamped_strip(NU, 1.0, f"y {ny * DX} traction 1.5e6 -2.0e6") + """run 0
write_dump all custom loads.${nprocs} x y fx fy modify format float %.17g
print "RESULT fx $(f_load[1]:%.17g)"
print "RESULT fy $(f_load[2]:%.17g)"
""")
    runs = {n: run_mpi(script, {"nprocs": n}, n).variables for n in (1, 2)}
    loads = {}
    for n in (1, 2):    # by position: the atom IDs follow the ranks
        rows = np.loadtxt(tmp_path / f"loads.{n}", skiprows=9)
        loads[n] = rows[np.lexsort((rows[:, 1], rows[:, 0]))]
    area = nx * DX * T
    assert runs[1]["fx"] == pytest.approx(1.5e6 * area, rel=0.1)    # the clamp takes a share
    for key in ("fx", "fy"):
        assert runs[2][key] == pytest.approx(runs[1][key], rel=1e-13)
    np.testing.assert_array_equal(loads[2][:, :2], loads[1][:, :2])
    # 5e-11 of the largest load apart, as with the coefficients gathered on
    # every rank before (measured; both bit-identical to the gathered ones)
    scale = np.abs(loads[1][:, 2:]).max()
    np.testing.assert_allclose(loads[2][:, 2:], loads[1][:, 2:], rtol=0, atol=1e-9 * scale)

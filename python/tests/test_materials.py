"""Material laws of pair_style sph/icb: compressible neo-Hookean beside
St. Venant-Kirchhoff, selected per type in pair_coeff.

The neo-Hookean reference here is written from the energy stated in
doc/pair_sph_icb.rst, W = mu/2 (tr C - 3) - mu ln J + lambda/2 (ln J)^2, in
its Cauchy form sigma = mu/J (B - I) + lambda ln J / J I (the code works with
S and C^-1), and that form is itself checked against a finite-difference
gradient of W.  Plane stress solves sigma_zz = 0 for the out-of-plane stretch
with scipy; the code uses its own Newton iteration."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.optimize import brentq

from conftest import apply_affine, block, make_lammps, per_atom, sph_header
from esph.problems import BEAM, BEAM3D, TRUSS
from esph.runner import run_script
from test_patch import VOIGT, rotation_matrix, svk_cauchy
from test_traction import lattice_2d

E, NU = 1.0e9, 0.3


def lame(youngs, nu):
    return youngs * nu / ((1 + nu) * (1 - 2 * nu)), youngs / (2 * (1 + nu))


def nh_energy(F, youngs=E, nu=NU):
    lam, mu = lame(youngs, nu)
    J = np.linalg.det(F)
    return 0.5 * mu * (np.trace(F.T @ F) - 3) - mu * math.log(J) + 0.5 * lam * math.log(J) ** 2


def nh_stretch_zz(F, youngs=E, nu=NU):
    """Out-of-plane stretch s of plane stress: sigma_zz = 0, i.e.
    mu (s^2 - 1) + lambda ln(J_2d s) = 0."""
    lam, mu = lame(youngs, nu)
    J2 = np.linalg.det(F[:2, :2])
    return brentq(lambda s: mu * (s * s - 1) + lam * math.log(J2 * s), 1e-3, 1e3, xtol=1e-15)


def nh_cauchy(F, youngs=E, nu=NU, plane=None):
    """Cauchy stress and Green strain of the compressible neo-Hookean law."""
    lam, mu = lame(youngs, nu)
    F = np.array(F, dtype=float)
    if plane == "stress":
        F[2, 2] = nh_stretch_zz(F, youngs, nu)
    J = np.linalg.det(F)
    sigma = mu / J * (F @ F.T - np.eye(3)) + lam * math.log(J) / J * np.eye(3)
    return sigma, 0.5 * (F.T @ F - np.eye(3))


def test_reference_cauchy_is_the_gradient_of_the_stated_energy():
    F = np.array([[1.3, 0.1, 0.05], [-0.04, 0.8, 0.02], [0.03, 0.01, 1.1]])
    P = np.zeros((3, 3))
    step = 1e-6
    for a in range(3):
        for b in range(3):
            d = np.zeros((3, 3))
            d[a, b] = step
            P[a, b] = (nh_energy(F + d) - nh_energy(F - d)) / (2 * step)
    sigma, _ = nh_cauchy(F)
    np.testing.assert_allclose(P @ F.T / np.linalg.det(F), sigma, atol=1e-6 * E)


def law_block(n, dim, plane=None, law="neohookean", types=1):
    lmp = make_lammps()
    extra = "stress pk1 gradient quadratic" + (f" plane {plane}" if dim == 2 else "")
    block(lmp, n=n, dim=dim, E=E, nu=NU, extra_pair=extra, law=law)
    lmp.command("atom_modify sort 0 0.0")
    return lmp


def deformed(lmp, F, dim):
    lmp.command("run 0")           # reference partners at x = x0
    apply_affine(lmp, F, dim)
    lmp.command("run 0")
    return per_atom(lmp, "out", cols=True)


STRETCHES = {
    2: np.array([[1.3, 0.1, 0.0], [0.05, 0.8, 0.0], [0.0, 0.0, 1.0]]),
    3: np.array([[1.2, 0.1, 0.0], [0.0, 0.85, 0.05], [0.02, 0.0, 1.1]]),
}


@pytest.mark.parametrize("dim,plane", [(2, "strain"), (2, "stress"), (3, None)])
def test_neohookean_uniform_stretch_gives_its_exact_stress(dim, plane):
    """A large uniform stretch (30 % in x, -20 % in y, shear): every particle,
    surfaces and corners included, carries the exact neo-Hookean stress."""
    F = STRETCHES[dim]
    lmp = law_block((7, 6, 1) if dim == 2 else (5, 5, 5), dim, plane)
    out = deformed(lmp, F, dim)
    sigma, green = nh_cauchy(F, plane=plane)
    want = np.array([sigma[a, b] for a, b in VOIGT])
    want_strain = np.array([green[a, b] for a, b in VOIGT])
    assert np.abs(out[:, 0:6] - want).max() < 1e-9 * np.abs(want).max()
    assert np.abs(out[:, 6:12] - want_strain).max() < 1e-12
    if plane == "stress":
        assert want_strain[2] < -0.01          # the body thinned: E_zz is the real one
    lmp.close()


def nh_uniaxial_strain_energy(eps, youngs=E, nu=NU):
    """W of F = diag(1 + eps, 1, 1), free of cancellation at small eps:
    tr C - 3 - 2 ln J = eps^2 + 2 (eps - ln(1 + eps)), the bracket summed
    as its series 2 sum_k>=2 (-1)^k eps^k / k."""
    lam, mu = lame(youngs, nu)
    series = sum((-1) ** k * eps ** k / k for k in range(2, 30))
    return 0.5 * mu * (eps * eps + 2.0 * series) + 0.5 * lam * math.log1p(eps) ** 2


def uniaxial_energy_error(law, eps):
    """Relative error of a 3d block's energy under F = diag(1 + eps, 1, 1)
    against the exact W of the law times the block's volume."""
    lmp = law_block((5, 5, 5), 3, law=law)
    lmp.commands_string("thermo_style custom step pe\nrun 0")
    apply_affine(lmp, np.diag([1.0 + eps, 1.0, 1.0]), 3)
    lmp.command("run 0")
    volume = float(np.sum(lmp.numpy.extract_atom("vfrac")[:lmp.get_natoms()]))
    if law == "svk":
        lam, mu = lame(E, NU)
        green = eps + 0.5 * eps * eps
        exact = (0.5 * lam + mu) * green * green
    else:
        exact = nh_uniaxial_strain_energy(eps)
    error = lmp.get_thermo("pe") / (exact * volume) - 1.0
    lmp.close()
    return error


@pytest.mark.parametrize("eps", [1e-7, 1e-4])
def test_neohookean_energy_keeps_its_precision_at_small_strain(eps):
    """The energy is O(strain^2) while tr C - 3 and 2 ln J are O(strain):
    formed naively their difference lost 1e-16/strain^2 (2e-3 at 1e-7),
    which stalled sph/newton's line search.  Both laws now share the floor
    of F itself (about 1e-14 from the quadratic gradient's solve: 4e-7 of
    the energy at a strain of 1e-7)."""
    nh, svk = uniaxial_energy_error("neohookean", eps), uniaxial_energy_error("svk", eps)
    assert abs(nh) < 1e-5
    assert abs(nh - svk) < 1e-8


@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_neohookean_statics_at_a_strain_of_1e_7_is_hookes_law(plane):
    """A strip stretched by 1e-7 between two sliding platens (fix sph/mirror
    displace) by min_style sph/newton: sigma_xx = E eps in plane stress,
    E eps/(1 - nu^2) in plane strain, at every particle (it stopped 1-8 %
    off at the energy's round-off floor before)."""
    eps, length = 1e-7, 0.02
    lmp = make_lammps()
    lattice_2d(lmp, "-3 23 0 8")         # spacing 1 mm
    lmp.commands_string(f"""
        set group all mol 1
        region left block INF 0.0 INF INF INF INF units box
        region right block {length} INF INF INF INF INF units box
        region pin block 0.0 0.001 0.0 0.001 INF INF units box
        group left region left
        group right region right
        group pin region pin
        group platens union left right
        group body subtract all platens
        set_sph_volumes all lattice 0.001 thickness 0.001 density 1000.0
        pair_style sph/icb 0.0012 plane {plane}
        pair_coeff * * {E} {NU} neohookean
        neighbor 0.0005 bin
        fix base left sph/mirror x 0.0 slip yes
        fix platen right sph/mirror x {length} displace {eps * length} 0.0 slip yes
        fix pin pin setforce NULL 0.0 NULL
        compute s body sph/elastic/atom stress
        min_style sph/newton
        minimize 0.0 {1e-9 * E * eps * 0.008 * 0.001} 50 100
    """)
    sxx = per_atom(lmp, "s", cols=True)[:, 0]
    want = E * eps / (1.0 if plane == "stress" else 1.0 - NU * NU)
    x0 = np.array(lmp.numpy.extract_atom("x0")[:lmp.get_natoms()])
    inside = (x0[:, 0] > 0.0) & (x0[:, 0] < length)
    assert np.abs(sxx[inside] / want - 1.0).max() < 1e-5
    lmp.close()


@pytest.mark.parametrize("dim", [2, 3])
def test_neohookean_rigid_rotation_is_stress_free(dim):
    lmp = law_block((7, 6, 1) if dim == 2 else (5, 5, 5), dim, "stress" if dim == 2 else None)
    out = deformed(lmp, rotation_matrix(dim, math.radians(60.0)), dim)
    assert np.abs(out[:, 0:6]).max() < 1e-12 * E
    f = np.array(lmp.numpy.extract_atom("f")[:lmp.get_natoms()])
    assert np.abs(f).max() < 1e-9
    lmp.close()


def test_two_types_carry_their_own_laws():
    """Type 1 St. Venant-Kirchhoff, type 2 neo-Hookean in one body: under a
    uniform stretch each particle has the stress of its own law."""
    F = STRETCHES[2]
    lmp = make_lammps()
    block(lmp, n=(8, 6, 1), dim=2, E=E, nu=NU, types=2,
          extra_pair="stress pk1 gradient quadratic plane stress")
    lmp.commands_string(f"""
        region upper block INF INF 3 INF INF INF
        set region upper type 2
        pair_coeff 1 1 {E} {NU} svk
        pair_coeff 2 2 {E} {NU} neohookean
    """)
    out = deformed(lmp, F, 2)
    types = np.array(lmp.numpy.extract_atom("type")[:lmp.get_natoms()])
    for t, (sigma, _) in ((1, svk_cauchy(F, E, NU, 2, "stress")), (2, nh_cauchy(F, plane="stress"))):
        want = np.array([sigma[a, b] for a, b in VOIGT])
        assert np.abs(out[types == t, 0:6] - want).max() < 1e-9 * np.abs(want).max()
    # the laws differ by far more than the tolerance at this stretch
    assert abs(svk_cauchy(F, E, NU, 2, "stress")[0][0, 0] - nh_cauchy(F, plane="stress")[0][0, 0]) \
        > 0.01 * E
    lmp.close()


@pytest.mark.parametrize("dim,plane", [(2, "strain"), (2, "stress"), (3, None)])
def test_neohookean_forces_are_minus_the_energy_gradient(dim, plane):
    """Random positions (10 % of the spacing): every force component checked
    equals the central difference of the total energy."""
    n = (6, 5, 1) if dim == 2 else (4, 4, 4)
    lmp = law_block(n, dim, plane)
    lmp.commands_string("thermo_style custom step pe\nrun 0")
    natoms = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    rng = np.random.default_rng(7)
    x[:natoms, :dim] += rng.uniform(-1e-4, 1e-4, size=(natoms, dim))
    lmp.command("run 0")
    f = np.array(lmp.numpy.extract_atom("f")[:natoms])
    step = 1e-9
    checked = 0
    for i in rng.choice(natoms, size=6, replace=False):
        for a in range(dim):
            energies = []
            for sign in (1, -1):
                x = lmp.numpy.extract_atom("x")
                x[i, a] += sign * step
                lmp.command("run 0")
                energies.append(lmp.get_thermo("pe"))
                x = lmp.numpy.extract_atom("x")
                x[i, a] -= sign * step
            assert f[i, a] == pytest.approx(-(energies[0] - energies[1]) / (2 * step),
                                            abs=1e-6 * np.abs(f).max())
            checked += 1
    assert checked == 6 * dim and np.abs(f).max() > 1.0
    lmp.close()


def fnorm_column(log: str) -> list[float]:
    """The Fnorm column of the last thermo block of a LAMMPS log."""
    block = log.split("Loop time of")[-2]
    lines = block[block.rindex("   Step"):].splitlines()
    column = lines[0].split().index("Fnorm")
    return [float(line.split()[column]) for line in lines[1:]
            if line.split() and line.split()[0].isdigit()]


@pytest.mark.parametrize("script,variables", [
    (BEAM, {"nu": 0.3, "plane": "stress", "dx": 0.004, "Fy": -500.0}),
    (BEAM, {"nu": 0.3, "plane": "strain", "dx": 0.004, "Fy": -500.0}),
    (BEAM3D, {"nu": 0.3, "L": 0.04, "H": 0.01, "W": 0.01, "dx": 0.0025, "Fy": -2000.0,
              "linear": "direct"}),
], ids=["beam-plane-stress", "beam-plane-strain", "beam3d"])
def test_newton_converges_quadratically_with_the_neohookean_tangent(tmp_path, script, variables):
    """The tangent is exact (condensed in plane stress): Newton squares the
    residual in its last steps, down to round-off.  Without hourglass
    control and solved by factorisation (also in 3d, where the default
    is PETSc's inexact Newton), so that each step uses the whole tangent."""
    log = tmp_path / "newton.log"
    run_script(script, {**variables, "law": "neohookean", "ftol": 1e-10, "thermo_every": 1,
                        "hg": 0.0},
               read=["tip_dv"], log=log)
    norms = [g / abs(variables["Fy"]) for g in fnorm_column(log.read_text())]
    assert norms[-1] < 1e-10
    assert len(norms) - 1 <= 20
    # in the quadratic regime each step squares the residual, down to the
    # round-off floor near 1e-11 of the load (St. Venant-Kirchhoff's own
    # constant on these beams is up to 100; a linearly converging Newton
    # would fail at the last step, 1e-5 -> 1e-11)
    steps = [(g0, g1) for g0, g1 in zip(norms, norms[1:]) if 1e-9 < g0 < 0.1]
    assert len(steps) >= 2, norms
    for g0, g1 in steps:
        assert g1 <= 100.0 * g0 * g0 + 1e-11, norms


def test_truss_at_minus_7000_newtons_is_the_exact_uniaxial_answer():
    """The paper's truss (nu = 0, so its state is uniform) at -7000 N, 7 % of
    E as the nominal stress: the neo-Hookean tip matches the exact
    uniaxial answer P = mu (l - 1/l) at the tip's material point."""
    dx = 0.005
    out = run_script(TRUSS, {"Fx": -7000.0, "dx": dx, "law": "neohookean", "ftol": 1e-10},
                     read=["tip_dh", "tip_dv", "load_x"])
    mu = 2.0e9 / 2
    nominal = -7000.0 / (0.05 * 0.001)
    stretch = (nominal / mu + math.sqrt((nominal / mu) ** 2 + 4)) / 2
    assert stretch < 0.94
    x_tip = 0.2 - dx / 2
    assert out.variables["tip_dh"] == pytest.approx((stretch - 1) * x_tip, rel=1e-8)
    assert abs(out.variables["tip_dv"]) < 1e-12
    # St. Venant-Kirchhoff at the same load: P = E (l^3 - l)/2 is visibly different
    svk = brentq(lambda s: 2.0e9 * (s ** 3 - s) / 2 - nominal, 0.6, 1.0)
    assert abs(svk - stretch) > 0.005


def periodic_compression(ratio, law, n=8):
    """A periodic n x n block squeezed to (1 - ratio) of its length in x by
    'change_box ... remap', jiggled by 5 % of the spacing, then minimised:
    confined compression in plane stress, whose exact state is uniform,
    F = diag(1 - ratio, 1, s), with no surface or corner to spoil it.  One
    atom is held against the rigid translations.  Hourglass control keeps
    the particle-scale modes the jiggle excites stable under compression
    (without it their stiffness turns negative near 25 % compression, for
    either law)."""
    dx, t = 1.0e-3, 1.0e-3
    lmp = make_lammps()
    lmp.commands_string(sph_header(f"0 {n} 0 {n}", dx, boundary="p p p") + f"""
        create_atoms 1 box
        set group all mol 1
        set group all volume {dx * dx * t}
        set group all mass {1000 * dx * dx * t}
        pair_style sph/icb {1.2 * dx} stress pk1 gradient quadratic plane stress hourglass 0.02
        pair_coeff * * {E} {NU} {law}
        neighbor {0.5 * dx} bin
        compute s all sph/elastic/atom stress
        thermo_style custom step pe fnorm
        run 0
        change_box all x scale {1 - ratio} remap
        displace_atoms all random {0.05 * dx} {0.05 * dx} 0.0 8123 units box
        group one id 1
        fix hold one setforce 0.0 0.0 0.0
        min_style sph/newton
        minimize 0 1e-8 200 2000
    """)
    return lmp


def test_block_compressed_by_half_converges_without_inversion():
    """50 % confined compression, far beyond St. Venant-Kirchhoff's limit
    point (a stretch of 1/sqrt(3)): from a jiggled start the neo-Hookean
    block converges to the exact uniform stress at every particle, without
    inversion (which would end the minimisation with an error)."""
    lmp = periodic_compression(0.5, "neohookean")
    natoms = lmp.get_natoms()
    sigma = np.array(lmp.numpy.extract_compute("s", 1, 2)[:natoms])
    want, _ = nh_cauchy(np.diag([0.5, 1.0, 1.0]), plane="stress")
    assert want[0, 0] < -0.5 * E
    np.testing.assert_allclose(sigma[:, 0], want[0, 0], rtol=1e-8)
    np.testing.assert_allclose(sigma[:, 1], want[1, 1], rtol=1e-8)
    np.testing.assert_allclose(sigma[:, 3], 0.0, atol=1e-8 * abs(want[0, 0]))
    lmp.close()


def test_svk_block_compressed_by_half_fails_loudly():
    """The same compression is beyond St. Venant-Kirchhoff's limit point:
    its minimisation diverges, and the run stops with an error instead of
    returning a state."""
    with pytest.raises(Exception, match="is gone|inverted|NOT an equilibrium"):
        periodic_compression(0.5, "svk")


BAD = [
    ("pair_coeff * * 1e9 0.3 mooney", "Unknown pair_coeff sph/icb material law mooney: use one of "
                                      "svk, neohookean"),
    ("pair_coeff * * 1e9 0.3 svk extra", "expected I J E nu [law]"),
]


@pytest.mark.parametrize("command, words", BAD)
def test_bad_law_is_a_clear_error(command, words):
    lmp = law_block((4, 4, 1), 2, "stress", law="svk")
    with pytest.raises(Exception, match=re.escape(words[:60])):
        lmp.command(command)
    lmp.close()


@pytest.mark.slow
def test_ccb_refuses_a_hyperelastic_law(tmp_path):
    from conftest import run_lmp
    script = sph_header("0 4 0 4", map_array=False) + f"""
        create_atoms 1 box
        set group all volume 1e-9
        set group all mass 1e-6
        set group all mol 1
        pair_style sph/ccb 0.0012 thickness 0.001
        pair_coeff * * {E} {NU} neohookean
        fix i all sph/ccb/nve
        run 0
    """
    rc, output = run_lmp(script, tmp_path)
    assert rc != 0
    assert "type 1 asks for the neohookean law, which needs the total-Lagrangian pair style " \
           "sph/icb" in " ".join(output.split())

"""Patch tests of pair_style sph/icb: an affine motion x = A X must give the
exact uniform deformation gradient A everywhere, free surfaces included
(the corrected gradient reproduces linear fields exactly), hence uniform
stress; a rigid rotation must give zero stress and zero force."""
from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import apply_affine, block, make_lammps, per_atom


def rotation_matrix(dim, angle):
    c, s = math.cos(angle), math.sin(angle)
    if dim == 2:
        return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    axis = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + s * K + (1 - c) * K @ K


def svk_cauchy(F, E, nu, dim, plane):
    """Cauchy stress and Green strain of the 3d St. Venant-Kirchhoff law at F;
    in plane stress the out-of-plane stretch is solved from S_zz = 0 (not
    the condensed lambda* of the code), and it changes J and E_zz."""
    mu = E / (2 * (1 + nu))
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    F = np.array(F, dtype=float)
    if dim == 2 and plane == "stress":
        G2 = 0.5 * (F.T @ F - np.eye(3))
        e_zz = -lam * (G2[0, 0] + G2[1, 1]) / (lam + 2 * mu)   # S_zz = 0
        F[2, 2] = math.sqrt(1 + 2 * e_zz)
    G = 0.5 * (F.T @ F - np.eye(3))
    S = lam * np.trace(G) * np.eye(3) + 2 * mu * G
    return F @ S @ F.T / np.linalg.det(F), G


VOIGT = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]


def run_affine(A, dim, measure, plane="strain", E=1.0e9, nu=0.3, gradient="linear"):
    lmp = make_lammps()
    n = (7, 6, 1) if dim == 2 else (5, 5, 5)
    extra = f"stress {measure} gradient {gradient}" + (f" plane {plane}" if dim == 2 else "")
    block(lmp, n=n, dim=dim, E=E, nu=nu, extra_pair=extra)
    lmp.command("run 0")           # builds the reference partners at x = x0
    apply_affine(lmp, A, dim)
    lmp.command("run 0")
    return lmp


@pytest.mark.parametrize("gradient", ["linear", "quadratic"])
@pytest.mark.parametrize("measure", ["corotated", "pk1"])
@pytest.mark.parametrize("dim,plane", [(2, "strain"), (2, "stress"), (3, None)])
def test_uniform_stretch_gives_exact_uniform_stress(measure, dim, plane, gradient):
    A = np.eye(3)
    A[0, 0], A[1, 1] = 1.01, 0.995
    if dim == 3:
        A[2, 2] = 1.003
    lmp = run_affine(A, dim, measure, plane or "strain", gradient=gradient)
    out = per_atom(lmp, "out", cols=True)
    sigma, G = svk_cauchy(A, 1.0e9, 0.3, dim, plane)
    want = np.array([sigma[a, b] for a, b in VOIGT])
    want_strain = np.array([G[a, b] for a, b in VOIGT])
    scale = np.abs(want).max()
    # every particle, surfaces and corners included
    assert np.abs(out[:, 0:6] - want).max() < 1e-9 * scale
    assert np.abs(out[:, 6:12] - want_strain).max() < 1e-12
    lmp.close()


@pytest.mark.parametrize("gradient", ["linear", "quadratic"])
@pytest.mark.parametrize("measure", ["corotated", "pk1"])
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("degrees", [30.0, 90.0])
def test_rigid_rotation_gives_zero_stress_and_force(measure, dim, degrees, gradient):
    A = rotation_matrix(dim, math.radians(degrees))
    lmp = run_affine(A, dim, measure, gradient=gradient)
    out = per_atom(lmp, "out", cols=True)
    assert np.abs(out[:, 0:12]).max() < 1e-12 * 1.0e9 + 1e-3   # Pa; E = 1e9
    f = np.array(lmp.numpy.extract_atom("f")[:lmp.get_natoms()])
    # force scale: E * V / dx = 1e9 * 1e-9 / 1e-3 (3d) -> 1e3 N; round-off level only
    assert np.abs(f).max() < 1e-9 * 1.0e3
    assert abs(lmp.get_thermo("pe")) < 1e-12
    # the rotation angle is reported exactly
    angle = out[:, 12]
    if dim == 2:
        assert np.allclose(angle, math.radians(degrees), atol=1e-12)
    else:
        assert np.allclose(angle, math.radians(degrees), atol=1e-10)
    lmp.close()


# round-off of the corrected gradient at the reference state: the quadratic
# correction solves a 5x5 (2d) least-squares system whose moment matrix is
# conditioned about 1e2 times worse than the linear one's 2x2
ROUNDOFF = {"linear": 1e-14, "quadratic": 1e-12}


@pytest.mark.parametrize("gradient", ["linear", "quadratic"])
def test_reference_state_has_identity_gradient_and_zero_force(lmp, gradient):
    block(lmp, n=(9, 7, 1), dim=2, extra_pair=f"stress pk1 gradient {gradient}")
    lmp.command("run 0")
    out = per_atom(lmp, "out", cols=True)
    eps = ROUNDOFF[gradient]
    # nothing but round-off: relative to E = 1e9 Pa for stress, absolute for strain
    assert np.abs(out[:, 0:6]).max() < eps * 1.0e9
    assert np.abs(out[:, 6:12]).max() < eps
    f = np.array(lmp.numpy.extract_atom("f")[:lmp.get_natoms()])
    # force scale E dx t = 1e9 * 1e-3 * 1e-3 = 1e3 N; round-off only
    assert np.abs(f).max() < eps * 1.0e3


def bending_green_strain(lmp, curvature):
    """Impose the pure-bending field u = (-k x y, k x^2/2) about the block's
    centre and return (computed, exact) Green strain xx, yy, xy per particle."""
    n = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    X = np.array(lmp.numpy.extract_atom("x0")[:n, :2])
    X -= X.mean(axis=0)
    k = curvature
    x[:n, 0] += -k * X[:, 0] * X[:, 1]
    x[:n, 1] += 0.5 * k * X[:, 0] ** 2
    lmp.command("run 0")
    got = per_atom(lmp, "out", cols=True)[:, [6, 7, 9]]
    want = np.empty_like(got)
    for i, (px, py) in enumerate(X):
        F = np.eye(2) + k * np.array([[-py, -px], [px, 0.0]])
        G = 0.5 * (F.T @ F - np.eye(2))
        want[i] = G[0, 0], G[1, 1], G[0, 1]
    return got, want


def test_quadratic_gradient_is_exact_for_bending_up_to_the_surfaces():
    # the linear correction is exact only for linear fields: on the one-sided
    # partner sets of the free surfaces it underestimates the bending strain,
    # which is what makes a coarse beam too soft; the quadratic one is exact
    results = {}
    for gradient in ("linear", "quadratic"):
        lmp = make_lammps()
        block(lmp, n=(12, 8, 1), dim=2, extra_pair=f"stress pk1 gradient {gradient}")
        lmp.command("run 0")
        got, want = bending_green_strain(lmp, curvature=2.0)   # 1/m; strain ~ 4e-3
        results[gradient] = np.abs(got - want).max() / np.abs(want).max()
        lmp.close()
    assert results["quadratic"] < 1e-10
    assert results["linear"] > 1e-2


# kernel support 2h = 2.4 dx: an interior particle has 20 reference partners,
# at dx (4), sqrt(2) dx (4), 2 dx (4) and sqrt(5) dx (8)
@pytest.mark.parametrize("lam,broken,failed", [(1.1, 4 / 20, 0.0), (2.5, 16 / 20, 1.0)])
def test_failure_indicators_of_a_uniform_stretch(lam, broken, failed):
    """Stretch by lam along x: adjacent partners move apart by lam; at 1.1
    the four at (2, 1) dx end 2.417 dx apart, beyond the support; at 2.5
    all but the four straight above and below are beyond it, adjacent ones
    too, which is failure."""
    lmp = make_lammps()
    block(lmp, n=(9, 9, 1))
    lmp.command("compute fail all sph/elastic/atom stretch broken failed")
    lmp.command("run 0")
    apply_affine(lmp, np.diag([lam, 1.0, 1.0]), 2)
    lmp.command("run 0")
    out = per_atom(lmp, "fail", cols=3)
    x0 = np.array(lmp.numpy.extract_atom("x0")[:lmp.get_natoms()], dtype=float)
    lmp.close()
    inner = np.all((x0[:, :2] > 2.0e-3) & (x0[:, :2] < 7.0e-3), axis=1)
    assert inner.sum() == 25
    assert out[inner, 0] == pytest.approx(lam, rel=1e-12)
    assert out[inner, 1] == pytest.approx(broken, abs=1e-12)
    assert np.all(out[inner, 2] == failed)
    # the edges have fewer partners but the same adjacent stretch
    assert out[:, 0] == pytest.approx(lam, rel=1e-12)


def test_failure_indicators_follow_atoms_that_are_sorted_during_a_run():
    """The adjacent partners are found once per neighbor list build, by local
    index; a shearing block sorted at every step must give, at the last step
    of the run, what a fresh evaluation of the same positions gives."""
    lmp = make_lammps()
    block(lmp, n=(9, 9, 1))
    lmp.commands_string("""
        compute fail all sph/elastic/atom stretch broken failed
        fix nve all nve
        atom_modify sort 1 0.0005
        neigh_modify every 1 delay 0 check no
        run 0
        velocity all ramp vx -400 400 y 0 0.009 units box
        timestep 1e-7
        compute most all reduce max c_fail[1]
        thermo_style custom step c_most
        thermo 1
        run 20
    """)
    n = lmp.get_natoms()
    ids = np.array(lmp.numpy.extract_atom("id")[:n])
    in_run = per_atom(lmp, "fail", cols=3)[np.argsort(ids)]
    lmp.command("run 0")
    ids = np.array(lmp.numpy.extract_atom("id")[:n])
    fresh = per_atom(lmp, "fail", cols=3)[np.argsort(ids)]
    lmp.close()
    assert np.max(fresh[:, 0]) > 1.01                  # sheared: stretches differ by atom
    np.testing.assert_allclose(in_run, fresh, rtol=1e-12)

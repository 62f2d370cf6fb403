"""Newton's third law, energy consistency (pk1 force = -grad energy, with and
without hourglass control) and the rotation fix against the exact polar
decomposition."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import polar

from conftest import block, make_lammps


def perturbed_block(dim, measure, hourglass=0.0, seed=1, amplitude=0.05, gradient="linear"):
    """hourglass None: the keyword left out (the pair style's default)."""
    lmp = make_lammps()
    n = (6, 5, 1) if dim == 2 else (4, 4, 3)
    extra = f"stress {measure} gradient {gradient}"
    if hourglass is not None:
        extra += f" hourglass {hourglass}"
    block(lmp, n=n, dim=dim, extra_pair=extra)
    lmp.command("run 0")
    rng = np.random.default_rng(seed)
    x = lmp.numpy.extract_atom("x")
    natoms = lmp.get_natoms()
    x[:natoms, :dim] += amplitude * 1e-3 * rng.standard_normal((natoms, dim))
    lmp.command("run 0")
    return lmp, natoms


@pytest.mark.parametrize("gradient", ["linear", "quadratic"])
@pytest.mark.parametrize("measure", ["corotated", "pk1"])
@pytest.mark.parametrize("dim", [2, 3])
def test_total_force_vanishes(measure, dim, gradient):
    lmp, natoms = perturbed_block(dim, measure, hourglass=0.5, gradient=gradient)
    f = np.array(lmp.numpy.extract_atom("f")[:natoms])
    scale = np.abs(f).max()
    assert scale > 1.0                       # the perturbation does load the particles
    assert np.abs(f.sum(axis=0)).max() < 1e-12 * scale * natoms
    lmp.close()


@pytest.mark.parametrize("dim", [2, 3])
def test_hourglass_control_is_on_by_default(dim):
    """Without the keyword the pair style uses hourglass 0.2 (the accurate
    default): the same energy and forces as the keyword, not those of 0."""
    runs = {}
    for hourglass in (None, 0.2, 0.0):
        lmp, natoms = perturbed_block(dim, "pk1", hourglass=hourglass, gradient="quadratic")
        runs[hourglass] = (lmp.get_thermo("pe"), np.array(lmp.numpy.extract_atom("f")[:natoms]))
        lmp.close()
    assert runs[None][0] == runs[0.2][0]
    assert np.array_equal(runs[None][1], runs[0.2][1])
    assert runs[None][0] > runs[0.0][0] * (1 + 1e-3)    # the penalty adds energy


@pytest.mark.parametrize("hourglass,gradient", [(0.0, "linear"), (0.5, "linear"),
                                                (0.0, "quadratic"), (0.5, "quadratic")])
@pytest.mark.parametrize("dim", [2, 3])
def test_pk1_force_is_minus_energy_gradient(dim, hourglass, gradient):
    lmp, natoms = perturbed_block(dim, "pk1", hourglass=hourglass, gradient=gradient)
    f = np.array(lmp.numpy.extract_atom("f")[:natoms])
    x = lmp.numpy.extract_atom("x")
    step = 1e-9   # m; spacing 1e-3 m, perturbation 5e-5 m
    rng = np.random.default_rng(7)
    for i in rng.choice(natoms, size=6, replace=False):
        for a in range(dim):
            x0 = x[i, a]
            x[i, a] = x0 + step
            lmp.command("run 0")
            ep = lmp.get_thermo("pe")
            x[i, a] = x0 - step
            lmp.command("run 0")
            em = lmp.get_thermo("pe")
            x[i, a] = x0
            fd = -(ep - em) / (2 * step)
            assert fd == pytest.approx(f[i, a], rel=1e-5, abs=1e-6 * np.abs(f).max())
    lmp.close()


def random_deformation(rng, dim):
    F = np.eye(3)
    F[:dim, :dim] += 0.3 * rng.standard_normal((dim, dim))
    Q, _ = np.linalg.qr(rng.standard_normal((dim, dim)))
    if np.linalg.det(Q) < 0:
        Q[:, 0] *= -1
    F[:dim, :dim] = Q @ F[:dim, :dim]
    if np.linalg.det(F) <= 0:
        F[:dim, 0] *= -1
        F[:dim, :dim] = F[:dim, :dim] @ np.diag([-1.0] + [1.0] * (dim - 1))
    return F


@pytest.mark.parametrize("method,dim", [("iterative", 3), ("polar", 3), ("iterative", 2)])
def test_rotation_fix_equals_polar_rotation(method, dim):
    """Affine motion x = F X: every particle sees exactly F; its rotation must
    be the polar rotation of F, orthonormal with det +1."""
    rng = np.random.default_rng(11)
    for trial in range(4):
        F = random_deformation(rng, dim)
        lmp = make_lammps()
        block(lmp, n=(5, 4, 1) if dim == 2 else (4, 4, 4), dim=dim, extra_pair="stress pk1",
              rotation=f"fix rot all sph/rotation method {method} tol 1e-14 maxiter 200"
              if dim == 3 else "fix rot all sph/rotation")
        lmp.command("run 0")
        natoms = lmp.get_natoms()
        x = lmp.numpy.extract_atom("x")
        x0 = lmp.numpy.extract_atom("x0")
        for i in range(natoms):
            x[i, :dim] = F[:dim, :dim] @ x0[i, :dim]
        lmp.command("run 0")
        rot = np.array(lmp.numpy.extract_fix("rot", 1, 2)[:natoms])
        R_exact, _ = polar(F[:dim, :dim])
        for i in range(natoms):
            R = rot[i, 1:].reshape(3, 3)[:dim, :dim]
            assert np.abs(R.T @ R - np.eye(dim)).max() < 1e-12
            assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
            assert np.abs(R - R_exact).max() < 1e-10
        lmp.close()

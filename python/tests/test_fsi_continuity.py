"""The twins' own velocities in the fluid's continuity equation (fix
sph/fluid continuity body, the default; src/ELASTIC-SPH/sph_twin_continuity.cpp).
RHEO's velocity gradient sees a solid neighbour with its wall image
velocity p (v_s - v_f), which for a moving wall is the velocity of a wall
at rest (studies/fsi_rheo 9.2).  The test that can tell: water and body
moving together at one velocity, with no force between them (no
viscosity, the fluid at its rest density), are one rigid translation.
Their velocity gradient must be zero and the density must stay the rest
density, on any number of ranks and with newton on or off; RHEO's image
velocity compresses the water ahead of the body instead."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import run_lmp
from test_fsi import ATOMS, SETTINGS

# an 8 x 4 elastic block (type 2) with 6 x 4 water particles (type 1)
# against its right face and 8 x 3 under it, 1 cm spacing, twins type 3;
# everything at (1.0, 0.5) m/s, zero gravity, no viscosity: pressure is
# zero at the rest density and pair rheo's artificial viscosity (fluid
# pairs only) acts on compression of the velocity field less its gradient,
# so nothing acts on anything.  The artificial viscosity reads the ghosts'
# gradients: on 2 ranks it fails the run if their differences are missing
GALILEAN = SETTINGS + """
{processors}
region box block -0.14 0.26 -0.10 0.12 -0.5 0.5 units box
create_box 3 box
lattice sq 0.01 origin 0.5 0.5 0.0
region body block 0 0.08 0 0.04 INF INF units box
region side block 0.08 0.14 0 0.04 INF INF units box
region under block 0 0.08 -0.03 0 INF INF units box
create_atoms 2 region body
create_atoms 1 region side
create_atoms 1 region under
""" + ATOMS + """pair_style hybrid/overlay rheo 0.03 artificial/visc 1.0 sph/icb 0.012 plane strain
pair_coeff * * rheo
pair_coeff 2 2 sph/icb 1e6 0.3
neigh_modify exclude type 1 2 exclude type 2 3
neighbor 0.003 bin
fix rheo all rheo 0.03 {kernel} 0 interface/reconstruct density 1000 1000 1000 \
speed/sound 10 10 10
fix visc all rheo/viscosity * constant 0.0
fix pres all rheo/pressure * linear
create_sph_twins body 3
fix fsi all sph/fluid {continuity}
fix 2d all enforce2d
velocity all set 1.0 0.5 0 units box
timestep 1e-4
compute grad all rheo/property/atom grad/v/xx grad/v/xy grad/v/yx grad/v/yy
compute den all property/atom rho
run {nsteps}
write_dump fluid custom end.txt id x y vx vy c_den c_grad[*] modify sort id format float %.17g
"""


def translate(tmp_path, continuity: str, nsteps: int, nprocs: int = 1,
              newton: str = "off", kernel: str = "quintic") -> np.ndarray:
    """The water's state after nsteps of the joint translation: rows of id,
    x, y, vx, vy, rho and the velocity gradient xx, xy, yx, yy"""
    script = GALILEAN.format(
        processors="processors 2 1 1" if nprocs == 2 else "",
        continuity=f"continuity {continuity}", nsteps=nsteps, kernel=kernel)
    script = script.replace("newton off", f"newton {newton}")
    rc, out = run_lmp(script, tmp_path, nprocs=nprocs, timeout=120)
    assert rc == 0, out[-2000:]
    return np.loadtxt(tmp_path / "end.txt", skiprows=9)


@pytest.mark.parametrize("nprocs,newton,kernel", [
    (1, "off", "quintic"), (1, "on", "quintic"), (2, "off", "quintic"), (2, "on", "quintic"),
    (1, "off", "wendland/c4")])
def test_joint_translation_keeps_the_rest_density(tmp_path, nprocs, newton, kernel):
    """With the twins' own velocities the water beside the body sees no
    relative motion: every gradient is zero and every density the rest
    density after 50 steps, to round-off (the correction is RHEO's term
    less the twins' own, each of order U/h = 100 1/s).  On 2 ranks the
    body and the water under it are split at x = 6 cm: the pairs across
    the cut are summed for ghosts (newton on, then sent back) or on both
    ranks (newton off), and the ghosts' gradients come by the forward
    communication of the differences.  The package's kernel gradient
    must be fix rheo's (quintic or Wendland C4) for the terms to cancel."""
    end = translate(tmp_path, "body", 50, nprocs, newton, kernel)
    assert end.shape[0] == 48
    # measured: gradients 2.2e-11 (1 rank) and 3.0e-11 1/s (2 ranks),
    # densities 8.0e-11 and 1.1e-10 kg/m^3 off, velocities 6e-13 m/s
    # off; without the step-start correction 17 1/s and 30 kg/m^3, without
    # the ghosts' differences (2 ranks) 0.85 1/s and 2.0 kg/m^3
    assert np.abs(end[:, 6:10]).max() < 1e-10 * 100.0
    assert np.abs(end[:, 5] - 1000.0).max() < 1e-12 * 1000.0
    # and the translation itself is untouched: 50 steps of 1e-4 s
    assert np.abs(end[:, 3] - 1.0).max() < 1e-10
    assert np.abs(end[:, 4] - 0.5).max() < 1e-10


def test_rheo_image_velocity_compresses_the_water(tmp_path):
    """The same translation with RHEO's image velocity (continuity rheo):
    the water next to the body takes the body for a wall at rest that it
    runs into, or away from: its velocity gradient is of order U/h and its
    density departs from the rest density within the first steps, which is
    the error the default removes."""
    end = translate(tmp_path, "rheo", 50)
    # measured: gradients up to 60 1/s, densities 37 kg/m^3 (3.7 %) off
    # the rest density, and the water slowed or turned by up to 0.65 m/s
    assert np.abs(end[:, 6:10]).max() > 10.0
    assert np.abs(end[:, 5] - 1000.0).max() > 10.0
    assert np.abs(end[:, 3:5] - [1.0, 0.5]).max() > 0.1


def test_continuity_keyword_errors(tmp_path):
    """A value other than body or rheo names both; a twin type that also
    holds other atoms (the correction takes every atom of it for a twin)
    is refused at the run's start."""
    from test_fsi import blob_script, refused
    script = blob_script().replace("fix fsi all sph/fluid\n", "")
    error = refused(tmp_path, script, "fix fsi all sph/fluid continuity own")
    assert "continuity must be body" in error and "or rheo" in error and ": own" in error
    # a fluid atom turned into the twins' type 3 (a RHEO solid of the same
    # density, so that only the new check can refuse it)
    script = blob_script() + "set atom 40 type 3\nset atom 40 rheo/status 1\n"
    error = refused(tmp_path, script, "run 1")
    assert "atom 40 is of twin type 3 but is not a twin" in error
    assert "give the twins a type of their own" in error

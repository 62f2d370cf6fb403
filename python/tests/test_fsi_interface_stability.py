"""A fluid particle alone at RHEO's walls, and the two cures in fix
sph/fluid (src/ELASTIC-SPH/sph_density_predictor.cpp,
sph_interface_viscosity.cpp).  Fix rheo evaluates the pressure of a step
from the density of the half step before it: a pressure that lags the
positions by dt/2 pumps a fluid particle's oscillation against its
neighbours at the rate w^2 dt/4.  Pair rheo's artificial viscosity removes
that between fluid particles, but with interface/reconstruct not between
fluid and solid ones: a water particle alone on RHEO's floor rattles with a
growing amplitude and is shot off (studies/fsi_rheo 9.9).  The default
pressure/density full gives the force the step's density; interface/visc
adds pair rheo's term across the interface, momentum exact."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import run_lmp
from test_fsi import ATOMS, COUPLE, SETTINGS, blob_script, momentum_history, refused
from test_fsi import assert_ranks_agree, run_on_1_and_2_ranks

# the block's share of the blob's momentum after 300 steps with the keyword
# (measured: 0.4819 at newton off and on; 0.449 without it, test_fsi.py)
BODY_SHARE = 0.482

# one water particle (type 1) at rest half a spacing above a floor of 3
# layers of RHEO wall particles (type 3, held by fix setforce), under
# gravity; a small elastic block (type 2, twins type 4) far above it,
# which fix sph/fluid needs and which takes no part.  1 cm spacing,
# c_f = 10 m/s, dt = 0.1 h/c_f as fix sph/fluid allows
LONE = SETTINGS.replace("boundary f f p", "boundary p f p") + """
region box block 0 0.30 -0.04 0.16 -0.5 0.5 units box
create_box 4 box
lattice sq 0.01 origin 0.5 0.5 0.0
region floor block INF INF -0.03 0 INF INF units box
region water block 0.10 0.11 0 0.01 INF INF units box
region blockr block 0 0.04 0.10 0.13 INF INF units box
create_atoms 3 region floor
create_atoms 1 region water
create_atoms 2 region blockr
""" + ATOMS + """group walls type 3
set group walls mass 0.1
set group walls rheo/status 1
pair_style hybrid/overlay rheo 0.03 artificial/visc 1.0 sph/icb 0.012 plane strain
pair_coeff * * rheo
pair_coeff 2 2 sph/icb 1e6 0.3
neigh_modify exclude type 1 2 exclude type 2 3 exclude type 2 4
neighbor 0.003 bin
fix rheo all rheo 0.03 quintic 0 interface/reconstruct density 1000 1000 1000 1000 &
    speed/sound 10 10 10 10
fix visc all rheo/viscosity * constant 1e-3
fix pres all rheo/pressure * linear
create_sph_twins body 4
fix fsi all sph/fluid {keyword}
fix gravity fluid gravity 9.81 vector 0 -1 0
fix 2d all enforce2d
fix hold walls setforce 0.0 0.0 0.0
timestep 1e-4
compute vy fluid reduce max vy
compute y fluid reduce max y
variable vy equal c_vy
variable y equal c_y
fix track all ave/time {every} 1 {every} v_vy v_y file track.txt format " %.17g"
run {nsteps}
"""


def lone_particle(tmp_path, keyword: str, nsteps: int = 3000,
                  every: int = 25) -> tuple[int, str, np.ndarray]:
    """The run's return code, output and the particle's (step, v_y, y)
    every `every` steps"""
    script = LONE.format(keyword=keyword, nsteps=nsteps, every=every)
    rc, out = run_lmp(script, tmp_path, timeout=120)
    track = np.loadtxt(tmp_path / "track.txt", ndmin=2)
    return rc, out, track


def oscillation(track: np.ndarray, first: int, last: int) -> tuple[float, float]:
    """The angular frequency of the particle's vertical oscillation between
    steps first and last (from its zero crossings) and the growth rate of
    its amplitude (a fit of log |v_y| at the peaks between crossings)"""
    steps, vy = track[:, 0], track[:, 1]
    keep = (steps > first) & (steps < last)
    t, vy = steps[keep] * 1e-4, vy[keep]
    cross = np.flatnonzero(np.diff(np.sign(vy)) != 0)
    period = 2.0 * np.median(np.diff(t[cross]))
    peaks = [cross[k] + np.argmax(np.abs(vy[cross[k]:cross[k + 1]]))
             for k in range(len(cross) - 1)]
    growth = np.polyfit(t[peaks], np.log(np.abs(vy[peaks])), 1)[0]
    return 2.0 * np.pi / period, growth


def test_half_step_pressure_pumps_a_lone_particle(tmp_path):
    """Fix rheo's own scheme (pressure/density half): the particle's
    oscillation on the floor grows at the rate w^2 dt/4 of a spring whose
    force lags by dt/2 (measured: w = 1309 1/s, growth 45.4 1/s against
    42.8 predicted), from the round-off of its landing until it is shot out
    of the box ('Lost atoms' after about 1600 steps).  RHEO's behaviour,
    which the default corrects: if a LAMMPS update changes it, this says
    so."""
    rc, out, track = lone_particle(tmp_path, "pressure/density half", nsteps=1200, every=1)
    assert rc == 0, out[-2000:]
    omega, growth = oscillation(track, 100, 1200)
    assert growth == pytest.approx(omega**2 * 1e-4 / 4.0, rel=0.2)
    assert np.abs(track[-100:, 1]).max() > 0.3


def test_step_density_keeps_it_bounded(tmp_path):
    """With the default (pressure/density full) the force sees the density
    of its own step: the particle's oscillation from its landing neither
    grows nor is damped (nothing damps it) over 3000 steps: amplitude
    2.909e-3 m/s in the first 500 steps, 2.903e-3 in the last (measured)."""
    rc, out, track = lone_particle(tmp_path, "", nsteps=3000, every=1)
    assert rc == 0, out[-2000:]
    steps, vy, y = track.T
    first = np.abs(vy[steps <= 500]).max()
    last = np.abs(vy[steps > 2500]).max()
    assert 1e-3 < first < 5e-3
    assert last == pytest.approx(first, rel=0.01)
    # it stays half a spacing above the floor's top layer
    assert np.abs(y - 0.005).max() < 0.01 * 0.005


def test_interface_visc_lets_it_rest(tmp_path):
    """With pair rheo's own artificial viscosity across the interface (and
    fix rheo's half-step pressure) the particle comes to rest half a
    spacing above the floor's top layer: |v_y| 1e-5 m/s after 1000 steps,
    6e-15 m/s after 3000 (measured), at y = 4.998 mm (its weight
    compresses it by 2e-4 of a spacing)."""
    rc, out, track = lone_particle(tmp_path, "pressure/density half interface/visc 1.0")
    assert rc == 0, out[-2000:]
    steps, vy, y = track.T
    assert steps[-1] == 3000
    assert np.abs(vy[steps >= 2500]).max() < 1e-12
    assert np.abs(y[steps >= 2000] - 0.005).max() < 0.01 * 0.005


@pytest.mark.parametrize("newton", ["off", "on"])
def test_interface_visc_conserves_momentum(lmp, tmp_path, newton):
    """The blob's impact on the free block with the keyword: the pairs'
    forces are antisymmetric bit for bit and each rank adds them to its
    owned atoms from a full list, so the total momentum stays to round-off
    with newton off and on.  And the term acts: the block takes more of
    the blob's momentum than without it (0.449)."""
    script = blob_script(couple=COUPLE.replace("sph/fluid", "sph/fluid interface/visc 1.0"))
    lmp.commands_string(script.replace("newton off", f"newton {newton}"))
    p = momentum_history(lmp, tmp_path, 300)
    p0 = -36 * 0.1 * 2.0
    drift = np.abs(p - [p0, 0.0]).max() / abs(p0)
    assert drift < 1e-13
    body = lmp.extract_compute("pb", 0, 0)
    assert body / p0 == pytest.approx(BODY_SHARE, abs=0.002)
    assert abs(body / p0 - 0.449) > 0.005


@pytest.mark.slow
def test_interface_visc_two_ranks_agree(tmp_path):
    """The blob's run with the keyword on 2 ranks (split through the body)
    conserves momentum and ends where 1 rank ends, to round-off: a pair
    across the cut is evaluated on both ranks, each for its own atom."""
    def script_of(processors):
        return blob_script(processors,
                           couple=COUPLE.replace("sph/fluid", "sph/fluid interface/visc 1.0"))
    assert_ranks_agree(run_on_1_and_2_ranks(tmp_path, script_of, 300))


def test_keyword_errors(tmp_path):
    """A negative coefficient, or a pressure/density other than full or
    half, is refused, naming the keyword and its values."""
    script = blob_script().replace("fix fsi all sph/fluid\n", "")
    error = refused(tmp_path, script, "fix fsi all sph/fluid interface/visc -1")
    assert "interface/visc must be an artificial viscosity coefficient >= 0" in error
    error = refused(tmp_path, script, "fix fsi all sph/fluid pressure/density step")
    assert "pressure/density must be full" in error and "or half" in error and ": step" in error

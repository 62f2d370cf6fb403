"""compute sph/probe: displacement, stress and strain at material points
given by their reference positions, exact for quadratic fields, the same
on any number of ranks and after a restart."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import lattice_2d_script, make_lammps, run_lmp
from test_traction import DX, lattice_2d

NX, NY = 12, 6


def quadratic_u(X):
    """A quadratic displacement field with every second-order term."""
    x, y = X[..., 0], X[..., 1]
    ux = 1e-4 * x + 3.0 * x * x - 2.0 * x * y + 1.5 * y * y + 2e-6
    uy = -2e-4 * y + 1.0 * x * x + 2.5 * x * y - 3.0 * y * y - 1e-6
    return np.stack([ux, uy], axis=-1)


def strip(lmp, probes):
    lattice_2d(lmp, f"0 {NX} 0 {NY}")
    pts = " ".join(f"{p[0]} {p[1]}" for p in probes)
    lmp.commands_string(f"""
        set group all mol 1
        set_sph_volumes all lattice {DX} thickness 1e-3 density 1000.0
        pair_style sph/icb {1.2 * DX} plane stress
        pair_coeff * * 1.0e9 0.3
        neighbor {0.5 * DX} bin
        compute probe all sph/probe {pts}
    """)


PROBES = [(0.5 * NX * DX, 0.5 * NY * DX),     # interior, between particles
          (NX * DX, 0.5 * NY * DX),           # end-face centre
          (0.3 * DX, 0.0),                     # on the bottom face near a corner
          (0.37 * NX * DX, 0.81 * NY * DX)]


def probed(displacement) -> np.ndarray:
    """The probe's array at PROBES after every particle of the strip is moved
    to x = X + displacement(X)."""
    lmp = make_lammps()
    strip(lmp, PROBES)
    lmp.command("run 0")
    n = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    x0 = np.array(lmp.numpy.extract_atom("x0")[:n])
    x[:n, :2] = x0[:, :2] + displacement(x0[:, :2])
    lmp.command("run 0")
    arr = lmp.numpy.extract_compute("probe", 0, 2)
    values = np.array([[arr[p, c] for c in range(15)] for p in range(len(PROBES))])
    lmp.close()
    return values


def test_quadratic_displacement_is_probed_exactly():
    got = probed(quadratic_u)[:, :2]
    exact = quadratic_u(np.array(PROBES))
    assert np.max(np.abs(got - exact)) < 1e-12 * np.max(np.abs(exact))


def test_uniform_stress_and_strain_are_probed_exactly():
    """A uniform stretch: the probe returns the particles' (uniform) stress
    and strain on the surface as inside."""
    values = probed(lambda X: np.stack([1e-3 * X[:, 0], 0.0 * X[:, 1]], axis=-1))
    sxx, exx = values[:, 3], values[:, 9]
    E_green = 0.5 * (1.001 ** 2 - 1.0)
    # the particles' own strains, and so their stresses, carry ~1e-10 of
    # round-off relative to a strain of 1e-3: F = sum (x_j - x_i) g_ij
    assert np.allclose(exx, E_green, rtol=1e-9, atol=0)
    assert np.ptp(sxx) < 1e-9 * abs(sxx[0]) and sxx[0] > 0.0


def test_point_outside_the_body_is_an_error():
    lmp = make_lammps()
    strip(lmp, [(3 * NX * DX, 0.5 * NY * DX)])
    with pytest.raises(Exception) as err:
        lmp.commands_string("thermo_style custom step c_probe[1][1]\nrun 0")
    assert "too few atoms of group all within" in str(err.value)
    lmp.close()


@pytest.mark.parametrize("words,message", [
    ("0.001", "takes reference points, 2 coordinates each"),
    ("0.001 0.002 0.003", "takes reference points, 2 coordinates each"),
    ("0.001 0.002 radius 0", "radius must be > 0"),
])
def test_probe_syntax_errors(words, message):
    lmp = make_lammps()
    lattice_2d(lmp, "0 4 0 4")
    with pytest.raises(Exception) as err:
        lmp.command(f"compute p all sph/probe {words}")
    assert message in str(err.value)
    lmp.close()


# the clamped strip's model and probes: what a restart does not keep
MODEL = """
pair_style sph/icb 0.0012 plane stress
pair_coeff * * 1.0e9 0.3
neighbor 0.0005 bin
region clampzone block INF 0.0 INF INF INF INF units box
group clamp region clampzone
group body subtract all clamp
fix hold clamp sph/mirror x 0.0
compute tip body sph/probe 0.02 0.0025 0.01 0.0
"""
PRINT = 'print "PROBE $(c_tip[1][1]:%.15e) $(c_tip[1][2]:%.15e) $(c_tip[2][4]:%.15e)"\n'
SCRIPT = (lattice_2d_script("-3 20 0 5") + """
set group all mol 1
set_sph_volumes all lattice 0.001 thickness 0.001 density 1000.0
""" + MODEL + """
fix load all sph/traction x 0.02 traction 0.0 -2.0e5
fix_modify load energy yes
min_style sph/newton
minimize 0 1e-10 50 100
{after}
""" + PRINT)


def probe_line(out: str) -> list[float]:
    line = [ln for ln in out.splitlines() if ln.startswith("PROBE")][-1]
    return [float(v) for v in line.split()[1:]]


@pytest.mark.slow
def test_probe_is_the_same_on_1_and_2_ranks_and_after_a_restart(tmp_path):
    one_rc, one = run_lmp(SCRIPT.format(after="write_restart probe.restart"),
                          tmp_path, nprocs=1)
    assert one_rc == 0, one
    two_rc, two = run_lmp(SCRIPT.format(after=""), tmp_path, nprocs=2)
    assert two_rc == 0, two
    a, b = probe_line(one), probe_line(two)
    assert a[1] < 0.0
    assert np.allclose(a, b, rtol=1e-10, atol=0)
    restarted = "read_restart probe.restart\n" + MODEL + "run 0\n" + PRINT
    rc, out = run_lmp(restarted, tmp_path, nprocs=2)
    assert rc == 0, out
    assert np.allclose(probe_line(out), a, rtol=1e-10, atol=0)

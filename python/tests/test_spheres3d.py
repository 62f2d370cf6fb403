"""Two identical elastic spheres colliding head on in 3d with fix
sph/contact (examples/spheres3d): the geometry the script documents, the
balances a collision must keep (momentum, energy, mirror symmetry, 1 and 2
ranks), and the contact against Hertz's impact theory and against the
flat-facet contact that a lattice sphere makes at coarse resolution."""
from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from esph import theory
from esph.runner import clean_environment, run_script
from esph.spheres3d import SPHERES3D, SpheresCase, run_spheres

CASE = SpheresCase()        # R = 5 cm, R/dx = 6, 20 m/s each: 1824 particles, ~370 steps


@pytest.fixture(scope="module")
def collision():
    """The default collision on one rank (about a second of LAMMPS)."""
    return run_spheres(CASE, 1)


def lattice_sites(nr: float) -> np.ndarray:
    """Offsets (i + 1/2, j + 1/2, k + 1/2) from the centre, in dx, of the
    cubic lattice sites within R = nr dx: one sphere of the script."""
    n = int(math.ceil(nr)) + 1
    axis = np.arange(-n, n) + 0.5
    g = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    return g[(g ** 2).sum(axis=1) < nr ** 2]


def test_hertz_impact_against_its_equation_of_motion():
    """theory.hertz_impact against a direct integration of the approach
    delta of the centres, m* delta'' = -(4/3) E* R*^(1/2) delta^(3/2), from
    delta' = v at first touch to separation; and against Johnson's rounded
    t_c = 2.87 (m*^2/(R* E*^2 v))^(1/5) for two identical spheres (R* = R/2,
    E* = E/(2 (1 - nu^2)), m* = m/2)."""
    R, E, nu, m, v = 0.05, 20.0e9, 0.3, 0.5, 40.0
    got = theory.hertz_impact(R, E, nu, m, v)
    Rs, Es, ms = R / 2, E / (2 * (1 - nu ** 2)), m / 2
    stiff = 4.0 / 3.0 * Es * math.sqrt(Rs)

    def rhs(_, y):
        return [y[1], -stiff * max(y[0], 0.0) ** 1.5 / ms]

    def apart(_, y):
        return y[0]
    apart.terminal, apart.direction = True, -1
    sol = solve_ivp(rhs, (0.0, 1.0), [0.0, v], events=apart, rtol=1e-11, atol=1e-14,
                    max_step=got.duration / 2000, first_step=got.duration / 1e6)
    assert got.duration == pytest.approx(sol.t_events[0][0], rel=1e-6)
    assert got.approach_max == pytest.approx(sol.y[0].max(), rel=1e-6)
    assert got.force_max == pytest.approx(stiff * sol.y[0].max() ** 1.5, rel=1e-6)
    assert got.duration == pytest.approx(2.87 * (ms ** 2 / (Rs * Es ** 2 * v)) ** 0.2, rel=2e-3)
    assert got.contact_radius == pytest.approx(math.sqrt(Rs * got.approach_max), rel=1e-12)
    # two different spheres: sphere 2 given explicitly, the same as the copy
    assert theory.hertz_impact(R, E, nu, m, v, R, E, nu, m) == got


def test_flat_contact_impact_is_a_half_period():
    """The facets' contact is a linear spring: flat punches (2 a E/(1 - nu^2)
    each) in series with the contact springs; t_c = pi sqrt(m*/k)."""
    area, E, nu, m, v, kc = 1.0e-3, 20.0e9, 0.3, 0.5, 40.0, 1.0e9
    got = theory.flat_contact_impact(area, E, nu, m, v, kc)
    k_body = 2.0 * math.sqrt(area / math.pi) * E / (1 - nu ** 2)
    k = 1.0 / (2.0 / k_body + 1.0 / kc)
    assert got.duration == pytest.approx(math.pi * math.sqrt(m / 2 / k), rel=1e-12)
    assert got.force_max == pytest.approx(v * math.sqrt(m / 2 * k), rel=1e-12)
    # the same duration at any speed; stiffer without the springs
    assert theory.flat_contact_impact(area, E, nu, m, 5.0, kc).duration == got.duration
    assert theory.flat_contact_impact(area, E, nu, m, v).duration < got.duration


@pytest.mark.slow
def test_geometry_is_the_documented_one(tmp_path):
    """in.spheres3d at R/dx = 6 before the first step: each sphere is the
    lattice sites within R of its centre ((i + 1/2) dx offsets, 912 sites),
    one molecule ID each, sphere 2 the mirror image of sphere 1, the facets
    (1 + gap) dx apart; set_sph_volumes keeps each sphere's volume N dx^3
    (its corrections sum to zero along every row) but changes the surface
    particles' volumes, and m = rho V."""
    got = {}

    def grab(lmp):
        n = lmp.get_natoms()
        got["x"] = np.array(lmp.numpy.extract_atom("x")[:n])
        got["x0"] = np.array(lmp.numpy.extract_atom("x0")[:n])
        got["vol"] = np.array(lmp.numpy.extract_atom("vfrac")[:n])
        got["mass"] = np.array(lmp.numpy.extract_atom("rmass")[:n])
        got["mol"] = np.array(lmp.numpy.extract_atom("molecule")[:n])

    run_script(SPHERES3D, {**CASE.variables(tmp_path), "tmax": 1e-12, "tail": 0.0}, read=[],
               inspect=grab)
    dx, x, mol = CASE.dx, got["x"], got["mol"]
    sites = lattice_sites(CASE.nr)
    assert len(sites) == 912
    assert np.array_equal(got["x0"], x)
    kf = sites[:, 0].max()                                  # the facet's offset, 5.5
    xc = (kf + 0.5 * (1.0 + CASE.gap)) * dx
    for body, centre in ((1, -xc), (2, xc)):
        sel = mol == body
        rel = (x[sel] - [centre, 0.0, 0.0]) / dx
        assert sel.sum() == len(sites)
        have = {tuple(r) for r in np.round(rel, 6)}
        assert have == {tuple(s) for s in sites}
        assert got["vol"][sel].sum() == pytest.approx(len(sites) * dx ** 3, rel=1e-12)
    assert got["vol"].std() > 0.01 * dx ** 3                 # surface-corrected
    assert np.allclose(got["mass"], CASE.rho * got["vol"], rtol=1e-12)
    a, b = x[mol == 1], x[mol == 2] * [-1.0, 1.0, 1.0]
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    assert d.min(axis=1).max() < 1e-12 * dx                  # mirror images
    gap = np.linalg.norm(x[mol == 1][:, None, :] - x[mol == 2][None, :, :], axis=2).min()
    assert gap == pytest.approx((1.0 + CASE.gap) * dx, rel=1e-9)
    assert (np.abs(x[mol == 1][:, 0] - x[mol == 1][:, 0].max()) < 1e-9 * dx).sum() == 16


@pytest.mark.slow
def test_collision_conserves_momentum_and_energy_and_stays_symmetric(collision):
    """Pair and contact forces cancel pair by pair: the total momentum stays
    at round-off of 2 m v.  Energy (kinetic + strain + contact, stress pk1:
    the forces are its exact gradient) has velocity Verlet's O(dt^2) error:
    8.2e-5 at R/dx = 6, 4.1e-5 at 8, 2.9e-5 at 10 (dt ~ dx: (6/8)^2 and
    (6/10)^2 of the first), a 5e-5 drift at the end; bounded here at 1.5e-4.
    The spheres are mirror images about x = 0, and velocity Verlet with
    mirror-symmetric forces keeps them so: the centroids mirror each other
    to round-off (7.6e-15 dx measured).  They come apart at the end and stay
    apart, intact, slower than they came (energy left in vibration)."""
    r = collision
    assert r.momentum_error < 1e-14 and r.momentum < 1e-14
    assert r.energy_error < 1.5e-4 and abs(r.energy_drift) < 1.5e-4
    assert r.mirror_error < 1e-12
    assert r.separated and not r.recontact and not r.failed
    assert 0.95 < r.restitution < 1.0                        # 0.977 measured


@pytest.mark.slow
def test_contact_starts_when_the_facets_come_dx_apart(collision):
    """The spheres move rigidly until their facets, (1 + gap) dx apart at
    the start, come within the contact distance dx: after gap dx/(2 v), at
    the next step."""
    r = collision
    t_touch = CASE.gap * CASE.dx / (2 * CASE.v)
    assert t_touch <= r.contact_first <= t_touch + r.dt


@pytest.mark.slow
def test_contact_against_hertz_and_the_flat_facets(collision):
    """Hertz's impact (Johnson 1985, 11.4) assumes the contact circle, of
    radius a = 0.15 R here (largest approach 2.2 mm = 0.26 dx), is resolved.
    A lattice sphere's pole is instead a flat facet of area about pi R dx
    (16 particles at R/dx = 6, 24 at 8, 32 at 10 and 12, 52 at 16), wider
    than that circle at every practical dx: its radius shrinks only as
    sqrt(dx).  Two such facets make a linear contact, flat punches in series
    with the contact springs (theory.flat_contact_impact), stiffer than
    Hertz's:
    measured at 20 m/s (Hertz: 162 us), the contact lasts
        R/dx  facet  t_c [us]  vs Hertz  vs the flat facets  F_max vs Hertz
          6     16     97.33   -40.0 %        +4.7 %            +44.5 %
          8     24     96.84   -40.4 %        +2.1 %            +47.2 %
         10     32     98.29   -39.4 %        +1.5 %            +43.0 %
         12     32    106.96   -33.7 %        +1.4 %            +27.2 %
         16     52    105.34   -35.0 %        -0.6 %            +29.7 %
    (and 97.33 / 97.81 us at 10 / 40 m/s and R/dx = 6, where Hertz's falls
    by 4^(1/5) = 1.32: a linear contact).  So the error against Hertz does
    not converge at these resolutions, it moves with the facet, while the
    flat-facet estimate holds to 5 % at R/dx = 6 and 2 % beyond: the solid
    and the contact springs do what an elastic continuum of that faceted
    shape would.  The bounds bracket the measured R/dx = 6 values by a few
    per cent; a change of the contact or the solver that moves them is
    worth a look, a rounder pole (not a lattice sphere) would move them
    towards Hertz."""
    r = collision
    assert r.facet == 16
    assert -0.45 < r.duration_error < -0.35
    assert 0.35 < r.force_error < 0.55
    assert 0.0 < r.facet_duration_error < 0.08


@pytest.mark.slow
def test_one_and_two_ranks_agree(collision):
    """The same collision on 2 ranks (the spheres on different ranks, the
    contact pairs across them): the same steps and, to the 10 digits the
    script prints, the same contact, rebound and energy."""
    two = run_spheres(CASE, 2)
    one = collision
    assert two.atoms == one.atoms and two.steps == one.steps
    assert two.contact_first == one.contact_first
    assert two.contact_duration == one.contact_duration
    for name in ("force_max", "restitution", "energy_drift", "energy_error"):
        assert getattr(two, name) == pytest.approx(getattr(one, name), rel=1e-9), name
    assert two.momentum_error < 1e-14
    assert two.mirror_error < 1e-12


@pytest.mark.slow
def test_command_line_prints_the_row_and_writes_json(tmp_path):
    """python -m esph spheres3d: one row per resolution and rank count, the
    legend, and the rows as JSON with the Hertz and facet references."""
    proc = subprocess.run([sys.executable, "-m", "esph", "spheres3d", "--nr", "6", "--out",
                           str(tmp_path)], capture_output=True, text=True, timeout=600,
                          env=clean_environment())
    assert proc.returncode == 0, proc.stderr
    row = next(line for line in proc.stdout.splitlines() if line.split()[:2] == ["6", "20"])
    assert "-40.0%" in row and "1824" in row
    rows = json.loads((tmp_path / "spheres3d.json").read_text())
    assert len(rows) == 1 and rows[0]["facet"] == 16 and rows[0]["nr"] == 6
    assert rows[0]["hertz_duration"] == pytest.approx(1.6211e-4, rel=1e-3)
    assert (tmp_path / "spheres3d_nr6_v20_exact_pk1.dat").exists()

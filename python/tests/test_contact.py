"""fix sph/contact: springs between particles of different bodies closer than
dx, F = k (dx - d), k = K1 K2/(K1 + K2) t in 2d, energy k (dx - d)^2/2;
and the colliding rings of examples/rings run through it."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import by_id, make_lammps, restart_round_trip, sph_header
from esph.problems import RINGS
from esph.runner import run_mpi, run_script

DX = 1.0e-3
T = 1.0e-3
E1, E2, NU = 1.0e9, 3.0e9, 0.3


def bulk(E, nu):
    return E / (3.0 * (1.0 - 2.0 * nu))


def two_blocks(lmp, shift=(-0.3, 0.37), fix="fix contact all sph/contact 0.001 thickness 0.001",
               seed=3, same_body=False):
    """Block A (type 1, molecule 1) and block B (type 2, molecule 2) of 4 x 3
    particles, B shifted so that several pairs across the gap are closer than
    dx; both jiggled so that the pair distances are all different.  As one
    body (same_body), B's shift moves reference partners apart by up to
    0.24 dx before the partners are built, which the skin must cover."""
    head = sph_header("-1 10 -2 6", DX, extra="comm_modify vel yes\n", types=2, map_array=False)
    lmp.commands_string(head + f"""
        region a block 0 4 0 3 INF INF
        region b block 4 8 0 3 INF INF
        create_atoms 1 region a
        create_atoms 2 region b
        group a type 1
        group b type 2
        displace_atoms b move {shift[0]} {shift[1]} 0.0 units lattice
        set group all volume {DX * DX * T}
        set group all mass {1000 * DX * DX * T}
        set group a mol 1
        set group b mol {1 if same_body else 2}
        pair_style sph/icb {1.2 * DX} stress pk1
        pair_coeff 1 1 {E1} {NU}
        pair_coeff 2 2 {E2} {NU}
        neighbor {(0.6 if same_body else 0.3) * DX} bin
        {fix}
        fix_modify contact energy yes
        thermo_style custom step pe
        run 0
    """)
    n = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    rng = np.random.default_rng(seed)
    x[:n, :2] += rng.uniform(-0.08, 0.08, size=(n, 2)) * DX
    v = lmp.numpy.extract_atom("v")
    v[:n, :2] = rng.uniform(-1.0, 1.0, size=(n, 2))


def expected_contact(x, mol, types, v, mass, damping=0.0):
    """Contact forces and energy by the formula, pair by pair."""
    K = {1: bulk(E1, NU), 2: bulk(E2, NU)}
    f = np.zeros_like(x)
    energy = 0.0
    pairs = 0
    for i in range(len(x)):
        for j in range(i + 1, len(x)):
            if mol[i] == mol[j]:
                continue
            d = x[i] - x[j]
            r = np.linalg.norm(d)
            if r >= DX:
                continue
            k = K[types[i]] * K[types[j]] / (K[types[i]] + K[types[j]]) * T
            fpair = k * (DX - r) / r
            if damping:
                meff = mass[i] * mass[j] / (mass[i] + mass[j])
                fpair -= 2 * damping * np.sqrt(k * meff) * np.dot(v[i] - v[j], d) / r ** 2
                fpair = max(fpair, 0.0)
            f[i] += fpair * d
            f[j] -= fpair * d
            energy += 0.5 * k * (DX - r) ** 2
            pairs += 1
    return f, energy, pairs


def contact_forces(lmp, fix_line):
    """The fix's share of the forces: with it minus without it."""
    lmp.command("run 0")
    with_fix = by_id(lmp, "f")
    energy = lmp.numpy.extract_fix("contact", 0, 0)
    pairs = lmp.numpy.extract_fix("contact", 0, 1, 0)
    lmp.command("unfix contact")
    lmp.command("run 0")
    without = by_id(lmp, "f")
    lmp.command(fix_line)
    lmp.command("fix_modify contact energy yes")
    return with_fix - without, energy, pairs


def atoms(lmp):
    return (by_id(lmp, "x")[:, :2], by_id(lmp, "molecule"), by_id(lmp, "type"),
            by_id(lmp, "v")[:, :2], by_id(lmp, "rmass"))


@pytest.mark.parametrize("damping", [0.0, 0.7])
def test_forces_and_energy_equal_the_formula(damping):
    fix = f"fix contact all sph/contact 0.001 thickness 0.001 damping {damping}"
    lmp = make_lammps()
    two_blocks(lmp, fix=fix)
    x, mol, types, v, mass = atoms(lmp)
    got, energy, pairs = contact_forces(lmp, fix)
    lmp.close()
    want, want_energy, want_pairs = expected_contact(x, mol, types, v, mass, damping)
    assert want_pairs >= 4                      # the blocks do touch
    assert pairs == want_pairs
    scale = np.abs(want).max()
    assert np.abs(got[:, :2] - want).max() < 1e-9 * scale
    assert energy == pytest.approx(want_energy, rel=1e-12)
    # Newton's third law: the contact forces add up to zero
    assert np.abs(got.sum(axis=0)).max() < 1e-12 * scale


def test_particles_of_one_body_never_touch():
    lmp = make_lammps()
    two_blocks(lmp, same_body=True)
    x, mol, types, v, mass = atoms(lmp)
    got, energy, pairs = contact_forces(lmp, "fix contact all sph/contact 0.001 thickness 0.001")
    lmp.close()
    close = [np.linalg.norm(x[i] - x[j]) < DX for i in range(len(x)) for j in range(i)]
    assert any(close)                             # there are close pairs, but one body
    assert np.abs(got).max() == 0.0
    assert energy == 0.0 and pairs == 0


def test_force_is_minus_the_gradient_of_the_contact_energy():
    lmp = make_lammps()
    two_blocks(lmp)
    x, mol, types, v, mass = atoms(lmp)
    got, energy, pairs = contact_forces(lmp, "fix contact all sph/contact 0.001 thickness 0.001")
    want, _, _ = expected_contact(x, mol, types, v, mass)
    i_id = int(np.argmax(np.linalg.norm(want, axis=1))) + 1
    xs = lmp.numpy.extract_atom("x")
    i = int(np.flatnonzero(lmp.numpy.extract_atom("id")[:lmp.get_natoms()] == i_id)[0])
    h = 1.0e-6 * DX
    for a in range(2):
        e = []
        for sign in (1, -1):
            xs[i, a] += sign * h
            lmp.command("run 0")
            e.append(lmp.numpy.extract_fix("contact", 0, 0))
            xs[i, a] -= sign * h
        assert got[i_id - 1, a] == pytest.approx(-(e[0] - e[1]) / (2 * h), rel=1e-6)
    lmp.close()


def test_contact_energy_is_part_of_the_minimised_energy():
    """minimize sees the contact energy (fix_modify energy yes): two free,
    overlapping blocks are pushed apart until the contact energy, which falls
    quadratically with the last overlap, has all but vanished."""
    lmp = make_lammps()
    two_blocks(lmp, shift=(-0.5, 0.0))
    lmp.commands_string("fix rot all sph/rotation\nrun 0")
    start = lmp.numpy.extract_fix("contact", 0, 0)
    pe_start = lmp.get_thermo("pe")
    lmp.commands_string("min_style cg\nminimize 0.0 1.0e-10 5000 50000")
    energy = lmp.numpy.extract_fix("contact", 0, 0)
    pe_end = lmp.get_thermo("pe")
    lmp.close()
    assert start > 0.0 and pe_start >= start
    assert energy < 1e-6 * start
    assert pe_end < 1e-6 * pe_start


# dx = 5 mm leaves 2 layers through the 1 cm wall: too few for the quadratic
# gradient's least-squares fit (and for surface-corrected volumes), so these
# coarse rings run the paper's linear correction
RING = {"dx": 0.005, "v": 5.0, "tend": 0.0012, "every": 20, "grad": "linear"}


def ring_run(tmp_path, scheme="icb", **extra):
    variables = {**RING, "scheme": scheme, "outdir": str(tmp_path), "tag": "t", **extra}
    state = {}

    def grab(lmp):
        n = lmp.get_natoms()
        state["x"] = np.array(lmp.numpy.extract_atom("x")[:n, :2])
        state["mol"] = np.array(lmp.numpy.extract_atom("molecule")[:n])

    out = run_script(RINGS, variables, read=["v1", "v2", "px", "etotal", "e0"], inspect=grab)
    series = np.loadtxt(tmp_path / "rings_t.dat")
    return out.variables, series, state


def mirror_error(x, mol):
    """Largest distance between a ring-1 particle and the mirror image of the
    nearest ring-2 particle."""
    a = x[mol == 1]
    b = x[mol == 2] * [-1.0, 1.0]
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return d.min(axis=1).max()


@pytest.mark.slow
def test_icb_rings_conserve_energy_and_momentum_and_stay_mirror_symmetric(tmp_path):
    """Coarse rings (dx = 5 mm, 2 layers) into contact, stress pk1 (whose
    forces are the exact energy gradient; the paper's corotated measure is
    not, and does not conserve energy exactly).  Velocity Verlet's energy
    error is O(dt^2): a time step 4x smaller must cut the largest energy
    error over the run by about 16 (8..32 brackets it between first and
    third order), and it must be small against the energy exchanged.
    Momentum: pair forces cancel to round-off."""
    vals, series, state = ring_run(tmp_path, stress="pk1", every=5)
    _, series_fine, _ = ring_run(tmp_path, stress="pk1", every=5, dtfac=0.0625)
    # columns: step v1 v2 estrain econtact etotal px py fcontact ncontact overlap symx symy failed
    e0 = series[0, 5]
    assert series[:, 9].max() > 0                     # the rings touched
    assert series[:, 3].max() > 0.5 * e0              # and turned most of KE into strain
    mass_speed = 2.0 * e0 / RING["v"]                 # sum m |v| = 2 KE / v
    assert np.abs(series[:, 6]).max() < 1e-12 * mass_speed
    err = np.abs(series[:, 5] - e0).max() / e0
    err_fine = np.abs(series_fine[:, 5] - e0).max() / e0
    assert err < 1e-3
    assert 8.0 < err / err_fine < 32.0
    assert mirror_error(state["x"], state["mol"]) < 1e-9 * RING["dx"]


@pytest.mark.parametrize("scheme", ["icb", "ccbwat"])
@pytest.mark.slow
def test_ring_runs_agree_on_1_2_4_ranks(tmp_path, scheme):
    runs = [run_mpi(RINGS, {**RING, "scheme": scheme, "outdir": str(tmp_path), "tag": f"n{n}"},
                    n).variables for n in (1, 2, 4)]
    assert runs[0]["v1"] < RING["v"]                  # contact slowed ring 1 down
    for other in runs[1:]:
        assert other["v1"] == pytest.approx(runs[0]["v1"], rel=1e-10)
        assert other["energy_drift"] == pytest.approx(runs[0]["energy_drift"], rel=1e-6, abs=1e-12)


def colliding_blocks(lmp, run_style="verlet"):
    """The two blocks, overlapping by 0.2 dx, pressed together at 2 m/s."""
    two_blocks(lmp, shift=(-0.2, 0.0))
    lmp.commands_string(f"""
        velocity a set 2.0 0.0 0.0 units box
        velocity b set -2.0 0.0 0.0 units box
        fix rot all sph/rotation
        fix nve all nve
        timestep 2.0e-8
        run_style {run_style}
    """)


def test_restart_continuation_equals_uninterrupted(tmp_path):
    rst = tmp_path / "mid.restart"
    lmp = make_lammps()
    colliding_blocks(lmp)
    lmp.command("run 0")
    touched = lmp.numpy.extract_fix("contact", 0, 0)
    uninterrupted, continued = restart_round_trip(lmp, rst, 300, """
        comm_modify vel yes
        fix contact all sph/contact 0.001 thickness 0.001
        fix_modify contact energy yes
        fix rot all sph/rotation
        fix nve all nve
        run 300
    """)
    assert touched > 0.0
    assert np.abs(continued - uninterrupted).max() == 0.0


def test_respa_with_one_inner_step_follows_verlet():
    """run_style respa 2 1 with everything on the outer level is velocity
    Verlet: the contact forces must enter at that level, once per step."""
    runs = []
    for style in ("verlet", "respa 2 1 pair 2"):
        lmp = make_lammps()
        colliding_blocks(lmp, style)
        lmp.command("run 0")
        touched = lmp.numpy.extract_fix("contact", 0, 0)
        lmp.command("run 400")
        runs.append((by_id(lmp, "x"), touched))
        lmp.close()
    assert runs[0][1] > 0.0
    assert np.abs(runs[1][0] - runs[0][0]).max() < 1e-12


@pytest.mark.slow
def test_rings_driver_reports_the_collision(tmp_path):
    """esph.rings through a whole collision at dx = 5 mm.  The rings move
    rigidly until the nearest outer particles come closer than dx.  Those
    sit at angles +-pi/n off the axis on the outer circle (radius r, n
    particles), 2 dx + 2 r (1 - cos(pi/n)) apart at the start: contact
    starts at t = (dx + 2 r (1 - cos(pi/n)))/(2v), seen at the next output
    row.  They rebound slower than they came (energy left in vibrations),
    and the snapshot and energy plots are written."""
    from esph import plots, rings
    from esph.runner import read_dump
    case = rings.RingsCase(dx=0.005, tend=0.003, every=20, snap=0.001, stress="corotated",
                           grad="linear", volumes="cells")
    res = rings.run_rings(case, tmp_path)
    dt = case.tend / res.steps
    r = 0.1 - case.dx / 2
    n = round(2 * np.pi * r / case.dx)
    t_touch = (case.dx + 2 * r * (1 - np.cos(np.pi / n))) / (2 * case.v)
    assert t_touch <= res.contact_start <= t_touch + case.every * dt
    assert res.contact_end > res.contact_start
    assert 0.3 < res.restitution < 1.0
    assert res.momentum_error < 1e-12
    assert res.energy_error < 1e-3      # corotated measure: not exactly conservative
    assert res.t_fail != res.t_fail     # nan: ICB stays intact
    assert res.mirror_error < 1e-9      # particle-level mirror symmetry kept
    rings.energy_plot(res, tmp_path / "e.png")
    frames = [read_dump(p) for p in sorted(tmp_path.glob("rings_*.dump"))]
    plots.plot_snapshots(frames, tmp_path / "s.png", "test")
    assert (tmp_path / "e.png").stat().st_size > 1000
    assert (tmp_path / "s.png").stat().st_size > 1000


def test_ring_geometry_is_the_documented_one(tmp_path):
    """in.rings at dx = 2.5 mm: four circles of radius r_k = Ri + (k - 1/2) dx
    per ring with n_k = round(2 pi r_k/dx) particles each, volumes that add
    up to the ring area times t, one molecule ID per ring, ring 2 the mirror
    image of ring 1, and the outer surfaces one dx apart."""
    dx, t, ro, ri = 0.0025, 0.001, 0.1, 0.09
    got = {}

    def grab(lmp):
        n = lmp.get_natoms()
        got["x"] = np.array(lmp.numpy.extract_atom("x")[:n, :2])
        got["x0"] = np.array(lmp.numpy.extract_atom("x0")[:n, :2])
        got["vol"] = np.array(lmp.numpy.extract_atom("vfrac")[:n])
        got["mol"] = np.array(lmp.numpy.extract_atom("molecule")[:n])

    run_script(RINGS, {"dx": dx, "tend": 0.0, "outdir": str(tmp_path), "tag": "g"}, read=[],
               inspect=grab)
    radii = ri + (np.arange(4) + 0.5) * dx
    counts = np.round(2 * np.pi * radii / dx).astype(int)
    x, mol = got["x"], got["mol"]
    assert len(x) == 2 * counts.sum()
    assert np.array_equal(got["x0"], x)                     # the reference is the ring
    xc = ro + 0.5 * dx
    for ring, sign in ((1, -1.0), (2, 1.0)):
        sel = mol == ring
        r = np.hypot(x[sel, 0] - sign * xc, x[sel, 1])
        k = np.argmin(np.abs(r[:, None] - radii[None, :]), axis=1)
        assert np.abs(r - radii[k]).max() < 1e-12
        assert np.array_equal(np.bincount(k, minlength=4), counts)
        assert got["vol"][sel].sum() == pytest.approx(np.pi * (ro ** 2 - ri ** 2) * t, rel=1e-12)
    assert mirror_error(x, mol) < 1e-12
    gap = np.linalg.norm(x[mol == 1][:, None, :] - x[mol == 2][None, :, :], axis=2).min()
    rout = radii[-1]
    assert gap == pytest.approx(2 * dx + 2 * rout * (1 - np.cos(np.pi / counts[-1])), rel=1e-9)

"""set_sph_volumes: surface-consistent particle volumes.  The particle sum
sum_i V_i p(X_i) must be the exact integral of every quadratic p over the
body, on rectangles, boxes, L-shapes, notched and holed bodies (faces on
lattice planes, edges and corners included) and on concentric rings; the
plain cell volumes (the paper's) must miss it by the midpoint rule's error.
Integrals come from the body's exact geometry (cells), not from the code."""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from conftest import input_head, make_lammps, sph_header

DX = 1.0e-3
T = 2.0e-3          # 2d thickness
RHO = 1200.0


def cells_integrals(cells, dim, thickness):
    """Exact integrals of the monomials of degree <= 2 over a union of unit
    lattice cells of size DX centred at `cells` (an (n, dim) array)."""
    # over one cell [c - DX/2, c + DX/2]: int 1 = DX, int x = c DX,
    # int x^2 = (c^2 + DX^2/12) DX; products factorise per axis
    out = {}
    for powers in monomials(dim):
        total = 0.0
        for c in cells:
            term = 1.0
            for a, p in enumerate(powers):
                term *= {0: DX, 1: c[a] * DX, 2: (c[a] ** 2 + DX ** 2 / 12.0) * DX}[p]
            total += term
        out[powers] = total * (thickness if dim == 2 else 1.0)
    return out


def monomials(dim):
    return [p for p in itertools.product(range(3), repeat=dim) if sum(p) <= 2]


def particle_sums(lmp, dim):
    n = lmp.get_natoms()
    order = np.argsort(lmp.numpy.extract_atom("id")[:n])
    X = np.array(lmp.numpy.extract_atom("x0")[:n])[order][:, :dim]
    V = np.array(lmp.numpy.extract_atom("vfrac")[:n])[order]
    m = np.array(lmp.numpy.extract_atom("rmass")[:n])[order]
    sums = {p: float(np.sum(V * np.prod(X ** np.array(p), axis=1))) for p in monomials(dim)}
    return sums, X, V, m


def lattice_body(dim, keep, nbox, volume_args="", group="all"):
    """Atoms on the cell centres (i + 1/2) DX of an nbox lattice for which
    keep(i, j, k) is true; volumes by set_sph_volumes."""
    lmp = make_lammps()
    zrange = "-0.5 0.5" if dim == 2 else f"0 {nbox[2]}"
    lattice = f"{'sq' if dim == 2 else 'sc'} {DX} origin 0.5 0.5 {0.0 if dim == 2 else 0.5}"
    lmp.commands_string(input_head(dim, f"f f {'p' if dim == 2 else 'f'}", lattice,
                                   f"0 {nbox[0]} 0 {nbox[1]} {zrange} units lattice",
                                   map_array=False))
    cells = []
    for idx in itertools.product(*(range(nbox[a]) for a in range(dim))):
        if keep(*idx):
            c = [(i + 0.5) * DX for i in idx]
            cells.append(c)
            z = c[2] if dim == 3 else 0.0
            lmp.command(f"create_atoms 1 single {c[0]} {c[1]} {z} units box")
    lmp.commands_string(f"""
        set group all mol 1
        set group all volume 1.0
        set group all mass {RHO}
    """)
    thickness = f"thickness {T}" if dim == 2 else ""
    lmp.command(f"set_sph_volumes {group} lattice {DX} {thickness} {volume_args}")
    return lmp, np.array(cells)


def filled_block(nx, ny, mol_setup="set group all mol 1"):
    """A 2d block of nx x ny particles on the cell centres, volumes unset."""
    lmp = make_lammps()
    lmp.commands_string(sph_header(f"0 {nx} 0 {ny}", DX, boundary="f f p", map_array=False) + f"""
        create_atoms 1 box
        {mol_setup}
        set group all volume {DX * DX * T}
        set group all mass 1.0
    """)
    return lmp


SHAPES_2D = {
    "rectangle": ((10, 4), lambda i, j: True),
    "L-shape": ((12, 10), lambda i, j: i < 5 or j < 4),
    "notch": ((14, 9), lambda i, j: not (5 <= i < 9 and j >= 5)),
    "hole": ((14, 12), lambda i, j: not (4 <= i < 9 and 4 <= j < 8)),
    "thin 3": ((9, 3), lambda i, j: True),
}
SHAPES_3D = {
    "box": ((7, 4, 3), lambda i, j, k: True),
    "L-box": ((8, 7, 4), lambda i, j, k: i < 4 or j < 3),
    "holed box": ((9, 9, 4), lambda i, j, k: not (3 <= i < 6 and 3 <= j < 6)),
}


def assert_exact(lmp, cells, dim):
    sums, X, V, m = particle_sums(lmp, dim)
    exact = cells_integrals(cells, dim, T)
    scale = exact[(0,) * dim]
    for p, value in exact.items():
        size = scale * max(1.0, float(np.max(np.abs(cells))) ** sum(p))
        assert sums[p] == pytest.approx(value, rel=0, abs=1e-12 * size), p
    # density stays uniform: m = rho V for the mass set before
    np.testing.assert_allclose(m / V, RHO, rtol=1e-12)
    return V


@pytest.mark.parametrize("name", list(SHAPES_2D))
def test_2d_shapes_integrate_every_quadratic_exactly(name):
    nbox, keep = SHAPES_2D[name]
    lmp, cells = lattice_body(2, keep, nbox + (1,))
    V = assert_exact(lmp, cells, 2)
    assert V.min() > 0
    lmp.close()


@pytest.mark.parametrize("name", list(SHAPES_3D))
def test_3d_shapes_integrate_every_quadratic_exactly(name):
    nbox, keep = SHAPES_3D[name]
    lmp, cells = lattice_body(3, keep, nbox)
    assert_exact(lmp, cells, 3)
    lmp.close()


def test_plain_cells_miss_the_second_moment_by_the_midpoint_error():
    """correction none gives dx^2 t per particle: the midpoint rule, short
    by H h^2/12 in int y^2 -- the error the correction removes."""
    nbox, keep = SHAPES_2D["rectangle"]
    lmp, cells = lattice_body(2, keep, nbox + (1,), volume_args="correction none")
    sums, X, V, m = particle_sums(lmp, 2)
    np.testing.assert_allclose(V, DX * DX * T, rtol=1e-14)
    exact = cells_integrals(cells, 2, T)
    W, H = nbox[0] * DX, nbox[1] * DX
    assert exact[(0, 2)] - sums[(0, 2)] == pytest.approx(W * H * DX ** 2 / 12 * T, rel=1e-9)
    lmp.close()


def test_weights_of_a_rectangle_are_the_end_corrections():
    """Inside the third layer the volume is the plain cell; the outermost
    three layers of a face get 1 + 1/12, 1 - 1/8, 1 + 1/24 (added at corners)."""
    lmp, cells = lattice_body(2, lambda i, j: True, (10, 8, 1))
    sums, X, V, m = particle_sums(lmp, 2)
    c = [1 / 12, -1 / 8, 1 / 24, 0.0]
    ix = np.rint(X[:, 0] / DX - 0.5).astype(int)
    iy = np.rint(X[:, 1] / DX - 0.5).astype(int)
    expect = 1 + np.array([c[min(i, 3)] + c[min(9 - i, 3)] + c[min(j, 3)] + c[min(7 - j, 3)]
                           for i, j in zip(ix, iy)])
    np.testing.assert_allclose(V / (DX * DX * T), expect, rtol=1e-13)
    lmp.close()


def test_density_keyword_sets_the_mass():
    lmp, cells = lattice_body(2, lambda i, j: True, (6, 5, 1), volume_args="density 500")
    sums, X, V, m = particle_sums(lmp, 2)
    np.testing.assert_allclose(m, 500.0 * V, rtol=1e-14)
    lmp.close()


def test_bodies_are_told_apart_by_molecule():
    """Two blocks side by side, one lattice spacing apart, are two bodies:
    each gets its own surface corrections at the faces that touch."""
    lmp = filled_block(10, 4, mol_setup="region left block 0 5 INF INF INF INF\n"
                       "group left region left\nset group all mol 2\nset group left mol 1")
    lmp.command(f"set_sph_volumes all lattice {DX} thickness {T}")
    sums, X, V, m = particle_sums(lmp, 2)
    left = X[:, 0] < 5 * DX
    for side in (left, ~left):
        cells = X[side]
        exact = cells_integrals(cells, 2, T)
        assert float(np.sum(V[side] * X[side, 0] ** 2)) == pytest.approx(exact[(2, 0)], rel=1e-12)
    lmp.close()


def test_thin_rows_are_reported():
    """A part only 2 particles thick cannot be corrected: say so."""
    lmp = filled_block(10, 2)
    lmp.command(f"set_sph_volumes all lattice {DX} thickness {T}")
    n = lmp.get_natoms()
    V = np.array(lmp.numpy.extract_atom("vfrac")[:n])
    # along y nothing is corrected, along x the ends are
    assert np.isclose(V.min(), DX * DX * T * (1 - 1 / 8))
    lmp.close()


def ring_body(nlayer, r_in, centre=(0.01, -0.02)):
    """Concentric circles r_k = r_in + (k + 1/2) DX with n_k = round(2 pi r_k / DX)."""
    lmp = make_lammps()
    lmp.commands_string("""
        units si
        dimension 2
        boundary f f p
        atom_style sph/elastic
        region box block -0.1 0.1 -0.1 0.1 -0.001 0.001 units box
        create_box 1 box
    """)
    layers = create_circles(lmp, nlayer, r_in, centre, 0.0)
    return lmp, layers


def create_circles(lmp, nlayer, r_in, centre, z):
    """Circles r_k = r_in + (k + 1/2) DX about centre in the plane z, n_k =
    round(2 pi r_k / DX) atoms each, one body, unit volumes and masses;
    returns [(r_k, n_k)]."""
    layers = []
    for k in range(nlayer):
        r = r_in + (k + 0.5) * DX
        n = round(2 * math.pi * r / DX)
        layers.append((r, n))
        for m in range(n):
            th = 2 * math.pi * (m + 0.3) / n
            lmp.command(f"create_atoms 1 single {centre[0] + r * math.cos(th)} "
                        f"{centre[1] + r * math.sin(th)} {z} units box")
    lmp.commands_string("""
        set group all mol 1
        set group all volume 1.0
        set group all mass 1.0
    """)
    return layers


@pytest.mark.parametrize("nlayer", [3, 5, 10])
def test_rings_integrate_every_quadratic_exactly(nlayer):
    centre = (0.01, -0.02)
    r_in = 0.03
    lmp, layers = ring_body(nlayer, r_in, centre)
    lmp.command(f"set_sph_volumes all polar {DX} {centre[0]} {centre[1]} thickness {T} density 7")
    sums, X, V, m = particle_sums(lmp, 2)
    a, b = r_in, r_in + nlayer * DX
    area = math.pi * (b * b - a * a)
    # moments about the centre: int 1, int x', int y', int x'^2 = int y'^2, int x' y'
    xr, yr = X[:, 0] - centre[0], X[:, 1] - centre[1]
    second = math.pi * (b ** 4 - a ** 4) / 4
    assert np.sum(V) == pytest.approx(area * T, rel=1e-12)
    assert abs(np.sum(V * xr)) < 1e-12 * area * T * b
    assert abs(np.sum(V * yr)) < 1e-12 * area * T * b
    assert np.sum(V * xr * xr) == pytest.approx(second * T, rel=1e-12)
    assert np.sum(V * yr * yr) == pytest.approx(second * T, rel=1e-12)
    assert abs(np.sum(V * xr * yr)) < 1e-12 * second * T
    np.testing.assert_allclose(m, 7 * V, rtol=1e-14)
    lmp.close()



def ring_volumes(lmp):
    n = lmp.get_natoms()
    tags = np.array(lmp.numpy.extract_atom("id")[:n])
    return dict(zip(tags.tolist(), np.array(lmp.numpy.extract_atom("vfrac")[:n]).tolist()))


def test_a_quarter_ring_between_mirror_planes_gets_the_full_rings_volumes(tmp_path):
    """A quarter model of a ring (x, y >= 0, plus the mirror atoms of the
    symmetry planes x = 0 and y = 0, 3.5 layers deep): each circle is an
    evenly spaced arc, whose atoms get the volumes they have in the full
    ring, so that the mirrored body integrates every quadratic exactly.
    Warned, as a free end of an arc would not be corrected; a circle that
    is neither one even arc nor evenly filled is an error."""
    full, _ = ring_body(8, 0.02, centre=(0.0, 0.0))
    full.command(f"set_sph_volumes all polar {DX} 0.0 0.0 thickness {T} density 7")
    want = ring_volumes(full)
    full.close()
    quarter, _ = ring_body(8, 0.02, centre=(0.0, 0.0))
    log = tmp_path / "log.lammps"
    quarter.command(f"log {log}")
    quarter.commands_string(f"""
        region farx block INF {-3.5 * DX} INF INF INF INF units box
        region fary block INF INF INF {-3.5 * DX} INF INF units box
        delete_atoms region farx compress no
        delete_atoms region fary compress no
        set_sph_volumes all polar {DX} 0.0 0.0 thickness {T} density 7
    """)
    got = ring_volumes(quarter)
    assert 0.25 * len(want) < len(got) < 0.5 * len(want)
    for tag, volume in got.items():
        assert volume == pytest.approx(want[tag], rel=1e-13)
    # one atom moved along its circle: no longer an even arc
    x = quarter.numpy.extract_atom("x0")
    r = math.hypot(x[0, 0], x[0, 1])
    th = math.atan2(x[0, 1], x[0, 0]) + 0.01
    x[0, 0], x[0, 1] = r * math.cos(th), r * math.sin(th)
    with pytest.raises(Exception, match="atoms on the circle of radius .* are neither"):
        quarter.command(f"set_sph_volumes all polar {DX} 0.0 0.0 thickness {T} density 7")
    quarter.close()
    assert "circles are evenly spaced arcs, not full circles" in log.read_text()


def tube_body(nlayer, r_in, nz, periodic=False, centre=(0.004, -0.003)):
    """A 3d tube: the circles of ring_body in nz planes z = (m + 1/2) DX."""
    lmp = make_lammps()
    lmp.commands_string(f"""
        units si
        dimension 3
        boundary f f {'p' if periodic else 'f'}
        atom_style sph/elastic
        region box block -0.05 0.05 -0.05 0.05 0.0 {nz * DX} units box
        create_box 1 box
    """)
    for m in range(nz):
        create_circles(lmp, nlayer, r_in, centre, (m + 0.5) * DX)
    return lmp


@pytest.mark.parametrize("periodic", [False, True])
def test_tubes_integrate_every_quadratic_exactly(periodic):
    """3d polar volumes: circles in planes along z, corrected through the
    wall and at the free ends along z (none across a periodic z), exact
    for every quadratic over the tube r_in < r < r_out, 0 < z < L (with a
    periodic z, for every quadratic that is periodic, so not z^2)."""
    centre, r_in, nlayer, nz = (0.004, -0.003), 0.012, 4, 5
    lmp = tube_body(nlayer, r_in, nz, periodic, centre)
    lmp.command(f"set_sph_volumes all polar {DX} {centre[0]} {centre[1]} density 7")
    n = lmp.get_natoms()
    X = np.array(lmp.numpy.extract_atom("x0")[:n])
    V = np.array(lmp.numpy.extract_atom("vfrac")[:n])
    m = np.array(lmp.numpy.extract_atom("rmass")[:n])
    lmp.close()
    a, b, length = r_in, r_in + nlayer * DX, nz * DX
    x, y, z = X[:, 0] - centre[0], X[:, 1] - centre[1], X[:, 2]
    ring = math.pi * (b * b - a * a)
    second = math.pi * (b ** 4 - a ** 4) / 4          # int x'^2 dA = int y'^2 dA
    exact = {"1": ring * length, "x": 0.0, "y": 0.0, "z": ring * length ** 2 / 2,
             "xx": second * length, "yy": second * length, "zz": ring * length ** 3 / 3,
             "xy": 0.0, "xz": 0.0, "yz": 0.0}
    fields = {"1": np.ones(n), "x": x, "y": y, "z": z, "xx": x * x, "yy": y * y, "zz": z * z,
              "xy": x * y, "xz": x * z, "yz": y * z}
    scale = ring * length * max(b, length) ** 2
    for name, field in fields.items():
        if periodic and name == "zz":
            continue        # not a periodic field: the midpoint rule in z is exact for z
        assert abs(np.sum(V * field) - exact[name]) < 1e-12 * scale, name
    np.testing.assert_allclose(m, 7 * V, rtol=1e-14)
    corrected = not periodic
    assert abs(V.max() / V.min() - 1) > 0.05        # corrected through the wall, always
    # the second circle of the wall (radial weight 1 - 1/8 + 1/24) in the end
    # plane (axial + 1/12) and the next (axial - 1/8), or no axial correction
    circle = np.isclose(np.hypot(x, y), a + 1.5 * DX)
    end, next_ = V[circle & np.isclose(z, 0.5 * DX)], V[circle & np.isclose(z, 1.5 * DX)]
    assert end.size == next_.size > 0
    want = (1 - 1 / 12 + 1 / 12) / (1 - 1 / 12 - 1 / 8) if corrected else 1.0
    np.testing.assert_allclose(end / next_, want, rtol=1e-12)

BAD = [
    # (commands before, the command, words the error must contain)
    ("", "set_sph_volumes all lattice 0.001", "thickness"),
    ("", "set_sph_volumes all lattice 0.0015 thickness 0.001", "not on a lattice"),
    ("", "set_sph_volumes all cubic 0.001 thickness 0.001", "use lattice or polar"),
    ("", "set_sph_volumes all lattice -1 thickness 0.001", "must be > 0"),
    ("", "set_sph_volumes all lattice 0.001 thickness 0.001 correction maybe", "surface or none"),
    ("", "set_sph_volumes all lattice 0.001 thickness 0.001 colour red", "Unknown set_sph_volumes"),
    ("create_atoms 1 single 0.0005 0.0005 0 units box\nset group all mol 1",
     "set_sph_volumes all lattice 0.001 thickness 0.001", "same lattice site"),
    ("", "set_sph_volumes all polar 0.001 0 0 thickness 0.001", "not on a circle"),
    ("pair_style sph/icb 0.0012 stress pk1\npair_coeff * * 1e9 0\nrun 0",
     "set_sph_volumes all lattice 0.001 thickness 0.001", "already built"),
]


@pytest.mark.parametrize("before, command, words", BAD)
def test_bad_input_is_a_clear_error(before, command, words):
    lmp = filled_block(6, 4)
    for line in filter(None, before.split("\n")):
        lmp.command(line)
    with pytest.raises(Exception, match=words):
        lmp.command(command)
    lmp.close()


@pytest.mark.parametrize("nz", [4, 5])
def test_a_periodic_length_below_two_kernel_supports_is_an_error(nz):
    """Across a periodic length under two supports (4.8 spacings at h =
    1.2 dx) an atom is its neighbours' partner through two images, of which
    the partner list keeps one: the stress-free tube of 4 planes had
    reference forces of 1e5 N, silently one-sided.  Refused; 5 planes are
    stress-free."""
    lmp = tube_body(3, 0.012, nz, periodic=True)
    lmp.commands_string(f"""
        set_sph_volumes all polar {DX} 0.004 -0.003 density 1000
        pair_style sph/icb {1.2 * DX}
        pair_coeff * * 1e9 0.3
        neighbor {0.5 * DX} bin
    """)
    if nz == 4:
        with pytest.raises(Exception, match="shorter than twice the SPH kernel support"):
            lmp.command("run 0")
    else:
        lmp.command("run 0")
        f = np.array(lmp.numpy.extract_atom("f")[:lmp.get_natoms()])
        assert np.abs(f).max() < 1e-6 * 1e9 * DX * DX
    lmp.close()


@pytest.mark.slow
def test_quarter_ring_volumes_are_the_same_on_1_and_2_ranks(tmp_path):
    """The arcs' angles meet on one rank per circle (a rendezvous), not on
    every rank: the quarter ring of the test above, whose arcs the ranks'
    boundary x = 0 cuts, gets the same volumes (masses at density 7) on 1
    and 2 ranks, and an arc that is not even is the same error on both."""
    from esph.runner import RunError, run_mpi
    atoms = []
    for k in range(8):
        r = 0.02 + (k + 0.5) * DX
        n = round(2 * math.pi * r / DX)
        for m in range(n):
            th = 2 * math.pi * (m + 0.3) / n
            if r * math.cos(th) > -3.5 * DX and r * math.sin(th) > -3.5 * DX:
                atoms.append((r * math.cos(th), r * math.sin(th)))
    head = """units si
dimension 2
boundary f f p
atom_style sph/elastic
atom_modify map array
region box block -0.1 0.1 -0.1 0.1 -0.001 0.001 units box
create_box 1 box
"""
    singles = "".join(f"create_atoms 1 single {x!r} {y!r} 0.0 units box\n" for x, y in atoms)
    tail = f"""set group all mol 1
set group all volume 1.0
set group all mass 1.0
set_sph_volumes all polar {DX} 0.0 0.0 thickness {T} density 7
write_dump all custom masses.${{nprocs}} x y mass modify format float %.17g
print "RESULT done 1"
"""
    script = tmp_path / "in.quarter"
    script.write_text(head + singles + tail)
    masses = {}
    for n in (1, 2):
        run_mpi(script, {"nprocs": n}, n)
        rows = np.loadtxt(tmp_path / f"masses.{n}", skiprows=9)
        masses[n] = rows[np.lexsort((rows[:, 1], rows[:, 0]))]
    assert len(masses[1]) == len(atoms)
    np.testing.assert_array_equal(masses[2], masses[1])
    # one atom moved along its circle: no longer an even arc
    r, th = math.hypot(*atoms[0]), math.atan2(atoms[0][1], atoms[0][0]) + 0.01
    moved = f"create_atoms 1 single {r * math.cos(th)!r} {r * math.sin(th)!r} 0.0 units box\n"
    script.write_text(head + moved + "".join(singles.splitlines(True)[1:]) + tail)
    for n in (1, 2):
        with pytest.raises(RunError, match="atoms on the circle of radius .* are neither"):
            run_mpi(script, {"nprocs": n}, n)

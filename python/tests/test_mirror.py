"""fix sph/mirror, the odd-mirror clamp of pair sph/icb: the mirror atoms at
x < 0 follow their sources with u(-x, y) = -u(x, y), carry no strain energy
and hand their forces to the sources.  Tests: exact patch test through the
clamp, forces = minus the gradient of the energy that is left, 1/2/4 ranks
with mirror and source atoms on different ranks, restart, beam accuracy."""
from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import (MIRROR_BAR_BODY, MIRROR_BAR_GROUPS, make_lammps, restart_round_trip, run_lmp,
                      sph_header)
from esph.beam import BeamCase, run_beam
from esph.runner import run_mpi

DX = 1.0e-3
T = 1.0e-3
E_MOD = 1.0e9


def mirror_bar_commands(nx=12, ny=4, depth=3, pair="stress pk1", nu=0.0):
    """A bar of nx x ny particles at x > 0 and `depth` mirror columns at x < 0."""
    return sph_header(f"-{depth} {nx} 0 {ny}", DX, map_array=False) + f"""
        create_atoms 1 box
        set group all volume {DX * DX * T}
        set group all mass {1000 * DX * DX * T}
        set group all mol 1
        pair_style sph/icb {1.2 * DX} {pair}
        pair_coeff * * {E_MOD} {nu}
        fix rot all sph/rotation
        neighbor {0.5 * DX} bin
        region left block INF 0.0 INF INF INF INF units box
        group mirror region left
        group body subtract all mirror
        fix clamp mirror sph/mirror x 0.0
        compute out all sph/elastic/atom stress strain
    """


def state(lmp):
    n = lmp.get_natoms()
    get = lambda name: np.array(lmp.numpy.extract_atom(name)[:n], dtype=float)
    return get("x0"), get("x"), get("f"), get("v")


@pytest.mark.parametrize("gradient", ["linear", "quadratic"])
@pytest.mark.parametrize("measure", ["corotated", "pk1"])
def test_uniform_stretch_is_exact_through_the_clamp(measure, gradient):
    """x = (1 + eps) X on the body (nu = 0): the mirror atoms land on the same
    affine field, so every body atom has the exact Green strain, all forces
    vanish except near the free end (atoms within two kernel supports of
    it), and those forces add up to the exact traction -P_xx A.  The clamp region is where a wrong sign, a wrong
    source or a counted mirror energy would show."""
    lmp = make_lammps()
    lmp.commands_string(mirror_bar_commands(pair=f"stress {measure} gradient {gradient}"))
    lmp.command("run 0")
    eps = 0.01
    n = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    x0 = lmp.numpy.extract_atom("x0")
    body = x0[:n, 0] > 0
    x[:n, 0][body] = (1 + eps) * x0[:n, 0][body]
    lmp.command("run 0")
    X0, X, F, V = state(lmp)
    strain = np.array(lmp.numpy.extract_compute("out", 1, 2)[:n])[:, 6:]
    lmp.close()

    mirror = X0[:, 0] < 0
    assert np.abs(X[mirror, 0] - (1 + eps) * X0[mirror, 0]).max() < 1e-15
    green_xx = eps + eps ** 2 / 2
    assert np.abs(strain[~mirror, 0] - green_xx).max() < 1e-10 * green_xx
    assert np.abs(strain[~mirror, 1:]).max() < 1e-10 * green_xx
    S = E_MOD * green_xx
    traction = ((1 + eps) * S if measure == "pk1" else S) * 4 * DX * T
    end = X0[:, 0] > 12 * DX - 2 * (2 * 1.2 * DX)
    assert np.abs(F[~end]).max() < 1e-10 * traction
    assert F[end, 0].sum() == pytest.approx(-traction, rel=1e-10)
    assert np.abs(F[end, 1].sum()) < 1e-10 * traction
    assert np.abs(V[mirror]).max() == 0.0


@pytest.mark.parametrize("gradient,hourglass", [("linear", 0.0), ("quadratic", 0.0),
                                                ("quadratic", 0.1)])
def test_forces_are_minus_the_gradient_of_the_body_energy(gradient, hourglass):
    """With pk1 the pair force is the exact energy gradient; the mirror
    constraint x_m = X_m - u_source must turn it into the gradient of the
    energy as a function of the body atoms alone (mirror atoms moved with
    their sources).  Central differences on atoms next to the clamp."""
    lmp = make_lammps()
    lmp.commands_string(mirror_bar_commands(nx=8, pair=f"stress pk1 gradient {gradient} "
                                                        f"hourglass {hourglass}"))
    lmp.commands_string("thermo_style custom step pe\nrun 0")
    n = lmp.get_natoms()
    x = lmp.numpy.extract_atom("x")
    x0 = np.array(lmp.numpy.extract_atom("x0")[:n])
    rng = np.random.default_rng(7)
    body = x0[:, 0] > 0
    x[:n, :2][body] += rng.uniform(-0.05, 0.05, size=(body.sum(), 2)) * DX
    lmp.command("run 0")
    force = np.array(lmp.numpy.extract_atom("f")[:n])
    h = 1.0e-7 * DX
    checked = 0
    for i in np.flatnonzero(body & (x0[:, 0] < 3 * DX)):
        for a in range(2):
            energies = []
            for sign in (1, -1):
                x[i, a] += sign * h
                lmp.command("run 0")
                energies.append(lmp.get_thermo("pe"))
                x[i, a] -= sign * h
            fd = -(energies[0] - energies[1]) / (2 * h)
            assert force[i, a] == pytest.approx(fd, rel=1e-5, abs=1e-6 * np.abs(force).max())
            checked += 1
    lmp.close()
    assert checked == 2 * 3 * 4


MPI_SCRIPT = sph_header("-3 12 0 4", extra="processors ${np} 1 1\ncomm_modify cutoff ${cut}\n",
                        map_array=False) + "create_atoms 1 box\n" + MIRROR_BAR_BODY + \
    MIRROR_BAR_GROUPS + """fix clamp mirror sph/mirror x 0.0
fix load tip addforce 0.0 -2.0 0.0
fix nve all nve
timestep 2.0e-8
compute ref all property/atom x0x x0y
variable uy atom y-c_ref[2]
compute tipdisp tip reduce ave v_uy
thermo_style custom step pe ke c_tipdisp
run 0
# rank boundaries between mirror and source atoms: x = -1.5, 0, 1.5 mm
variable c1 equal (-0.0015-xlo)/lx
variable c2 equal (0.0-xlo)/lx
variable c3 equal (0.0015-xlo)/lx
if "${np} == 2" then "balance 1.0 x ${c2}"
if "${np} == 4" then "balance 1.0 x ${c1} ${c2} ${c3}"
run 1500
print "RESULT tip_dv $(c_tipdisp:%.17g)"
print "RESULT pe $(pe:%.17g)"
"""


@pytest.mark.parametrize("stress", ["corotated", "pk1"])
@pytest.mark.slow
def test_mpi_ranks_agree_with_mirror_and_source_on_different_ranks(tmp_path, stress):
    """Rank boundaries at x = -1.5, 0 and 1.5 mm put mirror atoms and their
    sources on different ranks: positions go out by the fix's forward
    communication, forces come back by its reverse communication."""
    script = tmp_path / "in.mirror"
    script.write_text(MPI_SCRIPT)
    runs = [run_mpi(script, {"np": n, "cut": 0.008, "stress": stress}, n).variables
            for n in (1, 2, 4)]
    assert runs[0]["tip_dv"] < -1e-6    # the bar did bend
    for other in runs[1:]:
        assert other["tip_dv"] == pytest.approx(runs[0]["tip_dv"], rel=1e-10)
        assert other["pe"] == pytest.approx(runs[0]["pe"], rel=1e-10)


def test_source_beyond_the_ghost_cutoff_is_an_error(tmp_path):
    script = tmp_path / "in.mirror"
    script.write_text(MPI_SCRIPT)
    with pytest.raises(RuntimeError) as err:
        run_mpi(script, {"np": 4, "cut": 0.0, "stress": "pk1"}, 4)
    assert "is beyond the ghost cut-off" in str(err.value)
    assert "comm_modify cutoff" in str(err.value)


@pytest.mark.slow
def test_unmatched_mirror_is_the_same_error_on_several_ranks(tmp_path):
    """The pairing meets mirrors and candidate sources on the ranks of their
    region of space; a mirror without a source stops every rank with one
    error that names the same atom as on one rank (the first in the order
    of the ranks, then of their atoms)."""
    script = tmp_path / "in.mirror"
    script.write_text(MPI_SCRIPT.replace("sph/mirror x 0.0", "sph/mirror x 0.0002"))
    errors = []
    for n in (1, 2, 4):
        with pytest.raises(RuntimeError) as err:
            run_mpi(script, {"np": n, "cut": 0.008, "stress": "pk1"}, n)
        found = re.search(r"sph/mirror: atom (\d+) of group mirror at reference position "
                          r"\(([^)]*)\) has no source", str(err.value))
        assert found, str(err.value)[-2000:]
        errors.append(found.groups())
    assert errors[1] == errors[0] and errors[2] == errors[0]


def test_restart_continuation_equals_uninterrupted(tmp_path):
    """The fix keeps no state of its own: it pairs atoms again from their
    reference positions after read_restart."""
    rst = tmp_path / "mid.restart"
    dynamics = """
        region endzone block 0.011 INF INF INF INF INF units box
        group tip region endzone
        fix load tip addforce 0.0 -100.0 0.0
        fix nve all nve
        timestep 2.0e-8
    """
    lmp = make_lammps()
    lmp.commands_string(mirror_bar_commands(pair="stress corotated gradient quadratic"))
    lmp.commands_string(dynamics)
    uninterrupted, continued = restart_round_trip(
        lmp, rst, 300,
        "fix rot all sph/rotation\nfix clamp mirror sph/mirror x 0.0\n" + dynamics + "run 300")
    assert np.abs(uninterrupted[:, 1] - uninterrupted[0, 1]).max() > 1e-7   # it bent
    assert np.abs(continued - uninterrupted).max() == 0.0


@pytest.mark.slow
def test_mirror_clamp_removes_the_clamp_error_of_the_coarse_beam():
    """dx = 4 mm, Fy = -75 N, gradient quadratic.  The fixed clamp columns
    count their own strain energy and make the beam clamped about one dx
    behind x = 0: +3 L^2 dx / L^3 ~ +6 % at this spacing (studies/beam_error).
    The mirror clamp removes that term; what remains is the midpoint rule of
    the bending stiffness, 2d shear and the load point (each of order 1 % at
    4 mm), so the error must drop by more than 4 points and stay below 5 %.
    Damped dynamics reaches the same equilibrium as the minimiser."""
    common = dict(load=-75.0, dx=0.004, gradient="quadratic")
    fixed = run_beam(BeamCase(clamp="fixed", **common))
    mirror = run_beam(BeamCase(clamp="mirror", **common))
    damped = run_beam(BeamCase(clamp="mirror", route="dyn", **common))
    assert 0.0 < mirror.error_dv < 0.05
    assert fixed.error_dv - mirror.error_dv > 0.04
    assert damped.dv == pytest.approx(mirror.dv, rel=1e-3)


def tilted_clamp_script(mode: str, tilt: float = 0.0) -> str:
    """A 2d cantilever 0.2 x 0.02 m (dx = 2 mm) under its own weight, clamped
    on x = 0 by lattice mirror columns ('lattice') or by the images of
    create_sph_mirrors across the plane through the origin with normal
    (1, tilt) ('created'); volumes without surface correction (the images
    of a tilted plane are off the lattice)."""
    body = ("region domain block -3 100 0 10 -0.5 0.5 units lattice" if mode == "lattice"
            else "region domain block 0 100 0 10 -0.5 0.5 units lattice")
    if mode == "lattice":
        mirrors = ("region clampzone block INF 0.0 INF INF INF INF units box\n"
                   "group clamp region clampzone\ngroup body subtract all clamp\n"
                   "set_sph_volumes all lattice 0.002 thickness 0.001 density 1000 "
                   "correction none\n")
        clamp = "fix hold clamp sph/mirror x 0.0"
    else:
        mirrors = ("group body union all all\n"
                   "set_sph_volumes body lattice 0.002 thickness 0.001 density 1000 "
                   "correction none\n"
                   f"create_sph_mirrors body clamp plane 0 0 0 1 {tilt} 0 depth 0.0052\n")
        clamp = f"fix hold clamp sph/mirror plane 0 0 0 1 {tilt} 0"
    return sph_header("-4 101 -1 11", 0.002) + f"""
{body}
create_atoms 1 region domain
set group all mol 1
{mirrors}
pair_style sph/icb 0.0024 plane strain
pair_coeff * * 20e9 0.3 svk
neighbor 0.001 bin
{clamp}
fix g body sph/bodyforce 0.0 -6e4
fix_modify g energy yes
compute probe all sph/probe 0.2 0.01
thermo_style custom step pe c_probe[1][2]
min_style sph/newton
minimize 0 1e-8 100 1000
variable tip equal c_probe[1][2]
"""


def test_a_clamp_on_a_slightly_tilted_plane_is_the_lattice_clamp(tmp_path):
    """The general path of fix sph/mirror (images by create_sph_mirrors,
    pairing by reflection across a plane of any normal, volumes times the
    reflection's ratio, the tie in sph/newton) on a plane tilted by 1e-6
    rad: the mirror atoms move by at most 2e-8 m from the lattice columns,
    and the tip deflection agrees with the lattice mirror's to 1e-6."""
    tips = {}
    for mode in ("lattice", "created"):
        lmp = make_lammps()
        lmp.commands_string(tilted_clamp_script(mode, tilt=1e-6))
        tips[mode] = lmp.extract_variable("tip")
        lmp.close()
    assert tips["lattice"] < -0.01
    assert tips["created"] == pytest.approx(tips["lattice"], rel=1e-6)


def test_a_lattice_cut_at_a_slant_is_refused(tmp_path):
    """A plane tilted by 0.1 cuts the lattice's rows anywhere between 0 and
    a spacing from it: the first layer's cells overlap their images' there.
    Such clamps did not converge (a beam clamped on a cylinder with its
    lattice cut by the arc: +0.61 / +1.48 / +0.18 % at dx = 2 / 1 / 0.5 mm
    against the FE continuum), so they are refused, not run."""
    rc, out = run_lmp(tilted_clamp_script("created", tilt=0.1), tmp_path)
    assert rc != 0
    assert "from its source across the plane through (0, 0, 0)" in out
    assert "lay the body out in layers parallel to the surface" in out
    # the same plane along x is layered
    rc, out = run_lmp(tilted_clamp_script("created", tilt=0.0), tmp_path)
    assert rc == 0, out


def test_volumes_set_before_the_mirrors_are_warned(tmp_path):
    """set_sph_volumes before create_sph_mirrors corrected the clamped
    surface as a free one: create_sph_mirrors warns."""
    rc, out = run_lmp(tilted_clamp_script("created", tilt=0.0), tmp_path)
    assert rc == 0, out
    assert "already have volumes; if they come from set_sph_volumes" in out


def rotated_block_script(deg: float, solver: str = "sph/newton") -> str:
    """An 8 x 6 block (dx = 1 mm) turned by deg about the origin, sliding on
    two symmetry planes through the origin along its turned left and bottom
    faces (fix sph/mirror plane ... slip yes, images by create_sph_mirrors),
    pulled by a pressure on its far half's surface."""
    c, s = float(np.cos(np.radians(deg))), float(np.sin(np.radians(deg)))
    return sph_header("-20 20 -20 20") + f"""
region blk block 0 8 0 6 -0.5 0.5
create_atoms 1 region blk
set group all mol 1
set group all volume 1e-9
set group all mass 1e-6
displace_atoms all rotate 0 0 0 0 0 1 {deg} units box
reset_sph_reference all
group body union all all
pair_style sph/icb 0.0012 plane stress
pair_coeff * * 1e9 0.3
create_sph_mirrors body ml plane 0 0 0 {c!r} {s!r} 0 depth 0.0031
create_sph_mirrors body mb plane 0 0 0 {-s!r} {c!r} 0 depth 0.0031
fix sl ml sph/mirror plane 0 0 0 {c!r} {s!r} 0 slip yes
fix sb mb sph/mirror plane 0 0 0 {-s!r} {c!r} 0 slip yes
variable far atom x*{c!r}+y*{s!r}>0.004
group right variable far
fix pull right sph/traction surface pressure -1.0e6
fix_modify pull energy yes
min_style {solver}
minimize 0 1e-10 200 2000
"""


def body_displacements_in_block_frame(lmp, deg: float, nbody: int = 48):
    tag = np.array(lmp.gather_atoms("id", 0, 1))
    x = np.array(lmp.gather_atoms("x", 1, 3)).reshape(-1, 3)
    x0 = np.array(lmp.gather_atoms("x0", 1, 3)).reshape(-1, 3)
    body = tag <= nbody
    u = (x - x0)[body][np.argsort(tag[body])]
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return u @ np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]).T


def test_slip_planes_of_any_orientation_give_the_aligned_answer_under_newton():
    """Sliding on planes turned by 30 deg ties each mirror coordinate to
    both of its source's (T = I - 2 n n^T), which min_style sph/newton
    assembles as general ties.  The turned problem, turned back, is the
    aligned one (x and y planes, signed ties) to the solver's tolerance."""
    u = {}
    for deg in (0.0, 30.0):
        lmp = make_lammps()
        lmp.commands_string(rotated_block_script(deg))
        u[deg] = body_displacements_in_block_frame(lmp, deg)
        lmp.close()
    scale = np.abs(u[0.0]).max()
    assert scale > 1e-6
    assert np.abs(u[30.0] - u[0.0]).max() < 1e-9 * scale
    # the planes hold: the left column slides along y' only (x'-stretch
    # of the first layer, not a rigid shift), the bottom row along x'
    assert np.abs(u[0.0][:, 0]).min() < 0.1 * scale


def test_images_across_a_sphere_lie_on_the_ray_with_scaled_volumes(tmp_path):
    """create_sph_mirrors across a sphere (3d): each image lies on its
    source's ray at radius 2R - r, with the source's volume and mass times
    ((2R - r)/r)^2; fix sph/mirror then refuses the lattice the sphere cuts."""
    centre, radius, depth = np.array([-0.0195, 0.002, 0.002]), 0.0199, 0.0012
    setup = sph_header("-1 5 -1 5 -1 5", dim=3) + f"""
region cube block 0 4 0 4 0 4
create_atoms 1 region cube
set group all mol 1
set group all volume 1e-9
set group all mass 1e-6
group body union all all
create_sph_mirrors body m sphere {centre[0]} {centre[1]} {centre[2]} {radius} depth {depth}
"""
    lmp = make_lammps()
    lmp.commands_string(setup)
    tag = np.array(lmp.gather_atoms("id", 0, 1))
    x0 = np.array(lmp.gather_atoms("x0", 1, 3)).reshape(-1, 3)[np.argsort(tag)]
    vol = np.array(lmp.gather_atoms("vfrac", 1, 1))[np.argsort(tag)]
    mass = np.array(lmp.gather_atoms("rmass", 1, 1))[np.argsort(tag)]
    lmp.close()
    r = np.linalg.norm(x0[:64] - centre, axis=1)
    sources = np.nonzero(r - radius <= depth)[0]
    images = np.arange(64, len(x0))
    assert len(sources) == len(images) > 0
    rs = r[sources]
    expected = centre + (x0[sources] - centre) * ((2 * radius - rs) / rs)[:, None]
    assert np.abs(x0[images] - expected).max() < 1e-15
    ratio = ((2 * radius - rs) / rs) ** 2
    assert vol[images] == pytest.approx(1e-9 * ratio, rel=1e-14)
    assert mass[images] == pytest.approx(1e-6 * ratio, rel=1e-14)
    rc, out = run_lmp(setup + "pair_style sph/icb 0.0012\npair_coeff * * 1e9 0.3\n"
                      f"fix hold m sph/mirror sphere {centre[0]} {centre[1]} {centre[2]} "
                      f"{radius}\nrun 0\n", tmp_path)
    assert rc != 0 and "from its source across the sphere about" in out


@pytest.mark.slow
def test_created_images_are_the_same_on_1_and_2_ranks(tmp_path):
    """create_sph_mirrors makes each rank's images and moves them to the
    ranks that hold their positions (no rank gathers all images), and the
    default depth (3 spacings) comes from a rendezvous of the atoms near
    the surface.  A body above y = 0 split from its images by the ranks'
    boundary (processors 1 2 1): the same 3 layers of images, with the same
    masses, on 1 and 2 ranks."""
    from esph.runner import run_mpi
    script = tmp_path / "in.images"
    script.write_text(sph_header("-1 21 -10 10", 0.002, extra="processors 1 * 1\n") + """
region domain block 0 20 0 10 -0.5 0.5 units lattice
create_atoms 1 region domain
set group all mol 1
group body union all all
set group all volume 4e-9
set group all mass 4e-6
pair_style sph/icb 0.0024 plane strain
pair_coeff * * 20e9 0.3 svk
create_sph_mirrors body clamp plane 0 0.0 0 0 1 0
write_dump clamp custom images.${nprocs} x y mass mol proc modify format float %.17g
variable nclamp equal count(clamp)
print "RESULT nclamp ${nclamp}"
""")
    images = {}
    for n in (1, 2):
        assert run_mpi(script, {"nprocs": n}, n).variables["nclamp"] == 60    # 3 layers
        rows = np.loadtxt(tmp_path / f"images.{n}", skiprows=9)
        images[n] = rows[np.lexsort((rows[:, 1], rows[:, 0]))]
    assert images[1][:, 1].min() == pytest.approx(-0.005) and images[1][:, 1].max() < 0
    np.testing.assert_array_equal(images[2][:, :4], images[1][:, :4])
    assert (images[2][:, 4] == 0).all()    # made on rank 1, moved to rank 0 (y < 0)

"""Combinations of fixes and setups from a second hostile review (issue 32):
each case gave a silent wrong answer, a misleading message or no warning
before its fix; now a clear error, the right answer or a warning."""
from __future__ import annotations

import re

import pytest

from conftest import lattice_2d_script, make_lammps, run_lmp
from test_robustness import block_script, error_line, our_warnings

DX = 1.0e-3
T = 1.0e-3


def test_lattice_spacing_that_disagrees_with_the_atoms_is_an_error():
    """Half the atoms' spacing put every atom on the lattice, with volumes 4x
    too small and a warning that blamed a thin body."""
    lmp = make_lammps()
    lmp.commands_string(block_script(volume="unset", mass="unset"))
    with pytest.raises(Exception, match="spacing 0.0005 does not match the atoms of group all"):
        lmp.command(f"set_sph_volumes all lattice {DX / 2} thickness {T} density 1000")
    lmp.close()


def test_masses_kept_at_the_create_atoms_default_are_warned(tmp_path):
    """No density: m/V = 1/1 was kept, a density of 1 kg/m^3 that the density
    check let through (its bound was inclusive)."""
    script = block_script(volume="unset", mass="unset",
                          extra=f"set_sph_volumes all lattice {DX} thickness {T}\nrun 0\n")
    rc, out = run_lmp(script, tmp_path)
    assert rc == 0, error_line(out)
    assert "had create_atoms' volume 1 and mass 1" in out
    assert re.search(r"WARNING: Pair style sph/icb: atom \d+ has a reference density m/V = 1 kg", out)


def test_traction_on_a_mirror_plane_is_refused(tmp_path):
    """It applied half the requested force: the mirror carries the reaction."""
    extra = """
region clampzone block INF 3 INF INF INF INF units lattice
group clamp region clampzone
fix hold clamp sph/mirror x 0.003
fix t all sph/traction x 0.003 traction 1e6 0
run 0
"""
    script = block_script(pair_args="plane stress", extra=extra)
    rc, out = run_lmp(script, tmp_path)
    assert rc != 0
    assert "is the plane of fix hold sph/mirror, which is not a free surface" in error_line(out)


def test_bodies_created_inside_each_other_are_warned(tmp_path):
    """A second body created over the first one on a shifted lattice."""
    extra = """
lattice sq 0.001 origin 0.0 0.0 0.0
region second block 4 8 0 4 -0.5 0.5
create_atoms 1 region second
group second region second
set group second volume 1e-9
set group second mass 1e-6
set group second mol 2
run 0
"""
    rc, out = run_lmp(block_script(extra=extra), tmp_path)
    assert rc == 0, error_line(out)
    assert "have a particle of another body (molecule ID) nearer than 3/4" in out


def test_bodies_one_spacing_apart_are_not_warned(tmp_path):
    extra = """
region second block 6 12 0 4 -0.5 0.5 units lattice
group second region second
set group second mol 2
run 0
"""
    rc, out = run_lmp(block_script(extra=extra), tmp_path)
    assert rc == 0, error_line(out)
    assert not our_warnings(out), out


@pytest.mark.slow
def test_blow_up_is_caught_before_neighbor_binning(tmp_path):
    """1e9 N on a small body: the atoms flew kilometres in a step, and LAMMPS
    stopped on 'Too many neighbor bins' (or binned for minutes).  The run now
    stops when reference partners are ten kernel supports apart, with the
    time-step advice."""
    extra = """
region right block 11 INF INF INF INF INF units lattice
group right region right
fix push right addforce 1e9 0 0
fix i all nve
run 0
timestep $(0.25*v_dts)
run 200
"""
    rc, out = run_lmp(block_script(boundary="s s p", extra=extra), tmp_path, timeout=60)
    assert rc != 0
    err = error_line(out)
    assert "Too many neighbor bins" not in out
    assert "the run blew up" in err or "is inverted" in err, err


def test_advised_timestep_is_below_the_hourglass_limited_limit(tmp_path):
    """With strong hourglass springs the stable limit is below 0.25 h/c; the
    warning used to advise 0.25 h/c, the step already in use."""
    extra = "fix i all nve\nrun 0\ntimestep $(0.25*v_dts)\nrun 1\n"
    rc, out = run_lmp(block_script(pair_args="hourglass 5.0", extra=extra), tmp_path)
    warning = [ln for ln in out.splitlines() if "exceeds the stable limit" in ln]
    assert warning, out
    advised = float(re.search(r"use 'timestep ([0-9.e+-]+)' \(([0-9.]+) h/c\)", warning[0]).group(2))
    limit = float(re.search(r"stable limit of about ([0-9.]+) h/c", warning[0]).group(1))
    assert advised < limit < 0.25


def strip_model(lmp, box: str, before_clamp: str = "") -> None:
    """A 2d strip of the lattice box (spacing 1 mm, t = 1 mm, exact volumes,
    sph/icb plane stress, E = 1 GPa, nu = 0.3) and the group clamp of its
    atoms at x < 0; before_clamp runs between the pair style and the group."""
    from test_traction import lattice_2d
    lattice_2d(lmp, box)
    lmp.commands_string(f"""
        set group all mol 1
        set_sph_volumes all lattice {DX} thickness {T} density 1000
        pair_style sph/icb {1.2 * DX} plane stress
        pair_coeff * * 1e9 0.3
        neighbor {0.5 * DX} bin
        {before_clamp}
        region clampzone block INF 0.0 INF INF INF INF units box
        group clamp region clampzone
    """)


def clamped_tip(tmp_path, before_mirror: str) -> float:
    """Tip deflection of a mirror-clamped strip under an end traction, with
    some commands between the pair style and the fix sph/mirror."""
    from conftest import by_id
    lmp = make_lammps()
    strip_model(lmp, "-3 16 0 5", before_mirror)
    lmp.commands_string("""
        fix hold clamp sph/mirror x 0.0
        fix load all sph/traction x 0.016 traction 0.0 -1e5
        fix_modify load energy yes
        min_style sph/newton
        minimize 0 1e-10 50 100
    """)
    tip = (by_id(lmp, "x") - by_id(lmp, "x0"))[-1, 1]
    lmp.close()
    return tip


@pytest.mark.parametrize("command", ["write_data {dir}/before.data",
                                     "write_restart {dir}/before.restart"])
def test_writing_files_before_the_mirror_is_no_first_run(tmp_path, command):
    """write_data and write_restart initialise the pair style, whose
    partners fix then came before the mirror fix: it built the partners
    before the mirror copied its sources' volumes, and the run stopped
    saying the partners were built before the first run."""
    plain = clamped_tip(tmp_path, "")
    written = clamped_tip(tmp_path, command.format(dir=tmp_path))
    assert plain < 0.0
    assert written == plain


def test_periodic_box_remapped_before_the_first_run_is_refused(tmp_path):
    """change_box ... remap stretched the body and its periodic length but
    not its reference positions: the boundary particles carried -5.2e6 Pa
    where the exact answer is a uniform +1.35e6 Pa.  Refused, naming
    reset_sph_reference; after it, the remapped body is stress-free."""
    remap = "change_box all x scale 1.002 remap\n"
    script = block_script(boundary="p s p", extra=remap + "run 0\n")
    rc, out = run_lmp(script, tmp_path)
    assert rc != 0
    err = error_line(out)
    assert "The periodic box length in x is 0.012024 but was 0.012" in err
    assert "reset_sph_reference all" in err
    script = block_script(boundary="p s p", extra=remap + "reset_sph_reference all\nrun 0\n")
    rc, out = run_lmp(script, tmp_path)
    assert rc == 0, error_line(out)



PLATEN = lattice_2d_script("-3 19 0 7") + """
region left block -3 0 INF INF INF INF
region right block 16 19 INF INF INF INF
group left region left
group right region right
set group all mol 1
set_sph_volumes all lattice 0.001 thickness 0.001 density 1000
pair_style sph/icb 0.0012 plane stress
pair_coeff * * 1e9 0.3
neighbor 0.0005 bin
fix l left sph/mirror x 0.0
fix r right sph/mirror x 0.016 displace {u} 0.0
min_style sph/newton
minimize 0 1e-8 {iterations} 1000
"""


def test_platen_pushed_too_far_in_one_minimisation_is_refused_with_the_increments(tmp_path):
    """A 10 % platen compression in one minimisation put the mirror atoms
    inside the body's first layers: it ended inverted, and the message
    blamed St. Venant-Kirchhoff's compressive limit.  Refused, naming the
    increments; in those increments Newton reaches the state."""
    rc, out = run_lmp(PLATEN.format(u=-0.0016, iterations=20), tmp_path, timeout=120)
    assert rc != 0
    err = error_line(out)
    assert "Fix r sph/mirror pushes its surface 0.0016 into the body in one minimization" in err
    assert "in 4 increments of at most 0.0004" in err
    stepped = PLATEN.format(u="v_u", iterations=20).replace(
        "fix r right", "variable k loop 4\nvariable u equal -0.0004*v_k\nfix r right").replace(
        "minimize 0 1e-8 20 1000",
        "label again\nminimize 0 1e-8 20 1000\nprint \"FNORM $(fnorm)\"\nnext k\njump SELF again")
    rc, out = run_lmp(stepped, tmp_path, timeout=120)
    assert rc == 0, error_line(out)
    norms = [float(ln.split()[1]) for ln in out.splitlines() if ln.startswith("FNORM")]
    assert len(norms) == 4 and max(norms) < 1e-8
    assert "NOT an equilibrium" not in out and "inverts particles" not in out


def test_body_atoms_left_beyond_the_mirror_plane_are_warned(tmp_path):
    """A clamp group that stops two layers short of its plane left those
    layers as body beyond the clamp, silently."""
    extra = """
region clampzone block INF -0.002 INF INF INF INF units box
group clamp region clampzone
fix hold clamp sph/mirror x 0.0
run 0
"""
    script = block_script(pair_args="plane stress", extra=extra).replace(
        "region box block 0 12", "region box block -3 12")
    rc, out = run_lmp(script, tmp_path)
    assert rc == 0, error_line(out)
    assert "Fix hold sph/mirror: 8 atoms of the body lie beyond the plane x = 0" in out


def top_pressure_resultant(ny: int, mirror: str = "") -> float:
    """The y force that a pressure of 1e6 Pa on the top face of a strip of
    20 x ny particles (spacing 1 mm, t = 1 mm) applies: -20 N requested."""
    lmp = make_lammps()
    strip_model(lmp, f"{-3 if mirror else 0} 20 0 {ny}")
    lmp.commands_string(f"""
        {f'fix hold clamp sph/mirror x 0.0 {mirror}' if mirror else ''}
        fix t all sph/traction y {ny * DX} pressure 1e6
        run 0
    """)
    total = lmp.numpy.extract_fix("t", 0, 1, 1)
    lmp.close()
    return total


@pytest.mark.parametrize("mirror", ["", "slip no", "slip yes"])
def test_face_meeting_a_clamp_applies_the_requested_resultant(mirror):
    """A pressure on the top face of a strip clamped at x = 0: the clamp's
    mirror atoms hold 0.14 spacings of the face's area, which was handed
    to the sources with the clamp's signs, i.e. taken off: -19.72 N
    instead of -20 N at any depth.  Reflected, it is the requested -20 N
    to round-off, as without the clamp and at a symmetry plane."""
    assert top_pressure_resultant(30, mirror) == pytest.approx(-20.0, rel=1e-13)


def test_face_of_a_thin_body_is_refused_or_warned(tmp_path):
    """6 particles deep: the face's loads overlap the opposite side's and the
    resultant was +4.4 % off (the wrong sign at 4), silently."""
    with pytest.raises(Exception, match="kernel supports\\) deep behind the face y = 0.006"):
        top_pressure_resultant(6)
    extra = """
fix t all sph/traction y 0.008 pressure 1e6
run 0
"""
    rc, out = run_lmp(block_script(nx=20, ny=8, pair_args="plane stress", extra=extra), tmp_path)
    assert rc == 0, error_line(out)
    assert "the applied resultant is off by 0.1-2 % (7-8 particles through it)" in out


def test_ccb_far_above_its_stable_step_stops_before_binning(tmp_path):
    """sph/ccb at 25 h/c threw atoms metres away within steps, and LAMMPS
    stopped on 'Too many neighbor bins'; the run now stops on the partners'
    stretch with the time-step advice."""
    extra = ("velocity all ramp vy 0 1.0 x 0 0.04 units box\nfix i all sph/ccb/nve\nrun 0\n"
             "timestep $(25*v_dts)\nrun 200\n")
    rc, out = run_lmp(block_script(nx=40, ny=10, pair="sph/ccb", pair_args="", extra=extra),
                      tmp_path, timeout=60)
    assert rc != 0
    err = error_line(out)
    assert "kernel supports): the run blew up" in err and "25 h/c" in err, err

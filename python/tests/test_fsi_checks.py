"""Bad input of the fluid coupling (issue 35, item 3): a fluid and a body
in different units or at different spacings, a body thinner than the
fluid's kernel with fluid on both sides, and a coupling without the fixes
or the pair style the fluid needs.  Each stops at the start of the run with
an error that names both values and the command to change; the good inputs
beside them run.  The set-ups are test_fsi's blob and a plate between two
fluid layers."""
from __future__ import annotations

import pytest

from conftest import run_lmp
from test_fsi import ATOMS, COUPLE, PAIR, RHEO, SETTINGS, blob_script, refused


def edit(script: str, *changes: tuple[str, str]) -> str:
    """script with each (old, new) replaced; old must be there."""
    for old, new in changes:
        assert old in script, old
        script = script.replace(old, new)
    return script


def error_of(script: str, tmp_path, nprocs: int = 1) -> str:
    """The ERROR line an input stops with, run by the lmp binary (so that a
    crash fails the test, not the test process)."""
    rc, out = run_lmp(script, tmp_path, nprocs=nprocs, timeout=120)
    assert rc != 0, out[-2000:]
    return "\n".join(line for line in out.splitlines() if line.startswith("ERROR"))


def runs(script: str, tmp_path, nprocs: int = 1) -> None:
    rc, out = run_lmp(script, tmp_path, nprocs=nprocs, timeout=120)
    assert rc == 0, out[-3000:]


# ---------------------------------------------------------------------------
# units and spacings: the blob's fluid of rho0 = 1000 kg/m^3 and volume
# 1e-4 m^2 per particle (dx = 1 cm, per unit depth) against the body's
# density 2000 and volume 1e-4

# the fluid on a 2 cm lattice
COARSE_FLUID = ("create_atoms 1 region blob",
                "lattice sq 0.02 origin 0.5 0.5 0.0\ncreate_atoms 1 region blob")

UNITS = {
    # the body's density typed in g/cm^3 (2), the fluid's in kg/m^3
    "solid_density_in_g_per_cm3": (
        dict(), [("set group body mass 0.2", "set group body mass 0.0002")],
        ["elastic atoms of type 2 have a density of 2 ", "rest density 1000 (fix rheo density)",
         "a ratio of 0.002, outside the 0.01 to 100", "units of the 'units' command (si)"]),
    # a 2d body of the package's solid examples: volumes of a 1 mm thick
    # slice, dx^2 t; RHEO's are per unit depth (the twins given the fluid's
    # mass, as the mass check asks)
    "2d_volumes_with_a_thickness": (
        dict(twin_args="mass 0.1"),
        [("set group body mass 0.2", "set group body volume 1e-7\nset group body mass 2e-4")],
        ["fluid particles of type 1 have the volume 0.0001 (mean mass 0.1 over fix rheo "
         "density 1000), 1000 times the mean volume of the atoms of body (molecule) 1, 1e-07",
         "a thickness other than 1"]),
    # the fluid on a 2 cm lattice with masses for it, the twins given the
    # fluid's mass
    "fluid_spacing_twice_the_body's": (
        dict(twin_args="mass 0.4"),
        [COARSE_FLUID, ("set group fluid mass 0.1", "set group fluid mass 0.4")],
        ["have the volume 0.0004", "4 times the mean volume", "spacings 2 times apart"]),
    # the fluid on a 2 cm lattice with the masses of a 1 cm one
    "fluid_masses_for_another_spacing": (
        dict(), [COARSE_FLUID],
        ["the fluid particles are 0.02 apart", "2 times the spacing 0.01",
         "masses set for another spacing"]),
}


@pytest.mark.parametrize("case", sorted(UNITS))
def test_units_and_spacing_mismatch_is_an_error(tmp_path, case):
    kwargs, changes, messages = UNITS[case]
    error = refused(tmp_path, edit(blob_script(**kwargs), *changes), "run 1")
    for message in messages:
        assert message in error, error


def test_corrected_volumes_are_consistent(tmp_path):
    """set_sph_volumes' surface corrections change single atoms' volumes by
    up to a quarter (twins then need an explicit mass), not a lattice
    body's mean: the body at density 2000 with corrected volumes runs."""
    script = edit(blob_script(twin_args="mass 0.1"),
                  ("set group body mol 1",
                   "set group body mol 1\nset_sph_volumes body lattice 0.01 thickness 1.0 "
                   "density 2000"))
    runs(script + "run 5\n", tmp_path)


# ---------------------------------------------------------------------------
# a body thinner than fix rheo's cut with fluid on both sides.  The package
# needs 3 particles across a 2d body (gradient quadratic), so the cut here
# is 0.05 = 5 dx (quintic, h = 1.67 dx), and 5 particles make a plate the
# cut thick

CUT = 0.05


def sandwich(layers: int, below: bool = True, processors: str = "", gap: int = 0) -> str:
    """A free 12-particle-long plate `layers` particles thick under 3
    layers of fluid (and over 3 more if below, `gap` spacings under it), in
    zero gravity, fix rheo's cut 5 dx, up to the first run; with processors
    1 2 1 the ranks split between the plate (rank 0, with the fluid below
    it) and the fluid above it."""
    t = layers * 0.01
    low = -0.01 * gap
    rheo = edit(PAIR + RHEO.format(kernel="quintic 0", rho3="1000"),
                ("rheo 0.03 artificial", f"rheo {CUT} artificial"),
                ("all rheo 0.03 quintic", f"all rheo {CUT} quintic"))
    return SETTINGS + processors + f"""
region box block -0.01 0.13 {low - 0.05} {t + 0.06} -0.5 0.5 units box
create_box 3 box
lattice sq 0.01 origin 0.5 0.5 0.0
region plate block 0 0.12 0 {t} INF INF units box
region above block 0 0.12 {t} {t + 0.03} INF INF units box
region below block 0 0.12 {low - 0.03} {low} INF INF units box
create_atoms 2 region plate
create_atoms 1 region above
{"create_atoms 1 region below" if below else ""}
""" + ATOMS + rheo + "create_sph_twins body 3\n" + COUPLE + "timestep 1e-4\n"


# what both thin-body errors advise: a twin k layers deep in a plate of L
# has the fluid on its two sides k + 1 and L - k spacings away, within the
# reach of cut - dx/2 = 4.5 dx for some k up to L = 7
ADVICE = "make the body at least 8 layers thick at this spacing"
THIN = ["interact through a body near", "about 0.03 thick (3 particles at the spacing 0.01) "
        "along their line", "within fix rheo's cut 0.05", ADVICE]
# the 5-layer plate: its layers 1 to 3 see the fluid on both sides within
# 4.5 dx (2 and 4, 3 and 3, 4 and 2 spacings away)
THIN_TWINS = ["on opposite faces of its body, about 0.05 thick (5 particles at the spacing "
              "0.01) there", "within fix rheo's cut 0.05", "carries the pressure of one side",
              ADVICE]


def test_thin_body_with_fluid_on_both_sides(tmp_path):
    """A plate 3 particles thick between two fluid layers: the first fluid
    layers on its two sides are 4 dx apart, within the cut of 5 dx.  Of
    each layer's 12 atoms the 10 over the plate see through it; at its
    ends, where the fluid could also reach around it, the plate lies on one
    side of their pairs only."""
    error = refused(tmp_path, sandwich(3), "run 1")
    for message in THIN + ["20 fluid atoms see through"]:
        assert message in error, error


def test_twins_with_fluid_on_both_sides(tmp_path):
    """A plate 5 particles thick between two fluid layers: no fluid pair
    sees through it (6 dx apart), but its inner three layers' twins have
    fluid within 4.5 dx on both faces, and RHEO would give them a pressure
    averaged over both sides."""
    error = refused(tmp_path, sandwich(5), "run 1")
    for message in THIN_TWINS:
        assert message in error, error
    assert "see through" not in error


@pytest.mark.parametrize("layers,below", [(3, False), (5, False), (8, True)])
def test_thin_plate_one_sided_or_thick_plate_runs(tmp_path, layers, below):
    """The plates with fluid above them only, and a plate thick enough for
    the cut (8 particles) with fluid on both sides, run."""
    runs(sandwich(layers, below) + "run 5\n", tmp_path)


def test_fluid_reaching_the_second_side_in_a_run(tmp_path):
    """The 5-layer plate with the fluid below it 3 spacings away at the
    start (5 dx from the twins of layer 1, which see the fluid above 4 dx
    away), rising at 1 m/s: the check in the run stops it once that fluid
    is within 4.5 dx of them, after 50 steps (the check every 10, and
    the rising fluid slowed by the plate's own fluid below: 60 or 70
    then); with thin/check 0 the same steps run."""
    script = sandwich(5, gap=3) + "group rising region below\nvelocity rising set 0 1 0 units box\n"
    script = script.replace("fix fsi all sph/fluid", "fix fsi all sph/fluid thin/check 10 error")
    error = refused(tmp_path, script, "run 100")
    for message in THIN_TWINS[1:]:
        assert message in error, error
    step = int(error.split(" at step ")[1].split(":")[0])
    assert 50 <= step <= 70, error
    runs(script.replace("thin/check 10 error", "thin/check 0 error") + "run 100\n", tmp_path)
    # with warn the run goes on, and says so at every check from that step
    rc, out = run_lmp(script.replace("10 error", "10 warn") + "run 100\n", tmp_path, timeout=120)
    assert rc == 0, out[-3000:]
    warned = [line for line in out.splitlines()
              if line.startswith("WARNING: Fix sph/fluid fsi at step")]
    assert len(warned) == (100 - step) // 10 + 1, out[-3000:]
    assert all(THIN_TWINS[2] in line for line in warned)


def test_fluid_inside_a_body(tmp_path):
    """A fluid atom at the centre of a lattice cell of a plate 5 thick with
    fluid above it only: inside the body, among 4 twins around it (the
    water particle the 3-layer gate of examples/fsi_gate let in at its tip
    at step 4400 had the centroid of its twins 0.23 spacings off)."""
    script = sandwich(5, below=False).replace(
        "create_atoms 1 region above\n",
        "create_atoms 1 region above\ncreate_atoms 1 single 0.06 0.02 0 units box\n")
    error = refused(tmp_path, script, "run 1")
    assert "at (0.06, 0.02, 0), moving at 0, is inside a body, among its twins (1 fluid atom " \
        "so): the fluid went through the body's surface" in error, error


@pytest.mark.slow
def test_thin_body_two_ranks(tmp_path):
    """On 2 ranks, the fluid below the plate and the plate on rank 0, the
    fluid above on rank 1: each rank tests the pairs of its own fluid atoms
    (and its own twins) with the other's as ghosts, and finds as many as 1
    rank."""
    error = error_of(sandwich(3, processors="processors 1 2 1") + "run 1\n", tmp_path, 2)
    for message in THIN + ["20 fluid atoms see through"]:
        assert message in error, error
    error = error_of(sandwich(5, processors="processors 1 2 1") + "run 1\n", tmp_path, 2)
    for message in THIN_TWINS:
        assert message in error, error
    runs(sandwich(3, below=False, processors="processors 1 2 1") + "run 5\n", tmp_path, 2)


@pytest.mark.parametrize("values,message", [
    ("-1 error", "thin/check must be a whole number of steps, 0 for the check at setup only: -1"),
    ("often error", "whole number of steps, 0 for the check at setup only: often"),
    ("2.5 warn", "whole number of steps, 0 for the check at setup only: 2.5"),
    ("100 stop", "thin/check N takes error or warn (what a finding in the run does; at setup "
                 "it is always an error): stop"),
    ("100", "Illegal fix sph/fluid thin/check command: missing argument"),
])
def test_thin_check_keyword_is_checked(tmp_path, values, message):
    script = sandwich(3, below=False).replace("fix fsi all sph/fluid",
                                              f"fix fsi all sph/fluid thin/check {values}")
    error = error_of(script + "run 1\n", tmp_path)
    assert message in error, error


def test_thin_body_at_setup_is_an_error_with_warn(tmp_path):
    """warn is for what happens in a run: a body too thin at the start is
    bad input."""
    script = sandwich(3).replace("fix fsi all sph/fluid", "fix fsi all sph/fluid thin/check 1 warn")
    error = refused(tmp_path, script, "run 1")
    assert THIN[0] in error and " at step " not in error, error


# ---------------------------------------------------------------------------
# a coupling without what the fluid needs


def test_missing_rheo_viscosity_is_rheos_error(tmp_path):
    script = edit(blob_script(), ("fix visc all rheo/viscosity * constant 1e-3\n", ""))
    assert "Missing fix rheo/viscosity" in refused(tmp_path, script, "run 1")


def test_missing_rheo_pressure_is_an_error(tmp_path):
    """RHEO's interface reconstruction (4Feb2025) dereferences the missing
    fix in its init, before pair rheo's own check: a segmentation fault."""
    script = edit(blob_script(), ("fix pres all rheo/pressure * linear\n", ""))
    error = error_of(script + "run 1\n", tmp_path)
    assert "Fix sph/fluid needs fix rheo/pressure" in error


# neigh_modify exclusions that hide the twins (type 3) from the fluid (type
# 1, group fluid) or from each other, added after the blob's own (1 2 and 2
# 3, which hide the elastic atoms, as they should)
EXCLUSIONS = {
    "fluid_twin_type": ("neigh_modify exclude type 1 3\n",
                        "'neigh_modify exclude type 1 3' hides the twins of type 3 from the fluid "
                        "of type 1; twins must see the fluid and each other"),
    "twin_twin_type": ("neigh_modify exclude type 3 3\n",
                       "'neigh_modify exclude type 3 3' hides the twins of type 3 from the twins"),
    "fluid_twin_group": ("group twins type 3\nneigh_modify exclude group fluid twins\n",
                         "'neigh_modify exclude group fluid twins' hides twins from the fluid or "
                         "from each other"),
    # (molecule/intra all would also hide the body's atoms from each other:
    # fix sph/partners stops first)
    "molecule": ("group twins type 3\nneigh_modify exclude molecule/intra twins\n",
                 "'neigh_modify exclude molecule/intra twins' takes in twins"),
}


@pytest.mark.parametrize("case", sorted(EXCLUSIONS))
def test_exclusions_hiding_the_twins_are_an_error(tmp_path, case):
    """Twins hidden from the fluid let it run through the body unseen;
    twins hidden from each other leave the thin-body check blind (it takes
    a twin's outward normal from its twin neighbours)."""
    commands, message = EXCLUSIONS[case]
    error = refused(tmp_path, blob_script() + commands, "run 1")
    assert message in error, error


def test_missing_twins_is_an_error(tmp_path):
    """Without create_sph_twins the fluid would run through the body."""
    script = edit(blob_script(), ("create_sph_twins body 3 \n", ""))
    assert "there are no twins" in refused(tmp_path, script, "run 1")


def test_twins_without_fix_sph_fluid_is_an_error(tmp_path):
    """Twins left to fix rheo alone would drift off as free RHEO solids."""
    script = edit(blob_script(), ("fix fsi all sph/fluid\n", ""))
    error = refused(tmp_path, script, "run 1")
    assert "32 twins of create_sph_twins but no fix sph/fluid" in error


def test_missing_pair_rheo_is_an_error(tmp_path):
    """pair_style hybrid/overlay with sph/icb alone (the fluid's pairs
    switched off): the fluid would feel nothing."""
    pair = edit(PAIR, ("rheo 0.03 artificial/visc 1.0 ", ""),
                ("pair_coeff * * rheo", "pair_coeff * * none"))
    assert "needs pair style rheo" in refused(tmp_path, blob_script(pair=pair), "run 1")

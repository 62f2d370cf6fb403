"""Bad input of the fluid coupling (issue 35, item 3): a fluid and a body
in different units or at different spacings, and a coupling without the
fixes or the pair style the fluid needs.  Each stops at the start of the
run with an error that names both values and the command to change; the
good inputs beside them run.  The set-up is test_fsi's blob."""
from __future__ import annotations

import pytest

from conftest import run_lmp
from test_fsi import PAIR, blob_script, refused


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

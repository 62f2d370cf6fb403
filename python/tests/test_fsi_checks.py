"""Bad input of the fluid coupling (issue 35, item 3): a coupling without
the fixes or the pair style the fluid needs stops at the start of the run
with an error that names the command to add.  The set-up is test_fsi's
blob."""
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

"""Sub-stepping of the elastic bodies inside the fluid's step (fix
sph/fluid substeps N|auto, issue 35): the body is integrated in N
velocity-Verlet steps of dt/N with its elastic force recomputed and every
other force on it (the fluid's, through the twins) held at the step's
start, corrected at the step's end by dt/2 (G_n+1 - G_n).  Momentum must still be exchanged exactly, on 1 and 2
ranks; N = 1 must be the run without the keyword; a body that feels no
fluid must move as it does without sub-steps at dt/N; restarts continue to
the bit; timesteps beyond either limit stop with an error that names
the keyword's value that works; and the aluminium plate of
examples/fsi_plate, sub-stepped, stays with the run resolved at its own
step (RHEO's wall pressure is shown no acceleration of the body)."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from conftest import by_id, make_lammps, run_lmp
from test_fsi import (COUPLE, PAIR, RHEO, assert_ranks_agree, blob_script, momentum_history, refused,
                      restart_states, run_on_1_and_2_ranks)


def substepped(n) -> str:
    return COUPLE.replace("fix fsi all sph/fluid", f"fix fsi all sph/fluid substeps {n}")


# the blob's body a thousand times stiffer (c_s about 800 m/s): its stable
# limit, about 6.7e-6 s, is 1/15 of the fluid's step 1e-4 s
STIFF = PAIR.replace("2 2 sph/icb 1e6 0.3", "2 2 sph/icb 1e9 0.3")


@pytest.mark.parametrize("newton", ["off", "on"])
def test_momentum_conserved_with_substeps(lmp, tmp_path, newton):
    """The blob hits the stiff body, sub-stepped 16 times per fluid step:
    the total momentum stays what it was to round-off (the fluid gets
    dt/2 (F_n + F_n+1) from the twins, the body dt F_n over the sub-steps
    and dt/2 (F_n+1 - F_n) at the end; the elastic forces sum to zero).  With newton on the
    sub-steps' ghost forces come back by the fix's own reverse
    communication."""
    lmp.commands_string(blob_script(pair=STIFF, couple=substepped(16))
                        .replace("newton off", f"newton {newton}"))
    p = momentum_history(lmp, tmp_path, 300)
    p0 = -36 * 0.1 * 2.0
    assert p[0, 0] == pytest.approx(p0, rel=1e-15)
    # measured: 7.4e-16 (newton off and on)
    assert np.abs(p - [p0, 0.0]).max() / abs(p0) < 1e-13
    # the exchange is real: the stiff body took a third of the momentum
    body = lmp.extract_compute("pb", 0, 0)
    assert 0.2 < body / p0 < 0.6
    # the twins sit on their sources, their force handed over
    x, f, typ = by_id(lmp, "x"), by_id(lmp, "f"), by_id(lmp, "type")
    src = by_id(lmp, "i_sph_twin")
    twins = np.flatnonzero(typ == 3)
    assert np.array_equal(x[twins], x[src[twins] - 1])
    assert np.all(f[twins] == 0.0)


def test_one_substep_is_no_keyword(lmp):
    """substeps 1 leaves the integration to fix rheo: the run is the one
    without the keyword, to the bit."""
    runs = []
    for couple in (COUPLE, substepped(1)):
        lmp2 = make_lammps()
        lmp2.commands_string(blob_script(couple=couple) + "run 200\n")
        runs.append((by_id(lmp2, "x"), by_id(lmp2, "v")))
        lmp2.close()
    assert np.array_equal(runs[0][0], runs[1][0])
    assert np.array_equal(runs[0][1], runs[1][1])


def alone_script(couple: str) -> str:
    """The blob at rest 12 cm from the body (beyond the cut: the twins feel
    nothing), the body ringing in its first bending-like mode."""
    return (blob_script(couple=couple)
            .replace("region blob block 0.10 0.16", "region blob block 0.20 0.26")
            .replace("velocity fluid set -2 0 0 units box",
                     "variable vy atom 0.5*sin(PI*x/0.08)\nvelocity body set 0 v_vy 0 units box"))


@pytest.mark.parametrize("n", [4, 3])
def test_body_alone_as_without_substeps(n):
    """With no fluid force the scheme is velocity Verlet at dt/N: 200 fluid
    steps of 1e-4 s with N sub-steps end where 200 N steps of 1e-4/N s
    without the keyword end.  For N = 4 the arithmetic is the same (dt/4 is
    exact in binary, the held force and its correction are 0): identical to the bit.  For
    N = 3 the step typed into the input, 3.33333333333333e-05, differs from
    dt/3 in the 15th digit, and the ringing body carries that phase error:
    1e-12 of the motion is the bound (measured below)."""
    ends = []
    for couple, run in ((substepped(n), "run 200"),
                        (COUPLE, f"timestep {1e-4 / n:.15g}\nrun {200 * n}")):
        lmp = make_lammps()
        lmp.commands_string(alone_script(couple) + run + "\n")
        typ = by_id(lmp, "type")
        ends.append((by_id(lmp, "x")[typ == 2], by_id(lmp, "v")[typ == 2],
                     by_id(lmp, "x")[typ == 1]))
        lmp.close()
    (xs, vs, fs), (xr, vr, fr) = ends
    assert np.array_equal(fs, fr)    # the fluid did not move
    if n == 4:
        assert np.array_equal(xs, xr) and np.array_equal(vs, vr)
    else:
        # measured: 1e-18 m and 4e-15 m/s for velocities of 0.4 m/s
        assert np.abs(xs - xr).max() < 1e-12 * 0.01
        assert np.abs(vs - vr).max() < 1e-12 * 0.5
    assert np.abs(vs).max() > 0.1    # it rang


def test_two_ranks_agree_with_substeps(tmp_path):
    """On 2 ranks (split through the body) the sub-stepped stiff run
    conserves momentum and ends where 1 rank ends, to round-off: each
    sub-step forwards the positions of the body's ghosts."""
    ends = run_on_1_and_2_ranks(
        tmp_path, lambda proc: blob_script(proc, pair=STIFF, couple=substepped(16)), 200)
    # the same bounds as the run without sub-steps (test_fsi.py)
    assert_ranks_agree(ends)


def test_kept_forces_are_the_computed_ones():
    """Pair sph/icb keeps the elastic forces of the last sub-step for the
    step's own force computation (pair hybrid's), which starts from the
    same positions, and computes them again on the steps that tally
    energy or virial.  Thermo with pe and press at every step (computed
    every step) against thermo every 30 steps (kept on the others, the
    last step among them): the same positions, velocities and forces,
    to the bit."""
    ends = []
    for every in (1, 30):
        lmp = make_lammps()
        lmp.commands_string(blob_script(pair=STIFF, couple=substepped(16)))
        lmp.commands_string(f"thermo_style custom step pe press\nthermo {every}\nrun 100\n")
        ends.append({name: by_id(lmp, name) for name in ("x", "v", "f")})
        lmp.close()
    for name in ("x", "v", "f"):
        assert np.array_equal(ends[0][name], ends[1][name]), name


def test_restart_with_substeps(tmp_path):
    """Continued from a restart file, the sub-stepped run ends where the
    uninterrupted one ends, to the bit: the elastic force kept between
    steps is computed again at setup from the same positions."""
    uninterrupted, continued = restart_states(
        tmp_path, blob_script(pair=STIFF, couple=substepped("auto")),
        STIFF + RHEO.format(kernel="quintic 0", rho3="1000") + substepped("auto"), 100)
    for name in ("x", "v"):
        assert np.array_equal(continued[name], uninterrupted[name]), name


def test_substep_errors(tmp_path):
    """The stiff body at the fluid's step: without the keyword the error
    names the sub-steps that would do; with too few, the number again;
    auto finds it; a hold on elastic atoms and bad values are refused."""
    error = refused(tmp_path, blob_script(pair=STIFF), "run 1")
    assert "exceeds the elastic body's stable limit" in error
    assert "'fix fsi all sph/fluid substeps 15'" in error
    error = refused(tmp_path, blob_script(pair=STIFF, couple=substepped(4)), "run 1")
    assert "timestep/substeps = 0.0001/4 = 2.5e-05" in error
    assert "use 'substeps 15'" in error
    # the fluid's limit is dt itself, whatever N
    error = refused(tmp_path, blob_script(pair=STIFF, couple=substepped(40)),
                    "timestep 2e-4\nrun 1")
    assert "exceeds the fluid's stable limit" in error and "substeps 15" in error
    # auto: the fewest that fit, logged
    log = tmp_path / "auto.log"
    from lammps import lammps
    lmp = lammps(cmdargs=["-screen", "none", "-log", str(log), "-nocite"])
    lmp.commands_string(blob_script(pair=STIFF, couple=substepped("auto")) + "run 2\n")
    lmp.close()
    # auto: the fewest that bring the step under the pair's advised step
    # (half its limit), not under the limit itself, which needed 15
    match = re.search(r"Fix sph/fluid fsi: (\d+) sub-steps of (\S+) for the elastic bodies "
                      r"\(their advised step (\S+), stable limit (\S+)\)", log.read_text())
    assert match, "no sub-step line in the log"
    nsub, step, advised, limit = int(match[1]), *map(float, match.groups()[1:])
    assert step == pytest.approx(1e-4 / nsub, rel=1e-5)    # as printed
    assert step <= advised < step * nsub / (nsub - 1)    # the fewest
    assert advised <= 0.5 * limit * (1 + 1e-9) and nsub > 15
    error = refused(tmp_path, blob_script(couple=substepped(2)),
                    "fix hold body setforce 0 0 0\nrun 1")
    assert "holds elastic atoms" in error and "fix sph/mirror" in error
    for bad in ("0", "two"):
        error = refused(tmp_path, blob_script(couple=""), f"fix fsi all sph/fluid substeps {bad}")
        assert "substeps" in error
    error = refused(tmp_path, blob_script(couple=""), "fix fsi all sph/fluid substeps")
    assert "fix sph/fluid substeps" in error


def plate_run(tmp_path, substeps: int, T: float) -> dict:
    """examples/fsi_plate with the aluminium plate (E 70 GPa, 2700 kg/m^3,
    undamped): the RESULT lines and the water's largest kinetic energy."""
    import re
    from pathlib import Path
    script = (Path(__file__).parents[2] / "examples" / "fsi_plate" / "in.fsi_plate").read_text()
    script = script.replace("thermo          $(round(v_nsteps/20))", "thermo 10")
    head = "".join(f"variable {k} index {v}\n" for k, v in
                   (("E", 7e10), ("rhos", 2700), ("T", T), ("taus", 0), ("substeps", substeps)))
    case = tmp_path / f"n{substeps}"
    case.mkdir()
    rc, out = run_lmp(head + script, case, timeout=120)
    assert rc == 0, out[-2000:]
    res = {m[1]: float(m[2]) for m in re.finditer(r"^RESULT (\w+) (\S+)", out, re.M)}
    # thermo: step time c_kew ...
    number = r"[-+]?[\d.]+(?:[eE][-+]?\d+)?"
    rows = re.findall(rf"^\s*\d+\s+{number}\s+({number})(?:\s+{number}){{5}}\s*$", out, re.M)
    assert rows, out[-2000:]
    res["kemax"] = max(float(ke) for ke in rows)
    # the pair style's own step warning, which a sub-stepped body must not get
    res["blow_up_warned"] = "the run will blow up" in out
    return res


def test_stiff_plate_substepped_as_resolved(tmp_path):
    """The aluminium plate under its water column, at 2 sub-steps of its
    own stable step, against the run at that step (0.0015 s, 1850 plate
    steps, about 8 s in all).  Shown the body's mean acceleration over the
    fluid step, RHEO's wall pressure answered the plate's elastic modes a
    step and a half late and pumped them: the water's kinetic energy rose
    to 0.48 against 2.9e-4 and the force on the plate to 13 times the
    column's weight (0.001 s, plain cell volumes).  Shown none, measured
    (the plate's volumes of set_sph_volumes): kinetic energy 5.64e-4
    (both), force 0.9694 against 0.9697, mid-span 5.89e-9 against
    5.83e-9 m.  The undamped plate rings about its sag, so the mid-span
    average depends on where the window ends: over 0.001 s the two runs
    were 6.8 % apart (1.0 % over 0.0015 s, 1.5 % over 0.002 s)."""
    ref = plate_run(tmp_path, 1, 0.0015)
    sub = plate_run(tmp_path, 2, 0.0015)
    # the timestep is twice the plate's step, over pair sph/icb's limit:
    # fix sph/fluid judges the sub-step, and the pair does not warn
    assert not sub["blow_up_warned"]
    assert sub["kemax"] == pytest.approx(ref["kemax"], rel=0.2)
    assert sub["force"] == pytest.approx(ref["force"], rel=0.03)
    assert sub["wcol"] == pytest.approx(ref["wcol"], rel=0.05)


def test_stiff_plate_auto_substeps_bounded(tmp_path):
    """The same plate at the fluid's step, 88 sub-steps (examples/fsi_plate
    -var substeps 0), over 0.02 s (about 1.5 s): the water stays nearly at
    rest and carries its weight on the plate.  Measured: kinetic energy at
    most 1.6e-3 (the resolved run's 1.4e-3, plain cell volumes), force 1.01
    of the column's weight (second half), against 5e-3 and 1.5 with the
    mean acceleration shown."""
    sub = plate_run(tmp_path, 0, 0.02)
    assert sub["kemax"] < 3e-3
    assert sub["force"] == pytest.approx(1.0, abs=0.05)
    assert sub["wcol"] == pytest.approx(-5.85e-9, rel=0.1)


def test_unstable_substeps_are_named_in_the_error(tmp_path):
    """examples/fsi_plate 3 particles thick (exact volumes: 3/4 of a cell in
    the middle row) at 2 sub-steps of 0.42 h/c per fluid step, under the
    pair's 0.46 h/c estimate, inverts within 31 steps.  The error speaks of
    the sub-step, not of the fluid's timestep (which is 0.84 h/c), and
    names the sub-steps that hold; substeps auto takes them."""
    from esph.problems import FSI_PLATE
    from esph.runner import run_mpi
    from esph.validate import plate_variables
    given = "fix             fsi all sph/fluid substeps $(v_subkw)"
    text = FSI_PLATE.read_text()
    assert given in text
    variables = plate_variables(3, T=0.004, substeps=0)
    for count, name in (("2", "two"), ("auto", "auto")):
        script = tmp_path / f"in.plate_{name}"
        script.write_text(text.replace(given, f"fix             fsi all sph/fluid substeps {count}"))
        if count == "2":
            with pytest.raises(RuntimeError) as err:
                run_mpi(script, variables, 1)
            message = str(err.value)
            assert "is inverted" in message
            assert "the sub-step timestep/substeps = " in message and "/2 = " in message
            assert "= 0.42 h/c is within the stable estimate" in message
            assert "'substeps 4' in fix sph/fluid" in message
        else:
            out = run_mpi(script, variables, 1)
            assert "Fix sph/fluid fsi: 4 sub-steps" in out.log
            assert math.isfinite(out.variables["wcol"])
            # the number auto chose, as the fix's output (f_fsi[4])
            assert out.variables["substeps"] == 4

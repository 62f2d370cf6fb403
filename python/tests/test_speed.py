"""esph.speed: the rows of the speed-against-error table, and the MACHDYN
beam script measuring the same beam as in.beam."""
from __future__ import annotations

import pytest

from esph import speed, statics
from esph.problems import BEAM, BEAM_TLSPH
from esph.runner import run_mpi


def test_icb_row_has_counts_error_and_throughput():
    method = speed.METHODS["cg-paper"]             # ICB min CG, the paper's scheme
    row = speed.run_one("beam", -250.0, method, 0.005, 1)
    assert row.status == "ok"
    assert row.atoms == (40 + 3) * 4               # 40 columns + 3 clamp columns, 4 rows
    assert row.steps > 100 and row.throughput > 1e4
    # the coarse paper scheme is far too soft at 5 mm (Table 2 style: +30 %)
    assert 0.15 < row.error < 0.5
    assert "in.beam" in row.command and "-var dx 0.005" in row.command


@pytest.mark.slow
def test_tlsph_beam_is_the_same_beam():
    """The same suddenly applied load for the same time: the early response
    is set by mass, load and stiffness, so both codes' tips move alike."""
    common = {"Fy": -250.0, "dx": 0.004, "route": "nve"}
    icb = run_mpi(BEAM, {**common, "nsteps": 400}, 1).variables
    probe = run_mpi(BEAM_TLSPH, {**common, "nsteps": 100}, 1).variables
    steps = round(icb["time"] / (probe["time"] / 100))    # TLSPH's steps to the same time
    tls = run_mpi(BEAM_TLSPH, {**common, "nsteps": steps}, 1).variables
    assert tls["atoms"] == icb["atoms"]
    assert tls["time"] == pytest.approx(icb["time"], rel=0.02)
    assert icb["tip_dv"] < 0
    assert tls["tip_dv"] == pytest.approx(icb["tip_dv"], rel=0.1)


@pytest.mark.slow
def test_damped_route_reports_that_it_reached_rest():
    """20 damping times at 2 omega1: the force left is a tiny share of the
    load, and the tip is where minimisation puts it."""
    damped = speed.run_one("beam", -250.0, speed.METHODS["dyn-quadratic"], 0.005, 1)
    static = speed.run_one("beam", -250.0, speed.METHODS["cg-quadratic"], 0.005, 1)
    assert damped.status == "ok" and damped.residual < speed.AT_REST
    assert damped.value == pytest.approx(static.value, rel=1e-3)


@pytest.mark.slow
def test_statics_rows_against_the_converged_answer():
    """Newton reaches the converged answer in a handful of iterations, CG in
    thousands; both within 1e-6 of it (their force tolerance is 1e-7 of the
    load), and a loose Newton run (1e-3) within 0.1 %."""
    rows = {r.route: r for r in statics.statics(0.005, [1], ["newton", "newton-loose", "cg"],
                                              progress=lambda _: None)}
    assert rows["newton"].atoms == (40 + 3) * 4
    assert rows["newton"].iterations <= 15
    assert rows["cg"].iterations > 50 * rows["newton"].iterations
    assert abs(rows["newton"].deviation) < 1e-8
    assert abs(rows["cg"].deviation) < 1e-6
    assert abs(rows["newton-loose"].deviation) < 1e-3
    # the defaults at 5 mm (4 particles deep) against the mesh-converged FE
    # continuum at the same material points: +0.27 % measured; the issue's
    # bound for a body 4 particles deep is 0.5 %.  (Against the elastica it
    # is +0.96 %: the 2D continuum is 0.6 % softer, by shear.)
    from esph import fe
    continuum = fe.tip("beam", -250.0, 0.005)["dv"]
    assert 0.0 < rows["newton"].dv / continuum - 1 < 0.005

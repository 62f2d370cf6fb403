"""A cantilever clamped to a rigid cylinder (examples/beam_cylinder): the
body laid out to fit the arc (set_sph_volumes ... jacobian, fix sph/mirror
cylinder ... along x) converges to the FE continuum with the arc at the
order its 60-degree clamped corners allow (issue 32; a lattice the arc cuts
is refused, and converged erratically)."""
from __future__ import annotations

import math

import pytest

from esph import fe
from esph.problems import CATALOGUE
from esph.report import order
from esph.validate import CYLINDER_CASE, CYLINDER_DX, cylinder_clamp_errors


def test_beam_on_a_cylinder_converges_at_the_corner_bound():
    series = [cylinder_clamp_errors(dx) for dx in CYLINDER_DX]
    errors = [r["err_end"] for r in series]
    q = order(errors, list(CYLINDER_DX))
    _, _, q_max = fe.cylinder_corner(CATALOGUE["beam_cylinder"], *CYLINDER_CASE)
    # the end centre's deflection falls monotonically to the continuum's
    assert all(e > 0.0 for e in errors) and errors[0] > errors[1] > errors[2]
    # towards the bound 2 lambda = 1.74 of the corners, not first order
    assert 1.4 < q[-1] <= q_max + 0.05, q
    assert errors[-1] < 1e-3      # 32 particles across
    for r in series:
        assert math.isfinite(r["end_dv"]) and r["end_dv"] < 0.0


def test_beam_on_a_cylinder_is_the_same_on_two_ranks():
    """The same direct solve on 1 and 2 ranks: the same Newton iterates, the
    end to round-off.  The default on 2 ranks (solver auto: PETSc's CG,
    inexact Newton) stops elsewhere within ftol; with ftol a thousand times
    tighter it meets the same equilibrium to the same 1e-9."""
    serial = cylinder_clamp_errors(CYLINDER_DX[0])
    parallel = cylinder_clamp_errors(CYLINDER_DX[0], nprocs=2, linear="direct")
    assert parallel["end_dv"] == pytest.approx(serial["end_dv"], rel=1e-9)
    tight = {"ftol": 1e-9}
    serial = cylinder_clamp_errors(CYLINDER_DX[0], **tight)
    parallel = cylinder_clamp_errors(CYLINDER_DX[0], nprocs=2, **tight)
    assert parallel["end_dv"] == pytest.approx(serial["end_dv"], rel=1e-9)

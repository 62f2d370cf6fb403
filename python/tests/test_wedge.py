"""Corner exponents of elastic wedges (theory.wedge_exponents), which bound
the order at which any uniform discretisation of the clamped beam converges.

(a) two free edges at 270 degrees: Williams' (1952) classical exponents;
(b) a clamped and a free edge at any angle: the determinant's roots against
    the closed-form characteristic equation of the same corner,
    kappa^2 + 1 + 2 kappa cos(2 lambda alpha) = 4 lambda^2 sin^2(alpha);
(c) the cantilever's clamp: regular at nu = 0, singular for nu > 0, and the
    order bound the validation's Table 5 prints.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize

from esph import theory


def closed_form_clamped_free(angle: float, kappa: float, upper: float = 1.5) -> list[float]:
    """Real roots in (0, upper] of the clamped-free characteristic equation."""
    def residual(lam):
        return (kappa ** 2 + 1.0 + 2.0 * kappa * math.cos(2.0 * lam * angle)
                - 4.0 * lam ** 2 * math.sin(angle) ** 2)
    grid = np.linspace(1e-3, upper, 3000)
    values = [residual(lam) for lam in grid]
    return [optimize.brentq(residual, lo, hi, xtol=1e-14)
            for lo, hi, f_lo, f_hi in zip(grid[:-1], grid[1:], values[:-1], values[1:])
            if f_lo * f_hi < 0.0]


def test_free_free_270_degrees_gives_williams_exponents():
    # the re-entrant corner of an L-shaped plate: 0.5445 (symmetric) and
    # 0.9085 (antisymmetric), whatever kappa, then the rigid rotation at 1
    for kappa in (1.8, 3.0):
        roots = theory.wedge_exponents(1.5 * math.pi, ("free", "free"), kappa)
        assert roots[0] == pytest.approx(0.5444837, abs=1e-6)
        assert roots[1] == pytest.approx(0.9085292, abs=1e-6)
        assert roots[2] == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("angle", [math.pi / 3, math.pi / 2, 2 * math.pi / 3, 0.75 * math.pi,
                                   1.5 * math.pi])
@pytest.mark.parametrize("kappa", [1.4, 1.8, 2.7 / 1.3, 3.0])
def test_clamped_free_roots_match_the_closed_form(angle, kappa):
    roots = theory.wedge_exponents(angle, ("clamped", "free"), kappa)
    expected = closed_form_clamped_free(angle, kappa)
    assert len(roots) == len(expected)
    assert np.allclose(roots, expected, rtol=0.0, atol=1e-10)


def test_cantilever_clamp_is_regular_at_nu_0_and_singular_above():
    lam, q_max = theory.clamp_corner_order(0.0, "stress")
    assert lam == pytest.approx(1.0, abs=1e-12)
    assert q_max == 2.0
    lam_stress, q_stress = theory.clamp_corner_order(0.3, "stress")
    lam_strain, q_strain = theory.clamp_corner_order(0.3, "strain")
    assert lam_stress == pytest.approx(0.758349, abs=1e-6)
    assert q_stress == pytest.approx(2.0 * lam_stress)
    # plane strain (and a 3d body's clamped edges) is the more singular
    assert lam_strain == pytest.approx(0.711173, abs=1e-6)
    assert theory.clamp_corner_order(0.3, "3d") == (lam_strain, q_strain)
    # the singularity grows with nu
    lams = [theory.clamp_corner_order(nu, "stress")[0] for nu in (0.1, 0.2, 0.3, 0.4, 0.49)]
    assert all(a > b for a, b in zip(lams, lams[1:]))


def test_bad_edge_and_plane_are_refused():
    with pytest.raises(ValueError, match="plane must be"):
        theory.kolosov_kappa(0.3, "membrane")
    with pytest.raises(ValueError, match="edge must be"):
        theory.wedge_exponents(math.pi / 2, ("clamped", "sliding"), 1.8)

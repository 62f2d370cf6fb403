"""The reference answers the validation compares with at the material point
the scripts measure, where they need more than the catalogue's closed forms
(esph.problems): the finite-element continuum (esph.fe's tables) and, for a
load on the last column, Reissner's shear beam loaded there."""
from __future__ import annotations

import math

from . import theory
from .problems import load_point
from .schemes import VARIANTS


def continuum_tip(problem: str, load: float, dx: float, nu: float = 0.0, plane: str = "stress",
                  stress: str = "pk1") -> dict:
    """Tip column means (dh, dv, dz) of the finite-element continuum (esph.fe,
    loaded on the end face), or nans where it has none."""
    nan = {"dh": math.nan, "dv": math.nan, "dz": math.nan, "error_estimate": math.nan}
    if stress != "pk1":
        return nan    # the FE solves Green strain + St. Venant-Kirchhoff only
    try:
        from . import fe
        return fe.tip(problem, load, dx, nu=nu, plane=plane)
    except (ImportError, KeyError, FileNotFoundError):
        return nan


def continuum_dv(load: float, dx: float, stress: str, variant: str = "linear/fixed",
                 nu: float = 0.0, plane: str = "stress") -> float:
    """Tip dv of the continuum the particle beam tends to as dx -> 0.  A load
    on the last column acts at L - dx/2: Reissner's shear beam loaded there
    (nu = 0 only).  A face traction acts at x = L: the finite-element
    solution of the 2D continuum, nan if it is not tabulated."""
    where = VARIANTS[variant][1]["load"]
    if where == "column":
        if nu != 0.0:
            return math.nan
        beam = theory.Beam()
        return theory.shear_beam_tip(beam, load, a=load_point(beam.L, dx, where), model=stress)[1]
    return continuum_tip("beam", load, dx, nu, plane, stress)["dv"]

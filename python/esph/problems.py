"""The validation problems in one place: which example script runs each,
which variable loads it, which schemes (variants) it can run with, and the
reference answers at the material point the scripts measure.

Every beam and truss script reports the centroid of the tip column, whose
particles sit at X = L - dx/2; every reference answer here is evaluated
there.  Where the load acts is a separate matter: on the last column it acts
at L - dx/2 too, a face traction acts at x = L."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from . import theory
from .paths import EXAMPLES

BEAM = EXAMPLES / "beam" / "in.beam"
TRUSS = EXAMPLES / "truss" / "in.truss"
BEAM_TLSPH = EXAMPLES / "beam" / "in.beam_tlsph"
BEAM3D = EXAMPLES / "beam3d" / "in.beam3d"
BEAM3D_TLSPH = EXAMPLES / "beam3d" / "in.beam3d_tlsph"
RINGS = EXAMPLES / "rings" / "in.rings"
LAME = EXAMPLES / "lame" / "in.lame"


@dataclass(frozen=True)
class Problem:
    name: str
    script: Path
    load_var: str        # the example variable that sets the load, in N
    component: str       # the tip displacement compared: dh (along x) or dv (along y)


PROBLEMS = {
    "beam": Problem("beam", BEAM, "Fy", "dv"),
    "truss": Problem("truss", TRUSS, "Fx", "dh"),
    "beam3d": Problem("beam3d", BEAM3D, "Fy", "dv"),
    "beam_tlsph": Problem("beam_tlsph", BEAM_TLSPH, "Fy", "dv"),
}

# the schemes a beam or truss script can run, by name: a label and the
# example variables that select them
PAPER = {"grad": "linear", "clamp": "fixed", "volumes": "cells", "load": "column", "hg": 0.0}
QUADRATIC_MIRROR = {"grad": "quadratic", "clamp": "mirror", "volumes": "cells", "load": "column",
                    "hg": 0.0}
DEFAULT = {"grad": "quadratic", "clamp": "mirror", "volumes": "exact", "load": "traction",
           "hg": 0.2}
VARIANTS = {
    "linear/fixed": ("the paper's scheme: linear gradient correction, fixed clamp, cell volumes, "
                     "load on the last column", PAPER),
    "quadratic/fixed": ("gradient exact for quadratic fields, fixed clamp, cell volumes, column load",
                        {**QUADRATIC_MIRROR, "clamp": "fixed"}),
    "quadratic/mirror": ("gradient exact for quadratic fields, mirror clamp, cell volumes, column "
                         "load (the last release's recommendation)", QUADRATIC_MIRROR),
    "linear/mirror": ("linear gradient correction, mirror clamp, cell volumes, column load",
                      {**PAPER, "clamp": "mirror"}),
    "default": ("the defaults: quadratic gradient, mirror clamp, exact volumes "
                "(set_sph_volumes), traction on the end face (fix sph/traction), hourglass "
                "control 0.2", DEFAULT),
}
VARIANT_LABELS = {name: label for name, (label, _) in VARIANTS.items()}


def tip_point(length: float, dx: float) -> float:
    """Reference x of the tip column's particles, where the scripts measure."""
    return length - 0.5 * dx


def load_point(length: float, dx: float, load: str) -> float:
    """Reference x at which the load acts: the last column's (load column) or
    the end face (load traction); the examples print it as RESULT load_x."""
    if load == "column":
        return tip_point(length, dx)
    if load == "traction":
        return length
    raise ValueError(f"unknown load {load!r}: column or traction")


def beam_exact(load: float, dx: float) -> tuple[float, float]:
    """(dh, dv) of the elastica at the tip column's material point."""
    beam = theory.Beam()
    return theory.beam_tip(beam, load, s=tip_point(beam.L, dx))


def truss_exact(load: float, dx: float, model: str) -> float:
    """dh of the exact uniaxial answer of `model` (pk1, corotated, hypo) at
    the tip column's material point."""
    truss = theory.Truss()
    return truss.displacement(load, model, tip_point(truss.L, dx))


def exact_tip(problem: str, load: float, dx: float, model: str = "pk1") -> float:
    """The compared component (PROBLEMS[problem].component) of the exact
    answer of a 2D beam or truss."""
    if problem in ("beam", "beam_tlsph"):
        return beam_exact(load, dx)[1]
    if problem == "truss":
        return truss_exact(load, dx, model)
    raise ValueError(f"no closed-form answer for {problem!r}: use continuum_tip")


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

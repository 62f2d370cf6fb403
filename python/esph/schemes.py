"""The one registry of schemes by name: which example variables select a
pair style and its options (gradient, clamp, volumes, load, hourglass
control), a route (minimisation or damped dynamics) and a solver, with a
label and the continuum model each tends to.  Read by validate (VARIANTS),
speed (METHODS, BENCH_STYLES), statics (STATICS_ROUTES), matrix
(PAIR_SCHEMES) and bench3d (LINEAR_SOLVERS); nothing here runs LAMMPS.  Problems are named as in the
catalogue (esph.problems)."""
from __future__ import annotations

from dataclasses import dataclass

# -- the options of pair_style sph/icb the beam and truss scripts select -------

PAPER = {"grad": "linear", "clamp": "fixed", "volumes": "cells", "load": "column", "hg": 0.0}
QUADRATIC_MIRROR = {"grad": "quadratic", "clamp": "mirror", "volumes": "cells", "load": "column",
                    "hg": 0.0}
DEFAULT = {"grad": "quadratic", "clamp": "mirror", "volumes": "exact", "load": "traction",
           "hg": 0.2}

# the variants of esph validate: a label and the example variables
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


# -- the pair styles of the paper's failure matrix (esph matrix) ---------------

@dataclass(frozen=True)
class PairScheme:
    paper_name: str          # its name in the paper's tables
    variables: dict          # route (and stress) the failure matrix runs it with
    model: str               # the continuum model whose exact answer it tends to


# ICB by minimisation (pk1: exact energy gradient), CCB and CCBWAT by damped
# dynamics
PAIR_SCHEMES = {
    "ccb": PairScheme("CCB", {"route": "dyn"}, "hypo"),
    "ccbwat": PairScheme("CCBWAT", {"route": "dyn"}, "hypo"),
    "icb": PairScheme("ICB", {"route": "min", "stress": "pk1"}, "pk1"),
}


# -- every scheme and route of esph speed, by name ----------------------------

@dataclass(frozen=True)
class Method:
    label: str
    variables: dict          # example variables that select scheme and route
    model: str               # the continuum model whose exact answer it tends to
    # the problem whose script runs each problem asked for (none: cannot run it)
    runs: tuple = (("beam", "beam"), ("truss", "truss"))

    def script_problem(self, problem: str) -> str | None:
        return dict(self.runs).get(problem)


METHODS = {
    "cg-paper": Method("ICB min CG, paper (linear/fixed, pk1)",
                       {"route": "min", "solver": "cg", "stress": "pk1", **PAPER}, "pk1"),
    "cg-quadratic": Method("ICB min CG, quadratic/mirror, pk1",
                           {"route": "min", "solver": "cg", "stress": "pk1", **QUADRATIC_MIRROR},
                           "pk1"),
    "dyn-paper": Method("ICB dyn, paper (linear/fixed, corotated)",
                        {"route": "dyn", "stress": "corotated", **PAPER}, "corotated"),
    "dyn-quadratic": Method("ICB dyn, quadratic/mirror, pk1",
                            {"route": "dyn", "stress": "pk1", **QUADRATIC_MIRROR, "hg": 0.05},
                            "pk1"),
    "ccbwat": Method("CCBWAT dyn", {"scheme": "ccbwat", "route": "dyn"}, "hypo"),
    "tlsph": Method("MACHDYN smd/tlsph dyn", {"route": "dyn"}, "pk1",
                    runs=(("beam", "beam_tlsph"),)),
    "newton-paper": Method("ICB min Newton, paper (linear/fixed, pk1)",
                           {"route": "min", "solver": "newton", "stress": "pk1", **PAPER}, "pk1"),
    "newton-quadratic": Method("ICB min Newton, quadratic/mirror, pk1",
                               {"route": "min", "solver": "newton", "stress": "pk1",
                                **QUADRATIC_MIRROR}, "pk1"),
    "newton-default": Method("ICB min Newton, defaults (exact volumes, face traction, hg 0.2)",
                             {"route": "min", "solver": "newton", "stress": "pk1", **DEFAULT},
                             "pk1"),
}

# throughput of the dynamics (esph bench): the problem whose script runs
# each style, and the variables that select it
BENCH_STYLES = {
    "icb": ("beam", {"scheme": "icb"}),
    "icb-pk1": ("beam", {"scheme": "icb", "stress": "pk1"}),
    "ccb": ("beam", {"scheme": "ccb"}),
    "ccbwat": ("beam", {"scheme": "ccbwat"}),
    "tlsph": ("beam_tlsph", {}),
    # the 3d cantilever (0.2 x 0.02 x 0.02 m) with the defaults, and MACHDYN's
    "icb3d": ("beam3d", {}),
    "tlsph3d": ("beam3d_tlsph", {}),
}


# -- the routes to the static beam of esph statics ----------------------------

# The static beam of the performance issue: Fy = -250 N, our accurate model
STATICS_MODEL = {"Fy": -250.0, "stress": "pk1", "grad": "quadratic", "clamp": "mirror"}
STATICS_ROUTES = {
    "newton": {"route": "min", "solver": "newton"},
    "newton-loose": {"route": "min", "solver": "newton", "ftol": 1.0e-3},
    "cg": {"route": "min", "solver": "cg"},
    # damped dynamics (its hourglass control, the default 0.2, it needs)
    "dyn": {"route": "dyn"},
    # the paper's corotated stress: Newton-Krylov, CG and damped dynamics,
    # against the converged corotated answer
    "newton-corotated": {"route": "min", "solver": "newton", "stress": "corotated"},
    "cg-corotated": {"route": "min", "solver": "cg", "stress": "corotated"},
    "dyn-corotated": {"route": "dyn", "stress": "corotated", "tdamp": 30.0},
}


# the linear solvers of min_style sph/newton (min_modify solver), esph bench3d
LINEAR_SOLVERS = ("direct", "mumps", "petsc")

"""The problem catalogue: every validation problem once, with its geometry,
material and loads, the example script that runs it and the variable that
loads it, the finite-element reference's parameters (esph.fe solves and
tabulates the entries of END_LOAD_PROBLEMS, GRAVITY_PROBLEMS and
CYLINDER_PROBLEMS), and the closed-form reference answers at the material
point the scripts measure.  The paper's cantilever and truss are written
once, as theory.Beam and theory.Truss; every entry of that geometry takes
them from there.

Every beam and truss script reports the centroid of the tip column, whose
particles sit at X = L - dx/2; every reference answer here is evaluated
there.  Where the load acts is a separate matter: on the last column it acts
at L - dx/2 too, a face traction acts at x = L."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import theory
from .paths import EXAMPLES

BEAM = EXAMPLES / "beam" / "in.beam"
TRUSS = EXAMPLES / "truss" / "in.truss"
BEAM_TLSPH = EXAMPLES / "beam" / "in.beam_tlsph"
BEAM3D = EXAMPLES / "beam3d" / "in.beam3d"
BEAM3D_TLSPH = EXAMPLES / "beam3d" / "in.beam3d_tlsph"
RINGS = EXAMPLES / "rings" / "in.rings"
LAME = EXAMPLES / "lame" / "in.lame"
BEAM_CYLINDER = EXAMPLES / "beam_cylinder" / "in.beam_cylinder"
FSI_PLATE = EXAMPLES / "fsi_plate" / "in.fsi_plate"
FSI_GATE = EXAMPLES / "fsi_gate" / "in.fsi_gate"

# Lame's thick-walled cylinder of examples/lame: radii a < b (m), E (Pa), nu
# and the pressure p (Pa)
LAME_GEOMETRY = {"a": 0.05, "b": 0.1, "E": 20.0e9, "nu": 0.3, "p": 2.0e4}


@dataclass(frozen=True)
class Problem:
    name: str
    dim: int
    L: float
    H: float
    E: float
    # the FE reference's loads (in path order is not required: sorted per
    # sign), the particle spacings of its tip columns and its (nu, plane)
    # pairs (plane "3d" in 3D); empty for a problem without one
    loads: tuple = ()
    dxs: tuple = ()
    cases: tuple = ()
    W: float = 0.0          # 3D width (z)
    t: float = 1.0e-3       # 2D thickness
    component: int = 1      # load direction: 0 axial, 1 transverse (y)
    symmetric_y: bool = False   # keep the solution mirror-symmetric in y (truss)
    half_z: bool = False        # 3D: model z < W/2 only, u_z = 0 on the plane z = W/2
    # mesh family (see make_mesh) and its levels (the last is stored)
    grade: dict = field(default_factory=dict)
    levels: tuple = (0, 1, 2)
    # ((nu, plane), levels) pairs: cases computed on other levels than `levels`
    case_levels: tuple = ()
    note: str = ""
    max_step: float = 1.0 / 8.0     # load increments <= max_step * max|load|
    # "end": the loads are the resultant (N) of a dead uniform traction on x = L;
    # "gravity": the loads are the acceleration component g[component] (m/s^2)
    # of a dead body force rho g per unit reference volume (the gravity
    # problems, GRAVITY_PROBLEMS)
    load_kind: str = "end"
    rho: float = 0.0                # density (kg/m^3), gravity problems
    # extra single material points reported besides the tip columns:
    # (name, x, y) (2D)
    points: tuple = ()
    # > 0: the left end is not the straight face x = 0 but the concave arc
    # x_arc(y) = -R + sqrt(R^2 - (y - H/2)^2) of a rigid cylinder of radius R
    # = clamp_radius, centre (-R, H/2), to which it is fully clamped (the
    # CYLINDER_PROBLEMS; make_mesh maps the tensor mesh onto that domain and
    # arc_mapping represents its geometry exactly)
    clamp_radius: float = 0.0
    # load_kind "plate" (PLATE_PROBLEMS): a plate of thickness H (y in [0, H]
    # here; -H < y < 0 in the example) clamped on both ends x = 0, L under a
    # water column of depth `water` and density rho_fluid standing on its top
    # face y = H (a dead uniform pressure rho_fluid |g| water) plus its own
    # weight rho |g| (per unit depth: t = 1)
    water: float = 0.0
    rho_fluid: float = 0.0

    # the example script that runs it (None: the FE reference only), the
    # example variable that sets its load (N, or m/s^2 for gy)
    script: Path | None = None
    load_var: str = ""

    @property
    def area(self) -> float:
        return self.H * (self.t if self.dim == 2 else self.W)

    @property
    def compared(self) -> str:
        """The tip displacement compared: dh (along x) or dv (along y)."""
        return "dh" if self.component == 0 else "dv"


# -- the paper's cantilever and truss: their geometry and material are
# theory.Beam's and theory.Truss's, written there once ---------------------

_BEAM = theory.Beam()
_TRUSS = theory.Truss()
# the 2D cantilever (thickness t), and the 3D one of square section (W = H)
CANTILEVER = dict(dim=2, L=_BEAM.L, H=_BEAM.H, E=_BEAM.E, t=_BEAM.t)
CANTILEVER_3D = dict(CANTILEVER, dim=3, W=_BEAM.H)
# the 3D cantilever at half the size (beam3d_short)
SHORT_CANTILEVER_3D = dict(CANTILEVER_3D, L=0.1, H=0.01, W=0.01)
BAR = dict(dim=2, L=_TRUSS.L, H=_TRUSS.H, E=_TRUSS.E, t=_TRUSS.t)
# the cantilever's end-face centre (L, H/2), a single material point of the
# gravity problems
END_CENTRE = (("end", _BEAM.L, 0.5 * _BEAM.H),)

# -- the problems with a finite-element reference (esph.fe) -------------------
# END_LOAD_PROBLEMS: a dead end traction (table data/fe_reference.json)

BEAM_LOADS = (-10.0, -25.0, -50.0, -75.0, -150.0, -250.0)
TRUSS_LOADS = (1000.0, -1000.0, 3000.0, -3000.0, 5000.0, -5000.0, 7000.0, -7000.0)

NOTE_3D = ("Half model z <= W/2 (symmetry plane u_z = 0), so dz = 0 by construction "
           "(a full model gives the same dh, dv and dz ~ 0: tests/test_fe.py). Finest mesh "
           "~1e5 DOFs (SuperLU, ~4 GB). At nu = 0 the 3D solution is exactly the 2D "
           "plane-stress one and the FE error equals that of the 2D mesh with the same (x, y) "
           "layers: 2D analogue of this family, level 2: actual error 1.2e-5, Richardson "
           "estimate 1.4e-5. At nu = 0.3 the same 2D analogue has actual error 4.2e-5 against a "
           "Richardson estimate of 2.2e-5: the clamp-corner term (layers stop at hmin) takes "
           "over at the finest level, so the nu = 0.3 estimates here may be optimistic by ~2x.")

END_LOAD_PROBLEMS = {
    "beam": Problem("beam", **CANTILEVER, loads=BEAM_LOADS, script=BEAM, load_var="Fy",
                    dxs=(0.005, 0.004, 0.002, 0.001, 0.0005, 0.00025),
                    cases=((0.0, "stress"), (0.0, "strain"), (0.3, "stress"), (0.3, "strain")),
                    grade=dict(zone_x0=0.02, zone_x1=0.02, ratio=0.25, hmin=1e-4, n_mid=8),
                    levels=(1, 2, 3)),
    "truss": Problem("truss", **BAR, loads=TRUSS_LOADS, script=TRUSS, load_var="Fx",
                     dxs=(0.01, 0.005, 0.0025, 0.002, 0.001, 0.0005),
                     cases=((0.0, "stress"), (0.0, "strain"), (0.3, "stress"), (0.3, "strain")),
                     component=0, symmetric_y=True,
                     grade=dict(zone_x0=0.025, zone_x1=0.025, ratio=0.25, hmin=1e-3, n_mid=6),
                     levels=(1, 2, 3),
                     note="nu = 0: homogeneous, exact (1-D SVK bar) on every mesh. nu = 0.3 in "
                          "compression: SVK's compressive softening at the clamped corners "
                          "(Newton fails once layers finer than ~1e-4 m resolve them) limits "
                          "hmin to 1e-3 and slows convergence at -5000/-7000 N (observed order "
                          "~1, plane strain worst)."),
    "beam3d": Problem("beam3d", **CANTILEVER_3D, loads=(-200.0, -1500.0, -5000.0),
                      dxs=(0.005, 0.004, 0.002, 0.001), cases=((0.3, "3d"), (0.0, "3d")),
                      script=BEAM3D, load_var="Fy", half_z=True, max_step=0.2,
                      grade=dict(zone_x0=0.02, zone_x1=0.02, ratio=0.25, hmin=2.5e-3, n_mid=4),
                      note=NOTE_3D),
    "beam3d_short": Problem("beam3d_short", **SHORT_CANTILEVER_3D,
                            loads=(-50.0, -400.0, -1250.0),
                            dxs=(0.0025, 0.002, 0.00125, 0.001),
                            cases=((0.3, "3d"), (0.0, "3d")), half_z=True, max_step=0.2,
                            grade=dict(zone_x0=0.01, zone_x1=0.01, ratio=0.25, hmin=1.25e-3,
                                       n_mid=4),
                            note=NOTE_3D),
}


# -- the beam under its own weight (a dead body force rho g) -------------------

# g_y in m/s^2 (g = (0, g_y)): 1 and 9.81 are linear (the table checks dv
# scales with g), 1e4 and 6e4 geometrically nonlinear (tip rotation ~0.02
# and ~0.12 rad)
GRAVITY_LOADS = (-1.0, -9.81, -1.0e4, -6.0e4)

GRAVITY_NOTE = (
    "The beam's mesh family with the geometric layers down to hmin = 1e-5 (innermost "
    "layer 2e-5 m) instead of 1e-4: at nu = 0.4 plane strain (clamp-corner exponent "
    "0.65, theory.clamp_corner_order) hmin = 1e-4 converged at observed order 2.4 and its "
    "Richardson estimate (2.0e-6) was optimistic by 2x; with 1e-5 the order is 3.3 and "
    "the estimate honest: a level-4 solve (411k DOFs) moved the stored level-3 dv by "
    "3.7e-7 (estimate 4.0e-7) and dh by 6.6e-7 (estimate 7.0e-7); hmin = 1e-6 agrees "
    "within 2e-7 but raises the Newton residual's round-off floor to 1.5e-5. dh is "
    "second order in g (zero in linear theory by the mirror symmetry about mid-height), "
    "dv odd: dv(9.81)/dv(1) = 9.81 (1 - 1.7e-10). Cross-checks (tests/test_fe.py): the "
    "end-centre dv at g = 9.81 against the Timoshenko beam (kappa = 5/6, "
    "gravity_beam_tip): -2.6e-5 (nu = 0), -0.22 % (nu = 0.3, stress), -0.96 % (nu = 0.4, "
    "strain; the clamp restrains the Poisson contraction); the axis' second difference "
    "against the exact plane-elasticity polynomial solution (gravity_elasticity_axis).")

def self_weight() -> dict:
    """What the two self-weight cantilevers share: the spacings, the load,
    the measured point, the FE mesh grading and levels (a fresh dict each,
    so that no two problems share the grading's)."""
    return dict(dxs=(0.002, 0.001, 0.0005), load_kind="gravity", rho=1000.0, points=END_CENTRE,
                grade=dict(zone_x0=0.02, zone_x1=0.02, ratio=0.25, hmin=1e-5, n_mid=8),
                levels=(1, 2, 3))


GRAVITY_PROBLEMS = {
    "beam_gravity": Problem("beam_gravity", **CANTILEVER, **self_weight(), loads=GRAVITY_LOADS,
                            cases=((0.0, "stress"), (0.3, "stress"), (0.4, "strain")),
                            script=BEAM, load_var="gy", note=GRAVITY_NOTE),
}


# -- the beam under its own weight, clamped to a rigid cylinder ----------------

CYLINDER_LOADS = (-9.81, -6.0e4)
CYLINDER_RADIUS = 0.02

CYLINDER_NOTE = (
    "The beam of beam_gravity (same mesh family in the reference coordinates (s, y), "
    "s in [0, L]) whose left end is the concave arc x_arc(y) = -R + sqrt(R^2 - (y - H/2)^2) "
    "of a rigid cylinder (R = 0.02 m, centre (-R, H/2)), fully clamped there; the mesh is "
    "mapped by x = x_arc(y) + (s/L)(L - x_arc(y)) and the element geometry is that exact "
    "map (arc_mapping: the bilinear reference rectangle composed with it), so the domain "
    "is represented exactly (area to round-off). The arc meets the free faces y = 0, H at "
    "60 degrees (90 - asin(H/(2R))); Williams exponent of that clamped-free wedge "
    "(theory.wedge_exponents): 0.869 at nu = 0.4 plane strain, 1.258 at nu = 0 plane stress "
    "(0.650 and 1 at the straight clamp's 90 degrees); observed orders 3.7-3.9. nu = 0 is "
    "computed on levels 1-3 (estimate 9.4e-7), nu = 0.4 on levels 2-4 (case_levels; "
    "estimate 8.9e-8; on levels 1-3 it was 1.4e-6, and level 4 moved that level-3 value by "
    "6.1e-7, so the estimate was honest). Cross-check "
    "against the straight-clamp table (beam_gravity): with R = 100 m every entry (levels "
    "1-3) differs from it by the geometric effect of the arc's bulge (c^2/(2R) = 5e-7 m at "
    "the corners), which goes as 1/R (R = 1e2, 1e3, 1e4, 1e8 on level 1): 7.6e-4 m/R "
    "relative in dv and 1.3e-3 m/R in dh at nu = 0.4 (6.1e-4 and 1.05e-3 at nu = 0), to "
    "within 7e-8 relative, well inside the tables' error estimates; at R = 1e8 the level-1 "
    "values equal beam_gravity's level-1 values to 3e-11 (tests/test_fe.py).")

CYLINDER_PROBLEMS = {
    "beam_cylinder": Problem("beam_cylinder", **CANTILEVER, **self_weight(), loads=CYLINDER_LOADS,
                             cases=((0.4, "strain"), (0.0, "stress")),
                             case_levels=(((0.4, "strain"), (2, 3, 4)),),
                             clamp_radius=CYLINDER_RADIUS, note=CYLINDER_NOTE),
}


# -- the hydrostatic plate of issue 35 (examples/fsi_plate) -----------------

# O'Connor & Rogers (2021) / TrixiParticles' hydrostatic_water_column_2d
# (L = 1, t = 0.05, E = 67.5 GPa, water 2 m) scaled to what a 2-core machine
# runs in minutes (studies/fsi_rheo/README.md 5.2): a plate of L/t = 10,
# water L/2 deep, E/(rho_f g H) = 2.0e4 (the real one 3.4e6), so that the
# plate's step (0.48 dx/c_s) is only 2.1 times shorter than the fluid's
# (0.1 dx/c_f) and the mid-span deflection stays small, about 3 % of t
# (linear in the load to 0.1 %; the real plate: 0.14 %).  Particle spacings
# t/n for n = 3, 4, 6, 8, 10, 12, 16 layers through the thickness.
PLATE_GEOMETRY = {"L": 0.1, "t": 0.01, "water": 0.05, "E": 1.0e7, "nu": 0.3,
                  "rho": 2700.0, "rho_fluid": 1000.0, "g": 9.81}
PLATE_LAYERS = (3, 4, 6, 8, 10, 12, 16)

PLATE_NOTE = (
    "The plate (thickness H, y in [0, H]; the example's plate is -H < y < 0) clamped on "
    "both ends (u = 0 on x = 0 and x = L: the mirror planes of fix sph/mirror) under a "
    "dead uniform pressure rho_fluid |g| water on its top face y = H plus its own weight "
    "rho g (a dead body force), plane strain, per unit depth; the load is g_y (m/s^2). "
    "Reported: the mean u_y of the two mid-span particle columns, x = L/2 -+ dx/2, "
    "y = (j + 1/2) dx (the example's mid-span deflection), and the top face's mid-point "
    "(L/2, H). Mesh: the beam's family with geometric layers toward both clamps and both "
    "faces (the four clamped corners).")

PLATE_PROBLEMS = {
    "fsi_plate": Problem("fsi_plate", dim=2, L=PLATE_GEOMETRY["L"], H=PLATE_GEOMETRY["t"],
                         E=PLATE_GEOMETRY["E"], t=1.0, loads=(-PLATE_GEOMETRY["g"],),
                         dxs=tuple(PLATE_GEOMETRY["t"] / n for n in PLATE_LAYERS),
                         cases=((PLATE_GEOMETRY["nu"], "strain"),), load_kind="plate",
                         rho=PLATE_GEOMETRY["rho"], rho_fluid=PLATE_GEOMETRY["rho_fluid"],
                         water=PLATE_GEOMETRY["water"],
                         points=(("top", 0.5 * PLATE_GEOMETRY["L"], PLATE_GEOMETRY["t"]),),
                         grade=dict(zone_x0=0.01, zone_x1=0.01, ratio=0.25, hmin=1e-5,
                                    n_mid=8),
                         levels=(1, 2, 3), max_step=0.5, script=FSI_PLATE, load_var="g",
                         note=PLATE_NOTE),
}


def plate_kirchhoff(g: float = PLATE_GEOMETRY["g"], geometry: dict = PLATE_GEOMETRY) -> float:
    """Kirchhoff's clamped-clamped mid-span deflection q L^4/(384 D) (m,
    negative = down) under q = g (rho_f water + rho t), D = E t^3/(12 (1 -
    nu^2)): a sanity line only (no shear, no clamp-corner compliance)."""
    G = geometry
    q = g * (G["rho_fluid"] * G["water"] + G["rho"] * G["t"])
    D = G["E"] * G["t"] ** 3 / (12.0 * (1.0 - G["nu"] ** 2))
    return -q * G["L"] ** 4 / (384.0 * D)


# -- the whole catalogue ------------------------------------------------------

# problems an example script runs without an FE reference of their own
SCRIPT_ONLY = {
    "beam_tlsph": Problem("beam_tlsph", **CANTILEVER, script=BEAM_TLSPH, load_var="Fy"),
    "beam3d_tlsph": Problem("beam3d_tlsph", **CANTILEVER_3D, script=BEAM3D_TLSPH, load_var="Fy"),
}

CATALOGUE = {**END_LOAD_PROBLEMS, **GRAVITY_PROBLEMS, **CYLINDER_PROBLEMS, **PLATE_PROBLEMS,
             **SCRIPT_ONLY}

# the problems the examples' driver runs by name: those with a script
PROBLEMS = {name: p for name, p in CATALOGUE.items() if p.script is not None}

# the problems with an FE reference
ALL_PROBLEMS = (*END_LOAD_PROBLEMS, *GRAVITY_PROBLEMS, *CYLINDER_PROBLEMS, *PLATE_PROBLEMS)


def problem_by_name(name: str) -> Problem:
    """The problem `name` with an FE reference: END_LOAD_PROBLEMS (end loads),
    GRAVITY_PROBLEMS, CYLINDER_PROBLEMS or PLATE_PROBLEMS."""
    for group in (END_LOAD_PROBLEMS, GRAVITY_PROBLEMS, CYLINDER_PROBLEMS, PLATE_PROBLEMS):
        if name in group:
            return group[name]
    raise KeyError(f"unknown problem {name!r}: {', '.join(ALL_PROBLEMS)}")


# -- reference answers at the material point ------------------------------------

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
    """The compared component (PROBLEMS[problem].compared) of the exact
    answer of a 2D beam or truss."""
    if problem in ("beam", "beam_tlsph"):
        return beam_exact(load, dx)[1]
    if problem == "truss":
        return truss_exact(load, dx, model)
    raise ValueError(f"no closed-form answer for {problem!r}: use continuum_tip")


# -- closed-form cross-checks of the gravity problem (not from the FE) ---------

def _plane_constants(E: float, nu: float, plane: str) -> tuple[float, float]:
    """(E', nu') that turn the plane-stress formulas into plane strain."""
    if plane == "stress":
        return E, nu
    if plane == "strain":
        return E / (1.0 - nu * nu), nu / (1.0 - nu)
    raise ValueError(f"plane must be 'stress' or 'strain', not {plane!r}")


def gravity_beam_tip(problem: Problem | str, gy: float, nu: float = 0.0,
                     plane: str = "stress", kappa: float = 5.0 / 6.0) -> float:
    """Tip deflection u_y (m; negative = down) of a Timoshenko beam (linear,
    shear-flexible, clamped: w = 0 and the cross-section's rotation = 0 at
    x = 0) under its own weight g = (0, -gy): the uniform load q = rho gy H t
    gives

        w(L) = q L^4 / (8 E' I) + q L^2 / (2 kappa G A),

    I = t H^3/12, A = H t, G = E/(2(1 + nu)), E' = E (plane stress) or
    E/(1 - nu^2) (plane strain), kappa = 5/6 (rectangle; Cowper's
    10(1+nu)/(12+11nu) is the same at nu = 0).  The shear term is
    4 E' I/(kappa G A L^2) = 2(1 + nu)(H/L)^2/(3 kappa) of the bending term
    (0.8 % at nu = 0 for H/L = 0.1)."""
    pr = problem_by_name(problem) if isinstance(problem, str) else problem
    Ep, _ = _plane_constants(pr.E, nu, plane)
    G = pr.E / (2.0 * (1.0 + nu))
    q = pr.rho * gy * pr.H * pr.t
    inertia = pr.t * pr.H ** 3 / 12.0
    return -(q * pr.L ** 4 / (8.0 * Ep * inertia) + q * pr.L ** 2 / (2.0 * kappa * G * pr.H * pr.t))


def gravity_elasticity_axis(problem: Problem | str, gy: float, X, nu: float = 0.0,
                            plane: str = "stress", clamp: str | None = None):
    """u_y (m, y up) at the axis points (X, H/2) of the exact plane-elasticity
    (linear) solution of the cantilever under its own weight g = (0, -gy):
    the polynomial (Airy) solution with the Saint-Venant (resultant) end
    conditions.  With x = L - X (from the free end), y from mid-height,
    c = H/2, w = rho gy (body force (0, -w)):

        sigma_xy = 3 w x (c^2 - y^2)/(2 c^2),   sigma_yy = w y (y^2 - c^2)/(2 c^2),
        sigma_xx = 3 w x^2 y/(2 c^2) + w (3 y/5 - y^3/c^2),
        E u_y(x, 0) = s(x) - A x + B,
        s(x) = -w x^4/(8 c^2) + (w/2)(12/5 + 5 nu/2) x^2,

    in plane stress (plane strain: E', nu' of _plane_constants).  A and B are
    a rigid motion set by the clamp, which a polynomial cannot fully fix:
    clamp = "axis" fixes the axis direction at the clamp's axis point
    (d u_y/dx = 0: E A = 3(1+nu) w L - w L^3/(2c^2) - (3/5 + nu/2) w L),
    clamp = "section" the vertical section element there (d u_x/dy = 0:
    E A = -w L^3/(2c^2) - (3/5 + nu/2) w L; the axis then tilts by its shear
    strain 3 w L/(2G)); u_y = 0 there sets B.  A fully clamped face lies
    between the two (closer to "section").  clamp = None returns s(x)/E
    only: the fully clamped beam's u_y up to a rigid motion (and effects
    decaying exponentially, over ~H, from both ends), so a second
    difference of it along the axis away from both ends is a clamp-free
    check of the FE field."""
    pr = problem_by_name(problem) if isinstance(problem, str) else problem
    Ep, nup = _plane_constants(pr.E, nu, plane)
    w = pr.rho * gy
    c = 0.5 * pr.H
    L = pr.L
    x = L - np.asarray(X, float)

    def shape(x):
        return -w * x ** 4 / (8.0 * c * c) + 0.5 * w * (2.4 + 2.5 * nup) * x ** 2

    if clamp is None:
        return shape(x) / Ep
    if clamp == "axis":
        A = 3.0 * (1.0 + nup) * w * L - w * L ** 3 / (2.0 * c * c) - (0.6 + 0.5 * nup) * w * L
    elif clamp == "section":
        A = -w * L ** 3 / (2.0 * c * c) - (0.6 + 0.5 * nup) * w * L
    else:
        raise ValueError(f"clamp must be 'axis', 'section' or None, not {clamp!r}")
    B = A * L - shape(L)
    return (shape(x) - A * x + B) / Ep

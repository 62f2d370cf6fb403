"""Exact reference solutions for the validation problems.

Cantilever elastica (inextensible Euler-Bernoulli beam, tip load of fixed
direction): theta'' + alpha cos(theta) = 0 on 0 < zeta = s/L < 1 with
theta(0) = 0, theta'(1) = 0, alpha = |F| L^2 / (E I).  With
1 + sin(theta) = 2 k^2 sin^2(phi) the solution is expressed by incomplete
elliptic integrals (scipy's ellipkinc/ellipeinc take m = k^2):

    sqrt(alpha) zeta = F(phi, k) - F(phi0, k),    sin(phi0) = 1 / (k sqrt 2)
    v(zeta)/L = zeta - 2 (E(phi, k) - E(phi0, k)) / sqrt(alpha)   (deflection)
    x(zeta)/L = (sqrt(2 sin thB) - sqrt(2 (sin thB - sin theta))) / sqrt(alpha)

and the tip angle thB solves sqrt(alpha) = K(k) - F(phi0, k), k^2 = (1 + sin thB)/2.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, special

# Table 1 of Tran-Duc et al. (2023): loads (N) and displacements (mm)
PAPER_BEAM_LOADS = (-10.0, -25.0, -50.0, -75.0, -150.0, -250.0)
PAPER_BEAM = {
    "ICB": {"dv": (-2.03, -5.07, -10.13, -15.14, -29.74, -47.66),
            "dh": (-0.013, -0.078, -0.314, -0.702, -2.716, -7.096)},
    "CCBWAT": {"dv": (-2.36, -5.88, -11.96, -18.76, -37.30, -58.65),
               "dh": (-0.013, -0.094, -0.395, -0.945, -3.816, -9.541)},
    "CCB": {"dv": (-2.33, -8.22, None, None, None, None),
            "dh": (-0.011, -0.041, None, None, None, None)},
    "theory": {"dv": (-1.95, -4.94, -9.97, -14.90, -29.34, -47.12),
               "dh": (-0.012, -0.074, -0.298, -0.667, -2.599, -6.792)},
}

# Table 3 (truss, dx = 2 mm): horizontal tip displacement in mm, None = broken
PAPER_TRUSS_LOADS = (1000.0, 3000.0, 5000.0, 7000.0, -1000.0, -3000.0, -5000.0, -7000.0)
PAPER_TRUSS = {
    "CCB": (None, None, None, None, -2.04, -6.02, -9.86, -13.59),
    "CCBWAT": (2.51, 7.15, None, None, -2.04, -6.03, -9.86, -13.59),
    "ICB": (1.96, 5.82, 9.62, 13.45, -1.98, -5.95, -10.01, -14.33),
    "theory": (2.00, 6.00, 10.00, 14.00, -2.00, -6.00, -10.00, -14.00),
}


@dataclass(frozen=True)
class Beam:
    """Cantilever of the paper: lengths in m, E in Pa, thickness t out of plane."""
    L: float = 0.2
    H: float = 0.02
    E: float = 20.0e9
    t: float = 0.001

    @property
    def inertia(self) -> float:
        return self.t * self.H ** 3 / 12.0

    def alpha(self, load: float) -> float:
        return abs(load) * self.L ** 2 / (self.E * self.inertia)


def tip_angle(alpha: float) -> float:
    """Exact tip rotation theta_B (radians) of the elastica for load parameter alpha."""
    if alpha <= 0.0:
        return 0.0

    def residual(theta_b: float) -> float:
        m = 0.5 * (1.0 + math.sin(theta_b))
        phi0 = math.asin(1.0 / math.sqrt(2.0 * m))
        return special.ellipk(m) - special.ellipkinc(phi0, m) - math.sqrt(alpha)

    # the tip angle of a tip-loaded cantilever stays below pi/2
    return optimize.brentq(residual, 1.0e-14, 0.5 * math.pi - 1.0e-12, xtol=1e-15, rtol=1e-15)


def elastica_point(alpha: float, zeta: float = 1.0) -> tuple[float, float]:
    """Displacement (dh, dv) / L of the material point zeta = s/L on the axis.

    dh is along the undeformed axis (negative: the point moves toward the
    clamp), dv is the deflection (positive, in the load direction).
    """
    if alpha <= 0.0 or zeta <= 0.0:
        return 0.0, 0.0
    theta_b = tip_angle(alpha)
    m = 0.5 * (1.0 + math.sin(theta_b))
    k = math.sqrt(m)
    phi0 = math.asin(1.0 / (k * math.sqrt(2.0)))
    sa = math.sqrt(alpha)
    # F(phi, k) = F(phi0, k) + sqrt(alpha) zeta gives phi by the Jacobi amplitude
    u = special.ellipkinc(phi0, m) + sa * zeta
    _, _, _, phi = special.ellipj(u, m)
    deflection = zeta - 2.0 * (special.ellipeinc(phi, m) - special.ellipeinc(phi0, m)) / sa
    sin_theta = 2.0 * m * math.sin(phi) ** 2 - 1.0
    sb = math.sin(theta_b)
    x = (math.sqrt(2.0 * sb) - math.sqrt(max(0.0, 2.0 * (sb - sin_theta)))) / sa
    return x - zeta, deflection


def beam_tip(beam: Beam, load: float, s: float | None = None) -> tuple[float, float]:
    """Exact (dh, dv) in m at arc length s (default: the tip) for a tip load in N.

    Signs follow the simulation: dv has the sign of the load, dh < 0.
    """
    zeta = 1.0 if s is None else s / beam.L
    dh, dv = elastica_point(beam.alpha(load), zeta)
    return dh * beam.L, math.copysign(dv * beam.L, load)


def paper_tip_angle(alpha: float) -> float:
    """The paper's asymptotic tip slope, eq. (3.3), stated for 0 < alpha < 1.5."""
    coeffs = (0.5, -4.56543e-2, 8.02901e-3, -8.59983e-4, 2.28499e-6)
    return sum(c * alpha ** (2 * k + 1) for k, c in enumerate(coeffs))


def paper_tip(alpha: float, theta_b: float | None = None) -> tuple[float, float]:
    """The paper's route to the tip (dh, dv)/L: eqs. (3.1) and (3.2) with the
    slope of eq. (3.3) (or a given theta_b).  E(mu) and E(phi, mu) are the
    complete and incomplete integrals of the second kind; scipy takes m = mu^2."""
    theta_b = paper_tip_angle(alpha) if theta_b is None else theta_b
    m = 0.5 * (1.0 + math.sin(theta_b))
    phi = math.asin(1.0 / math.sqrt(2.0 * m))
    dv = 1.0 - 2.0 / math.sqrt(alpha) * (special.ellipe(m) - special.ellipeinc(phi, m))
    dh = 1.0 - math.sqrt(2.0 * math.sin(theta_b) / alpha)
    return -dh, dv


def elastica_quadrature(alpha: float) -> tuple[float, float]:
    """Tip (dh, dv)/L by direct integration of the ODE: an independent check."""
    from scipy.integrate import solve_ivp

    def shoot(theta_b):
        # integrate from the tip (theta = thB, theta' = 0) back to the clamp
        def rhs(_, y):
            theta, dtheta, _, _ = y
            return [dtheta, -alpha * math.cos(theta), math.cos(theta), math.sin(theta)]

        sol = solve_ivp(rhs, (0.0, 1.0), [theta_b, 0.0, 0.0, 0.0], rtol=1e-12, atol=1e-14)
        return sol.y[:, -1]

    theta_b = optimize.brentq(lambda tb: shoot(tb)[0], 1e-12, 0.5 * math.pi - 1e-9, xtol=1e-14)
    _, _, xlen, ylen = shoot(theta_b)
    return xlen - 1.0, ylen


def timoshenko_shear_coefficient(nu: float) -> float:
    """Cowper's shear coefficient of a rectangular section, 5/6 at nu = 0."""
    return 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)


# Fibre law P/E = e + c2 e^2 + c3 e^3 of a fibre of engineering strain e
# (nominal stress P) for each stress measure of pair_style sph/icb at nu = 0:
# pk1 is Green strain + SVK, P = F S; corotated is the paper's P = R S = S.
FIBRE_LAWS = {"linear": (0.0, 0.0), "pk1": (1.5, 0.5), "corotated": (0.5, 0.0)}


def section_strains(beam: Beam, axial_force: float, moment: float,
                    model: str) -> tuple[float, float]:
    """Axis strain eps and curvature kappa of a section of plane fibres,
    e(y) = eps - y kappa, carrying the axial force N and the moment M."""
    c2, c3 = FIBRE_LAWS[model]
    area, inertia = beam.H * beam.t, beam.inertia
    fourth = beam.t * beam.H ** 5 / 80.0          # integral of y^4 over the section
    eps = axial_force / (beam.E * area)
    kappa = moment / (beam.E * beam.inertia)
    # N/E = A eps + c2 (A eps^2 + I k^2) + c3 (A eps^3 + 3 eps I k^2)
    # M/E = I k + 2 c2 eps I k + c3 (3 eps^2 I k + J k^3): fixed point on the
    # linear terms; the nonlinear ones are O(strain) smaller
    for _ in range(60):
        eps_new = (axial_force / beam.E - c2 * (area * eps ** 2 + inertia * kappa ** 2)
                   - c3 * (area * eps ** 3 + 3.0 * eps * inertia * kappa ** 2)) / area
        kappa_new = (moment / beam.E - 2.0 * c2 * eps * inertia * kappa
                     - c3 * (3.0 * eps ** 2 * inertia * kappa + fourth * kappa ** 3)) / inertia
        done = abs(eps_new - eps) <= 1e-15 and abs(kappa_new - kappa) * beam.H <= 1e-15
        eps, kappa = eps_new, kappa_new
        if done:
            break
    return eps, kappa


def shear_beam_tip(beam: Beam, load: float, a: float | None = None, nu: float = 0.0,
                   model: str = "pk1") -> tuple[float, float]:
    """(dh, dv) in m of the loaded end of a cantilever of length a (default L)
    under a dead transverse load, for Reissner's geometrically exact beam:
    the elastica plus shear (kappa G A) and axial compliance, with plane
    sections of fibres of the stress measure `model` (FIBRE_LAWS).

    This is the limit a 2D plane-stress continuum of the beam's aspect ratio
    tends to, not the elastica: at H/L = 0.1 it is 3 E I/(kappa G A L^2) =
    0.60 % softer for small loads (a plane-stress Q9 model of the clamped
    beam gives 0.603 %, studies/beam_error/out_continuum.txt).  With a = L -
    dx/2 it is also loaded where the particle scheme puts the load, the
    centroid of the last column; the beam beyond a carries nothing.

    Equations, arc length s of the reference axis, section force n = (0, F):
      theta' = kappa(N, M),   M' = -F x',   M(a) = 0,
      x' = (1 + eps) cos(theta) - gamma sin(theta),
      y' = (1 + eps) sin(theta) + gamma cos(theta),
      N = F sin(theta),   eps = eps(N, M),   gamma = F cos(theta)/(kappa_s G A),
    solved by shooting on the clamp moment M(0)."""
    from scipy.integrate import solve_ivp

    a = beam.L if a is None else a
    shear = (timoshenko_shear_coefficient(nu) * beam.E / (2.0 * (1.0 + nu))
             * beam.H * beam.t)
    if load == 0.0:
        return 0.0, 0.0

    def rhs(_, state):
        theta, moment, _, _ = state
        c, s = math.cos(theta), math.sin(theta)
        eps, kappa = section_strains(beam, load * s, moment, model)
        gamma = load * c / shear
        dx_ds = (1.0 + eps) * c - gamma * s
        return [kappa, -load * dx_ds, dx_ds, (1.0 + eps) * s + gamma * c]

    def end_state(moment0):
        sol = solve_ivp(rhs, (0.0, a), [0.0, moment0, 0.0, 0.0], rtol=1e-12, atol=1e-16,
                        method="DOP853")
        return sol.y[:, -1]

    # M(0) = F x(a) and the end moves toward the clamp: M(0) lies between 0 and 1.1 F a
    moment0 = optimize.brentq(lambda m0: end_state(m0)[1], 0.0, 1.1 * load * a,
                              xtol=1e-14 * abs(load) * a, rtol=1e-14)
    _, _, x_end, y_end = end_state(moment0)
    return x_end - a, y_end


# Truss (section 3.2): axial load on a bar of Green strain + SVK material
# Table 2 (beam, ICB): relative errors in % of the tip (dv, dh) per dx in mm
PAPER_BEAM_CONVERGENCE = {
    -75.0: {5.0: (19.59, 47.98), 4.0: (11.14, 26.69), 2.0: (1.61, 5.25), 1.0: (0.26, 0.45),
            0.5: (0.03, 0.05)},
    -150.0: {5.0: (18.54, 45.40), 4.0: (10.53, 25.78), 2.0: (1.36, 4.50), 1.0: (0.17, 1.57),
             0.5: (0.02, 0.1)},
    -250.0: {5.0: (16.79, 41.70), 4.0: (9.72, 24.41), 2.0: (1.15, 4.48), 1.0: (0.04, 2.02),
             0.5: (0.0, 0.2)},
}

# Table 4 (truss, ICB): relative error in % of the tip dh per dx in mm
PAPER_TRUSS_CONVERGENCE = {
    3000.0: {10.0: 8.67, 5.0: 5.17, 2.0: 3.00, 1.0: 1.83, 0.5: 0.11},
    5000.0: {10.0: 9.70, 5.0: 6.10, 2.0: 3.80, 1.0: 3.00, 0.5: 0.19},
    7000.0: {10.0: 10.50, 5.0: 6.86, 2.0: 3.93, 1.0: 2.50, 0.5: 0.22},
    -3000.0: {10.0: 4.20, 5.0: 1.67, 2.0: 0.83, 1.0: 0.72, 0.5: 0.06},
    -5000.0: {10.0: 4.60, 5.0: 1.50, 2.0: 0.1, 1.0: 0.05, 0.5: 0.0},
    -7000.0: {10.0: 6.36, 5.0: 3.21, 2.0: 2.36, 1.0: 1.00, 0.5: 0.02},
}


@dataclass(frozen=True)
class Truss:
    L: float = 0.2
    H: float = 0.05
    E: float = 2.0e9
    t: float = 0.001

    @property
    def area(self) -> float:
        return self.H * self.t

    def linear(self, load: float) -> float:
        """The paper's theory, eq. (3.4): delta = F L/(A E)."""
        return load * self.L / (self.area * self.E)

    def stretch(self, load: float, model: str) -> float:
        """Exact uniaxial stretch lambda of the bar (nu = 0: no lateral strain,
        so the area stays A) for the constitutive model a scheme runs:
          pk1        Green strain + SVK, P = F S:  lambda (lambda^2 - 1) E/2 = F/A
          corotated  the paper's P = R S = S:      (lambda^2 - 1) E/2 = F/A
          hypo       CCB's Jaumann rate:           E ln(lambda) = F/A"""
        s = load / (self.area * self.E)
        if model == "corotated":
            return math.sqrt(1.0 + 2.0 * s)
        if model == "hypo":
            return math.exp(s)
        if model == "pk1":
            # lambda^3 - lambda - 2 s = 0, the root continuous from lambda = 1
            return optimize.brentq(lambda lam: lam ** 3 - lam - 2.0 * s, 0.58, 3.0)
        raise ValueError(f"unknown truss model {model!r}: pk1, corotated or hypo")

    def displacement(self, load: float, model: str, X: float | None = None) -> float:
        """Axial displacement of material point X (default the free end L)."""
        X = self.L if X is None else X
        return (self.stretch(load, model) - 1.0) * X


@dataclass(frozen=True)
class Impact:
    """A quasi-static elastic impact of two bodies, from first touch to
    separation (what `hertz_impact` and `flat_contact_impact` return)."""
    duration: float          # s, contact duration t_c
    force_max: float         # N, largest contact force
    approach_max: float      # m, largest mutual approach delta* of the two bodies
    contact_radius: float    # m, radius a of the contact circle at delta*
    pressure_max: float      # Pa, largest contact pressure (Hertz: central p0 = 3 F/(2 pi a^2))


def hertz_impact(R1: float, E1: float, nu1: float, m1: float, v: float,
                 R2: float | None = None, E2: float | None = None, nu2: float | None = None,
                 m2: float | None = None) -> Impact:
    """Head-on impact of two elastic spheres at the relative approach speed
    v (twice the speed of each when both move towards the other at the same
    speed); sphere 2 defaults to a copy of sphere 1.

    Hertz's contact (H. Hertz, J. reine angew. Math. 92, 156, 1882; K. L.
    Johnson, Contact Mechanics, Cambridge 1985, section 11.4) with
    1/R* = 1/R1 + 1/R2, 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 and
    1/m* = 1/m1 + 1/m2 (two identical spheres: R* = R/2, E* = E/(2 (1 - nu^2)),
    m* = m/2): the force at a mutual approach delta is
    F = (4/3) E* R*^(1/2) delta^(3/2), the largest approach follows from the
    energy, m* v^2/2 = (8/15) E* R*^(1/2) delta*^(5/2), and the time from
    first touch to separation is
        t_c = 2 (delta*/v) int_0^1 dx/sqrt(1 - x^(5/2)) = 2.943 delta*/v
            = 2.87 (m*^2/(R* E*^2 v))^(1/5).
    Quasi-static: it holds while t_c is long against the time elastic waves
    take to cross the spheres and the contact radius is small against R*."""
    R2 = R1 if R2 is None else R2
    E2 = E1 if E2 is None else E2
    nu2 = nu1 if nu2 is None else nu2
    m2 = m1 if m2 is None else m2
    Rs = 1.0 / (1.0 / R1 + 1.0 / R2)
    Es = 1.0 / ((1.0 - nu1 ** 2) / E1 + (1.0 - nu2 ** 2) / E2)
    ms = 1.0 / (1.0 / m1 + 1.0 / m2)
    delta = (15.0 * ms * v ** 2 / (16.0 * Es * math.sqrt(Rs))) ** 0.4
    force = 4.0 / 3.0 * Es * math.sqrt(Rs) * delta ** 1.5
    a = math.sqrt(Rs * delta)
    # int_0^1 (1 - x^(5/2))^(-1/2) dx = (2/5) B(2/5, 1/2) = 1.4716
    duration = 2.0 * 0.4 * float(special.beta(0.4, 0.5)) * delta / v
    return Impact(duration, force, delta, a, 1.5 * force / (math.pi * a ** 2))


def flat_contact_impact(area: float, E: float, nu: float, m: float, v: float,
                        k_contact: float = math.inf) -> Impact:
    """Head-on impact of two identical bodies of mass m at relative speed v
    that touch over a flat face of the given area, as two spheres built on a
    cubic lattice do with the flat facet at their poles while the approach is
    small against the lattice step.  The mid-plane between them stays plane
    by symmetry, so each body is pressed about as by a rigid flat punch, here
    the circle of the same area, a = sqrt(area/pi), on a half-space:
    stiffness 2 a E/(1 - nu^2) (Boussinesq's flat-ended punch; K. L. Johnson,
    Contact Mechanics, Cambridge 1985, chapter 3).  The two bodies act in
    series, and with them the stiffness k_contact of the contact itself (fix
    sph/contact: the springs of the facet's particle pairs, N dx K/2 in 3d).
    A linear spring: the contact lasts half a period, t_c = pi sqrt(m*/k),
    m* = m/2, whatever the speed, and the largest force is v sqrt(m* k).  It
    leaves out the compliance of a sphere's finite size and its waves, so a
    sphere's contact lasts somewhat longer."""
    a = math.sqrt(area / math.pi)
    k_body = 2.0 * a * E / (1.0 - nu ** 2)
    k = 1.0 / (2.0 / k_body + 1.0 / k_contact)
    ms = 0.5 * m
    force = v * math.sqrt(ms * k)
    return Impact(math.pi * math.sqrt(ms / k), force, force / k, a, force / area)


# Corner singularities (M. L. Williams, "Stress singularities resulting from
# various boundary conditions in angular corners of plates in extension",
# J. Appl. Mech. 19, 526-528, 1952).  Near the corner of a wedge of opening
# angle alpha the displacement goes as r^lambda, the stress as r^(lambda-1).
# With the Kolosov-Muskhelishvili potentials phi = a z^lambda and
# psi = b z^lambda (a, b complex, lambda real), on an edge theta = const
#     traction free:  phi + z conj(phi') + conj(psi) = 0
#     clamped:        kappa phi - z conj(phi') - conj(psi) = 0      (2 mu u = ...)
# which, divided by r^lambda, is
#     c_a a + c_abar conj(a) + c_bbar conj(b) = 0
# with c_a = e^(i lambda theta) (kappa e^(i lambda theta) when clamped),
# c_abar = +-lambda e^(i (2 - lambda) theta), c_bbar = +-e^(-i lambda theta)
# (+ free, - clamped).  Two edges give four real equations in Re/Im a, b;
# lambda is an exponent where their determinant vanishes.
WEDGE_EDGES = ("free", "clamped")


def kolosov_kappa(nu: float, plane: str) -> float:
    """Kolosov's constant: (3 - nu)/(1 + nu) in plane stress, 3 - 4 nu in
    plane strain (and along a straight edge of a 3d body, which is locally in
    plane strain)."""
    if plane == "stress":
        return (3.0 - nu) / (1.0 + nu)
    if plane in ("strain", "3d"):
        return 3.0 - 4.0 * nu
    raise ValueError(f"plane must be 'stress', 'strain' or '3d', not {plane!r}")


def _edge_equations(edge: str, lam: float, theta: float, kappa: float):
    """The two real rows (real and imaginary part) of one edge's condition,
    columns Re a, Im a, Re b, Im b."""
    sign = 1.0 if edge == "free" else -1.0
    c_a = (1.0 if edge == "free" else kappa) * np.exp(1j * lam * theta)
    c_abar = sign * lam * np.exp(1j * (2.0 - lam) * theta)
    c_bbar = sign * np.exp(-1j * lam * theta)
    # a = a1 + i a2: c_a a + c_abar conj(a) = (c_a + c_abar) a1 + i (c_a - c_abar) a2
    cols = np.array([c_a + c_abar, 1j * (c_a - c_abar), c_bbar, -1j * c_bbar])
    return np.vstack([cols.real, cols.imag])


def wedge_determinant(lam: float, angle: float, edges: tuple[str, str], kappa: float) -> float:
    """Determinant of the corner's homogeneous conditions for the exponent lam:
    edge edges[0] at theta = 0, edges[1] at theta = angle."""
    for edge in edges:
        if edge not in WEDGE_EDGES:
            raise ValueError(f"edge must be one of {WEDGE_EDGES}, not {edge!r}")
    rows = np.vstack([_edge_equations(edges[0], lam, 0.0, kappa),
                      _edge_equations(edges[1], lam, angle, kappa)])
    return float(np.linalg.det(rows))


def wedge_exponents(angle: float, edges: tuple[str, str], kappa: float,
                    upper: float = 1.5, samples: int = 3000) -> list[float]:
    """The real exponents lambda in (0, upper] of a wedge's corner fields,
    ascending.  Roots are found where the determinant changes sign, so a
    root of even multiplicity (the crack's double 1/2) and the complex
    exponents of, for example, a clamped-free half-plane are not listed.
    For two free edges lambda = 1 includes the rigid rotation."""
    grid = np.linspace(1e-3, upper, samples)
    values = [wedge_determinant(lam, angle, edges, kappa) for lam in grid]
    roots = []
    for lo, hi, f_lo, f_hi in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if f_lo == 0.0:
            roots.append(float(lo))
        elif f_lo * f_hi < 0.0:
            roots.append(optimize.brentq(wedge_determinant, lo, hi, xtol=1e-14,
                                         args=(angle, edges, kappa)))
    return roots


def clamp_corner_order(nu: float, plane: str) -> tuple[float, float]:
    """(lambda, q_max) at the corner where a clamped face meets a free face
    at a right angle (a cantilever's clamp).  The displacement near it goes as
    r^lambda; lambda = 1 at nu = 0, where the clamp does not stop a Poisson
    contraction, and below 1 for nu > 0, where the stress is singular.  A
    tip displacement, a functional whose dual problem has the same corner,
    then converges on uniform resolution at the order q_max = min(2, 2 lambda)
    at best (Strang and Fix, An Analysis of the Finite Element Method, 1973,
    ch. 8), whatever the scheme's own order."""
    lam = wedge_exponents(0.5 * math.pi, ("clamped", "free"), kolosov_kappa(nu, plane))[0]
    return lam, min(2.0, 2.0 * lam)


def lame_cylinder(r: float, a: float, b: float, E: float, nu: float, plane: str,
                  p_in: float = 0.0, p_out: float = 0.0) -> tuple[float, float, float]:
    """(u_r, sigma_rr, sigma_tt) at radius r of a thick-walled cylinder a < r < b
    under the pressures p_in inside and p_out outside, small strain (Lame):
        sigma_rr = A - B/r^2,  sigma_tt = A + B/r^2,
        A = (p_in a^2 - p_out b^2)/(b^2 - a^2),  B = (p_in - p_out) a^2 b^2/(b^2 - a^2),
    and u_r = r eps_tt with eps_tt = (sigma_tt - nu sigma_rr)/E in plane stress
    (a thin disk) and ((1 - nu) sigma_tt - nu sigma_rr)(1 + nu)/E in plane
    strain (a long tube)."""
    if plane not in ("stress", "strain"):
        raise ValueError(f"plane must be 'stress' or 'strain', not {plane!r}")
    A = (p_in * a * a - p_out * b * b) / (b * b - a * a)
    B = (p_in - p_out) * a * a * b * b / (b * b - a * a)
    srr, stt = A - B / (r * r), A + B / (r * r)
    if plane == "stress":
        eps_tt = (stt - nu * srr) / E
    else:
        eps_tt = (1.0 + nu) / E * ((1.0 - nu) * stt - nu * srr)
    return r * eps_tt, srr, stt


def clamped_cylinder(r: float, a: float, b: float, E: float, nu: float, plane: str,
                     p_out: float) -> tuple[float, float, float]:
    """(u_r, sigma_rr, sigma_tt) at radius r of a thick-walled cylinder a < r < b
    clamped on its inner surface (u_r(a) = 0) under a pressure p_out outside,
    small strain: u_r = C (r - a^2/r), so that
        sigma_rr = 2 (lam + mu) C + 2 mu C a^2/r^2,  sigma_tt = 2 (lam + mu) C - 2 mu C a^2/r^2,
    with sigma_rr(b) = -p_out; lam is Lame's first parameter in plane strain
    and 2 lam mu/(lam + 2 mu) in plane stress."""
    if plane not in ("stress", "strain"):
        raise ValueError(f"plane must be 'stress' or 'strain', not {plane!r}")
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    if plane == "stress":
        lam = 2.0 * lam * mu / (lam + 2.0 * mu)
    C = -p_out / (2.0 * (lam + mu) + 2.0 * mu * a * a / (b * b))
    srr = 2.0 * (lam + mu) * C + 2.0 * mu * C * a * a / (r * r)
    stt = 2.0 * (lam + mu) * C - 2.0 * mu * C * a * a / (r * r)
    return C * (r - a * a / r), srr, stt

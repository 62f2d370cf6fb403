"""The finite-element meshes of esph.fe: tensor-product families with
geometric layers toward the corners (make_mesh), the uniform peer of a
particle model (uniform_mesh), and the exact geometry of the beam clamped to
a rigid cylinder (arc_map, arc_mapping); see esph.fe's documentation."""
from __future__ import annotations

import math

import numpy as np

from ..problems import Problem


def layered_nodes(length: float, zone0: float, zone1: float, ratio: float, hmin: float,
                  n_mid: int, m: int) -> np.ndarray:
    """Nodes on [0, length]: geometric layers toward each end that has a zone
    > 0 (layer boundaries zone, zone*ratio, zone*ratio^2, ... down to the
    last one >= hmin), a uniform middle part of n_mid elements, and every
    layer and middle element split into m equal elements.

    The layers resolve the corner singularities (clamped corners r^lambda,
    loaded corners r log r); refining by m = 1, 2, 4, ... halves every
    element (the innermost layer too), so the meshes of a family differ by
    h only, as Richardson extrapolation wants.  hmin stays >= 1e-4 (see the
    module doc: thinner layers along a slender body cost accuracy in
    round-off)."""
    def layer_bounds(zone):
        if zone <= 0.0:
            return np.array([0.0])
        k = int(math.floor(math.log(hmin / zone) / math.log(ratio) + 1e-9))
        return np.r_[0.0, zone * ratio ** np.arange(k, -1, -1)]

    def split(bounds):
        return np.concatenate([np.linspace(a, b, m + 1)[:-1]
                               for a, b in zip(bounds[:-1], bounds[1:])] + [bounds[-1:]])

    left = split(layer_bounds(zone0))
    right = length - split(layer_bounds(zone1))[::-1]
    mid_len = length - zone0 - zone1
    if mid_len > 1e-12 * length:
        mid = np.linspace(zone0, length - zone1, n_mid * m + 1)
        nodes = np.concatenate([left[:-1], mid, right[1:]])
    else:
        nodes = np.concatenate([left[:-1], [zone0], right[1:]])
    nodes[0], nodes[-1] = 0.0, length
    if np.any(np.diff(nodes) <= 0.0):
        raise ValueError("layered_nodes: nodes not increasing")
    return nodes


def make_mesh(problem: Problem, level: int, grade: dict | None = None,
              half_z: bool | None = None):
    """The level-th mesh (elements split into m = 2^level) of the problem's
    tensor-product family `problem.grade` (updated by `grade`):
    zone_x0, zone_x1: the layered zones at the clamp and at the loaded end;
    ratio, hmin: the geometric layers; n_mid: elements of the uniform middle
    in x at level 0; in y and z the layers run from mid-height to both faces.
    half_z (default: the problem's) keeps z <= W/2 of a 3D mesh."""
    import skfem

    g = dict(problem.grade)
    g.update(grade or {})
    m = 2 ** level
    xs = layered_nodes(problem.L, g["zone_x0"], g["zone_x1"], g["ratio"], g["hmin"],
                       g["n_mid"], m)
    ys = layered_nodes(problem.H, 0.5 * problem.H, 0.5 * problem.H, g["ratio"], g["hmin"],
                       0, m)
    if problem.dim == 2:
        mesh = skfem.MeshQuad.init_tensor(xs, ys)
        if problem.clamp_radius > 0.0:
            # the (s, y) tensor mesh mapped onto the domain right of the arc
            # (the vertices exactly; the elements' geometry: arc_mapping)
            mesh = skfem.MeshQuad(arc_map(problem, mesh.p), mesh.t)
        return mesh
    zs = layered_nodes(problem.W, 0.5 * problem.W, 0.5 * problem.W, g["ratio"], g["hmin"],
                       0, m)
    if problem.half_z if half_z is None else half_z:
        zs = zs[zs <= 0.5 * problem.W * (1 + 1e-12)]
    return skfem.MeshHex.init_tensor(xs, ys, zs)


def arc_x(problem: Problem, y):
    """x_arc(y) = -R + sqrt(R^2 - (y - H/2)^2), the clamped arc (<= 0), in the
    cancellation-free form -(y - H/2)^2 / (R + sqrt(R^2 - (y - H/2)^2))."""
    R = problem.clamp_radius
    q = np.asarray(y, float) - 0.5 * problem.H
    return -q * q / (R + np.sqrt(R * R - q * q))


def arc_x_dy(problem: Problem, y):
    """d x_arc / dy = -(y - H/2) / sqrt(R^2 - (y - H/2)^2)."""
    R = problem.clamp_radius
    q = np.asarray(y, float) - 0.5 * problem.H
    return -q / np.sqrt(R * R - q * q)


def arc_map(problem: Problem, S):
    """The map (s, y) -> (x_arc(y) + (s/L)(L - x_arc(y)), y) of the reference
    rectangle [0, L] x [0, H] onto the cylinder problem's domain (S: (2, ...))."""
    S = np.asarray(S, float)
    a = arc_x(problem, S[1])
    return np.stack([a + S[0] / problem.L * (problem.L - a), S[1]])


def arc_unmap(problem: Problem, P):
    """The inverse of arc_map: (x, y) -> (s, y)."""
    P = np.asarray(P, float)
    a = arc_x(problem, P[1])
    return np.stack([problem.L * (P[0] - a) / (problem.L - a), P[1]])


def cylinder_exact_area(problem: Problem) -> float:
    """The exact area of the cylinder problem's domain: L H plus the area
    between the arc and x = 0, H R - c sqrt(R^2 - c^2) - R^2 asin(c/R), c = H/2
    (evaluated without cancellation as the integral of c'^2/(R + sqrt(R^2 - c'^2))
    for large R)."""
    R, c = problem.clamp_radius, 0.5 * problem.H
    if R > 100.0 * c:
        from scipy.integrate import quad

        extra = quad(lambda q: q * q / (R + math.sqrt(R * R - q * q)), -c, c,
                     epsabs=0.0, epsrel=1e-13)[0]
    else:
        extra = problem.H * R - c * math.sqrt(R * R - c * c) - R * R * math.asin(c / R)
    return problem.L * problem.H + extra


def cylinder_corner(problem: Problem, nu: float, plane: str) -> tuple[float, float, float]:
    """(angle, lambda, 2 lambda) at the corners where the clamped arc meets the
    free faces y = 0, H: the material wedge between the face (along +x) and
    the arc's tangent, angle = pi/2 - asin(H/(2R)) (radians; 60 degrees for
    R = H), and the leading real Williams exponent of that clamped-free
    wedge (theory.wedge_exponents) with the order bound 2 lambda of a tip
    functional on uniform resolution (theory.clamp_corner_order at 90
    degrees)."""
    from ..theory import kolosov_kappa, wedge_exponents

    angle = 0.5 * math.pi - math.asin(0.5 * problem.H / problem.clamp_radius)
    lam = wedge_exponents(angle, ("clamped", "free"), kolosov_kappa(nu, plane))[0]
    return angle, lam, 2.0 * lam


def arc_mapping(problem: Problem, mesh):
    """The exact geometry of a mesh of make_mesh for a cylinder problem: each
    element is the bilinear image of the reference square in (s, y) (a
    rectangle there), composed with arc_map, so the arc is represented exactly
    (not by the quadratic interpolation a MeshQuad2 would give).  F, the
    Jacobian and the (round-off tolerant) inverse of _mapping; the facet maps
    are those of the (s, y) mesh and are not used (no face loads here)."""
    import skfem

    ref = skfem.MeshQuad(arc_unmap(problem, mesh.p), mesh.t)
    base = type(_mapping(ref))

    class ArcMapping(base):
        def F(self, X, tind=None):
            return arc_map(problem, super().F(X, tind))

        def J(self, i, j, X, tind=None):
            if i == 1:
                return super().J(1, j, X, tind)
            S = super().F(X, tind)
            a = arc_x(problem, S[1])
            da = arc_x_dy(problem, S[1])
            # dx/ds = (L - a)/L, dx/dy = a' (1 - s/L)
            return ((problem.L - a) / problem.L * super().J(0, j, X, tind)
                    + da * (1.0 - S[0] / problem.L) * super().J(1, j, X, tind))

    return ArcMapping(ref, ref.elem(), ref.bndelem)


def arc_clamp_facets(problem: Problem, mesh) -> np.ndarray:
    """The boundary facets of a cylinder problem's mesh on the arc (s = 0)."""
    s = arc_unmap(problem, mesh.p)[0]
    f = mesh.boundary_facets()
    on = np.all(np.abs(s[mesh.facets[:, f]]) <= 1e-9 * problem.L, axis=0)
    return f[on]


def uniform_mesh(problem: Problem, node_spacing: float):
    """A uniform 2D Q2 mesh of the problem with nodes node_spacing apart
    (elements twice that): the uniform-resolution peer of a particle model
    with spacing dx = node_spacing, which, unlike the graded reference
    meshes, does not resolve the clamp's corner singularity."""
    import skfem

    if problem.dim != 2:
        raise ValueError(f"uniform_mesh is 2D only; {problem.name} is {problem.dim}D")
    element = 2.0 * node_spacing
    xs = np.linspace(0.0, problem.L, int(round(problem.L / element)) + 1)
    ys = np.linspace(0.0, problem.H, int(round(problem.H / element)) + 1)
    return skfem.MeshQuad.init_tensor(xs, ys)


def _is_box_mesh(mesh) -> bool:
    """Every element an axis-parallel box (each vertex coordinate is its
    element's min or max in that direction)."""
    P = mesh.p[:, mesh.t]                                          # (dim, nverts, ne)
    lo, hi = P.min(axis=1, keepdims=True), P.max(axis=1, keepdims=True)
    ok = (P == lo) | (P == hi)
    # a box has exactly 2^dim vertices, each corner once
    return bool(ok.all()) and P.shape[1] == 2 ** P.shape[0] and bool(
        np.all(np.sum(P == lo, axis=1) == 2 ** (P.shape[0] - 1)))


def _mapping(mesh):
    """The mesh's isoparametric map, with an inverse (used by facet bases and
    probes) that accepts the round-off floor: skfem's asks for a Newton
    correction below 1e-12 in reference coordinates, which the strongly
    graded meshes cannot give (elements 1e-6 of the body's size, where the
    round-off of x, 1e-16 |x|, is already 1e-10 of the element)."""
    from skfem.mapping import MappingIsoparametric

    class Mapping(MappingIsoparametric):
        def invF(self, x, tind=None, newton_max_iters=50, newton_tol=1e-12):
            X = np.zeros(x.shape) + 0.5
            last = np.inf
            for it in range(newton_max_iters):
                dX = np.einsum("ijkl,jkl->ikl", self.invDF(X, tind), x - self.F(X, tind))
                X = np.clip(X + dX, 0.0, 1.0)
                step = np.abs(dX).max() if dX.size else 0.0
                if step < newton_tol or (it >= 2 and step >= 0.5 * last and step < 1e-6):
                    return X
                last = step
            raise RuntimeError(f"inverse map did not converge ({last:.1e})")

    return Mapping(mesh, mesh.elem(), mesh.bndelem)

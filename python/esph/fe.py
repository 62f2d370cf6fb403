"""Nonlinear finite-element reference (scikit-fem) for the static validation problems.

An independent, mesh-converged continuum answer for what the particle code
discretises: total-Lagrangian St. Venant-Kirchhoff (SVK) solids,

    E = (F^T F - I)/2,   S = lambda tr(E) I + 2 mu E,   P = F S,
    psi = lambda/2 tr(E)^2 + mu E:E,

with mu = E/(2(1+nu)), lambda = E nu/((1+nu)(1-2nu)).  In 2D "strain" uses
these on 2x2 tensors, "stress" replaces lambda by lambda* = 2 lambda mu /
(lambda + 2 mu) (the particle code's plane-stress law, not the exact
finite-strain condensation); 2D bodies have thickness t.

Boundary conditions: the face x = 0 fully clamped, a dead uniform traction
on x = L whose resultant is the load, all other faces free.

Discretisation: biquadratic Lagrange quadrilaterals (scikit-fem ElementQuad2,
9 nodes) in 2D and triquadratic hexahedra (ElementHex2, 27 nodes) in 3D on
tensor-product meshes with geometric layers toward the clamp, the loaded end
and the faces y = 0, H (z = 0, W), where the corner singularities sit
(make_mesh), 3x3(x3) Gauss points.  scikit-fem provides the mesh, the
element, the quadrature and the gradients of the basis, the end-face load
vector and the point evaluation; the SVK residual and tangent are assembled
here with numpy (vectorised over the elements).  Newton's method with load
stepping (the loads of one (problem, nu, plane) are one continuation path)
solves each state to |r| <= 1e-10 |f|, or to a Newton correction below
1e-12 |u| where round-off keeps |r| above that (SVKSolver.newton).  The 3D
beams are modelled on z <= W/2 with the symmetry plane z = W/2 (u_z = 0
there; the solution is mirror-symmetric, so the tip-column mean of u_z is
0); the truss is kept on its straight, mirror-symmetric branch past
buckling by projecting every Newton iterate on that symmetry.

What is reported is the particle code's "tip column": the mean of the FE
displacement over the material points x = L - dx/2, y = (j + 1/2) dx (and
z = (k + 1/2) dx in 3D), evaluated in the FE field (scikit-fem probes).

The table python/esph/data/fe_reference.json holds, per entry, the value on
the finest of three meshes refined by 2 and a Richardson estimate of its
error; `tip()` reads it, `python -m esph.fe --write` regenerates it.

Two limits of the continuum found on the way (see make_mesh):
* the geometric layers stop at hmin: 1e-6-thin layers running the length of
  the slender beam made the discrete system so ill-conditioned that the
  round-off floor moved the tip by 5e-6 (checked against uniform meshes of
  this code and of studies/beam_error/fe_continuum.py); at hmin = 1e-4 the
  layered and uniform families agree;
* SVK softens under compression (uniaxially it has no stiffness left at a
  stretch of 1/sqrt(3)); at the clamped corners of the compressed truss and
  of the beam's compressed fibre the nu = 0.3 corner singularity drives the
  strain there in the smallest elements past that point, and Newton fails
  (the continuum problem has no smooth solution in a core of radius ~1e-5 m
  at the largest loads).  The layers toward those corners stop at hmin =
  1e-3 (truss) or 1e-4 (beam); the entries whose convergence this slows
  have the larger error estimates (truss, nu = 0.3, -7000 N).
"""
from __future__ import annotations

import argparse
import datetime
import json
import math
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .problems import tip_point

TABLE = Path(__file__).resolve().parent / "data" / "fe_reference.json"
REGENERATE = "python -m esph.fe --write"


# ----------------------------------------------------------------------------
# problems
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class Problem:
    name: str
    dim: int
    L: float
    H: float
    E: float
    loads: tuple            # in path order is not required: sorted per sign
    dxs: tuple
    cases: tuple            # (nu, plane) pairs; plane "3d" in 3D
    W: float = 0.0          # 3D width (z)
    t: float = 1.0e-3       # 2D thickness
    component: int = 1      # load direction: 0 axial, 1 transverse (y)
    symmetric_y: bool = False   # keep the solution mirror-symmetric in y (truss)
    half_z: bool = False        # 3D: model z < W/2 only, u_z = 0 on the plane z = W/2
    # mesh family (see make_mesh) and its levels (the last is stored)
    grade: dict = field(default_factory=dict)
    levels: tuple = (0, 1, 2)
    note: str = ""
    max_step: float = 1.0 / 8.0     # load increments <= max_step * max|load|

    @property
    def area(self) -> float:
        return self.H * (self.t if self.dim == 2 else self.W)


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

PROBLEMS = {
    "beam": Problem("beam", 2, 0.2, 0.02, 20.0e9, BEAM_LOADS,
                    (0.005, 0.004, 0.002, 0.001, 0.0005, 0.00025),
                    ((0.0, "stress"), (0.0, "strain"), (0.3, "stress"), (0.3, "strain")),
                    grade=dict(zone_x0=0.02, zone_x1=0.02, ratio=0.25, hmin=1e-4, n_mid=8),
                    levels=(1, 2, 3)),
    "truss": Problem("truss", 2, 0.2, 0.05, 2.0e9, TRUSS_LOADS,
                     (0.01, 0.005, 0.0025, 0.002, 0.001, 0.0005),
                     ((0.0, "stress"), (0.0, "strain"), (0.3, "stress"), (0.3, "strain")),
                     component=0, symmetric_y=True,
                     grade=dict(zone_x0=0.025, zone_x1=0.025, ratio=0.25, hmin=1e-3, n_mid=6),
                     levels=(1, 2, 3),
                     note="nu = 0: homogeneous, exact (1-D SVK bar) on every mesh. nu = 0.3 in "
                          "compression: SVK's compressive softening at the clamped corners "
                          "(Newton fails once layers finer than ~1e-4 m resolve them) limits "
                          "hmin to 1e-3 and slows convergence at -5000/-7000 N (observed order "
                          "~1, plane strain worst)."),
    "beam3d": Problem("beam3d", 3, 0.2, 0.02, 20.0e9, (-200.0, -1500.0, -5000.0),
                      (0.005, 0.004, 0.002, 0.001), ((0.3, "3d"), (0.0, "3d")),
                      W=0.02, half_z=True, max_step=0.2,
                      grade=dict(zone_x0=0.02, zone_x1=0.02, ratio=0.25, hmin=2.5e-3, n_mid=4),
                      note=NOTE_3D),
    "beam3d_short": Problem("beam3d_short", 3, 0.1, 0.01, 20.0e9, (-50.0, -400.0, -1250.0),
                            (0.0025, 0.002, 0.00125, 0.001), ((0.3, "3d"), (0.0, "3d")),
                            W=0.01, half_z=True, max_step=0.2,
                            grade=dict(zone_x0=0.01, zone_x1=0.01, ratio=0.25, hmin=1.25e-3,
                                       n_mid=4),
                            note=NOTE_3D),
}


def lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """(lambda, mu) of the law the particle code runs (see module doc)."""
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    if plane == "stress":
        lam = 2.0 * lam * mu / (lam + 2.0 * mu)
    elif plane not in ("strain", "3d"):
        raise ValueError(f"plane must be 'stress', 'strain' or '3d', not {plane!r}")
    return lam, mu


# ----------------------------------------------------------------------------
# meshes
# ----------------------------------------------------------------------------

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
        return skfem.MeshQuad.init_tensor(xs, ys)
    zs = layered_nodes(problem.W, 0.5 * problem.W, 0.5 * problem.W, g["ratio"], g["hmin"],
                       0, m)
    if problem.half_z if half_z is None else half_z:
        zs = zs[zs <= 0.5 * problem.W * (1 + 1e-12)]
    return skfem.MeshHex.init_tensor(xs, ys, zs)


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


# ----------------------------------------------------------------------------
# the solver
# ----------------------------------------------------------------------------

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


class SVKSolver:
    """Total-Lagrangian SVK on a scikit-fem mesh with quadratic Lagrange elements.

    Global vector DOF = dim * (scalar DOF) + component."""

    def __init__(self, mesh, lam: float, mu: float, thickness: float = 1.0,
                 dirichlet=None, intorder: int = 5):
        import skfem

        self.mesh = mesh
        self.dim = d = mesh.p.shape[0]
        elem = skfem.ElementQuad2() if d == 2 else skfem.ElementHex2()
        self.mapping = _mapping(mesh)
        # axis-parallel boxes (the tensor meshes): bounding box = element
        self._affine_boxes = _is_box_mesh(mesh)
        self.basis = skfem.Basis(mesh, elem, mapping=self.mapping, intorder=intorder)
        self.lam, self.mu = lam, mu
        b = self.basis
        self.nb = nb = b.Nbfun
        self.ne = mesh.t.shape[1]
        self.Ns = b.N
        self.N = d * b.N
        # reference gradients of the basis: G[a, J, e, q]
        self.G = np.array([b.basis[a][0].grad for a in range(nb)])
        self.w = b.dx * thickness                                  # (ne, nq)
        edofs = b.element_dofs                                     # (nb, ne)
        self.vdofs = (d * edofs[:, None, :] + np.arange(d)[None, :, None])  # (nb, d, ne)
        # fixed DOFs: [(where(x) -> bool, components)], default: clamp x = 0
        if dirichlet is None:
            dirichlet = [(lambda x: np.isclose(x[0], 0.0), range(d))]
        fixed = np.zeros(self.N, bool)
        for where, comps in dirichlet:
            sdofs = b.get_dofs(where).all()
            for i in comps:
                fixed[d * sdofs + i] = True
        self.set_fixed(fixed)

    # -- sparse pattern of the reduced (free x free) tangent --------------------
    def set_fixed(self, fixed: np.ndarray):
        self.fixed = fixed
        self.free = np.flatnonzero(~fixed)
        gmap = -np.ones(self.N, np.int64)
        gmap[self.free] = np.arange(self.free.size)
        loc = gmap[self.vdofs]                                     # (nb, d, ne)
        nl = self.nb * self.dim
        loc = loc.reshape(nl, self.ne)
        rows = np.broadcast_to(loc[:, None, :], (nl, nl, self.ne)).ravel()
        cols = np.broadcast_to(loc[None, :, :], (nl, nl, self.ne)).ravel()
        keep = (rows >= 0) & (cols >= 0)
        nf = self.free.size
        keys = rows[keep] * nf + cols[keep]
        ukeys, pos = np.unique(keys, return_inverse=True)
        self._keep = keep
        self._pos = pos
        self._indptr = np.searchsorted(ukeys // nf, np.arange(nf + 1))
        self._indices = (ukeys % nf).astype(np.int32)
        self._nnz = ukeys.size

    # -- kinematics and stress at the Gauss points -----------------------------
    def _state(self, u: np.ndarray, sl=slice(None)):
        d = self.dim
        ue = u[self.vdofs[:, :, sl]]                               # (nb, d, ne)
        G = self.G[:, :, sl]
        Hg = np.einsum("aie,aJeq->iJeq", ue, G)                    # grad u
        # Green strain from grad u directly (no cancellation in F^T F - I)
        Eg = 0.5 * (Hg + Hg.transpose(1, 0, 2, 3) + np.einsum("kIeq,kJeq->IJeq", Hg, Hg))
        F = Hg
        F += np.eye(d)[:, :, None, None]
        tr = np.einsum("IIeq->eq", Eg)
        S = 2.0 * self.mu * Eg
        for i in range(d):
            S[i, i] += self.lam * tr
        return G, F, S, Eg, tr

    def internal(self, u: np.ndarray) -> np.ndarray:
        G, F, S, _, _ = self._state(u)
        P = np.einsum("iIeq,IJeq->iJeq", F, S)
        re = np.einsum("iJeq,aJeq,eq->aie", P, G, self.w)
        return np.bincount(self.vdofs.ravel(), weights=re.ravel(), minlength=self.N)

    def energy(self, u: np.ndarray) -> float:
        _, _, _, Eg, tr = self._state(u)
        psi = 0.5 * self.lam * tr ** 2 + self.mu * np.einsum("IJeq,IJeq->eq", Eg, Eg)
        return float(np.sum(psi * self.w))

    def tangent(self, u: np.ndarray, chunk: int = 1000):
        """Reduced tangent (free x free) and the full internal force vector."""
        d, nb = self.dim, self.nb
        nl = nb * d
        data = np.zeros(self._nnz)
        fint = np.zeros(self.N)
        keep = self._keep.reshape(nl, nl, self.ne)
        pos_all = np.full(keep.shape, -1, np.int64)
        pos_all[keep] = self._pos
        eye = np.eye(d)
        for e0 in range(0, self.ne, chunk):
            sl = slice(e0, min(e0 + chunk, self.ne))
            G, F, S, _, _ = self._state(u, sl)
            w = self.w[sl]
            P = np.einsum("iIeq,IJeq->iJeq", F, S)
            re = np.einsum("iJeq,aJeq,eq->aie", P, G, w)
            fint += np.bincount(self.vdofs[:, :, sl].ravel(), weights=re.ravel(),
                                minlength=self.N)
            ne = w.shape[0]
            # B_a = F G_a per Gauss point, laid out (e, q, a i) for batched matmuls
            B = np.einsum("iJeq,aJeq->eqai", F, G).reshape(ne, -1, nl)
            Bw = B * w[:, :, None]
            M1 = np.matmul(Bw.transpose(0, 2, 1), B).reshape(ne, nb, d, nb, d)
            # lambda (F G_a)_i (F G_b)_k + mu (F G_b)_i (F G_a)_k
            K = self.lam * M1 + self.mu * M1.transpose(0, 3, 2, 1, 4)
            # mu (F F^T)_ik G_a.G_b + delta_ik G_a S G_b
            FFt = np.einsum("iIeq,kIeq->eqik", F, F).reshape(ne, -1, d * d)
            GG = np.einsum("aJeq,bJeq,eq->eqab", G, G, w).reshape(ne, -1, nb * nb)
            K += self.mu * np.matmul(FFt.transpose(0, 2, 1), GG).reshape(
                ne, d, d, nb, nb).transpose(0, 3, 1, 4, 2)
            GSG = np.einsum("aJeq,JLeq,bLeq,eq->eab", G, S, G, w, optimize=True)
            K += GSG[:, :, None, :, None] * eye[None, None, :, None, :]
            K = K.transpose(1, 2, 3, 4, 0)
            K = K.reshape(nl, nl, -1)
            p = pos_all[:, :, sl]
            m = p >= 0
            data += np.bincount(p[m], weights=K[m], minlength=self._nnz)
        nf = self.free.size
        Kt = sp.csr_matrix((data, self._indices, self._indptr), shape=(nf, nf))
        return Kt, fint

    # -- loads, probes ----------------------------------------------------------
    def face_load(self, x_face: float, force) -> np.ndarray:
        """Nodal forces of a dead uniform traction on the face x = x_face whose
        resultant is the vector `force` (traction = force / face area)."""
        import skfem

        facets = self.mesh.facets_satisfying(lambda x: np.isclose(x[0], x_face))
        fb = skfem.FacetBasis(self.mesh, self.basis.elem, mapping=self.mapping,
                              facets=facets, intorder=5)
        ones = skfem.asm(skfem.LinearForm(lambda v, w: v), fb)   # sums to the face measure
        f = np.zeros(self.N)
        for i in range(self.dim):
            f[i::self.dim] = force[i] * ones / ones.sum()
        return f

    def find_elements(self, points: np.ndarray) -> np.ndarray:
        """An element containing each point (dim, n), by bounding boxes (exact
        for the tensor-product meshes used here; skfem's own finder searches
        the nearest centroids, which misses in layers of thin elements and
        then falls back to a search of every element)."""
        P = self.mesh.p[:, self.mesh.t]                            # (dim, nverts, ne)
        lo, hi = P.min(axis=1), P.max(axis=1)
        tol = 1e-12 * np.ptp(self.mesh.p, axis=1)[:, None]
        size = np.ptp(self.mesh.p, axis=1).max()
        cells = np.empty(points.shape[1], np.int64)
        for j in range(points.shape[1]):
            x = points[:, j:j + 1]
            inside = np.flatnonzero(np.all((lo - tol <= x) & (x <= hi + tol), axis=0))
            if inside.size == 0:
                raise ValueError(f"point {points[:, j]} is outside the mesh")
            cells[j] = inside[0]
            if inside.size > 1 and not self._affine_boxes:
                # distorted elements: the first whose inverse map hits the point
                for c in inside:
                    try:
                        X = self.mapping.invF(x[:, :, None], tind=np.array([c]))
                    except RuntimeError:
                        continue
                    if np.abs(self.mapping.F(X, np.array([c])) - x[:, :, None]).max() \
                            <= 1e-10 * size:
                        cells[j] = c
                        break
        return cells

    def probe_matrix(self, points: np.ndarray):
        """Sparse (n, Ns): values of a scalar FE field at `points` (dim, n),
        as skfem's CellBasis.probes, with find_elements."""
        b = self.basis
        cells = self.find_elements(points)
        X = self.mapping.invF(points[:, :, None], tind=cells)
        phis = np.array([b.elem.gbasis(self.mapping, X, k, tind=cells)[0]
                         for k in range(b.Nbfun)]).reshape(b.Nbfun, -1)
        rows = np.tile(np.arange(points.shape[1]), b.Nbfun)
        cols = b.element_dofs[:, cells].ravel()
        return sp.coo_matrix((phis.ravel(), (rows, cols)),
                             shape=(points.shape[1], b.N)).tocsr()

    def column_probe(self, points: np.ndarray) -> np.ndarray:
        """Row vector m with m @ u_scalar = mean of the field over `points` (dim, n)."""
        P = self.probe_matrix(points)
        return np.asarray(P.mean(axis=0)).ravel()

    # -- Newton ---------------------------------------------------------------
    def newton(self, u: np.ndarray, fext: np.ndarray, tol: float = 1e-10,
               maxit: int = 25, project=None, log=None, du_tol: float = 1e-12,
               linear=None):
        """Solve fint(u) = fext on the free DOFs.

        Converged when |r| <= tol |fext| (free DOFs), or, once that stalls at
        the round-off floor of fint (grad u from nodal values carried far by
        the rigid motion of a slender body, in elements down to 1e-6 of its
        size: 1e-10 to 1e-6 |fext| on the graded meshes, in the few smallest
        elements), when the Newton correction is below du_tol |u| (max
        norms) -- the displacements no longer change.  Returns (u,
        iterations, final relative residual).  Raises RuntimeError when it
        does not converge."""
        scale = np.linalg.norm(fext[self.free])
        if scale == 0.0:          # no load (prescribed displacements only)
            scale = np.linalg.norm(self.internal(u)[self.free]) or 1.0
        linear = LinearSolver() if linear is None else linear
        rel = math.inf
        for it in range(maxit + 1):
            Kt, fint = self.tangent(u)
            r = (fext - fint)[self.free]
            rel = np.linalg.norm(r) / scale
            if not np.isfinite(rel):
                raise RuntimeError("residual not finite")
            if rel <= tol:
                return u, it, rel
            du = linear(Kt, r)
            u = u.copy()
            u[self.free] += du
            if project is not None:
                u = project(u)
            step = np.abs(du).max() / max(np.abs(u).max(), 1e-300)
            if log:
                log(f"      newton {it}: |r|/|f| = {rel:.3e}  |du|/|u| = {step:.3e}")
            if step <= du_tol and rel <= 1e-4:
                return u, it + 1, rel
        raise RuntimeError(f"Newton did not converge: |r|/|f| = {rel:.3e} after {maxit}")


class LinearSolver:
    """K du = r for the Newton corrections.

    Direct (SuperLU) by default.  lagged=True (used in 3D, where a
    factorisation costs 10-100 times a GMRES iteration) keeps the last LU and
    uses it as the preconditioner of GMRES (relative residual rtol: an
    inexact Newton step, which still converges to the round-off floor);
    only when that fails within `krylov` iterations is the current tangent
    factorised."""

    def __init__(self, lagged: bool = False, rtol: float = 1e-8, krylov: int = 60):
        self.lagged, self.rtol, self.krylov = lagged, rtol, krylov
        self.lu = None
        self.factorizations = 0
        self.krylov_iterations = 0

    def _factor(self, K):
        self.lu = spla.splu(K.tocsc(), permc_spec="MMD_AT_PLUS_A")
        self.factorizations += 1

    def __call__(self, K, r):
        if self.lagged and self.lu is not None and self.lu.shape == K.shape:
            count = [0]

            def cb(_):
                count[0] += 1

            M = spla.LinearOperator(K.shape, matvec=self.lu.solve, dtype=float)
            x, info = spla.gmres(K, r, rtol=self.rtol, atol=0.0, restart=self.krylov,
                                 maxiter=3, M=M, callback=cb, callback_type="pr_norm")
            self.krylov_iterations += count[0]
            if np.linalg.norm(K @ x - r) <= 10 * self.rtol * np.linalg.norm(r):
                if count[0] > self.krylov // 2:
                    self.lu = None          # getting stale: refactor at the next call
                return x
        self._factor(K)
        x = self.lu.solve(r)
        # one step of iterative refinement
        return x + self.lu.solve(r - K @ x)


# ----------------------------------------------------------------------------
# one case on one mesh
# ----------------------------------------------------------------------------

def column_points(problem: Problem, dx: float, x: float | None = None) -> np.ndarray:
    """The particle code's tip column for spacing dx: x = tip_point (L - dx/2)
    or x, y = (j + 1/2) dx, j < H/dx (and z = (k + 1/2) dx, k < W/dx in 3D)."""
    x = tip_point(problem.L, dx) if x is None else x
    ny = int(round(problem.H / dx))
    if abs(ny * dx - problem.H) > 1e-9 * problem.H:
        raise ValueError(f"dx = {dx} does not divide H = {problem.H}")
    ys = (np.arange(ny) + 0.5) * dx
    if problem.dim == 2:
        return np.vstack([np.full(ny, x), ys])
    nz = int(round(problem.W / dx))
    zs = (np.arange(nz) + 0.5) * dx
    Y, Z = np.meshgrid(ys, zs, indexing="ij")
    return np.vstack([np.full(Y.size, x), Y.ravel(), Z.ravel()])


def mirror_projector(solver: SVKSolver, height: float):
    """u -> its part symmetric under y -> H - y (u_x even, u_y odd), for the
    straight branch of the compressed truss (the mesh must be symmetric)."""
    from scipy.spatial import cKDTree

    d = solver.dim
    X = solver.basis.doflocs
    Xm = X.copy()
    Xm[1] = height - X[1]
    dist, mirror = cKDTree(X.T).query(Xm.T)      # dof mirror[i] sits at i's mirror image
    if dist.max() > 1e-9 * height:
        raise ValueError("the mesh is not symmetric in y")
    sign = np.ones(d)
    sign[1] = -1.0

    def project(u):
        U = u.reshape(-1, d)
        return (0.5 * (U + U[mirror] * sign)).ravel()

    return project


def solve_case(problem: Problem | str, loads, nu: float, plane: str, mesh,
               dxs=None, max_step: float | None = None, log=None,
               x_columns: dict | None = None) -> dict:
    """Solve one (problem, nu, plane) on `mesh` along the load path(s) through
    `loads` (each sign from zero, in increasing magnitude, sub-stepped so that
    no increment exceeds max_step, default problem.max_step * max|load|:
    1/8 in 2D, 1/5 in 3D).

    Returns {load: array (len(dxs), dim)} of the tip-column mean displacement
    for each dx (default: the problem's dxs); x_columns = {name: (x, dy)}
    adds means over other columns (x fixed, y = (j + 1/2) dy) under key name,
    and result["info"] has Newton statistics."""
    problem = PROBLEMS[problem] if isinstance(problem, str) else problem
    dxs = problem.dxs if dxs is None else tuple(dxs)
    lam, mu = lame(problem.E, nu, plane)
    d = mesh.p.shape[0]
    half = d == 3 and mesh.p[2].max() < 0.75 * problem.W
    dirichlet = [(lambda x: np.isclose(x[0], 0.0), range(d))]
    if half:
        dirichlet.append((lambda x: np.isclose(x[2], 0.5 * problem.W), [2]))
    solver = SVKSolver(mesh, lam, mu, thickness=problem.t if d == 2 else 1.0,
                       dirichlet=dirichlet)

    def probe(points):
        """Rows mapping the scalar field of each component to its mean over
        `points`; in a half-z model the points beyond z = W/2 are mirrored
        (u_x, u_y even, u_z odd in z - W/2)."""
        if not half:
            m = solver.column_probe(points)
            return [m] * d
        sign = np.where(points[2] > 0.5 * problem.W * (1 + 1e-12), -1.0, 1.0)
        pts = points.copy()
        pts[2] = np.where(sign < 0, problem.W - pts[2], pts[2])
        P = solver.probe_matrix(pts)
        even = np.asarray(P.mean(axis=0)).ravel()
        odd = np.asarray((sp.diags(sign) @ P).mean(axis=0)).ravel()
        return [even, even, odd]

    probes = {dx: probe(column_points(problem, dx)) for dx in dxs}
    for name, (x, dy) in (x_columns or {}).items():
        probes[name] = probe(column_points(problem, dy, x=x))
    unit = np.zeros(d)
    unit[problem.component] = 1.0
    # a half-z model carries half the load (the traction is F / (H W))
    fdir = solver.face_load(problem.L, unit) * (0.5 if half else 1.0)
    project = mirror_projector(solver, problem.H) if problem.symmetric_y else None
    loads = [float(f) for f in loads]
    if max_step is None:
        max_step = max(abs(f) for f in loads) * problem.max_step
    out = {}
    info = {"dofs": int(solver.free.size), "elements": int(solver.ne), "steps": 0,
            "newton": 0, "max_residual": 0.0, "half_z": bool(half)}
    linear = LinearSolver(lagged=(d == 3))
    for sign in (1.0, -1.0):
        path = sorted({abs(f) for f in loads if f * sign > 0})
        u = np.zeros(solver.N)
        hist = [(0.0, u)]
        level = 0.0
        for target in path:
            while level < target * (1 - 1e-14):
                step = min(max_step, target - level)
                while True:
                    new = min(target, level + step)
                    # secant predictor from the last two converged states
                    if len(hist) >= 2:
                        (f0, u0), (f1, u1) = hist[-2], hist[-1]
                        guess = u1 + (u1 - u0) * (new - f1) / (f1 - f0)
                    else:
                        guess = hist[-1][1]
                    try:
                        u, it, rel = solver.newton(guess, sign * new * fdir, project=project,
                                                   linear=linear)
                        break
                    except RuntimeError as err:
                        if step < max_step / 64:
                            raise
                        if log:
                            log(f"    step to {sign * new:g} failed ({err}); halving")
                        step *= 0.5
                info["steps"] += 1
                info["newton"] += it
                info["max_residual"] = max(info["max_residual"], rel)
                if log:
                    log(f"    load {sign * new:10g}: {it} Newton iterations, |r|/|f| = {rel:.1e}")
                level = new
                hist = hist[-1:] + [(level, u)]
            out[sign * target] = {k: np.array([m[i] @ u[i::d] for i in range(d)])
                                  for k, m in probes.items()}
    result = {f: np.array([v[dx] for dx in dxs]) for f, v in out.items()}
    for name in (x_columns or {}):
        result[name] = {f: v[name] for f, v in out.items()}
    info["factorizations"] = linear.factorizations
    info["krylov_iterations"] = linear.krylov_iterations
    result["info"] = info
    return result


# ----------------------------------------------------------------------------
# Richardson
# ----------------------------------------------------------------------------

def richardson(values, pmin: float = 1.0, pmax: float = 4.0):
    """Error estimate of the last of >= 2 values on meshes refined by 2.

    With three values and a consistent (monotone, contracting) sequence the
    observed order p = log2(|d1|/|d2|), clipped to [pmin, pmax], gives
    |d2| / (2^p - 1); otherwise (two values, or a non-monotone sequence)
    the estimate is the conservative max(|d1|, |d2|) (|d| for two).
    Returns (estimate, p or None)."""
    v = np.asarray(values, float)
    d2 = v[-1] - v[-2]
    if v.size < 3:
        return abs(d2), None
    d1 = v[-2] - v[-3]
    if d1 * d2 > 0 and abs(d2) < abs(d1):
        p = min(max(math.log2(abs(d1) / abs(d2)), pmin), pmax)
        return abs(d2) / (2.0 ** p - 1.0), p
    return max(abs(d1), abs(d2)), None


# ----------------------------------------------------------------------------
# the table
# ----------------------------------------------------------------------------

COMPONENTS = ("dh", "dv", "dz")


def _zero_by_symmetry(problem: Problem) -> set:
    """Components whose tip-column mean vanishes by symmetry (listed with an
    absolute error only): the truss's dv (mirror symmetry in y), dz in 3D."""
    zero = {"dz"}
    if problem.symmetric_y:
        zero.add("dv")
    return zero


def unique_cases(problem: Problem):
    """(nu, plane) pairs to compute, and the pairs that copy them: at nu = 0
    lambda = 0 and plane stress and plane strain are the same law."""
    todo, copies = [], {}
    for nu, plane in problem.cases:
        if nu == 0.0 and plane == "strain" and (0.0, "stress") in problem.cases:
            copies[(nu, plane)] = (0.0, "stress")
        else:
            todo.append((nu, plane))
    return todo, copies


def compute_problem(problem: Problem | str, levels=None, log=print, checkpoint=None) -> dict:
    """Solve every case of `problem` on its mesh levels; returns the table part
    {"entries": [...], "meta": {...}}.  checkpoint(part) is called with the
    part so far after each (nu, plane) case (the 3D cases take ~25 min)."""
    problem = PROBLEMS[problem] if isinstance(problem, str) else problem
    levels = problem.levels if levels is None else tuple(levels)
    t_start = time.time()
    todo, copies = unique_cases(problem)
    zero = _zero_by_symmetry(problem)
    comps = COMPONENTS[:problem.dim]
    entries, meshes, runs = [], {}, []
    def part():
        meta = {"levels": list(levels), "meshes": {str(k): v for k, v in meshes.items()},
                "grade": dict(problem.grade), "half_z": problem.half_z,
                "symmetric_y": problem.symmetric_y, "runs": runs,
                "wall_seconds": round(time.time() - t_start, 1),
                "L": problem.L, "H": problem.H, "W": problem.W if problem.dim == 3 else None,
                "t": problem.t if problem.dim == 2 else None, "E": problem.E,
                "loads": list(problem.loads), "dxs": list(problem.dxs),
                "cases": [list(c) for c in problem.cases],
                "max_error_estimate": max((e["error_estimate"] for e in entries), default=None),
                "note": problem.note}
        return {"entries": list(entries), "meta": meta}

    for nu, plane in todo:
        per_level = []
        for level in levels:
            t0 = time.time()
            mesh = make_mesh(problem, level)
            res = solve_case(problem, problem.loads, nu, plane, mesh,
                             log=(lambda s: log(s)) if log and problem.dim == 3 else None)
            info = res["info"]
            dt = time.time() - t0
            meshes[level] = {"elements": info["elements"], "free_dofs": info["dofs"],
                             "half_z": info["half_z"]}
            runs.append({"nu": nu, "plane": plane, "level": level, "seconds": round(dt, 1),
                         "load_steps": info["steps"], "newton_iterations": info["newton"],
                         "factorizations": info["factorizations"],
                         "max_final_residual": float(info["max_residual"])})
            if log:
                log(f"  {problem.name} nu={nu} {plane} level {level}: {info['dofs']} dofs, "
                    f"{info['steps']} load steps, {info['newton']} Newton iterations, "
                    f"max |r|/|f| {info['max_residual']:.1e}, {dt:.1f} s")
            per_level.append(res)
        for load in problem.loads:
            vals = np.array([r[load] for r in per_level])          # (level, dx, comp)
            for j, dx in enumerate(problem.dxs):
                e = {"problem": problem.name, "nu": nu, "plane": plane, "load": load, "dx": dx}
                rel = []
                for i, c in enumerate(comps):
                    v = vals[:, j, i]
                    err, p = richardson(v)
                    e[c] = float(v[-1])
                    e["err_" + c] = float(err)
                    e["order_" + c] = None if p is None else round(p, 2)
                    if c not in zero:
                        rel.append(err / abs(v[-1]))
                e["error_estimate"] = float(max(rel))
                e["levels"] = [[float(x) for x in row] for row in vals[:, j, :]]
                entries.append(e)
                for (cnu, cplane), (snu, splane) in copies.items():
                    if (snu, splane) == (nu, plane):
                        entries.append(dict(e, nu=cnu, plane=cplane, copy_of=splane))
        if checkpoint is not None:
            checkpoint(part())
    return part()


def write_table(names, path: Path = TABLE, log=print) -> dict:
    """Recompute the problems `names` and merge them into the table at `path`."""
    import skfem

    try:
        table = json.loads(path.read_text())
    except (FileNotFoundError, ValueError):
        table = {}
    table.setdefault("problems", {})
    def save(name, part):
        table["problems"][name] = part
        table["meta"] = _table_meta(skfem)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(table, indent=1, default=_json_default) + "\n")

    for name in names:
        if log:
            log(f"{name}: solving ...")
        part = compute_problem(name, log=log, checkpoint=lambda p, n=name: save(n, p))
        save(name, part)
        if log:
            log(f"{name}: {part['meta']['wall_seconds']} s wall, max error estimate "
                f"{part['meta']['max_error_estimate']:.1e}")
    _TABLE_CACHE.clear()
    return table


def _table_meta(skfem) -> dict:
    return {
        "description": "Tip-column mean displacements (m) of the static validation problems "
                       "by a nonlinear total-Lagrangian SVK finite-element model (esph.fe)",
        "scikit_fem": skfem.__version__ if hasattr(skfem, "__version__") else _version("scikit-fem"),
        "numpy": np.__version__, "scipy": _version("scipy"),
        "element": "ElementQuad2 (9-node biquadratic) in 2D, ElementHex2 (27-node "
                   "triquadratic) in 3D; 3x3(x3) Gauss points; tensor-product meshes with "
                   "geometric layers toward the corners (make_mesh)",
        "material": "SVK: S = lambda tr(E) I + 2 mu E, P = F S; 2D plane stress: lambda* = "
                    "2 lambda mu/(lambda + 2 mu); plane strain: 3D lambda",
        "loading": "x = 0 clamped, dead uniform traction on x = L with the load as resultant",
        "tip_column": "mean over x = L - dx/2, y = (j+1/2) dx (z = (k+1/2) dx)",
        "value": "the finest mesh (the last level); err_*: Richardson estimate of its "
                 "absolute error from the last three levels (|d2|/(2^p - 1), observed order p "
                 "clipped to [1, 4]; max(|d1|, |d2|) when not monotone); error_estimate: the "
                 "largest err_c/|c| over the components not zero by symmetry",
        "newton": "load stepping (increments <= max|load|/8 in 2D, /5 in 3D), "
                  "|r| <= 1e-10 |f| or, at the "
                  "round-off floor of the strongly graded meshes, Newton correction "
                  "<= 1e-12 |u| (max_final_residual per run)",
        "date": datetime.date.today().isoformat(),
        "command": "cd python && " + REGENERATE + " [--problems beam,truss,beam3d,beam3d_short]",
    }


def _json_default(x):
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not JSON serializable: {type(x)}")


def _version(dist: str) -> str:
    from importlib.metadata import version

    return version(dist)


_TABLE_CACHE: dict = {}


def _load_table(path: Path = TABLE) -> dict:
    key = str(path)
    if key not in _TABLE_CACHE:
        _TABLE_CACHE[key] = json.loads(path.read_text())
    return _TABLE_CACHE[key]


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1e-300)


def tip(problem: str, load: float, dx: float, nu: float = 0.0, plane: str = "stress") -> dict:
    """The FE reference tip-column mean displacement for one case.

    Returns {"dh", "dv" (and "dz" in 3D): metres, "error_estimate": relative
    (see the table's meta), "err_dh", "err_dv", ...: absolute}.  `plane` is
    ignored for the 3D problems.  Raises KeyError (naming the case and the
    command that regenerates the table) when the table lacks it."""
    where = f"(problem={problem!r}, load={load:g}, dx={dx:g}, nu={nu:g}, plane={plane!r})"
    try:
        part = _load_table()["problems"][problem]
    except FileNotFoundError:
        raise KeyError(f"no FE reference table {TABLE}; make it with: cd python && "
                       f"{REGENERATE}") from None
    except KeyError:
        raise KeyError(f"FE reference table has no problem {where}; regenerate with: "
                       f"cd python && {REGENERATE} --problems {problem}") from None
    is3d = problem in PROBLEMS and PROBLEMS[problem].dim == 3
    for e in part["entries"]:
        if (_close(e["load"], load) and _close(e["dx"], dx) and abs(e["nu"] - nu) < 1e-12
                and (is3d or e["plane"] == plane)):
            keys = ["dh", "dv", "dz", "error_estimate", "err_dh", "err_dv", "err_dz"]
            return {k: e[k] for k in keys if k in e}
    raise KeyError(f"FE reference table has no entry {where}; regenerate with: "
                   f"cd python && {REGENERATE} --problems {problem}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m esph.fe", description=__doc__.split("\n")[0])
    ap.add_argument("--write", action="store_true", help="recompute and write the table")
    ap.add_argument("--problems", default=",".join(PROBLEMS),
                    help="comma-separated subset of " + ",".join(PROBLEMS))
    ap.add_argument("--table", default=str(TABLE), help="table path (default: the package's)")
    args = ap.parse_args(argv)
    names = [n.strip() for n in args.problems.split(",") if n.strip()]
    for n in names:
        if n not in PROBLEMS:
            ap.error(f"unknown problem {n!r}: {', '.join(PROBLEMS)}")
    if not args.write:
        table = _load_table(Path(args.table))
        for n in names:
            meta = table["problems"].get(n, {}).get("meta")
            print(n, "missing" if meta is None else
                  f"{len(table['problems'][n]['entries'])} entries, max error estimate "
                  f"{meta['max_error_estimate']:.1e}, {meta['wall_seconds']} s")
        return 0
    t0 = time.time()
    write_table(names, Path(args.table), log=lambda s: print(s, flush=True))
    print(f"total {time.time() - t0:.1f} s; wrote {args.table}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The nonlinear finite-element solver of esph.fe: total-Lagrangian St.
Venant-Kirchhoff on a scikit-fem mesh (SVKSolver: assembly, loads, probes,
Newton), its linear solver, and one (problem, nu, plane) along its load
path on one mesh (solve_case); see esph.fe's documentation."""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..problems import Problem, problem_by_name, tip_point
from .meshes import _mapping, _is_box_mesh, arc_clamp_facets, arc_mapping


def lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """(lambda, mu) of the law the particle code runs (see module doc)."""
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    if plane == "stress":
        lam = 2.0 * lam * mu / (lam + 2.0 * mu)
    elif plane not in ("strain", "3d"):
        raise ValueError(f"plane must be 'stress', 'strain' or '3d', not {plane!r}")
    return lam, mu


class SVKSolver:
    """Total-Lagrangian SVK on a scikit-fem mesh with quadratic Lagrange elements.

    Global vector DOF = dim * (scalar DOF) + component."""

    def __init__(self, mesh, lam: float, mu: float, thickness: float = 1.0,
                 dirichlet=None, intorder: int = 5, mapping=None):
        import skfem

        self.mesh = mesh
        self.dim = d = mesh.p.shape[0]
        elem = skfem.ElementQuad2() if d == 2 else skfem.ElementHex2()
        # mapping: the element geometry (default: the mesh's isoparametric map)
        self.mapping = _mapping(mesh) if mapping is None else mapping
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
        self.thickness = thickness
        self.w = b.dx * thickness                                  # (ne, nq)
        edofs = b.element_dofs                                     # (nb, ne)
        self.vdofs = (d * edofs[:, None, :] + np.arange(d)[None, :, None])  # (nb, d, ne)
        # fixed DOFs: [(where, components)], where(x) -> bool on the facet
        # midpoints or an array of facet indices; default: clamp x = 0
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

    def face_traction(self, y_face: float, traction) -> np.ndarray:
        """Nodal forces of a dead uniform traction (force per unit reference
        area, the vector `traction`) on the face y = y_face: f_(a,i) = t_i
        int N_a dA, dA = thickness ds in 2D."""
        import skfem

        facets = self.mesh.facets_satisfying(lambda x: np.isclose(x[1], y_face))
        fb = skfem.FacetBasis(self.mesh, self.basis.elem, mapping=self.mapping,
                              facets=facets, intorder=5)
        area = skfem.asm(skfem.LinearForm(lambda v, w: v), fb) * self.thickness
        f = np.zeros(self.N)
        for i in range(self.dim):
            f[i::self.dim] = traction[i] * area
        return f

    def body_load(self, force_density) -> np.ndarray:
        """Nodal forces of a dead body force per unit reference volume (the
        vector force_density, e.g. rho g): f_(a,i) = b_i int N_a dV, dV =
        thickness dA in 2D.  Independent of u (a dead load: its work is
        -int b . u dV); on affine elements the quadrature (intorder 5, exact
        for the biquadratic/triquadratic N_a) integrates it exactly, so the
        nodal forces sum to b times the volume to round-off (the partition of
        unity).  Fixed DOFs get their share too (it is not used there)."""
        import skfem

        vol = skfem.asm(skfem.LinearForm(lambda v, w: v), self.basis) * self.thickness
        f = np.zeros(self.N)
        for i in range(self.dim):
            f[i::self.dim] = force_density[i] * vol
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


def column_points(problem: Problem, dx: float, x: float | None = None) -> np.ndarray:
    """The particle code's tip column for spacing dx: x = tip_point (L - dx/2)
    or x, y = (j + 1/2) dx, j < H/dx (and z = (k + 1/2) dx, k < W/dx in 3D);
    for the plate (load_kind "plate") without x, its two mid-span columns."""
    ny = int(round(problem.H / dx))
    if abs(ny * dx - problem.H) > 1e-9 * problem.H:
        raise ValueError(f"dx = {dx} does not divide H = {problem.H}")
    ys = (np.arange(ny) + 0.5) * dx
    if problem.load_kind == "plate" and x is None:
        # the plate's two mid-span columns, x = L/2 -+ dx/2
        xs = np.repeat([0.5 * (problem.L - dx), 0.5 * (problem.L + dx)], ny)
        return np.vstack([xs, np.tile(ys, 2)])
    x = tip_point(problem.L, dx) if x is None else x
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
               x_columns: dict | None = None, points: dict | None = None) -> dict:
    """Solve one (problem, nu, plane) on `mesh` along the load path(s) through
    `loads` (each sign from zero, in increasing magnitude, sub-stepped so that
    no increment exceeds max_step, default problem.max_step * max|load|:
    1/8 in 2D, 1/5 in 3D).

    Returns {load: array (len(dxs), dim)} of the tip-column mean displacement
    for each dx (default: the problem's dxs); x_columns = {name: (x, dy)}
    adds means over other columns (x fixed, y = (j + 1/2) dy) under key name,
    points = {name: coordinates (dim,)} the displacement of single material
    points (result[name] = {load: array (dim,)} in both cases), and
    result["info"] has Newton statistics.  The loads are end-face resultants
    (N) or, for problem.load_kind == "gravity", the acceleration component
    g[problem.component] (m/s^2) of the body force problem.rho g."""
    problem = problem_by_name(problem) if isinstance(problem, str) else problem
    dxs = problem.dxs if dxs is None else tuple(dxs)
    lam, mu = lame(problem.E, nu, plane)
    d = mesh.p.shape[0]
    half = d == 3 and mesh.p[2].max() < 0.75 * problem.W
    mapping = None
    if problem.clamp_radius > 0.0:
        # clamped on the cylinder's arc; exact geometry
        dirichlet = [(arc_clamp_facets(problem, mesh), range(d))]
        mapping = arc_mapping(problem, mesh)
    elif problem.load_kind == "plate":
        # clamped on both ends
        dirichlet = [(lambda x: np.isclose(x[0], 0.0) | np.isclose(x[0], problem.L), range(d))]
    else:
        dirichlet = [(lambda x: np.isclose(x[0], 0.0), range(d))]
    if half:
        dirichlet.append((lambda x: np.isclose(x[2], 0.5 * problem.W), [2]))
    solver = SVKSolver(mesh, lam, mu, thickness=problem.t if d == 2 else 1.0,
                       dirichlet=dirichlet, mapping=mapping)

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
    for name, X in (points or {}).items():
        probes[name] = probe(np.asarray(X, float).reshape(d, 1))
    unit = np.zeros(d)
    unit[problem.component] = 1.0
    if problem.load_kind == "gravity":
        # rho g per unit volume, per unit of g (a half-z model has half the volume)
        fdir = solver.body_load(problem.rho * unit)
    elif problem.load_kind == "end":
        # a half-z model carries half the load (the traction is F / (H W))
        fdir = solver.face_load(problem.L, unit) * (0.5 if half else 1.0)
    elif problem.load_kind == "plate":
        # per unit of g_y: the plate's weight and the water's pressure on y = H
        fdir = (solver.body_load(problem.rho * unit)
                + solver.face_traction(problem.H, problem.rho_fluid * problem.water * unit))
    else:
        raise ValueError(f"load_kind must be 'end', 'gravity' or 'plate', not "
                         f"{problem.load_kind!r}")
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
    for name in list(x_columns or {}) + list(points or {}):
        result[name] = {f: v[name] for f, v in out.items()}
    info["factorizations"] = linear.factorizations
    info["krylov_iterations"] = linear.krylov_iterations
    result["info"] = info
    return result

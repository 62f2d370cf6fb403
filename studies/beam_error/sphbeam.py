"""Linearised total-Lagrangian SPH cantilever (sph/icb small-strain limit).

K = sum_i w_i B_i^T C B_i, B_i from the corrected gradients g_ij.
Geometry: beam particles at ((i+1/2)dx, (k+1/2)dx), i=0..nx-1, k=0..ny-1,
clamp columns i=-1..-nclamp held fixed (u=0) but their energy counts.
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.spatial import cKDTree

E0, NU0, T0, L0, H0 = 20e9, 0.0, 1e-3, 0.2, 0.02
B2 = 0.710379


def dWdr(r, h):
    q = r / h
    x = 0.5 * np.pi * q
    s = np.sin(x) / x
    out = B2 / h**2 * 5 * s**4 * (x * np.cos(x) - np.sin(x)) / x**2 * (0.5 * np.pi / h)
    return np.where(q < 2.0, out, 0.0)


def exact_v(s, F=-10.0, L=L0, E=E0, H=H0, t=T0, a=None):
    """Euler-Bernoulli deflection at s for a point load F at a (default a=L)."""
    I = t * H**3 / 12
    a = L if a is None else a
    s = np.minimum(s, a)
    return F * s**2 * (3 * a - s) / (6 * E * I)


def geometry(dx, L=L0, H=H0, nclamp=3, ny=None):
    nx = int(round(L / dx))
    ny = int(round(H / dx)) if ny is None else ny
    ii, kk = np.meshgrid(np.arange(-nclamp, nx), np.arange(ny), indexing="ij")
    X = np.c_[(ii.ravel() + 0.5) * dx, (kk.ravel() + 0.5) * dx]
    col = ii.ravel()
    return X, col, nx, ny


def gradients(X, V, h, order=1, mask_partner=None):
    """Return pair lists (i, j) and g_ij (npair x 2)."""
    tree = cKDTree(X)
    pairs = tree.query_pairs(2 * h * (1 - 1e-12), output_type="ndarray")
    I = np.r_[pairs[:, 0], pairs[:, 1]]
    J = np.r_[pairs[:, 1], pairs[:, 0]]
    d = X[J] - X[I]
    r = np.linalg.norm(d, axis=1)
    keep = r < 2 * h
    I, J, d, r = I[keep], J[keep], d[keep], r[keep]
    if mask_partner is not None:
        k2 = mask_partner(I, J)
        I, J, d, r = I[k2], J[k2], d[k2], r[k2]
    w = -dWdr(r, h) / r
    if order == 1:
        P = d / h
    else:
        P = np.c_[d / h, d[:, 0] ** 2 / h**2, d[:, 0] * d[:, 1] / h**2, d[:, 1] ** 2 / h**2]
    nb = P.shape[1]
    wt = V[J] * w
    A = np.zeros((len(X), nb, nb))
    np.add.at(A, I, wt[:, None, None] * P[:, :, None] * P[:, None, :])
    Ainv = np.linalg.inv(A)
    g = wt[:, None] * np.einsum("pab,pb->pa", Ainv[I][:, :2, :], P) / h
    return I, J, g, A


def Cmat(E=E0, nu=NU0, plane="stress"):
    if plane == "stress":
        c = E / (1 - nu**2)
        return c * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    lam = E * nu / ((1 + nu) * (1 - 2 * nu)); mu = E / (2 * (1 + nu))
    return np.array([[lam + 2 * mu, lam, 0], [lam, lam + 2 * mu, 0], [0, 0, mu]])


def bmatrix(N, I, J, g):
    """Sparse B (3N x 2N): rows [exx_i, eyy_i, 2exy_i], dofs [ux_j, uy_j]."""
    rows, cols, vals = [], [], []
    # grad u_i[a,b] = sum_j (u_ja - u_ia) g_ij,b
    for (a, b, rowoff, fac) in [(0, 0, 0, 1.0), (1, 1, 1, 1.0), (0, 1, 2, 1.0), (1, 0, 2, 1.0)]:
        rows += [3 * I + rowoff, 3 * I + rowoff]
        cols += [2 * J + a, 2 * I + a]
        vals += [fac * g[:, b], -fac * g[:, b]]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(3 * N, 2 * N))


def stiffness(B, wts, C):
    N3 = B.shape[0]
    D = sp.kron(sp.diags(wts), sp.csr_matrix(C))
    return (B.T @ D @ B).tocsr()


def solve_beam(dx, order=1, F=-10.0, nclamp=3, hfac=1.2, clamp_energy=True,
               weights=None, nu=NU0, L=L0, H=H0, t=T0, mask_partner=None,
               return_all=False, Vfun=None, free_clamp_cols=0):
    X, col, nx, ny = geometry(dx, L, H, nclamp)
    N = len(X)
    V = np.full(N, dx * dx * t) if Vfun is None else Vfun(X, col, nx, ny, dx, t)
    h = hfac * dx
    I, J, g, A = gradients(X, V, h, order, mask_partner)
    B = bmatrix(N, I, J, g)
    wts = V.copy() if weights is None else weights(X, col, nx, ny, dx, t, V)
    if not clamp_energy:
        wts[col < 0] = 0.0
    K = stiffness(B, wts, Cmat(E0, nu))
    fixed = col < -free_clamp_cols if free_clamp_cols else col < 0
    free = np.repeat(~fixed, 2)
    tip = col == nx - 1
    f = np.zeros(2 * N)
    f[2 * np.where(tip)[0] + 1] = F / tip.sum()
    u = np.zeros(2 * N)
    Kf = K[free][:, free]
    u[free] = spla.spsolve(Kf.tocsc(), f[free])
    dv = u[2 * np.where(tip)[0] + 1].mean()
    s = L - dx / 2
    ref = exact_v(s, F, L, E0, H, t)
    if return_all:
        return dict(X=X, col=col, nx=nx, ny=ny, u=u, K=K, Kf=Kf, free=free, dv=dv, ref=ref,
                    B=B, V=V, wts=wts, I=I, J=J, g=g, f=f)
    return dv, ref, dv / ref - 1


if __name__ == "__main__":
    meas = {(1, 4): 25.2, (1, 2): 7.65, (1, 1): 2.94, (2, 4): 9.6, (2, 2): 3.93, (2, 1): 2.0}
    for order in (1, 2):
        for dxmm in (4, 2, 1):
            dv, ref, err = solve_beam(dxmm * 1e-3, order)
            print(f"order {order} dx {dxmm} mm: dv = {dv*1e3:.5f} mm, ref = {ref*1e3:.5f} mm, "
                  f"err = {100*err:+.3f} %  (LAMMPS {meas[(order, dxmm)]:+.2f} %)")

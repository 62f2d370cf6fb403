"""Continuum reference: 2D plane-stress Q9 FE of the same cantilever, fully clamped at x=0.

Gives the 2D-elasticity deflection (shear + clamp warping constraint included) at the
centroid of the vertical line x = s, for a load applied as a uniform shear traction on x = a
(a = L: end face; a = L - dx/2: line load through the last particle column).
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from sphbeam import E0, NU0, T0, L0, H0, Cmat, exact_v


def q9_shape(xi, eta):
    def l(z):
        return np.array([z * (z - 1) / 2, 1 - z * z, z * (z + 1) / 2])

    def dl(z):
        return np.array([z - 0.5, -2 * z, z + 0.5])
    lx, ly, dlx, dly = l(xi), l(eta), dl(xi), dl(eta)
    N = np.outer(lx, ly).ravel()
    dNx = np.outer(dlx, ly).ravel()
    dNy = np.outer(lx, dly).ravel()
    return N, dNx, dNy


def solve_fe(ex=800, ey=16, F=-10.0, a_load=None, L=L0, H=H0, nu=NU0, s_list=(), clamp_x=0.0):
    """ex, ey: number of Q9 elements. Mesh from x = clamp_x to L."""
    a_load = L if a_load is None else a_load
    xs = np.linspace(clamp_x, L, 2 * ex + 1)
    ys = np.linspace(0, H, 2 * ey + 1)
    nxn, nyn = len(xs), len(ys)
    nid = np.arange(nxn * nyn).reshape(nxn, nyn)
    X = np.array([[x, y] for x in xs for y in ys])
    hx, hy = (L - clamp_x) / ex, H / ey
    C = Cmat(E0, nu) * T0
    gp, gw = np.polynomial.legendre.leggauss(3)
    Ke = np.zeros((18, 18))
    for a, wa in zip(gp, gw):
        for b, wb in zip(gp, gw):
            N, dNx, dNy = q9_shape(a, b)
            dNx = dNx * 2 / hx; dNy = dNy * 2 / hy
            B = np.zeros((3, 18))
            B[0, 0::2] = dNx; B[1, 1::2] = dNy; B[2, 0::2] = dNy; B[2, 1::2] = dNx
            Ke += B.T @ C @ B * wa * wb * hx * hy / 4
    rows, cols, vals = [], [], []
    for e in range(ex):
        for f in range(ey):
            nodes = nid[2 * e:2 * e + 3, 2 * f:2 * f + 3].ravel()
            dofs = np.c_[2 * nodes, 2 * nodes + 1].ravel()
            rows.append(np.repeat(dofs, 18)); cols.append(np.tile(dofs, 18)); vals.append(Ke.ravel())
    K = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(2 * len(X), 2 * len(X)))
    # Simpson-type weights along a vertical node line (quadratic per element)
    wline = np.zeros(nyn)
    for f in range(ey):
        wline[2 * f:2 * f + 3] += np.array([1, 4, 1]) * hy / 6
    fvec = np.zeros(2 * len(X))
    ia = np.argmin(abs(xs - a_load)); assert abs(xs[ia] - a_load) < 1e-12
    fvec[2 * nid[ia] + 1] = F * wline / H
    fixed = np.zeros(2 * len(X), bool)
    fixed[np.c_[2 * nid[0], 2 * nid[0] + 1].ravel()] = True
    free = ~fixed
    u = np.zeros(2 * len(X))
    u[free] = spla.spsolve(K[free][:, free].tocsc(), fvec[free])
    out = []
    for s in s_list:
        i = np.argmin(abs(xs - s)); assert abs(xs[i] - s) < 1e-12
        out.append((u[2 * nid[i] + 1] * wline).sum() / H)
    return np.array(out)


if __name__ == "__main__":
    for dxmm in (4, 2, 1):
        dx = dxmm * 1e-3
        s = L0 - dx / 2
        ref = exact_v(s)
        for ex, ey in ((400, 8), (800, 16)):
            vL = solve_fe(ex, ey, s_list=[s])[0]
            va = solve_fe(ex, ey, a_load=s, s_list=[s])[0]
            print(f"dx {dxmm} mm mesh {ex}x{ey}: continuum v(s) load@L {vL*1e3:.5f} mm "
                  f"({100*(vL/ref-1):+.3f}% vs EB),  load@L-dx/2 {va*1e3:.5f} mm ({100*(va/ref-1):+.3f}%)")
    # EB with load at L-dx/2 for comparison
    for dxmm in (4, 2, 1):
        dx = dxmm * 1e-3; s = L0 - dx / 2
        print(f"EB, load at s instead of L, dx {dxmm}: {100*(exact_v(s, a=s)/exact_v(s)-1):+.3f}%")

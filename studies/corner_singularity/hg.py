import numpy as np, sys, scipy.sparse as sp, scipy.sparse.linalg as spla
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / 'python'))
from proto import *
from scipy.spatial import cKDTree

def Wval(r, h):
    q = r / h; x = 0.5 * np.pi * q; s = np.where(q > 1e-12, np.sin(x) / np.where(x == 0, 1, x), 1.0)
    return np.where(q < 2, B2 / h**2 * s**5, 0.0)

def fit_ops(X, V, h):
    """Per pair (i,j): gradient g_ij and full fit row (5 coefficients)."""
    tree = cKDTree(X)
    pairs = tree.query_pairs(2 * h.max(), output_type="ndarray")
    I = np.r_[pairs[:, 0], pairs[:, 1]]; J = np.r_[pairs[:, 1], pairs[:, 0]]
    d = X[J] - X[I]; r = np.linalg.norm(d, axis=1); hi = h[I]
    keep = r < 2 * hi
    I, J, d, r, hi = I[keep], J[keep], d[keep], r[keep], hi[keep]
    w = -dWdr(r, hi) / r
    P = np.c_[d / hi[:, None], d[:, 0]**2 / hi**2, d[:, 0] * d[:, 1] / hi**2, d[:, 1]**2 / hi**2]
    wt = V[J] * w
    A = np.zeros((len(X), 5, 5)); np.add.at(A, I, wt[:, None, None] * P[:, :, None] * P[:, None, :])
    Ainv = np.linalg.inv(A)
    c = wt[:, None] * np.einsum("pab,pb->pa", Ainv[I], P)   # fit coefficients (scaled basis) per pair
    g = c[:, :2] / hi[:, None]
    return I, J, d, r, hi, g, c, P

MIRROR_HG = True
def hg_matrix(kind, N, I, J, d, r, hi, g, c, P, V, alpha, real):
    """Scalar (per component) matrix M (N x N) with E_hg = 1/2 sum_a u_a^T M u_a."""
    rows, cols, vals = [], [], []
    npair = len(I)
    if kind == "ganz":
        # G_ik for all pairs: F_i = sum_k (u_k - u_i) g_ik
        # d_ij = u_j - u_i - 1/2 (grad_i + grad_j) X_ij ; X_ij = d
        # weight k_ij = alpha E (V_i|g_ij| + V_j|g_ji|)/(2 r)
        key = {(a, b): p for p, (a, b) in enumerate(zip(I, J))}
        gn = np.linalg.norm(g, axis=1)
        # per i: list of pairs
        order = np.argsort(I, kind="stable"); starts = np.searchsorted(I[order], np.arange(N + 1))
        Es = []
        for p in range(npair):
            i, j = I[p], J[p]
            if MIRROR_HG is False and not (real[i] and real[j]):
                continue
            q = key.get((j, i))
            gq = gn[q] if q is not None else 0.0
            kij = alpha * E0 * (V[i] * gn[p] + V[j] * gq) / (2 * r[p])
            coef = {}
            def add(m, v):
                coef[m] = coef.get(m, 0.0) + v
            add(j, 1.0); add(i, -1.0)
            for node, pr in ((i, order[starts[i]:starts[i + 1]]), (j, order[starts[j]:starts[j + 1]])):
                s = -0.5 * (g[pr] @ d[p])       # -1/2 g_node,k . X_ij
                for kk, sv in zip(J[pr], s):
                    add(kk, sv); add(node, -sv)
            ms = np.array(list(coef)); cs = np.array([coef[m] for m in ms])
            # E = 1/4 sum_i sum_j k |d|^2 -> per ordered pair 1/4 k |d|^2 -> M += 1/2 k c c^T
            rows.append(np.repeat(ms, len(ms))); cols.append(np.tile(ms, len(ms)))
            vals.append(0.5 * kij * np.outer(cs, cs).ravel())
    else:
        # fit residual r_ij = u_j - u_i - sum_k (u_k - u_i) (c_ik . P_ij)
        order = np.argsort(I, kind="stable"); starts = np.searchsorted(I[order], np.arange(N + 1))
        for i in range(N):
            if not real[i]:
                continue
            pr = order[starts[i]:starts[i + 1]]
            Pi = P[pr]; Ci = c[pr]
            R = np.eye(len(pr)) - Pi @ Ci.T        # r_j = sum_k R_jk (u_k - u_i)
            wj = V[J[pr]] * Wval(r[pr], hi[pr]) * (real[J[pr]])   # residual weights, real partners only
            M = R.T @ (wj[:, None] * R)            # sum_j w_j r_j^2 = du^T M du
            k = alpha * E0 * V[i] / hi[pr][0]**2
            nodes = np.r_[J[pr], i]
            T = np.c_[np.eye(len(pr)), -np.ones(len(pr))]
            Mf = k * T.T @ M @ T
            rows.append(np.repeat(nodes, len(nodes))); cols.append(np.tile(nodes, len(nodes))); vals.append(Mf.ravel())
    rows, cols, vals = map(np.concatenate, (rows, cols, vals))
    return sp.csr_matrix((vals, (rows, cols)), shape=(N, N))

def solve_body(Xb, Vb, Sb, dx, nu, kind, alpha, F, tip_x):
    """The particle body (positions, volumes, spacings) with its odd mirror
    clamp, linear elasticity, hourglass energy of `kind` and the consistent
    end traction F on the particles beyond L/2's face: the mean tip dv of
    the column at x = tip_x."""
    nb = len(Xb)
    X, V, S, src = with_mirror(Xb, Vb, Sb, 3 * dx); N = len(X)
    h = 1.2 * S
    I, J, d, r, hi, g, c, P = fit_ops(X, V, h)
    B = bmatrix(N, I, J, g)
    wts = np.r_[Vb, np.zeros(N - nb)]
    K = (B.T @ sp.kron(sp.diags(wts), sp.csr_matrix(Cmat(nu))) @ B).tocsr()
    if alpha > 0:
        real = np.r_[np.ones(nb, bool), np.zeros(N - nb, bool)]
        M = hg_matrix(kind, N, I, J, d, r, hi, g, c, P, V, alpha, real)
        K = K + sp.kron(M, sp.eye(2))
    rows = np.r_[np.arange(2 * nb), 2 * (nb + np.arange(len(src))), 2 * (nb + np.arange(len(src))) + 1]
    cols = np.r_[np.arange(2 * nb), 2 * src, 2 * src + 1]
    T = sp.csr_matrix((np.r_[np.ones(2 * nb), -np.ones(2 * len(src))], (rows, cols)), shape=(2 * N, 2 * nb))
    Kb = (T.T @ K @ T).tocsc()
    b = np.zeros((N, 2)); np.add.at(b, I, wts[I][:, None] * g); np.add.at(b, J, -wts[I][:, None] * g)
    face = Xb[:, 0] > L0 / 2
    f = np.zeros(2 * nb); f[2 * np.where(face)[0] + 1] = F / (H0 * T0) * (-b[:nb][face, 0])
    u = spla.spsolve(Kb, f)
    tip = np.isclose(Xb[:, 0], tip_x)
    return u[2 * np.where(tip)[0] + 1].mean()

def solve_hg(dx, nu, kind, alpha, F=-10.0):
    Xb, Vb, Sb = body(dx)
    return solve_body(Xb, Vb, Sb, dx, nu, kind, alpha, F, L0 - dx / 2)

DXS = (0.004, 0.002, 0.001, 0.0005)
ALPHAS = (0.0, 0.1, 0.2, 0.3, 0.5)
if __name__ == "__main__":
    from esph import fe
    P_ = fe.PROBLEMS["beam"]
    for nu in (0.0, 0.3):
        mesh = fe.make_mesh(P_, 2); lam, mu = fe.lame(P_.E, nu, "stress")
        s = fe.SVKSolver(mesh, lam, mu, thickness=P_.t)
        f = s.face_load(P_.L, np.array([0.0, 1.0])) * -1e-3
        ufe, it, rel = s.newton(np.zeros(s.N), f)
        for dx in DXS:
            pts = fe.column_points(P_, dx); Pm = s.column_probe(pts)
            ref = (Pm @ ufe[1::2]) * 1e4
            out = []
            for kind, alphas in (("ganz", ALPHAS),):
                for a in alphas:
                    if kind == "fit" or a > 0 or True:
                        v = solve_hg(dx, nu, kind, a)
                        out.append(f"{kind}{a}: {(v/ref-1)*100:+.4f}%")
            print(f"nu {nu} dx {dx*1e3:.0f}: " + "  ".join(out), flush=True)

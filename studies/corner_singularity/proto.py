"""Linear small-strain prototype of sph/icb (quadratic gradient, per-particle h,
odd mirror clamp, composite Euler-Maclaurin volumes, consistent end traction)."""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla, sys
from scipy.spatial import cKDTree
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / 'python'))
E0, T0, L0, H0 = 20e9, 1e-3, 0.2, 0.02
B2 = 0.710379

def dWdr(r, h):
    q = r / h; x = 0.5 * np.pi * q; s = np.sin(x) / x
    out = B2 / h**2 * 5 * s**4 * (x * np.cos(x) - np.sin(x)) / x**2 * (0.5 * np.pi / h)
    return np.where(q < 2.0, out, 0.0)

def em_weights(n, low=True, high=True):
    """1D midpoint weights with Euler-Maclaurin end corrections (exact for quadratics)."""
    w = np.ones(n)
    for k, c in enumerate((1/12, -1/8, 1/24)):
        if low: w[k] += c
        if high: w[n - 1 - k] += c
    return w

def block(x0, x1, y0, y1, d):
    nx, ny = int(round((x1 - x0) / d)), int(round((y1 - y0) / d))
    xs = x0 + (np.arange(nx) + 0.5) * d; ys = y0 + (np.arange(ny) + 0.5) * d
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    W = np.outer(em_weights(nx, low=x0 > 0), em_weights(ny)) * d * d * T0
    return np.c_[X.ravel(), Y.ravel()], W.ravel(), np.full(nx * ny, d)

def body(dx, a=0.0, r=2, L=L0, H=H0):
    """Blocks: coarse everywhere, fine (dx/r) corner squares of side a at x=0."""
    blocks = []
    if a > 0:
        blocks += [block(0, a, 0, a, dx / r), block(0, a, H - a, H, dx / r),
                   block(0, a, a, H - a, dx), block(a, L, 0, H, dx)]
    else:
        blocks += [block(0, L, 0, H, dx)]
    X = np.vstack([b[0] for b in blocks]); V = np.concatenate([b[1] for b in blocks])
    S = np.concatenate([b[2] for b in blocks])
    return X, V, S

def with_mirror(X, V, S, depth):
    src = np.where(X[:, 0] < depth)[0]
    Xm = X[src].copy(); Xm[:, 0] *= -1
    return np.vstack([X, Xm]), np.r_[V, V[src]], np.r_[S, S[src]], src

def gradients(X, V, h):
    tree = cKDTree(X)
    pairs = tree.query_pairs(2 * h.max(), output_type="ndarray")
    I = np.r_[pairs[:, 0], pairs[:, 1]]; J = np.r_[pairs[:, 1], pairs[:, 0]]
    d = X[J] - X[I]; r = np.linalg.norm(d, axis=1)
    hi = h[I]
    keep = r < 2 * hi
    I, J, d, r, hi = I[keep], J[keep], d[keep], r[keep], hi[keep]
    w = -dWdr(r, hi) / r
    P = np.c_[d / hi[:, None], d[:, 0]**2 / hi**2, d[:, 0] * d[:, 1] / hi**2, d[:, 1]**2 / hi**2]
    wt = V[J] * w
    A = np.zeros((len(X), 5, 5))
    np.add.at(A, I, wt[:, None, None] * P[:, :, None] * P[:, None, :])
    Ainv = np.linalg.inv(A)
    g = wt[:, None] * np.einsum("pab,pb->pa", Ainv[I][:, :2, :], P) / hi[:, None]
    return I, J, g

def Cmat(nu):
    c = E0 / (1 - nu**2)
    return c * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])

def bmatrix(N, I, J, g):
    rows, cols, vals = [], [], []
    for (a, b, ro) in [(0, 0, 0), (1, 1, 1), (0, 1, 2), (1, 0, 2)]:
        rows += [3 * I + ro, 3 * I + ro]; cols += [2 * J + a, 2 * I + a]; vals += [g[:, b], -g[:, b]]
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * N, 2 * N))

def solve(dx, nu, a=0.0, r=2, hfac=1.2, F=-10.0):
    Xb, Vb, Sb = body(dx, a, r)
    nb = len(Xb)
    X, V, S, src = with_mirror(Xb, Vb, Sb, 3 * dx)
    N = len(X)
    h = hfac * S
    I, J, g = gradients(X, V, h)
    B = bmatrix(N, I, J, g)
    wts = np.r_[Vb, np.zeros(N - nb)]
    K = (B.T @ sp.kron(sp.diags(wts), sp.csr_matrix(Cmat(nu))) @ B).tocsr()
    # T: body dofs -> all dofs (mirror = -source)
    rows = np.r_[np.arange(2 * nb), 2 * (nb + np.arange(len(src))), 2 * (nb + np.arange(len(src))) + 1]
    cols = np.r_[np.arange(2 * nb), 2 * src, 2 * src + 1]
    vals = np.r_[np.ones(2 * nb), -np.ones(2 * len(src))]
    T = sp.csr_matrix((vals, (rows, cols)), shape=(2 * N, 2 * nb))
    Kb = (T.T @ K @ T).tocsc()
    # consistent traction on x = L: b_i = sum_j (V_i g_ij - V_j g_ji), mirrors V = 0
    Vs = wts
    b = np.zeros((N, 2))
    np.add.at(b, I, Vs[I][:, None] * g)
    np.add.at(b, J, -Vs[I][:, None] * g)   # pair (I,J) with g = g_IJ contributes -V_I g_IJ to b_J
    face = X[:nb, 0] > L0 / 2
    ty = F / (H0 * T0)
    f = np.zeros(2 * nb)
    f[2 * np.where(face)[0] + 1] = ty * (-b[:nb][face, 0])
    u = spla.spsolve(Kb, f)
    tip = np.isclose(Xb[:, 0], L0 - dx / 2)
    return u[2 * np.where(tip)[0] + 1].mean(), nb

if __name__ == "__main__":
    from esph import fe
    for nu in (0.0, 0.3):
        for dx in (0.002, 0.001):
            ref = fe.tip("beam", -10.0, dx, nu, "stress")["dv"]
            for a, r in [(0, 2)] + [(k * dx, rr) for k in (3, 6) for rr in (2, 4)]:
                try:
                    v, nb = solve(dx, nu, a, r)
                    print(f"nu {nu} dx {dx*1e3:.0f} mm corner a={a/dx:.0f}dx r={r}: {(v/ref-1)*100:+.4f}%  ({nb} particles)", flush=True)
                except Exception as e:
                    print("fail", a, r, e)

"""Corner refinement (fine squares of side a dx at dx/r in the clamped corners)
with hourglass control: does the penalty remove the fine/coarse interface's soft modes?
usage: python refine_hg.py nu dx"""
import sys, time
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parent))
from hg import *
def solve_rhg(dx, nu, a, r, alpha, F=-10.0):
    Xb, Vb, Sb = body(dx, a, r); nb = len(Xb)
    X, V, S, src = with_mirror(Xb, Vb, Sb, 3 * dx); N = len(X)
    h = 1.2 * S
    I, J, d, rr, hi, g, c, P = fit_ops(X, V, h)
    B = bmatrix(N, I, J, g)
    wts = np.r_[Vb, np.zeros(N - nb)]
    K = (B.T @ sp.kron(sp.diags(wts), sp.csr_matrix(Cmat(nu))) @ B).tocsr()
    if alpha > 0:
        real = np.r_[np.ones(nb, bool), np.zeros(N - nb, bool)]
        M = hg_matrix("ganz", N, I, J, d, rr, hi, g, c, P, V, alpha, real)
        K = K + sp.kron(M, sp.eye(2))
    rows = np.r_[np.arange(2 * nb), 2 * (nb + np.arange(len(src))), 2 * (nb + np.arange(len(src))) + 1]
    cols = np.r_[np.arange(2 * nb), 2 * src, 2 * src + 1]
    T = sp.csr_matrix((np.r_[np.ones(2 * nb), -np.ones(2 * len(src))], (rows, cols)), shape=(2 * N, 2 * nb))
    Kb = (T.T @ K @ T).tocsc()
    b = np.zeros((N, 2)); np.add.at(b, I, wts[I][:, None] * g); np.add.at(b, J, -wts[I][:, None] * g)
    face = Xb[:, 0] > L0 / 2
    f = np.zeros(2 * nb); f[2 * np.where(face)[0] + 1] = F / (H0 * T0) * (-b[:nb][face, 0])
    u = spla.spsolve(Kb, f)
    tip = np.isclose(Xb[:, 0], L0 - dx / 2)
    return u[2 * np.where(tip)[0] + 1].mean(), nb
from esph import fe
nu = float(sys.argv[1]); dx = float(sys.argv[2])
ref = fe.tip("beam", -10.0, dx, nu, "stress")["dv"]
for a, r, alpha in [(0, 2, 0.2), (3, 2, 0.0), (3, 2, 0.2), (3, 2, 0.5)]:
    t=time.time()
    v, nb = solve_rhg(dx, nu, a*dx, r, alpha)
    print(f"nu {nu} dx {dx*1e3:.0f} a={a}dx r={r} alpha {alpha}: {(v/ref-1)*100:+.4f}% ({nb} p, {time.time()-t:.0f}s)", flush=True)

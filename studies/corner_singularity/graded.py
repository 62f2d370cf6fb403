"""Smoothly graded particles towards the clamped corners (no fine/coarse
interface): a tensor-product lattice x = phi(xi), y = psi(eta), spacing
dx/r at x = 0 and at y = 0, H, growing smoothly to dx over a length ell;
volumes by the Euler-Maclaurin midpoint rule in (xi, eta) times the
mapping's Jacobian, h = hfac times the larger local spacing; hourglass
control alpha.  Does grading restore order 2 at nu = 0.3?
usage: python graded.py nu r ell_in_dx alpha"""
import sys, time
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parent))
from hg import *


def graded_axis(length, dx, r, ell, both):
    """Cell centres and widths of [0, length], spacing dx/r at 0 (and at
    length if both), dx beyond ell: phi' = s(phi), s smooth, scaled so the
    cell count is whole; widths are phi'(xi) times the EM weights."""
    def s(x):
        t = np.minimum(x / ell, 1.0)
        if both:
            t = np.minimum(t, np.minimum((length - x) / ell, 1.0))
        smooth = t * t * (3 - 2 * t)
        return dx * (1.0 / r + (1 - 1.0 / r) * smooth)
    xs = np.linspace(0.0, length, 200001)
    inv = 1.0 / s(xs)
    xi = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(xs))])
    n = int(round(xi[-1]))
    xi *= n / xi[-1]                       # scale: whole number of cells
    centres = np.interp(np.arange(n) + 0.5, xi, xs)
    dphi = np.gradient(xs, xi)             # phi'(xi) on the fine grid
    jac = np.interp(np.arange(n) + 0.5, xi, dphi)
    return centres, jac * em_weights(n, low=both, high=True), jac


def graded_body(dx, r, ell):
    xc, wx, sx = graded_axis(L0, dx, r, ell, both=False)
    yc, wy, sy = graded_axis(H0, dx, r, ell, both=True)
    X, Y = np.meshgrid(xc, yc, indexing="ij")
    V = np.outer(wx, wy).ravel() * T0
    S = np.maximum.outer(sx, sy).ravel()
    return np.c_[X.ravel(), Y.ravel()], V, S, xc, yc


def solve_graded(dx, nu, r, ell, alpha, F=-10.0):
    Xb, Vb, Sb, xc, yc = graded_body(dx, r, ell); nb = len(Xb)
    X, V, S, src = with_mirror(Xb, Vb, Sb, 3 * dx); N = len(X)
    h = 1.2 * S
    I, J, d, rr, hi, g, c, P = fit_ops(X, V, h)
    B = bmatrix(N, I, J, g)
    wts = np.r_[Vb, np.zeros(N - nb)]
    K = (B.T @ sp.kron(sp.diags(wts), sp.csr_matrix(Cmat(nu))) @ B).tocsr()
    if alpha > 0:
        real = np.r_[np.ones(nb, bool), np.zeros(N - nb, bool)]
        K = K + sp.kron(hg_matrix("ganz", N, I, J, d, rr, hi, g, c, P, V, alpha, real), sp.eye(2))
    rows = np.r_[np.arange(2 * nb), 2 * (nb + np.arange(len(src))), 2 * (nb + np.arange(len(src))) + 1]
    cols = np.r_[np.arange(2 * nb), 2 * src, 2 * src + 1]
    T = sp.csr_matrix((np.r_[np.ones(2 * nb), -np.ones(2 * len(src))], (rows, cols)), shape=(2 * N, 2 * nb))
    Kb = (T.T @ K @ T).tocsc()
    b = np.zeros((N, 2)); np.add.at(b, I, wts[I][:, None] * g); np.add.at(b, J, -wts[I][:, None] * g)
    face = Xb[:, 0] > L0 / 2
    f = np.zeros(2 * nb); f[2 * np.where(face)[0] + 1] = F / (H0 * T0) * (-b[:nb][face, 0])
    u = spla.spsolve(Kb, f)
    tip = np.isclose(Xb[:, 0], xc[-1])
    return u[2 * np.where(tip)[0] + 1].mean(), nb, xc[-1], yc


if __name__ == "__main__":
    from esph import fe
    nu, r, ell_dx, alpha = (float(a) for a in sys.argv[1:5])
    P_ = fe.PROBLEMS["beam"]
    mesh = fe.make_mesh(P_, 2); lam, mu = fe.lame(P_.E, nu, "stress")
    s = fe.SVKSolver(mesh, lam, mu, thickness=P_.t)
    f = s.face_load(P_.L, np.array([0.0, 1.0])) * -1e-3
    ufe, it, rel = s.newton(np.zeros(s.N), f)
    for dx in (0.004, 0.002, 0.001):
        t = time.time()
        v, nb, xtip, yc = solve_graded(dx, nu, r, ell_dx * dx, alpha)
        pts = np.vstack([np.full(len(yc), xtip), yc])   # the particles' tip column
        ref = (s.column_probe(pts) @ ufe[1::2]) * 1e4
        print(f"nu {nu} r {r:g} ell {ell_dx:g} dx alpha {alpha}: dx {dx*1e3:g} mm "
              f"{(v / ref - 1) * 100:+.4f}% ({nb} particles, {time.time() - t:.0f} s)", flush=True)

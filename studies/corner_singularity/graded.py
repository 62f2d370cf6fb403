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
    Xb, Vb, Sb, xc, yc = graded_body(dx, r, ell)
    return solve_body(Xb, Vb, Sb, dx, nu, "ganz", alpha, F, xc[-1]), len(Xb), xc[-1], yc


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

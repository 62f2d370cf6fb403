"""graded.py with volumes exact for quadratics on the graded axes: each cell
[a_i, b_i] integrates the quadratic through the three nearest centres (on
the clamp axis, of the body mirrored about x = 0, as the mirror clamp sees
it; on a uniform axis these are the Euler-Maclaurin weights).
usage: python graded2.py nu r ell_in_dx alpha [exact_low 0|1] [dxs]"""
import sys, time
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parent))
from graded import *
import graded as G

def quad_weights(centres, edges):
    n = len(centres); w = np.zeros(n)
    for i in range(n):
        k = min(max(i - 1, 0), n - 3); idx = np.arange(k, k + 3)
        a, b = edges[i], edges[i + 1]
        # weights of the 3-point interpolant integrated over [a, b]
        x = centres[idx]
        for m in range(3):
            others = [x[j] for j in range(3) if j != m]
            coeffs = np.poly(others) / np.prod([x[m] - o for o in others])
            P = np.polyint(coeffs)
            w[idx[m]] += np.polyval(P, b) - np.polyval(P, a)
    return w

def graded_axis2(length, dx, r, ell, both, exact_low):
    c, w_old, jac = G.graded_axis(length, dx, r, ell, both)
    # cell edges: midpoints between centres, ends at 0 and length
    edges = np.r_[0.0, 0.5 * (c[1:] + c[:-1]), length]
    if exact_low:
        w = quad_weights(c, edges)
    else:   # mirror end: exact for quadratics on the symmetric extension [-length, length]
        cf = np.r_[-c[::-1], c]; ef = np.r_[-edges[::-1], edges[1:]]
        w = quad_weights(cf, ef)[len(c):]
    return c, w, jac

def graded_body2(dx, r, ell):
    xc, wx, sx = graded_axis2(L0, dx, r, ell, False, EXACT_LOW)
    yc, wy, sy = graded_axis2(H0, dx, r, ell, True, True)
    X, Y = np.meshgrid(xc, yc, indexing="ij")
    V = np.outer(wx, wy).ravel() * T0
    S = np.maximum.outer(sx, sy).ravel()
    return np.c_[X.ravel(), Y.ravel()], V, S, xc, yc

EXACT_LOW = True
if __name__ == "__main__":
    from esph import fe
    nu, r, ell_dx, alpha = (float(a) for a in sys.argv[1:5])
    EXACT_LOW = sys.argv[5] == "1" if len(sys.argv) > 5 else True
    dxs = [float(v) for v in sys.argv[6].split(",")] if len(sys.argv) > 6 else (0.004, 0.002, 0.001)
    P_ = fe.PROBLEMS["beam"]
    mesh = fe.make_mesh(P_, 2); lam, mu = fe.lame(P_.E, nu, "stress")
    s = fe.SVKSolver(mesh, lam, mu, thickness=P_.t)
    f = s.face_load(P_.L, np.array([0.0, 1.0])) * -1e-3
    ufe, it, rel = s.newton(np.zeros(s.N), f)
    for dx in dxs:
        t = time.time()
        ell = ell_dx * dx if ell_dx > 0 else -ell_dx   # negative: fixed length in m
        Xb, Vb, Sb, xc, yc = graded_body2(dx, r, ell)
        v = solve_body(Xb, Vb, Sb, dx, nu, "ganz", alpha, -10.0, xc[-1])
        pts = np.vstack([np.full(len(yc), xc[-1]), yc])
        ref = (s.column_probe(pts) @ ufe[1::2]) * 1e4
        print(f"nu {nu} r {r:g} ell {ell_dx:g} alpha {alpha} exact_low {EXACT_LOW}: "
              f"dx {dx*1e3:g} mm {(v / ref - 1) * 100:+.4f}% ({len(Xb)} particles, "
              f"{time.time() - t:.0f} s)", flush=True)

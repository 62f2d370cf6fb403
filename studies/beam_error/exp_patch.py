"""Patch tests for the variants.
(1) consistency: affine u -> grad u exact at every particle (free body, equal or 'exact2' volumes);
    linearised rigid rotation -> zero strain.
(2) clamped bar, nu = 0, axial tip load Fx: strain uniformity and tip u_x vs F s/(E A);
    the field u = (eps x, 0) is exactly representable with mirror ghosts (odd in x), not with
    fixed clamp particles at x < 0."""
import numpy as np, scipy.sparse.linalg as spla
from sphbeam import geometry, gradients, bmatrix, E0, T0, L0, H0
from variants import build, row_factor
rng = np.random.default_rng(0)
for order in (1, 2):
    for rows in ("midpoint", "exact2"):
        dx = 2e-3
        X, col, nx, ny = geometry(dx, nclamp=0)
        V = dx*dx*T0*(row_factor(X, col, nx, ny, dx) if rows == "exact2" else np.ones(len(X)))
        I, J, g, A = gradients(X, V, 1.2*dx, order)
        B = bmatrix(len(X), I, J, g)
        Aff = rng.standard_normal((2, 2))*1e-3
        u = (X@Aff.T).ravel()
        e = (B@u).reshape(-1, 3)
        ex = np.array([Aff[0, 0], Aff[1, 1], Aff[0, 1]+Aff[1, 0]])
        rot = (np.c_[-X[:, 1], X[:, 0]]*1e-3).ravel()
        print(f"(1) order {order} {rows}: max |strain - exact| affine {np.abs(e-ex).max():.1e} (|A|~1e-3), "
              f"rigid rotation max strain {np.abs(B@rot).max():.1e}")
F = 1000.0
for order in (1, 2):
    for kw in [dict(clamp="fixed"), dict(clamp="mirror"), dict(clamp="mirror", rows="exact2", rowsmode="volume")]:
        R = build(2e-3, order, **kw)
        beam, nx, ny, X = R['beam'], R['nx'], R['ny'], R['X']
        colb = R['col'][beam]
        tipb = np.where(colb == nx-1)[0]
        f = np.zeros(R['Kr'].shape[0]); f[2*tipb] = F/len(tipb)
        u = spla.spsolve(R['Kr'].tocsc(), f)
        s = L0 - 1e-3
        ex = F*s/(E0*H0*T0)
        Xg, colg, _, _ = geometry(2e-3)
        Ig, Jg, gg, _ = gradients(Xg, R['V'], 1.2*2e-3, order)
        eps = (bmatrix(len(Xg), Ig, Jg, gg)@(R['T']@u)).reshape(-1, 3)[beam, 0].reshape(nx, ny)
        epsx = eps.mean(axis=1)
        # consistency near the clamp: impose u = (eps x, 0) on the beam, ghosts by the clamp map
        ub = np.zeros(2*len(beam)); ub[0::2] = 1e-3*X[beam, 0]
        full = R['T']@ub
        Bfull = None
        print(f"(2) order {order} {str(kw):60s}: tip ux/(F s/EA) - 1 = {100*(u[2*tipb].mean()/ex-1):+.3f}%, "
              "SPH exx/(F/EA) column means at cols 0,1,2,mid,nx-2,nx-1: " + " ".join(f"{epsx[k]/(F/(E0*H0*T0)):.4f}" for k in (0, 1, 2, nx//2, nx-2, nx-1)))
# (3) representability of u=(eps x, 0) at the first beam columns
for kw in [dict(clamp="fixed"), dict(clamp="mirror")]:
    for order in (1, 2):
        dx = 2e-3
        X, col, nx, ny = geometry(dx)
        R = build(dx, order, **kw)
        I, J, g, A = gradients(X, R['V'], 1.2*dx, order)
        B = bmatrix(len(X), I, J, g)
        ub = np.zeros(2*len(R['beam'])); ub[0::2] = 1e-3*X[R['beam'], 0]
        e = (B@(R['T']@ub)).reshape(-1, 3)[R['beam']]
        c = col[R['beam']]
        print(f"(3) {kw['clamp']:6s} order {order}: imposed exx = 1e-3; computed exx/1e-3 at beam cols 0,1,2,3: "
              + " ".join(f"{e[c == k, 0].mean()/1e-3:.4f}" for k in range(4)))

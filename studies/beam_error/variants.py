"""Clamp and integration-weight variants of the linearised SPH beam.

clamp = 'fixed'   : baseline (clamp particles fixed, their energy counted)
        'noenergy': fixed, energy not counted (same as giving them F = I)
        'mirror'  : clamp particles are odd mirror ghosts, u(-x,y) = -u(x,y) (u = 0 on x = 0),
                    ghost energy not counted (they are outside the body)
        'mirrorE' : mirror ghosts, ghost energy counted
rows  = 'midpoint': equal V; 'exact2': top/bottom two rows get weights 1 +/- d, d = H/(24(H-2dx)),
                    so the nodal rule integrates 1, y, y^2, y^3 exactly over the section
rowsmode = 'energy' (integration weight only) or 'volume' (the particle volume V itself, i.e.
           'set volume' in LAMMPS: gradient correction and integration both use it)
"""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
from sphbeam import geometry, gradients, bmatrix, stiffness, Cmat, exact_v, E0, NU0, T0, L0, H0

def row_factor(X, col, nx, ny, dx, H=H0):
    k = np.rint(X[:, 1]/dx - 0.5).astype(int)
    d = H/(24*(H - 2*dx))
    f = np.ones(len(X))
    f[(k == 0) | (k == ny-1)] = 1 + d
    f[(k == 1) | (k == ny-2)] = 1 - d
    return f

# ghost extrapolation coefficients on beam columns (0, 1) for ghost columns -1, -2, -3 (u(0) = 0)
EXTRAP = {"mirror": None,
          "extrap1": {-1: (-1, 0), -2: (-3, 0), -3: (-5, 0)},       # line through u(0)=0 and column 0
          "extrap2": {-1: (-2, 1/3), -2: (-9, 2), -3: (-20, 5)}}    # parabola through u(0)=0, columns 0, 1

def build(dx, order=1, clamp="fixed", rows="midpoint", rowsmode="energy", nclamp=3, hfac=1.2,
          nu=NU0, L=L0, H=H0, t=T0, noclampE=False):
    X, col, nx, ny = geometry(dx, L, H, nclamp)
    if clamp == "shift":        # fixed clamp columns moved by +dx/2: first one on the face x = 0
        X[col < 0, 0] += dx/2
    N = len(X)
    fac = row_factor(X, col, nx, ny, dx, H) if rows == "exact2" else np.ones(N)
    V = dx*dx*t*(fac if rowsmode == "volume" else np.ones(N))
    I, J, g, A = gradients(X, V, hfac*dx, order)
    B = bmatrix(N, I, J, g)
    w = dx*dx*t*fac
    if clamp in ("noenergy", "mirror", "extrap1", "extrap2") or (clamp == "shift" and noclampE):
        w[col < 0] = 0.0
    K = stiffness(B, w, Cmat(E0, nu))
    beam = np.where(col >= 0)[0]
    # T: beam dofs -> all dofs
    rows_, cols_, vals_ = [], [], []
    bindex = -np.ones(N, int); bindex[beam] = np.arange(len(beam))
    for a in range(2):
        rows_.append(2*beam+a); cols_.append(2*bindex[beam]+a); vals_.append(np.ones(len(beam)))
    if clamp in ("extrap1", "extrap2"):
        gh = np.where(col < 0)[0]
        k = np.rint(X[gh, 1]/dx - 0.5).astype(int)
        for a in range(2):
            for m_, ci in enumerate((0, 1)):
                coef = np.array([EXTRAP[clamp][c][m_] for c in col[gh]])
                src = (ci + nclamp)*ny + k
                rows_.append(2*gh+a); cols_.append(2*bindex[src]+a); vals_.append(coef)
    if clamp.startswith("mirror"):
        gh = np.where(col < 0)[0]
        k = np.rint(X[gh, 1]/dx - 0.5).astype(int)
        mcol = -col[gh] - 1
        assert (mcol < nx).all()
        mirror = (mcol + nclamp)*ny + k
        assert np.allclose(X[mirror, 0], -X[gh, 0]) and np.allclose(X[mirror, 1], X[gh, 1])
        for a in range(2):
            rows_.append(2*gh+a); cols_.append(2*bindex[mirror]+a); vals_.append(-np.ones(len(gh)))
    T = sp.csr_matrix((np.concatenate(vals_), (np.concatenate(rows_), np.concatenate(cols_))),
                      shape=(2*N, 2*len(beam)))
    Kr = (T.T@K@T).tocsr()
    return dict(X=X, col=col, nx=nx, ny=ny, K=K, Kr=Kr, T=T, beam=beam, V=V, w=w)

def solve(dx, order=1, F=-10.0, **kw):
    R = build(dx, order, **kw)
    X, col, nx, beam = R['X'], R['col'], R['nx'], R['beam']
    tipb = np.where(col[beam] == nx-1)[0]
    f = np.zeros(R['Kr'].shape[0]); f[2*tipb+1] = F/len(tipb)
    u = spla.spsolve(R['Kr'].tocsc(), f)
    dv = u[2*tipb+1].mean()
    ref = exact_v(L0 - dx/2, F)
    R.update(u=u, dv=dv, ref=ref, err=dv/ref-1, f=f)
    return R

def lowest_omegas(R, k=6, rho=1000.0):
    m = np.repeat(rho*R['V'][R['beam']], 2)
    s = sp.diags(1/np.sqrt(m))
    vals = spla.eigsh((s@R['Kr']@s).tocsc(), k=k, sigma=-1.0, which='LM', return_eigenvectors=False)
    return np.sqrt(np.abs(np.sort(vals)))

if __name__ == "__main__":
    import itertools
    print("relative error of tip dv vs EB at s = L-dx/2 (load at L), %")
    for clamp, rows, mode in [("fixed", "midpoint", "energy"), ("fixed", "exact2", "energy"),
                              ("fixed", "exact2", "volume"), ("noenergy", "midpoint", "energy"),
                              ("mirror", "midpoint", "energy"), ("mirrorE", "midpoint", "energy"),
                              ("mirror", "exact2", "energy"), ("mirror", "exact2", "volume")]:
        for order in (1, 2):
            errs = [100*solve(d*1e-3, order, clamp=clamp, rows=rows, rowsmode=mode)['err'] for d in (4, 2, 1)]
            print(f"clamp {clamp:8s} rows {rows:8s} ({mode:6s}) order {order}: "
                  + "  ".join(f"{d}mm {e:+7.3f}" for d, e in zip((4, 2, 1), errs)))

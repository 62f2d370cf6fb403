"""Stability: lowest natural frequencies (rho = 1000) of the clamped beam for the variants,
labelled smooth/alternating (x-roughness), vs the continuum Q9 values; free-free null space size."""
import numpy as np, scipy.linalg as sla, scipy.sparse as sp
from variants import build
from sphbeam import geometry, gradients, bmatrix, stiffness, Cmat, E0
cont = [2254.8, 13616.5, 35124.1, 36159.3, 66289.3, 101913.8]
def spectrum(R, rho=1000.0, k=10):
    m = np.repeat(rho*R['V'][R['beam']], 2)
    s = 1/np.sqrt(m)
    lam, Phi = sla.eigh(s[:, None]*R['Kr'].toarray()*s[None, :])
    nx, ny = R['nx'], R['ny']
    U = (s[:, None]*Phi).reshape(nx, ny, 2, -1)
    ax = U[2:]-2*U[1:-1]+U[:-2]
    rough = np.sqrt((ax**2).sum(axis=(0, 1, 2))/(U**2).sum(axis=(0, 1, 2)))
    return np.sqrt(np.abs(lam)), rough
def freefree(dx, order, rows="midpoint", rowsmode="energy"):
    from variants import row_factor
    X, col, nx, ny = geometry(dx, nclamp=0)
    fac = row_factor(X, col, nx, ny, dx) if rows == "exact2" else np.ones(len(X))
    V = dx*dx*1e-3*(fac if rowsmode == "volume" else np.ones(len(X)))
    I, J, g, A = gradients(X, V, 1.2*dx, order)
    K = stiffness(bmatrix(len(X), I, J, g), dx*dx*1e-3*fac, Cmat()).toarray()
    ev = np.linalg.eigvalsh(K)
    return (ev < 1e-10*ev.max()).sum(), ev[3]/ev.max()
if __name__ == "__main__":
    print("continuum:", cont)
    for dxmm in (4, 2):
        dx = dxmm*1e-3
        for clamp, rows, mode in [("fixed", "midpoint", "energy"), ("mirror", "midpoint", "energy"),
                                  ("mirror", "exact2", "volume"), ("fixed", "exact2", "volume")]:
            for order in (1, 2):
                w, r = spectrum(build(dx, order, clamp=clamp, rows=rows, rowsmode=mode))
                alt = w[r > 2.0]
                print(f"dx {dxmm} {clamp:6s} {rows:8s} order {order}: lowest omega "
                      + " ".join(f"{x:.0f}" for x in w[:6]) + f" | lowest x-alternating mode {alt.min():.0f}")
        for order in (1, 2):
            for rows, mode in [("midpoint", "energy"), ("exact2", "volume")]:
                nz, r4 = freefree(dx, order, rows, mode)
                print(f"  free-free dx {dxmm} order {order} rows {rows}: zero eigenvalues {nz} (3 = rigid only), "
                      f"4th/max = {r4:.2e}")

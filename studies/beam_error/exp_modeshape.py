"""Mode shapes of the SPH clamped beam: smoothness (fraction of alternating component) and where it lives."""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla, sys
from sphbeam import solve_beam
rho = 1000.0
def analyse(R, k=6):
    m = np.repeat(rho*R['V'], 2)[R['free']]
    Mi = sp.diags(1/np.sqrt(m))
    vals, vecs = spla.eigsh((Mi@R['Kf']@Mi).tocsc(), k=k, sigma=-1.0, which='LM')
    o = np.argsort(vals); vals, vecs = vals[o], vecs[:, o]
    nx, ny = R['nx'], R['ny']
    out = []
    for lam, v in zip(vals, vecs.T):
        u = np.zeros(len(R['free'])); u[R['free']] = Mi@v
        U = u.reshape(-1, 2)[R['col'] >= 0].reshape(nx, ny, 2)
        # second difference in x and y (alternating content)
        ax = U[2:] - 2*U[1:-1] + U[:-2]; ay = U[:, 2:] - 2*U[:, 1:-1] + U[:, :-2]
        rough = (np.sqrt((ax**2).sum()/(U**2).sum()), np.sqrt((ay**2).sum()/(U**2).sum()))
        amp = np.sqrt((U**2).sum(axis=(1, 2)))
        icen = (amp*np.arange(nx)).sum()/amp.sum()
        out.append((np.sqrt(abs(lam)), rough, icen/nx, np.abs(U[..., 0]).max()/np.abs(U[..., 1]).max()))
    return out
if __name__ == "__main__":
    dx = float(sys.argv[1])*1e-3 if len(sys.argv) > 1 else 2e-3
    for order in (1, 2):
        R = solve_beam(dx, order, return_all=True)
        print(f"order {order}:")
        for w, r, c, uxuy in analyse(R, 8):
            print(f"  omega {w:9.1f}  roughness x,y {r[0]:.3f},{r[1]:.3f}  centroid x/L {c:.2f}  max|ux|/max|uy| {uxuy:.2f}")

"""Linearised hourglass energy of pair_style sph/icb (U_hg = 1/4 sum_i sum_j k_ij |d_ij|^2,
d_ij = u_j - u_i - (G_i + G_j)/2 X_ij, k_ij = alpha E (V_i|g_ij| + V_j|g_ji|)/(2 r)), added to the
variants of variants.py; i runs over 'owners' (all particles, or beam only for ghost clamps)."""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
from sphbeam import geometry, gradients, E0, L0, exact_v
import variants

def hg_matrix(X, V, I, J, g, alpha, owner_mask):
    N = len(X); npair = len(I)
    # full gradient G_i[a,b] as rows 4i + 2a + b
    r, c, v = [], [], []
    for a in range(2):
        for b in range(2):
            r += [4*I+2*a+b, 4*I+2*a+b]; c += [2*J+a, 2*I+a]; v += [g[:, b], -g[:, b]]
    G = sp.csr_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))), shape=(4*N, 2*N))
    # pair lookup for g_ji
    key = {(i, j): p for p, (i, j) in enumerate(zip(I, J))}
    rev = np.array([key[(j, i)] for i, j in zip(I, J)])
    Xd = X[J] - X[I]; R = np.linalg.norm(Xd, axis=1)
    hgw = 0.5*(V[I]*np.linalg.norm(g, axis=1) + V[J]*np.linalg.norm(g[rev], axis=1))/R
    k = alpha*E0*hgw
    sel = owner_mask[I]
    rows, cols, vals = [], [], []
    P = np.arange(npair)
    for a in range(2):
        # u_j - u_i
        rows += [2*P+a, 2*P+a]; cols += [2*J+a, 2*I+a]; vals += [np.ones(npair), -np.ones(npair)]
    D1 = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(2*npair, 2*N))
    # -(G_i + G_j)/2 X : selector matrices
    rows, cols, vals = [], [], []
    for a in range(2):
        for b in range(2):
            rows += [2*P+a, 2*P+a]; cols += [4*I+2*a+b, 4*J+2*a+b]; vals += [-0.5*Xd[:, b], -0.5*Xd[:, b]]
    S = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(2*npair, 4*N))
    D = (D1 + S@G).tocsr()
    kk = np.repeat(np.where(sel, k, 0.0), 2)
    return (0.5*D.T@sp.diags(kk)@D).tocsr()

def solve_hg(dx, order, alpha, F=-10.0, **kw):
    R = variants.build(dx, order, **kw)
    X, col = R['X'], R['col']
    I, J, g, A = gradients(X, R['V'], 1.2*dx, order)
    owner = np.ones(len(X), bool)
    if kw.get("clamp", "fixed") in ("mirror", "extrap1", "noenergy"):
        owner = col >= 0
    Khg = hg_matrix(X, R['V'], I, J, g, alpha, owner) if alpha > 0 else None
    Kr = R['Kr'] + (R['T'].T@Khg@R['T'] if alpha > 0 else 0)
    R['Kr'] = Kr.tocsr()
    beam, nx = R['beam'], R['nx']
    tipb = np.where(col[beam] == nx-1)[0]
    f = np.zeros(Kr.shape[0]); f[2*tipb+1] = F/len(tipb)
    u = spla.spsolve(R['Kr'].tocsc(), f)
    R.update(u=u, dv=u[2*tipb+1].mean(), err=u[2*tipb+1].mean()/exact_v(L0-dx/2, F)-1)
    return R

if __name__ == "__main__":
    from exp_stability import spectrum
    for order in (2, 1):
        for kw in [dict(clamp="fixed"), dict(clamp="mirror"), dict(clamp="mirror", rows="exact2", rowsmode="volume")]:
            for alpha in (0.0, 0.05, 0.2, 1.0):
                errs = [100*solve_hg(d*1e-3, order, alpha, **kw)['err'] for d in (4, 2, 1)]
                w, r = spectrum(solve_hg(2e-3, order, alpha, **kw))
                print(f"order {order} {str(kw):62s} alpha {alpha:4.2f}: err 4/2/1 mm "
                      + " ".join(f"{e:+7.3f}" for e in errs)
                      + f" | 2mm omega1 {w[0]:.0f}, lowest alternating {w[r > 2].min():.0f}")

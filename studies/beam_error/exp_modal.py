"""(e) modal decomposition of the static tip deflection: contribution of smooth vs x-alternating
(hourglass-like) modes.  Dense generalized eigenproblem K phi = lam M phi, M = rho V (lumped)."""
import numpy as np, scipy.linalg as sla, sys
from sphbeam import solve_beam
def modal(dx, order, **kw):
    R = solve_beam(dx, order, return_all=True, **kw)
    fr = R['free']; nx, ny = R['nx'], R['ny']
    m = np.repeat(R['V'], 2)[fr]
    Kd = R['Kf'].toarray()
    s = 1/np.sqrt(m)
    lam, Phi = sla.eigh(s[:, None]*Kd*s[None, :])
    Phi = s[:, None]*Phi              # M-orthonormal
    f = R['f'][fr]
    tipdofs = np.zeros(len(R['f'])); tip = np.where(R['col'] == nx-1)[0]
    tipdofs[2*tip+1] = 1/len(tip); tipdofs = tipdofs[fr]
    contrib = (Phi.T@f)*(Phi.T@tipdofs)/lam
    # roughness along x of each mode (beam part)
    beam = (R['col'] >= 0)
    full = np.zeros((len(R['f']), len(lam))); full[fr] = Phi
    U = full.reshape(-1, 2, len(lam))[beam].reshape(nx, ny, 2, len(lam))
    ax = U[2:]-2*U[1:-1]+U[:-2]
    rough = np.sqrt((ax**2).sum(axis=(0, 1, 2))/(U**2).sum(axis=(0, 1, 2)))
    return lam, contrib, rough, R['dv']
if __name__ == "__main__":
    for dxmm in (4, 2):
        for order in (1, 2):
            lam, c, r, dv = modal(dxmm*1e-3, order)
            ro = r > 2.0
            print(f"dx {dxmm} order {order}: dv {dv*1e3:.5f} mm = sum modes {c.sum()*1e3:.5f}; "
                  f"x-alternating modes (roughness>2) contribute {100*c[ro].sum()/dv:+.4f}% of dv; "
                  f"lowest such omega(rho=1000) {np.sqrt(lam[ro].min()/1000):.0f}; first mode alone {100*c[0]/dv:.2f}%")

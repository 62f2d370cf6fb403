"""Smallest eigenvalues of the clamped stiffness (mass-normalised, rho=1000) vs EB cantilever modes,
and the free-free spectrum (count of (near) zero-energy modes)."""
import numpy as np, scipy.sparse.linalg as spla, scipy.sparse as sp, sys
from sphbeam import solve_beam, E0, T0, L0, H0
rho = 1000.0
I = T0*H0**3/12; A = T0*H0
beta = np.array([1.8751, 4.6941, 7.8548, 10.9955])
w_eb = beta**2*np.sqrt(E0*I/(rho*A*L0**4))
def smallest(K, m, k=8):
    Mi = sp.diags(1/np.sqrt(m))
    Kn = (Mi @ K @ Mi).tocsc()
    vals = spla.eigsh(Kn, k=k, sigma=-1.0, which='LM', return_eigenvectors=False)
    return np.sort(vals)
if __name__ == "__main__":
    dx = float(sys.argv[1])*1e-3 if len(sys.argv) > 1 else 2e-3
    print("EB cantilever omega (rad/s):", np.round(w_eb, 1))
    for order in (1, 2):
        for ce in (True, False):
            R = solve_beam(dx, order, clamp_energy=ce, return_all=True)
            m = np.repeat(rho*R['V'], 2)[R['free']]
            ev = smallest(R['Kf'], m, 6)
            print(f"order {order} clamp energy {ce}: omega = {np.round(np.sqrt(np.abs(ev)),1)}")
        # free-free (no clamp columns at all)
        R = solve_beam(dx, order, nclamp=0, return_all=True) if False else None

"""Lowest x-alternating (hourglass-like) mode of the FREE-FREE beam (no clamp at all), for comparison
with the clamped variants: is the mode the mirror clamp lets through already present at a free end?"""
import numpy as np, scipy.linalg as sla
from sphbeam import geometry, gradients, bmatrix, stiffness, Cmat
for dxmm in (4, 2):
    dx = dxmm*1e-3
    for order in (1, 2):
        X, col, nx, ny = geometry(dx, nclamp=0)
        V = np.full(len(X), dx*dx*1e-3)
        I, J, g, A = gradients(X, V, 1.2*dx, order)
        K = stiffness(bmatrix(len(X), I, J, g), V, Cmat()).toarray()
        m = np.repeat(1000*V, 2); s = 1/np.sqrt(m)
        lam, Phi = sla.eigh(s[:, None]*K*s[None, :]); Phi = s[:, None]*Phi
        U = Phi.reshape(nx, ny, 2, -1); ax = U[2:]-2*U[1:-1]+U[:-2]
        rough = np.sqrt((ax**2).sum(axis=(0, 1, 2))/(U**2).sum(axis=(0, 1, 2)))
        w = np.sqrt(np.abs(lam))
        k = np.where(rough > 2)[0][0]
        amp = np.sqrt((U[..., k]**2).sum(axis=(1, 2)))
        print(f"free-free dx {dxmm} order {order}: first elastic omegas {np.round(w[3:6])}, lowest alternating {w[k]:.0f}, "
              f"amplitude ends/middle {amp[0]/amp.max():.2f} {amp[nx//2]/amp.max():.2f} {amp[-1]/amp.max():.2f}")

"""Hourglass energy of a pure-bending (quadratic) field, relative to its elastic energy:
with the quadratic gradient F is exact for quadratic fields, so d_ij = 0 and U_hg = 0."""
import numpy as np
from sphbeam import geometry, gradients, bmatrix, stiffness, Cmat, T0
from hourglass import hg_matrix
dx = 2e-3
X, col, nx, ny = geometry(dx, nclamp=0)
V = np.full(len(X), dx*dx*T0)
kap = 1e-2; y = X[:, 1] - 0.01
u = np.c_[-kap*X[:, 0]*y, 0.5*kap*X[:, 0]**2].ravel()     # pure bending, nu = 0
for order in (1, 2):
    I, J, g, A = gradients(X, V, 1.2*dx, order)
    Ke = stiffness(bmatrix(len(X), I, J, g), V, Cmat())
    Kh = hg_matrix(X, V, I, J, g, 1.0, np.ones(len(X), bool))
    print(f"order {order}: U_hg/U_elastic (alpha=1) for pure bending = {(u@Kh@u)/(u@Ke@u):.2e}")

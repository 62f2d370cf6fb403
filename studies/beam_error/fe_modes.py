"""Continuum (Q9 FE, plane stress, clamped at x=0) lowest natural frequencies, rho = 1000."""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
from fe_continuum import q9_shape
from sphbeam import E0, NU0, T0, L0, H0, Cmat
def modes(ex=200, ey=6, k=8, rho=1000.0):
    xs = np.linspace(0, L0, 2*ex+1); ys = np.linspace(0, H0, 2*ey+1)
    nid = np.arange(len(xs)*len(ys)).reshape(len(xs), len(ys))
    hx, hy = L0/ex, H0/ey
    C = Cmat(E0, NU0)*T0
    gp, gw = np.polynomial.legendre.leggauss(3)
    Ke = np.zeros((18, 18)); Me = np.zeros((18, 18))
    for a, wa in zip(gp, gw):
        for b, wb in zip(gp, gw):
            N, dNx, dNy = q9_shape(a, b); dNx = dNx*2/hx; dNy = dNy*2/hy
            B = np.zeros((3, 18)); B[0, 0::2] = dNx; B[1, 1::2] = dNy; B[2, 0::2] = dNy; B[2, 1::2] = dNx
            Nm = np.zeros((2, 18)); Nm[0, 0::2] = N; Nm[1, 1::2] = N
            jw = wa*wb*hx*hy/4
            Ke += B.T@C@B*jw; Me += rho*T0*Nm.T@Nm*jw
    r, c, vk, vm = [], [], [], []
    for e in range(ex):
        for f in range(ey):
            nodes = nid[2*e:2*e+3, 2*f:2*f+3].ravel(); dofs = np.c_[2*nodes, 2*nodes+1].ravel()
            r.append(np.repeat(dofs, 18)); c.append(np.tile(dofs, 18)); vk.append(Ke.ravel()); vm.append(Me.ravel())
    n = 2*nid.size
    K = sp.csr_matrix((np.concatenate(vk), (np.concatenate(r), np.concatenate(c))), shape=(n, n))
    M = sp.csr_matrix((np.concatenate(vm), (np.concatenate(r), np.concatenate(c))), shape=(n, n))
    free = np.ones(n, bool); free[np.c_[2*nid[0], 2*nid[0]+1].ravel()] = False
    vals = spla.eigsh(K[free][:, free].tocsc(), M=M[free][:, free].tocsc(), k=k, sigma=0, return_eigenvectors=False)
    return np.sqrt(np.sort(vals))
if __name__ == "__main__":
    print("continuum omega (rad/s):", np.round(modes(), 1))

"""(a),(c),(d): effective bending stiffness from a pure end moment, and an interior cubic fit of
the tip-load deflection giving effective clamp position x0, load position a and shear slope.
v(x) = F/EI [a (x-x0)^2/2 - (x-x0)^3/6] + gam (x-x0) on interior columns 0.2L..0.8L."""
import numpy as np, scipy.sparse.linalg as spla, sys
from sphbeam import solve_beam, E0, T0, L0, H0, exact_v
from scipy.optimize import least_squares
I = T0*H0**3/12

def centreline(R):
    nx, ny = R['nx'], R['ny']
    U = R['u'].reshape(-1, 2)[R['col'] >= 0].reshape(nx, ny, 2)
    X = R['X'][R['col'] >= 0].reshape(nx, ny, 2)
    return X[:, 0, 0], U[..., 1].mean(axis=1), U, X

def moment_test(dx, order, **kw):
    R = solve_beam(dx, order, return_all=True, **kw)
    nx, ny = R['nx'], R['ny']
    tip = np.where(R['col'] == nx-1)[0]
    yc = R['X'][tip, 1] - H0/2
    M = 1e-2  # N m
    f = np.zeros_like(R['f']); f[2*tip] = -M*yc/(yc**2).sum()   # couple: top row pulled back
    u = np.zeros_like(f); u[R['free']] = spla.spsolve(R['Kf'].tocsc(), f[R['free']])
    R['u'] = u
    x, v, U, X = centreline(R)
    sel = (x > 0.25*L0) & (x < 0.75*L0)
    c = np.polyfit(x[sel], v[sel], 2)
    kappa = 2*c[0]
    # curvature from rotation: theta = -d ux/dy (row fit), kappa = d theta/dx
    th = np.array([-np.polyfit(X[i, :, 1], U[i, :, 0], 1)[0] for i in range(nx)])
    k2 = np.polyfit(x[sel], th[sel], 1)[0]
    return (M/I/E0)/kappa, (M/I/E0)/k2   # EI_eff/EI from v'' and from theta'

def fit_tip(dx, order, F=-10.0, **kw):
    R = solve_beam(dx, order, F=F, return_all=True, **kw)
    x, v, U, X = centreline(R)
    sel = (x > 0.2*L0) & (x < 0.8*L0)
    c3, c2, c1, c0 = np.polyfit(x[sel], v[sel], 3)
    EI = -F/(6*c3)
    # a + x0 = 2 EI c2 / F ; solve remaining for x0, gam
    S = 2*EI*c2/F
    def res(p):
        x0, gam = p; a = S - x0
        return [F/EI*(-a*x0 - x0**2/2) + gam - c1, F/EI*(a*x0**2/2 + x0**3/6) - gam*x0 - c0]
    x0, gam = least_squares(res, [0.0, 0.0], x_scale=[1e-3, 1e-3]).x
    a = S - x0
    s = L0 - dx/2
    vfit = F/EI*(a*(s-x0)**2/2 - (s-x0)**3/6) + gam*(s-x0)
    return dict(EIr=EI/(E0*I), x0=x0, a=a, gam_rel=gam/(F*L0**2/(2*E0*I)), dv=R['dv'], vfit=vfit, ref=R['ref'])

if __name__ == "__main__":
    for order in (1, 2):
        for dxmm in (4, 2, 1):
            dx = dxmm*1e-3
            m1, m2 = moment_test(dx, order)
            r = fit_tip(dx, order)
            print(f"order {order} dx {dxmm}: pure moment EI_eff/EI = {m1:.4f} (v''), {m2:.4f} (theta'); "
                  f"midpoint I_h/I = {1-(dx/H0)**2:.4f}")
            print(f"   tip-load interior fit: EI/EI = {r['EIr']:.4f}, x0 = {r['x0']/dx:+.3f} dx, a = L{(r['a']-L0)/dx:+.3f} dx, "
                  f"shear slope/(FL^2/2EI) = {r['gam_rel']:.4f}; tip dv vs fit extrapolation {100*(r['dv']/r['vfit']-1):+.3f}%")

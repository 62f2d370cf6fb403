"""Shape and static participation of the lowest x-alternating (hourglass-like) mode per variant."""
import numpy as np, scipy.linalg as sla, sys
from variants import build, solve
def info(dx, order, **kw):
    R = solve(dx, order, **kw)
    m = np.repeat(1000.0*R['V'][R['beam']], 2); s = 1/np.sqrt(m)
    lam, Phi = sla.eigh(s[:, None]*R['Kr'].toarray()*s[None, :]); Phi = s[:, None]*Phi
    nx, ny = R['nx'], R['ny']
    U = Phi.reshape(nx, ny, 2, -1)
    ax = U[2:]-2*U[1:-1]+U[:-2]
    rough = np.sqrt((ax**2).sum(axis=(0, 1, 2))/(U**2).sum(axis=(0, 1, 2)))
    tipb = np.where(R['col'][R['beam']] == nx-1)[0]
    t = np.zeros(len(R['f'])); t[2*tipb+1] = 1/len(tipb)
    contrib = (Phi.T@R['f'])*(Phi.T@t)/lam
    k = np.where(rough > 2)[0][0]
    Uk = U[..., k]
    amp = np.sqrt((Uk**2).sum(axis=(1, 2)))
    return dict(omega=np.sqrt(lam[k]), ux_uy=np.abs(Uk[..., 0]).max()/np.abs(Uk[..., 1]).max(),
                amp_profile=amp[[0, 1, 2, 5, nx//4, nx//2, 3*nx//4, nx-1]]/amp.max(),
                alt_share=100*contrib[rough > 2].sum()/R['dv'], err=100*R['err'])
if __name__ == "__main__":
    for dxmm in (4, 2, 1) if len(sys.argv) < 2 else [float(sys.argv[1])]:
        for kw in [dict(clamp="fixed"), dict(clamp="mirror"), dict(clamp="mirror", rows="exact2", rowsmode="volume")]:
            for order in (1, 2):
                if dxmm == 1 and order == 1: continue
                d = info(dxmm*1e-3, order, **kw)
                print(f"dx {dxmm} {kw} order {order}: err {d['err']:+.3f}%, lowest alternating omega {d['omega']:.0f}, "
                      f"|ux|/|uy| {d['ux_uy']:.2f}, amplitude at cols 0,1,2,5,L/4,L/2,3L/4,tip "
                      + " ".join(f"{a:.2f}" for a in d['amp_profile']) + f", share of static dv {d['alt_share']:+.4f}%")

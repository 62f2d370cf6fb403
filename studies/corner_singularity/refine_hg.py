"""Corner refinement (fine squares of side a dx at dx/r in the clamped corners)
with hourglass control: does the penalty remove the fine/coarse interface's soft modes?
usage: python refine_hg.py nu dx"""
import sys, time
from pathlib import Path
sys.path.insert(0, str(Path(__file__).resolve().parent))
from hg import *
def solve_rhg(dx, nu, a, r, alpha, F=-10.0):
    Xb, Vb, Sb = body(dx, a, r)
    return solve_body(Xb, Vb, Sb, dx, nu, "ganz", alpha, F, L0 - dx / 2), len(Xb)
from esph import fe
nu = float(sys.argv[1]); dx = float(sys.argv[2])
ref = fe.tip("beam", -10.0, dx, nu, "stress")["dv"]
for a, r, alpha in [(0, 2, 0.2), (3, 2, 0.0), (3, 2, 0.2), (3, 2, 0.5)]:
    t=time.time()
    v, nb = solve_rhg(dx, nu, a*dx, r, alpha)
    print(f"nu {nu} dx {dx*1e3:.0f} a={a}dx r={r} alpha {alpha}: {(v/ref-1)*100:+.4f}% ({nb} p, {time.time()-t:.0f}s)", flush=True)

"""Multiplicative decomposition of the tip-deflection error at dx (default 2 mm) vs EB (load at L, v at s=L-dx/2).
 v_SPH/v_EB = [EB load at s / EB load at L] x [continuum FE / EB, both load at s] x [1/(EI_eff/EI)]
              x [clamp: fixed / mirror]  x residual."""
import sys, numpy as np
from sphbeam import exact_v, L0
from fe_continuum import solve_fe
from exp_fit import moment_test
from variants import solve
dx = float(sys.argv[1])*1e-3 if len(sys.argv) > 1 else 2e-3
s = L0 - dx/2
eb = exact_v(s); eb_s = exact_v(s, a=s)
fe_s = solve_fe(400, 8, a_load=s, s_list=[s])[0]
fe_L = solve_fe(400, 8, s_list=[s])[0]
print(f"dx = {dx*1e3:g} mm: EB(load L) {eb*1e3:.5f} mm; (b) load at s instead of L: {100*(eb_s/eb-1):+.3f}%")
print(f"(d) continuum/EB (shear + clamp-face restraint): load at L {100*(fe_L/eb-1):+.3f}%, load at s {100*(fe_s/eb_s-1):+.3f}%;"
      f" Timoshenko 0.6(H/L)^2 = {60*(0.02/0.2)**2:.3f}%")
for order in (1, 2):
    base = solve(dx, order, clamp="fixed"); mir = solve(dx, order, clamp="mirror")
    mirw = solve(dx, order, clamp="mirror", rows="exact2", rowsmode="volume")
    EIr = moment_test(dx, order)[0]
    fac = dict(load=eb_s/eb, continuum=fe_s/eb_s, EI=1/EIr, clamp=base['dv']/mir['dv'])
    prod = np.prod(list(fac.values()))
    print(f"order {order}: total {100*base['err']:+.3f}% = " + " x ".join(f"{k} {100*(v-1):+.3f}%" for k, v in fac.items())
          + f" x residual {100*((1+base['err'])/prod-1):+.3f}%;  (a) I_h/I = {1-(dx/0.02)**2:.4f}, EI_eff/EI = {EIr:.4f}")
    print(f"    mirror clamp: {100*mir['err']:+.3f}% vs EB, {100*(mir['dv']/fe_s-1):+.3f}% vs continuum (same load point); "
          f"mirror+exact2 rows: {100*mirw['err']:+.3f}% vs EB, {100*(mirw['dv']/fe_s-1):+.3f}% vs continuum")

"""Clamp treatments at fixed everything else: error vs EB, and stability (lowest omega, lowest
x-alternating mode) at dx = 4, 2 mm; error also at 1 mm."""
import numpy as np
from variants import solve, build
from exp_stability import spectrum
cases = [("fixed (baseline)", dict(clamp="fixed")),
         ("fixed, no clamp energy", dict(clamp="noenergy")),
         ("fixed cols shifted +dx/2, energy", dict(clamp="shift")),
         ("fixed cols shifted +dx/2, no energy", dict(clamp="shift", noclampE=True)),
         ("odd mirror ghosts", dict(clamp="mirror")),
         ("linear-extrapolated ghosts", dict(clamp="extrap1")),
         ("quadratic-extrapolated ghosts", dict(clamp="extrap2"))]
for rows in ("midpoint", "exact2"):
    for name, kw in cases:
        for order in (1, 2):
            errs = [100*solve(d*1e-3, order, rows=rows, rowsmode="volume", **kw)['err'] for d in (4, 2, 1)]
            st = []
            for d in (4, 2):
                w, r = spectrum(build(d*1e-3, order, rows=rows, rowsmode="volume", **kw))
                st.append(f"{w[0]:.0f}/{w[r > 2].min():.0f}")
            print(f"{rows:8s} {name:36s} o{order}: " + " ".join(f"{e:+8.3f}" for e in errs)
                  + "   omega1/lowest-alt (4mm, 2mm): " + "  ".join(st))

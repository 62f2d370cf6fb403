"""(c) clamp experiments: clamp energy counted or not, number of clamp columns."""
import numpy as np
from sphbeam import solve_beam
for order in (1, 2):
    for dxmm in (4, 2, 1):
        dx = dxmm*1e-3
        row = []
        for nc in (1, 2, 3, 4, 5):
            row.append(100*solve_beam(dx, order, nclamp=nc)[2])
        ne = [100*solve_beam(dx, order, nclamp=nc, clamp_energy=False)[2] for nc in (1, 2, 3)]
        print(f"order {order} dx {dxmm}: nclamp 1..5 (energy counted): " + " ".join(f"{e:+.3f}" for e in row)
              + " | clamp energy NOT counted, nclamp 1..3: " + " ".join(f"{e:+.3f}" for e in ne))

#!/usr/bin/env bash
# The water particle the 3-layer gate of examples/fsi_gate lets into its tip
# (README section 9.4): run the example to 0.0441 s with the thin-body check
# off, dump the water, walls and twins near the tip every 10 steps from step
# 4250 with RHEO's pressure and density, and follow the particle fix
# sph/fluid's check names at step 4400 (atom 180 on one rank): its density,
# pressure and velocity, and the pressures of the twins and walls within the
# cut of it.  About 2 minutes on one core.
#
#   studies/fsi_rheo/probes/gate_squeeze.sh [OUTDIR]   (default /tmp/gate_squeeze)
source "$(dirname "${BASH_SOURCE[0]}")/../../../scripts/common.sh"
esph_env
set +e
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=${1:-/tmp/gate_squeeze}
mkdir -p "$out"
sed -e 's|thin/check 100 ${thin}|thin/check 0 error|' \
    -e 's|^run             ${nsteps2}|group wt union water twins walls\
compute rp all rheo/property/atom pressure rho\
region tipzone block 0.10 0.14 -0.01 0.02 INF INF units box\
group tz dynamic wt region tipzone every 10\
dump d tz custom 10 dump.*.txt id type x y vx vy c_rp[1] c_rp[2]\
dump_modify d delay 4250\
run             ${nsteps2}|' \
    "$here/../../../examples/fsi_gate/in.fsi_gate" > "$out/in.squeeze"
grep -q "dump d tz" "$out/in.squeeze" || { echo "gate_squeeze: the example's run line moved" >&2; exit 1; }
(cd "$out" && rm -f dump.*.txt && mpirun -np 1 lmp -in in.squeeze -log log -screen none \
   -var T 0.0441 -var file tip.dat > /dev/null 2>&1)
python - "$out" <<'PY'
import glob, sys
import numpy as np
out = sys.argv[1]
dx, atom = 0.005 / 3, 180
print(f"{'step':>5} {'x[m]':>8} {'y[m]':>8} {'vx':>6} {'vy':>6} {'rho':>7} {'P[Pa]':>8}"
      f" {'twins P min..max [Pa]':>22} {'walls P min..max [Pa]':>22}")
for f in sorted(glob.glob(f"{out}/dump.*.txt"), key=lambda f: int(f.split(".")[-2])):
    a = np.loadtxt(f, skiprows=9)
    ids = a[:, 0].astype(int)
    if atom not in ids:
        continue
    p = a[ids == atom][0]
    near = (np.hypot(a[:, 2] - p[2], a[:, 3] - p[3]) < 3 * dx) & (ids != atom)
    def span(t):
        m = near & (a[:, 1] == t)
        return f"{a[m, 6].min():10.0f}..{a[m, 6].max():<10.0f}" if m.any() else f"{'-':>22}"
    print(f"{int(f.split('.')[-2]):5d} {p[2]:8.5f} {p[3]:8.5f} {p[4]:6.2f} {p[5]:6.2f}"
          f" {p[7]:7.1f} {p[6]:8.0f} {span(4):>22} {span(3):>22}")
PY

#!/usr/bin/env python3
"""Summaries of the hydrostatic probe's outputs (studies/fsi_rheo/probes).

  python3 analyze.py hydro LOG PROFILE [--tol 0.01]
  python3 analyze.py gal LOG REFLOG

prints, from the log: the settling time (the first thermo time after which the
bottom wall force stays within tol of the fluid's weight), the last line's
values, particle-steps/s; and from the profile (the last fifth of the run): the
pressure against rho0 g (H_s - y), H_s = top particle + dx/2, and a straight
line fitted to the bulk (the bins more than 3 dx from the floor and the surface).

gal compares two runs of in.galilean that differ only by the frame: the
largest difference over time of the walls' forces, beside the largest force
of the reference, and the fluid's velocity relative to the walls at the end.

No dependencies beyond the standard library.
"""
import re
import sys

G, RHO0 = 9.81, 1000.0


def thermo_rows(log):
    """The thermo rows of the (single) run in LOG, as dicts of floats."""
    rows, header = [], None
    for line in open(log):
        words = line.split()
        if words[:2] == ["Step", "Time"]:
            header = words
            continue
        if header and line.startswith("Loop time"):
            break
        if header and len(words) == len(header):
            try:
                rows.append(dict(zip(header, map(float, words))))
            except ValueError:
                pass
    return rows


def performance(log):
    """Particle-steps per second of the run's loop (LAMMPS prints no rate in si units)."""
    text = open(log).read()
    loop = re.search(r"Loop time of ([0-9.e+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    if not loop:
        return None, None
    t, procs, steps, atoms = float(loop.group(1)), int(loop.group(2)), int(loop.group(3)), int(loop.group(4))
    return steps * atoms / t, (t, procs, steps, atoms)


def probe_params(log):
    for line in open(log):
        if line.startswith("PROBE "):
            w = line.split()[1:]
            return dict(zip(w[0::2], w[1::2]))
    return {}


def settle_time(rows, key, tol):
    """First time after which |rows[key] - 1| <= tol for the rest of the run."""
    t = None
    for r in rows:
        if abs(r[key] - 1.0) <= tol:
            if t is None:
                t = r["Time"]
        else:
            t = None
    return t


def last_profile(path):
    """The last block of a fix ave/chunk file: [(y, count, p, rho)]."""
    blocks, cur = [], None
    for line in open(path):
        if line.startswith("#"):
            continue
        w = line.split()
        if len(w) == 3:
            cur = []
            blocks.append(cur)
        elif cur is not None and len(w) == 5 and float(w[2]) > 0:
            cur.append((float(w[1]), float(w[2]), float(w[3]), float(w[4])))
    return blocks[-1]


def fit(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    b = sxy / sxx
    return my - b * mx, b


def hydro(log, profile, tol=0.01):
    par = probe_params(log)
    dx, H = float(par["dx"]), float(par["H"])
    rows = thermo_rows(log)
    last = rows[-1]
    rate, loop = performance(log)
    prof = last_profile(profile)
    ytop = last["v_ytop"]
    Hs = ytop + dx / 2
    ref = [RHO0 * G * (Hs - y) for y, _, _, _ in prof]
    scale = RHO0 * G * H
    dev = [(p - r) / scale for (y, _, p, _), r in zip(prof, ref)]
    bulk = [(y, p) for y, _, p, _ in prof if 3 * dx < y < ytop - 3 * dx]
    a, b = fit([y for y, _ in bulk], [p for _, p in bulk])
    rho_mean = sum(rho * c for _, c, _, rho in prof) / sum(c for _, c, _, _ in prof)
    print(f"params: {par}")
    print(f"settle (|F_bottom/weight - 1| <= {tol} from then on): t = {settle_time(rows, 'v_fbot_w', tol)} s")
    print(f"end: t={last['Time']:.4g} s  KE={last['c_ke']:.3g} J/m  F_bottom/weight={last['v_fbot_w']:.4f}  "
          f"F_walls_y/weight={last['v_fall_w']:.4f}  F_left/(rho g H^2/2)={last['v_fleft_ratio']:.4f}  "
          f"vmax=({last['c_vmax[1]']:.3g}, {last['c_vmax[2]']:.3g}) m/s")
    fb = [r["v_fbot_w"] for r in rows[len(rows) * 4 // 5:]]
    print(f"F_bottom/weight over the last fifth: mean {sum(fb) / len(fb):.4f}, min {min(fb):.4f}, max {max(fb):.4f}")
    print(f"profile (last fifth): H_s={Hs:.4f} m; P - rho0 g (H_s - y), in units of rho0 g H: "
          f"bottom bin {dev[0]:+.4f}, top bin {dev[-1]:+.4f}, max |.| {max(abs(d) for d in dev):.4f}, "
          f"bulk max |.| {max(abs(d) for (y, _, _, _), d in zip(prof, dev) if 3 * dx < y < ytop - 3 * dx):.4f}")
    print(f"bulk fit: dP/dy = {b:.1f} Pa/m = {-b / (rho_mean * G):.4f} rho_mean g "
          f"(rho_mean {rho_mean:.2f}); P = 0 at y = {-a / b:.4f} m (H_s {Hs:.4f})")
    print(f"rate: {rate:.3g} particle-steps/s (loop time, procs, steps, atoms: {loop})")


def gal(log, ref):
    a, b = thermo_rows(log), thermo_rows(ref)
    keys = [("c_fb[1]", "Fx_bot"), ("c_fb[2]", "Fy_bot"), ("c_ft[1]", "Fx_top"), ("c_ft[2]", "Fy_top")]
    parts = []
    for k, name in keys:
        d = max(abs(x[k] - y[k]) for x, y in zip(a, b))
        m = max(abs(y[k]) for y in b)
        parts.append(f"max|d{name}| {d:.3g} (ref max {m:.3g})")
    vr = max(abs(x["v_rely"]) for x in a), max(abs(x["v_relx"]) for x in a)
    print(f"{'; '.join(parts)}; max |v_rel| x {vr[1]:.3g} y {vr[0]:.3g} m/s; "
          f"p_max {max(x['c_pmax'] for x in a):.4g} (ref {max(x['c_pmax'] for x in b):.4g}) Pa")


if __name__ == "__main__":
    if sys.argv[1] == "gal":
        gal(sys.argv[2], sys.argv[3])
    if sys.argv[1] == "hydro":
        tol = float(sys.argv[sys.argv.index("--tol") + 1]) if "--tol" in sys.argv else 0.01
        hydro(sys.argv[2], sys.argv[3], tol)

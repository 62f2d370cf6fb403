"""Roofline of pair sph/icb's sweeps (issue 34, item 2) for the two bodies of
the head-to-head bench: bytes and flops per particle-step, counted from the
code of the sweeps (src/ELASTIC-SPH/sph_pair_sweeps.h, pair_sph_icb.cpp) and
the exact number of partner pairs of each body; the time per particle-step
from the bench (doc/results/headtohead.json, written by scripts/bench); the
bandwidth of this machine by the STREAM-like triad in triad.c.

    cc -O3 -o triad triad.c && ./triad 3 256 > triad.txt
    python roofline.py [--bench ../../doc/results/headtohead.json] [--triad triad.txt]

Counting conventions: a multiply-add is two flops; bytes are what each sweep
must read or write at least once per step (the pair list streamed by each of
the three sweeps, and each per-atom array each time a loop over atoms or
pairs touches it), i.e. the traffic if every reuse within a sweep hits the
cache.  Both are lower bounds of what the hardware moves and executes."""
from __future__ import annotations

import argparse
import json
import re
from itertools import product
from pathlib import Path


HERE = Path(__file__).resolve().parent
SUPPORT = 2.4       # kernel support 2h in spacings (sinc5, h = 1.2 dx)

# the bodies of the head-to-head bench, in lattice cells (3 clamp columns at x < 0)
BODIES = {"2D beam": (203, 20, 1), "3D cantilever": (103, 10, 4)}


def pair_count(shape) -> int:
    """Partner pairs (each once) of a simple lattice block of the given shape."""
    nx, ny, nz = shape
    dim = 2 if nz == 1 else 3
    reach = int(SUPPORT)
    count = 0
    for off in product(range(-reach, reach + 1), repeat=dim):
        r2 = sum(o * o for o in off)
        if r2 == 0 or r2 >= SUPPORT ** 2:
            continue
        o = list(off) + [0] * (3 - dim)
        count += max(nx - abs(o[0]), 0) * max(ny - abs(o[1]), 0) * max(nz - abs(o[2]), 0)
    return count // 2


def per_pair(dim: int, hourglass: bool) -> tuple[float, float]:
    """(flops, bytes) of one pair over the sweeps of one step."""
    d2 = dim * dim
    # gradients: d, then d (x) g on both sides
    flops = dim + 2 * 2 * d2
    # divergence: Q_i g_ij and Q_j g_ji, their difference, added to both atoms
    flops += dim * (2 * 2 * dim + 1) + 2 * dim
    pair_bytes = 2 * (8 + 2 * dim * 8)             # atom indices and g_ij, g_ji, read twice
    if hourglass:
        # (G_i + G_j) X, d, k d / 2, its outer product with X on both sides, k d on both
        flops += d2 + 2 * d2 + 3 * dim + 1 + dim + d2 + 2 * d2 + 2 * dim + dim
        pair_bytes += 8 + (1 + dim) * 8              # atom indices, k and X
    return flops, pair_bytes


def per_atom(dim: int, hourglass: bool) -> tuple[float, float]:
    """(flops, bytes) per atom and step outside the pair loops: the stress
    pass (St. Venant-Kirchhoff, S and Q = V F S) and the arrays the sweeps
    stream atom by atom."""
    flops = 2 * dim ** 3 + 4 * dim * dim + 2 * dim ** 3 + 20
    x, f, row = 24, 24, 72
    # x read by gradients (and hourglass); F written, read by the stress pass
    # (and hourglass); Q written, read by divergence (and updated by
    # hourglass); f updated by divergence (and hourglass); S kept for output
    nbytes = x + 2 * row + 2 * row + 2 * f + 56 + 16
    if hourglass:
        nbytes += x + row + 2 * row + 2 * f
    return flops, nbytes


def triad_bandwidth(path: Path) -> dict[float, float]:
    out = {}
    for line in path.read_text().splitlines():
        m = re.match(r"triad\s+([\d.]+) MB:\s+([\d.]+) GB/s", line)
        if m:
            out[float(m.group(1))] = float(m.group(2))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bench", default=str(HERE.parents[1] / "doc" / "results" / "headtohead.json"))
    ap.add_argument("--triad", default=str(HERE / "triad.txt"))
    ap.add_argument("--json", default=str(HERE / "roofline.json"))
    args = ap.parse_args()
    bench = json.loads(Path(args.bench).read_text())
    bandwidth = triad_bandwidth(Path(args.triad))
    cache_bw = max(bw for mb, bw in bandwidth.items() if 1 <= mb <= 16)
    memory_bw = bandwidth[max(bandwidth)]
    rows = []
    print(f"bandwidth: {cache_bw:.1f} GB/s (triad, working set in cache), {memory_bw:.1f} GB/s "
          "(triad, memory)")
    print(f"{'body':<14} {'hourglass':>9} {'pairs/atom':>10} {'flop/pst':>9} {'byte/pst':>9} "
          f"{'flop/byte':>9} {'Mpst/s':>7} {'GFLOP/s':>8} {'GB/s':>6} {'of cache bw':>11}")
    for body in bench["rows"]:
        name = body["body"]
        shape = BODIES[name]
        dim = 2 if shape[2] == 1 else 3
        atoms = shape[0] * shape[1] * shape[2]
        pairs = pair_count(shape) / atoms
        for label, hourglass, rate in (("0.2", True, body["rate_defaults"]),
                                       ("0", False, body["rate_hg0"])):
            fp, bp = per_pair(dim, hourglass)
            fa, ba = per_atom(dim, hourglass)
            flops, nbytes = pairs * fp + fa, pairs * bp + ba
            gflops, gbs = flops * rate / 1e9, nbytes * rate / 1e9
            row = {"body": name, "hourglass": label, "atoms": atoms, "pairs_per_atom": pairs,
                   "flops_per_particle_step": flops, "bytes_per_particle_step": nbytes,
                   "intensity": flops / nbytes, "rate": rate, "gflops": gflops, "gbs": gbs,
                   "fraction_of_cache_bandwidth": gbs / cache_bw}
            rows.append(row)
            print(f"{name:<14} {label:>9} {pairs:10.2f} {flops:9.0f} {nbytes:9.0f} "
                  f"{flops / nbytes:9.2f} {rate / 1e6:7.2f} {gflops:8.2f} {gbs:6.1f} "
                  f"{100 * gbs / cache_bw:10.1f}%")
    Path(args.json).write_text(json.dumps({"cache_bandwidth": cache_bw,
                                           "memory_bandwidth": memory_bw, "rows": rows},
                                          indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

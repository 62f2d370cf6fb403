"""The "Per MPI rank memory allocation" line counts bytes that are really
allocated: what the pair styles (and the fix sph/partners they create) add to
it is what they add to the heap, neither more nor less.

The figure is not small for a small body: LAMMPS sizes every per-atom array
by atom->nmax, at least 16384 slots however few the atoms, and fix
sph/partners keeps maxpartner tags and 11 doubles per slot (56 partners on a
cubic lattice with h = 1.2 dx, ~5.2 kB a slot).  A 125-atom block reports
~96 MB that way while its resident set grows by only ~2 MB: the untouched
slots are allocated but never paged in.  So the yardstick here is the heap
(glibc's in-use bytes, which `info memory` prints as the "Current reserved
memory pool size"), not the resident set nor the atom count.
"""
from __future__ import annotations

import re

import pytest

from conftest import run_lmp, sph_header

BLOCK = sph_header("0 5 0 5 0 5", dim=3) + """create_atoms 1 box
set group all volume 1e-9
set group all mass 1e-6
set group all mol 1
{pair}
neighbor 0.0005 bin
fix integrate all {integrator}
timestep 1e-8
run 2
info memory
"""

PAIRS = {
    "sph/icb": ("pair_style sph/icb 0.0012\npair_coeff * * 1e9 0.3", "nve"),
    "sph/ccb": ("pair_style sph/ccb 0.0012\npair_coeff * * 1e9 0.3", "sph/ccb/nve"),
}
NONE = ("pair_style zero 0.0012\npair_coeff * *", "nve")


def memory(script, tmp_path):
    """(reported "Per MPI rank" maximum, heap in use after the run), Mbytes"""
    rc, out = run_lmp(script, tmp_path)
    assert rc == 0, out[-2000:]
    reported = re.findall(r"Per MPI rank memory allocation \(min/avg/max\) = \S+ \| \S+ \| (\S+)",
                          out)
    heap = re.findall(r"Current reserved memory pool size: (\S+) Mbyte", out)
    assert reported and heap, out[-2000:]
    return float(reported[-1]), float(heap[-1])


@pytest.mark.slow
@pytest.mark.parametrize("style", sorted(PAIRS))
def test_reported_memory_is_what_the_pair_allocates(style, tmp_path):
    pair, integrator = PAIRS[style]
    (tmp_path / "none").mkdir()
    (tmp_path / "pair").mkdir()
    base_reported, base_heap = memory(BLOCK.format(pair=NONE[0], integrator=NONE[1]),
                                      tmp_path / "none")
    reported, heap = memory(BLOCK.format(pair=pair, integrator=integrator), tmp_path / "pair")
    # the whole figure is part of the heap (which also holds MPI's and
    # LAMMPS' uncounted small allocations, ~4 MB here)
    assert reported <= heap
    # what the pair style adds: its per-atom arrays x nmax, its pair lists
    # and fix sph/partners, ~90 MB of heap for these 125 atoms.  The few
    # allocations it does not count (materials, kernel, MPI buffers) are
    # ~0.6-0.9 MB; the rounding of the printed figures is 0.2 MB at most.
    added, added_heap = reported - base_reported, heap - base_heap
    assert added <= added_heap + 0.25, (added, added_heap)
    assert added >= 0.95 * added_heap, (added, added_heap)

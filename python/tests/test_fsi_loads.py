"""A coupled run with the other loads and supports of the package (issue
35: "it works with fix sph/mirror/clamps, body forces and contact"): test_fsi's
fluid blob hits its block, which is pushed into a second block by fix
sph/contact, while fix sph/bodyforce pulls both blocks down.  The
clamps of fix sph/mirror are the gate's (test_fsi_gate).  Contact is
internal and the body force the only outer force, so the momentum of water
and bodies must follow the body force's impulse exactly, with and without
the bodies sub-stepped inside the fluid's step."""
from __future__ import annotations

import numpy as np
import pytest

from test_fsi import COUPLE, HEAD, PAIR, RHEO, START, TWINS

# a second block, molecule 2, 1 cm (one spacing) left of test_fsi's block:
# the block and the blob move in -x
SECOND_BLOCK = ("create_atoms 1 region blob\n",
                "create_atoms 1 region blob\n"
                "region blockl block -0.05 0.0 0 0.04 INF INF units box\n"
                "create_atoms 2 region blockl\n")
G = 9.81
DT = 1.0e-4
P0 = -36 * 0.1 * 2.0            # the blob's momentum
BODY_MASS = (32 + 20) * 0.2     # the two blocks'


def two_blocks_script(substeps: int) -> str:
    head = HEAD.replace(*SECOND_BLOCK).format(processors="")
    assert head.count("blockl") == 2
    return (head + "group left region blockl\nset group left mol 2\n" + PAIR
            + RHEO.format(kernel="quintic 0", rho3="1000") + TWINS.format(twin_args="")
            + COUPLE.replace("sph/fluid", f"sph/fluid substeps {substeps}")
            + "fix contact body sph/contact 0.01 thickness 1.0\n"
            + f"fix weight body sph/bodyforce 0 -{G}\n" + START
            + "compute pl left reduce sum v_pxa\n")


@pytest.mark.parametrize("substeps", [1, 2])
def test_contact_and_body_force_in_the_fluid(lmp, tmp_path, substeps):
    """Over 300 steps: the blocks touch (4 contact pairs from the start,
    one spacing apart, pressed up to 400 N/m from step 50, apart after step
    184), the second block leaves with a quarter of
    the blob's momentum, which no fluid particle reaches; the momentum in x
    stays the blob's and the one in y is the body force's impulse, to
    round-off."""
    lmp.commands_string(two_blocks_script(substeps))
    path = tmp_path / "p.txt"
    lmp.commands_string(f"""
        fix pt all ave/time 1 1 1 c_p[1] c_p[2] c_pl f_contact[1] f_contact[3] \
            file {path} format " %.17g"
        run 300
    """)
    step, px, py, pleft, pairs, overlap = np.loadtxt(path).T
    # measured: 7.4e-16 (x) and 6.2e-16 (y) of the blob's momentum with 1
    # sub-step, 8.6e-16 and 5.6e-16 with 2
    assert np.abs(px - P0).max() / abs(P0) < 1e-13
    assert np.abs(py + BODY_MASS * G * DT * step).max() / abs(P0) < 1e-13
    # the contact acts, without the blocks passing into each other
    # (measured: largest overlap 2.7 % of a spacing)
    assert pairs.max() >= 4 and 0.0 < overlap.max() < 0.1
    # the second block got its momentum from the contact alone: measured
    # 0.259 (1 sub-step) and 0.256 (2) of the blob's, and none after the
    # contact ended
    assert pleft[-1] / P0 == pytest.approx(0.257, abs=0.01)
    after = step > 200
    assert np.all(pairs[after] == 0)
    assert np.abs(pleft[after] - pleft[-1]).max() < 1e-12

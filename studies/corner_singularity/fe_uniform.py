"""Q2 finite elements on UNIFORM meshes (node spacing = particle spacing dx)
against the graded, mesh-converged reference of esph.fe: the beam's tip
column at -10 N, plane stress.  With nu = 0.3 the clamped corners are
singular and a uniform mesh converges at order ~1.45 only; with nu = 0 the
error is at round-off.  Run from python/ (cd ../../python) with the venv."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))
from esph import fe  # noqa: E402

P = fe.PROBLEMS["beam"]
for nu in (0.0, 0.3):
    ref = {dx: fe.tip("beam", -10.0, dx, nu, "stress")["dv"] for dx in (0.002, 0.001)}
    for he in (0.004, 0.002, 0.001):   # Q2 element size; node spacing he/2
        mesh = fe.uniform_mesh(P, he / 2)
        v = fe.solve_case(P, [-10.0], nu, "stress", mesh, dxs=(0.002, 0.001))[-10.0]
        print(f"nu {nu} uniform Q2, nodes every {he / 2 * 1e3:.1f} mm: tip column of dx = 2 / 1 mm "
              + " / ".join(f"{(v[i][1] / ref[dx] - 1) * 100:+.4f} %"
                           for i, dx in enumerate((0.002, 0.001))), flush=True)

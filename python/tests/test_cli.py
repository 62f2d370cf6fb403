"""The command line: python -m esph validate prints the beam table."""
from __future__ import annotations

import json
import subprocess
import sys


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "esph", *args], capture_output=True, text=True,
                          timeout=600)


def test_validate_prints_a_row_per_load_and_variant(tmp_path):
    out = tmp_path / "rows.json"
    proc = run_cli("validate", "--dx", "0.004", "--loads", "-10", "--variants",
                   "linear/fixed,quadratic/mirror", "--json", str(out))
    assert proc.returncode == 0, proc.stderr
    assert "the paper's scheme: linear gradient correction, fixed clamp" in proc.stdout
    assert "gradient exact for quadratic fields, mirror clamp" in proc.stdout
    rows = json.loads(out.read_text())
    assert [(r["gradient"], r["clamp"]) for r in rows] == [("linear", "fixed"),
                                                          ("quadratic", "mirror")]
    # the same beam, so the same exact answer; the mirror clamp and the
    # quadratic gradient both remove stiffness error of the coarse beam
    assert rows[0]["exact_dv"] == rows[1]["exact_dv"]
    assert 0.0 < rows[1]["err_dv"] < rows[0]["err_dv"]


def test_validate_refuses_an_unknown_variant():
    proc = run_cli("validate", "--variants", "cubic/glued")
    assert proc.returncode == 2
    assert "unknown variant 'cubic/glued'" in proc.stderr

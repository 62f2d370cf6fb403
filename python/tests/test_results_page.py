"""The results page (doc/Results.rst) is what its data (doc/results/*.json)
gives: a page edited by hand, or data changed without regenerating the
page, fails here.  Plus the renderer on a tiny synthetic data set."""
from __future__ import annotations

import json
import math

from esph import results_page


def test_committed_page_matches_the_data():
    committed = results_page.PAGE.read_text()
    assert committed == results_page.render(results_page.RESULTS), (
        "doc/Results.rst differs from what doc/results/*.json gives: regenerate it with "
        "'python -m esph.results_page' (never edit it by hand)")


def test_check_flags_a_page_edited_by_hand(tmp_path):
    page = tmp_path / "Results.rst"
    page.write_text(results_page.render(results_page.RESULTS))
    assert results_page.main(["--check", "--page", str(page)]) == 0
    page.write_text(page.read_text().replace("%", "%%", 1))
    assert results_page.main(["--check", "--page", str(page)]) == 1


def test_every_source_is_listed_and_every_json_has_a_source():
    sources = json.loads((results_page.RESULTS / "sources.json").read_text())
    on_disk = {p.name for p in results_page.RESULTS.glob("*.json")} - {"sources.json"}
    assert set(sources) == on_disk
    for name, source in sources.items():
        assert source["kind"] in results_page.SECTIONS, name
        assert source["command"], name


def _row(table, load, dx, dv, exact, **extra):
    row = {"table": table, "problem": "beam", "variant": "default", "load": load, "dx": dx,
           "dh": -1e-5, "dv": dv, "exact": exact, "error": dv / exact - 1, "paper": math.nan,
           "steps": 4, "wall": 0.25, "note": "", "continuum": exact,
           "error_continuum": dv / exact - 1}
    row.update(extra)
    return row


def test_renderer_formats_a_synthetic_validation(tmp_path):
    rows = [_row("1", -10.0, 0.002, -2.00028e-3, -2.0e-3, paper=-2.03),
            _row("2", -250.0, 0.004, -1.004e-3, -1.0e-3),
            _row("2", -250.0, 0.002, -1.001e-3, -1.0e-3),
            _row("2", -250.0, 0.001, -1.00025e-3, -1.0e-3),
            {**_row("3", 3000.0, 0.002, 1e-6, 1.0), "problem": "truss", "dh": 5.7209e-3,
             "exact": 5.7209e-3, "error": -1e-15}]
    (tmp_path / "validate.json").write_text(json.dumps(rows))
    (tmp_path / "sources.json").write_text(json.dumps({"validate.json": {
        "kind": "validate", "command": "python -m esph validate --tables 123",
        "date": "2026-11-27", "machine": "testbox, 2 cores"}}))
    text = results_page.render(tmp_path)
    flat = " ".join(text.split())       # paragraphs are wrapped
    # provenance: the command and the machine line
    assert "``python -m esph validate --tables 123``" in flat
    assert "Machine: testbox, 2 cores." in flat
    # Table 1: displacements in mm to 4 decimals, errors as signed percentages
    assert "-2.0003" in text and "-2.0000" in text
    assert "+0.01 %" in text            # vs the elastica, 2 decimals
    assert "+0.014 %" in text           # vs the continuum, 3 decimals
    assert "-2.03" in text and "+1.50 %" in text    # the paper's value and its error
    # Table 2: the observed order between successive spacings (0.4, 0.1, 0.025 %: q = 2)
    assert "   * - 4\n     - +0.40 %\n     -\n" in text              # no order at the first
    assert "   * - 2\n     - +0.10 %\n     - 2.00\n" in text
    # Table 3: round-off shows without a sign
    assert "0.0000 %" in text and "-0.0000 %" not in text
    # absent tables leave no heading behind
    assert "Table 5" not in text and "Speed" not in text


def test_renderer_formats_the_gate_with_sphinxsys_inputs(tmp_path):
    """Table 10b: ours, SPHinXsys's run and the experiment, the differences
    as percentages of theirs."""
    row = {"table": "10b", "problem": "fsi_gate", "E": 7.8e6, "nu": 0.47, "law": "svk",
           "substeps": 6, "steps": 20000, "wall": 800.0, "uxmax": 0.0418, "tpeak": 0.1136,
           "uymax": 0.0160, "uxmax_sphinxsys": 0.0440, "uymax_sphinxsys": 0.0196,
           "uxmax_experiment": 0.0464, "tpeak_experiment": 0.161}
    (tmp_path / "validate_gate.json").write_text(json.dumps([row]))
    (tmp_path / "sources.json").write_text(json.dumps({"validate_gate.json": {
        "kind": "validate_gate", "command": "python -m esph validate --full --tables g",
        "date": "2026-11-28", "machine": "testbox, 2 cores"}}))
    text = results_page.render(tmp_path)
    flat = " ".join(text.split())
    assert "Table 10b: the elastic gate with SPHinXsys's inputs" in text
    assert "E = 7.8 MPa, nu = 0.47, svk" in flat and "6 sub-steps, 20000 steps" in flat
    assert "41.80" in text and "44.00" in text and "46.40" in text
    assert "-5.0 %" in text and "-9.9 %" in text      # 41.8/44 - 1, 41.8/46.4 - 1


def test_formatters():
    assert results_page.pct(0.00014) == "+0.014 %"
    assert results_page.pct(-0.0765, 2) == "-7.65 %"
    assert results_page.pct(-1e-16, 4) == "0.0000 %"
    assert results_page.pct(math.nan) == ""
    assert results_page.mm(-0.0470980) == "-47.0980"
    q = results_page.orders([0.004, 0.001], [0.002, 0.001])
    assert math.isnan(q[0]) and abs(q[1] - 2.0) < 1e-12


BENCH3D_TEXT = """\
3D cantilever statics (square section, L = 10 H, ...); machine vm, 2 cores, x86_64
dx[mm]   atoms ranks  solver iters  wall[s]  MB/rank dyn100[s]  ratio  solver log / command
-------------------------------------------------------------------------------------------
  2.00   10300     1  direct     8     52.3     4100      1.30   40.2  8 Hessians, 94 GMRES  |  cd examples/beam3d && mpirun -np 1 lmp -in in.beam3d -var dx 0.002
  1.00           2  direct failed: out of memory  cd examples/beam3d && mpirun -np 2 lmp -in in.beam3d -var dx 0.001
"""

BENCH_TEXT = """\
Throughput, beam under -250 N, undamped dynamics, 200 steps; machine vm (2 cores), x86_64
   style  dx[mm]   atoms ranks  loop[s]  Mpart-steps/s us/part-step  command
----------------------------------------------------------------------------
   icb3d    2.00   10300     1    1.126          1.830        0.546  cd examples/beam3d && mpirun -np 1 lmp -in in.beam3d
"""


def test_printed_benches_become_json_and_a_table(tmp_path):
    b3d = results_page.parse_bench3d(BENCH3D_TEXT)
    assert b3d["machine"] == "vm, 2 cores, x86_64"
    ok, failed = b3d["rows"]
    assert (ok["atoms"], ok["ranks"], ok["solver"], ok["iterations"]) == (10300, 1, "direct", 8)
    assert (ok["wall"], ok["rss_mb"], ok["dyn100"]) == (52.3, 4100.0, 1.30)
    assert ok["command"].startswith("cd examples/beam3d")
    assert failed["failed"] == "failed: out of memory" and failed["ranks"] == 2
    bench = results_page.parse_bench(BENCH_TEXT)
    assert bench["rows"][0]["rate"] == 1.83e6 and bench["rows"][0]["style"] == "icb3d"
    (tmp_path / "bench3d.json").write_text(json.dumps(b3d))
    (tmp_path / "bench.json").write_text(json.dumps(bench))
    (tmp_path / "sources.json").write_text(json.dumps({
        "bench3d.json": {"kind": "bench3d", "command": "python -m esph bench3d --np 1"},
        "bench.json": {"kind": "bench", "command": "python -m esph bench --styles icb3d"}}))
    text = results_page.render(tmp_path)
    assert "     - 52.3\n     - 4100\n     - 1.30\n     - 40.2\n" in text
    assert "     - failed: failed: out of memory\n" not in text
    assert "failed: out of memory" in text
    assert "     - 1.830\n" in text

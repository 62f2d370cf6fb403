"""esph bench --suite (scripts/bench): the head-to-head rows against
MACHDYN, the 3D statics rows, the weak-scaling memory rows, their JSON with
its sources entry, and the results page rendered from them -- all at tiny
sizes, one repetition.  No timing thresholds: the machine is shared."""
from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import asdict

import pytest

from esph import bench, results_page
from esph.runner import clean_environment

# 2D beam at 5 mm (172 particles); the 3D cantilever (W = 8 mm) at 2.5 mm,
# the coarsest spacing with 3 particles across its width (1992 particles)
TINY_DX = (0.005, 0.0025)
TINY_STEPS = (50, 10, 10, 5)      # ours, MACHDYN per body


def check_headtohead(rows: list[dict], reps: int) -> None:
    assert [r["body"] for r in rows] == ["2D beam", "3D cantilever"]
    assert [r["dim"] for r in rows] == [2, 3]
    assert [r["particles"] for r in rows] == [(40 + 3) * 4, (80 + 3) * 8 * 3]
    for r in rows:
        # the same lattice in both codes
        assert r["machdyn_particles"] == r["particles"]
        assert (r["reps"], r["steps"], r["machdyn_steps"]) == (reps, *r_steps(r))
        for k in ("defaults", "hg0", "machdyn"):
            loops = r[f"loops_{k}"]
            assert len(loops) == reps and all(t > 0 for t in loops)
            assert r[f"rate_{k}"] > 0
            # the best of the runs, by LAMMPS's loop time
            steps = r["machdyn_steps"] if k == "machdyn" else r["steps"]
            assert r[f"rate_{k}"] == pytest.approx(r["particles"] * steps / min(loops))
        assert r["ratio_defaults"] == pytest.approx(r["rate_defaults"] / r["rate_machdyn"])
        assert r["ratio_hg0"] == pytest.approx(r["rate_hg0"] / r["rate_machdyn"])
        assert "-var hg 0" in r["command_hg0"] and "-var hg" not in r["command_defaults"]
        assert "-var route nve" in r["command_defaults"]
        assert "in.beam" in r["command_defaults"] and "_tlsph" in r["command_machdyn"]
    beam, solid = rows
    assert "-var hfac 2.01" in beam["command_machdyn"]
    assert "-var Fy -250" in beam["command_machdyn"]
    assert "-var scheme icb" in beam["command_defaults"]
    assert "-var W 0.008" in solid["command_machdyn"]
    assert "-var hfac 2.4" in solid["command_machdyn"]


def r_steps(row: dict) -> tuple[int, int]:
    k = 0 if row["dim"] == 2 else 2
    return TINY_STEPS[k], TINY_STEPS[k + 1]


@pytest.mark.slow
def test_headtohead_rows_alternate_and_keep_the_best():
    bodies = bench.bodies_for(("beam", "beam3d"), TINY_DX, TINY_STEPS)
    rows = bench.headtohead(bodies, reps=2, progress=lambda _: None)
    check_headtohead([asdict(r) for r in rows], reps=2)


@pytest.mark.slow
def test_suite_writes_json_with_sources_that_the_results_page_renders(tmp_path):
    """The whole suite through the command line at tiny sizes: each part's
    JSON and its sources.json entry, then the page from them."""
    out = tmp_path / "results"
    args = ["bench", "--suite", "--reps", "1",
            "--h2h-dx", ",".join(map(str, TINY_DX)), "--h2h-steps", ",".join(map(str, TINY_STEPS)),
            "--statics-dx", "0.0025", "--statics-np", "1", "--statics-side", "0.01",
            "--weak-dx", "0.005", "--weak-ranks", "1,2", "--weak-steps", "20",
            "--weak-cases", "beam-dyn,beam3d-newton", "--json-dir", str(out)]
    proc = subprocess.run([sys.executable, "-m", "esph", *args], capture_output=True, text=True,
                          timeout=600, env=clean_environment())
    assert proc.returncode == 0, proc.stderr
    sources = json.loads((out / "sources.json").read_text())
    assert list(sources) == ["headtohead.json", "statics_bench.json", "weak.json"]
    for name, source in sources.items():
        assert source["kind"] in results_page.SECTIONS
        assert source["command"] == "python -m esph " + " ".join(args)
        assert source["date"] and source["commit"] and "load average" in source["machine"]

    h2h = json.loads((out / "headtohead.json").read_text())
    check_headtohead(h2h["rows"], reps=1)

    statics = json.loads((out / "statics_bench.json").read_text())["rows"]
    assert len(statics) == 1 and not statics[0].get("failed")
    (s,) = statics
    assert (s["atoms"], s["ranks"], s["solver"]) == (688, 1, "auto")
    assert 7 <= s["iterations"] <= 14
    assert s["ratio"] == pytest.approx(s["wall"] / s["dyn100"])
    assert "-var linear auto" in s["command"] and "-var nsteps 100" in s["dyn100_command"]

    weak = json.loads((out / "weak.json").read_text())["rows"]
    assert [(r["case"], r["ranks"]) for r in weak] == [
        ("beam-dyn", 1), ("beam-dyn", 2), ("beam3d-newton", 1), ("beam3d-newton", 2)]
    for r in weak:
        # every rank's own peak memory, measured
        assert len(r["rss_mb"]) == r["ranks"] and all(10.0 < mb < 4000.0 for mb in r["rss_mb"])
        assert r["max_rss_mb"] == max(r["rss_mb"])
        assert r["per_rank"] == r["atoms"] / r["ranks"]
        assert r["bytes_per_particle"] == pytest.approx(r["max_rss_mb"] * 2**20 / r["per_rank"])
    # the body grows with the ranks: nearly the same particles per rank
    assert weak[1]["atoms"] > weak[0]["atoms"]
    assert weak[1]["per_rank"] == pytest.approx(weak[0]["per_rank"], rel=0.1)

    text = results_page.render(out)
    flat = " ".join(text.split())
    assert "Head to head with MACHDYN" in text and "Weak scaling of memory" in text
    assert "3D cantilever statics against 100 dynamic steps" in text
    beam = h2h["rows"][0]
    assert f"     - {beam['ratio_defaults']:.2f}\n     - {beam['ratio_hg0']:.2f}\n" in text
    assert f"{beam['loops_machdyn'][0]:.3f}" in text
    assert beam["command_hg0"] in text                      # the commands, each once
    assert text.count(beam["command_hg0"]) == 1
    assert f"     - {weak[0]['bytes_per_particle']:.0f}\n" in text
    assert f"``{sources['weak.json']['command']}``" in flat


def test_sections_render_hand_made_rows(tmp_path):
    """The renderer alone, on rows shaped like the suite's (numbers made up
    for this test only, never committed as data)."""
    row = {"body": "2D beam", "dim": 2, "particles": 4060, "machdyn_particles": 4060,
           "steps": 2000, "machdyn_steps": 250, "reps": 2, "rate_defaults": 2.0e6,
           "rate_hg0": 3.0e6, "rate_machdyn": 0.25e6, "ratio_defaults": 8.0, "ratio_hg0": 12.0,
           "loops_defaults": [4.1, 4.06], "loops_hg0": [2.71, 2.8], "loops_machdyn": [4.06, 4.2],
           "command_defaults": "cd examples/beam && mpirun -np 1 lmp -in in.beam",
           "command_hg0": "cd examples/beam && mpirun -np 1 lmp -in in.beam -var hg 0",
           "command_machdyn": "cd examples/beam && mpirun -np 1 lmp -in in.beam_tlsph"}
    weak = {"case": "beam-dyn", "dim": 2, "route": "dyn", "ranks": 2, "atoms": 8060,
            "per_rank": 4030.0, "wall": 1.1, "rss_mb": [59.1, 59.2], "max_rss_mb": 59.2,
            "bytes_per_particle": 59.2 * 2**20 / 4030, "command": "cd examples/beam && x"}
    (tmp_path / "headtohead.json").write_text(json.dumps(
        {"title": "Head to head", "machine": "testbox", "rows": [row]}))
    (tmp_path / "weak.json").write_text(json.dumps(
        {"title": "Weak", "machine": "testbox", "rows": [weak]}))
    (tmp_path / "sources.json").write_text(json.dumps({
        "headtohead.json": {"kind": "headtohead", "command": "python -m esph bench --suite"},
        "weak.json": {"kind": "weak", "command": "python -m esph bench --suite"}}))
    text = results_page.render(tmp_path)
    assert "     - 2000 / 250\n     - 2.000\n     - 3.000\n     - 0.250\n     - 8.00\n" \
           "     - 12.00\n" in text
    assert "     - 4.100 4.060\n     - 2.710 2.800\n     - 4.060 4.200\n" in text
    assert "     - 59.1 59.2\n     - 59.2\n     - 15403\n" in text

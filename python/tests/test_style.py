"""The C++ sources follow LAMMPS's conventions that a tool can check: its own
.clang-format (which also sorts the includes and keeps lines within 100
columns), as scripts/format applies it."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_sources_are_clang_formatted_with_lammps_style():
    proc = subprocess.run([str(ROOT / "scripts" / "format"), "--check"], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, f"run scripts/format:\n{proc.stderr[-3000:]}"


def test_no_line_longer_than_100_columns():
    long = [f"{path.name}:{n}" for path in sorted((ROOT / "src" / "ELASTIC-SPH").glob("*.[ch]*"))
            for n, line in enumerate(path.read_text().splitlines(), 1) if len(line) > 100]
    assert not long, long


def test_python_has_no_unused_or_undefined_names():
    """pyflakes over the driver and the tests: an unused import or local, an
    undefined name, an f-string without a placeholder."""
    proc = subprocess.run([sys.executable, "-m", "pyflakes", str(ROOT / "python" / "esph"),
                           str(ROOT / "python" / "tests")], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]

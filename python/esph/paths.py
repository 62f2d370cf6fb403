"""Where the project's pieces are: examples, the lmp binary of our build."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def lmp_binary() -> str:
    """The lmp of our build (scripts/setup.sh exports ESPH_LMP)."""
    path = os.environ.get("ESPH_LMP") or shutil.which("lmp")
    if not path or not Path(path).exists():
        raise RuntimeError("lmp not found: run scripts/setup.sh (it exports ESPH_LMP)")
    return path

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


def plugin_route() -> tuple[str, str]:
    """(lmp, elasticsphplugin.so) of the plugin route: a plain LAMMPS with the
    PLUGIN package and the package built as a plugin for it (scripts/setup.sh
    --plugin exports ESPH_HOST_BUILD and ESPH_PLUGIN)."""
    host, plugin = os.environ.get("ESPH_HOST_BUILD"), os.environ.get("ESPH_PLUGIN")
    lmp = Path(host) / "lmp" if host else None
    if not lmp or not lmp.exists() or not plugin or not Path(plugin).exists():
        raise RuntimeError("the plugin route is not built: run scripts/setup.sh --plugin "
                           "(scripts/test does)")
    return str(lmp), plugin

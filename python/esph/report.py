"""Text and file output shared by the commands: table headings, the
observed order of convergence, the machine a measurement ran on, and rows
written as JSON and CSV."""
from __future__ import annotations

import csv
import json
import math
import os
import platform
import sys
from pathlib import Path


def progress(msg: str) -> None:
    """A progress line on stderr, so that stdout holds only the tables."""
    print(msg, file=sys.stderr, flush=True)


def print_head(head: str) -> None:
    print(head)
    print("-" * len(head))


def order(errors: list[float], dxs: list[float]) -> list[float]:
    """Observed order between successive resolutions, log(e1/e2)/log(dx1/dx2)."""
    out = [float("nan")]
    for k in range(1, len(errors)):
        e1, e2 = abs(errors[k - 1]), abs(errors[k])
        ok = e1 > 0 and e2 > 0
        out.append(math.log(e1 / e2) / math.log(dxs[k - 1] / dxs[k]) if ok else float("nan"))
    return out


def machine() -> str:
    return (f"{platform.node()}, {os.cpu_count()} cores, "
            f"{platform.processor() or platform.machine()}, {platform.platform()}")


def command_line(script: Path, variables: dict, nprocs: int, lmp: str = "lmp") -> str:
    """The shell command that reruns one measurement from the project root."""
    folder = script.parent.relative_to(script.parents[1].parent)
    return (f"cd {folder} && mpirun -np {nprocs} {lmp} -in {script.name} "
            + " ".join(f"-var {k} {v}" for k, v in variables.items()))


def write_rows(path: Path, rows: list[dict]) -> None:
    """The rows as JSON at `path` and as CSV beside it (same name, .csv), one
    column per field of any row, for a spreadsheet or pandas."""
    path = Path(path)
    path.write_text(json.dumps(rows, indent=1))
    fields = list(dict.fromkeys(key for row in rows for key in row))
    with open(path.with_suffix(".csv"), "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields, restval="")
        writer.writeheader()
        writer.writerows(rows)

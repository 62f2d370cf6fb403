"""python -m esph.fe: list the finite-element reference tables, or with
--write recompute and write them (see esph.fe)."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .. import fe
from ..problems import ALL_PROBLEMS, CYLINDER_PROBLEMS, GRAVITY_PROBLEMS, PLATE_PROBLEMS
from ..problems import END_LOAD_PROBLEMS as PROBLEMS
from .tables import (CYLINDER_TABLE, GRAVITY_TABLE, PLATE_TABLE, TABLE, _load_table, table_path,
                     write_table)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m esph.fe", description=fe.__doc__.split("\n")[0])
    ap.add_argument("--write", action="store_true", help="recompute and write the table(s)")
    ap.add_argument("--problems", default=",".join(PROBLEMS),
                    help="comma-separated subset of " + ",".join(PROBLEMS) + " (table "
                         f"{TABLE.name}, the default) and " + ",".join(GRAVITY_PROBLEMS)
                         + f" (the beam under its own weight, table {GRAVITY_TABLE.name}) and "
                         + ",".join(CYLINDER_PROBLEMS) + " (the beam clamped to a rigid "
                         f"cylinder under its own weight, table {CYLINDER_TABLE.name}) and "
                         + ",".join(PLATE_PROBLEMS) + " (the hydrostatic plate clamped at "
                         f"both ends, table {PLATE_TABLE.name})")
    ap.add_argument("--table", default=None,
                    help="table path (default: the package's table of each problem)")
    args = ap.parse_args(argv)
    names = [n.strip() for n in args.problems.split(",") if n.strip()]
    for n in names:
        if n not in ALL_PROBLEMS:
            ap.error(f"unknown problem {n!r}: {', '.join(ALL_PROBLEMS)}")
    if args.table is not None and len({table_path(n) for n in names}) > 1:
        ap.error("--table with problems of both tables; write them one table at a time")
    if not args.write:
        for n in names:
            table = _load_table(Path(args.table) if args.table else table_path(n))
            meta = table["problems"].get(n, {}).get("meta")
            print(n, "missing" if meta is None else
                  f"{len(table['problems'][n]['entries'])} entries, max error estimate "
                  f"{meta['max_error_estimate']:.1e}, {meta['wall_seconds']} s")
        return 0
    t0 = time.time()
    write_table(names, Path(args.table) if args.table else None,
                log=lambda s: print(s, flush=True))
    written = args.table or ", ".join(str(p) for p in dict.fromkeys(map(table_path, names)))
    print(f"total {time.time() - t0:.1f} s; wrote {written}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

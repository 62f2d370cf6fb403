"""The finite-element reference tables of esph.fe (python/esph/data/*.json):
computing and writing them (compute_problem, write_table, with the
Richardson error estimate) and reading them at the material points the
scripts measure (tip, gravity_tip, cylinder_tip); see esph.fe's
documentation."""
from __future__ import annotations

import datetime
import json
import math
import time
from pathlib import Path

import numpy as np

from ..problems import (CYLINDER_PROBLEMS, END_LOAD_PROBLEMS, GRAVITY_PROBLEMS, PLATE_PROBLEMS,
                        Problem, problem_by_name)
from .meshes import make_mesh
from .solver import solve_case

DATA = Path(__file__).resolve().parents[1] / "data"
TABLE = DATA / "fe_reference.json"
GRAVITY_TABLE = DATA / "fe_bodyforce.json"
CYLINDER_TABLE = DATA / "fe_cylinder.json"
PLATE_TABLE = DATA / "fe_plate.json"
REGENERATE = "python -m esph.fe --write"


def table_path(name: str) -> Path:
    """The table file that holds problem `name`."""
    if name in GRAVITY_PROBLEMS:
        return GRAVITY_TABLE
    if name in CYLINDER_PROBLEMS:
        return CYLINDER_TABLE
    if name in PLATE_PROBLEMS:
        return PLATE_TABLE
    return TABLE


def richardson(values, pmin: float = 1.0, pmax: float = 4.0):
    """Error estimate of the last of >= 2 values on meshes refined by 2.

    With three values and a consistent (monotone, contracting) sequence the
    observed order p = log2(|d1|/|d2|), clipped to [pmin, pmax], gives
    |d2| / (2^p - 1); otherwise (two values, or a non-monotone sequence)
    the estimate is the conservative max(|d1|, |d2|) (|d| for two).
    Returns (estimate, p or None)."""
    v = np.asarray(values, float)
    d2 = v[-1] - v[-2]
    if v.size < 3:
        return abs(d2), None
    d1 = v[-2] - v[-3]
    if d1 * d2 > 0 and abs(d2) < abs(d1):
        p = min(max(math.log2(abs(d1) / abs(d2)), pmin), pmax)
        return abs(d2) / (2.0 ** p - 1.0), p
    return max(abs(d1), abs(d2)), None


COMPONENTS = ("dh", "dv", "dz")


def _zero_by_symmetry(problem: Problem) -> set:
    """Components whose tip-column mean vanishes by symmetry (listed with an
    absolute error only): the truss's dv (mirror symmetry in y), dz in 3D,
    the plate's dh at mid-span."""
    zero = {"dz"}
    if problem.symmetric_y:
        zero.add("dv")
    if problem.load_kind == "plate":
        zero.add("dh")      # the mid-span points: mirror symmetry in x - L/2
    return zero


def unique_cases(problem: Problem):
    """(nu, plane) pairs to compute, and the pairs that copy them: at nu = 0
    lambda = 0 and plane stress and plane strain are the same law."""
    todo, copies = [], {}
    for nu, plane in problem.cases:
        if nu == 0.0 and plane == "strain" and (0.0, "stress") in problem.cases:
            copies[(nu, plane)] = (0.0, "stress")
        else:
            todo.append((nu, plane))
    return todo, copies


def compute_problem(problem: Problem | str, levels=None, log=print, checkpoint=None) -> dict:
    """Solve every case of `problem` on its mesh levels (`levels`, else
    problem.levels or the case's problem.case_levels); returns the table part
    {"entries": [...], "meta": {...}}.  checkpoint(part) is called with the
    part so far after each (nu, plane) case (the 3D cases take ~25 min).
    Entries of the problem's single points (problem.points) have "point":
    its name, "x", "y" and "dx": None; tip-column entries have no "point"."""
    problem = problem_by_name(problem) if isinstance(problem, str) else problem
    explicit = levels is not None
    levels = problem.levels if levels is None else tuple(levels)
    t_start = time.time()
    todo, copies = unique_cases(problem)
    zero = _zero_by_symmetry(problem)
    comps = COMPONENTS[:problem.dim]
    entries, meshes, runs = [], {}, []
    def part():
        meta = {"levels": list(levels), "meshes": {str(k): v for k, v in meshes.items()},
                **({"case_levels": [[list(c), list(lv)] for c, lv in problem.case_levels]}
                   if problem.case_levels and not explicit else {}),
                "grade": dict(problem.grade), "half_z": problem.half_z,
                "symmetric_y": problem.symmetric_y, "runs": runs,
                "wall_seconds": round(time.time() - t_start, 1),
                "L": problem.L, "H": problem.H, "W": problem.W if problem.dim == 3 else None,
                "t": problem.t if problem.dim == 2 else None, "E": problem.E,
                "loads": list(problem.loads), "dxs": list(problem.dxs),
                **({"load_kind": problem.load_kind, "rho": problem.rho,
                    "points": [list(p) for p in problem.points]}
                   if problem.load_kind != "end" or problem.points else {}),
                **({"water": problem.water, "rho_fluid": problem.rho_fluid}
                   if problem.load_kind == "plate" else {}),
                "cases": [list(c) for c in problem.cases],
                "max_error_estimate": max((e["error_estimate"] for e in entries), default=None),
                "note": problem.note}
        return {"entries": list(entries), "meta": meta}

    for nu, plane in todo:
        per_level = []
        case_levels = levels if explicit else dict(problem.case_levels).get((nu, plane), levels)
        for level in case_levels:
            t0 = time.time()
            mesh = make_mesh(problem, level)
            res = solve_case(problem, problem.loads, nu, plane, mesh,
                             log=(lambda s: log(s)) if log and problem.dim == 3 else None,
                             points={p[0]: p[1:] for p in problem.points})
            info = res["info"]
            dt = time.time() - t0
            meshes[level] = {"elements": info["elements"], "free_dofs": info["dofs"],
                             "half_z": info["half_z"]}
            runs.append({"nu": nu, "plane": plane, "level": level, "seconds": round(dt, 1),
                         "load_steps": info["steps"], "newton_iterations": info["newton"],
                         "factorizations": info["factorizations"],
                         "max_final_residual": float(info["max_residual"])})
            if log:
                log(f"  {problem.name} nu={nu} {plane} level {level}: {info['dofs']} dofs, "
                    f"{info['steps']} load steps, {info['newton']} Newton iterations, "
                    f"max |r|/|f| {info['max_residual']:.1e}, {dt:.1f} s")
            per_level.append(res)
        for load in problem.loads:
            vals = np.array([r[load] for r in per_level])          # (level, dx, comp)
            heads = [{"dx": dx} for dx in problem.dxs]
            if problem.points:
                vals = np.concatenate(
                    [vals, np.array([[r[p[0]][load] for p in problem.points]
                                     for r in per_level])], axis=1)
                heads += [{"point": p[0], **dict(zip("xyz", p[1:])), "dx": None}
                          for p in problem.points]
            for j, head in enumerate(heads):
                e = {"problem": problem.name, "nu": nu, "plane": plane, "load": load, **head}
                rel = []
                for i, c in enumerate(comps):
                    v = vals[:, j, i]
                    err, p = richardson(v)
                    e[c] = float(v[-1])
                    e["err_" + c] = float(err)
                    e["order_" + c] = None if p is None else round(p, 2)
                    if c not in zero:
                        rel.append(err / abs(v[-1]))
                e["error_estimate"] = float(max(rel))
                e["levels"] = [[float(x) for x in row] for row in vals[:, j, :]]
                entries.append(e)
                for (cnu, cplane), (snu, splane) in copies.items():
                    if (snu, splane) == (nu, plane):
                        entries.append(dict(e, nu=cnu, plane=cplane, copy_of=splane))
        if checkpoint is not None:
            checkpoint(part())
    return part()


def write_table(names, path: Path | None = None, log=print) -> dict:
    """Recompute the problems `names` and merge them into the table at `path`
    (default: the problems' own table, TABLE for PROBLEMS, GRAVITY_TABLE for
    GRAVITY_PROBLEMS, CYLINDER_TABLE for CYLINDER_PROBLEMS; names of several
    kinds then write each table, and the last table written is returned)."""
    import skfem

    if path is None:
        table = None
        for target in dict.fromkeys(table_path(n) for n in names):
            table = write_table([n for n in names if table_path(n) == target], target, log)
        return table
    kinds = {table_path(n) for n in names}
    if len(kinds) > 1:
        raise ValueError("write_table: end-load, gravity and cylinder problems go to "
                         "different tables")
    kind = kinds.pop() if kinds else TABLE
    try:
        table = json.loads(path.read_text())
    except (FileNotFoundError, ValueError):
        table = {}
    table.setdefault("problems", {})
    def save(name, part):
        table["problems"][name] = part
        table["meta"] = _table_meta(skfem, kind=kind)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(table, indent=1, default=_json_default) + "\n")

    for name in names:
        if log:
            log(f"{name}: solving ...")
        part = compute_problem(name, log=log, checkpoint=lambda p, n=name: save(n, p))
        save(name, part)
        if log:
            log(f"{name}: {part['meta']['wall_seconds']} s wall, max error estimate "
                f"{part['meta']['max_error_estimate']:.1e}")
    _TABLE_CACHE.clear()
    return table


def _table_meta(skfem, gravity: bool = False, kind: Path | None = None) -> dict:
    if kind == PLATE_TABLE:
        return _plate_table_meta(skfem)
    if kind == CYLINDER_TABLE:
        return _cylinder_table_meta(skfem)
    if gravity or kind == GRAVITY_TABLE:
        return _gravity_table_meta(skfem)
    return {
        "description": "Tip-column mean displacements (m) of the static validation problems "
                       "by a nonlinear total-Lagrangian SVK finite-element model (esph.fe)",
        "scikit_fem": skfem.__version__ if hasattr(skfem, "__version__") else _version("scikit-fem"),
        "numpy": np.__version__, "scipy": _version("scipy"),
        "element": "ElementQuad2 (9-node biquadratic) in 2D, ElementHex2 (27-node "
                   "triquadratic) in 3D; 3x3(x3) Gauss points; tensor-product meshes with "
                   "geometric layers toward the corners (make_mesh)",
        "material": "SVK: S = lambda tr(E) I + 2 mu E, P = F S; 2D plane stress: lambda* = "
                    "2 lambda mu/(lambda + 2 mu); plane strain: 3D lambda",
        "loading": "x = 0 clamped, dead uniform traction on x = L with the load as resultant",
        "tip_column": "mean over x = L - dx/2, y = (j+1/2) dx (z = (k+1/2) dx)",
        "value": "the finest mesh (the last level); err_*: Richardson estimate of its "
                 "absolute error from the last three levels (|d2|/(2^p - 1), observed order p "
                 "clipped to [1, 4]; max(|d1|, |d2|) when not monotone); error_estimate: the "
                 "largest err_c/|c| over the components not zero by symmetry",
        "newton": _newton_note("max|load|/8 in 2D, /5 in 3D"),
        "date": datetime.date.today().isoformat(),
        "command": "cd python && " + REGENERATE + " [--problems beam,truss,beam3d,beam3d_short]",
    }


def _newton_note(increments: str) -> str:
    """How every table's Newton solves stop, with its load increments."""
    return (f"load stepping (increments <= {increments}), |r| <= 1e-10 |f| or, at the "
            "round-off floor of the strongly graded meshes, Newton correction "
            "<= 1e-12 |u| (max_final_residual per run)")


def _regenerate_command(problems) -> str:
    """The command that rewrites a table of the given problems."""
    return "cd python && " + REGENERATE + " --problems " + ",".join(problems)


def _gravity_table_meta(skfem) -> dict:
    meta = _table_meta(skfem)
    meta.update({
        "description": "Displacements (m) of the cantilever under its own weight (a dead body "
                       "force rho g per unit reference volume) by the nonlinear total-Lagrangian "
                       "SVK finite-element model esph.fe: the tip-column means and single "
                       "material points",
        "loading": "x = 0 clamped (u = 0 on the whole face), all other faces free; body force "
                   "rho g per unit reference volume, g = (0, load) m/s^2, dead (its work is "
                   "-int rho g . u dV)",
        "point": "entries with 'point' (and 'x', 'y', 'dx': null): the displacement (dh = u_x, "
                 "dv = u_y) of that single material point; 'end' = (L, H/2), the end-face "
                 "centre",
        "newton": _newton_note("max|load|/8"),
        "command": _regenerate_command(GRAVITY_PROBLEMS),
    })
    return meta


def _cylinder_table_meta(skfem) -> dict:
    meta = _gravity_table_meta(skfem)
    meta.update({
        "description": "Displacements (m) of the cantilever clamped to a rigid cylinder under "
                       "its own weight (a dead body force rho g per unit reference volume) by "
                       "the nonlinear total-Lagrangian SVK finite-element model esph.fe: the "
                       "tip-column means and the end-face centre",
        "geometry": "0 <= y <= H, x <= L, (x + R)^2 + (y - H/2)^2 >= R^2, x >= -R: the left "
                    "end is the concave arc x_arc(y) = -R + sqrt(R^2 - (y - H/2)^2) of the "
                    "cylinder (radius R = clamp_radius, centre (-R, H/2)); it meets the free "
                    "faces y = 0, H at 90 - asin(H/(2R)) degrees (60 for R = H)",
        "loading": "the arc fully clamped (u = 0), all other faces free; body force rho g per "
                   "unit reference volume, g = (0, load) m/s^2, dead",
        "element": "ElementQuad2 (9-node biquadratic), 3x3 Gauss points, on the (s, y) "
                   "tensor mesh of the beam (make_mesh, layers toward the arc, the end and "
                   "y = 0, H) mapped by x = x_arc(y) + (s/L)(L - x_arc(y)); the element "
                   "geometry is that exact map (arc_mapping), the area exact to the "
                   "quadrature (1.6e-10 relative at level 1, h^6)",
        "command": _regenerate_command(CYLINDER_PROBLEMS),
    })
    return meta


def _plate_table_meta(skfem) -> dict:
    meta = _gravity_table_meta(skfem)
    meta.update({
        "description": "Displacements (m) of the plate clamped at both ends under a water "
                       "column and its own weight (examples/fsi_plate's hydrostatic plate) by "
                       "the nonlinear total-Lagrangian SVK finite-element model esph.fe: the "
                       "mean of the two mid-span columns and the top face's mid-point",
        "loading": "x = 0 and x = L clamped (u = 0 on both faces: the mirror planes of fix "
                   "sph/mirror), a dead uniform pressure rho_fluid |g| water on the top face "
                   "y = H and a dead body force rho g per unit reference volume, g = (0, load) "
                   "m/s^2; plane strain, per unit depth",
        "tip_column": "mean over the two mid-span columns x = L/2 -+ dx/2, y = (j+1/2) dx",
        "point": "'top' = (L/2, H), the top face's mid-point",
        "command": _regenerate_command(PLATE_PROBLEMS),
    })
    return meta


def _json_default(x):
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not JSON serializable: {type(x)}")


def _version(dist: str) -> str:
    from importlib.metadata import version

    return version(dist)


_TABLE_CACHE: dict = {}


def _load_table(path: Path = TABLE) -> dict:
    key = str(path)
    if key not in _TABLE_CACHE:
        _TABLE_CACHE[key] = json.loads(path.read_text())
    return _TABLE_CACHE[key]


def _close(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1e-300)


def tip(problem: str, load: float, dx: float, nu: float = 0.0, plane: str = "stress") -> dict:
    """The FE reference tip-column mean displacement for one case.

    Returns {"dh", "dv" (and "dz" in 3D): metres, "error_estimate": relative
    (see the table's meta), "err_dh", "err_dv", ...: absolute}.  `plane` is
    ignored for the 3D problems.  Raises KeyError (naming the case and the
    command that regenerates the table) when the table lacks it."""
    where = f"(problem={problem!r}, load={load:g}, dx={dx:g}, nu={nu:g}, plane={plane!r})"
    try:
        part = _load_table()["problems"][problem]
    except FileNotFoundError:
        raise KeyError(f"no FE reference table {TABLE}; make it with: cd python && "
                       f"{REGENERATE}") from None
    except KeyError:
        raise KeyError(f"FE reference table has no problem {where}; regenerate with: "
                       f"cd python && {REGENERATE} --problems {problem}") from None
    is3d = problem in END_LOAD_PROBLEMS and END_LOAD_PROBLEMS[problem].dim == 3
    for e in part["entries"]:
        if (_close(e["load"], load) and _close(e["dx"], dx) and abs(e["nu"] - nu) < 1e-12
                and (is3d or e["plane"] == plane)):
            keys = ["dh", "dv", "dz", "error_estimate", "err_dh", "err_dv", "err_dz"]
            return {k: e[k] for k in keys if k in e}
    raise KeyError(f"FE reference table has no entry {where}; regenerate with: "
                   f"cd python && {REGENERATE} --problems {problem}")


def gravity_tip(gy: float, dx: float | None = None, nu: float = 0.0, plane: str = "stress",
                point: str = "column", problem: str = "beam_gravity") -> dict:
    """The FE reference displacement of the cantilever under its own weight,
    g = (0, -gy) (gy > 0: downward, m/s^2), from python/esph/data/fe_bodyforce.json.

    point = "column": the tip-column mean (x = L - dx/2, y = (j + 1/2) dx),
    as tip(); point = "end": the single material point (L, H/2), the
    end-face centre (dx is then ignored).  Returns {"dh": u_x, "dv": u_y
    (metres), "error_estimate": relative, "err_dh", "err_dv": absolute
    Richardson estimates}.  Raises KeyError (naming the case and the command
    that regenerates the table) when the table lacks it."""
    return _body_force_entry(GRAVITY_TABLE, "gravity", gy, dx, nu, plane, point, problem)


def cylinder_tip(gy: float, dx: float | None = None, nu: float = 0.4, plane: str = "strain",
                 point: str = "column", problem: str = "beam_cylinder") -> dict:
    """The FE reference displacement of the cantilever clamped to a rigid
    cylinder (CYLINDER_PROBLEMS) under its own weight, g = (0, -gy), from
    python/esph/data/fe_cylinder.json; arguments and result as gravity_tip
    (point = "column": tip-column mean for dx; "end": the end-face centre
    (L, H/2)).  Raises KeyError (naming the case and the regenerating
    command) when the table lacks it."""
    return _body_force_entry(CYLINDER_TABLE, "cylinder", gy, dx, nu, plane, point, problem)


def plate_deflection(gy: float, dx: float | None = None, nu: float = 0.3, plane: str = "strain",
                     point: str = "column", problem: str = "fsi_plate") -> dict:
    """The FE reference displacement of the hydrostatic plate (PLATE_PROBLEMS)
    under g = (0, -gy), from python/esph/data/fe_plate.json; point =
    "column": the mean of the two mid-span columns for dx; "top": the top
    face's mid-point.  Returns {"dh", "dv", "error_estimate", "err_dh",
    "err_dv"} as gravity_tip (dh vanishes by symmetry for the columns' mean).
    Raises KeyError (naming the case and the regenerating command) when the
    table lacks it."""
    return _body_force_entry(PLATE_TABLE, "plate", gy, dx, nu, plane, point, problem)


def _body_force_entry(path: Path, kind: str, gy, dx, nu, plane, point, problem) -> dict:
    load = -float(gy)
    column = point == "column"
    if column and dx is None:
        raise ValueError(f"{kind}_tip: point='column' needs dx")
    where = (f"(problem={problem!r}, gy={gy:g}, " + (f"dx={dx:g}, " if column else "")
             + f"nu={nu:g}, plane={plane!r}, point={point!r})")
    command = f"cd python && {REGENERATE} --problems {problem}"
    try:
        part = _load_table(path)["problems"][problem]
    except FileNotFoundError:
        raise KeyError(f"no FE {kind} table {path}; make it with: {command}") from None
    except KeyError:
        raise KeyError(f"FE {kind} table has no problem {where}; regenerate with: "
                       f"{command}") from None
    for e in part["entries"]:
        if (e.get("point", "column") == point and _close(e["load"], load)
                and abs(e["nu"] - nu) < 1e-12 and e["plane"] == plane
                and (not column or _close(e["dx"], dx))):
            keys = ["dh", "dv", "error_estimate", "err_dh", "err_dv"]
            return {k: e[k] for k in keys}
    raise KeyError(f"FE {kind} table has no entry {where}; regenerate with: {command}")

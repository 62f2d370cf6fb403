"""The results page, doc/Results.rst, rendered from the JSON in doc/results/.

Every measured figure of the docs lives in one of those JSON files, each
written by a command of this harness (or, where the command prints only, a
transcription of its output that says so); doc/results/sources.json records
for each file the command, date, commit and machine.  The page is a pure
function of those files:

    python -m esph.results_page            # write doc/Results.rst
    python -m esph.results_page --check    # exit 1 if the committed page differs

python/tests/test_results_page.py runs the check, so a page edited by hand,
or data changed without regenerating the page, fails the tests."""
from __future__ import annotations

import argparse
import difflib
import json
import math
import re
import sys
import textwrap
from pathlib import Path

DOC = Path(__file__).resolve().parents[2] / "doc"
RESULTS = DOC / "results"
PAGE = DOC / "Results.rst"

# the validate variants by name, as esph.validate labels them
VARIANTS = {"linear/fixed": "the paper's scheme (linear gradient, fixed clamp columns, cell "
                            "volumes, load on the last column)",
            "default": "the defaults (quadratic gradient, mirror clamp, set_sph_volumes, "
                       "fix sph/traction on the end face, hourglass 0.2)",
            "quadratic/mirror": "quadratic gradient, mirror clamp, cell volumes, column load",
            "quadratic/fixed": "quadratic gradient, fixed clamp, cell volumes, column load",
            "linear/mirror": "linear gradient, mirror clamp, cell volumes, column load"}


# ---------------------------------------------------------------- formatting

def isnan(x) -> bool:
    return x is None or (isinstance(x, float) and math.isnan(x))


def pct(x, digits: int = 3) -> str:
    """A relative error as a signed percentage, '' for a missing value."""
    if isnan(x):
        return ""
    if round(100 * x, digits) == 0:
        return f"{0:.{digits}f} %"           # round-off: no sign
    return f"{100 * x:+.{digits}f} %"


def num(x, fmt: str = ".4g") -> str:
    return "" if isnan(x) else format(x, fmt)


def mm(x, digits: int = 4) -> str:
    return "" if isnan(x) else f"{1e3 * x:.{digits}f}"


def orders(errors, spacings) -> list:
    """Observed order between successive resolutions, log(e1/e2)/log(h1/h2);
    nan for the first and where an error is zero."""
    out = [math.nan]
    for k in range(1, len(errors)):
        e1, e2 = abs(errors[k - 1]), abs(errors[k])
        ok = e1 > 0 and e2 > 0 and spacings[k - 1] != spacings[k]
        out.append(math.log(e1 / e2) / math.log(spacings[k - 1] / spacings[k]) if ok else math.nan)
    return out


def order_text(q) -> str:
    return "" if isnan(q) else f"{q:.2f}"


def heading(text: str, char: str) -> list[str]:
    return [text, char * len(text), ""]


def table(header: list[str], rows: list[list[str]], widths: str | None = None) -> list[str]:
    """An rst list-table."""
    out = [".. list-table::", "   :header-rows: 1"]
    if widths:
        out.append(f"   :widths: {widths}")
    out.append("")
    for row in [header] + rows:
        for j, cell in enumerate(row):
            out.append(("   * - " if j == 0 else "     - ") + (cell if cell != "" else ""))
    out.append("")
    return [line.rstrip() for line in out]


def paragraph(text: str) -> list[str]:
    """A paragraph wrapped at 78 columns, never inside a ``literal`` or a
    word, nor at a hyphen."""
    parts = text.split("``")
    for k in range(1, len(parts), 2):
        parts[k] = parts[k].replace(" ", _KEEP)
    lines = textwrap.wrap("``".join(parts), 78, break_long_words=False, break_on_hyphens=False)
    return [line.replace(_KEEP, " ") for line in lines] + [""]


_KEEP = "\x00"     # a space inside a literal while wrapping


# ---------------------------------------------------------------- sources

def load_results(folder: Path) -> tuple[dict, dict]:
    """(sources, data): sources.json, and each JSON file it lists by name."""
    sources = json.loads((folder / "sources.json").read_text())
    data = {name: json.loads((folder / name).read_text()) for name in sources}
    return sources, data


def sourced_heading(title: str, name: str, source: dict, char: str = "-") -> list[str]:
    """A section's heading and where its data come from (provenance)."""
    return heading(title, char) + provenance(name, source)


def provenance(name: str, source: dict) -> list[str]:
    """Where a JSON file came from: the command that wrote it, when, at which
    commit, on which machine."""
    if source.get("transcribed_from"):
        text = (f"Data: ``doc/results/{name}``, transcribed by hand from "
                f"{source['transcribed_from']}")
    else:
        text = f"Data: ``doc/results/{name}``, written by ``{source['command']}``"
    if source.get("output"):
        text += f" (as ``{source['output']}``)"
    if source.get("via"):
        text += f"; its printed table turned into JSON by ``{source['via']}``"
    details = [f"{key} {source[key]}" for key in ("date", "commit") if source.get(key)]
    if details:
        text += "; " + ", ".join(details)
    text += "."
    if source.get("machine"):
        text += f"  Machine: {source['machine']}."
    if source.get("note"):
        text += "  " + source["note"]
    return paragraph(text)


# ---------------------------------------------------------------- validate

def rows_of(data: list, table_id: str, **match) -> list[dict]:
    return [r for r in data if str(r.get("table")) == table_id
            and all(r.get(k) == v for k, v in match.items())]


def variants_in(rows) -> list[str]:
    return list(dict.fromkeys(r["variant"] for r in rows))


def validate_table1(data) -> list[str]:
    rows = rows_of(data, "1")
    if not rows:
        return []
    out = heading("Table 1: the beam at all loads", "-")
    out += paragraph("Tip deflection dv of the cantilever (L = 0.2 m, H = 0.02 m, E = 20 GPa, "
                     "nu = 0, plane stress) at the centroid of the last column, against the "
                     "elastica at the same material point, beside the paper's ICB value; "
                     "*vs continuum* is the error against the 2D continuum (finite elements "
                     "for a face load, Reissner's beam with shear for the paper's column load), "
                     "which the elastica's missing shear compliance (about 0.6 %) hides.")
    for variant in variants_in(rows):
        sel = rows_of(data, "1", variant=variant)
        out += paragraph(f"**{VARIANTS.get(variant, variant)}**, dx = "
                         f"{sel[0]['dx'] * 1e3:g} mm:")
        out += table(["Fy [N]", "dv [mm]", "elastica [mm]", "paper [mm]", "vs elastica",
                      "paper vs elastica", "vs continuum", "Newton iterations", "wall [s]"],
                     [[f"{r['load']:g}", mm(r["dv"]), mm(r["exact"]), num(r["paper"], ".2f"),
                       pct(r["error"], 2),
                       pct(r["paper"] * 1e-3 / r["exact"] - 1, 2) if not isnan(r["paper"]) else "",
                       pct(r["error_continuum"], 3), str(r["steps"]), f"{r['wall']:.2f}"]
                      for r in sel])
    return out


def convergence(sel: list[dict], key: str) -> list[tuple[dict, float]]:
    sel = sorted(sel, key=lambda r: -r["dx"])
    qs = orders([r[key] for r in sel], [r["dx"] for r in sel])
    return list(zip(sel, qs))


def validate_table2(data) -> list[str]:
    rows = rows_of(data, "2")
    if not rows:
        return []
    out = heading("Table 2: the beam's convergence in dx", "-")
    out += paragraph("Relative error of the tip deflection against the elastica and against "
                     "the 2D continuum, q = observed order between successive spacings; "
                     "*paper* is the paper's Table 2 (its error against its own theory).")
    for variant in variants_in(rows):
        for load in dict.fromkeys(r["load"] for r in rows_of(data, "2", variant=variant)):
            sel = rows_of(data, "2", variant=variant, load=load)
            ela, cont = convergence(sel, "error"), convergence(sel, "error_continuum")
            out += paragraph(f"**{VARIANTS.get(variant, variant)}**, Fy = {load:g} N:")
            out += table(["dx [mm]", "atoms' dv vs elastica", "q", "paper", "vs continuum", "q"],
                         [[f"{r['dx'] * 1e3:g}", pct(r["error"], 2), order_text(q),
                           "" if isnan(r["paper"]) else f"{r['paper']:.2f} %",
                           pct(r["error_continuum"], 3), order_text(qc)]
                          for (r, q), (_, qc) in zip(ela, cont)])
    return out


def validate_table3(data) -> list[str]:
    rows = rows_of(data, "3")
    if not rows:
        return []
    out = heading("Table 3: the truss at all loads", "-")
    out += paragraph("Axial tip displacement dh of the bar (L = 0.2 m, H = 5 cm, E = 2 GPa) "
                     "against the exact answer of Green strain and St. Venant-Kirchhoff at the "
                     "same material point; the paper's value beside it.")
    for variant in variants_in(rows):
        sel = rows_of(data, "3", variant=variant)
        out += paragraph(f"**{VARIANTS.get(variant, variant)}**, dx = "
                         f"{sel[0]['dx'] * 1e3:g} mm:")
        out += table(["Fx [N]", "dh [mm]", "exact [mm]", "error", "paper [mm]", "note"],
                     [[f"{r['load']:g}", mm(r["dh"]), mm(r["exact"]), pct(r["error"], 4),
                       num(r["paper"], ".2f"), r.get("note", "")] for r in sel])
    return out


def validate_table4(data) -> list[str]:
    rows = rows_of(data, "4")
    if not rows:
        return []
    out = heading("Table 4: the truss's convergence in dx", "-")
    out += paragraph("Relative error of dh against the exact answer, q = observed order "
                     "(none where the error is round-off); *paper* is the paper's Table 4 "
                     "(against F L/(A E)).")
    for variant in variants_in(rows):
        for load in dict.fromkeys(r["load"] for r in rows_of(data, "4", variant=variant)):
            sel = convergence(rows_of(data, "4", variant=variant, load=load), "error")
            # errors that show as 0.0000 % are the solver's tolerance: no order
            roundoff = all(pct(r["error"], 4) == pct(0.0, 4) for r, _ in sel)
            out += paragraph(f"**{VARIANTS.get(variant, variant)}**, Fx = {load:g} N:")
            out += table(["dx [mm]", "error", "q", "paper"],
                         [[f"{r['dx'] * 1e3:g}", pct(r["error"], 4),
                           "" if roundoff else order_text(q),
                           "" if isnan(r["paper"]) else f"{r['paper']:.2f} %"]
                          for r, q in sel])
    return out


def validate_table5(data) -> list[str]:
    rows = rows_of(data, "5")
    if not rows:
        return []
    out = heading("Table 5: the defaults against the finite-element continuum", "-")
    out += paragraph("Tip deflection against mesh-converged Q2 finite elements of the same "
                     "continuum (``esph.fe``: Green strain and St. Venant-Kirchhoff, clamped at "
                     "x = 0, dead traction on x = L) at the same material point, q = observed "
                     "order; beside the particles, Q2 elements on uniform meshes with a node "
                     "every dx, which meet the clamp's corners as the particles do.  With "
                     "nu > 0 the clamped corners are singular and bound the order of any uniform "
                     "discretisation (Williams' exponent, ``esph.theory.clamp_corner_order``: "
                     "2 lambda = 1.52 in plane stress, 1.42 at a 3D body's clamped edges).")
    beam = [r for r in rows if r["problem"] == "beam"]
    for note in dict.fromkeys(r["note"] for r in beam if r["variant"] != "fe-uniform"):
        sel = [r for r in beam if r["note"] == note and r["variant"] != "fe-uniform"]
        peer = [r for r in beam
                if r["note"].startswith(note + ",") and r["variant"] == "fe-uniform"]
        dxs = sorted(dict.fromkeys(r["dx"] for r in sel), reverse=True)
        header = ["Fy [N]"]
        for dx in dxs:
            header += [f"particles, {dx * 1e3:g} mm", "q"]
        for dx in dxs:
            header += [f"uniform Q2, {dx * 1e3:g} mm", "q"]
        body = []
        for load in dict.fromkeys(r["load"] for r in sel):
            cells = [f"{load:g}"]
            for group in (sel, peer):
                series = sorted((r for r in group if r["load"] == load), key=lambda r: -r["dx"])
                qs = orders([r["error"] for r in series], [r["dx"] for r in series])
                for r, q in zip(series, qs):
                    cells += [pct(r["error"], 4), order_text(q)]
            body.append(cells)
        out += paragraph(f"**Beam, {note.replace('nu ', 'nu = ')}, plane stress:**")
        out += table(header, body)
    truss = [r for r in rows if r["problem"] == "truss"]
    if truss:
        out += paragraph(f"**Truss, {truss[0]['note'].replace('nu ', 'nu = ')}, dx = "
                         f"{truss[0]['dx'] * 1e3:g} mm** (the clamp stops the Poisson "
                         "contraction, so the bar is not homogeneous):")
        out += table(["Fx [N]", "dh [mm]", "FE [mm]", "error"],
                     [[f"{r['load']:g}", mm(r["dh"]), mm(r["exact"]), pct(r["error"], 4)]
                      for r in truss])
    solid = [r for r in rows if r["problem"].startswith("beam3d")]
    if solid:
        shapes = {"beam3d": "0.2 x 0.02 x 0.02 m", "beam3d_short": "0.1 x 0.01 x 0.01 m"}
        out += paragraph("**3D cantilevers** (end traction, tip deflection against 3D Q2 "
                         "elements):")
        out += table(["body", "dx [mm]", "Fy [N]", "nu", "dv [mm]", "FE [mm]", "error",
                      "wall [s]"],
                     [[shapes.get(r["problem"], r["problem"]), f"{r['dx'] * 1e3:g}",
                       f"{r['load']:g}", r["note"].replace("nu ", ""), mm(r["dv"]),
                       mm(r["exact"]), pct(r["error"], 3), f"{r['wall']:.1f}"] for r in solid])
    return out


def validate_table6(data) -> list[str]:
    rows = rows_of(data, "6")
    if not rows:
        return []
    out = heading("Table 6: two spheres colliding in 3D, against Hertz", "-")
    out += paragraph("``examples/spheres3d``: two identical spheres (R = 5 cm, E = 20 GPa, "
                     "nu = 0.3) head on at +-v, ``fix sph/contact`` between them.  The lattice "
                     "sphere's pole is a flat facet wider than Hertz's contact circle at these "
                     "resolutions, so the contact is shorter and stiffer than Hertz's; two flat "
                     "punches in series with the contact springs (``theory.flat_contact_impact``"
                     ") model it.")
    out += table(["R/dx", "atoms", "v [m/s]", "contact vs Hertz", "peak force vs Hertz",
                  "contact vs flat punch", "restitution", "energy error", "wall [s]"],
                 [[num(r.get("nr"), "g"), num(r.get("atoms"), "d"), num(r.get("v"), "g"),
                   pct(r.get("duration_error"), 1), pct(r.get("force_error"), 1),
                   pct(r.get("facet_duration_error"), 1), num(r.get("restitution"), ".4f"),
                   num(r.get("energy_error"), ".1e"), num(r.get("wall"), ".2f")]
                  for r in rows])
    return out


def validate_table7(data) -> list[str]:
    rows = rows_of(data, "7")
    if not rows:
        return []
    out = heading("Table 7: Lame's thick-walled cylinder", "-")
    out += paragraph("``examples/lame``: a = 5 cm, b = 10 cm, nu = 0.3, inner pressure p/E = "
                     "1e-6 (*full*: the ring pinned at three atoms; *quarter*: between two "
                     "``fix sph/mirror ... slip yes`` planes; *clamped*: clamped on r = a by "
                     "``fix sph/mirror cylinder``, the same pressure outside).  Relative errors "
                     "of the layer means of the radial displacement and the hoop stress at the "
                     "innermost (a+) and outermost (b-) layers against the exact solution, "
                     "q = observed order in the number of layers nw (clamped: u_r(a+) is itself "
                     "O(dr), so its q = 1 is an absolute order 2).")
    header = ["plane", "model", "nw", "atoms", "u_r(a+)", "q", "u_r(b-)", "q", "stt(a+)", "q",
              "stt(b-)", "q", "wall [s]"]
    body = []
    for plane in dict.fromkeys(r["plane"] for r in rows):
        for model in dict.fromkeys(r["model"] for r in rows if r["plane"] == plane):
            series = sorted((r for r in rows if r["plane"] == plane and r["model"] == model),
                            key=lambda r: r["nw"])
            hs = [1.0 / r["nw"] for r in series]
            qs = {k: orders([r[k] for r in series], hs)
                  for k in ("ur_in", "ur_out", "stt_in", "stt_out")}
            for j, r in enumerate(series):
                cells = [plane, model, str(r["nw"]), str(r["atoms"])]
                for k in ("ur_in", "ur_out", "stt_in", "stt_out"):
                    cells += [pct(r[k], 3), order_text(qs[k][j])]
                body.append(cells + [f"{r['wall']:.2f}"])
    out += table(header, body)
    return out


def validate_table8(data) -> list[str]:
    rows = [r for r in rows_of(data, "8") if r.get("problem") != "beam_cylinder"]
    cylinder = [r for r in rows_of(data, "8") if r.get("problem") == "beam_cylinder"]
    if not rows:
        return []
    out = heading("Table 8: the beam under its own weight", "-")
    out += paragraph("``examples/beam -var Fy 0 -var gy -6e4`` (``fix sph/bodyforce``; tip "
                     "deflection about 9 % of L), against the FE continuum under the same body "
                     "force: the tip column's mean deflection and the end-face centre's "
                     "(``compute sph/probe``), q = observed order.")
    body = []
    for nu, plane in dict.fromkeys((r["nu"], r["plane"]) for r in rows):
        series = sorted((r for r in rows if r["nu"] == nu and r["plane"] == plane),
                        key=lambda r: -r["dx"])
        dxs = [r["dx"] for r in series]
        q_col = orders([r["err_column"] for r in series], dxs)
        q_end = orders([r["err_end"] for r in series], dxs)
        for j, r in enumerate(series):
            body.append([f"{nu:g}", plane, f"{r['dx'] * 1e3:g}", pct(r["err_column"], 4),
                         order_text(q_col[j]), pct(r["err_end"], 4), order_text(q_end[j]),
                         num(r["fe_error"], ".1e"), f"{r['wall']:.2f}"])
    out += table(["nu", "plane", "dx [mm]", "tip column", "q", "end centre", "q",
                  "FE error estimate", "wall [s]"], body)
    return out + cylinder_table(cylinder)


def cylinder_table(rows) -> list[str]:
    if not rows:
        return []
    out = paragraph("The same beam clamped to a rigid cylinder of radius H (``examples/"
                    "beam_cylinder``: the body laid out to fit the arc, ``set_sph_volumes ... "
                    "jacobian``, ``fix sph/mirror cylinder ... along x``), against the FE "
                    "continuum with the arc: the end-face centre, q = observed order.  The arc "
                    "meets the free faces at 60 degrees; Williams' exponent there bounds q by "
                    "2 lambda = 1.74 at nu = 0.4 in plane strain.")
    series = sorted(rows, key=lambda r: -r["dx"])
    q = orders([r["err_end"] for r in series], [r["dx"] for r in series])
    body = [[f"{r['nu']:g}", r["plane"], f"{round(0.02 / r['dx']):d}", f"{r['dx'] * 1e3:g}",
             pct(r["err_end"], 4), order_text(q[j]), num(r["fe_error"], ".1e"),
             f"{r['wall']:.2f}"] for j, r in enumerate(series)]
    return out + table(["nu", "plane", "across", "dx [mm]", "end centre", "q",
                        "FE error estimate", "wall [s]"], body)


def validate_table9(data) -> list[str]:
    rows = sorted(rows_of(data, "9"), key=lambda r: r["layers"])
    if not rows:
        return []
    out = heading("Table 9: the hydrostatic plate (RHEO's water on an elastic plate)", "-")
    r0 = rows[0]
    out += paragraph("``examples/fsi_plate`` scaled (``esph.problems.PLATE_GEOMETRY``: L = 0.1 m, "
                     "L/t = 10, water 0.05 m deep, E = 10 MPa, nu = 0.3, rho_s = 2700, plane "
                     "strain, the plate's own weight on; O'Connor & Rogers' set-up made cheap, "
                     "``studies/fsi_rheo/README.md`` 5.2): water of RHEO coupled to the clamped "
                     "``sph/icb`` plate by ``create_sph_twins`` and ``fix sph/fluid``, against "
                     "the FE continuum under the same load (uniform pressure rho_f g H on the "
                     "top face plus the weight).  The plate's volumes are ``set_sph_volumes``' "
                     "(exact for quadratics).  w: the two mid-span columns' mean deflection, "
                     f"time-averaged over {r0['window']:.3g} s after {r0['tstart']:.3g} s of "
                     "settling (``fix viscous`` on water and plate); sub: the plate's sub-steps "
                     "per fluid step (``fix sph/fluid substeps``); q = observed order in the "
                     "layers through the thickness; dry: the same plate without water "
                     "(``in.fsi_plate_dry``, the column's pressure as forces on its top atoms, "
                     "Newton statics) against the FE, coupled/dry: the coupled deflection over "
                     "the dry one - 1, the coupling's own share; force: the fluid's force on the "
                     "plate / "
                     "(rho_f g H L) (walls: on the tank's walls over the clamps); mass: relative "
                     "change of the water's and plate's mass; dP_y: change of their momentum over "
                     "the window / the load's impulse over it.  Kirchhoff's q L^4/(384 D) = "
                     f"{r0['kirchhoff']:.4e} m is a sanity line (no shear, no clamp compliance).")
    q = orders([r["err_fe"] for r in rows], [r["dx"] for r in rows])
    # rows of runs before the dry plate and the sub-steps were recorded: blank
    dry = [r.get("err_dry", math.nan) for r in rows]
    q_dry = orders(dry, [r["dx"] for r in rows])
    body = [[str(r["layers"]), str(r["atoms"]), str(r.get("substeps", "")), f"{r['w']:.4e}",
             f"{r['fe']:.4e}", pct(r["err_fe"], 3), order_text(q[j]), pct(dry[j], 3),
             order_text(q_dry[j]), pct(r.get("vs_dry", math.nan), 3), pct(r["err_kirchhoff"], 2),
             f"{r['force']:.4f}", f"{r['wallforce']:+.4f}", num(r["mass_drift"], ".1e"),
             num(r["dp_y"], "+.1e"), num(r["fe_error"], ".1e"), f"{r['wall']:.1f}"]
            for j, r in enumerate(rows)]
    out += table(["layers", "atoms", "sub", "w [m]", "FE [m]", "err FE", "q", "dry", "q dry",
                  "coupled/dry", "err Kirchhoff", "force", "walls", "mass", "dP_y",
                  "FE error estimate", "wall [s]"], body)
    return out


def validate_table10(data) -> list[str]:
    """The elastic-gate dam break against the experiment and the peers:
    the tip's displacement at T (quick) or its peak (full)."""
    rows = rows_of(data, "10")
    if not rows:
        return []
    out = heading("Table 10: the elastic-gate dam break (Antoci et al. 2007)", "-")
    r0 = rows[0]
    out += paragraph("``examples/fsi_gate``: RHEO's water column (0.1 x 0.14 m, at its "
                     "hydrostatic density) behind a rubber gate 5 mm thick, clamped by ``fix "
                     "sph/mirror`` above 0.079 m (E = 12 MPa, nu = 0.4, rho_s = 1100 kg/m^3, "
                     "plane strain), coupled by ``create_sph_twins`` and ``fix sph/fluid``, "
                     "with a repulsive water-twin guard (LJ within 0.6 dx, ``-var guard``: "
                     "without it water is shot into the gate's tip, ``studies/fsi_rheo/"
                     "README.md`` 9.4); dx "
                     "= 5/3 mm (the gate 3 particles thick, RHEO's cut), the gate sub-stepped "
                     f"{r0['substeps']} times per fluid step"
                     + (f", the fluid's speed of sound c_f = {r0['cfac']:g} sqrt(2 g H) and "
                        f"pair rheo's artificial viscosity {r0['av']:g} (``-var cfac``, ``-var "
                        "av``: the peak converges in c_f at a fixed av c_f, "
                        "``studies/fsi_rheo/README.md`` 9.6)" if "cfac" in r0 else "")
                     + (", the fluid's pressure in each step's force from the density of "
                        "that step (``fix sph/fluid pressure/density full``: fix rheo's "
                        "half-step density lets water particles at the walls rattle until "
                        "they are shot off, ``studies/fsi_rheo/README.md`` 9.9)"
                        if r0.get("pdensity") == "full" else "")
                     + f".  {r0['atoms']} atoms ({r0['water']} "
                     f"water, {r0['gate']} in the gate), {r0['steps']} steps of "
                     f"{r0['dt']:.3g} s to T = {r0['T']:.3g} s in {r0['wall']:.0f} s of wall "
                     "time.  Tip: the gate's free end, its downstream corner.  The references "
                     "are digitised curves (``python/esph/data/elastic_gate.json``, with the "
                     "source of each: the experiment as digitised from Ng et al. 2020 in "
                     "dineshadepu/fsi_etvf), interpolated linearly at t between their points; "
                     "their peaks are the largest tabulated points.  "
                     f"Mass: relative change {num(r0['mass_drift'], '.1e')}; the water's "
                     "momentum change less the impulse on it (gravity, walls, gate), over "
                     f"gravity's impulse: {num(r0['dpx'], '+.1e')} (x), "
                     f"{num(r0['dpy'], '+.1e')} (y).")
    if "thin_inside" in r0:
        from .validate import thin_summary
        found = r0.get("thin_inside") or r0.get("thin_through") or r0.get("thin_two_faces")
        out += paragraph("``fix sph/fluid``'s thin-body check, every 100 steps as warnings "
                         f"(``thin/check 100 warn``), up to T: {thin_summary(r0)}."
                         + ("  The tip's curve rests on a run with these (``studies/"
                            "fsi_rheo/README.md`` section 9.4)." if found else ""))
    if "uxmax" in r0:
        curves = "ux_rms" in r0
        body = [["this (``examples/fsi_gate``)", mm(r0["uxmax"], 2), f"{r0['tpeak']:.3f}",
                 mm(r0["uypeak"], 2), mm(r0["uymax"], 2), ""] + (["", ""] if curves else [])]
        body += [[r["reference"], mm(r["uxmax_ref"], 2), f"{r['tpeak_ref']:.3f}",
                  mm(r["uypeak_ref"], 2), mm(r["uymax_ref"], 2),
                  pct(r["uxmax"] / r["uxmax_ref"] - 1.0, 1)]
                 + ([mm(r["ux_rms"], 2), mm(r["uy_rms"], 2)] if curves else []) for r in rows]
        head = ["", "peak ux [mm]", "at t [s]", "uy then [mm]", "max uy [mm]", "ours vs peak ux"]
        if curves:
            # the whole curves: ours less the reference at its points up to T
            out += paragraph("*rms dux*, *rms duy*: the root mean square of ours less the "
                             "reference over the reference's points up to T, ours "
                             "interpolated at them.")
            head += ["rms dux [mm]", "rms duy [mm]"]
        return out + table(head, body)
    body = [["this (``examples/fsi_gate``)", mm(r0["ux"], 2), mm(r0["uy"], 2), ""]]
    body += [[r["reference"], mm(r["ux_ref"], 2), mm(r["uy_ref"], 2),
              pct(r["ux"] / r["ux_ref"] - 1.0, 1)] for r in rows]
    return out + table(["", f"ux({r0['t']:g} s) [mm]", "uy [mm]", "ours vs ux"], body)


def validate_section(name: str, source: dict, data: list) -> list[str]:
    out = sourced_heading("Validation (``scripts/validate``)", name, source, "=")
    out += paragraph("ICB-SPH (``pair_style sph/icb``) with the paper's scheme and with the "
                     "defaults, beside the exact answer of each model at the same material "
                     "point and the paper's numbers (Tran-Duc et al. 2023, Tables 1-4); then the "
                     "defaults against finite elements, Hertz, Lame and the beam's self-weight. "
                     "Errors are (ours - reference)/reference.")
    for render in (validate_table1, validate_table2, validate_table3, validate_table4,
                   validate_table5, validate_table6, validate_table7, validate_table8,
                   validate_table9, validate_table10):
        out += render(data)
    return out


def validate_plate_section(name: str, source: dict, data: list) -> list[str]:
    """Table 9 alone, in full mode: the hydrostatic plate down to the finest
    resolution whose coupled run fits in 10 minutes on one core."""
    out = sourced_heading("Validation: the hydrostatic plate in full (``python -m esph validate "
                          "--full --tables 9``)", name, source, "=")
    out += paragraph("Table 9 of ``scripts/validate --full``, down to the finest resolution "
                     "whose coupled run takes at most 10 minutes on one core; wall [s] is each "
                     "coupled run's wall time on the machine above, at its load.")
    return out + validate_table9(data)


# ---------------------------------------------------------------- speed

def statics_section(name: str, source: dict, data: list) -> list[str]:
    out = sourced_heading("Statics: time to the static beam (``python -m esph statics``)", name,
                          source)
    out += paragraph("The beam under -250 N with the defaults (pk1, quadratic gradient, mirror "
                     "clamp, exact volumes, face traction); *vs converged* is against Newton "
                     "to 1e-10 of the load with the row's stress measure, *vs elastica* at the "
                     "same material point.  Routes: *newton* = ``min_style sph/newton`` (force "
                     "tolerance 1e-7 of the load), *newton-loose* = the same to 1e-3, *cg* = "
                     "``min_style cg`` with ``line forcezero``, *dyn* = damped dynamics, "
                     "*-corotated* = the paper's stress measure (Newton-Krylov).")
    out += table(["route", "ranks", "atoms", "dx [mm]", "iterations / steps", "wall [s]",
                  "loop [s]", "vs converged", "vs elastica"],
                 [[r["route"], str(r["nprocs"]), str(r["atoms"]), f"{r['dx'] * 1e3:g}",
                   str(r["iterations"]), f"{r['wall']:.2f}", num(r["loop"], ".2f"),
                   pct(r["deviation"], 5), pct(r["error"], 3)] for r in data])
    return out


def speed_section(name: str, source: dict, data: list) -> list[str]:
    out = sourced_heading("Speed against error (``python -m esph speed``)", name, source)
    out += paragraph("Wall time to the answer, throughput of the loop (particle-steps per "
                     "second) and error against the exact answer of each method's model.")
    out += table(["problem", "load", "method", "dx [mm]", "atoms", "steps", "wall [s]",
                  "M particle-steps/s", "error", "status"],
                 [[r["problem"], f"{r['load']:g}", r["method"], f"{r['dx'] * 1e3:g}",
                   str(r["atoms"]), str(r["steps"]), num(r["wall"], ".2f"),
                   num(r["throughput"] / 1e6 if not isnan(r["throughput"]) else math.nan, ".3f"),
                   pct(r["error"], 3), r["status"]] for r in data])
    return out


def recorded_section(name: str, source: dict, data: dict) -> list[str]:
    """Tables transcribed from commands that print only: each with its own
    command, columns and rows as given in the file."""
    out = sourced_heading("Recorded: tables transcribed from earlier runs", name, source)
    for entry in data["tables"]:
        out += heading(entry["title"], "^")
        out += paragraph(f"Command: ``{entry['command']}``.  {entry['description']}")
        out += table(entry["columns"], [[str(c) for c in row] for row in entry["rows"]])
        if entry.get("note"):
            out += paragraph(entry["note"])
    return out


def bench_section(name: str, source: dict, data: dict) -> list[str]:
    out = sourced_heading(source.get("title", "Throughput of the dynamics (``scripts/bench``)"),
                          name, source)
    out += paragraph(f"{data['title']}.  Particle-steps per second of LAMMPS's loop time; "
                     "*tlsph* and *tlsph3d* are LAMMPS's MACHDYN ``smd/tlsph`` on the same "
                     "body (``examples/beam/in.beam_tlsph``, ``examples/beam3d/in.beam3d_tlsph``"
                     "), *icb3d* the 3D cantilever 0.2 x 0.02 x 0.02 m with the defaults.")
    out += table(["style", "dx [mm]", "atoms", "ranks", "loop [s]", "M particle-steps/s",
                  "us per particle-step and rank"],
                 [[r["style"], f"{r['dx'] * 1e3:g}", str(r["atoms"]), str(r["ranks"]),
                   f"{r['loop']:.3f}", f"{r['rate'] / 1e6:.3f}", f"{r['us_per_step']:.3f}"]
                  for r in data["rows"]])
    return out


def bench3d_rows(rows: list) -> list[str]:
    """The table of esph bench3d's rows (as bench3d.bench3d returns them)."""
    return table(["dx [mm]", "atoms", "ranks", "solver", "Newton iterations", "wall [s]",
                  "MB per rank", "100 dynamic steps [s]", "ratio"],
                 [[f"{r['dx'] * 1e3:g}", str(r.get("atoms", "")), str(r["ranks"]), r["solver"],
                   str(r.get("iterations", "")), num(r.get("wall"), ".1f"),
                   num(r.get("rss_mb"), ".0f"), num(r.get("dyn100"), ".2f"),
                   num(r.get("ratio"), ".1f")] if not r.get("failed") else
                  [f"{r['dx'] * 1e3:g}", "", str(r["ranks"]), r["solver"],
                   r["failed"], "", "", "", ""]
                  for r in rows])


def bench3d_section(name: str, source: dict, data: dict) -> list[str]:
    out = sourced_heading("3D cantilever statics per linear solver (``scripts/bench3d``)", name,
                          source)
    out += paragraph(f"{data['title']}.  Wall time of the whole run, Newton iterations, peak "
                     "memory of a rank, and the ratio to 100 dynamic steps of the same body "
                     "on the same ranks; *direct* = the Hessian gathered and factorised on "
                     "rank 0, *mumps* = PETSc's MUMPS across the ranks, *petsc* = matrix-free "
                     "CG with multigrid across the ranks (the default in 3D).")
    return out + bench3d_rows(data["rows"])


def commands(rows: list, keys: tuple, lmp: str | None = None) -> list[str]:
    """The command lines of rows (each key of `keys` in turn) as one
    literal block, each once, in order, after a line that says where they
    run (and which binary `lmp` was, if known)."""
    lines = list(dict.fromkeys(r[k] for r in rows for k in keys if r.get(k)))
    if not lines:
        return []
    intro = "The commands, from the project root"
    intro += f" (``lmp`` = ``{lmp}``):" if lmp else ":"
    return paragraph(intro) + ["::", ""] + [f"   {line}" for line in lines] + [""]


def headtohead_section(name: str, source: dict, data: dict) -> list[str]:
    out = sourced_heading("Head to head with MACHDYN (``scripts/bench``)", name, source)
    out += paragraph(f"{data['title']}.  Million particle-steps per second of LAMMPS's loop "
                     "time on one rank: ``pair_style sph/icb`` with the defaults (hourglass "
                     "control 0.2) and with ``-var hg 0``, beside LAMMPS's MACHDYN "
                     "``smd/tlsph`` on the same body (``hfac`` 2.01 in 2D, its most accurate "
                     "kernel radius there; 2.4 in 3D); *ratio* = ours / MACHDYN.  The variants "
                     "ran alternately, each keeping its best run; *loop times* lists every "
                     "run, in order, so the spread is visible.  MACHDYN runs fewer steps per "
                     "run (*steps*: ours / MACHDYN); the rate is per particle-step.")
    rows = data["rows"]
    out += table(["body", "particles", "steps", "defaults", "hourglass 0", "MACHDYN",
                  "ratio defaults", "ratio hourglass 0"],
                 [[r["body"], str(r["particles"]), f"{r['steps']} / {r['machdyn_steps']}",
                   num(r["rate_defaults"] / 1e6, ".3f"), num(r["rate_hg0"] / 1e6, ".3f"),
                   num(r["rate_machdyn"] / 1e6, ".3f"), num(r["ratio_defaults"], ".2f"),
                   num(r["ratio_hg0"], ".2f")] for r in rows])
    out += table(["body", "loop times, defaults [s]", "hourglass 0 [s]", "MACHDYN [s]"],
                 [[r["body"]] + [" ".join(f"{t:.3f}" for t in r[k])
                                 for k in ("loops_defaults", "loops_hg0", "loops_machdyn")]
                  for r in rows])
    out += commands(rows, ("command_defaults", "command_hg0", "command_machdyn"), data.get("lmp"))
    return out


def statics_bench_section(name: str, source: dict, data: dict) -> list[str]:
    out = sourced_heading("3D cantilever statics against 100 dynamic steps (``scripts/bench``)",
                          name, source)
    out += paragraph(f"{data['title']}.  Wall time of the whole run (start-up included), "
                     "Newton iterations, peak memory of the largest rank, and the ratio of the "
                     "static solve's wall time to that of 100 dynamic steps.")
    out += bench3d_rows(data["rows"])
    out += commands(data["rows"], ("command", "dyn100_command"), data.get("lmp"))
    return out


def weak_section(name: str, source: dict, data: dict) -> list[str]:
    out = sourced_heading("Weak scaling of memory (``scripts/bench``)", name, source)
    out += paragraph(f"{data['title']}: the body grows along its length with the rank count "
                     "(4 ranks oversubscribe 2 cores where the machine has 2).  *MB per rank* "
                     "is each rank's peak resident memory (``getrusage`` of its ``lmp``), in "
                     "rank order; *bytes per particle* is the largest rank's over the "
                     "particles per rank, the whole footprint (binary, libraries and MPI "
                     "buffers included): a case whose bytes per particle stay flat as the "
                     "ranks grow has memory that scales.  *dyn* = ``route nve``, *newton* = "
                     "``min_style sph/newton`` with the defaults.")
    rows = data["rows"]
    out += table(["case", "dim", "ranks", "particles", "per rank", "wall [s]", "MB per rank",
                  "max MB", "bytes per particle"],
                 [[r["case"], str(r["dim"]), str(r["ranks"]), str(r["atoms"]),
                   f"{r['per_rank']:.0f}", num(r["wall"], ".1f"),
                   " ".join(f"{v:.1f}" for v in r["rss_mb"]), num(r["max_rss_mb"], ".1f"),
                   num(r["bytes_per_particle"], ".0f")] for r in rows])
    out += commands(rows, ("command",), data.get("lmp"))
    return out


def validate_gate_section(name: str, source: dict, data: list) -> list[str]:
    """Table 10 in full mode: the elastic gate over 0.2 s, its peak."""
    out = sourced_heading("Validation: the elastic gate in full (``python -m esph validate "
                          "--full --tables g``)", name, source, "=")
    out += paragraph("Table 10 of ``scripts/validate --full``: the elastic-gate dam break "
                     "over 0.2 s (past every reference's first peak; at its defaults the "
                     "example also runs to 0.36 s, the experiment's record, in about 47 minutes, "
                     "``studies/fsi_rheo/README.md`` 9.9) on one core; wall time on the "
                     "machine above, at its load.")
    return out + validate_table10(data) + validate_table10b(data)


def validate_table10b(data) -> list[str]:
    """The gate with SPHinXsys's inputs beside SPHinXsys's own run."""
    rows = rows_of(data, "10b")
    if not rows:
        return []
    r = rows[0]
    out = heading("Table 10b: the elastic gate with SPHinXsys's inputs", "-")
    out += paragraph("The peers of Table 10 publish curves, not all their inputs. SPHinXsys "
                     "publishes its inputs (``tests/2d_examples/test_2d_elastic_gate``: E = "
                     f"{r['E'] / 1e6:g} MPa, nu = {r['nu']:g}, {r['law']}) and a regression run "
                     "of them, so ``examples/fsi_gate`` is run again with that material "
                     "(``-var E``, ``-var nu``, ``-var law``; the gate sub-stepped as its stable "
                     f"step needs: {r['substeps']} sub-steps, {r['steps']} steps, "
                     f"{r['wall']:.0f} s of wall time). SPHinXsys's value is the largest "
                     "excursion of its observer (the gate's free downstream corner, "
                     "interpolated) over its 0.4 s, without a time; the experiment's is its "
                     "largest digitised point.  The fluid is the example's"
                     + (f" (c_f = {r['cfac']:g} sqrt(2 g H), artificial viscosity {r['av']:g}"
                        + (", pressure/density full" if r.get("pdensity") == "full" else "")
                        + ")" if "cfac" in r else "")
                     + "; SPHinXsys's is a Riemann solver's with c_f = 20 sqrt(g H) = 14.1 "
                     "sqrt(2 g H): what the speed of sound, the artificial viscosity and the "
                     "spacing change is measured in ``studies/fsi_rheo/README.md`` sections "
                     "9.5 and 9.6.")
    if "thin_inside" in r:
        from .validate import thin_summary
        out += paragraph(f"``fix sph/fluid``'s thin-body check up to T: {thin_summary(r)}.")
    body = [["this (``examples/fsi_gate``, SPHinXsys's material)", mm(r["uxmax"], 2),
             f"{r['tpeak']:.3f}", mm(r["uymax"], 2), ""],
            ["SPHinXsys regression run, same inputs", mm(r["uxmax_sphinxsys"], 2), "-",
             mm(r["uymax_sphinxsys"], 2), pct(r["uxmax"] / r["uxmax_sphinxsys"] - 1.0, 1)],
            ["Antoci 2007, experiment", mm(r["uxmax_experiment"], 2),
             f"{r['tpeak_experiment']:.3f}", "-",
             pct(r["uxmax"] / r["uxmax_experiment"] - 1.0, 1)]]
    return out + table(["", "peak ux [mm]", "at t [s]", "max uy [mm]", "ours vs peak ux"],
                       body)


SECTIONS = {"validate": validate_section, "validate_plate": validate_plate_section,
            "validate_gate": validate_gate_section,
            "statics": statics_section, "speed": speed_section,
            "bench": bench_section, "bench3d": bench3d_section, "recorded": recorded_section,
            "headtohead": headtohead_section, "statics_bench": statics_bench_section,
            "weak": weak_section}


# ------------------------------------------- the benches that print only

_MACHINE = re.compile(r"machine (.*)$")
_BENCH = re.compile(r"^\s*(\S+)\s+([\d.]+)\s+(\d+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)\s+([\d.]+)"
                    r"\s+(\S.*)$")
_BENCH3D = re.compile(r"^\s*([\d.]+)\s+(\d+)\s+(\d+)\s+(\w+)\s+(\d+)\s+([\d.]+)\s+([\d.]+)"
                      r"\s+([\d.]+)\s+([\d.]+)\s+(.*?)\s+\|\s+(\S.*)$")
_BENCH3D_FAILED = re.compile(r"^\s*([\d.]+)\s+(\d+)\s+(\w+)\s+(failed: .*?|\w+Error|\w+Expired)"
                             r"\s+(cd \S.*)$")


def parse_bench(text: str) -> dict:
    """The table 'python -m esph bench' prints, as JSON rows."""
    lines = text.splitlines()
    rows = []
    for line in lines[3:]:
        m = _BENCH.match(line)
        if m:
            rows.append({"style": m[1], "dx": float(m[2]) * 1e-3, "atoms": int(m[3]),
                         "ranks": int(m[4]), "loop": float(m[5]), "rate": float(m[6]) * 1e6,
                         "us_per_step": float(m[7]), "command": m[8].strip()})
    if not rows:
        raise ValueError("no rows of 'python -m esph bench' found")
    return {"title": lines[0].split("; machine")[0], "machine": _MACHINE.search(lines[0])[1],
            "rows": rows}


def parse_bench3d(text: str) -> dict:
    """The table 'python -m esph bench3d' prints, as JSON rows."""
    lines = text.splitlines()
    rows = []
    for line in lines[3:]:
        m = _BENCH3D.match(line)
        if m:
            rows.append({"dx": float(m[1]) * 1e-3, "atoms": int(m[2]), "ranks": int(m[3]),
                         "solver": m[4], "iterations": int(m[5]), "wall": float(m[6]),
                         "rss_mb": float(m[7]), "dyn100": float(m[8]), "ratio": float(m[9]),
                         "solver_log": m[10].strip(), "command": m[11].strip()})
            continue
        m = _BENCH3D_FAILED.match(line)
        if m:
            rows.append({"dx": float(m[1]) * 1e-3, "ranks": int(m[2]), "solver": m[3],
                         "failed": m[4], "command": m[5].strip()})
    if not rows:
        raise ValueError("no rows of 'python -m esph bench3d' found")
    return {"title": lines[0].split("; machine")[0], "machine": _MACHINE.search(lines[0])[1],
            "rows": rows}


PARSERS = {"bench": parse_bench, "bench3d": parse_bench3d}


# ---------------------------------------------------------------- page

def render(folder: Path = RESULTS) -> str:
    sources, data = load_results(folder)
    lines = heading("ELASTIC-SPH results", "=")
    lines += ["..", "   Generated by python -m esph.results_page from doc/results/*.json:",
              "   do not edit by hand.", ""]
    lines += paragraph("Every measured figure of the package's documentation: the validation "
                       "against exact and finite-element references, and the speed of the "
                       "solvers.  The page is generated from the JSON files in "
                       "``doc/results/`` by ``python -m esph.results_page``; each section "
                       "names the command that wrote its file.  Timings depend on the machine "
                       "and its load; the errors do not.  The section *Recorded* holds tables "
                       "transcribed from earlier runs whose commands were not rerun for this "
                       "page; it says so for each.  To refresh: run the command, copy its JSON "
                       "into ``doc/results/``, update ``doc/results/sources.json`` and "
                       "regenerate this page (``python/tests/test_results_page.py`` fails while "
                       "page and data disagree; ``doc/Developer.md`` has the details).")
    speed_started = False
    for name, source in sources.items():
        kind = source["kind"]
        if not kind.startswith("validate") and not speed_started:
            lines += heading("Speed", "=")
            speed_started = True
        lines += SECTIONS[kind](name, source, data[name])
    while lines and lines[-1] == "":
        lines.pop()
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m esph.results_page", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--check", action="store_true",
                        help="compare the committed page with the data; exit 1 if they differ")
    parser.add_argument("--results", default=str(RESULTS), help="folder of the JSON files")
    parser.add_argument("--page", default=str(PAGE), help="the page (doc/Results.rst)")
    parser.add_argument("--import", dest="imports", nargs=3, action="append", default=[],
                        metavar=("KIND", "TEXT", "JSON"),
                        help="turn the printed table of a command that writes no JSON (KIND "
                             "bench or bench3d; TEXT its stdout) into JSON, e.g. --import "
                             "bench3d bench3d.txt doc/results/bench3d.json")
    args = parser.parse_args(argv)
    for kind, text, target in args.imports:
        Path(target).write_text(json.dumps(PARSERS[kind](Path(text).read_text()), indent=1))
        print(f"wrote {target}")
    text = render(Path(args.results))
    page = Path(args.page)
    if args.check:
        committed = page.read_text() if page.exists() else ""
        if committed == text:
            return 0
        diff = difflib.unified_diff(committed.splitlines(), text.splitlines(),
                                    f"{page} (committed)", f"{page} (from the data)", lineterm="")
        print(f"{page} differs from what {args.results} gives; regenerate it with "
              "'python -m esph.results_page':", file=sys.stderr)
        print("\n".join(list(diff)[:60]), file=sys.stderr)
        return 1
    page.write_text(text)
    print(f"wrote {page}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The package as a LAMMPS plugin (issue 31): elasticsphplugin.so, built
from the same sources by plugin/CMakeLists.txt, loaded into a plain LAMMPS
of the same tree built with the PLUGIN package (scripts/setup.sh --plugin).
Every style registers; `plugin load`, `clear` and a second input work, and
so does loading from LAMMPS_PLUGIN_PATH; a plugin for another version, a
second load and a style used before the load are clear errors; and the
examples give the in-tree build's numbers."""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from conftest import lattice_2d_script
from esph.paths import EXAMPLES, ROOT, lmp_binary, plugin_route
from esph.runner import mpirun_command, run_mpirun

RESULT = re.compile(r"^RESULT (\S+) (\S+)", re.M)


def block_input(load: str) -> str:
    """A clamped 2d block under its weight, solved by min_style sph/newton:
    every kind of style the plugin brings (atom, pair, fix, compute, command,
    min).  `load` comes first (a plugin load command, or nothing)."""
    return load + lattice_2d_script("0 8 0 4") + """set group all mol 1
set_sph_volumes all lattice 0.001 thickness 0.001 density 1000
pair_style sph/icb 0.0012 plane strain
pair_coeff * * 1e9 0.3
region clampzone block INF 0.002 INF INF INF INF units box
group clamp region clampzone
group body subtract all clamp
fix g body sph/bodyforce 0.0 -1.0e4
fix_modify g energy yes
fix hold clamp setforce 0 0 0
compute probe all sph/probe 0.008 0.002
compute s all sph/elastic/atom stress
thermo_style custom step pe c_probe[1][2]
min_style sph/newton
minimize 0 1e-10 50 500
print "RESULT tip $(c_probe[1][2]:%.16e)"
"""


def launch(cmd: list[str], cwd: Path, env: dict | None = None) -> tuple[int, str]:
    """Run an mpirun command line in cwd with extra environment variables;
    returns (return code, output)."""
    saved = {k: os.environ.get(k) for k in (env or {})}
    os.environ.update(env or {})
    try:
        run = run_mpirun(cmd, cwd, 600)
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
    return run.proc.returncode, run.proc.stdout + run.proc.stderr


def run_host(script: str, tmp_path: Path, nprocs: int = 1, env: dict | None = None,
             lmp: str | None = None) -> tuple[int, str]:
    """Run script with the plain LAMMPS (or `lmp`) under mpirun."""
    host, _ = plugin_route()
    path = tmp_path / "in.case"
    path.write_text(script)
    cmd = mpirun_command(nprocs) + [lmp or host, "-in", path.name,
           "-log", "none", "-nocite", "-echo", "none"]
    return launch(cmd, tmp_path, env)


def results(out: str) -> dict:
    return {k: float(v) for k, v in RESULT.findall(out)}


def package_styles() -> dict:
    """kind -> names of the styles the package's headers declare."""
    styles: dict = {}
    for header in (ROOT / "src" / "ELASTIC-SPH").glob("*.h"):
        for kind, name in re.findall(r"^(\w+)Style\(([^,]+),", header.read_text(), re.M):
            styles.setdefault(kind, set()).add(name)
    return styles


def test_every_style_of_the_package_is_registered(tmp_path):
    """The plugin API's kinds are listed by `plugin list`; the atom and min
    styles, which it cannot register, are usable (the block input uses both)."""
    _, plugin = plugin_route()
    rc, out = run_host(f"plugin load {plugin}\nplugin list\n", tmp_path)
    assert rc == 0, out
    listed = set(re.findall(r"^\s*\d+: (\w+) style plugin (\S+)", out, re.M))
    kinds = {"Pair": "pair", "Fix": "fix", "Compute": "compute", "Command": "command"}
    declared = package_styles()
    for kind, names in declared.items():
        if kind in kinds:
            for name in names:
                assert (kinds[kind], name) in listed, (kind, name, out)
    assert declared["Atom"] == {"sph/elastic"} and declared["Minimize"] == {"sph/newton"}
    rc, out = run_host(block_input(f"plugin load {plugin}"), tmp_path)
    assert rc == 0, out
    assert results(out)["tip"] < 0.0


def test_load_clear_and_a_second_input(tmp_path):
    """`clear` unloads the plugin's styles (and keeps its library mapped for
    the atom and min objects it deletes afterwards); loaded again, the same
    input gives the same answer."""
    _, plugin = plugin_route()
    first = block_input(f"plugin load {plugin}")
    rc, out = run_host(first + "clear\n" + first.replace("RESULT tip", "RESULT tip2"), tmp_path)
    assert rc == 0, out
    values = results(out)
    assert values["tip"] < 0.0 and values["tip2"] == values["tip"]


def test_auto_load_from_the_plugin_path(tmp_path):
    """A folder in LAMMPS_PLUGIN_PATH: no plugin command in the input, and
    the styles come back after `clear`."""
    _, plugin = plugin_route()
    folder = tmp_path / "plugins"
    folder.mkdir()
    (folder / "elasticsphplugin.so").symlink_to(plugin)
    rc, out = run_host(block_input("") + "clear\n" + block_input("").replace("RESULT tip",
                                                                            "RESULT tip2"),
                       tmp_path, env={"LAMMPS_PLUGIN_PATH": str(folder)})
    assert rc == 0, out
    values = results(out)
    assert values["tip"] < 0.0 and values["tip2"] == values["tip"]


def test_a_plugin_for_another_lammps_version_is_refused(tmp_path):
    _, plugin = plugin_route()
    twin = Path(plugin).with_name("wrongversiontestplugin.so")
    assert twin.exists(), "scripts/setup.sh --plugin builds the test twin"
    rc, out = run_host(f"plugin load {twin}\n", tmp_path)
    assert rc != 0
    assert "built for LAMMPS version 1 Jan 2000 but is loaded into LAMMPS version" in out


def test_a_second_load_is_an_error(tmp_path):
    _, plugin = plugin_route()
    rc, out = run_host(f"plugin load {plugin}\nplugin load {plugin}\n", tmp_path)
    assert rc != 0
    assert "Pair style sph/icb exists already: the ELASTIC-SPH plugin is loaded" in out


def test_the_plugin_into_a_lammps_with_the_package_is_an_error(tmp_path):
    """The in-tree build has no PLUGIN package: `plugin` is an unknown
    command there, an error, not a second copy of every style."""
    _, plugin = plugin_route()
    rc, out = run_host(f"plugin load {plugin}\n", tmp_path, lmp=lmp_binary())
    assert rc != 0 and "ERROR" in out


def test_a_style_before_the_load_is_lammps_own_error(tmp_path):
    rc, out = run_host(block_input(""), tmp_path)
    assert rc != 0
    assert "sph/elastic" in out and "ERROR" in out


EXAMPLES_QUICK = [
    ("beam", "in.beam", {"dx": 0.004, "route": "min"}),
    ("lame", "in.lame", {"nw": 6}),
    ("lame", "in.lame", {"nw": 6, "support": "clamp", "side": "outer"}),
    # the fluid coupling, RHEO's fields read by fix sph/fluid's headers only
    ("fsi_gate", "in.fsi_gate", {"T": 0.0005, "file": "/dev/null"}),
]


@pytest.mark.parametrize("nprocs", [1, 2])
@pytest.mark.parametrize("folder,script,variables", EXAMPLES_QUICK)
def test_examples_through_the_plugin_give_the_in_tree_results(folder, script, variables, nprocs,
                                                              tmp_path):
    """The same input through the in-tree lmp and through the plain LAMMPS
    with the plugin (auto-loaded): RESULT values agree to 1e-12."""
    host, plugin = plugin_route()
    plugins = tmp_path / "plugins"
    plugins.mkdir()
    (plugins / "elasticsphplugin.so").symlink_to(plugin)
    args = [a for k, v in variables.items() for a in ("-var", k, str(v))]
    outputs = []
    for lmp, env in ((lmp_binary(), {}), (host, {"LAMMPS_PLUGIN_PATH": str(plugins)})):
        cmd = mpirun_command(nprocs) + [lmp, "-in",
               str(EXAMPLES / folder / script), "-log", "none", "-nocite", "-echo", "none"] + args
        # in the example's folder: inputs include ../common; they write no files
        rc, out = launch(cmd, EXAMPLES / folder, env)
        assert rc == 0, out[-3000:]
        outputs.append(results(out))
    in_tree, through_plugin = outputs
    assert in_tree and set(in_tree) == set(through_plugin)
    for key, value in in_tree.items():
        assert through_plugin[key] == pytest.approx(value, rel=1e-12, abs=1e-300), key

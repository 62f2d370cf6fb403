#!/bin/sh
# Reruns every number in the report; outputs in out_*.txt
# the project venv (scripts/setup.sh); any python with numpy and scipy works
PY=${PY:-python3}
cd "$(dirname "$0")"
$PY sphbeam.py            > out_reproduce.txt      # task 1: reproduces the LAMMPS errors
$PY fe_continuum.py       > out_continuum.txt      # 2D continuum (Q9 FE) reference, load at L or L-dx/2
$PY fe_modes.py           > out_fe_modes.txt       # continuum natural frequencies
$PY exp_fit.py            > out_fit.txt            # (a) EI_eff from pure moment
$PY exp_clamp.py          > out_clamp.txt          # (c) clamp energy on/off, 1..5 clamp columns
$PY exp_modal.py          > out_modal.txt          # (e) static share of hourglass-like modes
$PY decompose.py 4 > out_decompose.txt; $PY decompose.py 2 >> out_decompose.txt; $PY decompose.py 1 >> out_decompose.txt
$PY variants.py           > out_variants.txt       # clamp x row-weight variants
$PY exp_clampvariants.py  > out_clampvariants.txt  # all clamp treatments + spectra
$PY exp_stability.py      > out_stability.txt      # lowest modes, free-free null space
$PY exp_freefree_alt.py   > out_freefree_alt.txt
$PY exp_spurious.py 2     > out_spurious.txt
$PY exp_patch.py          > out_patch.txt          # patch tests
$PY exp_hg_quadratic.py   > out_hg_quadratic.txt
$PY hourglass.py          > out_hourglass.txt      # mirror clamp + existing hourglass keyword

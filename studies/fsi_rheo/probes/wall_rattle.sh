#!/usr/bin/env bash
# studies/fsi_rheo 9.9: the lone particle on RHEO's floor (in.wall_rattle,
# RHEO alone) against the step, and films on a floor with fix sph/fluid's
# choices (in.film_fsi).  Output: out_wall_rattle.txt.  One rank each.
#   source scripts/common.sh && esph_env && studies/fsi_rheo/probes/wall_rattle.sh
set -u
cd "$(dirname "$0")"
out=out_wall_rattle.txt
lmp() { mpirun -np 1 "$ESPH_LMP" -log none -nocite "$@" 2>&1; }
{
  echo "# in.wall_rattle: lone particle at rest, every 500 steps: step time ke max(vy) min(vy) min(y) max(y) max(rho)"
  for f in 0.1 0.05 0.025; do
    n=$(python3 -c "print(int(round(3000*0.1/$f)))")
    echo "## dtfac $f"
    lmp -in in.wall_rattle -var vx 0 -var dtfac "$f" -var nsteps "$n" |
      awk '/^ +[0-9]+ +[0-9.e-]+ /{print} /ERROR/{print}'
  done
  echo "## interface none (no reconstruction)"
  lmp -in in.wall_rattle -var vx 0 -var interface "" -var nsteps 3000 |
    awk '/^ +[0-9]+ +[0-9.e-]+ /{print} /ERROR/{print}'
  echo "# in.film_fsi: film of nl layers at U, after each 1000 steps: step, mean vx, max |vy|"
  for kw in "pressure/density half" "pressure/density full" "interface/visc 1.0"; do
    for U in 0 0.3 1.0; do
      for nl in 1 3; do
        printf '## %s U %s layers %s: ' "$kw" "$U" "$nl"
        lmp -in in.film_fsi -var kw "$kw" -var nl "$nl" -var U "$U" |
          awk '/^ +[0-9]+ +[-0-9.e]+ /{if ($1 % 1000 == 0) printf "%d %.4g %.3g; ", $1, $2, ($3 > -$4 ? $3 : -$4)}
               /ERROR/{printf "%s", $0}'
        echo
      done
    done
  done
} >"$out"

#!/usr/bin/env bash
# Run the RHEO probes of studies/fsi_rheo/README.md ("Measured probes") on
# one core each and print their summaries. Needs the in-tree build with RHEO
# (scripts/setup.sh). About 30 minutes in all on one core; each group can be
# run alone:
#
#   studies/fsi_rheo/probes/run.sh [a|stab|dt|mass|c|d|e|all] [OUTDIR]
#
# OUTDIR (default /tmp/fsi_rheo_probes) gets the logs and profiles.
source "$(dirname "${BASH_SOURCE[0]}")/../../../scripts/common.sh"
esph_env
set +e
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
what=${1:-all}
out=${2:-/tmp/fsi_rheo_probes}
mkdir -p "$out"
cd "$here"
lmp1() { mpirun -np 1 lmp "$@"; }

hydro() { # tag, then variables
  local tag=$1; shift
  lmp1 -in in.hydrostatic -var out "$out" -var tag "$tag" "$@" -log "$out/hydro.$tag.log" >/dev/null 2>&1
  echo "== hydrostatic $tag: $*"
  if grep -q "^PROBE_END" "$out/hydro.$tag.log"; then
    python3 analyze.py hydro "$out/hydro.$tag.log" "$out/profile.$tag.txt"
  else
    grep -E "^ERROR|Lost atoms" "$out/hydro.$tag.log" | head -2
    grep -E "^ +[0-9]+ +[0-9.e+-]+ " "$out/hydro.$tag.log" | tail -2
  fi
}

if [ "$what" = a ] || [ "$what" = all ]; then
  # a: reconstruction on (the study's choice); b: off, walls at rho0 or hydrostatic
  hydro recon1 -var recon 1 -var init hyd
  hydro recon0 -var recon 0 -var init hyd
  hydro recon0_wallhyd -var recon 0 -var init hyd -var wallrho hyd
  # settling from a uniform density (no hydrostatic start)
  hydro recon1_uniform -var recon 1 -var init uniform -var T 1.0
  hydro recon0_uniform -var recon 0 -var init uniform -var T 1.0
fi
if [ "$what" = stab ] || [ "$what" = all ]; then
  # a's runs with reconstruction go unstable after about 0.35 s: RHEO's own
  # stabilisers (its examples: shift, RK1 with rho/damp 0.1 cut c, zeta 1,
  # rho/sum), 1 s each
  D=$(python3 -c "print(0.1*0.03*10*(9.81*0.3)**0.5)")
  hydro stab_shift -var recon 1 -var init hyd -var shift 1 -var T 1.0
  hydro stab_RK1 -var recon 1 -var init hyd -var kernel RK1 -var T 1.0
  hydro stab_RK1_damp -var recon 1 -var init hyd -var kernel RK1 -var damp "$D" -var T 1.0
  hydro stab_zeta1 -var recon 1 -var init hyd -var zeta 1.0 -var T 1.0
  hydro stab_rhosum -var recon 1 -var init uniform -var rhosum 1 -var T 1.0
  hydro stab_recon0_wallhyd -var recon 0 -var init hyd -var wallrho hyd -var T 2.0
  hydro stab_zeta1_2s -var recon 1 -var init hyd -var zeta 1.0 -var T 2.0
  hydro stab_zeta1_uniform -var recon 1 -var init uniform -var zeta 1.0 -var T 1.0
fi
if [ "$what" = dt ] || [ "$what" = all ]; then
  # the stable step: dt = dtf (cut/3)/c, RHEO's examples use dtf = 0.1
  for r in 1 0; do
    for f in 0.2 0.4 0.8 1.2; do
      hydro "dt${f}_recon$r" -var recon $r -var init hyd -var dtf $f -var T 0.2
    done
  done
fi
if [ "$what" = mass ] || [ "$what" = all ]; then
  # study items 2 and 3: walls heavier than the fluid (a denser solid)
  hydro mass1_rm0 -var recon 1 -var init hyd -var mw 1 -var rm 0 -var T 0.2
  hydro mass1_rm1 -var recon 1 -var init hyd -var mw 1 -var rm 1 -var T 0.2
  hydro mass1_rw1.1_rm0 -var recon 1 -var init hyd -var mw 1 -var rw 1.1 -var rm 0 -var T 0.2
  for mw in 1.1 2.7; do
    hydro "mass${mw}_rm0" -var recon 1 -var init hyd -var mw $mw -var rm 0 -var T 0.2
    hydro "mass${mw}_rm1" -var recon 1 -var init hyd -var mw $mw -var rm 1 -var T 0.2
    # the solid type's rest density = its own (fix rheo density): volume m/rho right
    hydro "mass${mw}_rw_rm0" -var recon 1 -var init hyd -var mw $mw -var rw $mw -var rm 0 -var T 0.2
    hydro "mass${mw}_rw_rm1" -var recon 1 -var init hyd -var mw $mw -var rw $mw -var rm 1 -var T 0.2
    # the same without atom sorting (fix_rheo_pressure.cpp:201 then gives each
    # atom its own type's EOS on one rank)
    hydro "mass${mw}_rw_nosort_rm0" -var recon 1 -var init hyd -var mw $mw -var rw $mw -var rm 0 -var sort 0 -var T 0.2
    hydro "mass${mw}_rw_nosort_rm1" -var recon 1 -var init hyd -var mw $mw -var rw $mw -var rm 1 -var sort 0 -var T 0.2
  done
  hydro mass1_rw1.1_nosort_rm0 -var recon 1 -var init hyd -var mw 1 -var rw 1.1 -var rm 0 -var sort 0 -var T 0.2
fi
if [ "$what" = c ] || [ "$what" = all ]; then
  # Galilean pairs: each line's cases differ only by the frame
  U=0.1
  for r in 1 0; do
    for rs in 0 1; do
      [ $r = 0 ] && [ $rs = 1 ] && continue
      for case in "still" "tang_whole -var uwx $U -var ufx $U" "norm_whole -var uwy $U -var ufy $U" \
                  "tang_wall -var uwx $U" "tang_frame -var ufx -$U" \
                  "norm_wall -var uwy $U" "norm_frame -var ufy -$U"; do
        set -- $case; name=$1; shift
        log="$out/gal.r$r.s$rs.$name.log"
        lmp1 -in in.galilean -var recon $r -var rhosum $rs "$@" -log "$log" >/dev/null 2>&1
      done
      # each case against its Galilean twin
      for pair in "tang_whole still" "norm_whole still" "tang_wall tang_frame" "norm_wall norm_frame"; do
        set -- $pair
        printf '== galilean recon %s rhosum %s %s vs %s: ' $r $rs $1 $2
        python3 analyze.py gal "$out/gal.r$r.s$rs.$1.log" "$out/gal.r$r.s$rs.$2.log"
      done
    done
  done
  # the box moving along its walls without physical viscosity (eta 0), and
  # without artificial viscosity (zeta 0), against the still box
  lmp1 -in in.galilean -var eta 0 -log "$out/gal.still.eta0.log" >/dev/null 2>&1
  lmp1 -in in.galilean -var zeta 0 -log "$out/gal.still.zeta0.log" >/dev/null 2>&1
  for v in eta zeta; do
    lmp1 -in in.galilean -var $v 0 -var uwx 0.1 -var ufx 0.1 -log "$out/gal.tang_whole.${v}0.log" >/dev/null 2>&1
    printf '== galilean recon 1 rhosum 0 %s 0: tang_whole vs still: ' $v
    python3 analyze.py gal "$out/gal.tang_whole.${v}0.log" "$out/gal.still.${v}0.log"
  done
  # the tangential part alone: viscous (zeta 0), against eta and U
  for v in "1e-3 0.1" "1e-2 0.1" "1e-3 0.2"; do
    set -- $v
    log="$out/gal.visc.eta$1.U$2.log"
    lmp1 -in in.galilean -var zeta 0 -var eta $1 -var uwx $2 -var ufx $2 -log "$log" >/dev/null 2>&1
    printf '== galilean recon 1, zeta 0, eta %s, tang_whole U %s: ' $1 $2
    grep -E "^ +[0-9]+ +[0-9.e+-]+ " "$log" | sed -n 2p |
      awk -v eta=$1 -v U=$2 '{printf "Fx_bot at step %s = %.4g N/m = eta U L / (%.3f dx)\n",$1,$3,eta*U*0.2/$3/0.01}'
  done
fi
if [ "$what" = d ] || [ "$what" = all ]; then
  for rm in 1 0; do
    for m in "1 2" "2 1" "1 1" "2 2"; do
      set -- $m
      lmp1 -in in.jmass_pair -var rm $rm -var m1 $1 -var m2 $2 -log none 2>&1 | grep PROBE_D1
    done
  done
  for rm in 0 1; do
    for nw in off on; do
      for np in 1 2; do
        log="$out/mom.rm$rm.$nw.np$np.log"
        mpirun -np $np lmp -in in.jmass_momentum -var rm $rm -var mr 1.1 -var newt $nw -log "$log" >/dev/null 2>&1
        printf '== momentum rm %s newton %s np %s: ' $rm $nw $np
        if grep -q PROBE_D2 "$log"; then grep PROBE_D2 "$log" | tail -1
        else
          grep -m1 -E '^ERROR' "$log"
          grep -E '^ +[0-9]+ +[0-9.e+-]+ ' "$log" |
            awk '{printf "   step %s: Px %s Py %s sum|p| %s Px/sum|p| %s\n",$1,$2,$3,$4,$5}'
        fi
      done
    done
  done
fi
if [ "$what" = e ] || [ "$what" = all ]; then
  for s in 1 2 3 4; do
    log="$out/hybrid.stage$s.log"
    lmp1 -in in.hybrid_icb -var stage $s -log "$log" >/dev/null 2>&1
    echo "== hybrid stage $s"
    grep -E "^PROBE_E|^ERROR" "$log"
  done
fi

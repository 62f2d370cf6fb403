#!/usr/bin/env bash
# The elastic gate's tip at 0.041 s (Table 10 quick) under changes of the
# numerical and material settings, one at a time: does the early lead over
# the experiment and the peers come from our discretisation or from what is
# modelled?  README section 9.2.  Each case runs examples/fsi_gate on one
# core, 2 to 12 minutes (dx100 about 40).
#
#   studies/fsi_rheo/probes/gate_sensitivity.sh [run|summary] [OUTDIR]
#
# run (the default) runs the cases into OUTDIR (default /tmp/gate_sensitivity)
# and prints the summary; summary only prints it from OUTDIR's logs.
# CONTINUITY=rheo|body (environment) sets fix sph/fluid continuity in every
# case (default body, the example's; out_gate_sensitivity.txt was measured
# before the keyword existed, as rheo; out_gate_sensitivity_body.txt with
# body).
source "$(dirname "${BASH_SOURCE[0]}")/../../../scripts/common.sh"
esph_env
set +e
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
gate="$here/../../../examples/fsi_gate/in.fsi_gate"
what=${1:-run}
out=${2:-/tmp/gate_sensitivity}
mkdir -p "$out"
# name, then the -var settings (rhosum: fix rheo with rho/sum, its density
# by summation instead of the continuity equation)
cases=(
  "base"
  "c20 -var cfac 20"
  "dx125 -var dx 0.00125"
  "dx100 -var dx 0.001"
  "E24 -var E 24e6"
  "rho2 -var rhos 2200"
  "rhosum"
)
if [ "$what" = run ]; then
  sed 's|quintic 0 interface/reconstruct|quintic 0 interface/reconstruct rho/sum|' "$gate" \
    > "$out/in.fsi_gate.rhosum"
  cp "$gate" "$out/in.fsi_gate"
  for c in "${cases[@]}"; do
    read -r name vars <<< "$c"
    input="$out/in.fsi_gate"
    [ "$name" = rhosum ] && input="$out/in.fsi_gate.rhosum"
    (cd "$out" && mpirun -np 1 lmp -in "$input" -log "log.$name" -screen none \
       -var T 0.041 -var file "tip.$name" -var continuity "${CONTINUITY:-body}" $vars \
       > /dev/null 2>&1)
  done
fi
printf '%-7s %-24s %12s %12s %9s %8s\n' case settings "ux(0.041)[mm]" "uy[mm]" "loop[s]" steps
for c in "${cases[@]}"; do
  read -r name vars <<< "$c"
  log="$out/log.$name"
  [ -f "$log" ] || continue
  ux=$(awk '/^RESULT ux1 /{printf "%.3f", $3*1000}' "$log")
  uy=$(awk '/^RESULT uy1 /{printf "%.3f", $3*1000}' "$log")
  loop=$(awk '/^Loop time of/{t=$4} END{print t}' "$log")
  steps=$(awk '/^RESULT steps /{print $3}' "$log")
  [ "$name" = rhosum ] && vars="fix rheo ... rho/sum"
  printf '%-7s %-24s %12s %12s %9s %8s\n' "$name" "${vars:--}" "${ux:-(none)}" "${uy:-}" "${loop:-}" "${steps:-}"
done

#!/bin/bash
# Tip error of examples/beam against the FE continuum for hourglass
# coefficients alpha (Fy = -10 N, plane stress), with the defaults
# otherwise.  Run from the repository root after scripts/setup.sh.
source scripts/common.sh; esph_env; set +e +o pipefail
cd examples/beam
ref() { python -c "from esph import fe; print(fe.tip('beam', -10.0, $1, $2, 'stress')['dv'])"; }
for nu in 0.0 0.3; do for dx in 0.004 0.002 0.001; do
  r=$(cd ../../python && ref $dx $nu)
  for hg in 0.0 0.1 0.2 0.3 0.5; do
    v=$(lmp -in in.beam -var Fy -10 -var nu $nu -var dx $dx -var hg $hg -log none 2>&1 | awk '/RESULT tip_dv/{print $3}')
    python -c "print('nu $nu dx $dx hg $hg: %+.4f %%' % (($v / $r - 1) * 100))"
  done
done; done

#!/usr/bin/env bash
# OpenBLAS's own kernels against hencky's restart with OPENBLAS_CORETYPE (linalg/blas_kernels.hpp):
# each case of bench/work/ named below (made by run_plastic_bench.py --sizes 10000,30000,100000
# and run_contact_bench.py --sizes 10000,30000,60000) run with HENCKY_BLAS_KERNELS=keep, then
# with the default. Prints: case, mode, kernels, wall s, peak MiB, factorization s,
# its GFLOP/s, iterations, factorizations. Usage: bash bench/run_blas_kernels.sh [HENCKY]
bin="$(readlink -f "${1:-build/hencky}")"
cd "$(dirname "$0")/work" || exit 1
for c in plastic-ring-l2_h0.01393/case-perfect-newton.yaml plastic-ring-l2_h0.007897/case-perfect-newton.yaml plastic-ring-l2_h0.004259/case-perfect-newton.yaml plastic-ring-l2_h0.004259/case-perfect-initial-stress+auto.yaml contact-hertz-L100a_h0.0005465/case.yaml contact-hertz-L100a_h0.0001482/case.yaml contact-hertz-L100a_h9.132e-05/case.yaml; do
  for mode in keep auto; do
    o=/tmp/ab_out; rm -rf $o
    /usr/bin/time -f "%e %M" -o /tmp/ab_time env HENCKY_BLAS_KERNELS=$mode "$bin" run $c -o $o --quiet
    read wall kb < /tmp/ab_time
    /usr/bin/python3 -c "
import json; s=json.load(open('$o/summary.json')); ls=s['linear_solver']
print('$c', '$mode', ls.get('blas_kernels'), '$wall', round($kb/1024),  round(s['wall_seconds']['factorization'],2), round(ls.get('factor_gflops_per_second',0),1), s['iterations'], s['factorizations'])"
  done
done

#!/usr/bin/env bash
# Issue 3's hardware checks in one prepared command, for a session that is lent a GPU (the `device` tool).
# Each stage has its own time limit, cut to what is left of DEADLINE seconds (default 560) since the
# start, so one that hangs or fails leaves the others' results; every result lands in $OUT (at most 8
# files come back). Here, first: bash benchmarks/device/fetch_wheels.sh
# Then, through the device tool, from the repository root (carry [".whl"], timeout_s 600):
#     bash benchmarks/device/check.sh                  # info bench par cpu: 5 minutes on an H200
#     bash benchmarks/device/check.sh bench            # or some of: info bench tests seed par cpu rip
# Stages:
#   info   GPU, driver, Python/Numba/numba-cuda versions, a one-kernel smoke test (tries CUDA_HOME=
#          /usr/local/cuda and nvJitLink when the default NVVM fails, and keeps what works), `shoal info`
#                                                                                        -> $OUT/info.txt
#   bench  the DualSPHysics 3D dam break (bench_dambreak.py --backend cuda, float32) at 0.89M, 4.2M
#          and 20.8M particles: particle-steps/s, compile s, device_bytes_per_particle -> $OUT/bench.jsonl
#   tests  the CUDA parity and grid tests on the hardware (8 xdist workers)              -> $OUT/tests.log
#   seed   the seed cases with --backend cuda at the papers' resolutions, short runs: the tidal bore at
#          dp = 5 mm (3D, half width with the symmetry plane, 580k particles) and the rip-current basin
#          at dp = 0.02 m (4.15M particles)                                              -> $OUT/seed.log
#   par    tests and seed at once (neither is timed; the GPU and 16 cores are shared)
#   cpu    the same dam break on the CPU backend with all the machine's cores, ~1M particles, for the
#          speed-up on one node                                                          -> $OUT/bench.jsonl
#   spheric  issue 34 must-show 1: SPHERIC Test 2 as the cross-code benchmark runs it (bench_dambreak.py --case
#          spheric-benchmark, float32) at dp = 6 mm (4,993,539 particles), 2,000 steps from t = 0.5 s (run from
#          rest first, in the same process; DualSPHysics 5.4: 14.52 ms a step on an H100 SXM) -> $OUT/bench.jsonl
#   regs   the same case from rest, 300 steps, with the rates kernel's registers capped (SHOAL_CUDA_MAX_REGISTERS
#          unset, 80, 64, 48; ptxas's report of each: benchmarks/rates_registers.py)      -> $OUT/bench.jsonl
#   rip    issue 6 item 5: the rip-current validation run (validation/rip-current/run.py) at RIP_DP
#          (default 0.04 m: 437,262 particles, 36,571 steps to t = 22.5 s, 1.6e10 particle-steps; 0.03 m:
#          896,148 and 48,761, 4.4e10) on the GPU within RIP_LIMIT s (default 480), then its analysis
#          -> $OUT/rip.log, results.json, meanflow_current.png, meanflow_setup.png (not in the default set)
# Environment: OUT (results folder, default runs/device), DEADLINE (s, default 560), PY (the Python, default
# python3). Without a GPU, `NUMBA_ENABLE_CUDASIM=1 PY=.venv/bin/python OUT=/tmp/x bash benchmarks/device/check.sh
# info` runs the info stage on Numba's CUDA simulator (the smoke kernel passes, nvidia-smi is missing): the
# smoke test of tests/test_scripts_smoke.py.
set -u
OUT=${OUT:-runs/device}
DEADLINE=${DEADLINE:-560}
mkdir -p "$OUT"
stages=("$@"); [ ${#stages[@]} -eq 0 ] && stages=(info bench par cpu)
for s in "${stages[@]}"; do
  case $s in info|bench|tests|seed|par|cpu|spheric|regs|rip) ;;
  *) echo "check.sh: unknown stage '$s'; allowed: info bench tests seed par cpu spheric regs rip" >&2; exit 2 ;; esac
done
export PYTHONUNBUFFERED=1
if [ -d .whl ] && [ ! -e /tmp/site/.shoal-wheels ]; then
    python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
        || { echo "check.sh: the carried wheels did not install" | tee -a "$OUT/info.txt"; exit 2; }
    touch /tmp/site/.shoal-wheels
fi
if [ -d /tmp/site ]; then export PATH=/tmp/site/bin:$PATH PYTHONPATH=/tmp/site; fi
# numba-cuda 0.30.4 needs numpy.row_stack, which NumPy 2.5 removed (shoal restores it on import; this is
# for the smoke test, which imports numba.cuda alone)
mkdir -p /tmp/compat && printf 'import numpy\nif not hasattr(numpy, "row_stack"):\n    numpy.row_stack = numpy.vstack\n' \
    > /tmp/compat/sitecustomize.py && export PYTHONPATH=/tmp/compat${PYTHONPATH:+:$PYTHONPATH}
export PYTHONPATH=$PWD/src${PYTHONPATH:+:$PYTHONPATH}
PY=${PY:-python3}  # the Python that runs each stage (tests/test_scripts_smoke.py names the venv's)
stamp() { echo "== $(date -u +%H:%M:%S) t=${SECONDS}s $*"; }
# limit L: L seconds, or what is left before the deadline (at least 5)
limit() { local left=$((DEADLINE - SECONDS)); [ "$left" -lt 5 ] && left=5; [ "$1" -lt "$left" ] && echo "$1" || echo "$left"; }
smoke() {  # compile and launch one kernel; prints OK on success
  timeout 90 $PY - <<'PYEOF'
import numpy as np
from numba import cuda
@cuda.jit
def k(a):
    i = cuda.grid(1)
    if i < a.size:
        a[i] = np.float32(2.0) * i
try:
    a = cuda.device_array(1000, dtype=np.float32)
    k[8, 128](a)
    assert a.copy_to_host()[999] == 1998.0
except Exception as exc:
    print("smoke failed:", type(exc).__name__, str(exc).strip().splitlines()[-1:])
    raise SystemExit(1)
print("SMOKE OK")
PYEOF
}
bench() {  # dp steps limit [backend threads]; BENCH_ARGS: more arguments of bench_dambreak.py
  local be=${4:-cuda} extra=()
  [ "$be" = cpu ] && extra=(--threads "$5")
  local more=(); read -r -a more <<< "${BENCH_ARGS:-}"; extra+=("${more[@]}")
  stamp "bench $be dp=$1 steps=$2 ${BENCH_ARGS:-} ${SHOAL_CUDA_MAX_REGISTERS:+max_registers=$SHOAL_CUDA_MAX_REGISTERS}"
  timeout "$(limit "$3")" $PY benchmarks/bench_dambreak.py --backend "$be" --dp "$1" --steps "$2" --precision float32 \
    "${extra[@]}" > "$OUT/bench_one.json" 2> "$OUT/bench_err_$1.txt"
  local rc=$?
  if [ $rc -eq 0 ]; then $PY -c "import json,sys; print(json.dumps(json.load(open(sys.argv[1]))))" \
       "$OUT/bench_one.json" | tee -a "$OUT/bench.jsonl"; rm -f "$OUT/bench_err_$1.txt"
  else echo "{\"backend\": \"$be\", \"dp\": $1, \"failed\": $rc}" | tee -a "$OUT/bench.jsonl"; tail -5 "$OUT/bench_err_$1.txt"; fi
  rm -f "$OUT/bench_one.json"
}
tests() {
  stamp tests
  timeout "$(limit "${1:-300}")" $PY -m pytest tests/test_cuda_parity.py tests/test_cuda_grid.py -q -rs -n 8 \
      -p no:cacheprovider > "$OUT/tests.log" 2>&1
  echo "pytest exit $?" >> "$OUT/tests.log"
}
seed() {
  local each=${1:-150}
  { stamp "seed tidal-bore dp=0.005 half width to 0.1 s";
    timeout "$(limit "$each")" $PY -m shoal run tidal-bore --backend cuda --dp 0.005 --half --end-time 0.1 \
        --no-progress --no-plot --out /tmp/seed-bore --overwrite; echo "exit $?"; tail -3 /tmp/seed-bore/run.log 2>/dev/null
    stamp "seed rip-current dp=0.02 to 0.05 s";
    timeout "$(limit "$each")" $PY -m shoal run rip-current --backend cuda --dp 0.02 --end-time 0.05 --no-progress \
        --no-plot --out /tmp/seed-rip --overwrite; echo "exit $?"; tail -3 /tmp/seed-rip/run.log 2>/dev/null
    stamp "seed done"
  } > "$OUT/seed.log" 2>&1
}
for s in "${stages[@]}"; do
  case $s in
  info)
    { stamp info; nvidia-smi; $PY -c "import sys, numba, numba_cuda, numpy; print(sys.version); print('numba', numba.__version__, 'numba-cuda', numba_cuda.__version__, 'numpy', numpy.__version__)";
      ls -d /usr/local/cuda*/nvvm 2>/dev/null
      if smoke; then echo "smoke: default NVVM works"
      elif CUDA_HOME=/usr/local/cuda smoke; then export CUDA_HOME=/usr/local/cuda; echo "smoke: works with CUDA_HOME=/usr/local/cuda"
      elif CUDA_HOME=/usr/local/cuda NUMBA_CUDA_ENABLE_PYNVJITLINK=1 smoke; then
        export CUDA_HOME=/usr/local/cuda NUMBA_CUDA_ENABLE_PYNVJITLINK=1; echo "smoke: works with CUDA_HOME and nvJitLink"
      else echo "smoke: FAILED every way"; fi
      timeout 120 $PY -m shoal info; } > "$OUT/info.txt" 2>&1
    tail -22 "$OUT/info.txt"
    ;;
  bench)
    # dp for 0.89M, 4.2M and 20.8M particles; steps; time limit [s] (on an H200, 2026-12-04: 17, 29 and 90 s,
    # the last mostly the host's setup; results in benchmarks/device/RESULTS.md)
    bench 0.00475 200 90; bench 0.00278 200 120; bench 0.0016 50 200 ;;
  cpu)
    bench 0.00475 20 120 cpu "$(nproc)" ;;
  spheric)
    BENCH_ARGS="--case spheric-benchmark --developed-from 0.5" bench 0.006 2000 420 ;;
  regs)
    for r in 0 80 64 48; do SHOAL_CUDA_MAX_REGISTERS=$r BENCH_ARGS="--case spheric-benchmark" bench 0.006 300 100; done ;;
  tests)
    tests 300; tail -15 "$OUT/tests.log" ;;
  seed)
    seed 150; tail -20 "$OUT/seed.log" ;;
  par)
    tests 240 & seed 120; wait; tail -12 "$OUT/tests.log"; tail -14 "$OUT/seed.log" ;;
  rip)
    { stamp "rip-current dp=${RIP_DP:-0.04}";
      timeout "${RIP_LIMIT:-480}" $PY validation/rip-current/run.py --out /tmp/rip --dp "${RIP_DP:-0.04}" \
          --backend cuda --overwrite; echo "run exit $?"; tail -4 /tmp/rip/run.log 2>/dev/null
      stamp analyse; timeout 120 $PY validation/rip-current/analyse.py /tmp/rip --out "$OUT"; echo "analyse exit $?"
    } > "$OUT/rip.log" 2>&1
    tail -30 "$OUT/rip.log" ;;
  esac
done
stamp "check.sh done"

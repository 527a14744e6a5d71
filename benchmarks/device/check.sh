#!/usr/bin/env bash
# Issue 3's hardware checks in one prepared command, for a session that is lent a GPU (the `device` tool).
# Each stage has its own time limit, so one that hangs or fails leaves the others' results; every result
# lands in $OUT (at most 8 files come back). Here, first: bash benchmarks/device/fetch_wheels.sh
# Then, through the device tool, from the repository root (carry [".whl"], timeout_s 600):
#     bash benchmarks/device/check.sh                  # all stages, about 9 minutes
#     bash benchmarks/device/check.sh bench            # or some of: info bench tests seed
# Stages:
#   info   GPU, driver, Python/Numba/numba-cuda versions, `shoal info`                -> $OUT/info.txt
#   bench  the DualSPHysics 3D dam break (bench_dambreak.py --backend cuda, float32) at about
#          1M, 5M and 20M particles: particle-steps/s, compile s, device_bytes_per_particle -> $OUT/bench.jsonl
#   tests  the CUDA parity, grid and MPI tests on the hardware                          -> $OUT/tests.log
#   seed   the seed cases with --backend cuda: the tidal bore at the paper's dp = 5 mm (3D) and the
#          rip-current basin at the paper's dp = 0.02 m (4.1M particles), short runs      -> $OUT/seed.log
#   rip    issue 6 item 5: the rip-current validation run (validation/rip-current/run.py) at RIP_DP
#          (default 0.04 m: 437,262 particles, 36,571 steps to t = 22.5 s, 1.6e10 particle-steps; 0.03 m:
#          896,148 and 48,761, 4.4e10) on the GPU within RIP_LIMIT s (default 480), then its analysis
#          -> $OUT/rip.log, results.json, meanflow_current.png, meanflow_setup.png (not in the default set)
set -u
OUT=${OUT:-runs/device}
mkdir -p "$OUT"
stages=("$@"); [ ${#stages[@]} -eq 0 ] && stages=(info bench tests seed)
for s in "${stages[@]}"; do
  case $s in info|bench|tests|seed|rip) ;;
  *) echo "check.sh: unknown stage '$s'; allowed: info bench tests seed rip" >&2; exit 2 ;; esac
done
export PYTHONUNBUFFERED=1
if [ -d .whl ]; then
    python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl \
        || { echo "check.sh: the carried wheels did not install" | tee -a "$OUT/info.txt"; exit 2; }
    export PATH=/tmp/site/bin:$PATH
    export PYTHONPATH=/tmp/site
fi
export PYTHONPATH=$PWD/src${PYTHONPATH:+:$PYTHONPATH}
PY=python3
stamp() { echo "== $(date -u +%H:%M:%S) $*"; }
for s in "${stages[@]}"; do
  case $s in
  info)
    { stamp info; nvidia-smi; $PY -c "import sys, numba, numba_cuda, numpy; print(sys.version); print('numba', numba.__version__, 'numba-cuda', numba_cuda.__version__, 'numpy', numpy.__version__)";
      timeout 120 $PY -m shoal info; } > "$OUT/info.txt" 2>&1
    tail -25 "$OUT/info.txt" ;;
  bench)
    # dp for about 1M, 5M and 20M particles (173,531 at dp = 0.0085 m; N ~ dp^-3); steps, time limit [s]
    for spec in "0.00475 200 100" "0.00278 200 150" "0.00175 100 240"; do
      set -- $spec
      stamp "bench dp=$1 steps=$2"
      timeout "$3" $PY benchmarks/bench_dambreak.py --backend cuda --dp "$1" --steps "$2" --precision float32 \
        > "$OUT/bench_one.json" 2> "$OUT/bench_err.txt"
      rc=$?
      if [ $rc -eq 0 ]; then $PY -c "import json,sys; print(json.dumps(json.load(open(sys.argv[1]))))" \
           "$OUT/bench_one.json" | tee -a "$OUT/bench.jsonl"
      else echo "{\"dp\": $1, \"failed\": $rc}" | tee -a "$OUT/bench.jsonl"; tail -5 "$OUT/bench_err.txt"; fi
    done
    rm -f "$OUT/bench_one.json" ;;
  tests)
    stamp tests
    timeout 300 $PY -m pytest tests/test_cuda_parity.py tests/test_cuda_grid.py tests/test_mpi_cuda.py -q -rs \
        -p no:cacheprovider > "$OUT/tests.log" 2>&1
    echo "pytest exit $?" | tee -a "$OUT/tests.log"; tail -15 "$OUT/tests.log" ;;
  seed)
    { stamp "seed tidal-bore dp=0.005 3D to 0.3 s";
      timeout 150 $PY -m shoal run tidal-bore --backend cuda --dp 0.005 --end-time 0.3 --no-progress --no-plot \
          --out /tmp/seed-bore --overwrite; echo "exit $?"; tail -3 /tmp/seed-bore/run.log 2>/dev/null
      stamp "seed rip-current dp=0.02 to 0.05 s";
      timeout 150 $PY -m shoal run rip-current --backend cuda --dp 0.02 --end-time 0.05 --no-progress --no-plot \
          --out /tmp/seed-rip --overwrite; echo "exit $?"; tail -3 /tmp/seed-rip/run.log 2>/dev/null
    } > "$OUT/seed.log" 2>&1
    tail -20 "$OUT/seed.log" ;;
  rip)
    { stamp "rip-current dp=${RIP_DP:-0.04}";
      timeout "${RIP_LIMIT:-480}" $PY validation/rip-current/run.py --out /tmp/rip --dp "${RIP_DP:-0.04}" \
          --backend cuda --overwrite; echo "run exit $?"; tail -4 /tmp/rip/run.log 2>/dev/null
      stamp analyse; timeout 120 $PY validation/rip-current/analyse.py /tmp/rip --out "$OUT"; echo "analyse exit $?"
    } > "$OUT/rip.log" 2>&1
    tail -30 "$OUT/rip.log" ;;
  esac
done

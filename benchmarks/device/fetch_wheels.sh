#!/usr/bin/env bash
# Fetch, on this (networked) machine, the wheels that shoal needs and the lent GPU machine's image lacks
# (its package list: /work/.library/device/KINDS.md; it has numba, numba-cuda, numpy, scipy, h5py, xarray,
# matplotlib, rich, markdown-it-py, mpi4py, pytest, pytest-xdist, hypothesis, but not these). The device
# runs Python 3.12 on x86-64 and reaches no registry, so the wheels travel in the ignored folder .whl/
# (name it in the run's `carry`). Usage, from the repository root:
#     bash benchmarks/device/fetch_wheels.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
grep -qx '/.whl/' .git/info/exclude 2>/dev/null || echo '/.whl/' >> .git/info/exclude
rm -rf .whl && mkdir -p .whl
plat=(--platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64
      --platform manylinux2014_x86_64 --platform manylinux1_x86_64 --platform any)
get() { python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
        "${plat[@]}" -d .whl "$@"; }
# pydantic and its compiled core (the core's version must be the one pydantic pins)
get "pydantic==2.12.5" "pydantic-core==2.41.5" "annotated-types==0.7.0" "typing-inspection==0.4.2"
get "meshio==5.3.5" "numpy-stl==3.2.0" "python-utils==3.9.1" "tomli-w==1.2.0"
# MPICH's wheel brings mpiexec for tests/test_mpi_cuda.py (mpi4py is on the image)
get "mpich==4.3.2" || echo "fetch_wheels: no mpich wheel; tests/test_mpi_cuda.py will skip on the device" >&2
ls -la .whl
du -sh .whl

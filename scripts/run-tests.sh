#!/usr/bin/env bash
# Sets up pomlab on a fresh Debian machine and runs every check CI runs:
# the formatting check, the ctest suite, the suite again under
# AddressSanitizer + UndefinedBehaviorSanitizer, the two fuzz targets for a
# short fixed time (clang's libFuzzer, docs/fuzzing.md) and the MPI build's
# 2-rank study compared with the threaded one.
# Usage: bash scripts/run-tests.sh
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh -DPOM_WERROR=ON

echo "== formatting (clang-format, .clang-format) =="
mapfile -t sources < <(git ls-files '*.c' '*.h')
clang-format --dry-run --Werror "${sources[@]}"
echo "formatting ok (${#sources[@]} files)"

echo "== test suite =="
# the pomlab view tests open pages in headless Chromium (installed by setup.sh)
export POM_REQUIRE_BROWSER=1
ctest --test-dir build --output-on-failure -j2

echo "== test suite under -fsanitize=address,undefined =="
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPOM_SANITIZE=ON -DPOM_WERROR=ON >/dev/null
cmake --build build-asan -j"$(nproc)"
# (the browser tests once is enough: test_view_cli runs pomlab view here)
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j2 -LE browser

echo "== fuzz targets: config loading, a study's setup, the flat C layer's overrides (libFuzzer, docs/fuzzing.md) =="
# Only the fuzz targets and the libraries they use are built; each runs for
# POM_FUZZ_TIME seconds (20) from the shipped and test configs.
cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPOM_FUZZ=ON \
  -DPOM_WERROR=ON >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_config fuzz_study fuzz_api fuzz_arch_file
ctest --test-dir build-fuzz --output-on-failure -L fuzz -j2

echo "== MPI build: 2-rank study against the threaded run =="
cmake -S . -B build-mpi -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPOM_WITH_MPI=ON -DPOM_WERROR=ON >/dev/null
cmake --build build-mpi -j"$(nproc)"
ctest --test-dir build-mpi --output-on-failure -R 'test_doe_study'

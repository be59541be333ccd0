#!/usr/bin/env bash
# The setting of a measured MF-7923D from its needle-thread take-up, with
# ILLUSTRATIVE readings: examples/mf7923d-bench-n1.csv holds the mf7923d
# preset's own P of needle thread n1 at B every 10 deg at z = -3 mm and
# dphi = 5 deg, plus documented noise (see the file's comment), ten readings
# per angle, not a measurement.
#   1. the readings processed per angle (`stitchkin measured`);
#   2. the fit of z and dphi from the shipped setting, with their 95 %
#      intervals, the correlation, the residuals and the advice: the fitted
#      machine's match and the adjustment to the best setting (`stitchkin fit
#      --measured`), as text and as JSON;
#   3. the residuals over phi as a chart.
#
# Run from the repository root:   bash examples/mf7923d_bench_fit.sh
# Tables go to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes the cycle coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then STEP=10; else STEP=1; fi
BENCH=examples/mf7923d-bench-n1.csv

stitchkin measured "$BENCH" -o "$OUT/mf7923d_bench_processed.csv"
stitchkin fit --preset mf7923d --measured "n1=$BENCH" --adjust z,dphi --step $STEP \
  --chart "$OUT/mf7923d_bench_residuals.svg" -o "$OUT/mf7923d_bench_fit.txt"
stitchkin fit --preset mf7923d --measured "n1=$BENCH" --adjust z,dphi --step $STEP --no-advice \
  -o "$OUT/mf7923d_bench_fit.json"

echo "wrote $OUT/mf7923d_bench_processed.csv, $OUT/mf7923d_bench_fit.txt, $OUT/mf7923d_bench_fit.json, $OUT/mf7923d_bench_residuals.svg (illustrative readings)"

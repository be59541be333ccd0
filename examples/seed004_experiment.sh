#!/usr/bin/env bash
# Seed 004's bench experiment (Polyakov (2022) §3.3–3.4), with ILLUSTRATIVE
# readings: the thesis took ten readings of the lower-looper thread every
# 10 deg of the main shaft and processed them per angle (mean, standard
# deviation, Student's t interval at 95 %, random, systematic, total and
# relative errors); its readings are in figures and an appendix missing from
# the text, so examples/seed004-bench-lower.csv holds the altin504 preset's
# own take-up plus documented noise (see the file's comment), not a
# measurement. Table 1's constants: m = 2.5 mm, t = 2.8 mm (the preset's
# defaults).
#   1. the readings processed: one row per angle, the columns of §3.4
#      (`stitchkin measured`);
#   2. the mean curve with its interval beside the model (`match --measured`);
#   3. the take-up chart with the mean curve's error bars.
#
# Run from the repository root:   bash examples/seed004_experiment.sh
# Tables go to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes the cycle coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then STEP=10; else STEP=1; fi
BENCH=examples/seed004-bench-lower.csv

stitchkin measured "$BENCH" -o "$OUT/seed004_bench_processed.csv"
stitchkin measured "$BENCH" --format table -o "$OUT/seed004_bench_processed.txt"
stitchkin match --preset altin504 --measured "lower=$BENCH" --step $STEP -o "$OUT/seed004_bench_match.txt"
stitchkin plot takeup --preset altin504 --measured "lower=$BENCH" --step $STEP -o "$OUT/seed004_bench_takeup.svg"

echo "wrote $OUT/seed004_bench_processed.csv, $OUT/seed004_bench_processed.txt, $OUT/seed004_bench_match.txt, $OUT/seed004_bench_takeup.svg (illustrative readings)"

#!/usr/bin/env bash
# Seed 002 (class 876 eight-link needle mechanism with adjustable stroke,
# presets/needle876.toml): the needle stroke and the transmission angles
# against the angle alpha of the adjustable hinge F, 0...40 deg. The paper
# gives a stroke of 18 mm at alpha = 0 and 23 mm at alpha = 35 deg, with the
# needle's lowest position fixed; needle_y.range_mm is the stroke, mu.* the
# transmission angles (mu.ok = 1 while every one stays inside 30...150 deg).
#
# Run from the repository root:   bash examples/seed002_stroke_table.sh
# The CSV table goes to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes the grid coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then N=3 STEP=30; else N=41 STEP=1; fi

stitchkin sweep --preset needle876 --vary alpha=0:40:$N --figures 'needle_y.range_mm,mu.*' --step $STEP -o "$OUT/seed002_stroke.csv"

echo "wrote $OUT/seed002_stroke.csv"

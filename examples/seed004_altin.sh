#!/usr/bin/env bash
# Seed 004 (Textima Altin overlock, stitch 504, presets/altin504.toml):
#   1. the match of the take-up P with the thread the stitch needs, P', for
#      the needle, lower-looper and upper-looper threads (m = 2.5, t = 2.8 mm),
#      every metric (`match --details`) and the needle thread's physical
#      checks;
#   2. the thread one stitch 504 consumes, per thread (seed 004 section 2.6:
#      8.121, 11.383 and 11.383 mm for m = 2.5, t = 2.8, a = 4 mm, beta = 20 deg);
#   3. a sweep of the material thickness m (0.5...2.5 mm) and the stitch
#      length t (1...2.8 mm): each thread's max P' (the needle thread's at B,
#      the eye's top position: needle.max_Pprime_B_mm), its match score, and
#      whether the needle thread's physical checks pass (checks.ok).
#
# Run from the repository root:   bash examples/seed004_altin.sh
# Tables go to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes every grid coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then NM=2 NT=2 STEP=30; else NM=9 NT=7 STEP=1; fi

stitchkin match --preset altin504 --details --step $STEP -o "$OUT/seed004_altin504_match.txt"
stitchkin consumption --type 504 --thickness 2.5 --stitch 2.8 --width 4 --incline 20 --format csv > "$OUT/seed004_consumption_504.csv"
stitchkin sweep --preset altin504 --vary m=0.5:2.5:$NM --vary stitch=1:2.8:$NT --figures '*.max_Pprime*,*.score,score.mean,checks.ok' --step $STEP -o "$OUT/seed004_altin504_m_t.csv"

echo "wrote $OUT/seed004_altin504_match.txt, $OUT/seed004_consumption_504.csv, $OUT/seed004_altin504_m_t.csv"

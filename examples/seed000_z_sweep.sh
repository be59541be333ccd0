#!/usr/bin/env bash
# Seed 000 (Juki MF-7923D needle-thread take-up, presets/mf7923d.toml):
# sweeps of the three adjustments the paper studies (its Figs. 6-9):
#   z     ball arm O2B along its shaft, -10...10 mm (Table 3)
#   r1    eccentric radius O1A, 4...6 mm (section 6)
#   dphi  phase of the eccentric against the needle crank, -20...20 deg (Table 3)
# For each: the largest take-up max P of every thread path (needles 1-3,
# feed contours A and B) under the preset's reading of the take-up phase,
# which reproduces the published P results, and the P-P' match score of every
# needle thread under the other reading, t1_phase = 180 (every score is 0
# under the preset's reading: docs/stitch-formation.md section 10.1).
#
# Run from the repository root:   bash examples/seed000_z_sweep.sh
# CSV tables go to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes every grid coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then N=3 STEP=30; else N=41 STEP=1; fi

# max P per path (mm) against z, r1 and dphi
stitchkin sweep --vary z=-10:10:$N --figures '*.max_P_mm' --step $STEP -o "$OUT/seed000_z_max_P.csv"
stitchkin sweep --vary r1=4:6:$N --figures '*.max_P_mm' --step $STEP -o "$OUT/seed000_r1_max_P.csv"
stitchkin sweep --vary dphi=-20:20:$N --figures '*.max_P_mm' --step $STEP -o "$OUT/seed000_dphi_max_P.csv"

# the match with stitch 407 (m = t = 3 mm): per-needle score, mean score,
# transmission angles, with T1 up at the needle's top dead centre
stitchkin sweep --set t1_phase=180 --vary z=-10:10:$N --figures '*.score,score.mean,mu.min_deg,mu.max_deg' --step $STEP -o "$OUT/seed000_z_match.csv"
stitchkin sweep --set t1_phase=180 --vary r1=4:6:$N --figures '*.score,score.mean,mu.min_deg,mu.max_deg' --step $STEP -o "$OUT/seed000_r1_match.csv"
stitchkin sweep --set t1_phase=180 --vary dphi=-20:20:$N --figures '*.score,score.mean,mu.min_deg,mu.max_deg' --step $STEP -o "$OUT/seed000_dphi_match.csv"

echo "wrote $OUT/seed000_{z,r1,dphi}_{max_P,match}.csv"

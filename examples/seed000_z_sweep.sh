#!/usr/bin/env bash
# Seed 000 (Juki MF-7923D needle-thread take-up, presets/mf7923d.toml):
# sweeps of the three adjustments the paper studies (its Figs. 6-9):
#   z     ball arm O2B along its shaft, -10...10 mm (Table 3)
#   r1    eccentric radius O1A, 4...6 mm (section 6)
#   dphi  phase of the eccentric against the needle crank, -20...20 deg (Table 3)
# For each:
#   - the largest take-up past B, max P_B, of every thread path (needles 1-3,
#     feed contours A and B) at the preset's reading, T1 up at the needle's
#     top dead centre (t1_phase = 180);
#   - the same at the other reading, t1_phase = 0 (T1 down at the top dead
#     centre), with checks.ok: it gives seed 000's signs for r1 and O2B but
#     passes more thread through B than the needle can take (thread_bound
#     fails, checks.ok = 0; docs/published-facts.md, rows MF05, MF07, MF20);
#   - the P-P' match of every needle thread with stitch 407 on 3 mm material
#     with 3 mm stitches (scores, checks.ok, transmission angles), at the
#     preset's reading.
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

# max P_B per path (mm) against z, r1 and dphi
stitchkin sweep --vary z=-10:10:$N --figures '*.max_P_B_mm' --step $STEP -o "$OUT/seed000_z_max_P.csv"
stitchkin sweep --vary r1=4:6:$N --figures '*.max_P_B_mm' --step $STEP -o "$OUT/seed000_r1_max_P.csv"
stitchkin sweep --vary dphi=-20:20:$N --figures '*.max_P_B_mm' --step $STEP -o "$OUT/seed000_dphi_max_P.csv"

# the same at the other reading of the take-up phase, with whether every
# physical check passes
stitchkin sweep --set t1_phase=0 --vary z=-10:10:$N --figures '*.max_P_B_mm,checks.ok' --step $STEP -o "$OUT/seed000_z_max_P_t1phase0.csv"
stitchkin sweep --set t1_phase=0 --vary r1=4:6:$N --figures '*.max_P_B_mm,checks.ok' --step $STEP -o "$OUT/seed000_r1_max_P_t1phase0.csv"
stitchkin sweep --set t1_phase=0 --vary dphi=-20:20:$N --figures '*.max_P_B_mm,checks.ok' --step $STEP -o "$OUT/seed000_dphi_max_P_t1phase0.csv"

# the match with stitch 407 (m = t = 3 mm): per-needle score, mean score,
# the physical checks, transmission angles
stitchkin sweep --vary z=-10:10:$N --figures '*.score,score.mean,checks.ok,mu.min_deg,mu.max_deg' --step $STEP -o "$OUT/seed000_z_match.csv"
stitchkin sweep --vary r1=4:6:$N --figures '*.score,score.mean,checks.ok,mu.min_deg,mu.max_deg' --step $STEP -o "$OUT/seed000_r1_match.csv"
stitchkin sweep --vary dphi=-20:20:$N --figures '*.score,score.mean,checks.ok,mu.min_deg,mu.max_deg' --step $STEP -o "$OUT/seed000_dphi_match.csv"

echo "wrote $OUT/seed000_{z,r1,dphi}_{max_P,max_P_t1phase0,match}.csv"

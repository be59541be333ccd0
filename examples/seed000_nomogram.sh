#!/usr/bin/env bash
# Seed 000 (Juki MF-7923D, presets/mf7923d.toml): the nomogram of the take-up
# adjustment against material thickness m (and stitch length t). Seed 000
# concludes that z = -2...-5 mm suits 3-5 mm material; docs/studies.md
# ("Nomograms") compares these tables with that conclusion.
#   1. z alone, the preset's reading of the take-up phase (t1_phase = 0):
#      every match score is 0, whatever z (the table says why);
#   2. z alone, T1 up at the needle's top dead centre (t1_phase = 180): the
#      recommended z falls from about +1 mm at m = 0.5 to about -5.4 mm at
#      m = 5 (-3.9...-5.4 mm for 3-5 mm material), with a flat optimum;
#   3. z and dphi together over m and t (t1_phase = 180): the optimum leaves
#      for the ends of the ranges (z = 10 mm, dphi -17...-20 deg; the
#      thickest material with the longest stitches: z = -10 mm, dphi +15 deg).
#
# Run from the repository root:   bash examples/seed000_nomogram.sh
# Tables go to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes every grid coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then NM=1 NT=2 STEP=30; else NM=10 NT=8 STEP=1; fi

stitchkin nomogram --thickness 0.5:5:$NM --adjust z --seed 1 --step $STEP -o "$OUT/seed000_nomogram_z_t1phase0.txt"
stitchkin nomogram --set t1_phase=180 --thickness 0.5:5:$NM --adjust z --seed 1 --step $STEP -o "$OUT/seed000_nomogram_z.txt"
stitchkin nomogram --set t1_phase=180 --thickness 0.5:5:$NM --stitch 1:4.5:$NT --adjust z,dphi --seed 1 --step $STEP --format csv -o "$OUT/seed000_nomogram_z_dphi.csv"

echo "wrote $OUT/seed000_nomogram_z_t1phase0.txt, $OUT/seed000_nomogram_z.txt, $OUT/seed000_nomogram_z_dphi.csv"

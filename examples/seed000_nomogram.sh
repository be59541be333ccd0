#!/usr/bin/env bash
# Seed 000 (Juki MF-7923D, presets/mf7923d.toml): the nomogram of the take-up
# adjustment against material thickness m (and stitch length t). Seed 000
# concludes that z = -2...-5 mm suits 3-5 mm material; docs/studies.md
# ("Seed 000's z finding") and docs/published-facts.md (rows MF11-MF13)
# compare these tables with that conclusion.
#   1. z alone, as the preset stands (T1 up at the needle's top dead centre;
#      the regulator window computed from the thread's tension): the
#      recommended z is about -7 mm at m = 0.5 and -8...-10 mm for 3-5 mm
#      material, and tuning it gains about 20 score points;
#   2. z alone with the window assumed, each stitch drawn through the
#      regulator in the 60 deg before the needle's top dead centre
#      (`regulator = { width_deg = 60 }`): z slightly positive, about
#      +1.7 mm at m = 0.5 to +2.4 mm at m = 5, with a flat optimum;
#   3. z alone with the whole stitch passing the regulator at its lock
#      (`regulator = { at_lock = true }`, the accounting of the reference
#      tables): z falls from about -2.5 mm at m = 0.5 to -5.4 mm at m = 5;
#   4. z alone at the other reading of the take-up phase (t1_phase = 0, T1
#      down at the top dead centre): every match score is 0 and thread_bound
#      fails whatever z (the table says why);
#   5. z and dphi together over m and t, as the preset stands.
#
# Run from the repository root:   bash examples/seed000_nomogram.sh
# Tables go to $STITCHKIN_OUT (default target/examples), with the model of
# tables 2 and 3 (mf7923d_window60.toml, mf7923d_at_lock.toml).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes every grid coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then TH=2.5 NT=2 STEP=30; else TH=0.5:5:10 NT=8 STEP=1; fi

# The preset with the regulator window assumed (the 60 deg before the
# needle's top dead centre), and with the whole stitch passing the
# regulator at the lock.
sed '/^\[stitch\]$/a regulator = { width_deg = 60 }' presets/mf7923d.toml > "$OUT/mf7923d_window60.toml"
sed '/^\[stitch\]$/a regulator = { at_lock = true }' presets/mf7923d.toml > "$OUT/mf7923d_at_lock.toml"

stitchkin nomogram --thickness $TH --adjust z --seed 1 --step $STEP -o "$OUT/seed000_nomogram_z.txt"
stitchkin nomogram "$OUT/mf7923d_window60.toml" --thickness $TH --adjust z --seed 1 --step $STEP -o "$OUT/seed000_nomogram_z_window60.txt"
stitchkin nomogram "$OUT/mf7923d_at_lock.toml" --thickness $TH --adjust z --seed 1 --step $STEP -o "$OUT/seed000_nomogram_z_at_lock.txt"
stitchkin nomogram --set t1_phase=0 --thickness $TH --adjust z --seed 1 --step $STEP -o "$OUT/seed000_nomogram_z_t1phase0.txt"
stitchkin nomogram --thickness $TH --stitch 1:4.5:$NT --adjust z,dphi --seed 1 --step $STEP --format csv -o "$OUT/seed000_nomogram_z_dphi.csv"

echo "wrote $OUT/seed000_nomogram_z.txt, $OUT/seed000_nomogram_z_at_lock.txt, $OUT/seed000_nomogram_z_t1phase0.txt, $OUT/seed000_nomogram_z_dphi.csv"

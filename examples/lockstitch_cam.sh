#!/usr/bin/env bash
# The lockstitch 301 (presets/lockstitch.toml; seed 001's take-up lever, a
# needle bar and a rotary hook, illustrative): how well the lever gives what
# the stitch needs, the lever and hook settings that match best, and the
# inverse: the profile of a rotary cam take-up that would make the take-up
# P equal the required P' (examples/lockstitch-cam.toml, the same machine
# with a disc cam on the main shaft in place of the lever).
#
# Run from the repository root:   bash examples/lockstitch_cam.sh
# The tables go to $STITCHKIN_OUT (default target/examples).
# STITCHKIN=/path/to/stitchkin runs that binary instead of
# `cargo run --release --`; STITCHKIN_QUICK=1 makes the grids coarse (the
# test suite's smoke run).
set -euo pipefail
OUT="${STITCHKIN_OUT:-target/examples}"
mkdir -p "$OUT"
stitchkin() { if [[ -n "${STITCHKIN:-}" ]]; then "$STITCHKIN" "$@"; else cargo run --release --quiet -- "$@"; fi; }
# The tuning shapes the lever as well as setting the hook: the lever's pivot
# height y4 is a fixed dimension of the machine, searched as a design change
# (--allow-dimensions) beside the technician's settings, the hook's timing
# and the needle bar's height. The hook timing changes the stitch, so each
# of its settings recomputes P' (the lever alone shares one P'): the smoke
# run tunes the lever only.
if [[ -n "${STITCHKIN_QUICK:-}" ]]; then STEP=6 POINTS=60 ADJUST=y4; else STEP=1 POINTS=360 ADJUST=y4,catch_rise,s_b; fi

stitchkin match --preset lockstitch --details --step $STEP -o "$OUT/lockstitch_match.txt"
stitchkin tune --preset lockstitch --adjust $ADJUST --allow-dimensions --step $STEP -o "$OUT/lockstitch_tune.txt"
stitchkin cam examples/lockstitch-cam.toml --path needle --target required --anchor-radius 100 --smooth 25 \
    --points $POINTS --format all -o "$OUT/lockstitch_cam"

echo "wrote $OUT/lockstitch_match.txt, $OUT/lockstitch_tune.txt and $OUT/lockstitch_cam.{csv,svg,dxf,toml}"

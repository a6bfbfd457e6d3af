#!/usr/bin/env bash
# usage: scripts/render_hashes.sh SSS_BINARY OUTDIR
# Renders ten small images (every method, shading flag and scene kind, 96×64, every shading flag
# given explicitly so that a change of defaults does not change them) and prints the sha256 of
# each PFM: run it with the binaries before and after a refactor and diff the lists.
set -euo pipefail
BIN=$1; OUT=$2; mkdir -p "$OUT"
COMMON="--width 96 --height 64 --photons 200000 --incidence-photons 20000 --translucency-photons 5000 --profiles $OUT/profiles"
GATHER="--samples 4 --frames 2 --light-map 256"
OFF="--incidence-aware off --exit-aware off --entry-shift off"
failed=0
run() { name=$1; shift; "$BIN" render $COMMON --out "$OUT/$name" "$@" >/dev/null 2>"$OUT/$name.log" || { echo "FAIL $name" >&2; tail -3 "$OUT/$name.log" >&2; failed=1; }; }
run plain $OFF --translucency off
run shaded --incidence-aware on --exit-aware entry --entry-shift on --translucency on
run exit_on --incidence-aware on --exit-aware on --entry-shift off --translucency off
run pair --scene pair --material skin1,marble $OFF --translucency on --resolution half
run fin_fast --scene fin $OFF --translucency on --blur fast --depth-test gaussian
run nosss --no-sss $OFF --translucency off
run dipole --method directional-dipole $OFF $GATHER
run area --method area-gather $OFF --material marble
run surf_radial --method surface-gather --bssrdf radial $OFF $GATHER
run surf_dir --method surface-gather --bssrdf directional $OFF $GATHER
(cd "$OUT" && sha256sum */render.pfm | sort -k2)
exit $failed

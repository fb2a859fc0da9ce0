#!/usr/bin/env bash
# The patch-test hypotheses of docs/FIDELITY.md (I-30..I-34) on a mesh (default: the Stanford bunny
# of ../shared/meshes, the one shared mesh identical to the paper's): T/F, W max, W avg, A and E of
# each configuration, as a Markdown table, with the command that measured each row. The default unit
# of ε is I-34's box-half-extent since 2026-12-01: the specification's hypotheses (I-30..I-33) run
# with --tolerance-unit diagonal, as they were measured.
#   scripts/patch-fidelity.sh [MESH] [MESHTOUR]
set -euo pipefail
cd "$(dirname "$0")/.."
mesh=${1:-../shared/meshes/bunny.ply}
exe=${2:-build/cli/meshtour}
[ -f "$mesh" ] || { echo "patch-fidelity: no mesh $mesh" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
configs=(
  ""
  "--tolerance-unit diagonal"
  "--tolerance-unit diagonal --patch-measure algebraic"
  "--tolerance-unit diagonal --patch-measure algebraic-normalized"
  "--tolerance-unit diagonal --face-samples edges-4"
  "--tolerance-unit diagonal --face-samples vertices"
  "--tolerance-unit diagonal --patch-normal-angle 30"
  "--tolerance-unit diagonal --patch-normal-angle 20"
  "--tolerance-unit diagonal --patch-normal-angle 15"
  "--tolerance-unit diagonal --patch-normal-angle 10"
  "--tolerance-unit diagonal --smoothing none"
  "--tolerance-unit diagonal --smoothing none --patch-normal-angle 20"
  "--tolerance-unit diagonal --leftovers grow-leftovers"
  "--tolerance-unit diagonal --seed-order index"
  "--tolerance-unit diagonal --tolerance 0.00035"
  "--tolerance-unit box-extent"
  "--face-samples vertices"
)
[ $# -ge 3 ] && configs=("${@:3}")
echo "| options | T | T/F | W max | W avg | A | E | r | h |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
for c in "${configs[@]}"; do
  # shellcheck disable=SC2086
  text=$("$exe" path "$mesh" -o "$out/p.json" --threads 1 $c 2>&1)
  T=$(sed -n 's/.*T = \([0-9]*\) (T\/F = \([0-9.]*\)%.*/\1 | \2 %/p' <<<"$text")
  W=$(sed -n 's/.*Wmax = \([0-9.]*\), Wavg = \([0-9.]*\).*/\1 | \2/p' <<<"$text")
  AE=$(sed -n 's/.*A = \([0-9.]*\)% of h.*E = \([0-9]*\),.*/\1 % | \2/p' <<<"$text")
  RH=$(sed -n 's/.*r = \([0-9.]*\), h = \([0-9.]*\).*/\1 | \2/p' <<<"$text")
  echo "| \`${c:-(defaults)}\` | $T | $W | $AE | $RH |"
done

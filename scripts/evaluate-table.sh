#!/usr/bin/env bash
# Regenerates the evaluation table of docs/EVALUATION.md: `meshtour evaluate --compare` on every mesh of
# ../shared/meshes (up axes from its meshes.tsv), then the markdown between the
# <!-- evaluate-table:begin --> and <!-- evaluate-table:end --> markers is replaced.
# Usage: scripts/evaluate-table.sh [MESHES_DIR]   (after scripts/build.sh; about 2 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
meshes="${1:-../shared/meshes}"
[ -f "$meshes/meshes.tsv" ] || { echo "evaluate-table: $meshes/meshes.tsv not found" >&2; exit 1; }
meshtour=build/cli/meshtour
[ -x "$meshtour" ] || { echo "evaluate-table: build first (scripts/build.sh)" >&2; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# name, file, up axis ("+Y" -> y) of every mesh that exists.
tail -n +2 "$meshes/meshes.tsv" | while IFS=$'\t' read -r name file _v _f _c _b up _rest; do
  [ "$file" = "-" ] && continue
  [ -f "$meshes/$file" ] || continue
  axis=$(echo "${up#+}" | tr 'A-Z' 'a-z')
  echo "evaluate-table: $name (up $axis)" >&2
  "$meshtour" evaluate "$meshes/$file" --up "$axis" --compare -q --json "$out/$name.json"
  echo "$name" >>"$out/order"
done

node scripts/evaluate-table.js "$out" docs/EVALUATION.md
echo "evaluate-table: docs/EVALUATION.md updated" >&2

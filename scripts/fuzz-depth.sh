#!/usr/bin/env bash
# Runs the libFuzzer targets to depth, outside CI: each until it has executed --runs inputs in all
# (10 million by default) or fuzzed for --hours (8 by default), whichever comes first, with its
# dictionary (fuzz/dict/) and a fixed -max_len. Work is resumable: each target's corpus and a ledger
# of every run stay in --work, and a second call continues where the first stopped (the counts add
# up). A crash, leak, timeout or out-of-memory input stops that target and is kept in
# WORK/findings-TARGET/ for replay (`build-fuzz/fuzz/fuzz_TARGET FILE`).
#
#   scripts/fuzz-depth.sh [--build DIR] [--work DIR] [--runs N] [--hours H] [--parallel P]
#                         [--slice-minutes M] [--report] [TARGET...]
#
# TARGET: a target of fuzz/CMakeLists.txt without its fuzz_ prefix: mesh, gltf, voyager, ... (default:
# every target there).
# --parallel P runs P targets at once (default 1); --slice-minutes M stops each run after M minutes
# and moves on, so that a session of limited length leaves every target's ledger current.
# Runs at nice 19: the machine stays usable. --report prints the table (markdown) and exits.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-fuzz work=fuzz-depth runs=10000000 hours=8 parallel=1 slice=0 report_only=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --hours) hours=$2; shift 2 ;;
    --parallel) parallel=$2; shift 2 ;;
    --slice-minutes) slice=$2; shift 2 ;;
    --report) report_only=1; shift ;;
    -h|--help) sed -n '2,/^[^#]/{/^#/p}' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz-depth: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
# The targets and each one's -max_len, as CTest's short runs take them: declared once, in
# fuzz/CMakeLists.txt, as `meshtour_fuzz_target(fuzz_NAME CORPUS MAX_LEN ...)`.
mapfile -t all < <(sed -n 's/^meshtour_fuzz_target(fuzz_\([a-z_]*\) .*/\1/p' fuzz/CMakeLists.txt)
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")

max_len() {
  local n
  n=$(sed -n "s/^meshtour_fuzz_target(fuzz_$1 [^ ]* \([0-9]*\).*/\1/p" fuzz/CMakeLists.txt)
  [ -n "$n" ] || { echo "fuzz-depth: no target '$1' in fuzz/CMakeLists.txt (one of: ${all[*]})" >&2; return 2; }
  echo "$n"
}
for t in "${targets[@]}"; do max_len "$t" >/dev/null; done
mkdir -p "$work"
ledger=$work/ledger.tsv
[ -f "$ledger" ] || printf 'target\tstarted\texecutions\tseconds\tcoverage\tfeatures\tcorpus\tfinding\n' >"$ledger"

# Sums of a target's executions and seconds, and its last coverage, over the ledger.
totals() {
  awk -F'\t' -v t="$1" '$1==t {e+=$3; s+=$4; c=$5; f=$6; n=$7; if ($8!="") x=x" "$8}
    END {printf "%d %d %s %s %s %s\n", e, s, (c==""?"-":c), (f==""?"-":f), (n==""?"-":n), (x==""?"-":x)}' "$ledger"
}

report() {
  echo "| target | executions | hours | coverage (edges) | features | corpus | findings |"
  echo "|---|---:|---:|---:|---:|---:|---|"
  for t in "${targets[@]}"; do
    read -r e s c f n x < <(totals "$t")
    printf '| %s | %s | %.2f | %s | %s | %s | %s |\n' "$t" "$e" "$(echo "$s/3600" | bc -l)" "$c" "$f" "$n" "${x# }"
  done
}
if [ "$report_only" = 1 ]; then report; exit 0; fi

run_target() {
  local t=$1
  local binary=$build/fuzz/fuzz_$t
  [ -x "$binary" ] || { echo "fuzz-depth: $binary is missing; build it (docs/TESTING.md, Fuzzing)" >&2; return 1; }
  read -r done_runs done_seconds _ _ _ finding < <(totals "$t")
  if [ "$finding" != "-" ]; then echo "fuzz-depth: $t: stopped at a finding ($finding); fix and clear it first"; return 0; fi
  local left_runs=$((runs - done_runs))
  local left_seconds=$((hours * 3600 - done_seconds))
  if [ $left_runs -le 0 ] || [ $left_seconds -le 0 ]; then echo "fuzz-depth: $t: done ($done_runs inputs, ${done_seconds} s)"; return 0; fi
  [ "$slice" -gt 0 ] && [ $((slice * 60)) -lt $left_seconds ] && left_seconds=$((slice * 60))
  local corpus=$work/corpus-$t
  local findings=$work/findings-$t
  local log=$work/$t.log
  mkdir -p "$corpus" "$findings"
  local dict=() ; [ -f "fuzz/dict/$t.dict" ] && dict=(-dict="fuzz/dict/$t.dict")
  local started; started=$(date -u +%Y-%m-%dT%H:%M:%SZ)
  echo "fuzz-depth: $t: $left_runs inputs or $left_seconds s from $done_runs done"
  local status=0
  nice -n 19 "$binary" -runs="$left_runs" -max_total_time="$left_seconds" -max_len="$(max_len "$t")" \
    "${dict[@]}" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$findings/" \
    "$corpus" "fuzz/corpus/$t" >"$log" 2>&1 || status=$?
  local executions seconds line coverage features corpus_size finding=""
  executions=$(grep -oE 'stat::number_of_executed_units: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+$' || true)
  line=$(grep -E '^#[0-9]+' "$log" | tail -1)
  [ -n "$executions" ] || executions=$(echo "$line" | grep -oE '^#[0-9]+' | tr -d '#')
  seconds=$(( $(date +%s) - $(date -d "$started" +%s) ))  # wall clock, start-up and corpus loading included
  coverage=$(echo "$line" | grep -oE 'cov: [0-9]+' | grep -oE '[0-9]+' || echo -)
  features=$(echo "$line" | grep -oE 'ft: [0-9]+' | grep -oE '[0-9]+' || echo -)
  corpus_size=$(find "$corpus" -type f | wc -l)
  if [ "$status" != 0 ]; then
    finding=$(ls -t "$findings" 2>/dev/null | grep -v '^starved$' | head -1)
    finding=${finding:-exit-$status}
    # At nice 19 on a busy machine an input can wait for the CPU past the alarm: a timeout counts
    # only if it repeats when the input runs alone.
    if [[ "$finding" == timeout-* ]] && LSAN_OPTIONS=$LSAN_OPTIONS timeout 60 "$binary" "$findings/$finding" >/dev/null 2>&1; then
      mkdir -p "$findings/starved"
      mv "$findings/$finding" "$findings/starved/"
      echo "fuzz-depth: $t: $finding does not time out when run alone (the fuzzer was starved); kept in $findings/starved" >&2
      finding=""
    else
      echo "fuzz-depth: $t: FINDING $finding (exit $status); see $log" >&2
    fi
  fi
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$t" "$started" "${executions:-0}" "${seconds:-0}" "$coverage" "$features" \
    "$corpus_size" "$finding" >>"$ledger"
}

export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0"
export -f run_target totals max_len
export build work runs hours slice ledger all
status=0
printf '%s\n' "${targets[@]}" | xargs -P "$parallel" -I{} bash -c 'run_target "$@"' _ {} || status=$?
report
exit $status

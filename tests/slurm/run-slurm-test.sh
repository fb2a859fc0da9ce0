#!/usr/bin/env bash
# Integration test of `meshtour farm slurm` on a REAL single-node Slurm cluster: starts munged,
# slurmctld and slurmd in a temporary directory (tests/slurm/slurm-local.sh), submits a small tour
# of the default path (the feature orbit) as a job array of frame chunks plus a dependent encode
# job, waits for them, and checks that the path was searched once (at submission: the search
# announces itself, and the lines are counted in every log), that the frames are byte-identical
# and the video is the bytes of `meshtour tour` on one machine. Then the same job again with each
# array task forced onto another instruction set (MESHTOUR_TILE_KERNEL): the same bytes. Also: a
# re-submitted array renders nothing (resume), and no node was drained.
# Stops the daemons by PID at the end, whatever happens.
#
#   run-slurm-test.sh MESHTOUR_EXECUTABLE
#
# Exit codes: 0 passed, 1 failed, 77 skipped (CTest's SKIP_RETURN_CODE): not root, or Slurm not
# installed (scripts/install-deps.sh --tests installs it). Under MESHTOUR_REQUIRE_SHARED=1 (CI), a
# missing Slurm is a failure instead of a skip.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
meshtour=$(realpath "${1:?usage: $0 MESHTOUR_EXECUTABLE}")
timeout=${MESHTOUR_SLURM_TEST_TIMEOUT:-180}

log() { printf '[slurm-test %s] %s\n' "$(date +%T)" "$*" >&2; }
fail() { log "FAILED: $*"; exit 1; }
skip() {
  local why=$1
  if [ "${MESHTOUR_REQUIRE_SHARED:-0}" = 1 ]; then
    fail "cannot run the Slurm integration test: $why (MESHTOUR_REQUIRE_SHARED=1 makes this a failure)"
  fi
  printf '\n*****************************************************************\n' >&2
  printf '*** SKIPPED: Slurm integration test NOT RUN: %s\n' "$why" >&2
  printf '*****************************************************************\n\n' >&2
  exit 77
}

[ "$(id -u)" = 0 ] || skip "it must run as root (it starts munged, slurmctld and slurmd)"
for tool in munged mungekey slurmctld slurmd sbatch squeue scontrol sinfo ffmpeg; do
  command -v "$tool" >/dev/null || skip "'$tool' is not installed (run scripts/install-deps.sh --tests)"
done

t0=$(date +%s.%N)
dir=$(mktemp -d /tmp/meshtour-slurm.XXXXXX)
cleanup() {
  local rc=$?
  trap - EXIT
  "$here/slurm-local.sh" stop "$dir" || true
  if [ $rc -ne 0 ]; then
    log "last log lines (kept in $dir):"
    tail -n 20 "$dir"/log/*.log "$dir"/work/farm/logs/*.log >&2 2>/dev/null || true
  else
    rm -rf "$dir"
  fi
  log "total $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s, exit $rc"
  exit $rc
}
trap cleanup EXIT
"$here/slurm-local.sh" start "$dir"
# shellcheck disable=SC1091
. "$dir/env.sh"

work=$dir/work
mkdir -p "$work"
tour=(--frames 12 --width 64 --height 48 --spp 2 --crf 18)  # the built-in scene: no input files needed

wait_jobs() {  # bounded 0.2-s poll (sbatch --wait backs off to 32 s)
  local end=$(( $(date +%s) + timeout ))
  while squeue -h -j "$1" -t PENDING,CONFIGURING,RUNNING,COMPLETING 2>/dev/null | grep -q .; do
    [ "$(date +%s)" -lt "$end" ] || { squeue >&2; fail "jobs $1 not finished after ${timeout}s"; }
    sleep 0.2
  done
}
job_states() {  # "JobId State ExitCode" for every record of the jobs (array tasks included)
  for id in "$@"; do
    scontrol -o show job "$id" | sed -E 's/^JobId=([0-9]+) .* JobState=([A-Z_]+) .* ExitCode=([0-9:]+) .*/\1 \2 \3/'
  done
}

log "submitting: meshtour farm slurm --submit ${tour[*]} --chunk-size 5"
submitted=$(date +%s.%N)
out=$("$meshtour" farm slurm --out-dir "$work/farm" "${tour[@]}" --chunk-size 5 --submit 2>"$work/submit.log")
cat "$work/submit.log" >&2
echo "$out" >&2
render_job=$(sed -n 's/^render_job=//p' <<<"$out")
encode_job=$(sed -n 's/^encode_job=//p' <<<"$out")
[ -n "$render_job" ] && [ -n "$encode_job" ] || fail "farm slurm printed no job ids"
grep -q -- '--array=0-2$' "$work/farm/render.sbatch" || fail "12 frames in chunks of 5 should be a 3-task array"
wait_jobs "$render_job,$encode_job"
log "array + encode done $(awk -v a="$submitted" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}') s after submission"

states=$(job_states "$render_job" "$encode_job")
echo "$states" | sed 's/^/  job /' >&2
[ "$(echo "$states" | wc -l)" -eq 4 ] || fail "expected 3 render tasks and 1 encode job"
if echo "$states" | grep -vq ' COMPLETED 0:0$'; then fail "a job did not complete with 0:0"; fi
[ -z "$(sinfo -h -R)" ] || { sinfo -R >&2; fail "a node was drained (a silent launch failure)"; }

# What the jobs produced, not only what Slurm says.
frames=$work/farm/frames
[ "$(ls "$frames"/frame_*.png | wc -l)" -eq 12 ] || fail "expected 12 frames in $frames"
if ls -A "$frames" | grep -q '^\.'; then fail "temporary files left in $frames"; fi
video=$work/farm/meshtour-default.mp4
[ -s "$video" ] || fail "no video $video"
grep -h '"event":"summary"' "$work"/farm/logs/render_*.log | sed 's/^/  log /' >&2
[ "$(grep -h '"event":"frame"' "$work"/farm/logs/render_*.log | wc -l)" -eq 12 ] || fail "expected 12 JSON frame lines in the task logs"

# One path search for the whole job: at submission, none in the tasks.
searches() { cat "$@" | grep -c 'path search:' || true; }
[ "$(searches "$work/submit.log")" -eq 1 ] || fail "the submission should search the path once"
[ "$(searches "$work"/farm/logs/render_*.log)" -eq 0 ] || fail "a render task searched the path again"
grep -q '"mode": "feature-orbit"' "$work/farm/path.json" || fail "path.json does not hold the feature orbit"
log "path searched once, at submission; the tasks read $work/farm/path.json"

# The same tour on one machine.
"$meshtour" tour -o "$work/single.mp4" "${tour[@]}" --frames-dir "$work/single" -q
same_as_single() {  # $1: a farm's output directory
  for f in "$work"/single/frame_*.png; do
    cmp -s "$f" "$1/frames/$(basename "$f")" || fail "$(basename "$f") differs between the farm ($1) and one machine"
  done
  cmp -s "$1/meshtour-default.mp4" "$work/single.mp4" || fail "the farm's video $1/meshtour-default.mp4 is not the bytes of tour's"
}
[ "$(ffmpeg -v error -i "$video" -f rawvideo -pix_fmt rgb24 - | wc -c)" -eq $((64 * 48 * 3 * 12)) ] || fail "the farm's video does not decode to 12 frames of 64x48"
same_as_single "$work/farm"
log "12 frames and the video byte-identical to 'meshtour tour'"

# Each array task forced onto another instruction set of the tile kernel: one path, the same bytes.
kernels=(baseline)
grep -qw avx2 /proc/cpuinfo && kernels+=(x86-64-v3)
grep -qw avx512bw /proc/cpuinfo && kernels+=(x86-64-v4)
"$meshtour" farm slurm --out-dir "$work/isa" "${tour[@]}" --chunk-size 5 -q
ids=()
for task in 0 1 2; do
  kernel=${kernels[$(( task % ${#kernels[@]} ))]}
  id=$(sbatch --parsable --array="$task" --export=ALL,MESHTOUR_TILE_KERNEL="$kernel" "$work/isa/render.sbatch"); ids+=("${id%%;*}")
  log "task $task on $kernel: job ${id%%;*}"
done
deps=$(IFS=:; echo "${ids[*]}")
enc=$(sbatch --parsable --dependency=afterok:"$deps" --kill-on-invalid-dep=yes "$work/isa/encode.sbatch"); enc=${enc%%;*}
wait_jobs "$(IFS=,; echo "${ids[*]}"),$enc"
if job_states "${ids[@]}" "$enc" | grep -vq ' COMPLETED 0:0$'; then fail "a job of the instruction-set run failed"; fi
[ "$(searches "$work"/isa/logs/render_*.log)" -eq 0 ] || fail "a render task of the instruction-set run searched the path"
same_as_single "$work/isa"
log "tasks on ${kernels[*]}: frames and video byte-identical to 'meshtour tour'"

# Resume: the same array again renders nothing.
again=$(sbatch --parsable "$work/farm/render.sbatch"); again=${again%%;*}
wait_jobs "$again"
if job_states "$again" | grep -vq ' COMPLETED 0:0$'; then fail "the re-submitted array failed"; fi
[ "$(grep -h '"event":"summary"' "$work"/farm/logs/render_"$again"_*.log | grep -c '"done":0,')" -eq 3 ] ||
  fail "the re-submitted array rendered frames again"
log "re-submitted array $again rendered nothing (all frames there)"
log "PASSED"

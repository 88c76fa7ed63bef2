# Sourced by tools/test and tools/reliability: times one part of a stage (set-up and build, tests,
# fuzzing), prints it, and appends "PART<TAB>SECONDS" to $GPSEMU_STAGE_TIMES when set (.ci/run
# collects them into one table at the end).
# Usage: gpsemu_timed "part name" COMMAND ARGS...   (returns the command's status)
gpsemu_timed() {
  local part=$1
  shift
  local t0=$SECONDS rc=0
  "$@" || rc=$?
  local took=$((SECONDS - t0))
  echo "== $part: $took s$( ((rc)) && echo " (failed, status $rc)")" >&2
  if [[ -n "${GPSEMU_STAGE_TIMES:-}" ]]; then
    printf '%s\t%s\t%s\n' "$part" "$took" "$rc" >>"$GPSEMU_STAGE_TIMES"
  fi
  return $rc
}

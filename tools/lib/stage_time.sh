# Sourced by tools/test and tools/reliability: times one part of a stage (set-up and build, tests,
# fuzzing), prints it, and appends "PART<TAB>SECONDS" to $GPSEMU_STAGE_TIMES when set (.ci/run
# collects them into one table at the end).
# Usage: gpsemu_timed "part name" COMMAND ARGS...   (returns the command's status)
# gpsemu_record_part "part name" SECONDS STATUS: the same line for a part timed by hand.
gpsemu_record_part() {
  echo "== $1: $2 s$( (($3)) && echo " (failed, status $3)")" >&2
  if [[ -n "${GPSEMU_STAGE_TIMES:-}" ]]; then
    printf '%s\t%s\t%s\n' "$1" "$2" "$3" >>"$GPSEMU_STAGE_TIMES"
  fi
}
gpsemu_timed() {
  local part=$1
  shift
  local t0=$SECONDS rc=0
  "$@" || rc=$?
  gpsemu_record_part "$part" $((SECONDS - t0)) $rc
  return $rc
}

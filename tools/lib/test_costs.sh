# Sourced by tools/test and tools/reliability: CTest starts the longest tests first when it knows
# their times (<build>/Testing/Temporary/CTestCostData.txt, which it writes after every run). A
# fresh clone has none, and started its 100 s tests last, after the short ones, as the suite's
# tail; so a build without it starts from the times recorded in tests/costs/<kind>.txt
# (tools/update-test-costs writes them from a run's trees). Names not there cost the average.
# Usage: gpsemu_seed_test_costs BUILD-DIR KIND   (KIND: release or sanitize)
gpsemu_seed_test_costs() {
  local build=$1 kind=$2
  local root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
  local data="$build/Testing/Temporary/CTestCostData.txt"
  [[ -s "$data" || ! -s "$root/tests/costs/$kind.txt" ]] && return 0
  mkdir -p "$(dirname "$data")"
  cp "$root/tests/costs/$kind.txt" "$data"
}

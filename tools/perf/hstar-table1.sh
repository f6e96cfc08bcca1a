#!/usr/bin/env bash
# H* on every instance of the H* paper's Table I (issue 15): sum of costs, makespan, wall time of
# the planner (the plan file's runtime_ms) and a hash of the paths, one line per instance, so two
# builds can be compared side by side (same plans = same hashes).
#
#   tools/perf/hstar-table1.sh [MRPP_BINARY] [extra solve arguments...]
#
# The binary defaults to target/release/mrpp (build it with cargo build --release).
set -euo pipefail
cd "$(dirname "$0")/../.."
bin="${1:-target/release/mrpp}"
shift || true
d=data/hstar-paper
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cases=()
for n in 6 7 8 9 10 11 12 13 14 15; do cases+=("1-$n $d/scenario1/scenery.txt $d/scenario1/${n}coordinates.txt"); done
for n in 3 4 5 6; do cases+=("2-${n}x4 $d/scenario2/scenery_4rooms_B.txt $d/scenario2/${n}robots-per-room.txt"); done
for n in 10 15 20 25 30; do cases+=("3-$n $d/scenario3/scenery_warehouse.txt $d/scenario3/${n}warehouse"); done
printf '%-8s %6s %5s %9s  %s\n' instance soc mksp ms paths-sha256
for c in "${cases[@]}"; do
  set -- $c
  name=$1 map=$2 scen=$3
  "$bin" -q solve --map "$map" --scen "$scen" --planner hstar --out "$out/$name.json" "${@:4}" || true
  python3 - "$out/$name.json" "$name" <<'PY'
import hashlib, json, sys
e = json.load(open(sys.argv[1]))
m = e.get("metrics") or {}
paths = json.dumps([a.get("path") for a in e.get("agents", [])], separators=(",", ":"))
ms = e.get("run", {}).get("runtime_ms", e.get("runtime_ms", float("nan")))
print(f"{sys.argv[2]:<8} {m.get('sum_of_costs', '-'):>6} {m.get('makespan', '-'):>5} {ms:>9.2f}  {hashlib.sha256(paths.encode()).hexdigest()[:16]}")
PY
done

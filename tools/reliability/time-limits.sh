#!/usr/bin/env bash
# Every grid planner against its time limit on a 1000 x 1000 map (10% walls) with 2000 agents:
# wall time and peak memory of the whole `mrpp solve` process (loading included), per planner and
# limit. Usage: tools/reliability/time-limits.sh [MRPP_BINARY] (default: target/release/mrpp,
# built with `cargo build --release`). The promise: wall <= limit * 1.1 + 0.05 s, peak < 500 MB.
set -euo pipefail
cd "$(dirname "$0")/../.."
mrpp=${1:-target/release/mrpp}
dir=target/reliability
mkdir -p "$dir"
"$mrpp" gen map --width 1000 --height 1000 --obstacles 0.1 --seed 0 --out "$dir/random-1000-1000-10.map" -q
"$mrpp" gen scen --map "$dir/random-1000-1000-10.map" --agents 2000 --seed 0 --out "$dir/random-1000-2000.scen" -q
echo "limit_s planner exit wall_s peak_mb promise_s within"
for limit in 0.1 0.5 1; do
  for planner in hstar ca hca whca coevolution nsga3 pibt lacam cbs eecbs; do
    set +e
    /usr/bin/time -f "%e %M" -o "$dir/time.txt" "$mrpp" solve -q --map "$dir/random-1000-1000-10.map" \
      --scen "$dir/random-1000-2000.scen" --planner "$planner" --time-limit "$limit"
    code=$?
    set -e
    read -r wall kb < <(tail -1 "$dir/time.txt")
    python3 - "$limit" "$planner" "$code" "$wall" "$kb" <<'PY'
import sys
limit, planner, code, wall, kb = sys.argv[1:]
promise = float(limit) * 1.1 + 0.05
print(limit, planner, code, wall, round(int(kb) / 1024), round(promise, 3),
      "yes" if float(wall) <= promise and int(kb) < 500 * 1024 else "NO")
PY
  done
done

#!/usr/bin/env bash
# Runs the cargo-fuzz targets in fuzz/ (docs/reliability.md, "Fuzzed parsers").
#
#   tools/fuzz/run.sh [--seconds S | --runs N] [--jobs J] [TARGET...]
#   tools/fuzz/run.sh --save-corpus [TARGET...]
#
# Each target runs for S seconds (default 30) or N executions, J targets at a time (default 2),
# starting from its committed corpus (fuzz/corpus/T.tar.gz, unpacked into target/) and seeds
# (fuzz/seeds/T); inputs found on the way go to target/fuzz-corpus/T, so the checkout is left as
# it was. Prints one line per target (executions, seconds, result) and exits 1 if any target
# crashed; the crashing input is in fuzz/artifacts/T/ and the log in target/fuzz-logs/T.log.
# --save-corpus merges what the runs found into fuzz/corpus/T.tar.gz, minimised (libFuzzer's
# -merge=1: the fewest inputs that keep the coverage) and kept small (inputs of at most 512
# bytes). Needs the nightly toolchain; installs cargo-fuzz when it is missing.
set -euo pipefail
cd "$(dirname "$0")/../.."

limit=(-max_total_time=30)
jobs=2
save=0
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) limit=(-max_total_time="$2"); shift 2 ;;
    --runs) limit=(-runs="$2"); shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --save-corpus) save=1; shift ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    -*) echo "fuzz: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done

if ! cargo +nightly --version >/dev/null 2>&1; then
  echo "fuzz: SKIP (no nightly toolchain: rustup toolchain install nightly)"
  exit 0
fi
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
  cargo install --quiet cargo-fuzz --version 0.13.2 --locked
fi
cargo +nightly fuzz build -O
[ ${#targets[@]} -gt 0 ] || mapfile -t targets < <(cargo +nightly fuzz list)

mkdir -p target/fuzz-logs
# The committed corpus of target T, unpacked (empty when there is none).
committed() {
  local dir="target/fuzz-corpus-committed/$1"
  rm -rf "$dir" && mkdir -p "$dir"
  [ -f "fuzz/corpus/$1.tar.gz" ] && tar -xzf "fuzz/corpus/$1.tar.gz" -C "$dir"
  echo "$dir"
}
export -f committed

if [ "$save" = 1 ]; then
  for t in "${targets[@]}"; do
    base=$(committed "$t")
    merged=$(mktemp -d)
    mkdir -p "target/fuzz-corpus/$t"
    cargo +nightly fuzz run -O "$t" "$merged" "$base" "target/fuzz-corpus/$t" -- -merge=1 -max_len=512 \
      > "target/fuzz-logs/$t-merge.log" 2>&1
    tar -czf "fuzz/corpus/$t.tar.gz.tmp" -C "$merged" . && mv "fuzz/corpus/$t.tar.gz.tmp" "fuzz/corpus/$t.tar.gz"
    printf '%-18s %6s inputs  %8s bytes compressed\n' "$t" "$(ls "$merged" | wc -l)" "$(wc -c < "fuzz/corpus/$t.tar.gz")"
    rm -rf "$merged"
  done
  exit 0
fi

export LIMIT="${limit[*]}"
run_one() {
  local t="$1" start end rc=0 base
  mkdir -p "target/fuzz-corpus/$t"
  base=$(committed "$t")
  start=$(date +%s)
  # shellcheck disable=SC2086
  cargo +nightly fuzz run -O "$t" "target/fuzz-corpus/$t" "$base" "fuzz/seeds/$t" -- \
    $LIMIT -print_final_stats=1 > "target/fuzz-logs/$t.log" 2>&1 || rc=$?
  end=$(date +%s)
  local runs
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "target/fuzz-logs/$t.log" | grep -o '[0-9]*$' || echo '?')
  if [ "$rc" -eq 0 ]; then
    printf '%-18s %12s runs %6ss  ok\n' "$t" "$runs" "$((end - start))"
  else
    printf '%-18s %12s runs %6ss  CRASH (exit %s, log target/fuzz-logs/%s.log)\n' "$t" "$runs" "$((end - start))" "$rc" "$t"
    tail -40 "target/fuzz-logs/$t.log" >&2
    return 1
  fi
}
export -f run_one
printf '%s\n' "${targets[@]}" | xargs -P "$jobs" -I{} bash -c 'run_one {}'

#!/usr/bin/env bash
# Runs the example sweep as 3 shards with GNU parallel (2 at a time), merges
# the parts, and checks that the merged records.csv equals an unsharded run's
# (runtime_ms aside). Prints `SKIP: ...` and exits 0 where GNU parallel can't
# be installed; exits 1 if the records differ.
# Env: MRPP (default target/release/mrpp), CONFIG (default
# bench/configs/example.toml), KEEP_TMP=1 keeps the temp dir.
set -euo pipefail

REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$REPO"

skip() { echo "SKIP: $*"; exit 0; }
abspath() { case $1 in /*) echo "$1" ;; *) echo "$REPO/$1" ;; esac; }

MRPP=$(abspath "${MRPP:-target/release/mrpp}")
CONFIG=$(abspath "${CONFIG:-bench/configs/example.toml}")

# Build the CLI once if the default binary is missing.
if [[ ! -x $MRPP && $MRPP == "$REPO/target/release/mrpp" ]]; then
    cargo build --release -p mrpp-cli
fi
[[ -x $MRPP ]] || { echo "error: $MRPP is not executable" >&2; exit 1; }

TMP=$(mktemp -d /tmp/parallel-local-test.XXXXXX)
trap 'if [[ ${KEEP_TMP:-0} == 1 ]]; then echo "kept $TMP"; else rm -rf "$TMP"; fi' EXIT

# GNU parallel (moreutils' `parallel` is another program).
if ! parallel --version 2>/dev/null | grep -q 'GNU parallel'; then
    [[ $(id -u) == 0 ]] || skip "GNU parallel cannot be installed here (not root)"
    command -v apt-get >/dev/null || skip "GNU parallel cannot be installed here (no apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    apt_install() { apt-get install -y --no-install-recommends parallel >"$TMP/apt.log" 2>&1; }
    if ! apt_install; then
        apt-get update >>"$TMP/apt.log" 2>&1 || true  # a fresh machine may have no lists
        apt_install || skip "GNU parallel cannot be installed here ($(grep -E '^E:' "$TMP/apt.log" | tail -1 || tail -1 "$TMP/apt.log"))"
    fi
fi
parallel --version | head -n 1 || true

PARTS=$TMP/parts MERGED=$TMP/merged WHOLE=$TMP/whole
mkdir -p "$PARTS"
start=$SECONDS
# --halt now,fail=1: stop at the first failed shard and exit non-zero.
parallel --will-cite --halt now,fail=1 -j 2 \
    "$MRPP" bench run --config "$CONFIG" --shard {}/3 --out "$PARTS" ::: 1 2 3 >"$TMP/shards.log" 2>&1 \
    || { echo "error: a shard failed" >&2; tail -n 30 "$TMP/shards.log" >&2; exit 1; }
echo "3 shards done in $((SECONDS - start)) s"
"$MRPP" bench merge --out "$MERGED" "$PARTS" >/dev/null
"$MRPP" bench run --config "$CONFIG" --out "$WHOLE" >"$TMP/whole.log" 2>&1

bash "$REPO/tools/cluster/same-records.sh" "$WHOLE/records.csv" "$MERGED/records.csv" "GNU parallel run of 3 shards"

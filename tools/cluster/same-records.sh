#!/usr/bin/env bash
# Usage: same-records.sh WHOLE/records.csv MERGED/records.csv LABEL
# Compares two records.csv files without their runtime_ms column (found by its header name;
# python3's csv module if there, else awk, fine while no field holds a quoted comma). Prints
# `OK: LABEL merged equals the unsharded run` and exits 0, or prints the diff and exits 1.
set -euo pipefail
strip() {
    if command -v python3 >/dev/null; then
        python3 -c 'import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline="")))
c = rows[0].index("runtime_ms")
w = csv.writer(sys.stdout, lineterminator="\n")
for r in rows: w.writerow(r[:c] + r[c + 1:])' "$1"
    else
        awk -F, -v OFS=, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "runtime_ms") c = i
                if (!c) { print "no runtime_ms column in " FILENAME > "/dev/stderr"; exit 2 } }
            { out = ""; for (i = 1; i <= NF; i++) if (i != c) out = out (out == "" ? "" : OFS) $i; print out }' "$1"
    fi
}
if ! diff -u <(strip "$1") <(strip "$2"); then
    echo "FAIL: merged shards differ from the unsharded run (diff: whole -> merged)"
    exit 1
fi
echo "OK: $3 merged equals the unsharded run"

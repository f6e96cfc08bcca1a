#!/usr/bin/env bash
# Usage: same-records.sh WHOLE/records.csv MERGED/records.csv LABEL
# Compares two records.csv files without their machine-dependent columns (runtime_ms, and where
# present first_solution_ms and peak_memory_mb; found by their header names; python3's csv module
# if there, else awk, fine while no field holds a quoted comma). Prints
# `OK: LABEL merged equals the unsharded run` and exits 0, or prints the diff and exits 1.
set -euo pipefail
strip() {
    if command -v python3 >/dev/null; then
        python3 -c 'import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline="")))
drop = {"runtime_ms", "first_solution_ms", "peak_memory_mb"}
keep = [i for i, h in enumerate(rows[0]) if h not in drop]
if len(keep) == len(rows[0]):
    sys.exit("no runtime_ms column in " + sys.argv[1])
w = csv.writer(sys.stdout, lineterminator="\n")
for r in rows: w.writerow([r[i] for i in keep if i < len(r)])' "$1"
    else
        awk -F, -v OFS=, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "runtime_ms" || $i == "first_solution_ms" || $i == "peak_memory_mb") d[i] = 1
                if (length(d) == 0) { print "no runtime_ms column in " FILENAME > "/dev/stderr"; exit 2 } }
            { out = ""; n = 0; for (i = 1; i <= NF; i++) if (!(i in d)) { out = out (n ? OFS : "") $i; n = 1 } print out }' "$1"
    fi
}
if ! diff -u <(strip "$1") <(strip "$2"); then
    echo "FAIL: merged shards differ from the unsharded run (diff: whole -> merged)"
    exit 1
fi
echo "OK: $3 merged equals the unsharded run"

#!/usr/bin/env python3
"""Independent checker of MovingAI benchmark files (Python standard library only, no mrpp code).

    tools/check/movingai.py MAP [SCEN ...]

Checks MAP against the format of the MovingAI benchmark pages (N. Sturtevant, "Benchmarks for
grid-based pathfinding", IEEE TCIAIG 2012; https://movingai.com/benchmarks/formats.html): a
header of `type`, `height` and `width` lines (any order), a `map` line, then exactly `height`
rows of `width` terrain characters from `.G@OTSW`. Each SCEN must start with `version 1` (or
`version 1.0`) and hold lines of 9 tab-separated fields: bucket, map file, map width, map height,
start x, start y, goal x, goal y, optimal length; the map size must be MAP's, the cells inside
it and passable (`.`, `G`, `S`), and the length a number.

Prints one JSON line ({"valid": ..., "width": ..., "height": ..., "free": ..., "agents": [...]})
and exits 0 when every file is valid, 1 with the first problem (file:line: rule) otherwise.
"""

import json
import sys

TERRAIN = set(".G@OTSW")
PASSABLE = set(".GS")


class Invalid(Exception):
    pass


def read_map(path):
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    header = {}
    i = 0
    while True:
        if i >= len(lines):
            raise Invalid(f"{path}:{i}: no `map` line")
        words = lines[i].strip().split()
        i += 1
        if not words:
            continue
        if words == ["map"]:
            break
        if len(words) != 2 or words[0] not in ("type", "height", "width"):
            raise Invalid(f"{path}:{i}: unexpected header line {lines[i - 1]!r}")
        if words[0] in header:
            raise Invalid(f"{path}:{i}: `{words[0]}` given twice")
        header[words[0]] = words[1]
    for key in ("height", "width"):
        if key not in header or not header[key].isdigit() or int(header[key]) == 0:
            raise Invalid(f"{path}:{i}: `{key}` missing or not a positive integer")
    h, w = int(header["height"]), int(header["width"])
    rows = []
    for k in range(h):
        if i + k >= len(lines):
            raise Invalid(f"{path}:{i + k + 1}: {k} of {h} rows")
        row = lines[i + k].rstrip("\r")
        if len(row) != w:
            raise Invalid(f"{path}:{i + k + 1}: row of {len(row)} cells, expected {w}")
        bad = set(row) - TERRAIN
        if bad:
            raise Invalid(f"{path}:{i + k + 1}: terrain {sorted(bad)} not in {''.join(sorted(TERRAIN))}")
        rows.append(row)
    rest = [l for l in lines[i + h:] if l.strip()]
    if rest:
        raise Invalid(f"{path}:{i + h + 1}: text after the last row")
    return w, h, rows


def check_scen(path, w, h, rows):
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    first = lines[0].strip() if lines else ""
    if first not in ("version 1", "version 1.0"):
        raise Invalid(f"{path}:1: expected `version 1`, found {first!r}")
    agents = []
    for no, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        f = line.rstrip("\r").split("\t")
        if len(f) != 9:
            raise Invalid(f"{path}:{no}: {len(f)} tab-separated fields, expected 9")
        try:
            bucket, mw, mh, sx, sy, gx, gy = (int(f[k]) for k in (0, 2, 3, 4, 5, 6, 7))
            float(f[8])
        except ValueError:
            raise Invalid(f"{path}:{no}: a number field is not a number")
        if bucket < 0:
            raise Invalid(f"{path}:{no}: negative bucket")
        if (mw, mh) != (w, h):
            raise Invalid(f"{path}:{no}: map size {mw}x{mh}, the map is {w}x{h}")
        for x, y, what in ((sx, sy, "start"), (gx, gy, "goal")):
            if not (0 <= x < w and 0 <= y < h):
                raise Invalid(f"{path}:{no}: {what} ({x},{y}) off the map")
            if rows[y][x] not in PASSABLE:
                raise Invalid(f"{path}:{no}: {what} ({x},{y}) on `{rows[y][x]}`")
        agents.append([sx, sy, gx, gy])
    return agents


def main(argv):
    if len(argv) < 2:
        print(__doc__.strip().split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        w, h, rows = read_map(argv[1])
        agents = [len(check_scen(s, w, h, rows)) for s in argv[2:]]
    except (Invalid, OSError, UnicodeDecodeError) as e:
        print(json.dumps({"valid": False, "error": str(e)}))
        return 1
    free = sum(c in PASSABLE for r in rows for c in r)
    print(json.dumps({"valid": True, "width": w, "height": h, "free": free, "agents": agents}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

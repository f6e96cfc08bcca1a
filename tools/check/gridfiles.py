"""Map and scenario readers shared by tools/check/tracker.py and tools/check/planviz.py (stdlib only).

Written from the MovingAI format pages and the checkers' docstrings, not from mrpp's Rust
readers. Lenient where the checkers are: a map cell is free or blocked, never malformed.

- read_text: a file as text (UTF-8, a byte-order mark dropped);
- read_map: a MovingAI `.map` (header `type`/`height`/`width`/`map`; '.', 'G', 'S', 'E' free,
  anything else blocked; at least `height` rows) or an ASCII map ('#' wall, space or '.' free,
  a row shorter than the longest free beyond its end);
- read_scen: a MovingAI `.scen` (`version 1`, then per agent: bucket, map, width, height,
  start x, start y, goal x, goal y, optimal length; tab- or space-separated).

Cells are (x, y): x the column, y the row, from 0 at the top-left.
"""


class Invalid(Exception):
    """An input breaks a rule; the message says which."""


def read_text(path):
    try:
        with open(path, "rb") as f:
            return f.read().decode("utf-8-sig")
    except OSError as e:
        raise Invalid(f"cannot read {path}: {e.strerror}")
    except UnicodeDecodeError:
        raise Invalid(f"{path}: not UTF-8 text")


def read_map(path):
    """The set of free (x, y) cells and (width, height)."""
    lines = read_text(path).replace("\r", "").split("\n")
    if lines and lines[0].startswith("type"):
        header = {}
        k = 1
        while k < len(lines) and lines[k].strip() != "map":
            parts = lines[k].split()
            if len(parts) == 2:
                header[parts[0]] = parts[1]
            k += 1
        try:
            w, h = int(header["width"]), int(header["height"])
        except (KeyError, ValueError):
            raise Invalid(f"{path}: MovingAI header without width/height")
        rows = lines[k + 1:k + 1 + h]
        if len(rows) < h:
            raise Invalid(f"{path}: {len(rows)} map rows, header says {h}")
        free = {(x, y) for y, row in enumerate(rows) for x, c in enumerate(row[:w]) if c in ".GSE"}
        return free, (w, h)
    while lines and lines[-1] == "":
        lines.pop()
    w = max((len(r) for r in lines), default=0)
    free = {(x, y) for y, row in enumerate(lines) for x in range(w)
            if (row[x] if x < len(row) else " ") in " ."}
    return free, (w, len(lines))


def read_scen(path):
    """[(start, goal)] of the scenario, cells as (x, y)."""
    agents = []
    for no, line in enumerate(read_text(path).splitlines(), 1):
        if not line.strip() or line.startswith("version"):
            continue
        f = line.split("\t") if "\t" in line else line.split()
        if len(f) < 8:
            raise Invalid(f"{path}:{no}: a scenario line has 9 fields, found {len(f)}")
        try:
            sx, sy, gx, gy = (int(v) for v in f[4:8])
        except ValueError:
            raise Invalid(f"{path}:{no}: coordinates are not integers")
        agents.append(((sx, sy), (gx, gy)))
    return agents

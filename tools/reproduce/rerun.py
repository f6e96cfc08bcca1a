#!/usr/bin/env python3
r"""Re-run the reproduction write-ups and diff their tables (Python 3 standard library only).

Usage:
  python3 tools/reproduce/rerun.py [--only hstar,ga-formation] [--workdir DIR] [--mrpp PATH]
                                   [--skip-build] [--skip-tests] [--commands 2-4,6]
  python3 tools/reproduce/rerun.py --list [--only ...]
  python3 tools/reproduce/rerun.py --compare-only DIR [--partial] [--only ...]
  python3 tools/reproduce/rerun.py --self-test

For each write-up docs/reproduction/<name>.md (hstar, gp-trees, ga-formation, hbmo; or those
named by --only) it

1. extracts the shell block of the section "## How to re-run" and splits it into top-level
   commands (a multi-line `for` loop is one command);
2. runs them, one after another in one bash process (so `export` and `M=...` carry over), in a
   scratch folder of the write-up's own, WORKDIR/<name>, filled with `git archive` of the
   repository's HEAD (what a fresh clone holds; --rev picks another commit). Every output lands
   under that folder, never in the repository. `./target/release/mrpp` in the block is replaced
   by the binary to use (--mrpp PATH; default: $CARGO_TARGET_DIR/release/mrpp or
   <repo>/target/release/mrpp when --skip-build drops the block's `cargo build` lines, otherwise
   the binary that `cargo build` makes). Each command's exit code and wall time go to the
   console and to WORKDIR/<name>/.rerun/times.tsv; the commands' own output to
   WORKDIR/<name>/.rerun/run.log;
3. diffs every table of the write-up against the generated table its marker names (below), with
   the timing columns left out, and prints a summary per write-up: tables matched, tables that
   differ (cell by cell), tables not diffed (with the reason). Exit 1 on any difference, on a
   table without a marker or on a missing output (unless --partial, which lists the tables whose
   outputs are missing as "not checked"); 2 on wrong usage.

--compare-only DIR skips step 2 and diffs against outputs already produced: DIR is the folder
the block ran in (a clone's root, where `out/...` lies), or a WORKDIR of an earlier run (then
DIR/<name> is used for each write-up). So the long blocks can run once, e.g. on a cluster, and
be compared later.

Markers. A table of a write-up is diffed against what its marker, an HTML comment placed
between the previous table (or the start) and the table, names; GitHub does not show it:

  <!-- rerun: out/hstar-table2/table2.md table 2 -->

The body is a list of clauses, one a line (or separated by ";"; a line starting with "|"
continues the previous clause, a line starting with "#" is a comment, new lines inside brackets
do not end a clause):

  SOURCE [| OP]...        rows of the generated table; several such clauses are concatenated
                          in order ("rows from A, then B")
  let NAME = EXPR         a Python value (often a lambda) for the expressions that follow
  ignore cols: A, "B, c"  doc columns not compared (labels, the paper's own values); the
                          reason may follow " -- "
  ignore rows: 9, 10      doc rows (1-based) not compared, likewise
  derived: HOW            the whole marker: the table is not diffed, HOW says how it was made
                          (listed as "not diffed" with that reason)

SOURCE is PATH (relative to the run folder) of a Markdown page, optionally followed by
`under "TEXT"` (the tables after the first line containing TEXT; repeatable, each searched after
the previous) and `table N` (the N-th table from there, default 1); or PATH of a .csv file (the
whole file as one table); or `py: EXPR`, a Python expression giving a Table or a list of dicts
(header -> cell). Expressions see the helpers of `Env.namespace`: md(path, table=1, under=None),
csv(path), tables(path), text(path), matches(path, regex) (the named groups of every match, as
rows), num(cell), nums(cell), fmt(x, d), pct(x, d), signed_pct(x, d), mean(xs), table(dicts);
a table's .dicts(), .col(name), .get(header=value, ...) and .where(...) read it. A repeated
header is reached as "name#2" (and a generated column named "name#2" pairs with the doc's second
"name").

OP is one of
  where EXPR               keep rows for which EXPR (Python; `c` is the row, header -> cell,
                           `i` its 1-based index) is true
  cols A, B as "X", C      keep these columns in this order, optionally renamed
  rename A as "X", ...     rename columns, keep all
  set "NAME" = EXPR        add (or replace) a column computed per row (EXPR as for where)
  rows 1-3,5               keep rows by position (1-based)
  sub "REGEX" => "REPL"    re.sub on every cell (e.g. sub "^0\.000$" => "< 0.001")

Comparison: doc columns are looked up by header in the generated table (extra generated
columns are ignored, repeated headers pair up in order); rows are compared in order and must be
as many. Cells are compared after normalising: bold markers, "\|", the Unicode minus,
thousands separators ("3 737", "1,330") and the number format ("100" = "100.0") do not count.
Timing columns: a header that names a time unit or a clock (s, ms, seconds, time, wall, CPU,
runtime, minutes, hours; "time steps" is not one) is not compared.
"""

import argparse
import csv as csv_module
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs" / "reproduction"
WRITEUPS = ["hstar", "gp-trees", "ga-formation", "hbmo"]
MRPP_IN_BLOCK = "./target/release/mrpp"


class UsageError(Exception):
    pass


# ------------------------------------------------------------------ Markdown tables


def split_row(line):
    """Cells of a Markdown table row ("| a | b |"), honouring "\\|" inside cells."""
    s = line.strip()
    if s.startswith("|"):
        s = s[1:]
    if s.endswith("|") and not s.endswith("\\|"):
        s = s[:-1]
    cells, cur, k = [], [], 0
    while k < len(s):
        ch = s[k]
        if ch == "\\" and k + 1 < len(s) and s[k + 1] == "|":
            cur.append("\\|")
            k += 2
            continue
        if ch == "|":
            cells.append("".join(cur).strip())
            cur = []
        else:
            cur.append(ch)
        k += 1
    cells.append("".join(cur).strip())
    return cells


SEPARATOR = re.compile(r"^\s*\|?\s*:?-{3,}:?\s*(\|\s*:?-{3,}:?\s*)*\|?\s*$")


class Table:
    """A table: headers and rows of cell strings. `line` is where it starts (1-based)."""

    def __init__(self, headers, rows, line=0, source=""):
        self.headers = list(headers)
        self.rows = [list(r) + [""] * (len(self.headers) - len(r)) for r in rows]
        self.line = line
        self.source = source

    def dicts(self):
        return [Row(self.headers, r) for r in self.rows]

    def col(self, name):
        k = self.index(name)
        return [r[k] for r in self.rows]

    def index(self, name, used=()):
        want = norm_header(name)
        for k, h in enumerate(self.headers):
            if norm_header(h) == want and k not in used:
                return k
        raise KeyError(f"no column {name!r} (have: {', '.join(self.headers)})")

    def get(self, **eq):
        """The one row whose columns equal the given values (keyword = header with spaces as
        underscores, or use where())."""
        found = self.where(**eq)
        if len(found) != 1:
            raise KeyError(f"{len(found)} rows match {eq} in {self.source}")
        return found[0]

    def where(self, **eq):
        out = []
        for d in self.dicts():
            if all(norm_cell(d[k.replace("_", " ")]) == norm_cell(str(v)) for k, v in eq.items()):
                out.append(d)
        return out

    def __repr__(self):
        return f"Table({self.headers}, {len(self.rows)} rows)"


class Row(dict):
    """A row as header -> cell; lookups ignore bold, backticks and spacing of the header; a
    repeated header's later columns are reachable as "name#2", "name#3"."""

    def __init__(self, headers, cells):
        super().__init__()
        self._keys = {}
        for h, v in zip(headers, cells):
            key = h
            n = 2
            while key in self:
                key = f"{h}#{n}"
                n += 1
            super().__setitem__(key, v)
            self._keys.setdefault(norm_header(key), key)

    def __getitem__(self, k):
        if dict.__contains__(self, k):
            return dict.__getitem__(self, k)
        nk = self._keys.get(norm_header(k))
        if nk is None:
            raise KeyError(f"no column {k!r} (have: {', '.join(self.keys())})")
        return dict.__getitem__(self, nk)


def parse_tables(text, source=""):
    """Every pipe table of a Markdown text (outside code fences), in order."""
    lines = text.splitlines()
    tables, k, fence = [], 0, None
    while k < len(lines):
        s = lines[k].strip()
        m = re.match(r"^(`{3,}|~{3,})", s)
        if m:
            if fence is None:
                fence = m.group(1)
            elif s.startswith(fence):
                fence = None
            k += 1
            continue
        if fence is None and s.startswith("|") and k + 1 < len(lines) and SEPARATOR.match(lines[k + 1]):
            headers = split_row(lines[k])
            rows, j = [], k + 2
            while j < len(lines) and lines[j].strip().startswith("|"):
                rows.append(split_row(lines[j]))
                j += 1
            tables.append(Table(headers, rows, line=k + 1, source=source))
            k = j
            continue
        k += 1
    return tables


def read_csv_table(path):
    with open(path, newline="", encoding="utf-8") as f:
        data = list(csv_module.reader(f))
    if not data:
        return Table([], [], source=str(path))
    return Table(data[0], data[1:], source=str(path))


# ------------------------------------------------------------------ normalising and diffing

TIMING = re.compile(
    r"(?<![\w'’*])(ms|s|secs?|seconds?|time|wall|cpu|runtime|minutes?|hours?)(?![\w'’])"
)


def is_timing(header):
    """Whether a column header names a time (so the column is not compared)."""
    h = norm_header(header).lower()
    h = re.sub(r"time[ -]?steps?", "", h)
    h = h.replace("(s)", "")
    return bool(TIMING.search(h))


def norm_header(h):
    """A header as matched: bold, escapes and spacing do not count, nor a "#2" suffix (how a
    recipe names the second column of a repeated header)."""
    h = re.sub(r"#\d+$", "", h)
    return re.sub(r"\s+", " ", h.replace("**", "").replace("\\|", "|").replace("\\*", "*")).strip()


NUMBER = re.compile(r"-?\d+(?:\.\d+)?")


def canon_number(m):
    x = float(m.group(0))
    if x == 0:
        x = 0.0  # -0 = 0
    return repr(int(x)) if x == int(x) and abs(x) < 1e15 else repr(x)


def norm_cell(c):
    """A cell as compared: formatting (bold, escapes, Unicode minus, thousands separators,
    spacing, number format) does not count."""
    s = c.replace("**", "").replace("\\|", "|").replace("\\*", "*").replace("\u2212", "-")
    s = re.sub(r"(?<=\d)[ ,\u202f\u2009\u00a0](?=\d{3}(?!\d))", "", s)
    s = re.sub(r"\s+", " ", s).strip()
    return NUMBER.sub(canon_number, s)


def diff_tables(doc, gen, ignore_cols=(), ignore_rows=()):
    """Compare a doc table with the generated one. Returns (problems, notes): problems are
    strings describing differences (empty = match), notes what was left out."""
    problems, notes = [], []
    ignore = {norm_header(c) for c in ignore_cols}
    cols, used, dropped = [], set(), []
    for k, h in enumerate(doc.headers):
        if norm_header(h) in ignore:
            continue
        if is_timing(h):
            dropped.append(h)
            continue
        try:
            g = gen.index(h, used)
        except KeyError:
            problems.append(f"column {h!r} is not in the generated table (it has: {' | '.join(gen.headers)})")
            continue
        used.add(g)
        cols.append((k, g, h))
    if dropped:
        notes.append("timing columns left out: " + ", ".join(dropped))
    rows = [(k, r) for k, r in enumerate(doc.rows, 1) if k not in ignore_rows]
    if len(rows) != len(gen.rows):
        problems.append(f"{len(rows)} rows in the doc, {len(gen.rows)} generated")
    for (k, drow), grow in zip(rows, gen.rows):
        label = " | ".join(c for c in drow[:2])
        for dk, gk, h in cols:
            d = drow[dk] if dk < len(drow) else ""
            g = grow[gk] if gk < len(grow) else ""
            if norm_cell(d) != norm_cell(g):
                problems.append(f"row {k} ({label}), column {h!r}: doc {d!r}, generated {g!r}")
    for k, drow in rows[len(gen.rows):]:
        problems.append(f"row {k} ({' | '.join(drow[:2])}) only in the doc")
    for grow in gen.rows[len(rows):]:
        problems.append(f"generated row ({' | '.join(grow[:2])}) not in the doc")
    return problems, notes


# ------------------------------------------------------------------ markers


def split_top(text, sep):
    """Split text at `sep` outside quotes and brackets."""
    parts, cur, depth, quote, k = [], [], 0, None, 0
    while k < len(text):
        ch = text[k]
        if quote:
            cur.append(ch)
            if ch == "\\" and k + 1 < len(text):
                cur.append(text[k + 1])
                k += 2
                continue
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
            cur.append(ch)
        elif ch in "([{":
            depth += 1
            cur.append(ch)
        elif ch in ")]}":
            depth -= 1
            cur.append(ch)
        elif depth == 0 and text.startswith(sep, k):
            parts.append("".join(cur))
            cur = []
            k += len(sep)
            continue
        else:
            cur.append(ch)
        k += 1
    parts.append("".join(cur))
    return parts


def parse_names(text):
    """A, "B, c", 'D' -> ['A', 'B, c', 'D']"""
    out = []
    for part in split_top(text, ","):
        p = part.strip()
        if not p:
            continue
        if len(p) >= 2 and p[0] == p[-1] and p[0] in "\"'":
            p = p[1:-1]
        out.append(p)
    return out


def parse_index_list(text):
    """'1-3,5' -> [1, 2, 3, 5]"""
    out = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        m = re.fullmatch(r"(\d+)\s*-\s*(\d+)", part)
        if m:
            out.extend(range(int(m.group(1)), int(m.group(2)) + 1))
        elif part.isdigit():
            out.append(int(part))
        else:
            raise ValueError(f"not a list of row numbers: {text!r}")
    return out


class Marker:
    def __init__(self, body, line):
        self.body = body.strip()
        self.line = line
        self.sources = []  # list of (source text, [op texts])
        self.ignore_cols = []
        self.ignore_rows = set()
        self.derived = None
        self.reasons = []
        self.lets = []  # (name, expression), evaluated in order before the sources
        m = re.match(r"^derived\s*:\s*(.*)$", self.body, re.S)
        if m:  # the rest of the marker is the reason, whatever it holds
            self.derived = re.sub(r"\s+", " ", m.group(1)).strip()
            return
        lines = self.body.splitlines()
        self.comments = [ln.strip().lstrip("#").strip() for ln in lines if ln.strip().startswith("#")]
        body = "\n".join(ln for ln in lines if not ln.strip().startswith("#"))
        body = re.sub(r"\n\s*\|", " |", body)  # a line starting with "|" continues a pipeline
        clauses = [x for part in split_top(body, "\n") for x in split_top(part, ";")]
        for clause in clauses:
            c = clause.strip()
            if not c:
                continue
            m = re.match(r"^derived\s*:\s*(.*)$", c, re.S)
            if m:
                self.derived = m.group(1).strip()
                continue
            m = re.match(r"^let\s+([A-Za-z_]\w*)\s*=(?!=)\s*(.*)$", c, re.S)
            if m:
                self.lets.append((m.group(1), m.group(2).strip()))
                continue
            m = re.match(r"^ignore\s+(cols|columns|rows)\s*:\s*(.*)$", c, re.S)
            if m:
                what, _, why = m.group(2).partition(" -- ")
                if m.group(1) == "rows":
                    self.ignore_rows.update(parse_index_list(what))
                    note = "rows not compared: " + what.strip()
                else:
                    self.ignore_cols.extend(parse_names(what))
                    note = "columns not compared: " + what.strip()
                self.reasons.append(note + (f" ({why.strip()})" if why.strip() else ""))
                continue
            parts = split_top(c, " | ")
            self.sources.append((parts[0].strip(), [p.strip() for p in parts[1:]]))
        if self.derived is None and not self.sources:
            raise ValueError(f"marker on line {line} names no source: {body!r}")

    def paths(self):
        """The output files this marker reads (for --list and missing-output checks)."""
        out = []
        for src, ops in self.sources:
            if not src.startswith("py:"):
                out.append(shlex.split(src)[0])
            for text in [src] + ops:
                out.extend(re.findall(r"(?:md|csv|tables|text|matches)\(\s*[\"']([^\"']+)[\"']", text))
        return list(dict.fromkeys(out))


MARKER = re.compile(r"<!--\s*rerun\s*:(.*?)-->", re.S)


def doc_tables_with_markers(text):
    """[(table, marker or None)] for every table of a write-up; a marker belongs to the first
    table after it."""
    tables = parse_tables(text)
    markers = []
    for m in MARKER.finditer(text):
        line = text.count("\n", 0, m.start()) + 1
        markers.append((line, m.group(1)))
    out, prev = [], 0
    for t in tables:
        mine = [(ln, b) for ln, b in markers if prev < ln < t.line]
        if len(mine) > 1:
            raise ValueError(f"table on line {t.line}: {len(mine)} markers before it")
        out.append((t, Marker(mine[0][1], mine[0][0]) if mine else None))
        prev = t.line
    stray = [ln for ln, _ in markers if ln > prev]
    if stray:
        raise ValueError(f"marker on line {stray[0]} is after the last table")
    return out


# ------------------------------------------------------------------ evaluating markers


def num(s):
    """The first number of a cell as a float (None if none): '71.4%' -> 71.4, '3 737' -> 3737."""
    s = norm_cell(str(s))
    m = NUMBER.search(s)
    return float(m.group(0)) if m else None


def nums(s):
    """Every number of a cell: '32.0 / 116.0' -> [32.0, 116.0]."""
    return [float(x) for x in NUMBER.findall(norm_cell(str(s)))]


def fmt(x, d=1):
    """x with d decimals ('' for None)."""
    return "" if x is None else f"{x:.{d}f}"


def pct(x, d=1):
    return "" if x is None else f"{x:.{d}f}%"


def signed_pct(x, d=1):
    """A signed percentage, '0' when it rounds to zero: 1.44 -> '+1.4%', -5.2 -> '-5.2%'."""
    if x is None:
        return ""
    return "0" if round(x, d) == 0 else f"{x:+.{d}f}%"


def mean(xs):
    xs = list(xs)
    return sum(xs) / len(xs) if xs else None


def make_table(rows, headers=None):
    """A Table from a list of dicts (headers: the first dict's keys unless given)."""
    rows = list(rows)
    if headers is None:
        headers = list(rows[0].keys()) if rows else []
    return Table(headers, [[str(r.get(h, "")) for h in headers] for r in rows])


class Env:
    """Resolves marker paths against a run folder and evaluates sources and operations."""

    def __init__(self, root):
        self.root = Path(root)
        self.cache = {}
        self.vars = {}

    def path(self, p):
        q = Path(p)
        return q if q.is_absolute() else self.root / q

    def md(self, path, table=1, under=None):
        """The table-th table of a Markdown page, after the line(s) containing `under` (a string
        or a list of strings searched one after another)."""
        full = self.path(path)
        if full not in self.cache:
            self.cache[full] = full.read_text(encoding="utf-8")
        text = self.cache[full]
        start = 0
        for u in ([under] if isinstance(under, str) else (under or [])):
            k = text.find(u, start)
            if k < 0:
                raise LookupError(f"{path}: no line containing {u!r}")
            start = k
        line0 = text.count("\n", 0, start) + 1
        tables = [t for t in parse_tables(text, str(path)) if t.line >= line0]
        if len(tables) < table:
            raise LookupError(f"{path}: fewer than {table} tables" + (f" under {under!r}" if under else ""))
        return tables[table - 1]

    def csv(self, path):
        return read_csv_table(self.path(path))

    def text(self, path):
        return self.path(path).read_text(encoding="utf-8")

    def matches(self, path, regex):
        """The named groups of every match of `regex` (multi-line) in a text file, as rows."""
        return [m.groupdict() for m in re.finditer(regex, self.text(path), re.M)]

    def tables(self, path):
        return parse_tables(self.path(path).read_text(encoding="utf-8"), str(path))

    def namespace(self, **extra):
        ns = {
            "md": self.md,
            "csv": self.csv,
            "tables": self.tables,
            "text": self.text,
            "matches": self.matches,
            "num": num,
            "nums": nums,
            "fmt": fmt,
            "pct": pct,
            "signed_pct": signed_pct,
            "mean": mean,
            "table": make_table,
            "Table": Table,
            "re": re,
            "math": math,
            "exists": lambda p: self.path(p).exists(),
        }
        ns.update(extra)
        return ns

    def eval(self, expr, **extra):
        # One globals dict, so that a `let` lambda sees the helpers and the earlier lets.
        g = {"__builtins__": __builtins__, **self.namespace(), **self.vars, **extra}
        return eval(expr, g)  # noqa: S307 - expressions from the repository's own write-ups

    def source(self, text):
        if text.startswith("py:"):
            v = self.eval(text[3:].strip())
            if isinstance(v, Table):
                return Table(v.headers, v.rows, source=text)
            return make_table(v)
        words = shlex.split(text)
        path, rest = words[0], words[1:]
        if path.endswith(".csv") and not rest:
            return self.csv(path)
        table, under, k = 1, [], 0
        while k < len(rest):
            if rest[k] == "table" and k + 1 < len(rest):
                table = int(rest[k + 1])
            elif rest[k] == "under" and k + 1 < len(rest):
                under.append(rest[k + 1])
            else:
                raise ValueError(f"cannot read source {text!r} (at {rest[k]!r})")
            k += 2
        return self.md(path, table, under)

    def op(self, t, text):
        m = re.match(r"^(\w+)\s*(.*)$", text, re.S)
        if not m:
            raise ValueError(f"empty operation in {text!r}")
        name, arg = m.group(1), m.group(2).strip()
        if name == "where":
            keep = [r for k, (r, d) in enumerate(zip(t.rows, t.dicts()), 1) if self.eval(arg, c=d, i=k)]
            return Table(t.headers, keep, source=t.source)
        if name == "cols":
            headers, idx, used = [], [], set()
            for item in split_top(arg, ","):
                parts = split_top(item.strip(), " as ")
                src = parse_names(parts[0])[0]
                dst = parse_names(parts[1])[0] if len(parts) > 1 else src
                k = t.index(src, used)
                used.add(k)
                headers.append(dst)
                idx.append(k)
            return Table(headers, [[r[k] for k in idx] for r in t.rows], source=t.source)
        if name == "rename":
            headers = list(t.headers)
            for item in split_top(arg, ","):
                parts = split_top(item.strip(), " as ")
                if len(parts) != 2:
                    raise ValueError(f"rename needs A as B: {item!r}")
                headers[t.index(parse_names(parts[0])[0])] = parse_names(parts[1])[0]
            return Table(headers, t.rows, source=t.source)
        if name == "set":
            lhs, rhs = split_top(arg, "=")[0], "=".join(split_top(arg, "=")[1:])
            col = parse_names(lhs)[0]
            vals = [str(self.eval(rhs.strip(), c=d, i=k)) for k, d in enumerate(t.dicts(), 1)]
            headers = list(t.headers)
            try:
                k = t.index(col)
                rows = [r[:k] + [v] + r[k + 1:] for r, v in zip(t.rows, vals)]
            except KeyError:
                headers.append(col)
                rows = [r + [v] for r, v in zip(t.rows, vals)]
            return Table(headers, rows, source=t.source)
        if name == "rows":
            keep = parse_index_list(arg)
            return Table(t.headers, [t.rows[k - 1] for k in keep if 0 < k <= len(t.rows)], source=t.source)
        if name == "sub":
            parts = split_top(arg, "=>")
            if len(parts) != 2:
                raise ValueError(f"sub needs \"REGEX\" => \"REPL\": {text!r}")
            pat, repl = parse_names(parts[0])[0], parse_names(parts[1])[0]
            return Table(t.headers, [[re.sub(pat, repl, c) for c in r] for r in t.rows], source=t.source)
        raise ValueError(f"unknown operation {name!r} in {text!r}")

    def build(self, marker):
        """The generated table a marker describes (rows of its sources, concatenated)."""
        result = None
        self.vars = {}
        for name, expr in marker.lets:
            self.vars[name] = self.eval(expr)
        for src, ops in marker.sources:
            t = self.source(src)
            for o in ops:
                t = self.op(t, o)
            if result is None:
                result = t
            else:
                if [norm_header(h) for h in t.headers] != [norm_header(h) for h in result.headers]:
                    raise ValueError(
                        f"sources give different columns: {' | '.join(result.headers)} and {' | '.join(t.headers)}"
                    )
                result = Table(result.headers, result.rows + t.rows, source=result.source)
        return result


# ------------------------------------------------------------------ write-ups and blocks


def read_block(text):
    """The first fenced code block of the section '## How to re-run'."""
    m = re.search(r"^## How to re-run\s*$", text, re.M)
    if not m:
        raise ValueError("no section '## How to re-run'")
    rest = text[m.end():]
    nxt = re.search(r"^## ", rest, re.M)
    if nxt:
        rest = rest[: nxt.start()]
    f = re.search(r"^(`{3,})[^\n]*\n(.*?)^\1\s*$", rest, re.M | re.S)
    if not f:
        raise ValueError("no code block in '## How to re-run'")
    return f.group(2)


def bash_complete(text):
    if text.rstrip().endswith("\\"):
        return False
    r = subprocess.run(["bash", "-n"], input=text, text=True, capture_output=True)
    return r.returncode == 0


def split_commands(block):
    """Top-level commands of a shell block: [(comment, command)]. Comment lines between
    commands are kept as the next command's description."""
    out, cur, comments = [], [], []
    for line in block.splitlines():
        if not cur and (not line.strip() or line.lstrip().startswith("#")):
            if line.strip():
                comments.append(line.strip().lstrip("#").strip())
            continue
        cur.append(line)
        text = "\n".join(cur)
        if bash_complete(text):
            out.append((" ".join(comments), text))
            cur, comments = [], []
    if cur:
        raise ValueError("the block ends inside a command: " + "\n".join(cur))
    return out


def is_cargo(cmd, verb):
    """Whether a command runs `cargo VERB` (first, or after &&, ; or a pipe)."""
    return re.search(rf"(^|&&|;|\|)\s*cargo\s+{verb}\b", cmd) is not None


class Writeup:
    def __init__(self, name):
        self.name = name
        self.path = DOCS / f"{name}.md"
        self.text = self.path.read_text(encoding="utf-8")
        self.commands = split_commands(read_block(self.text))
        self.tables = doc_tables_with_markers(self.text)


def default_binary(building):
    """The mrpp binary the block's `./target/release/mrpp` stands for, None = leave it."""
    target = os.environ.get("CARGO_TARGET_DIR")
    if building:
        return str(Path(target).resolve() / "release" / "mrpp") if target else None
    return str(Path(target).resolve() / "release" / "mrpp") if target else str(REPO / "target" / "release" / "mrpp")


def plan_commands(w, args):
    """[(index, description, command text to run or None if skipped, why skipped)]"""
    chosen = set(parse_index_list(args.commands)) if args.commands else None
    building = not args.skip_build and any(is_cargo(c, "build") for _, c in w.commands)
    binary = args.mrpp or default_binary(building)
    plan = []
    for k, (desc, cmd) in enumerate(w.commands, 1):
        skip = None
        if chosen is not None and k not in chosen:
            skip = "not in --commands"
        elif args.skip_build and is_cargo(cmd, "build"):
            skip = "--skip-build"
        elif args.skip_tests and is_cargo(cmd, "test"):
            skip = "--skip-tests"
        run = cmd
        if binary:
            run = cmd.replace(MRPP_IN_BLOCK, shlex.quote(str(Path(binary).resolve())))
        plan.append((k, desc, None if skip else run, skip))
    return plan, binary


def prepare_workdir(dest, rev):
    """A fresh copy of the repository at `rev` (git archive), unless dest already holds one."""
    stamp = dest / ".rerun" / "source"
    if stamp.exists():
        return stamp.read_text().strip()
    dest.mkdir(parents=True, exist_ok=True)
    commit = subprocess.run(
        ["git", "-C", str(REPO), "rev-parse", rev], check=True, capture_output=True, text=True
    ).stdout.strip()
    arch = subprocess.Popen(["git", "-C", str(REPO), "archive", "--format=tar", commit], stdout=subprocess.PIPE)
    subprocess.run(["tar", "-x", "-C", str(dest)], stdin=arch.stdout, check=True)
    if arch.wait() != 0:
        raise RuntimeError("git archive failed")
    stamp.parent.mkdir(parents=True, exist_ok=True)
    stamp.write_text(commit + "\n")
    return commit


def run_block(w, args, dest):
    plan, binary = plan_commands(w, args)
    if binary and not Path(binary).exists() and not any(
        c and is_cargo(c, "build") for _, _, c, _ in plan
    ):
        raise UsageError(f"{binary} does not exist: build it, or pass --mrpp PATH")
    commit = prepare_workdir(dest, args.rev)
    meta = dest / ".rerun"
    script = ["cd " + shlex.quote(str(dest))]
    for k, desc, cmd, skip in plan:
        if cmd is None:
            continue
        script += [
            f"echo '@@rerun start {k}'",
            "__rerun_t0=$EPOCHREALTIME",
            cmd,
            "__rerun_rc=$?",
            f"echo \"@@rerun end {k} $__rerun_rc $__rerun_t0 $EPOCHREALTIME\"",
        ]
    (meta / "block.sh").write_text("\n".join(script) + "\n")
    print(f"== {w.name}: running in {dest} (commit {commit[:10]}, mrpp {binary or './target/release/mrpp'})", flush=True)
    for k, desc, cmd, skip in plan:
        if cmd is None:
            print(f"   #{k} skipped ({skip}): {first_line(w.commands[k - 1][1])}")
    times = []
    log = open(meta / "run.log", "w", encoding="utf-8")
    total0 = time.time()
    proc = subprocess.Popen(
        ["bash", str(meta / "block.sh")], stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT, text=True, errors="replace",
    )
    for line in proc.stdout:
        log.write(line)
        if line.startswith("@@rerun start"):
            k = int(line.split()[2])
            print(f"   #{k} {first_line(w.commands[k - 1][1])}", flush=True)
        elif line.startswith("@@rerun end"):
            _, _, k, rc, t0, t1 = line.split()
            secs = float(t1.replace(",", ".")) - float(t0.replace(",", "."))  # a locale's decimal comma
            times.append((int(k), int(rc), secs))
            print(f"      exit {rc}, {secs:.1f} s", flush=True)
        elif args.verbose:
            sys.stdout.write("      | " + line)
    proc.wait()
    log.close()
    with open(meta / "times.tsv", "w") as f:
        f.write("command\texit\tseconds\ttext\n")
        for k, rc, secs in times:
            f.write(f"{k}\t{rc}\t{secs:.1f}\t{first_line(w.commands[k - 1][1])}\n")
    total = time.time() - total0
    print(f"   {w.name}: block done in {total:.1f} s; log {meta / 'run.log'}")
    return times, total


def first_line(cmd):
    s = cmd.strip().splitlines()[0]
    return s if len(s) <= 110 else s[:107] + "..."


# ------------------------------------------------------------------ comparing


def describe_table(text, table):
    """The heading a doc table is under, for messages."""
    text = MARKER.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    head, fence = "", None
    for line in text.splitlines()[: table.line]:
        m = re.match(r"^(`{3,}|~{3,})", line.strip())
        if m:
            fence = None if fence and line.strip().startswith(fence) else (fence or m.group(1))
        elif fence is None and line.startswith("#"):
            head = line.lstrip("#").strip()
    return head


def compare_writeup(w, root, partial, out=sys.stdout):
    """Diff every table of a write-up against the outputs under root. Returns counts."""
    env = Env(root)
    counts = {"matched": 0, "differ": 0, "not diffed": 0, "unmarked": 0, "missing": 0, "error": 0}
    print(f"== {w.name}: tables of docs/reproduction/{w.name}.md against {root}", file=out)
    for n, (t, m) in enumerate(w.tables, 1):
        where = f"table {n} (line {t.line}, under \"{describe_table(w.text, t)}\")"
        if m is None:
            counts["unmarked"] += 1
            print(f"   UNMARKED   {where}: no <!-- rerun: ... --> marker", file=out)
            continue
        if m.derived is not None:
            counts["not diffed"] += 1
            print(f"   NOT DIFFED {where}: {m.derived}", file=out)
            continue
        missing = [p for p in m.paths() if not env.path(p).exists()]
        if missing:
            counts["missing"] += 1
            tag = "NOT CHECKED" if partial else "MISSING"
            print(f"   {tag:<10} {where}: output missing: {', '.join(missing)}", file=out)
            continue
        try:
            gen = env.build(m)
            problems, notes = diff_tables(t, gen, m.ignore_cols, m.ignore_rows)
        except FileNotFoundError as e:  # a path the marker builds in an expression
            counts["missing"] += 1
            tag = "NOT CHECKED" if partial else "MISSING"
            missing = os.path.relpath(e.filename, root) if e.filename else str(e)
            print(f"   {tag:<10} {where}: output missing: {missing}", file=out)
            continue
        except Exception as e:  # a marker that does not fit its output is a difference too
            counts["error"] += 1
            print(f"   ERROR      {where}: {type(e).__name__}: {e}", file=out)
            continue
        src = re.sub(r"\s+", " ", "; ".join(s for s, _ in m.sources))
        if len(src) > 100:
            src = src[:97] + "..."
        if problems:
            counts["differ"] += 1
            print(f"   DIFFERS    {where} vs {src}:", file=out)
            for p in problems[:40]:
                print(f"      - {p}", file=out)
            if len(problems) > 40:
                print(f"      ... and {len(problems) - 40} more", file=out)
        else:
            counts["matched"] += 1
            extra = f" ({'; '.join(notes + m.reasons)})" if notes or m.reasons else ""
            print(f"   MATCHES    {where} = {src}{extra}", file=out)
    c = counts
    print(
        f"   {w.name}: {c['matched']} matched, {c['differ'] + c['error']} differ, {c['not diffed']} not diffed"
        + (f", {c['missing']} {'not checked (outputs missing)' if partial else 'with missing outputs'}" if c["missing"] else "")
        + (f", {c['unmarked']} without a marker" if c["unmarked"] else ""),
        file=out,
    )
    return counts


def list_writeup(w, args):
    plan, binary = plan_commands(w, args)
    print(f"== {w.name} (docs/reproduction/{w.name}.md): {len(w.commands)} commands, mrpp = {binary or './target/release/mrpp (built by the block)'}")
    for k, desc, cmd, skip in plan:
        text = w.commands[k - 1][1]
        if desc:
            print(f"   # {desc}")
        lines = text.splitlines()
        print(f"   #{k}{' [skipped: ' + skip + ']' if skip else ''} {lines[0]}")
        for line in lines[1:]:
            print(f"       {line}")
    print(f"   tables: {len(w.tables)}")
    for n, (t, m) in enumerate(w.tables, 1):
        head = describe_table(w.text, t)
        if m is None:
            print(f"   {n}. line {t.line} [{head}]: NO MARKER")
        elif m.derived is not None:
            print(f"   {n}. line {t.line} [{head}]: not diffed: {m.derived}")
        else:
            print(f"   {n}. line {t.line} [{head}]:")
            for line in m.body.splitlines():
                if line.strip():
                    print(f"        {line.strip()}")


# ------------------------------------------------------------------ self-test


def self_test():
    fails = []

    def check(name, got, want):
        if got != want:
            fails.append(f"{name}: got {got!r}, want {want!r}")

    # tables
    page = (
        "# T\n\n| a | b \\| c | wall time s |\n|---|---|---|\n| 1 | x | 3.2 |\n| 2 | **y** | 9 |\n\n"
        "```\n| not | a |\n|---|---|\n```\n\n## Sec\n\n| k | v |\n|---|---|\n| p | 1,330 |\n"
    )
    ts = parse_tables(page)
    check("two tables outside fences", len(ts), 2)
    check("escaped pipe", ts[0].headers, ["a", "b \\| c", "wall time s"])
    check("rows", ts[0].rows, [["1", "x", "3.2"], ["2", "**y**", "9"]])
    check("table line", ts[1].line, 15)
    # timing columns
    for h, want in [
        ("H* ms", True), ("GA ms / generation", True), ("roadmap ms", True), ("wall time s", True),
        ("GP seconds per problem (mean / max)", True), ("CPU", True), ("runtime_ms", False),
        ("PSW mean time steps", False), ("H* ours", False), ("robot(s)", False), ("GP's total", False),
        ("steps (mean ± sd)", False), ("time", True), ("Enol2023 s", True),
    ]:
        check(f"is_timing({h!r})", is_timing(h), want)
    # cells
    check("thousands", norm_cell("3 737"), norm_cell("3737"))
    check("comma thousands", norm_cell("1,330: 71.4%"), norm_cell("1330: 71.4%"))
    check("not a list", norm_cell("32 / 116") == norm_cell("32 / 1160"), False)
    check("bold, minus", norm_cell("**−5.2%**"), norm_cell("-5.2%"))
    check("number format", norm_cell("100%"), norm_cell("100.0%"))
    check("-0", norm_cell("-0.00"), norm_cell("0.00"))
    check("decimals count", norm_cell("5.51") == norm_cell("5.5"), False)
    check("num", num("1,330: 71.4%"), 1330.0)
    check("nums", nums("32.0 / 116.0 (4/10)"), [32.0, 116.0, 4.0, 10.0])
    # markers
    doc = (
        "intro\n<!-- rerun: out/a/t.md table 2 | where c['k'] != 'x' | cols k, \"v, w\" as v -->\n"
        "| k | v |\n|---|---|\n| a | 1 |\n\n<!-- rerun:\n  out/b.csv | cols k, v\n  out/c.csv | cols k, v\n"
        "  ignore rows: 3 -- the paper's row\n-->\n| k | v | s |\n|---|---|---|\n| a | 1 | 0.1 |\n| b | 2 | 0.2 |\n"
        "| paper | 9 | |\n\n| no | marker |\n|---|---|\n\n<!-- rerun: derived: by hand -->\n| d | e |\n|---|---|\n"
    )
    tm = doc_tables_with_markers(doc)
    check("markers found", [m is not None for _, m in tm], [True, True, False, True])
    m1 = tm[0][1]
    check("one source", m1.sources, [("out/a/t.md table 2", ["where c['k'] != 'x'", "cols k, \"v, w\" as v"])])
    m2 = tm[1][1]
    check("two sources", [s for s, _ in m2.sources], ["out/b.csv", "out/c.csv"])
    check("ignore rows", m2.ignore_rows, {3})
    check("paths", m2.paths(), ["out/b.csv", "out/c.csv"])
    check("derived", tm[3][1].derived, "by hand")
    check("names", parse_names('A, "B, c", \'D\''), ["A", "B, c", "D"])
    check("index list", parse_index_list("1-3,5"), [1, 2, 3, 5])
    # evaluating a marker on files
    with tempfile.TemporaryDirectory() as d:
        Path(d, "out", "a").mkdir(parents=True)
        Path(d, "out", "a", "t.md").write_text(
            "| z |\n|---|\n| 0 |\n\n## Sec\n\n| k | v, w | ms |\n|---|---|---|\n| a | 1.0 | 3 |\n| x | 5 | 4 |\n"
        )
        Path(d, "out", "b.csv").write_text("k,v,s\na,1,9\n")
        Path(d, "out", "c.csv").write_text("k,v\nb,2.0\n")
        env = Env(d)
        g1 = env.build(m1)
        check("built table", (g1.headers, g1.rows), (["k", "v"], [["a", "1.0"]]))
        check("marker 1 matches", diff_tables(tm[0][0], g1)[0], [])
        g2 = env.build(m2)
        check("concatenated", g2.rows, [["a", "1"], ["b", "2.0"]])
        probs, notes = diff_tables(tm[1][0], g2, m2.ignore_cols, m2.ignore_rows)
        check("marker 2 matches, timing and paper row left out", probs, [])
        check("notes", notes + m2.reasons, ["timing columns left out: s", "rows not compared: 3 (the paper's row)"])
        under = env.md("out/a/t.md", under="## Sec")
        check("under", under.headers, ["k", "v, w", "ms"])
        t = env.op(env.op(under, "set \"sum\" = fmt(num(c['v, w']) + 1, 0)"), "sub \"^x$\" => \"y\"")
        check("set and sub", t.rows, [["a", "1.0", "3", "2"], ["y", "5", "4", "6"]])
        check("rows op", env.op(t, "rows 2").rows, [["y", "5", "4", "6"]])
        check("rename op", env.op(under, 'rename "v, w" as v, ms as t').headers, ["k", "v", "t"])
        Path(d, "out", "log.txt").write_text("x\nhbmo: 9 arrived, 1 deadlocks\nde: 8 arrived, 2 deadlocks\n")
        lm = Marker(
            "# a comment line\nlet get = lambda p: matches(p, r'(?P<planner>\\w+): (?P<arrived>\\d+) arrived')\n"
            "let twice = lambda p: [dict(r, n=2 * int(r['arrived'])) for r in get(p)]\npy: twice('out/log.txt')\n"
            "  | rename n as \"2x\"",
            1,
        )
        check("comments", lm.comments, ["a comment line"])
        check("let, matches, continuation", (env.build(lm).headers, env.build(lm).rows),
              (["planner", "arrived", "2x"], [["hbmo", "9", "18"], ["de", "8", "16"]]))
        check("let paths", lm.paths(), [])
        try:
            env.build(Marker("out/none.md", 1))
            check("missing file raises", False, True)
        except FileNotFoundError:
            pass
        py = Marker("py: [{'k': r['k'], 'v': r['v, w']} for r in md('out/a/t.md', under='## Sec').dicts()]", 1)
        check("py source", env.build(py).rows, [["a", "1.0"], ["x", "5"]])
        check("py paths", py.paths(), ["out/a/t.md"])
    # diffs
    doc_t = Table(["SC", "Sum", "H* ms"], [["1", "116.0", "0.2"], ["2", "120", "0.3"]])
    gen_t = Table(["SC", "Sum", "extra", "H* ms"], [["1", "116", "e", "9"], ["2", "121", "e", "9"]])
    probs, _ = diff_tables(doc_t, gen_t)
    check("cell diff", probs, ["row 2 (2 | 120), column 'Sum': doc '120', generated '121'"])
    probs, _ = diff_tables(doc_t, Table(["SC"], [["1"]]))
    check("missing column and row", len(probs), 3)
    dup_doc = Table(["a", "H* paper", "b", "H* paper"], [["1", "p", "2", "q"]])
    dup_gen = Table(["a", "H* paper", "b", "H* paper"], [["1", "p", "2", "q"]])
    check("repeated headers pair up", diff_tables(dup_doc, dup_gen)[0], [])
    check("repeated headers in a row", Row(dup_gen.headers, dup_gen.rows[0])["H* paper#2"], "q")
    # blocks
    blk = (
        "cargo build --release\nexport X=1\n# a comment\nfor s in 0 1; do\n  echo $s \\\n    done\ndone   # trailing\n"
        "./target/release/mrpp a && python3 b\n"
    )
    cmds = split_commands(blk)
    check("commands", len(cmds), 4)
    check("loop is one command", cmds[2][1].count("\n"), 3)
    check("comment kept", cmds[2][0], "a comment")
    check("cargo build", is_cargo(cmds[0][1], "build"), True)
    text = "x\n## How to re-run\n\nSome words.\n\n```sh\necho hi\n```\n\n## Next\n```\nno\n```\n"
    check("read_block", read_block(text), "echo hi\n")
    for f in fails:
        print("FAIL", f)
    print(f"self-test: {'ok' if not fails else str(len(fails)) + ' failed'}")
    return 0 if not fails else 1


# ------------------------------------------------------------------ main


def main(argv):
    ap = argparse.ArgumentParser(
        prog="rerun.py", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--only", help="comma-separated write-ups (default: " + ",".join(WRITEUPS) + ")")
    ap.add_argument("--workdir", help="scratch root; each write-up runs in WORKDIR/<name> (default: a new temp dir)")
    ap.add_argument("--rev", default="HEAD", help="commit to copy into the scratch folders (default HEAD)")
    ap.add_argument("--mrpp", help="the mrpp binary standing for ./target/release/mrpp")
    ap.add_argument("--skip-build", action="store_true", help="drop the blocks' `cargo build` commands")
    ap.add_argument("--skip-tests", action="store_true", help="drop the blocks' `cargo test` commands")
    ap.add_argument("--commands", help="run only these commands of each block (numbers from --list, e.g. 2-4,6)")
    ap.add_argument("--list", action="store_true", help="show the commands and markers, run nothing")
    ap.add_argument("--compare-only", metavar="DIR", help="diff against outputs already under DIR")
    ap.add_argument("--partial", action="store_true", help="tables whose outputs are missing are 'not checked', not failures")
    ap.add_argument("--verbose", action="store_true", help="echo the commands' output")
    ap.add_argument("--self-test", action="store_true", help="run the built-in tests (no experiment) and exit")
    args = ap.parse_args(argv)
    if args.self_test:
        return self_test()
    names = WRITEUPS if not args.only else [n.strip() for n in args.only.split(",") if n.strip()]
    for n in names:
        if not (DOCS / f"{n}.md").exists():
            ap.error(f"no write-up docs/reproduction/{n}.md")
    try:
        writeups = [Writeup(n) for n in names]
    except ValueError as e:
        print(f"rerun.py: {e}", file=sys.stderr)
        return 2
    if args.list:
        for w in writeups:
            list_writeup(w, args)
        return 0
    totals, timing = {}, []
    if args.compare_only:
        base = Path(args.compare_only).resolve()
        roots = {w.name: (base / w.name if (base / w.name).is_dir() else base) for w in writeups}
    else:
        base = Path(args.workdir).resolve() if args.workdir else Path(tempfile.mkdtemp(prefix="mrpp-rerun-"))
        if base == REPO or REPO in base.parents:
            print("rerun.py: --workdir must be outside the repository", file=sys.stderr)
            return 2
        roots = {}
        for w in writeups:
            roots[w.name] = base / w.name
            try:
                times, total = run_block(w, args, roots[w.name])
            except UsageError as e:
                print(f"rerun.py: {e}", file=sys.stderr)
                return 2
            timing.append((w.name, times, total))
    for w in writeups:
        counts = compare_writeup(w, roots[w.name], args.partial)
        for k, v in counts.items():
            totals[k] = totals.get(k, 0) + v
    print("== summary")
    for name, times, total in timing:
        bad = [f"#{k} exit {rc}" for k, rc, _ in times if rc != 0]
        print(f"   {name}: block {total:.0f} s" + (f" (non-zero exits: {', '.join(bad)})" if bad else ""))
    print(
        f"   {totals.get('matched', 0)} tables matched, {totals.get('differ', 0) + totals.get('error', 0)} differ, "
        f"{totals.get('not diffed', 0)} not diffed, {totals.get('missing', 0)} with missing outputs, "
        f"{totals.get('unmarked', 0)} without a marker"
    )
    failed = totals.get("differ", 0) + totals.get("error", 0) + totals.get("unmarked", 0)
    if not args.partial:
        failed += totals.get("missing", 0)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

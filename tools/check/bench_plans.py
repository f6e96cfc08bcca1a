#!/usr/bin/env python3
"""Every instance of a `mrpp bench` grid config, solved again by one mrpp planner with its plan
saved, and each plan replayed by the independent checker `tools/check/grid.py` (stdlib only).

`mrpp bench run` validates every plan with mrpp's own validator but keeps only the records; this
script is the independent half of "every plan validated": it expands the config's instances
(`scen` with `{k}` over `scens`, `agents` as a list or "a..=b step s", paths relative to the
config), runs `MRPP solve -m MAP -i SCEN -N AGENTS -P PLANNER -t LIMIT -s SEED -o PLAN.json` for
each, and checks each plan the solver reported as solved. It prints one line per instance and a
summary, and exits 1 if any plan is rejected by the checker (or its sum of costs differs from
mrpp's), 0 otherwise. Runs that end unsolved are counted, not checked. With `--bounds` the
checker also computes the lower bound of the sum of costs and of the makespan by its own
breadth-first searches, and both must equal the ones mrpp prints (the bounds `mrpp bench`
records); when mrpp prints the plan's sum of loss (LaCAM's `final_sum_of_loss`), it must equal
the checker's, and the summary says on how many plans it was compared.

Usage:
  python3 tools/check/bench_plans.py CONFIG.toml --out DIR [--mrpp PATH] [--planner lacam]
                                     [--time-limit S] [--seed N] [--jobs J] [--data DIR]
                                     [--bounds]

`--data DIR` replaces the folder of every map and scenario path (e.g. a benchmark unpacked
elsewhere than the config's `data/movingai`).
"""

import argparse
import concurrent.futures
import os
import re
import subprocess
import sys
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))


def counts(spec):
    """Agent counts of a config entry: a list, an int, or comma-separated items, each a count
    or a range "a..=b" / "a..=b step s"."""
    if isinstance(spec, list):
        return [int(x) for x in spec]
    if isinstance(spec, int):
        return [spec]
    out = []
    for item in spec.split(","):
        m = re.fullmatch(r"\s*(\d+)\s*\.\.=\s*(\d+)(?:\s+step\s+(\d+))?\s*", item)
        if m:
            lo, hi, step = int(m[1]), int(m[2]), int(m[3] or 1)
            out.extend(range(lo, hi + 1, step))
        else:
            out.append(int(item))
    return out


def scen_numbers(spec):
    m = re.fullmatch(r"\s*(\d+)\s*\.\.=\s*(\d+)\s*", str(spec))
    if m:
        return list(range(int(m[1]), int(m[2]) + 1))
    return [int(x) for x in str(spec).split(",")]


def instances(config, data):
    with open(config, "rb") as f:
        cfg = tomllib.load(f)
    base = os.path.dirname(os.path.abspath(config))

    def place(p):
        p = os.path.normpath(os.path.join(base, p))
        return os.path.join(data, os.path.basename(p)) if data else p

    out = []
    for inst in cfg.get("instances", []):
        scens = [inst["scen"]]
        if "scens" in inst:
            scens = [inst["scen"].replace("{k}", str(k)) for k in scen_numbers(inst["scens"])]
        for scen in scens:
            for n in counts(inst["agents"]):
                out.append((place(inst["map"]), place(scen), n))
    return out, cfg


def one(args, job):
    m, s, n = job
    name = f"{os.path.basename(s)[:-5]}-a{n}"
    plan = os.path.join(args.out, name + ".json")
    cmd = [args.mrpp, "solve", "-m", m, "-i", s, "-N", str(n), "-P", args.planner,
           "-t", str(args.time_limit), "-s", str(args.seed), "-o", plan, "--progress", "none"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0 or not os.path.exists(plan):
        return name, "unsolved", (r.stderr.strip().splitlines() or [f"exit {r.returncode}"])[-1]
    c = subprocess.run([sys.executable, os.path.join(HERE, "grid.py")]
                       + (["--bounds"] if args.bounds else []) + [m, plan],
                       capture_output=True, text=True)
    text = (c.stdout + c.stderr).strip()
    if c.returncode != 0:
        return name, "rejected", text.splitlines()[-1] if text else f"exit {c.returncode}"
    # mrpp's summary line says "solved: sum_of_costs N ..."; the checker prints JSON.
    ours = re.search(r"^solved: sum_of_costs (\d+)", r.stdout, re.M)
    theirs = re.search(r'"sum_of_costs": (\d+)', text)
    if not ours or not theirs or ours[1] != theirs[1]:
        return name, "rejected", f"sum of costs: mrpp {ours and ours[1]}, grid.py {theirs and theirs[1]}"
    # "sum_of_costs N (lower bound B, ...) | makespan M (lower bound C, ...)" and LaCAM's notes.
    pairs = [("sum_of_loss", r"final_sum_of_loss (\d+)")]
    if args.bounds:
        pairs += [("lower_bound", r"^solved: sum_of_costs \d+ \(lower bound (\d+)"),
                  ("makespan_lower_bound", r"\| makespan \d+ \(lower bound (\d+)")]
    for key, pattern in pairs:
        mine = re.search(pattern, r.stdout, re.M)
        checked = re.search(rf'"{key}": (\d+)', text)
        if key != "sum_of_loss" and not mine:
            return name, "rejected", f"mrpp printed no {key}"
        if mine and (not checked or mine[1] != checked[1]):
            return name, "rejected", f"{key}: mrpp {mine[1]}, grid.py {checked and checked[1]}"
    loss = "loss compared" if re.search(pairs[0][1], r.stdout, re.M) else "loss not printed"
    return name, "accepted", f"({loss}) " + (text.splitlines()[-1] if text else "")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--out", required=True, help="folder for the plans")
    ap.add_argument("--mrpp", default=os.path.join(HERE, "..", "..", "target", "release", "mrpp"))
    ap.add_argument("--planner", default="lacam")
    ap.add_argument("--time-limit", type=float, default=None,
                    help="seconds per run (default: the config's time_limit)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--data", default=None)
    ap.add_argument("--bounds", action="store_true",
                    help="also check the lower bounds (slow on large maps: one BFS per agent)")
    args = ap.parse_args()
    jobs, cfg = instances(args.config, args.data)
    if args.time_limit is None:
        args.time_limit = float(cfg.get("time_limit", 10))
    missing = sorted({p for m, s, _ in jobs for p in (m, s) if not os.path.exists(p)})
    if missing:
        print(f"{len(missing)} map or scenario files are missing, e.g. {missing[0]}", file=sys.stderr)
        return 1
    os.makedirs(args.out, exist_ok=True)
    tally = {"accepted": 0, "rejected": 0, "unsolved": 0, "loss": 0}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for name, status, note in pool.map(lambda j: one(args, j), jobs):
            tally[status] += 1
            tally["loss"] += note.startswith("(loss compared)")
            print(f"{name}: {status} {note}", flush=True)
    print(f"{len(jobs)} instances: {tally['accepted']} plans accepted by grid.py, "
          f"{tally['rejected']} rejected, {tally['unsolved']} unsolved; the sum of loss "
          f"compared with mrpp's on {tally['loss']} (the others' planner prints none)")
    return 1 if tally["rejected"] else 0


if __name__ == "__main__":
    sys.exit(main())

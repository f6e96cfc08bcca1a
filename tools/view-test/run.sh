#!/usr/bin/env bash
# Browser tests of `mrpp view`: makes a grid, a continuous, a tree and a formation plan and a
# lifelong run, writes their viewer pages, and checks them in headless Debian Chromium through playwright-core (view-test.mjs).
# Screenshots go to target/view-screenshots/. Installs chromium (apt-get) and playwright-core
# (npm) when missing; prints `SKIP: ...` and exits 0 when they cannot be installed. Last, a
# 10,000-agent warehouse plan must open and play (its frame time is printed).
set -euo pipefail
REPO=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$REPO"
MRPP=${MRPP:-$REPO/target/release/mrpp}
skip() { echo "SKIP: $*"; exit 0; }

[[ -x $MRPP ]] || cargo build --release -p mrpp-cli
if [[ ! -x /usr/bin/chromium ]]; then
    [[ $(id -u) == 0 ]] || skip "Chromium is not installed and this is not root"
    apt-get install -y --no-install-recommends chromium >/tmp/mrpp-apt-chromium.log 2>&1 \
        || { apt-get update >>/tmp/mrpp-apt-chromium.log 2>&1 \
             && apt-get install -y --no-install-recommends chromium >>/tmp/mrpp-apt-chromium.log 2>&1; } \
        || skip "Debian's chromium cannot be installed ($(tail -1 /tmp/mrpp-apt-chromium.log))"
fi
command -v node >/dev/null || skip "node is not installed"
if [[ ! -d tools/view-test/node_modules/playwright-core ]]; then
    (cd tools/view-test && npm install --no-audit --no-fund >/tmp/mrpp-npm.log 2>&1) \
        || skip "playwright-core cannot be installed from npm ($(tail -1 /tmp/mrpp-npm.log))"
fi

OUT=target/view-test
mkdir -p "$OUT"
"$MRPP" solve --map data/movingai/random-32-32-20.map --scen data/movingai/random-32-32-20-random-1.scen \
    --agents 60 --planner lacam --out "$OUT/grid.json" >/dev/null
"$MRPP" view --map data/movingai/random-32-32-20.map --plan "$OUT/grid.json" --out "$OUT/grid.html" >/dev/null
"$MRPP" solve --world data/continuous/six-robots-four-obstacles.json --planner orca \
    --out "$OUT/continuous.json" >/dev/null
"$MRPP" view --world data/continuous/six-robots-four-obstacles.json --plan "$OUT/continuous.json" \
    --out "$OUT/continuous.html" >/dev/null
"$MRPP" trees solve --instance data/trees/example.json --planner psw --out "$OUT/trees.json" >/dev/null
"$MRPP" view --instance data/trees/example.json --plan "$OUT/trees.json" --out "$OUT/trees.html" >/dev/null
"$MRPP" solve --formation data/formation/var_density2-8.json --planner ga --out "$OUT/formation.json" >/dev/null
"$MRPP" view --formation data/formation/var_density2-8.json --plan "$OUT/formation.json" --out "$OUT/formation.html" >/dev/null
node tools/view-test/view-test.mjs target/view-screenshots \
    "$OUT/grid.html" "$OUT/grid.json" "$OUT/continuous.html" "$OUT/continuous.json" \
    "$OUT/trees.html" "$OUT/trees.json" "$OUT/formation.html" "$OUT/formation.json"

# A lifelong run (League of Robot Runners), under both action models.
for model in MAPF_T MAPF; do
    "$MRPP" solve --lorr data/robot-runners/lorr2026-maze/maze-example_40.json --planner lifelong-pibt \
        --steps 200 --action-model $model --out "$OUT/lifelong-$model.json" >/dev/null
    "$MRPP" view --lorr data/robot-runners/lorr2026-maze/maze-example_40.json --plan "$OUT/lifelong-$model.json" \
        --out "$OUT/lifelong-$model.html" >/dev/null
    node tools/view-test/view-test.mjs --lifelong target/view-screenshots "$OUT/lifelong-$model.html" "$OUT/lifelong-$model.json"
done

# A grid plan executed under delays (mrpp execute), naive and ADG.
for ex in adg naive; do
    "$MRPP" execute -m data/movingai/random-32-32-20.map --plan "$OUT/grid.json" --delays bernoulli:p=0.02,min=1,max=4 \
        --executor $ex --ticks-per-move 3 --agent-size 0.5 -s 1 -o "$OUT/exec-$ex.json" >/dev/null 2>&1 || true
    "$MRPP" view -m data/movingai/random-32-32-20.map --plan "$OUT/exec-$ex.json" --out "$OUT/exec-$ex.html" >/dev/null
    node tools/view-test/view-test.mjs --execution target/view-screenshots "$OUT/exec-$ex.html" "$OUT/exec-$ex.json"
done

# 10,000 agents on warehouse-20-40-10-2-2: the page must open and play; the frame time is printed.
"$MRPP" gen scen --map data/movingai/warehouse-20-40-10-2-2.map --agents 10000 --seed 0 --out "$OUT/warehouse-10k.scen" >/dev/null
"$MRPP" solve --map data/movingai/warehouse-20-40-10-2-2.map --scen "$OUT/warehouse-10k.scen" --planner lacam \
    --time-limit 60 --out "$OUT/warehouse-10k.json" >/dev/null
"$MRPP" view --map data/movingai/warehouse-20-40-10-2-2.map --plan "$OUT/warehouse-10k.json" --out "$OUT/warehouse-10k.html" >/dev/null
node tools/view-test/view-test.mjs --perf "$OUT/warehouse-10k.html"

// Browser test of `mrpp view` pages: for each (page, plan file) pair, load the page in headless
// Chromium, move to t = 0, t = mid and t = end, and check that
//  - the positions the page computes (window.mrppView.positions) are the plan file's positions,
//  - the canvas pixel inside every agent's disc has that agent's colour (what is drawn),
// and save a screenshot of each time step.
// Usage: node view-test.mjs OUT_DIR PAGE.html PLAN.json [PAGE.html PLAN.json ...]
import { chromium } from "playwright-core";
import { readFileSync, mkdirSync } from "node:fs";
import { basename } from "node:path";
import { pathToFileURL } from "node:url";

// Headless Debian Chromium, without the background traffic this machine's closed network refuses.
function launch() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    args: ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
      "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-quic"],
  });
}

// `--perf PAGE.html`: open a (large) page, play 60 frames, print the mean draw time.
if (process.argv[2] === "--perf") {
  const pagePath = process.argv[3];
  const browser = await launch();
  const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
  const t0 = Date.now();
  await page.goto(pathToFileURL(pagePath).href, { timeout: 120000 });
  await page.waitForFunction(() => window.mrppView !== undefined, null, { timeout: 120000 });
  const load = Date.now() - t0;
  const r = await page.evaluate(() => {
    const v = window.mrppView;
    const frames = 60, start = performance.now();
    for (let k = 0; k < frames; k++) v.setTime(v.steps * k / frames);
    return { agents: v.scene.agents.length, steps: v.steps, ms: (performance.now() - start) / frames };
  });
  await page.screenshot({ path: pagePath.replace(/\.html$/, "-perf.png") });
  await browser.close();
  console.log(`perf ${pagePath}: ${r.agents} agents, ${r.steps} steps, page ready in ${load} ms, ${r.ms.toFixed(1)} ms per frame`);
  process.exit(r.agents > 0 && r.ms < 1000 ? 0 : 1);
}

// `--lifelong OUT_DIR PAGE.html RUN.json`: a lifelong run's page (RUN.json: the League of Robot
// Runners' output). The robots' cells and headings the page shows at t = 0, mid and end must be
// a replay of the output's own actions from its starts (done here, independently), its
// tasks-finished series must rise to numTaskFinished, and the chart must be drawn.
if (process.argv[2] === "--lifelong") {
  const [outDir, pagePath, runPath] = process.argv.slice(3);
  mkdirSync(outDir, { recursive: true });
  const run = JSON.parse(readFileSync(runPath, "utf8"));
  const rotations = run.actionModel === "MAPF_T";
  const step = [[1, 0], [0, 1], [-1, 0], [0, -1]];
  const letters = run.actualPaths.map(p => (p ? p.split(",") : []));
  const states = [run.start.map(([row, col, o]) => [col, row, "ESWN".indexOf(o)])];
  for (let t = 0; t < letters[0].length; t++) {
    states.push(states[t].map(([x, y, o], i) => {
      const a = letters[i][t];
      if (rotations) {
        if (a === "F") return [x + step[o][0], y + step[o][1], o];
        if (a === "R") return [x, y, (o + 1) % 4];
        if (a === "C") return [x, y, (o + 3) % 4];
        return [x, y, o];
      }
      const d = { R: 0, U: 1, L: 2, D: 3 }[a];
      return d === undefined ? [x, y, o] : [x + step[d][0], y + step[d][1], o];
    }));
  }
  const browser = await launch();
  const page = await browser.newPage({ viewport: { width: 1000, height: 700 } });
  const errors = [];
  page.on("pageerror", e => errors.push(String(e)));
  await page.goto(pathToFileURL(pagePath).href);
  await page.waitForFunction(() => window.mrppView !== undefined);
  const steps = await page.evaluate(() => window.mrppView.steps);
  const series = await page.evaluate(() => window.mrppView.scene.series.values);
  const bad = [...errors];
  if (steps !== states.length - 1) bad.push(`page has ${steps} steps, the run ${states.length - 1}`);
  if (series.length !== states.length || series.some((v, k) => k && v < series[k - 1])
      || series[series.length - 1] !== Number(run.numTaskFinished)) {
    bad.push(`series ends at ${series[series.length - 1]}, numTaskFinished ${run.numTaskFinished}`);
  }
  for (const [label, t] of [["start", 0], ["mid", Math.floor(steps / 2)], ["end", steps]]) {
    const got = await page.evaluate(t => {
      const v = window.mrppView;
      v.setTime(t);
      // Pixels of the chart's line colour in the bottom-right corner.
      const c = document.getElementById("canvas"), dpr = window.devicePixelRatio || 1;
      const [w, h] = [c.width, c.height], box = Math.round(250 * dpr);
      const d = c.getContext("2d").getImageData(w - box, h - box, box, box).data;
      let line = 0;
      for (let k = 0; k < d.length; k += 4) {
        if (Math.abs(d[k] - 21) < 30 && Math.abs(d[k + 1] - 101) < 30 && Math.abs(d[k + 2] - 192) < 30) line++;
      }
      return { pos: v.positions(t), headings: v.headings(t), goals: v.goals(t), line };
    }, t);
    states[t].forEach(([x, y, o], i) => {
      const [px, py] = got.pos[i];
      if (Math.abs(px - x - 0.5) > 1e-9 || Math.abs(py - y - 0.5) > 1e-9) {
        bad.push(`t=${t} robot ${i}: page ${JSON.stringify(got.pos[i])}, replay [${x + 0.5}, ${y + 0.5}]`);
      }
      if (rotations && got.headings[i] !== o) bad.push(`t=${t} robot ${i}: heading ${got.headings[i]}, replay ${o}`);
    });
    if (got.line < 20) bad.push(`t=${t}: the tasks-finished chart is not drawn (${got.line} pixels)`);
    if (t > 0 && !got.goals.some(g => g)) bad.push(`t=${t}: no robot shows a goal`);
    const shot = `${outDir}/${basename(pagePath, ".html")}-${label}.png`;
    await page.screenshot({ path: shot });
    console.log(`${bad.length ? "FAIL" : "ok  "} ${basename(pagePath)} t=${t} (${label}): ${states[0].length} robots -> ${shot}`);
  }
  await browser.close();
  if (bad.length) console.log("  " + bad.slice(0, 8).join("\n  "));
  process.exit(bad.length ? 1 : 0);
}

// `--execution OUT_DIR PAGE.html RECORD.json`: an executed record's page (`mrpp execute`). At
// t = 0 every robot is on its start, at the end on its last move's cell, and a robot is marked
// held at the end of the first tick of each of its delays.
if (process.argv[2] === "--execution") {
  const [outDir, pagePath, recordPath] = process.argv.slice(3);
  mkdirSync(outDir, { recursive: true });
  const record = JSON.parse(readFileSync(recordPath, "utf8"));
  const browser = await launch();
  const page = await browser.newPage({ viewport: { width: 900, height: 700 } });
  const errors = [];
  page.on("pageerror", e => errors.push(String(e)));
  await page.goto(pathToFileURL(pagePath).href);
  await page.waitForFunction(() => window.mrppView !== undefined);
  const steps = await page.evaluate(() => window.mrppView.steps);
  const bad = [...errors];
  if (steps !== record.ticks) bad.push(`page has ${steps} steps, the record ${record.ticks} ticks`);
  const at = async t => page.evaluate(t => {
    const v = window.mrppView;
    v.setTime(t);
    return { pos: v.positions(t), held: v.held(t) };
  }, t);
  const first = await at(0), last = await at(steps);
  record.agents.forEach((a, i) => {
    const end = a.moves.length ? a.moves[a.moves.length - 1][3] : a.start;
    const near = (p, c) => Math.abs(p[0] - c[0] - 0.5) < 1e-6 && Math.abs(p[1] - c[1] - 0.5) < 1e-6;
    if (!near(first.pos[i], a.start)) bad.push(`robot ${i}: at t=0 ${JSON.stringify(first.pos[i])}, start ${a.start}`);
    if (!near(last.pos[i], end)) bad.push(`robot ${i}: at the end ${JSON.stringify(last.pos[i])}, last cell ${end}`);
  });
  let checked = 0;
  for (const [i, a] of record.agents.entries()) {
    for (const [s] of a.delays) {
      if (s + 1 > steps || checked > 20) continue;
      const h = await at(s + 1);
      if (!h.held[i]) bad.push(`robot ${i}: not marked held after tick ${s}`);
      checked++;
    }
  }
  await page.screenshot({ path: `${outDir}/${basename(pagePath, ".html")}.png` });
  await browser.close();
  console.log(`${bad.length ? "FAIL" : "ok  "} ${basename(pagePath)}: ${record.agents.length} robots, ${steps} ticks, ${checked} delays marked`);
  if (bad.length) console.log("  " + bad.slice(0, 8).join("\n  "));
  process.exit(bad.length ? 1 : 0);
}

const [outDir, ...pairs] = process.argv.slice(2);
if (!outDir || pairs.length === 0 || pairs.length % 2) {
  console.error("usage: node view-test.mjs OUT_DIR PAGE.html PLAN.json [...]");
  process.exit(2);
}
mkdirSync(outDir, { recursive: true });

// A plan file's point of agent i at step t (an agent rests on its last point). Grid cells
// [x, y] are drawn at their centres.
// Trees: nodes are drawn where the page's layout puts them (`scene.nodes[id]`).
function planPoint(plan, i, t, scene) {
  const path = plan.agents[i].path;
  const p = path[Math.min(t, path.length - 1)];
  if (plan.family === "trees") return scene.nodes[p];
  return plan.family === "grid" ? [p[0] + 0.5, p[1] + 0.5] : p;
}

// Formations move in continuous time along curved corridors: at t = 0 a robot is on its path's
// first roadmap vertex, at the end on its last, and in between on its route: within the
// largest distance a corridor of length L can stray from its chord c, sqrt((L/2)^2 - (c/2)^2).
function formationCheck(plan, i, t, steps, got) {
  const pts = plan.roadmap.points, path = plan.agents[i].path;
  const near = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]) < 1e-6;
  if (t === 0) return near(got, pts[path[0]]) ? null : `not on its start ${JSON.stringify(pts[path[0]])}`;
  if (t === steps) return near(got, pts[path[path.length - 1]]) ? null : "not on its goal";
  const len = new Map(plan.roadmap.edges.map(e => [`${Math.min(e[0], e[1])}-${Math.max(e[0], e[1])}`, e[2]]));
  for (let k = 0; k + 1 < path.length; k++) {
    const [a, b] = [pts[path[k]], pts[path[k + 1]]];
    const c = Math.hypot(b[0] - a[0], b[1] - a[1]);
    const L = len.get(`${Math.min(path[k], path[k + 1])}-${Math.max(path[k], path[k + 1])}`) ?? c;
    const slack = Math.sqrt(Math.max(0, (L / 2) ** 2 - (c / 2) ** 2)) + 1e-6;
    const u = c > 0 ? Math.max(0, Math.min(1, ((got[0] - a[0]) * (b[0] - a[0]) + (got[1] - a[1]) * (b[1] - a[1])) / (c * c))) : 0;
    const d = Math.hypot(got[0] - (a[0] + u * (b[0] - a[0])), got[1] - (a[1] + u * (b[1] - a[1])));
    if (d <= slack) return null;
  }
  return "off its route";
}

const browser = await launch();
let failures = 0;
for (let k = 0; k < pairs.length; k += 2) {
  const [pagePath, planPath] = [pairs[k], pairs[k + 1]];
  const plan = JSON.parse(readFileSync(planPath, "utf8"));
  const page = await browser.newPage({ viewport: { width: 900, height: 700 } });
  const errors = [];
  page.on("pageerror", e => errors.push(String(e)));
  await page.goto(pathToFileURL(pagePath).href);
  await page.waitForFunction(() => window.mrppView !== undefined);
  const steps = await page.evaluate(() => window.mrppView.steps);
  const scene = await page.evaluate(() => window.mrppView.scene);
  const n = plan.agents.length;
  for (const [label, t] of [["start", 0], ["mid", Math.floor(steps / 2)], ["end", steps]]) {
    const state = await page.evaluate(t => {
      const v = window.mrppView;
      v.setTime(t);
      const canvas = document.getElementById("canvas");
      const g = canvas.getContext("2d");
      const dpr = window.devicePixelRatio || 1;
      const pos = v.positions(t);
      // The drawn colour at each agent's centre, and the colour it should have.
      const probe = document.createElement("canvas").getContext("2d");
      const drawn = pos.map((p, i) => {
        const [sx, sy] = v.toScreen(p[0], p[1]);
        // Left of the centre, inside the disc, clear of the agent's number.
        const [ex] = v.toScreen(p[0] + v.scene.agents[i].radius, p[1]);
        const off = 0.7 * Math.abs(ex - sx);
        const px = g.getImageData(Math.round((sx - off) * dpr), Math.round(sy * dpr), 1, 1).data;
        probe.fillStyle = v.colour(i);
        probe.fillRect(0, 0, 1, 1);
        const want = probe.getImageData(0, 0, 1, 1).data;
        return [Array.from(px.slice(0, 3)), Array.from(want.slice(0, 3))];
      });
      return { time: v.time, pos, drawn };
    }, t);
    const bad = [];
    for (let i = 0; i < n; i++) {
      if (plan.family === "formation") {
        const why = formationCheck(plan, i, t, steps, state.pos[i]);
        if (why) bad.push(`robot ${i}: ${why} at ${JSON.stringify(state.pos[i])}`);
        continue;
      }
      const want = planPoint(plan, i, t, scene);
      const got = state.pos[i];
      if (Math.abs(got[0] - want[0]) > 1e-6 || Math.abs(got[1] - want[1]) > 1e-6) {
        bad.push(`agent ${i}: page ${JSON.stringify(got)}, plan ${JSON.stringify(want)}`);
      }
    }
    // Discs may overlap (a later agent drawn over an earlier one, or a formation's robots
    // sharing a corridor): at least 80% must show their own colour exactly, except formations,
    // whose robots travel together by design and must show at least one.
    const [pix, want] = [state.drawn.map(d => d[0]), state.drawn.map(d => d[1])];
    const close = (a, b, tol) => a.every((x, c) => Math.abs(x - b[c]) <= tol);
    const exact = pix.filter((p, i) => close(p, want[i], 3)).length;
    const need = plan.family === "formation" ? 1 : Math.ceil(0.8 * n);
    if (exact < need) {
      bad.push(`only ${exact} of ${n} agents show their colour inside their disc`);
    }
    const shot = `${outDir}/${basename(pagePath, ".html")}-${label}.png`;
    await page.screenshot({ path: shot });
    const ok = bad.length === 0 && errors.length === 0;
    failures += ok ? 0 : 1;
    console.log(`${ok ? "ok  " : "FAIL"} ${basename(pagePath)} t=${t} (${label}): ${n} agents${ok ? "" : "\n  " + [...bad.slice(0, 5), ...errors].join("\n  ")} -> ${shot}`);
  }
  await page.close();
}
await browser.close();
process.exit(failures ? 1 : 0);

// The browser side of bench/ui_chart.py: opens the web app's Live tab in Debian's chromium
// (driven by playwright-core from ui/node_modules) and measures, after a warm-up, for a while:
// animation frames per second, the 95th percentile frame interval, long tasks, samples the page
// received per second, and the renderer's main-thread time. Prints one JSON object on stdout.
//
// Environment: BENCH_URL, BENCH_TOKEN (a user token), BENCH_PATH (the Live tab's path with its
// query), BENCH_SECONDS, BENCH_WARMUP_S, BENCH_CHROMIUM (default /usr/bin/chromium),
// BENCH_SHOT (optional screenshot file), BENCH_PROFILE=1 (adds the functions that took the
// most main-thread time while measuring, from a CPU profile), BENCH_PAUSED=1 (click Pause
// before measuring: the page's cost without live data, as a baseline).
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', 'ui', 'package.json'));
const { chromium } = require('playwright-core');

const env = (name, fallback) => {
  const value = process.env[name] ?? fallback;
  if (value === undefined) throw new Error(`${name} is not set`);
  return value;
};
const url = env('BENCH_URL');
const seconds = Number(env('BENCH_SECONDS', '20'));
const warmupS = Number(env('BENCH_WARMUP_S', '3'));

// Installed before the app loads: long tasks are only reported to observers that exist.
function installProbes() {
  window.__bench = { longTasks: [] };
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.__bench.longTasks.push({ start: e.startTime, duration: e.duration });
  }).observe({ type: 'longtask', buffered: true });
}

// Runs in the page: counts frames for `ms` and reads the points counter at both ends.
function measureInPage(ms) {
  const points = () => Number(document.querySelector('[data-testid="live-points"]')?.textContent ?? 'NaN');
  return new Promise((resolve) => {
    const frames = [];
    const start = performance.now();
    const startPoints = points();
    const tick = (t) => {
      frames.push(t);
      if (t - start < ms) requestAnimationFrame(tick);
      else {
        const end = performance.now();
        const longTasks = window.__bench.longTasks.filter((l) => l.start >= start && l.start < end);
        resolve({ start, end, frames, startPoints, endPoints: points(), longTasks });
      }
    };
    requestAnimationFrame(tick);
  });
}

function percentile(sorted, q) {
  if (sorted.length === 0) return null;
  return sorted[Math.min(sorted.length - 1, Math.max(0, Math.ceil(q * sorted.length) - 1))];
}

function summarize(m, before, after) {
  const spanS = (m.end - m.start) / 1000;
  const intervals = m.frames.slice(1).map((t, i) => t - m.frames[i]).sort((a, b) => a - b);
  const metric = (set, name) => set.metrics.find((x) => x.name === name)?.value ?? 0;
  const busy = (name) => (metric(after, name) - metric(before, name)) / spanS;
  return {
    seconds: Math.round(spanS * 10) / 10,
    fps: (m.frames.length - 1) / spanS,
    frame_p50_ms: percentile(intervals, 0.5),
    frame_p95_ms: percentile(intervals, 0.95),
    frame_p99_ms: percentile(intervals, 0.99),
    frame_max_ms: intervals.at(-1) ?? null,
    long_tasks: m.longTasks.length,
    long_task_ms: m.longTasks.reduce((sum, l) => sum + l.duration, 0),
    long_task_max_ms: Math.max(0, ...m.longTasks.map((l) => l.duration)),
    samples_per_s: (m.endPoints - m.startPoints) / spanS,
    points_total: m.endPoints,
    main_thread_busy_pct: 100 * busy('TaskDuration'),
    script_pct: 100 * busy('ScriptDuration'),
    js_heap_mb: metric(after, 'JSHeapUsedSize') / 2 ** 20,
  };
}

/** Self time per function of a CDP CPU profile, the largest first. */
function topFunctions(profile, count = 15) {
  const spanUs = profile.endTime - profile.startTime;
  const perSample = spanUs / Math.max(1, profile.samples.length);
  const self = new Map();
  for (const node of profile.nodes) {
    const f = node.callFrame;
    const key = `${f.functionName || '(anonymous)'} ${f.url.split('/').pop()}:${f.lineNumber + 1}`;
    self.set(key, (self.get(key) ?? 0) + (node.hitCount ?? 0) * perSample);
  }
  return [...self]
    .sort((a, b) => b[1] - a[1])
    .slice(0, count)
    .map(([fn, us]) => ({ fn, ms_per_s: Math.round((us / spanUs) * 10000) / 10 }));
}

const browser = await chromium.launch({
  executablePath: env('BENCH_CHROMIUM', '/usr/bin/chromium'),
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.setDefaultTimeout(30000);
  await page.addInitScript(installProbes);
  // Sign in as the app does: its token in sessionStorage.
  await page.goto(`${url}/app/login`);
  await page.evaluate((token) => sessionStorage.setItem('twinlink.token', token), env('BENCH_TOKEN'));
  await page.goto(`${url}${env('BENCH_PATH')}`);
  await page.waitForFunction(() => Number(document.querySelector('[data-testid="live-points"]')?.textContent) > 0);
  if (process.env.BENCH_PAUSED) await page.getByRole('button', { name: 'Pause' }).click();
  await page.waitForTimeout(warmupS * 1000);
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Performance.enable');
  const profiling = Boolean(process.env.BENCH_PROFILE);
  if (profiling) {
    await cdp.send('Profiler.enable');
    await cdp.send('Profiler.start');
  }
  const before = await cdp.send('Performance.getMetrics');
  const measured = await page.evaluate(measureInPage, seconds * 1000);
  const after = await cdp.send('Performance.getMetrics');
  const profile = profiling ? topFunctions((await cdp.send('Profiler.stop')).profile) : undefined;
  const stats = await page.getByLabel('Live delay per stream').textContent();
  // A long window makes the page subscribe with a max_rate, which it states.
  const thinned = /thinned to at most ([\d,]+) samples\/s/.exec(await page.locator('main').innerText());
  const maxRate = thinned ? Number(thinned[1].replaceAll(',', '')) : null;
  if (process.env.BENCH_SHOT) await page.screenshot({ path: process.env.BENCH_SHOT });
  process.stdout.write(JSON.stringify({ ...summarize(measured, before, after), stats_text: stats, max_rate: maxRate, page_errors: errors, profile_top: profile }) + '\n');
} finally {
  await browser.close();
}

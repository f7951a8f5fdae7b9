// End-to-end check of the web app in Debian's chromium, driven by playwright-core.
// Run by tests/integration/test_ui_e2e.py against a real server:
//   E2E_URL, E2E_USER, E2E_PASSWORD, E2E_TOKEN (an admin API token), E2E_TWIN (a twin with a
//   service `self`, and a signal `level` whose only sample is two minutes old), E2E_SHOTS
//   (folder). The server holds the demo's data: the example twins, Tingen streaming from the
//   simulated rig, and Tingen.fmu uploaded.
import { chromium } from 'playwright-core';

const env = (name) => {
  const value = process.env[name];
  if (!value) throw new Error(`${name} is not set`);
  return value;
};
const url = env('E2E_URL');
const shots = env('E2E_SHOTS');
const browser = await chromium.launch({
  executablePath: process.env.E2E_CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
const pageErrors = [];
page.on('pageerror', (e) => pageErrors.push(String(e)));
// Every page names the site's icon; none may be missing (a 404 in the console).
const icons = [];
page.on('response', (r) => {
  if (/\/favicon\.(svg|ico)$/.test(new URL(r.url()).pathname)) icons.push(`${r.status()} ${r.url()}`);
});
page.setDefaultTimeout(15000);
// How many samples a stream holds, read from the API (not the page) to know time has passed.
const api = async (path) => {
  const r = await fetch(`${url}${path}`, { headers: { Authorization: `Bearer ${env('E2E_TOKEN')}` } });
  if (!r.ok) throw new Error(`GET ${path}: ${r.status}`);
  return r.json();
};
const storedCount = async (twin, stream) => {
  const { streams } = await api(`/api/v1/twins/${twin}/streams`);
  return streams.find((s) => s.name === stream)?.count ?? 0;
};
const waitStored = async (twin, stream, more) => {
  const target = (await storedCount(twin, stream)) + more;
  const deadline = Date.now() + 20000;
  for (;;) {
    if ((await storedCount(twin, stream)) >= target) return;
    if (Date.now() > deadline) throw new Error(`${twin}/${stream} did not grow by ${more} samples`);
    await new Promise((resolve) => setTimeout(resolve, 100)); // polling interval, not a wait for an outcome
  }
};
// Whether the chart's first series (its first colour, #1f5fbf) is drawn in its plot's last
// tenth, the part nearest now, and in its first tenth: read from the canvas's pixels.
const drawnAt = () =>
  page.evaluate(() => {
    const canvas = document.querySelector('.time-chart canvas');
    const over = document.querySelector('.time-chart .u-over');
    if (!canvas || !over) return null;
    const ratio = canvas.width / canvas.getBoundingClientRect().width;
    const box = over.getBoundingClientRect();
    const origin = canvas.getBoundingClientRect();
    const left = Math.round((box.left - origin.left) * ratio);
    const width = Math.round(box.width * ratio);
    const height = Math.round(box.height * ratio);
    const top = Math.round((box.top - origin.top) * ratio);
    const { data } = canvas.getContext('2d').getImageData(left, top, width, height);
    const inColumns = (from, to) => {
      for (let y = 0; y < height; y++) {
        for (let x = from; x < to; x++) {
          const i = 4 * (y * width + x);
          if (Math.abs(data[i] - 31) < 40 && Math.abs(data[i + 1] - 95) < 40 && Math.abs(data[i + 2] - 191) < 40 && data[i + 3] > 100) return true;
        }
      }
      return false;
    };
    return { start: inColumns(0, Math.round(width / 10)), end: inColumns(Math.round((width * 9) / 10), width) };
  });
const waitDrawn = async (parts) => {
  const deadline = Date.now() + 15000;
  for (;;) {
    const drawn = await drawnAt();
    if (drawn && parts.every((part) => drawn[part])) return;
    if (Date.now() > deadline) throw new Error(`the held value is not drawn across the chart: ${JSON.stringify(drawn)}`);
    await new Promise((resolve) => setTimeout(resolve, 100)); // polling interval, not a wait for an outcome
  }
};
const step = async (name, fn) => {
  try {
    await fn();
  } catch (err) {
    await page.screenshot({ path: `${shots}/failed-${name}.png` }).catch(() => {});
    throw new Error(`step "${name}" failed: ${err.message}`);
  }
  await page.screenshot({ path: `${shots}/${name}.png` });
  console.log(`ok ${name}`);
};

try {
  await step('1-login', async () => {
    await page.goto(`${url}/app/`);
    await page.getByLabel('Username').fill(env('E2E_USER'));
    await page.getByLabel('Password').fill(env('E2E_PASSWORD'));
    await page.getByLabel('Password').press('Enter');
    await page.getByRole('heading', { name: 'Catalog' }).waitFor();
  });
  await step('2-search-cad', async () => {
    // The hit names the feature that matched; its link opens the twin at that feature's card.
    await page.getByLabel('Search twins and features').fill('CAD');
    await page.getByRole('link', { name: 'CAD store' }).first().click();
    await page.getByRole('heading', { name: 'Ilmatar crane' }).waitFor();
    // The card is highlighted...
    const card = page.locator('#feature-cad-store.feature-target');
    await card.getByRole('heading', { name: 'CAD store' }).waitFor();
    await card.getByText('PLM', { exact: true }).waitFor();
    // ...and scrolled into view.
    await page.waitForFunction(() => {
      const top = document.querySelector('#feature-cad-store')?.getBoundingClientRect().top;
      return top !== undefined && top >= 0 && top < window.innerHeight;
    });
  });
  await step('3-try-it', async () => {
    await page.goto(`${url}/app/twins/${env('E2E_TWIN')}`);
    await page.getByText('Try it').first().click();
    await page.getByLabel('Path').fill('healthz');
    await page.getByRole('button', { name: /send/i }).click();
    await page.getByText(/200/).first().waitFor();
    await page.getByText('"ok"').first().waitFor();
  });
  await step('4-gateway', async () => {
    await page.goto(`${url}/app/gateway`);
    await page.getByText('/healthz').first().waitFor();
  });
  // Tingen's live page: the rig streams through `twinlink simulate`, the chart receives it.
  const points = async () => Number(await page.getByTestId('live-points').textContent());
  const waitPointsAbove = (n) =>
    page.waitForFunction(
      (min) => Number(document.querySelector('[data-testid="live-points"]')?.textContent) > min,
      n,
    );
  await step('5-live', async () => {
    await page.goto(`${url}/app/twins/tingen/live`);
    await page.getByRole('button', { name: 'Pause' }).waitFor();
    await waitPointsAbove(0);
    await waitPointsAbove(await points());
  });
  await step('6-pause-resume', async () => {
    await page.getByRole('button', { name: 'Pause' }).click();
    await page.getByText('Paused: not receiving').waitFor();
    // Samples received just before the pause may still be counted at the next refresh of the
    // figures, so the count is read once the server has stored 50 more of the rig's samples,
    // and again after 50 more: paused, it must not move.
    await waitStored('tingen', 'telemetry', 50);
    const frozen = await points();
    await waitStored('tingen', 'telemetry', 50);
    const after = await points();
    if (after !== frozen) throw new Error(`paused, the chart still received points (${frozen} -> ${after})`);
    // ...and once resumed, the chart receives again.
    await page.getByRole('button', { name: 'Resume' }).click();
    await waitPointsAbove(after);
  });
  await step('7-fmu-processor', async () => {
    await page.goto(`${url}/app/twins/tingen/processors`);
    await page.getByRole('button', { name: 'New processor' }).click();
    await page.getByLabel('Blueprint').selectOption('fmu');
    await page.getByLabel('FMU', { exact: true }).selectOption('Tingen.fmu');
    await page.getByLabel('Signal for F').selectOption('Input_F_in');
    await page.getByRole('button', { name: 'Create processor' }).click();
    await page.getByTestId('processor-fmu').getByText('running').waitFor();
  });
  await step('8-fmu-series', async () => {
    await waitStored('tingen', 'fmu', 1); // the processor's first outputs are stored
    await page.goto(`${url}/app/twins/tingen/live?s=telemetry:Cantilever_Angle_radians,fmu:theta&w=10`);
    const theta = page.getByRole('checkbox', { name: 'fmu/theta' });
    await theta.waitFor();
    if (!(await theta.isChecked())) throw new Error('fmu/theta is not plotted');
    await page.getByRole('figure', { name: /fmu\/theta/ }).waitFor();
    await page.getByTestId('stats-fmu').waitFor(); // simulated samples arrive live
    await waitPointsAbove(await points());
    await page.screenshot({ path: `${shots}/tingen-live.png` });
  });
  await step('9-document-error', async () => {
    await page.goto(`${url}/app/twins/tingen/document`);
    const editor = page.getByLabel(/^YAML of the .* part$/);
    await page.waitForFunction(() => document.querySelector('textarea')?.value.includes('features:'));
    const lines = (await editor.inputValue()).split('\n');
    const at = lines.findIndex((line) => line.startsWith('features:'));
    lines.splice(at + 1, 0, '- description: no name here');
    await editor.fill(lines.join('\n'));
    const line = at + 2; // 1-based line of the inserted entry
    await page.locator(`[data-error-line="${line}"]`).first().waitFor();
    await page.getByRole('list', { name: 'Problems' }).getByText(`Line ${line}`).first().waitFor();
  });
  // A signal sent on change holds its value: its only sample, two minutes old, is drawn over
  // the whole 30 s live window (from before it, to now), and in the last 15 minutes of history
  // from that sample to now (dashed: held with no sample).
  await step('10-held-live', async () => {
    await page.goto(`${url}/app/twins/${env('E2E_TWIN')}/live?s=telemetry:level&w=30`);
    await page.getByRole('figure', { name: /telemetry\/level/ }).waitFor();
    await waitDrawn(['start', 'end']);
  });
  await step('11-held-history', async () => {
    await page.goto(`${url}/app/twins/${env('E2E_TWIN')}/history`);
    await page.getByLabel('Range').selectOption('15m');
    await page.getByRole('figure', { name: /History of level/ }).waitFor();
    await waitDrawn(['end']);
    if (!icons.length || icons.some((line) => !line.startsWith('200 '))) throw new Error(`the icon: ${icons.join('; ') || 'never asked for'}`);
  });
  if (pageErrors.length) throw new Error(`errors in the page: ${pageErrors.join('; ')}`);
} finally {
  await browser.close();
}

// The Co-simulations pages in Debian's chromium, driven by playwright-core. Run by
// tests/integration/test_ui_cosim.py against a real server: E2E_URL, E2E_USER, E2E_PASSWORD
// (an admin), E2E_ZIP (a zip of a Maestro multi-model beside the two mass-spring-damper FMUs it
// names, 30 s of simulated time), E2E_BAD (a .json that is no multi-model), E2E_TWIN (a twin's
// slug the admin may write), E2E_SHOTS (folder).
// Prints "ok <step>" for each step that passed.
import { readFileSync } from 'node:fs';
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
const context = await browser.newContext({ viewport: { width: 1280, height: 1000 }, acceptDownloads: true });
const page = await context.newPage();
// No errors in the page and none in its console; an expected refusal (a 4xx of the API) shows
// in the page, not as a script error.
const errors = [];
page.on('pageerror', (e) => errors.push(String(e)));
page.on('console', (m) => {
  if (m.type() === 'error' && !/the server responded with a status of 4\d\d/.test(m.text())) errors.push(m.text());
});
page.setDefaultTimeout(20000);
const step = async (name, fn) => {
  try {
    await fn();
  } catch (err) {
    await page.screenshot({ path: `${shots}/failed-cosim-${name}.png`, fullPage: true }).catch(() => {});
    throw new Error(`step "${name}" failed: ${err.message}`);
  }
  await page.screenshot({ path: `${shots}/cosim-${name}.png`, fullPage: true });
  console.log(`ok ${name}`);
};
const state = () => page.getByRole('heading', { level: 1 }).locator('.badge');
const chart = () => page.getByRole('figure', { name: /^Results: / });
/** The points the results chart holds (its data-points), once it is drawn. */
const points = async () => Number((await chart().getAttribute('data-points')) ?? '0');
const progress = async () => Number((await page.getByRole('progressbar', { name: 'Progress' }).getAttribute('value')) ?? '0');
/** Poll `check` until it holds (the page refreshes by itself; nothing is clicked). */
const until = async (what, check, timeoutMs = 60000) => {
  const deadline = Date.now() + timeoutMs;
  while (!(await check())) {
    if (Date.now() > deadline) throw new Error(`${what}: not so after ${timeoutMs / 1000} s`);
    await page.waitForTimeout(200);
  }
};
const create = async (file, name, start, twin = '') => {
  await page.getByRole('button', { name: 'New co-simulation' }).click();
  const form = page.getByRole('form', { name: 'New co-simulation' });
  await form.getByLabel('File').setInputFiles(file);
  await form.getByLabel('Name').fill(name);
  if (twin) {
    await form.getByRole('option', { name: twin, exact: true }).waitFor({ state: 'attached' });
    await form.getByLabel('Twin').selectOption(twin);
    await form.getByLabel('Signal prefix').fill('sim.');
  }
  const box = form.getByRole('checkbox', { name: 'Start it now' });
  if ((await box.isChecked()) !== start) await box.click();
  await form.getByRole('button', { name: 'Create' }).click();
  return form;
};

try {
  await step('1-login', async () => {
    await page.goto(`${url}/app/cosims`);
    await page.getByLabel('Username').fill(env('E2E_USER'));
    await page.getByLabel('Password').fill(env('E2E_PASSWORD'));
    await page.getByLabel('Password').press('Enter');
    await page.getByRole('heading', { name: 'Co-simulations' }).waitFor();
    await page.getByText('No co-simulation yet').waitFor();
  });
  await step('2-batch', async () => {
    // The zip is uploaded, the co-simulation made and started at once; batch runs to the end,
    // its rows into the twin's history.
    await create(env('E2E_ZIP'), 'msd-ui', true, env('E2E_TWIN'));
    await page.getByRole('heading', { name: /^msd-ui/ }).waitFor();
    await state().getByText('finished', { exact: true }).waitFor({ timeout: 120000 });
    await page.getByText('100%', { exact: false }).first().waitFor();
    if ((await progress()) !== 1) throw new Error(`progress ${await progress()} after the end`);
    const twin = page.getByRole('link', { name: env('E2E_TWIN'), exact: true });
    if ((await twin.getAttribute('href')) !== `/app/twins/${env('E2E_TWIN')}/history`) throw new Error('no link to the twin\'s history');
  });
  await step('3-graph', async () => {
    // The pair: the mass gives the spring x1 and v1, the spring gives the mass fk back (a cycle,
    // drawn below), and no algebraic loop.
    const graph = page.getByRole('img', { name: 'Connection graph: 2 instances, 3 connections' });
    await graph.locator('[data-instance="msd1.m1"]').waitFor();
    await graph.locator('[data-instance="msd2.m2"]').waitFor();
    await graph.locator('.cosim-edge-forward').getByText('x1, v1', { exact: true }).waitFor();
    await graph.locator('.cosim-edge-back').getByText('fk', { exact: true }).waitFor();
    await page.getByText('No algebraic loop.').waitFor();
    if ((await graph.locator('.cosim-box.cosim-loop, .cosim-edge.cosim-loop').count()) !== 0) throw new Error('a loop is marked');
  });
  await step('4-results', async () => {
    await chart().locator('canvas').first().waitFor();
    // 30 s at 0.01 s: 3001 rows, decimated by the server to at most 2000 points per column.
    const n = await points();
    if (n < 100 || n > 2000) throw new Error(`the chart holds ${n} points`);
    for (const column of ['x2', 'v2']) { // the multi-model's logVariables
      await chart().locator('.u-legend').getByText(new RegExp(`\\.${column}$`)).first().waitFor();
    }
  });
  await step('5-csv', async () => {
    const [download] = await Promise.all([page.waitForEvent('download'), page.getByRole('button', { name: 'Download CSV' }).click()]);
    if (download.suggestedFilename() !== 'msd-ui-outputs.csv') throw new Error(`downloaded as ${download.suggestedFilename()}`);
    const lines = readFileSync(await download.path(), 'utf8').trim().split('\n');
    if (!lines[0].startsWith('time,')) throw new Error(`the CSV starts with ${lines[0]}`);
    if (lines.length !== 3002) throw new Error(`the CSV has ${lines.length} lines`);
    console.log(`csv ${lines[0]} ${lines.length} lines`);
  });
  await step('6-realtime-stop', async () => {
    // Again, paced to the wall clock: 30 s, so it is still running when stopped. Its progress
    // and its chart move while it runs, read again by the page by itself.
    await page.getByLabel('Mode').selectOption('realtime');
    await page.getByLabel('Speed factor').fill('1');
    await page.getByRole('button', { name: 'Start again' }).click();
    await state().getByText('running', { exact: true }).waitFor();
    await until('progress shown while running', async () => (await progress()) > 0);
    await until('results charted while running', async () => (await chart().count()) > 0 && (await points()) > 0);
    const first = await points();
    await until('more results charted while running', async () => (await points()) > first);
    if ((await state().innerText()) !== 'running') throw new Error('it ended before it was stopped');
    await page.getByRole('button', { name: 'Stop', exact: true }).click();
    await state().getByText('stopped', { exact: true }).waitFor();
    const left = await progress();
    if (!(left > 0 && left < 1)) throw new Error(`stopped at progress ${left}`);
  });
  await step('7-list', async () => {
    await page.goto(`${url}/app/cosims`);
    const row = page.getByRole('table', { name: 'Co-simulations' }).getByRole('row', { name: /msd-ui/ });
    await row.getByText('stopped', { exact: true }).waitFor();
    await row.getByText('real time ×1').waitFor();
  });
  await step('8-refused', async () => {
    // A file that is no multi-model: the server's reason is shown in the form, nothing made.
    const form = await create(env('E2E_BAD'), 'broken', true);
    await form.getByRole('alert').getByText('(422)', { exact: false }).waitFor();
  });
  await step('9-delete', async () => {
    // Made without starting it: no results yet; then deleted after asking.
    await page.getByRole('form', { name: 'New co-simulation' }).getByRole('button', { name: 'Cancel' }).click();
    await create(env('E2E_ZIP'), 'msd-gone', false);
    await page.getByRole('heading', { name: /^msd-gone/ }).waitFor();
    await state().getByText('created', { exact: true }).waitFor();
    await page.getByText('No results yet').waitFor();
    page.once('dialog', (d) => void d.accept());
    await page.getByRole('button', { name: 'Delete', exact: true }).click();
    await page.getByRole('heading', { name: 'Co-simulations' }).waitFor();
    const table = page.getByRole('table', { name: 'Co-simulations' });
    await table.getByRole('row', { name: /msd-ui/ }).waitFor();
    if ((await table.getByRole('row', { name: /msd-gone/ }).count()) !== 0) throw new Error('msd-gone is still listed');
  });
  if (errors.length) throw new Error(`errors in the page: ${errors.join('; ')}`);
} finally {
  await browser.close();
}

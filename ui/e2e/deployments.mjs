// The Deployments pages in Debian's chromium, driven by playwright-core. Run by
// tests/integration/test_ui_deployments.py against a real server that holds the twin package
// common/twins/ui-tank (parameters capacity, sensors, medium, heated; a device `level`;
// lifecycle/analyze prints two lines, lifecycle/evolve prints one and runs until cancelled): E2E_URL, E2E_USER, E2E_PASSWORD (an
// admin), E2E_RUNS ("1" when the server has the runs API), E2E_SHOTS (folder). Prints
// "ok <step>" for each step that passed.
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
const page = await browser.newPage({ viewport: { width: 1280, height: 1000 } });
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
    await page.screenshot({ path: `${shots}/failed-deployments-${name}.png`, fullPage: true }).catch(() => {});
    throw new Error(`step "${name}" failed: ${err.message}`);
  }
  await page.screenshot({ path: `${shots}/deployments-${name}.png`, fullPage: true });
  console.log(`ok ${name}`);
};
const state = () => page.getByRole('heading', { level: 1 }).locator('.badge');

try {
  await step('1-login', async () => {
    await page.goto(`${url}/app/deployments`);
    await page.getByLabel('Username').fill(env('E2E_USER'));
    await page.getByLabel('Password').fill(env('E2E_PASSWORD'));
    await page.getByLabel('Password').press('Enter');
    await page.getByRole('heading', { name: 'Deployments' }).waitFor();
    await page.getByText('No deployment yet').waitFor();
  });
  await step('2-form', async () => {
    await page.getByRole('button', { name: 'New deployment' }).click();
    const form = page.getByRole('form', { name: 'New deployment' });
    await form.getByLabel('Twin package').selectOption('common/twins/ui-tank');
    // The form generated from the package's parameters, with their defaults and limits.
    const capacity = form.getByLabel('Capacity');
    await capacity.waitFor();
    if ((await capacity.inputValue()) !== '2.5') throw new Error(`capacity starts at ${await capacity.inputValue()}`);
    await form.getByText('tank volume in m³ Default: 2.5. Allowed: ≥ 0.1, ≤ 10.').waitFor();
    if ((await form.getByLabel('Name').inputValue()) !== 'ui-tank') throw new Error('the name is not the package name');
    // Filled from the keyboard only: every field is reached with Tab and has a label.
    await capacity.focus();
    await page.keyboard.press('Control+A');
    await page.keyboard.type('20');
    await form.getByLabel('Medium').selectOption('oil');
    await form.getByLabel('Heated').focus();
    await page.keyboard.press('Space');
    await form.getByLabel('Name').fill('tank-a');
    await form.getByRole('button', { name: 'Plan' }).click();
    // Checked before sending: 20 is over the maximum.
    await form.getByText('must be ≥ 0.1, ≤ 10').waitFor();
    await capacity.fill('4');
  });
  await step('3-plan', async () => {
    const form = page.getByRole('form', { name: 'New deployment' });
    await form.getByRole('button', { name: 'Plan' }).click();
    const plan = form.getByRole('region', { name: 'Plan' });
    await plan.getByText('2 to create, 0 to update, 0 to delete', { exact: false }).waitFor();
    const create = plan.getByRole('list', { name: 'Create' });
    await create.getByText('tank-a', { exact: true }).waitFor();
    await create.getByText('level', { exact: true }).waitFor();
  });
  await step('4-deploy', async () => {
    await page.getByRole('form', { name: 'New deployment' }).getByRole('button', { name: 'Deploy' }).click();
    await page.getByRole('heading', { name: /^tank-a/ }).waitFor();
    await state().getByText('running').waitFor();
    await page.getByRole('status').getByText('level:').waitFor(); // its device token, shown once
    await page.getByText('{"capacity":4,"sensors":1,"medium":"oil","heated":true}').waitFor();
  });
  if (process.env.E2E_RUNS === '1') {
    const runs = page.getByRole('table', { name: 'Runs' });
    await step('5-run-analyze', async () => {
      await page.getByLabel('Run phase').selectOption('analyze');
      await page.getByRole('button', { name: 'Run', exact: true }).click();
      const log = page.getByRole('region', { name: /^Log of run / });
      await log.getByTestId('run-log').getByText('analyzing tank-a', { exact: false }).waitFor();
      await log.locator('.badge').getByText('succeeded', { exact: true }).waitFor();
      await runs.getByRole('row', { name: /analyze/ }).locator('.badge').getByText('succeeded', { exact: true }).waitFor();
    });
    await step('6-live-log', async () => {
      // evolve prints a line, then runs until it is cancelled: the line is shown while the
      // run is still running, so it came over the live log, not from the stored one.
      await page.getByLabel('Run phase').selectOption('evolve');
      await page.getByRole('button', { name: 'Run', exact: true }).click();
      const log = page.getByRole('region', { name: /^Log of run / });
      await log.getByTestId('run-log').getByText('evolving tank-a', { exact: false }).waitFor();
      await log.locator('.badge').getByText('running', { exact: true }).waitFor();
      await runs.getByRole('button', { name: /^Cancel evolve run / }).click();
      await log.locator('.badge').getByText('cancelled', { exact: true }).waitFor();
      await runs.getByRole('row', { name: /evolve/ }).locator('.badge').getByText('cancelled', { exact: true }).waitFor();
    });
    await step('7-log-kept', async () => {
      // Reopened later, the page shows the whole log of any run.
      await page.reload();
      await runs.getByRole('button', { name: /^Log of analyze run / }).click();
      const log = page.getByRole('region', { name: /^Log of run / }).getByTestId('run-log');
      await log.getByText('analyzing tank-a', { exact: false }).waitFor();
      await log.getByText('capacity 4', { exact: false }).waitFor();
      await runs.getByRole('button', { name: /^Log of evolve run / }).click();
      await log.getByText('evolving tank-a', { exact: false }).waitFor();
    });
  }
  await step('8-reconfigure', async () => {
    // New parameters: the diff plan (the twin's description changes, the device is kept),
    // then applied; the deployment keeps running.
    await page.getByRole('button', { name: 'Reconfigure' }).click();
    const form = page.getByRole('form', { name: 'Reconfigure' });
    const capacity = form.getByLabel('Capacity');
    if ((await capacity.inputValue()) !== '4') throw new Error(`capacity shown as ${await capacity.inputValue()}`);
    await capacity.fill('5');
    await form.getByRole('button', { name: 'Plan changes' }).click();
    const plan = form.getByRole('region', { name: 'Plan' });
    await plan.getByText('oil tank of 5 m³', { exact: false }).waitFor();
    await plan.getByRole('list', { name: 'Keep' }).getByText('level', { exact: true }).waitFor();
    await form.getByRole('button', { name: 'Apply' }).click();
    await form.waitFor({ state: 'detached' });
    await page.getByText('{"capacity":5,"sensors":1,"medium":"oil","heated":true}').waitFor();
    await state().getByText('running').waitFor();
  });
  await step('9-stop', async () => {
    await page.getByRole('button', { name: 'Stop', exact: true }).click();
    await state().getByText('stopped').waitFor();
    await page.getByRole('button', { name: 'Start', exact: true }).waitFor();
    await page.goto(`${url}/app/deployments`);
    await page.getByRole('table', { name: 'Deployments' }).getByRole('row', { name: /tank-a/ }).getByText('stopped').waitFor();
  });
  await step('10-held', async () => {
    // The package's version is held by the deployment: deleting it is refused, and says why.
    await page.goto(`${url}/app/library?asset=common/twins/ui-tank`);
    page.once('dialog', (d) => void d.accept());
    await page.getByRole('table', { name: 'Versions' }).getByRole('button', { name: /^Delete / }).click();
    await page.getByRole('alert').getByText('(409)', { exact: false }).waitFor();
    const text = await page.getByRole('alert').innerText();
    if (!/deployment/.test(text)) throw new Error(`the refusal does not name its holder: ${text}`);
  });
  if (errors.length) throw new Error(`errors in the page: ${errors.join('; ')}`);
} finally {
  await browser.close();
}

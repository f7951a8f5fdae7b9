// The header's Workspace link in Debian's chromium, driven by playwright-core. Run by
// tests/integration/test_ui_workspace.py against a real server: E2E_URL, E2E_USER,
// E2E_PASSWORD, E2E_SHOTS (folder). Prints "ok <step>" for each step that passed.
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
const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
const page = await context.newPage();
const errors = [];
page.on('pageerror', (e) => errors.push(String(e)));
page.on('console', (m) => {
  if (m.type() === 'error') errors.push(m.text());
});
page.setDefaultTimeout(20000);
let shown = page;
const step = async (name, fn) => {
  try {
    await fn();
  } catch (err) {
    await shown.screenshot({ path: `${shots}/failed-workspace-${name}.png` }).catch(() => {});
    throw new Error(`step "${name}" failed: ${err.message}`);
  }
  await shown.screenshot({ path: `${shots}/workspace-${name}.png` });
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
  await step('2-open', async () => {
    // The tab opens at the click; the workspace starts (its first start takes a while), then
    // the tab follows the one-time link, which the proxy swaps for its cookie.
    const [tab] = await Promise.all([context.waitForEvent('page'), page.getByRole('button', { name: 'Workspace' }).click()]);
    shown = tab;
    await tab.waitForURL(new RegExp(`^${url}/workspaces/${env('E2E_USER')}/`), { timeout: 120000 });
    if (tab.url().includes('ticket=')) await tab.waitForURL((u) => !u.search.includes('ticket='), { timeout: 30000 });
    await tab.waitForFunction(() => /JupyterLab/.test(document.title), null, { timeout: 120000 });
    // The lab's own scripts came through the proxy too: its shell is drawn.
    await tab.locator('.jp-LabShell').waitFor({ timeout: 120000 });
    if ((await tab.evaluate(() => window.opener)) !== null) throw new Error('the workspace tab can reach the app through window.opener');
    await page.getByRole('button', { name: 'Workspace' }).waitFor(); // not left "Starting…"
  });
  if (errors.length) throw new Error(`errors in the app's page: ${errors.join('; ')}`);
} finally {
  await browser.close();
}

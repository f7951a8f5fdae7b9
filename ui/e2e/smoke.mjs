// End-to-end check of the web app in Debian's chromium, driven by playwright-core.
// Run by tests/integration/test_ui_e2e.py against a real server:
//   E2E_URL, E2E_USER, E2E_PASSWORD, E2E_TWIN (a twin with a service `self`), E2E_SHOTS (folder)
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
page.setDefaultTimeout(15000);
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
    await page.getByLabel('Search twins and features').fill('CAD');
    await page.getByText('CAD store').first().waitFor();
    await page.getByRole('link', { name: 'Ilmatar crane' }).first().click();
    await page.getByRole('heading', { name: 'Ilmatar crane' }).waitFor();
    await page.getByRole('heading', { name: 'CAD store' }).waitFor();
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
  if (pageErrors.length) throw new Error(`errors in the page: ${pageErrors.join('; ')}`);
} finally {
  await browser.close();
}

// The README's screenshot of Tingen's live page, taken from a running `make demo`:
//   node e2e/screenshot.mjs http://127.0.0.1:8000 ../docs/images/tingen-live.png
// with TWINLINK_PASSWORD set to the admin password (.twinlink-demo/admin-credentials.txt).
// It waits until the chart holds at least 20 s of the rig's samples.
import { chromium } from 'playwright-core';

const [url = 'http://127.0.0.1:8000', out = '../docs/images/tingen-live.png'] = process.argv.slice(2);
const password = process.env.TWINLINK_PASSWORD;
if (!password) throw new Error('TWINLINK_PASSWORD is not set');
const browser = await chromium.launch({
  executablePath: process.env.E2E_CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 760 } });
  page.setDefaultTimeout(60000);
  await page.goto(`${url}/app/`);
  await page.getByLabel('Username').fill(process.env.TWINLINK_USER || 'admin');
  await page.getByLabel('Password').fill(password);
  await page.getByLabel('Password').press('Enter');
  await page.getByRole('heading', { name: 'Catalog' }).waitFor();
  await page.goto(`${url}/app/twins/tingen/live?s=telemetry:Cantilever_Angle_radians,fmu:theta&w=30`);
  await page.getByRole('figure').waitFor();
  // 20 s of samples from the 100/s rig, for both signals.
  await page.waitForFunction(() => Number(document.querySelector('[data-testid="live-points"]')?.textContent) > 4000);
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await browser.close();
}

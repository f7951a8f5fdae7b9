// The server's API viewer (/docs) in Debian's chromium, driven by playwright-core. Run by
// tests/integration/test_ui_e2e.py against a real server: E2E_URL, E2E_TOKEN (an admin API
// token), E2E_SHOTS (folder). Prints "ok <step>" for each step that passed.
import { chromium } from 'playwright-core';

const env = (name) => {
  const value = process.env[name];
  if (!value) throw new Error(`${name} is not set`);
  return value;
};
const url = env('E2E_URL');
const token = env('E2E_TOKEN');
const browser = await chromium.launch({
  executablePath: process.env.E2E_CHROMIUM || '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
const pageErrors = [];
page.on('pageerror', (e) => pageErrors.push(String(e)));
// Every request the page makes goes to this server: nothing from a CDN.
const elsewhere = [];
page.on('request', (r) => {
  if (!r.url().startsWith(url) && !r.url().startsWith('data:')) elsewhere.push(r.url());
});
page.setDefaultTimeout(20000);
const ok = (step) => console.log(`ok ${step}`);

try {
  // The page asks for a token before it loads the API description.
  await page.goto(`${url}/docs`);
  await page.locator('#signin').waitFor();
  if ((await page.locator('.opblock-tag').count()) !== 0) throw new Error('operations shown before signing in');
  ok('asks for a token');

  await page.fill('#token', token);
  await page.click('#signin button[type=submit]');
  await page.locator('.opblock-tag').first().waitFor();
  const body = await page.locator('#swagger-ui').innerText();
  if (/Unable to render this definition/.test(body)) throw new Error('Swagger UI cannot read the description');
  // The operations are listed by tag, each tag collapsed (Swagger UI renders a long list of
  // operations only as far as it is scrolled): every tag of the description is there.
  const described = await page.evaluate(async (t) => {
    const spec = await (await fetch('/openapi.json', { headers: { Authorization: `Bearer ${t}` } })).json();
    const tags = new Set();
    for (const ops of Object.values(spec.paths)) for (const op of Object.values(ops)) for (const tag of op.tags || []) tags.add(tag);
    return [...tags].sort();
  }, token);
  await page.waitForFunction((n) => document.querySelectorAll('.opblock-tag').length >= n, described.length);
  const listed = (await page.locator('.opblock-tag').evaluateAll((els) => els.map((e) => e.dataset.tag))).sort();
  if (described.length < 15 || JSON.stringify(listed) !== JSON.stringify(described)) {
    throw new Error(`tags listed ${JSON.stringify(listed)}, described ${JSON.stringify(described)}`);
  }
  // A tag opens to its operations.
  await page.locator('.opblock-tag[data-tag="auth"]').click();
  await page.waitForFunction(() => document.querySelectorAll('.opblock').length >= 5);
  ok(`lists ${listed.length} tags of operations`);

  // "Try it out" on GET /api/v1/auth/me sends the token the page signed in with.
  const me = page.locator('.opblock-get', { has: page.locator('[data-path="/api/v1/auth/me"]') });
  await me.locator('.opblock-summary').click();
  await me.getByRole('button', { name: 'Try it out' }).click();
  await me.getByRole('button', { name: 'Execute' }).click();
  const status = me.locator('.live-responses-table .response .response-col_status').first();
  await status.waitFor();
  if ((await status.innerText()).trim() !== '200') throw new Error(`/auth/me answered ${await status.innerText()}`);
  const answer = await me.locator('.live-responses-table .response-col_description pre').first().innerText();
  if (!/"username": "admin"/.test(answer)) throw new Error(`unexpected answer: ${answer.slice(0, 300)}`);
  ok('try it out with the token');

  // An error answer is shown as the problem it is.
  await page.locator('.opblock-tag[data-tag="twins"]').click();
  const twin = page.locator('.opblock-get', { has: page.locator('[data-path="/api/v1/twins/{slug}"]') });
  await twin.locator('.opblock-summary').click();
  await twin.getByRole('button', { name: 'Try it out' }).click();
  await twin.locator('input[placeholder="slug"]').fill('no-such-twin');
  await twin.getByRole('button', { name: 'Execute' }).click();
  const missing = twin.locator('.live-responses-table .response .response-col_status').first();
  await missing.waitFor();
  if ((await missing.innerText()).trim() !== '404') throw new Error(`a missing twin answered ${await missing.innerText()}`);
  ok('an error answer');

  await page.screenshot({ path: `${env('E2E_SHOTS')}/apidocs.png`, fullPage: false });
  if (pageErrors.length) throw new Error(`page errors: ${pageErrors.join('; ')}`);
  if (elsewhere.length) throw new Error(`requests to other hosts: ${elsewhere.join(', ')}`);
  ok('no page errors, nothing from elsewhere');
} finally {
  await browser.close();
}

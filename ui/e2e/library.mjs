// The Library page in Debian's chromium, driven by playwright-core. Run by
// tests/integration/test_ui_library.py against a real server: E2E_URL, E2E_USER, E2E_PASSWORD
// (an admin), E2E_ZIP (a zip archive of a few files, one of them executable), E2E_SHOTS
// (folder). Prints "ok <step>" for each step that passed.
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
const context = await browser.newContext({ viewport: { width: 1280, height: 900 }, acceptDownloads: true });
const page = await context.newPage();
// No errors in the page and none in its console; an expected refusal (a 4xx of the API) shows
// in the page, not as a script error.
const errors = [];
page.on('pageerror', (e) => errors.push(String(e)));
page.on('console', (m) => {
  if (m.type() === 'error' && !/the server responded with a status of 4\d\d/.test(m.text())) errors.push(m.text());
});
page.setDefaultTimeout(15000);
const step = async (name, fn) => {
  try {
    await fn();
  } catch (err) {
    await page.screenshot({ path: `${shots}/failed-library-${name}.png` }).catch(() => {});
    throw new Error(`step "${name}" failed: ${err.message}`);
  }
  await page.screenshot({ path: `${shots}/library-${name}.png` });
  console.log(`ok ${name}`);
};
const upload = async (file, { scope, kind, name, tags }) => {
  const form = page.getByRole('form', { name: 'Upload' });
  await form.getByLabel('File or archive').setInputFiles(file);
  await form.getByLabel('Scope').selectOption(scope);
  await form.getByLabel('Kind').selectOption(kind);
  await form.getByLabel('Name').fill(name);
  await form.getByLabel('Tags').fill(tags);
  await form.getByRole('button', { name: 'Upload' }).click();
  return form.getByRole('status');
};

try {
  await step('1-login', async () => {
    await page.goto(`${url}/app/library`);
    await page.getByLabel('Username').fill(env('E2E_USER'));
    await page.getByLabel('Password').fill(env('E2E_PASSWORD'));
    await page.getByLabel('Password').press('Enter');
    await page.getByRole('heading', { name: 'Library' }).waitFor();
  });
  await step('2-upload-file', async () => {
    await page.getByRole('button', { name: 'Upload', exact: true }).click();
    const file = { name: 'readings.csv', mimeType: 'text/csv', buffer: Buffer.from('time,level\n0,1.5\n1,1.6\n') };
    const status = await upload(file, { scope: 'common', kind: 'data', name: 'tank-readings', tags: '1.0.0' });
    await status.getByText('Uploaded: common/data/tank-readings').waitFor();
    // Listed, with its tags, and opened with its one version.
    const row = page.getByRole('table', { name: 'Assets' }).getByRole('row', { name: /common\/data\/tank-readings/ });
    await row.getByText('1.0.0').waitFor();
    await page.getByRole('table', { name: 'Versions' }).getByText('1.0.0').waitFor();
  });
  await step('3-upload-archive', async () => {
    const status = await upload(env('E2E_ZIP'), { scope: 'common', kind: 'tools', name: 'tank-tool', tags: '0.1.0' });
    await status.getByText(/Uploaded: common\/tools\/tank-tool .*\(3 files\)/).waitFor();
    const versions = page.getByRole('table', { name: 'Versions' });
    await versions.getByRole('button', { name: /^Files of / }).click();
    const files = page.getByRole('table', { name: /^Files of / });
    await files.getByText('bin/run.sh').waitFor();
    await files.getByRole('row', { name: /bin\/run\.sh/ }).getByText('executable').waitFor();
    await files.getByText('docs/README.md').waitFor();
  });
  await step('4-filter-search', async () => {
    await page.getByRole('button', { name: 'tools', exact: true }).click();
    const assets = page.getByRole('table', { name: 'Assets' });
    await assets.getByText('common/tools/tank-tool').waitFor();
    await assets.getByText('common/data/tank-readings').waitFor({ state: 'detached' });
    await page.getByRole('button', { name: 'all kinds' }).click();
    await page.getByLabel('Search the library').fill('readings');
    await assets.getByText('common/tools/tank-tool').waitFor({ state: 'detached' });
    await assets.getByText('common/data/tank-readings').waitFor();
  });
  await step('5-download', async () => {
    // The open asset is in the page's address: a view can be linked.
    await page.goto(`${url}/app/library?asset=common/tools/tank-tool`);
    const versions = page.getByRole('table', { name: 'Versions' });
    const [download] = await Promise.all([
      page.waitForEvent('download'),
      versions.getByRole('button', { name: /as zip$/ }).click(),
    ]);
    const name = download.suggestedFilename();
    if (!/^tank-tool-[0-9a-f]{12}\.zip$/.test(name)) throw new Error(`downloaded as ${name}`);
    const bytes = readFileSync(await download.path());
    if (bytes.subarray(0, 2).toString() !== 'PK') throw new Error('the download is not a zip archive');
    console.log(`downloaded ${name} ${bytes.length}`);
  });
  await step('6-delete-version', async () => {
    // A second version of the readings, then the first one deleted: one is left.
    await page.getByRole('button', { name: 'Upload', exact: true }).click();
    const file = { name: 'readings.csv', mimeType: 'text/csv', buffer: Buffer.from('time,level\n0,1.5\n1,1.7\n') };
    const status = await upload(file, { scope: 'common', kind: 'data', name: 'tank-readings', tags: '1.1.0' });
    await status.getByText('Uploaded: common/data/tank-readings').waitFor();
    const versions = page.getByRole('table', { name: 'Versions' });
    await versions.getByText('1.1.0').waitFor();
    page.once('dialog', (d) => void d.accept());
    await versions.getByRole('row', { name: /1\.0\.0/ }).getByRole('button', { name: /^Delete / }).click();
    await versions.getByText('1.0.0').waitFor({ state: 'detached' });
    await versions.getByText('1.1.0').waitFor();
  });
  await step('7-tags', async () => {
    // A tag set on the version left, another removed: the version stays.
    const form = page.getByRole('form', { name: 'Set a tag' });
    await form.getByLabel('Tag').fill('stable');
    await form.getByRole('button', { name: 'Set tag' }).click();
    const versions = page.getByRole('table', { name: 'Versions' });
    await versions.getByText('stable').waitFor();
    await versions.getByRole('button', { name: 'Remove tag 1.1.0' }).click();
    await versions.getByText('1.1.0').waitFor({ state: 'detached' });
    await versions.getByText('latest').waitFor();
  });
  await step('8-compose', async () => {
    // The tool put in the package cart, composed into a twin package and pushed.
    await page.getByRole('button', { name: 'Add common/tools/tank-tool to the package' }).click();
    const form = page.getByRole('form', { name: 'Compose a package' });
    await form.getByLabel('Name of lib:common/tools/tank-tool@latest in the package').fill('tool');
    await form.getByLabel('Package name').fill('tank-kit');
    await form.getByLabel('Scope').selectOption('common');
    await form.getByLabel('Description').fill('A tank with its tool');
    const yaml = await form.getByLabel('twin.yaml').inputValue();
    if (!yaml.includes('  tool: "lib:common/tools/tank-tool@latest"')) throw new Error(`twin.yaml: ${yaml}`);
    await form.getByRole('button', { name: 'Push package' }).click();
    await form.getByRole('status').getByText('Pushed common/twins/tank-kit').waitFor();
    await page.getByRole('table', { name: 'Assets' }).getByText('common/twins/tank-kit').waitFor();
  });
  if (errors.length) throw new Error(`errors in the page: ${errors.join('; ')}`);
} finally {
  await browser.close();
}

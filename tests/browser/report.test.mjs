// SPDX-License-Identifier: MIT
// navbench's HTML reports in a real browser: Debian's chromium, headless, driven by npm's
// playwright-core (pinned to 1.61.1, the last release that runs on Debian 12's Node 18).
// Runs are made with the navbench under test (NAVBENCH), then each report is opened from
// file:// with every request but the file itself blocked, and must draw every plot, show
// its verdict, log no console error and run no script of its own text. A PNG screenshot and
// an A4 PDF of each go to the test's temporary folder (printed at the end).
//
//   NAVBENCH=build/bin/navbench NAV_SOURCE_DIR=. node --test tests/browser/report.test.mjs
//
// ctest runs it with label `browser`. Without chromium it is skipped, except under CI=true.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const NAVBENCH = process.env.NAVBENCH;
const SRC = process.env.NAV_SOURCE_DIR;
const CHROMIUM = process.env.NAV_CHROMIUM || '/usr/bin/chromium';
const CI = process.env.CI === 'true';
if (!NAVBENCH || !SRC) throw new Error('set NAVBENCH and NAV_SOURCE_DIR');

const haveChromium = fs.existsSync(CHROMIUM);
if (!haveChromium && CI) throw new Error(`${CHROMIUM} missing under CI=true (scripts/setup installs chromium)`);
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'navbench-browser-'));
const src = (p) => path.join(SRC, p);

/// Runs navbench with args in the work folder; resolves to its exit code and output.
function navbench(args) {
  return new Promise((resolve) => {
    const child = spawn(NAVBENCH, args, { cwd: work, stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '';
    child.stdout.on('data', (d) => { out += d; });
    child.stderr.on('data', (d) => { out += d; });
    child.on('close', (code) => resolve({ code, out }));
  });
}

// The runs: realtime ones one at a time (they are timed), then the lockstep ones together.
// The smoke scenario's 60 s play in lockstep: the modem and witness runs give the realtime
// report (lateness, deadlines).
const realtime = [
  { name: 'modem', args: ['run', src('scenarios/two-vehicles-modem.yaml'), '-o', 'modem', '-q'],
    verdict: 'PASS' },
  { name: 'crashed', args: ['run', src('tests/integration/scenarios/dut_exits.yaml'), '-o', 'crashed'],
    verdict: 'DUT crashed' },
  { name: 'witness', args: ['run', src('tests/integration/scenarios/witness.yaml'), '--witness',
                            '-o', 'witness', '-q'], verdict: 'PASS' },
];
const lockstep = [
  { name: 'smoke', args: ['run', src('scenarios/smoke.yaml'), '--mode', 'lockstep', '-o', 'smoke', '-q'] },
  { name: 'p0', args: ['run', src('scenarios/p0-pool-circle-ekf.yaml'), '--mode', 'lockstep', '-o', 'p0'] },
  { name: 'failing', args: ['run', src('tests/browser/scenarios/failing.yaml'), '-o', 'failing'],
    verdict: 'FAIL' },
  { name: 'hostile', args: ['run', src('tests/browser/scenarios/hostile.yaml'), '-o', 'hostile'] },
  { name: 'campaign', campaign: true,
    args: ['campaign', src('tests/integration/scenarios/campaign/straight_default.yaml'),
           src('tests/integration/scenarios/campaign/arc_stiff.yaml'), '--seeds', '2', '-j', '2',
           '-o', 'campaign', '-q'] },
];

let browser;
const made = {};

before(async () => {
  if (!haveChromium) return;
  for (const r of realtime) made[r.name] = await navbench(r.args);
  const results = await Promise.all(lockstep.map((r) => navbench(r.args)));
  lockstep.forEach((r, i) => { made[r.name] = results[i]; });
  const { chromium } = await import('playwright-core');
  browser = await chromium.launch({
    executablePath: CHROMIUM,
    headless: true,
    chromiumSandbox: false,
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--disable-dev-shm-usage'],
  });
});

after(async () => {
  if (browser) await browser.close();
  console.log(`# screenshots and PDFs in ${work}`);
});

/// Opens a report from file:// with the network blocked; returns the page and what it did.
async function open(file, { javaScript = true } = {}) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 }, javaScriptEnabled: javaScript });
  const page = await context.newPage();
  const url = pathToFileURL(file).href;
  const seen = { requests: [], errors: [], dialogs: [] };
  page.on('request', (r) => seen.requests.push(r.url()));
  page.on('console', (m) => { if (m.type() === 'error') seen.errors.push(m.text()); });
  page.on('pageerror', (e) => seen.errors.push(String(e)));
  page.on('dialog', (d) => { seen.dialogs.push(d.message()); d.dismiss(); });
  await page.route('**/*', (route) =>
    (route.request().url() === url ? route.continue() : route.abort('blockedbyclient')));
  await page.goto(url, { waitUntil: 'load' });
  return { page, context, url, seen };
}

/// What every report must do in the browser; returns the page for more checks.
async function checkReport(name, file, verdictText) {
  assert.ok(fs.existsSync(file), `${file} missing`);
  const { page, context, url, seen } = await open(file);
  try {
    const plots = await page.$$eval('[data-plot]', (els) => els.map((el) => {
      const canvas = el.querySelector('canvas');
      const box = canvas ? canvas.getBoundingClientRect() : { width: 0, height: 0 };
      const chart = window.navbenchCharts.find((c) => c.el === el);
      const values = chart ? chart.plot.data.slice(1).flat(2).filter((v) => v !== null && v !== undefined).length : 0;
      return { id: el.getAttribute('data-plot'), width: box.width, height: box.height, values };
    }));
    assert.ok(plots.length > 0, `${name}: no plot`);
    for (const p of plots) {
      assert.ok(p.width > 0 && p.height > 0, `${name}: plot ${p.id} has no size`);
      assert.ok(p.values > 0, `${name}: plot ${p.id} has no data`);
    }
    const verdict = page.locator('#verdict .verdict');
    assert.ok(await verdict.isVisible(), `${name}: verdict not visible`);
    assert.equal(await verdict.innerText(), verdictText);
    assert.deepEqual(seen.errors, [], `${name}: console errors`);
    assert.deepEqual(seen.dialogs, [], `${name}: a script of the report's text ran`);
    assert.deepEqual(seen.requests, [url], `${name}: requests other than the file`);
    await page.screenshot({ path: path.join(work, `${name}.png`), fullPage: true });
    await page.pdf({ path: path.join(work, `${name}.pdf`), format: 'A4', printBackground: true });
    assert.ok(fs.statSync(path.join(work, `${name}.pdf`)).size > 10000);
    return { page, plots };
  } finally {
    await context.close();
  }
}

function summaryOf(dir) {
  return JSON.parse(fs.readFileSync(path.join(work, dir, 'summary.json'), 'utf8'));
}

describe('run reports', { skip: !haveChromium && 'chromium is not installed' }, () => {
  for (const r of [...realtime, ...lockstep].filter((x) => !x.campaign)) {
    test(`${r.name}: report.html opens offline, every plot drawn, verdict shown`, async () => {
      const s = summaryOf(r.name);
      if (r.verdict) assert.equal(s.verdict, r.verdict, made[r.name].out);
      const { plots } = await checkReport(r.name, path.join(work, r.name, 'report.html'), s.verdict);
      const ids = plots.map((p) => p.id);
      assert.ok(ids.includes('plot-track'), `${r.name}: no track in ${ids}`);
      assert.ok(ids.some((id) => id.startsWith('plot-device-')), `${r.name}: no device timeline`);
    });
  }

  test('failing: the failed check is explained in the banner and marked on its plot', async () => {
    const file = path.join(work, 'failing', 'report.html');
    const { page, context } = await open(file);
    try {
      const why = await page.locator('#verdict ul.why').innerText();
      assert.match(why, /horizontal_error\s+NAV-REQ-012: max [0-9.]+ m \(limit 0\.050\)/);
      const over = await page.evaluate(() => {
        const c = window.navbenchCharts.find((x) => x.spec.id === 'plot-check-0');
        const i = c.spec.series.findIndex((s) => s.label === 'over the limit') + 1;
        return c.plot.data[i].filter((v) => v !== null).length;
      });
      assert.ok(over > 0, 'no sample marked over the limit');
      assert.match(await page.locator('#checks').innerText(), /horizontal error within 5 cm after alignment/);
    } finally {
      await context.close();
    }
  });

  test('witness: the timing audit table and the arrival histogram are drawn', async () => {
    const { page, context } = await open(path.join(work, 'witness', 'report.html'));
    try {
      const timing = await page.locator('#timing').innerText();
      assert.match(timing, /Timing audit/);
      assert.match(timing, /witness arrival lateness/);
      assert.doesNotMatch(timing, /DUT latency/);
      for (const line of ['ahrs', 'gps', 'dvl']) assert.match(timing, new RegExp(`\\n${line}\\t`));
      const bars = await page.evaluate(() => {
        const c = window.navbenchCharts.find((x) => x.spec.id === 'plot-arrival-hist');
        return c ? c.plot.data[1].filter((v) => v > 0).length : -1;
      });
      assert.ok(bars > 0, `arrival histogram: ${bars} bars`);
    } finally {
      await context.close();
    }
  });

  test('modem: both vehicles on the track and in the vehicle table', async () => {
    const { page, context } = await open(path.join(work, 'modem', 'report.html'));
    try {
      const labels = await page.evaluate(() =>
        window.navbenchCharts.find((c) => c.spec.id === 'plot-track').spec.series.map((s) => s.label));
      assert.ok(labels.includes('bravo truth') && labels.includes('bravo estimate'), labels.join(', '));
      const vehicles = await page.locator('#vehicles').innerText();
      assert.match(vehicles, /alpha/);
      assert.match(vehicles, /bravo/);
      assert.match(await page.locator('#devices').innerText(), /Acoustic links/);
    } finally {
      await context.close();
    }
  });

  test('hostile: a description and labels made of markup show as text and never run', async () => {
    const { page, context, seen } = await open(path.join(work, 'hostile', 'report.html'));
    try {
      const identity = await page.locator('#identity').innerText();
      assert.ok(identity.includes('<script>alert(1)</script><img src=x onerror=alert(2)>'), identity);
      assert.ok(identity.includes('</script><script>alert(3)</script>'), identity);
      assert.ok((await page.locator('#checks').innerText()).includes('<script>alert(5)</script>'));
      assert.equal(await page.locator('img').count(), 0);
      assert.deepEqual(seen.dialogs, []);
    } finally {
      await context.close();
    }
  });

  test('without JavaScript the text is all there', async () => {
    const { page, context } = await open(path.join(work, 'failing', 'report.html'), { javaScript: false });
    try {
      assert.equal(await page.locator('#verdict .verdict').innerText(), 'FAIL');
      assert.ok(await page.locator('#checks tr.fail').count() >= 1);
      assert.ok(await page.locator('#devices td').count() > 0);
      assert.ok(await page.locator('.needs-js').first().isVisible());
    } finally {
      await context.close();
    }
  });
});

describe('campaign report', { skip: !haveChromium && 'chromium is not installed' }, () => {
  test('campaign.html: distributions drawn, every run linked by a relative path', async () => {
    const file = path.join(work, 'campaign', 'campaign.html');
    assert.ok(fs.existsSync(file), made.campaign && made.campaign.out);
    const c = JSON.parse(fs.readFileSync(path.join(work, 'campaign', 'campaign.json'), 'utf8'));
    const code = c.exit_code;
    const verdict = code === 0 ? 'ALL PASSED' : code === 1 ? 'CHECKS FAILED' : 'RUNS IN ERROR';
    const { plots } = await checkReport('campaign', file, verdict);
    assert.ok(plots.some((p) => p.id.startsWith('plot-ecdf-')));
    const { page, context } = await open(file);
    try {
      const links = await page.$$eval('#runs a', (as) => as.map((a) => a.getAttribute('href')));
      assert.equal(links.length, c.runs.length);
      for (const href of links) {
        assert.ok(!href.startsWith('/') && !href.includes('://'), href);
        assert.ok(fs.existsSync(path.join(work, 'campaign', href)), href);
      }
    } finally {
      await context.close();
    }
  });
});

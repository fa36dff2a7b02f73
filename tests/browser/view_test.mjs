// `clever-support view` in a real browser (Debian's chromium, driven by the pinned puppeteer-core):
// the server refuses foreign requests, the page draws model and supports, and a strut omitted, a
// support point and a blocker added by mouse, then Regrow, leave the .scad holding the three edits,
// the supports exactly as `clever-support regrow` grows them from that file, and `check` passing
// (what the edits left bare reported as left out on purpose).
//
// usage: node view_test.mjs CLEVER_SUPPORT SOURCE_DIR [SCREENSHOT.png]
// Exit 0 pass, 1 fail, 77 skipped (chromium cannot start here; with CI=true that is a failure).
import { execFileSync, spawn } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import assert from 'node:assert/strict';

const [cli, source, screenshotOut] = process.argv.slice(2);
const SKIP = 77;
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'cs-view-'));
const out = path.join(tmp, 'arches');
const scad = path.join(out, 'arches.scad');
const started = Date.now();
const say = (what) => console.log(`[${((Date.now() - started) / 1000).toFixed(1)} s] ${what}`);
let server = null, browser = null;

async function finish(code) {
  if (browser) await browser.close().catch(() => browser.process()?.kill('SIGKILL'));
  if (server) server.kill('SIGTERM');
  fs.rmSync(tmp, { recursive: true, force: true, maxRetries: 5, retryDelay: 200 });
  process.exit(code);
}
function skip(why) {
  if (process.env.CI === 'true') {
    console.error(`FAIL: under CI=true this test may not skip: ${why}`);
    return finish(1);
  }
  console.log(`SKIPPED: ${why}`);
  return finish(SKIP);
}

const run = (...args) => execFileSync(cli, args, { encoding: 'utf8' });
const scadList = (text, name) => {
  const m = new RegExp(`^${name} = ([^;]*);`, 'm').exec(text);
  assert.ok(m, `${name} is assigned in the .scad`);
  return JSON.parse(m[1]);
};

// An ASCII STL of the box from corner `a` to corner `b`, its faces outward.
function boxStl(a, b) {
  const v = [];
  for (const z of [a[2], b[2]]) for (const y of [a[1], b[1]]) for (const x of [a[0], b[0]]) v.push([x, y, z]);
  const quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
  const facets = quads.flatMap(([p, q, r, t]) => [[p, q, r], [p, r, t]]).map((f) =>
    ` facet normal 0 0 0\n  outer loop\n${f.map((i) => `   vertex ${v[i].join(' ')}`).join('\n')}\n  endloop\n endfacet`);
  return `solid box\n${facets.join('\n')}\nendsolid box\n`;
}

// A raw request: the path exactly as given (no normalising), any Host header.
function request(port, rawPath, host, method = 'GET', body = null) {
  return new Promise((resolve, reject) => {
    const headers = host === null ? {} : { Host: host };  // null: no Host header at all
    const req = http.request({ host: '127.0.0.1', port, path: rawPath, method, headers, setHost: false }, (res) => {
      let data = '';
      res.on('data', (c) => { data += c; });
      res.on('end', () => resolve({ status: res.statusCode, body: data }));
    });
    req.on('error', reject);
    if (body) req.write(body);
    req.end();
  });
}

async function startServer() {
  server = spawn(cli, ['view', out + '/'], { stdio: ['ignore', 'pipe', 'pipe'] });
  let text = '';
  server.stderr.on('data', (c) => process.stderr.write(c));
  return new Promise((resolve, reject) => {
    server.stdout.on('data', (c) => {
      text += c;
      const m = /http:\/\/127\.0\.0\.1:(\d+)\/([0-9a-f]+)\//.exec(text);
      if (m) resolve({ url: m[0], port: Number(m[1]), token: m[2] });
    });
    server.on('exit', (code) => reject(new Error(`clever-support view exited (${code}) before printing its address`)));
  });
}

// Every request that is not the page's own is refused, and none reads or writes outside the folder.
async function checkRefusals({ port, token }) {
  const host = `127.0.0.1:${port}`;
  const ok = await request(port, `/${token}/files/report.json`, host);
  assert.equal(ok.status, 200, 'the page\'s own request is served');
  const refused = [
    ['/', host], [`/${token}`, host], ['/files/model.stl', host], [`/${'0'.repeat(token.length)}/`, host],
    [`/${token}/`, `evil.example:${port}`], [`/${token}/`, 'evil.example'], [`/${token}/`, `127.0.0.1:${port + 1}`],
    [`/${token}/`, null], [`/${token}/`, `localhost.evil.example:${port}`],
  ];
  for (const [p, h] of refused) {
    const r = await request(port, p, h);
    assert.equal(r.status, 403, `${p} with Host "${h}" is refused`);
  }
  const traversal = [
    `/${token}/files/../arches.scad`, `/${token}/files/..%2farches.scad`, `/${token}/files/%2e%2e/%2e%2e/etc/passwd`,
    `/${token}/../${token}/files/model.stl`, `/${token}/three/../../package.json`, `/${token}/page/../view_server.cpp`,
    `/${token}/files/model.stl/../../../../../etc/passwd`, `/${token}//etc/passwd`, `/${token}/files/%2Fetc%2Fpasswd`,
    `/${token}/..%2f..%2f..%2fetc%2fpasswd`, `/${token}/files/arches.scad`, `/${token}/page/..\\..\\view_server.cpp`,
  ];
  for (const p of traversal) {
    const r = await request(port, p, host);
    assert.ok(r.status === 403 || r.status === 404, `${p} is refused (got ${r.status})`);
    assert.ok(!r.body.includes('root:') && !r.body.includes('include') && r.body.length < 100, `${p} returns no file`);
  }
  const before = fs.readFileSync(scad, 'utf8');
  const bad = await request(port, `/${token}/api/edit`, host, 'POST', JSON.stringify({ op: 'set', name: '../../../tmp/x', value: 1 }));
  assert.equal(bad.status, 400, 'an edit of a name that is no Customizer value is refused');
  const foreign = await request(port, `/${token}/api/edit`, `evil.example:${port}`, 'POST', JSON.stringify({ op: 'toggle_strut', strut: 0 }));
  assert.equal(foreign.status, 403, 'an edit from a foreign Host is refused');
  assert.equal(fs.readFileSync(scad, 'utf8'), before, 'refused requests wrote nothing');
}

async function main() {
  run(path.join(source, 'examples/models/arches.stl'), '--orient', 'keep', '--no-timings', '-q', '--out', out);
  const filesBefore = fs.readdirSync(out).sort();
  const supportsBefore = fs.readFileSync(path.join(out, 'arches.supports.stl'));
  const site = await startServer();
  say(`serving ${site.url}`);
  await checkRefusals(site);
  say('foreign, token-less and path-traversal requests refused');

  let puppeteer;
  try {
    puppeteer = (await import('puppeteer-core')).default;
  } catch (e) {
    return skip(`puppeteer-core is not installed in tests/browser (scripts/install-deps.sh installs it): ${e.message.split('\n')[0]}`);
  }
  const profile = fs.mkdtempSync(path.join(tmp, 'profile-'));
  const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!fs.existsSync(chromium)) return skip(`no ${chromium} (scripts/install-deps.sh installs Debian's chromium)`);
  try {
    browser = await puppeteer.launch({
      executablePath: chromium, headless: true, userDataDir: profile, timeout: 60000,
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
             '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    });
  } catch (e) {
    return skip(`chromium cannot start here: ${e.message.split('\n')[0]}`);
  }
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
  await page.setViewport({ width: 1280, height: 800 });
  await page.goto(site.url, { waitUntil: 'load' });
  await page.waitForFunction('window.csView && window.csView.ready', { timeout: 60000 });
  assert.deepEqual(errors, [], 'the page loads without errors');
  const first = await page.evaluate(() => window.csView.state());
  assert.ok(!first.error, first.error);
  assert.ok(first.struts.length > 100, 'the tree\'s struts are there');
  assert.equal(first.check.ok, true, 'check passes on the generated supports');
  const counts = await page.evaluate(() => window.csView.colourCounts());
  say(`drawn: ${counts.grey} grey and ${counts.orange} orange pixels of ${counts.total}`);
  assert.ok(counts.grey > 0.02 * counts.total, 'the model is drawn (grey)');
  assert.ok(counts.orange > 0.01 * counts.total, 'the supports are drawn (orange)');

  // Hover a strut: its index, kind, width and length.
  const target = await page.evaluate(() => {
    const s = window.csView.state().struts;
    const order = [...s.keys()].sort((a, b) => s[b][5] - s[a][5]);  // longest first: easy to hit
    for (const i of order) { const at = window.csView.strutPixel(i); if (at) return { i, at }; }
    return null;
  });
  assert.ok(target, 'some strut is visible');
  await page.mouse.move(target.at.x, target.at.y);
  const tip = await page.$eval('#tip', (e) => e.textContent);
  assert.match(tip, new RegExp(`^strut ${target.i} · onto \\w+ · width [\\d.]+–[\\d.]+ mm · length [\\d.]+ mm`));
  say(`hover: "${tip}"`);

  // 1. Click the strut: omitted.
  await page.mouse.click(target.at.x, target.at.y);
  await page.waitForFunction((i) => window.csView.state().edits.omit_struts.includes(i), {}, target.i);
  // Click the (now faint) strut again: kept; and once more: omitted.
  await page.mouse.click(target.at.x, target.at.y);
  await page.waitForFunction(() => window.csView.state().edits.omit_struts.length === 0);
  assert.match(fs.readFileSync(scad, 'utf8'), /^omit_struts = \[\];/m, 'the second click undoes it in the file');
  await page.mouse.click(target.at.x, target.at.y);
  await page.waitForFunction((i) => window.csView.state().edits.omit_struts.includes(i), {}, target.i);
  // 2. From below, click the underside: a support point.
  await page.click('[data-camera=below]');
  await page.click('[data-mode=point]');
  const vp = { w: 1280 - 300, h: 800 };
  const pointAt = await page.evaluate((x, y) => window.csView.undersidePixel({ x, y }), vp.w * 0.65, vp.h * 0.5);
  assert.ok(pointAt, 'the underside is visible from below');
  await page.mouse.move(pointAt.x, pointAt.y);
  const where = await page.$eval('#tip', (e) => e.textContent);
  assert.match(where, /^x -?[\d.]+ {2}y -?[\d.]+ {2}z [\d.]+ mm$/, 'hovering the model shows placed coordinates');
  say(`hover on the model: "${where}"`);
  await page.mouse.click(pointAt.x, pointAt.y);
  await page.waitForFunction(() => window.csView.state().edits.support_points.length === 1 ||
    !document.getElementById('message').hidden);
  assert.equal(await page.$eval('#message', (e) => e.textContent), '', 'the point is taken');
  // 3. Drag out a blocker across another part of the underside.
  await page.click('[data-mode=blocker]');
  const from = await page.evaluate((x, y) => window.csView.undersidePixel({ x, y }), vp.w * 0.3, vp.h * 0.5);
  const to = await page.evaluate((x, y) => window.csView.undersidePixel({ x, y }), from.x + 50, from.y - 50);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(to.x, to.y, { steps: 5 });
  await page.mouse.up();
  await page.waitForFunction(() => window.csView.state().edits.support_blockers.length === 1 ||
    !document.getElementById('message').hidden);
  assert.equal(await page.$eval('#message', (e) => e.textContent), '', 'the blocker is taken');
  // 4. A Customizer slider re-sizes the struts without a regrow; a value regrow would refuse is
  // refused with its message, and the file keeps the last good value.
  const slide = (name, value) => page.$eval(`input[name=${name}]`, (el, v) => {
    el.value = String(v);
    el.dispatchEvent(new Event('change'));
  }, value);
  const widthsBefore = await page.evaluate(() => window.csView.state().struts.map((s) => s[3]));
  await slide('k', 0.004);
  await page.waitForFunction(() => window.csView.state().sliders.find((s) => s.name === 'k').value === 0.004);
  const widthsAfter = await page.evaluate(() => window.csView.state().struts.map((s) => s[3]));
  assert.equal(widthsAfter.length, widthsBefore.length, 'the same struts');
  assert.ok(widthsAfter.some((w, i) => w > widthsBefore[i] + 0.1), 'a larger k makes slanted struts thicker');
  // The picture for README: the edits shown, the omitted strut hovered.
  await page.click('[data-camera=front]');
  const ghost = await page.evaluate((i) => window.csView.strutPixel(i), target.i);
  if (ghost) await page.mouse.move(ghost.x, ghost.y);
  await page.screenshot({ path: path.join(tmp, 'view.png') });
  if (screenshotOut) fs.copyFileSync(path.join(tmp, 'view.png'), screenshotOut);

  await slide('d_min', 5);  // thicker than d_max = 4
  await page.waitForFunction(() => !document.getElementById('message').hidden);
  const refusal = await page.$eval('#message', (e) => e.textContent);
  assert.match(refusal, /arches\.scad:\d+: d_max = 4 is out of range/, 'the message names the file, the line and the value, as regrow says it');
  say(`refused: "${refusal}"`);
  assert.deepEqual(errors, ['Failed to load resource: the server responded with a status of 400 (Bad Request)'],
    'the refused edit is the only failed request');
  errors.length = 0;
  assert.match(fs.readFileSync(scad, 'utf8'), /^d_min = 1;/m);

  const edited = fs.readFileSync(scad, 'utf8');
  assert.match(edited, /^k = 0\.004;/m);
  assert.deepEqual(scadList(edited, 'omit_struts'), [target.i]);
  say(`edits in the .scad: omit_struts ${JSON.stringify(scadList(edited, 'omit_struts'))}, support_points ` +
      `${JSON.stringify(scadList(edited, 'support_points'))}, support_blockers ${JSON.stringify(scadList(edited, 'support_blockers'))}`);

  // 5. Regrow, with progress, and the view reloads.
  await page.click('#regrow');
  await page.waitForFunction(() => window.csView.regrows === 1, { timeout: 300000 });
  const stage = await page.$eval('#stage', (e) => e.textContent);
  const message = await page.$eval('#message', (e) => (e.hidden ? '' : e.textContent));
  assert.equal(stage, 'regrown', `regrow finished (${message})`);
  say('regrown from the page');
  assert.deepEqual(errors, [], 'no errors in the page');
  // check's verdict on the regrown supports, in the panel: it passes, what the edits left bare
  // counted as left out on purpose (the omitted branch by the file's omit_struts, the blocker's region).
  const judged = await page.evaluate(() => window.csView.state().check);
  assert.equal(judged.ok, true, `check passes on the regrown supports:\n${judged.summary}`);
  assert.ok(judged.left_out_area_mm2 > 0, 'the overhang the edits left bare is counted as left out on purpose');
  assert.match(await page.$eval('#verdict', (e) => e.textContent), /^passes: .*mm² left out on purpose by your edits\)$/);
  assert.equal((await page.evaluate(() => window.csView.markCount())).beyond, 0, 'nothing is marked red');

  // The .scad holds the three edits (regrow keeps them).
  const text = fs.readFileSync(scad, 'utf8');
  assert.deepEqual(scadList(text, 'omit_struts'), [target.i]);
  assert.equal(scadList(text, 'support_points').length, 1);
  assert.equal(scadList(text, 'support_blockers').length, 1);

  // The supports changed, exactly as `clever-support regrow` changes them from the edited file.
  const supportsAfter = fs.readFileSync(path.join(out, 'arches.supports.stl'));
  assert.ok(!supportsAfter.equals(supportsBefore), 'the supports changed');
  const twin = path.join(tmp, 'twin');
  fs.mkdirSync(twin);
  for (const f of ['arches.model.stl', 'clever_support.scad']) fs.copyFileSync(path.join(out, f), path.join(twin, f));
  fs.writeFileSync(path.join(twin, 'arches.scad'), edited);
  run('regrow', '-q', path.join(twin, 'arches.scad'));
  assert.ok(fs.readFileSync(path.join(twin, 'arches.supports.stl')).equals(supportsAfter),
    'the page\'s regrow wrote the supports `clever-support regrow` writes');
  assert.equal(fs.readFileSync(path.join(twin, 'arches.scad'), 'utf8'), text, 'and the same .scad');
  assert.deepEqual(fs.readdirSync(out).sort(), filesBefore, 'the folder holds the same files (nothing else written)');

  // `check` on the folder, as a user runs it, passes (exit 0: execFileSync throws on any other):
  // the omitted branch's overhang and the blocked region are reported as left out on purpose.
  const report = JSON.parse(run('check', out + '/', '--json'));
  assert.equal(report.ok, true);
  const leftOut = report.coverage.left_out_on_purpose;
  assert.deepEqual(report.settings.omit_struts, [target.i]);
  assert.equal(leftOut.regions, 1, 'the blocker is a region left out on purpose');
  assert.ok(leftOut.omitted_struts.tips > 0 && leftOut.omitted_struts.points > 0,
    `the omitted branch's tips and the overhang they held are reported (${JSON.stringify(leftOut.omitted_struts)})`);
  assert.match(run('check', out + '/'), /left out on purpose by the user's edit/);
  say(`check passes: ${leftOut.omitted_struts.area_mm2.toFixed(1)} mm² left out by omit_struts ` +
      `(${leftOut.omitted_struts.tips} tips), ${leftOut.area_mm2.toFixed(1)} mm² in the blocked region`);

  // That is the edit's doing: undo the omission (its ✕ in the panel) without regrowing, and the
  // bare branch is judged again: red on the page, exit 4 from the command line.
  await page.click('#edits li button');
  await page.waitForFunction(() => window.csView.state().edits.omit_struts.length === 0);
  const undone = await page.evaluate(() => window.csView.state().check);
  assert.equal(undone.coverage_ok, false, 'with the omission undone, the branch\'s overhang is beyond reach');
  assert.ok(undone.uncovered.length > 0, 'with places to mark in red');
  const red = await page.evaluate(() => window.csView.markCount());
  assert.ok(red.beyond >= undone.uncovered.length, `the places are drawn (${red.beyond} red marks)`);
  assert.throws(() => run('check', out + '/'), (e) => e.status === 4, 'check fails on the folder');

  // A solid fused into the model (a 2 mm cube planted in the arches' beam, in place of the
  // supports) is marked magenta once the page next asks (here: removing the support point).
  fs.writeFileSync(path.join(out, 'arches.supports.stl'), boxStl([-1, -1, 39.5], [1, 1, 41.5]));
  await page.click('#edits ul:nth-of-type(1) li button');
  await page.waitForFunction(() => window.csView.state().edits.support_points.length === 0);
  const planted = await page.evaluate(() => window.csView.state().check);
  assert.ok(planted.flagged.some((f) => /fused/.test(f.what)) && planted.flagged.some((f) => /too deep|penetration/.test(f.what)),
    `the fused, penetrating solid is flagged (${JSON.stringify(planted.flagged.map((f) => f.what))})`);
  assert.ok((await page.evaluate(() => window.csView.markCount())).flagged > 0, 'and marked in magenta');
  assert.match(await page.$eval('#verdict', (e) => e.textContent), /solid problem\(s\) \(magenta\)/);

  // A regrow that fails (the input moved away, as a hand edit of cs_input_path says) shows regrow's
  // own error and leaves the outputs as they were.
  fs.writeFileSync(scad, fs.readFileSync(scad, 'utf8').replace(/^cs_input_path = .*$/m, 'cs_input_path = "/nonexistent/arches.stl";'));
  const supportsPlanted = fs.readFileSync(path.join(out, 'arches.supports.stl'));
  await page.click('#regrow');
  await page.waitForFunction(() => window.csView.regrows === 2, { timeout: 300000 });
  assert.equal(await page.$eval('#stage', (e) => e.textContent), 'regrow failed (exit 3)');
  assert.match(await page.$eval('#message', (e) => e.textContent), /error: \/nonexistent\/arches\.stl: cannot open/);
  assert.ok(fs.readFileSync(path.join(out, 'arches.supports.stl')).equals(supportsPlanted), 'nothing was rewritten');
  assert.deepEqual(errors, [], 'no errors in the page');
  say('PASSED');
  return finish(0);
}

main().catch((e) => {
  console.error(`FAIL: ${e.stack || e.message}`);
  return finish(1);
});

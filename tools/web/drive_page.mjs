// Drives a published walkthrough page (`nestwalk publish`) in Debian's Chromium with playwright-core,
// for the tests: serves the site folder on a loopback port (no server of the project's needed),
// opens the page headless with software WebGL (Mesa's llvmpipe through ANGLE's EGL back end, the
// software GL the offscreen renderer uses; NESTWALK_CHROMIUM_GL replaces those flags, e.g.
// "--use-angle=swiftshader --enable-unsafe-swiftshader"), and prints one JSON object:
//   {"console_errors": [...], "load_seconds", "webgl_renderer", "at_time": {"t", "walker", "pose"} (with --time),
//    "shots": [{"t", "file"}] (with --shot T FILE, repeatable: the view alone, the page's overlays and
//    contact markers hidden),
//    "contact": {"info", "pose"} (after clicking contact button --contact N),
//    "fps" (frames drawn per second while playing, over --fps-ms), "screenshot" (with --screenshot)}.
// Exit status 0 when it could drive the page (the checks are the caller's), 2 otherwise.
//    "file_loaded", "problem" (with --file: the page opened as file://: whether it loaded, and what it
//    says to do when it could not).
// Usage: node drive_page.mjs SITE [--file] [--time T] [--contact N] [--fps-ms MS] [--screenshot FILE] [--shot T FILE]...
//        [--size WxH] [--chromium PATH]
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import { chromium } from 'playwright-core';

const args = process.argv.slice(2);
const site = args[0];
const option = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};
const [width, height] = option('--size', '1280x720').split('x').map(Number);
const types = { '.html': 'text/html', '.js': 'text/javascript', '.json': 'application/json', '.glb': 'model/gltf-binary', '.png': 'image/png' };

const server = createServer(async (req, res) => {
  const name = decodeURIComponent(new URL(req.url, 'http://localhost').pathname);
  const file = path.join(site, name === '/' ? 'index.html' : name);
  if (!file.startsWith(path.resolve(site))) { res.writeHead(403).end(); return; }
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'Content-Type': types[path.extname(file)] ?? 'application/octet-stream' }).end(body);
  } catch {
    res.writeHead(404).end();
  }
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const url = `http://127.0.0.1:${server.address().port}/`;

let browser;
const out = { console_errors: [] };
try {
  browser = await chromium.launch({
    executablePath: option('--chromium', '/usr/bin/chromium'),
    headless: true,
    args: [...(process.env.NESTWALK_CHROMIUM_GL ?? '--use-angle=gl-egl').split(' '), '--no-sandbox', '--ignore-gpu-blocklist',
           '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
           '--disable-quic'],
  });
  const page = await browser.newPage({ viewport: { width: width + 360, height } }); // the side panel is 360 px
  page.on('console', (m) => { if (m.type() === 'error') out.console_errors.push(m.text()); });
  page.on('pageerror', (e) => out.console_errors.push(String(e)));
  const start = Date.now();
  if (args.includes('--file')) {
    // Opened as a plain file: Chromium does not let the page read run.json beside it; the page
    // must say what to do instead.
    await page.goto(`file://${path.resolve(site, 'index.html')}`);
    out.file_loaded = await page.evaluate(() => window.nestwalk.ready.then(() => true, () => false));
    out.problem = await page.locator('#problem').textContent();
    if (!out.file_loaded) out.console_errors = [];  // the refused reads are the point there
    throw new Error('opened from a file');
  }
  await page.goto(url);
  await page.evaluate(() => window.nestwalk.ready);
  out.load_seconds = (Date.now() - start) / 1000;
  out.webgl_renderer = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas').getContext('webgl2');
    const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
    return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : (gl ? gl.getParameter(gl.RENDERER) : 'none');
  });
  const t = option('--time');
  if (t !== undefined) {
    out.at_time = await page.evaluate((value) => {
      window.nestwalk.setTime(value);
      return { t: window.nestwalk.time(), walker: window.nestwalk.walker(), pose: window.nestwalk.pose() };
    }, Number(t));
  }
  const contact = option('--contact');
  if (contact !== undefined) {
    await page.locator('.contact').nth(Number(contact)).click();
    out.contact = { info: await page.locator('#info').textContent(), pose: await page.evaluate(() => window.nestwalk.pose()) };
  }
  const shot = option('--screenshot');
  if (shot) {
    await page.locator('#view canvas').screenshot({ path: shot });
    out.screenshot = shot;
  }
  // --shot T FILE (repeatable): the view alone at time T, the page's overlays hidden.
  out.shots = [];
  for (let i = args.indexOf('--shot'); i >= 0; i = args.indexOf('--shot', i + 1)) {
    const [time, file] = [Number(args[i + 1]), args[i + 2]];
    await page.evaluate((value) => {
      for (const id of ['info', 'controls']) document.getElementById(id).style.visibility = 'hidden';
      window.nestwalk.showMarkers(false);
      window.nestwalk.setTime(value);
    }, time);
    await page.locator('#view canvas').screenshot({ path: file });
    out.shots.push({ t: time, file });
  }
  await page.evaluate(() => {
    for (const id of ['info', 'controls']) document.getElementById(id).style.visibility = '';
    window.nestwalk.showMarkers(true);
  });
  const fpsMs = option('--fps-ms');
  if (fpsMs !== undefined) {
    await page.locator('#play').click();
    out.fps = await page.evaluate((ms) => window.nestwalk.framesPerSecond(ms), Number(fpsMs));
  }
} catch (e) {
  if (out.problem === undefined) {
    console.error(String(e));
    process.exitCode = 2;
  }
} finally {
  if (browser) await browser.close();
  server.close();
}
console.log(JSON.stringify(out, null, 1));

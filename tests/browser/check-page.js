// Opens a contact sheet written by `meshtour batch --web` in headless Chromium (Debian's, driven
// by puppeteer-core) over a loopback HTTP server, and checks that every poster loaded, every video
// reaches readyState >= 2 and plays (currentTime advances), and the failed items show their error.
// Usage: node check-page.js OUT_DIR SCREENSHOT.png EXPECTED_ERROR_TEXT
// Exit 0: passed; 1: a check failed; 77: Chromium could not start (the caller decides: skip or fail).
'use strict';
const fs = require('fs');
const http = require('http');
const path = require('path');

const [outArg, screenshot, expectedError] = process.argv.slice(2);
const outDir = outArg && path.resolve(outArg);
if (!outArg || !screenshot || !expectedError) {
  console.error('usage: node check-page.js OUT_DIR SCREENSHOT.png EXPECTED_ERROR_TEXT');
  process.exit(2);
}
const types = { '.html': 'text/html; charset=utf-8', '.png': 'image/png', '.mp4': 'video/mp4', '.webm': 'video/webm',
                '.json': 'application/json', '.gltf': 'model/gltf+json', '.bin': 'application/octet-stream' };

// Static files of OUT_DIR with byte ranges (what a browser asks for when it plays a video).
function serve(req, res) {
  const name = decodeURIComponent(new URL(req.url, 'http://localhost').pathname).replace(/^\/+/, '') || 'index.html';
  const file = path.join(outDir, name);
  if (!file.startsWith(outDir + path.sep) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
    res.writeHead(404);
    return res.end();
  }
  const size = fs.statSync(file).size;
  const headers = { 'Content-Type': types[path.extname(file)] || 'application/octet-stream', 'Accept-Ranges': 'bytes' };
  const range = /bytes=(\d*)-(\d*)/.exec(req.headers.range || '');
  if (range) {
    const start = range[1] ? Number(range[1]) : 0;
    const end = range[2] ? Math.min(Number(range[2]), size - 1) : size - 1;
    res.writeHead(206, { ...headers, 'Content-Range': `bytes ${start}-${end}/${size}`, 'Content-Length': end - start + 1 });
    return fs.createReadStream(file, { start, end }).pipe(res);
  }
  res.writeHead(200, { ...headers, 'Content-Length': size });
  fs.createReadStream(file).pipe(res);
}

async function main() {
  const puppeteer = require('puppeteer-core');
  const server = http.createServer(serve);
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const url = `http://127.0.0.1:${server.address().port}/index.html`;
  let browser;
  try {
    browser = await puppeteer.launch({
      executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
      headless: true,
      args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--autoplay-policy=no-user-gesture-required',
             '--mute-audio'],
      timeout: 60000,
    });
  } catch (e) {
    server.close();
    console.error(`SKIP: Chromium could not start: ${e.message.split('\n')[0]}`);
    process.exit(77);
  }
  const failures = [];
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1100, height: 700 });
    const offsite = [];
    page.on('request', (r) => { if (!r.url().startsWith(`http://127.0.0.1:${server.address().port}/`) && !r.url().startsWith('data:')) offsite.push(r.url()); });
    await page.goto(url, { waitUntil: 'load', timeout: 60000 });
    const result = await page.evaluate(async () => {
      const wait = (ms) => new Promise((r) => setTimeout(r, ms));
      const posters = [...document.querySelectorAll('img.poster')];
      await Promise.all(posters.map((img) => (img.complete ? null : new Promise((r) => { img.onload = img.onerror = r; }))));
      const videos = [...document.querySelectorAll('video')];
      const played = await Promise.all(videos.map(async (v) => {
        v.muted = true;
        const advanced = new Promise((resolve) => v.addEventListener('timeupdate', () => { if (v.currentTime > 0) resolve(true); }));
        v.load();
        try { await v.play(); } catch (e) { return { src: v.currentSrc, error: String(e) }; }
        const ok = await Promise.race([advanced, wait(20000).then(() => false)]);
        return { src: v.currentSrc, readyState: v.readyState, currentTime: v.currentTime, advanced: ok,
                 error: v.error ? v.error.message || String(v.error.code) : '' };
      }));
      const failed = [...document.querySelectorAll('[data-status="failed"]')].map((d) => {
        const e = d.querySelector('.error');
        return { text: e ? e.textContent : '', visible: !!e && e.getBoundingClientRect().height > 0 };
      });
      return { posters: posters.map((i) => ({ src: i.src, width: i.naturalWidth })), played, failed,
               items: document.querySelectorAll('.item').length };
    });
    // Pause everything at the poster-like first frame for a stable screenshot.
    await page.evaluate(() => document.querySelectorAll('video').forEach((v) => { v.pause(); v.currentTime = 0; }));
    await new Promise((r) => setTimeout(r, 500));
    await page.screenshot({ path: screenshot, fullPage: true });
    console.log(JSON.stringify(result, null, 1));
    if (result.posters.length === 0) failures.push('no posters on the page');
    for (const p of result.posters) if (!(p.width > 0)) failures.push(`poster not loaded: ${p.src}`);
    if (result.played.length === 0) failures.push('no videos on the page');
    for (const v of result.played)
      if (v.error || !(v.readyState >= 2) || !v.advanced) failures.push(`video did not play: ${JSON.stringify(v)}`);
    if (result.failed.length === 0) failures.push('no failed item on the page');
    for (const f of result.failed)
      if (!f.visible || !f.text.includes(expectedError)) failures.push(`failed item does not show its error: ${JSON.stringify(f)}`);
    if (offsite.length) failures.push(`the page asked the network for: ${offsite.join(', ')}`);
  } finally {
    await browser.close();
    server.close();
  }
  if (failures.length) {
    for (const f of failures) console.error(`FAIL: ${f}`);
    process.exit(1);
  }
  console.log(`OK: ${screenshot}`);
}

main().catch((e) => { console.error(`FAIL: ${e.stack || e}`); process.exit(1); });

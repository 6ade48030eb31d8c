// The live view in a real browser (tests/tests/live_view.rs runs this inside the private
// network namespace): Debian's chromium, headless, driven by playwright-core. Loads the page,
// waits until it is connected and lists the movers, axes and nodes, takes two screenshots a
// second apart and compares the XPlanar panel's pixels: which changed, and whether they lie
// where the movers were or are. Prints one JSON line; the Rust test asserts on it.
//   node tests/web/live_view.mjs PAGE_URL OUT_DIR
import { chromium } from "playwright-core";
import { mkdtempSync, rmSync, mkdirSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

const [url, out] = process.argv.slice(2);
mkdirSync(out, { recursive: true });
const profile = mkdtempSync(join(tmpdir(), "live-view-chromium-"));
const ctx = await chromium.launchPersistentContext(profile, {
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  headless: true,
  viewport: { width: 1360, height: 1200 },
  args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync"],
});
const result = { url };
const errors = [];
let page;
try {
  page = ctx.pages()[0] ?? (await ctx.newPage());
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  await page.goto(url);
  await page.waitForFunction(() => {
    const v = window.motionView;
    return v && v.connected && v.movers.length > 0 && v.axes.length > 0 && v.nodes.length >= 3
      && v.transforms.planar;
  }, null, { timeout: 30000 });
  // What the page lists, as a user reads it.
  result.movers = await page.$$eval("#movers li", (li) => li.map((e) => e.dataset.mover));
  result.axes = await page.$$eval("#axes input", (i) => i.map((e) => e.dataset.axis));
  result.nodes = await page.$$eval("#stats tbody tr td:first-child", (td) => td.map((e) => e.textContent));
  // The scope draws: some pixels of the SetPos panel are not background.
  result.scope_pixels = await page.evaluate(() => {
    const c = document.getElementById("scope-pos");
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 3; i < d.length; i += 4) if (d[i]) n++;
    return n;
  });
  const grab = () => page.evaluate(() => {
    const c = document.getElementById("planar");
    const v = window.motionView;
    const at = {};
    for (const [name, [x, y]] of Object.entries(v.moverPositions)) {
      at[name] = v.toCanvas("planar", x / 1000, y / 1000);
    }
    return {
      pixels: Array.from(c.getContext("2d").getImageData(0, 0, c.width, c.height).data),
      width: c.width, height: c.height, at, scale: v.transforms.planar.s,
    };
  });
  const shot = async (name) => page.screenshot({ path: join(out, name), fullPage: true });
  await shot("live_view_1.png");
  const a = await grab();
  await page.waitForTimeout(1000);
  await shot("live_view_2.png");
  const b = await grab();
  // Changed pixels of the XPlanar panel, and those farther from every mover position (before
  // or after) than half a mover's diagonal plus a margin for its name label.
  const reach = 0.155 * Math.SQRT2 / 2 * a.scale + 16;
  let changed = 0, stray = 0;
  const near = (x, y) => Object.keys(a.at).some((m) =>
    [a.at[m], b.at[m]].some((p) => p && Math.hypot(p[0] - x, p[1] - y) <= reach));
  for (let y = 0; y < a.height; y++) {
    for (let x = 0; x < a.width; x++) {
      const i = 4 * (y * a.width + x);
      if (a.pixels[i] !== b.pixels[i] || a.pixels[i + 1] !== b.pixels[i + 1]
        || a.pixels[i + 2] !== b.pixels[i + 2] || a.pixels[i + 3] !== b.pixels[i + 3]) {
        changed++;
        if (!near(x, y)) stray++;
      }
    }
  }
  result.changed_pixels = changed;
  result.stray_pixels = stray;
  result.moved_px = Object.fromEntries(Object.keys(a.at).map((m) =>
    [m, b.at[m] ? Math.hypot(b.at[m][0] - a.at[m][0], b.at[m][1] - a.at[m][1]) : null]));
  result.errors = errors;
} catch (e) {
  result.failure = String(e);
  result.errors = errors;
  // What the page knew when it failed.
  result.view = await page?.evaluate(() => {
    const v = window.motionView;
    return v && { connected: v.connected, channels: v.channels, messages: v.messages,
      movers: v.movers, axes: v.axes, nodes: v.nodes, frames: v.frames,
      transforms: Object.keys(v.transforms), status: document.getElementById("status").textContent };
  }).catch((e) => String(e));
} finally {
  await ctx.close();
  rmSync(profile, { recursive: true, force: true });
}
console.log(JSON.stringify(result));

// tests/web/measure.mjs: frame times of the browser explorer in headless Chromium (docs/web.md).
//   node measure.mjs <aniso binary> <built page folder> [WxH ...] [--open FILE]
// For each size of the lit views' canvas: the mean time of a redraw (JavaScript + WebGL, gl.finish()
// at the end) when the light moves (every view recomputed) and when only the exposure changes (the
// lit views alone), 8 changes each after 2 warm-up ones (the shader compiles). --open: material A
// is that file (a measured .bsdf or .binary, or a JSON material), opened as the Open button does.
import { launch, serve } from "./harness.mjs";

const args = process.argv.slice(2);
const openAt = args.indexOf("--open");
const file = openAt >= 0 ? args.splice(openAt, 2)[1] : null;
const [aniso, webDir, ...sizes] = args;
const url = await serve(aniso, webDir);
const browser = await launch();
for (const size of sizes.length ? sizes : ["512x384", "1024x768"]) {
  const page = await browser.newPage({ viewport: { width: 1600, height: 1100 } });
  await page.goto(`${url}#size=${size}`);
  await page.waitForFunction(() => window.anisoExplorer && window.anisoExplorer.idle() && window.anisoExplorer.state.redraws > 0, null, { timeout: 120000 });
  if (file) {
    const opened = Date.now();
    await page.setInputFiles("#load", file);
    await page.waitForFunction(() => window.anisoExplorer.state.fileLoads > 0 && window.anisoExplorer.idle(), null, { timeout: 300000 });
    const err = await page.evaluate(() => window.anisoExplorer.error());
    if (err) throw new Error(err);
    const ms = await page.evaluate(() => window.anisoExplorer.results.fileMs);
    const tables = ms ? ` (read and tables ${ms.read.toFixed(0)} ms, texture upload ${ms.upload.toFixed(0)} ms)` : "";
    console.log(`${size}: ${file} opened and every view drawn, shaders compiled, in ${Date.now() - opened} ms${tables}`);
  }
  const run = async (id, values) => {
    const times = [];
    for (const v of values) {
      const n = await page.evaluate(([i, x]) => {
        const e = document.getElementById(i);
        e.value = x;
        e.dispatchEvent(new Event("input"));
        return window.anisoExplorer.state.redraws;
      }, [id, v]);
      await page.waitForFunction((k) => window.anisoExplorer.state.redraws > k && window.anisoExplorer.idle(), n, { timeout: 120000 });
      times.push(await page.evaluate(() => [window.anisoExplorer.results.frameMs.at(-1), window.anisoExplorer.results.stageMs.at(-1)]));
    }
    const t = times.slice(2), mean = (f) => (t.reduce((a, b) => a + f(b), 0) / t.length).toFixed(1);
    return `${mean((x) => x[0])} (lit ${mean((x) => x[1].lit)}, polar ${mean((x) => x[1].polar)}, albedo ${mean((x) => x[1].albedo)}, lobe ${mean((x) => x[1].lobe)})`;
  };
  const light = await run("theta", [20, 25, 30, 35, 40, 45, 50, 55, 60, 65]);
  const exposure = await run("exposure", [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]);
  console.log(`${size}: light moves ${light} ms a redraw; exposure only ${exposure} ms`);
  await page.close();
}
await browser.close();
process.exit(0);  // the server (harness.mjs) stops with the script

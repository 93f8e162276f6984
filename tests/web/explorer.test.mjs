// tests/web/explorer.test.mjs: the browser explorer (web/, docs/web.md) in headless Debian
// Chromium, driven by playwright-core (npm, pinned by package-lock.json; no browser download),
// software WebGL2 (SwiftShader). Run by ctest (tests/CMakeLists.txt):
//   node explorer.test.mjs <aniso binary> <built page folder> <output folder> [check ...]
// Exit 0: every check passed; 1: a check failed; 77: skipped (no Chromium, no playwright-core),
// with the reason on stdout. Screenshots of every view go to the output folder.
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { checker } from "./checks.mjs";

const [anisoArg, webDir, outDir, ...only] = process.argv.slice(2);
const aniso = path.resolve(anisoArg);
const skip = (why) => {
  console.log(`SKIPPED: ${why}`);
  process.exit(77);
};
const CHROMIUM = process.env.ANISO_CHROMIUM || "/usr/bin/chromium";  // as harness.mjs
if (!fs.existsSync(CHROMIUM)) skip(`${CHROMIUM} not found (install Debian's chromium: scripts/install-deps.sh)`);
let serve, launch, spherePixels;
try {
  ({ serve, launch, spherePixels } = await import("./harness.mjs"));  // imports playwright-core
} catch {
  skip(`playwright-core not installed (cd ${path.dirname(fileURLToPath(import.meta.url))} && npm ci)`);
}
fs.mkdirSync(outDir, { recursive: true });

// ---- the CLI, the reference for every number and message ------------------------------------
function run(args, input, cwd) {
  const r = spawnSync(aniso, args, { input, cwd, encoding: "utf8", maxBuffer: 64 << 20 });
  return { code: r.status, out: r.stdout, err: r.stderr };
}
const g9 = (x) => Number(x).toPrecision(9);

const url = await serve(aniso, webDir);
const browser = await launch();
const { check, finish } = checker();

// A page, with every console error, page error and request to another host recorded.
async function openPage(hash = "") {
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
  const page = await context.newPage();
  page.errors = [];
  page.foreign = [];
  page.on("console", (m) => m.type() === "error" && page.errors.push(m.text()));
  page.on("pageerror", (e) => page.errors.push(String(e)));
  page.on("request", (r) => !r.url().startsWith(url) && !r.url().startsWith("blob:") && !r.url().startsWith("data:") && page.foreign.push(r.url()));
  await page.goto(url + hash);
  await page.waitForFunction(() => window.anisoExplorer && window.anisoExplorer.idle() && window.anisoExplorer.state.redraws > 0, null, { timeout: 60000 });
  return page;
}
const idle = (page) => page.waitForFunction(() => window.anisoExplorer.idle(), null, { timeout: 60000 });
// A fingerprint of what the page shows: the lit sphere's radiance and the plots' values.
const fingerprint = (page) =>
  page.evaluate(() => {
    const E = window.anisoExplorer, s = E.readSphere();
    let a = 0;
    for (let i = 0; i < s.data.length; i += 7) a += s.data[i] * ((i % 13) + 1);
    let b = 0;
    E.results.polar.A.values.forEach((v, i) => (b += v * ((i % 11) + 1)));
    return [a, b];
  });

const want = (name) => only.length === 0 || only.includes(name);
const t0 = Date.now();

// 1. The page loads with no console error, draws every view, asks no other host.
if (want("load")) {
  const page = await openPage();
  check(page.errors.length === 0, `load: console errors: ${page.errors.join(" | ")}`);
  check(page.foreign.length === 0, `load: requests to other hosts: ${page.foreign.join(" ")}`);
  for (const id of ["gl", "polar-in", "polar-perp", "albedo", "lobe", "light"]) {
    const file = path.join(outDir, `view-${id}.png`);
    await page.locator(`#${id}`).screenshot({ path: file });
    check(fs.statSync(file).size > 1000, `load: view ${id} screenshot is empty`);
  }
  await page.screenshot({ path: path.join(outDir, "page.png") });
  const flat = await page.evaluate(() => {
    const s = window.anisoExplorer.readSphere();
    const vals = new Set();
    for (let i = 0; i < s.data.length; i += 97) vals.add(s.data[i].toFixed(4));
    return vals.size;
  });
  check(flat > 20, `load: the lit sphere is flat (${flat} distinct values)`);
  await page.context().close();
}

// 2. Every model's sliders exist and move the picture (the sphere or the plots).
if (want("sliders")) {
  const page = await openPage("#views=lit,polar");  // the albedo and the lobe are not needed here
  // The measured models are files (listed, disabled: tests/web/measured.test.mjs opens them).
  const models = await page.evaluate(() => [...document.querySelectorAll("#model option:not([disabled])")].map((o) => o.value));
  const tables = await page.evaluate(() => {
    const D = window.ANISO_DATA;
    return D.models.filter((m) => !D.no_glsl.includes(m.name) && !D.measured.models.includes(m.name)).map((m) => m.name);
  });
  check(JSON.stringify(models) === JSON.stringify(tables), `sliders: the model list ${models} is not the tables' ${tables}`);
  for (const model of models) {
    await page.selectOption("#model", model);
    await idle(page);
    check((await page.evaluate(() => window.anisoExplorer.error())) === "", `sliders: ${model}: error after choosing it`);
    const keys = await page.evaluate(() => [...document.querySelectorAll('#params input[type=range]')].map((r) => r.dataset.key));
    const expected = await page.evaluate((m) => {
      // Every Scalar and Color key of the material's table (nested ones included), shorthands apart.
      const out = [];
      const walk = (spec, v, prefix) => {
        for (const p of spec.params) {
          if (p.sets || !(p.name in v)) continue;
          if (p.kind === "scalar") out.push(prefix + p.name);
          if (p.kind === "color") for (let c = 0; c < 3; ++c) out.push(`${prefix}${p.name}[${c}]`);
          if (p.kind === "object") walk(p.sub, v[p.name], `${prefix}${p.name}.`);
          if (p.kind === "tagged-object") walk(p.subs[v[p.name].model], v[p.name], `${prefix}${p.name}.`);
          if (p.kind === "list") v[p.name].forEach((it, i) => walk(p.sub, it, `${prefix}${p.name}[${i}].`));
        }
      };
      walk(window.ANISO_DATA.models.find((t) => t.name === m), window.anisoExplorer.material(), "");
      return out;
    }, model);
    check(JSON.stringify(keys) === JSON.stringify(expected), `sliders: ${model}: sliders ${keys} but the table has ${expected}`);
    for (const key of keys) {
      const before = await fingerprint(page);
      const moved = await page.evaluate((k) => {
        const r = document.querySelector(`#params input[type=range][data-key="${k}"]`);
        // Colour channels move by different steps so that a colour leaves grey: tints (principled's
        // specular_tint and sheen_tint) act only on a coloured base.
        const step = k.endsWith("[1]") ? 200 : k.endsWith("[2]") ? 100 : 300;
        const v = Number(r.value);
        r.value = v > 500 ? v - step : v + step;
        r.dispatchEvent(new Event("input"));
        return true;
      }, key);
      await idle(page);
      const after = await fingerprint(page);
      const err = await page.evaluate(() => window.anisoExplorer.error());
      check(moved && (err !== "" || before[0] !== after[0] || before[1] !== after[1]), `sliders: ${model}: moving ${key} changes nothing`);
    }
    await page.locator("#views").screenshot({ path: path.join(outDir, `model-${model}.png`) });
  }
  check(page.errors.length === 0, `sliders: console errors: ${page.errors.join(" | ")}`);
  await page.context().close();
}

// 3. The polar plots' values (GPU, float target, read back) equal `aniso eval` at the same
// directions: relative 1e-4 (against max(|f|, 1e-2)), as tests/test_glsl.cpp holds the GLSL to the
// C++, unless float itself cannot resolve that: pow(n.h, e) with n.h rounded to float (2^-24) is
// off by e 2^-24 relative, so a material whose largest exponent e (n_u, n_v, n, exponent) makes
// 4 e 2^-24 exceed 1e-4 is held to that (blue acrylic's Ashikhmin-Shirley fit, e = 11600: 2.8e-3).
if (want("polar")) {
  const page = await openPage();
  const materials = ["brushed-gold", "ngan/ward/nickel", "ngan/lafortune/nickel", "ngan/ashikhminshirley/blue-acrylic", "matte-steel"];
  const models = await page.evaluate(() => [...document.querySelectorAll("#model option:not([disabled])")].map((o) => o.value));
  const cases = materials.map((m) => ({ preset: m })).concat(models.map((m) => ({ model: m })));
  for (const c of cases) {
    if (c.preset) {
      const ok = await page.evaluate((n) => window.ANISO_DATA.presets.some((p) => p.name === n), c.preset);
      if (!ok) continue;
      await page.selectOption("#preset", c.preset);
    } else await page.selectOption("#model", c.model);
    await page.evaluate(() => {
      const t = document.getElementById("theta");
      t.value = 50;
      t.dispatchEvent(new Event("input"));
    });
    await idle(page);
    const r = await page.evaluate(() => {
      const p = window.anisoExplorer.results.polar.A;
      return { wi: p.wi, wo: p.wo, values: Array.from(p.values), material: window.anisoExplorer.material() };
    });
    let emax = 0;
    JSON.stringify(r.material, (k, v) => {
      if (["n_u", "n_v", "n", "exponent"].includes(k)) emax = Math.max(emax, ...[].concat(v));
      return v;
    });
    const tol = Math.max(1e-4, 4 * emax * 2 ** -24);
    const lines = r.wo.map((wo) => `${r.wi.map(g9).join(" ")} ${wo.map(g9).join(" ")}`).join("\n") + "\n";
    const e = run(["eval", "--material", JSON.stringify(r.material)], lines);
    check(e.code === 0, `polar: aniso eval failed: ${e.err}`);
    const ref = e.out.trim().split("\n").map((l) => l.trim().split(/\s+/).map(Number));
    let worst = 0, where = "";
    ref.forEach((row, i) => {
      for (let k = 0; k < 4; ++k) {
        const g = r.values[i * 4 + k], d = Math.abs(g - row[k]) / Math.max(Math.abs(row[k]), 1e-2);
        if (d > worst) {
          worst = d;
          where = `direction ${i} channel ${k}: page ${g}, aniso eval ${row[k]}`;
        }
      }
    });
    const name = c.preset || c.model;
    console.log(`polar ${name}: ${ref.length} directions, worst relative difference ${worst.toExponential(2)} (tolerance ${tol.toExponential(2)})`);
    check(ref.length === 362 && worst <= tol, `polar: ${name}: ${where} (relative ${worst}, tolerance ${tol})`);
  }
  await page.context().close();
}

// 4. A link restores the material and the view exactly.
if (want("url")) {
  const page = await openPage();
  await page.selectOption("#preset", "ngan/lafortune/nickel").catch(() => {});
  await page.click("#add-lobes").catch(() => {});
  await idle(page);
  await page.evaluate(() => {
    const r = document.querySelector("#params input[type=number]");
    r.value = "0.123456789012345";
    r.dispatchEvent(new Event("change"));
    const t = document.getElementById("phi");
    t.value = 33.3;
    t.dispatchEvent(new Event("input"));
    document.getElementById("log").click();
  });
  await idle(page);
  const before = await page.evaluate(() => ({ m: window.anisoExplorer.material(), s: window.anisoExplorer.state, h: window.anisoExplorer.linkHash() }));
  const page2 = await openPage(before.h);
  const after = await page2.evaluate(() => ({ m: window.anisoExplorer.material(), s: window.anisoExplorer.state }));
  check(JSON.stringify(before.m) === JSON.stringify(after.m), `url: material ${JSON.stringify(before.m)} came back as ${JSON.stringify(after.m)}`);
  check(JSON.stringify([before.s.light, before.s.tangent, before.s.view]) === JSON.stringify([after.s.light, after.s.tangent, after.s.view]), "url: the view did not come back");
  check(JSON.stringify(before.m).includes("0.123456789012345"), "url: the typed value is not in the material");
  // A value out of range in the link: the message, and the default state kept.
  const page3 = await openPage("#theta=95&material=" + encodeURIComponent('{"model":"ward","alpha_x":2}'));
  const err3 = await page3.evaluate(() => window.anisoExplorer.error());
  check(err3 === 'aniso: error: link: key "theta": expected a number in [0, 89], got "95"', `url: bad theta: ${err3}`);
  const page4 = await openPage("#material=" + encodeURIComponent('{"model":"ward","alpha_x":2,"alpha_y":0.1}'));
  const err4 = await page4.evaluate(() => window.anisoExplorer.error());
  const cli4 = run(["eval", "--material", '{"model":"ward","alpha_x":2,"alpha_y":0.1}'], "0 0 1 0 0 1\n").err.trim();
  check(err4 === cli4, `url: bad material: page "${err4}", CLI "${cli4}"`);
  await page3.screenshot({ path: path.join(outDir, "error-url.png") });
  for (const p of [page, page2, page3, page4]) await p.context().close();
}

// 5. A bad material file shows the CLI's message, and the material stays the last good one.
if (want("errors")) {
  const page = await openPage();
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "aniso-web-"));
  const bad = [
    '{"model": "ward", "alpha_x": 0.1, "alpha_y": 0.2, "colour": 1}',
    '{"model": "ward", "alpha_x": 0, "alpha_y": 0.2}',
    '{"model": "ward", "alpha_x": 0.1}',
    '{"model": "ward", "alpha": 0.1, "alpha_x": 0.1}',
    '{"model": "ward", "kd": [0.1, 0.2]}',
    '{"model": "ward", "kd": [0.1, "x", 0.2]}',
    '{"model": "ward", "form": "fast"}',
    '{"model": "wardd"}',
    '{"kd": 0.5}',
    '[1, 2]',
    '{"model": "ward", "alpha_x": 0.1, "alpha_x": 0.2}',
    '{"model": "metal", "metal": "gold", "eta": 1}',
    '{"model": "metal"}',
    '{"model": "metal", "eta": 1, "lobe": {"model": "ggx"}}',
    '{"model": "metal", "metal": "gold", "lobe": {"model": "ggx"}, "directional_diffuse": {"cx": 0, "cy": 0, "cz": 0}}',
    '{"model": "metal", "metal": "gold", "lobe": {"model": "phong"}}',
    '{"model": "metal", "metal": "gold", "lobe": {"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.1, "q": 1}}',
    '{"model": "lafortune", "lobes": []}',
    '{"model": "lafortune", "lobes": [{"cx": -1, "cy": -1, "cz": 1, "n": 200, "scale": 1e10}]}',
    '{"model": "lafortune", "lobes": [3]}',
    '{"model": "phong", "normalized": 1}',
    '{"model": "ggx", "fit": 3}',
    '{"model": "lambert", "kd": 2.0}',
    '{"model": "ward", "alpha_x": 1.5e-7, "alpha_y": 0.1}',
    '{"model": "ward", "alpha_x": 123456789012.5, "alpha_y": 0.1}',
    '{"model": "ward", "alpha_x": 1e300, "alpha_y": 0.1}',
  ];
  const good = await page.evaluate(() => window.anisoExplorer.material());
  for (const text of bad) {
    fs.writeFileSync(path.join(dir, "bad.json"), text);
    const cli = run(["eval", "--material", "bad.json"], "0 0 1 0 0 1\n", dir);
    const msg = await page.evaluate((t) => {
      window.anisoExplorer.setMaterial(t, "bad.json");
      return window.anisoExplorer.error();
    }, text);
    check(cli.code === 2 && msg === cli.err.trim(), `errors: ${text}: page "${msg}", CLI "${cli.err.trim()}"`);
    const now = await page.evaluate(() => window.anisoExplorer.material());
    check(JSON.stringify(now) === JSON.stringify(good), `errors: ${text}: the material changed`);
  }
  // Invalid JSON: the page's syntax message is its own; the CLI's prefix and position are kept.
  for (const text of ['{"model": "ward",, }', '{"model": "ward"', '{"model": "ward", "kd": tru}']) {
    fs.writeFileSync(path.join(dir, "bad.json"), text);
    const cli = run(["eval", "--material", "bad.json"], "0 0 1 0 0 1\n", dir).err.trim();
    const msg = await page.evaluate((t) => {
      window.anisoExplorer.setMaterial(t, "bad.json");
      return window.anisoExplorer.error();
    }, text);
    const head = (m) => m.replace(/(column \d+).*/, "$1");
    check(head(msg) === head(cli), `errors: ${text}: page "${msg}", CLI "${cli}"`);
  }
  await idle(page);
  await page.screenshot({ path: path.join(outDir, "error-file.png") });
  fs.rmSync(dir, { recursive: true });
  await page.context().close();
}

// 6. The exports equal `aniso export-glsl` / `aniso export-brdf` of the same material.
if (want("exports")) {
  const page = await openPage();
  for (const preset of ["brushed-gold", "ngan/lafortune/nickel", "matte-steel", "ngan/ashikhminshirley/blue-acrylic"]) {
    const has = await page.evaluate((n) => window.ANISO_DATA.presets.some((p) => p.name === n), preset);
    if (!has) continue;
    await page.selectOption("#preset", preset);
    await idle(page);
    const [glsl, brdf] = await page.evaluate(() => {
      const E = window.anisoExplorer, m = E.state.A;
      return [E.exportGlsl(m), E.exportBrdf(m)];
    });
    check(glsl === run(["export-glsl", "--full", "--material", preset]).out, `exports: ${preset}: GLSL differs from aniso export-glsl --full`);
    check(brdf === run(["export-brdf", "--material", preset]).out, `exports: ${preset}: .brdf differs from aniso export-brdf`);
  }
  await page.context().close();
}

// 7. The lit sphere's pixels against the CPU: at a pixel the sphere's normal, its natural tangent
// and the light give wi and wo in the local frame; radiance = f(wi, wo) cos(theta_i) E by
// `aniso eval` (double) against the float target read back: relative 1e-3 (the float shading
// frame of the GPU against the CLI's double one).
if (want("sphere")) {
  const page = await openPage();
  for (const preset of ["brushed-gold", "ngan/ward/nickel", "ngan/lafortune/nickel"]) {
    await page.selectOption("#preset", preset);
    await idle(page);
    const r = await page.evaluate(() => {
      const E = window.anisoExplorer, s = E.readSphere(), st = E.state;
      return { w: s.w, h: s.h, data: s.data, light: st.light, material: E.material() };
    });
    const picks = spherePixels(r.w, r.h, r.light);
    const e = run(["eval", "--material", JSON.stringify(r.material)], picks.map((q) => `${q.wi.map(g9).join(" ")} ${q.wo.map(g9).join(" ")}`).join("\n") + "\n");
    const rows = e.out.trim().split("\n").map((l) => l.split(/\s+/).map(Number));
    let worst = 0, at = "";
    picks.forEach((q, i) => {
      for (let c = 0; c < 3; ++c) {
        const cpu = rows[i][c] * q.wi[2] * r.light.irradiance, gpu = r.data[(q.y * r.w + q.x) * 4 + c];
        const dd = Math.abs(gpu - cpu) / Math.max(Math.abs(cpu), 1e-2);
        if (dd > worst) {
          worst = dd;
          at = `pixel (${q.x}, ${q.y}) channel ${c}: page ${gpu}, CPU ${cpu}`;
        }
      }
    });
    console.log(`sphere ${preset}: ${picks.length} pixels, worst relative difference ${worst.toExponential(2)}`);
    check(picks.length > 50 && worst <= 1e-3, `sphere: ${preset}: ${at}`);
  }
  await page.context().close();
}

// The page's display pass against the CPU's tone map: the bytes of render::tonemap in
// tests/reference/tonemap_cpu.json (held to the CPU by tests/test_tonemap_parity.cpp), its ACES
// cases (the page has no clamp curve), every probe value in each channel, read back as floats.
if (want("tonemap")) {
  const page = await openPage();
  const ref = JSON.parse(fs.readFileSync(path.join(path.dirname(fileURLToPath(import.meta.url)), "..", "reference", "tonemap_cpu.json"), "utf8"));
  const radiance = ref.radiance.map(Number), n = radiance.length;
  const texels = [];
  for (let i = 0; i < n; ++i) texels.push(radiance[i], radiance[(i + 1) % n], radiance[(i + 2) % n], 1);
  let worst = 0, cases = 0;
  for (const c of ref.cases) {
    if (c.curve !== "aces") continue;
    ++cases;
    const out = await page.evaluate(([t, w, e]) => window.anisoExplorer.toneMapProbe(t, w, e), [texels, n, c.exposure]);
    for (let i = 0; i < n; ++i)
      for (let k = 0; k < 3; ++k) {
        const j = (i + k) % n, d = out[i * 4 + k], want = c.bytes[j];
        const diff = Number.isFinite(d) ? Math.abs(255 * d - want) : Infinity;
        worst = Math.max(worst, diff);
        // As the GL backend's test: the CPU rounds 255 d to a byte; 0.05 of a step covers pow's last bits.
        check(diff <= 0.55, `tonemap: radiance ${ref.radiance[j]}, exposure ${c.exposure}: page ${d} (x 255 = ${255 * d}), CPU byte ${want}`);
      }
  }
  console.log(`tonemap: ${cases} exposures x ${n} values x 3 channels, worst ${worst.toFixed(4)} of an 8-bit step`);
  check(cases >= 3, "tonemap: the reference has ACES cases");
  // One curve: the page holds no copy of its own (the ACES fit's constants come only in the GLSL).
  const js = await (await fetch(url + "explorer.js")).text();
  check(!/2\.43/.test(js) && !/0\.0031308/.test(js), "tonemap: web/explorer.js carries its own copy of the curve");
  await page.context().close();
}

await browser.close();
finish(t0, outDir);

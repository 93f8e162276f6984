// tests/web/measured.test.mjs: measured files in the browser explorer (web/measured.js, docs/web.md
// "Measured files"), against the CLI. Run by ctest (tests/CMakeLists.txt):
//   node measured.test.mjs <aniso binary> <built page folder> <output folder> [check ...]
// Checks:
//   reader   (Node, no browser) the page's reader on aniso-written tensor files (spectral, RGB,
//            anisotropic), a generated MERL table and the RGL database's files when
//            ../shared/data/rgl-real/ is present: its tables equal `aniso export-glsl`'s side file
//            float for float; 30 truncated or corrupt files give the CLI's message, word for word,
//            and the readers' notes are the CLI's.
//   rgl      an aniso-written anisotropic tensor file dropped on the page: every view, the polar
//            values and sphere pixels against `aniso eval`, the albedo against `aniso albedo`, the
//            exports against `aniso export-glsl`; a truncated and a corrupt file show the CLI's
//            message and change nothing.
//   rgl_real the same for one of the RGL database's files (skipped, saying why, without them).
//   merl     a generated MERL table opened: polar, sphere and albedo against the CLI, A | B against
//            an analytic material; truncated and corrupt tables, and one too large for the
//            browser's textures, show their messages and change nothing.
// Exit 0: passed; 1: a check failed; 77: skipped (no Chromium or playwright-core for a browser
// check, no real files for rgl_real), with the reason on stdout.
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import vm from "node:vm";
import { fileURLToPath } from "node:url";
import { checker } from "./checks.mjs";

const [anisoArg, webDir, outDir, ...only] = process.argv.slice(2);
const aniso = path.resolve(anisoArg);
const here = path.dirname(fileURLToPath(import.meta.url));
const realDir = path.resolve(here, "..", "..", "..", "shared", "data", "rgl-real");  // ../shared from the source dir
const skip = (why) => {
  console.log(`SKIPPED: ${why}`);
  process.exit(77);
};
const want = (name) => only.length === 0 || only.includes(name);
fs.mkdirSync(outDir, { recursive: true });
const dir = fs.mkdtempSync(path.join(os.tmpdir(), "aniso-web-measured-"));
process.on("exit", () => fs.rmSync(dir, { recursive: true, force: true }));
const t0 = Date.now();

const { check, finish } = checker();
// The CLI in the files' folder, so that its messages name the files as the page does.
function run(args, input = "") {
  const r = spawnSync(aniso, args, { input, cwd: dir, encoding: "utf8", maxBuffer: 256 << 20 });
  return { code: r.status, out: r.stdout, err: r.stderr };
}
const g9 = (x) => Number(x).toPrecision(9);

// ---- the files -----------------------------------------------------------------------------------
const small = ["--resolution", "8", "--theta-i", "4", "--ndf", "16", "--vndf", "16"];
function exportRgl(name, material, extra = []) {
  const r = run(["export-rgl", "-m", JSON.stringify(material), "-o", name, ...small, ...extra]);
  if (r.code !== 0) throw new Error(`aniso export-rgl failed: ${r.err}`);
  return name;
}
// A MERL table written here (aniso has no command that writes one): a Ward-like lobe plus a
// coloured diffuse part at MERL's bin centres (phi_h = 0); a bin whose centre pair dips below the
// horizon is missing (-1), as in MERL's own files and aniso's tabulate_merl.
function merlBytes() {
  const H = 90, T = 90, P = 180, bins = H * T * P, scale = [1 / 1500, 1.15 / 1500, 1.66 / 1500];
  const kd = [0.3, 0.2, 0.1], ks = 0.4, a = 0.15;
  const v = new Float64Array(3 * bins);
  for (let i = 0; i < H; ++i) {
    const u = (i + 0.5) / H, th = (u * u * Math.PI) / 2;
    for (let j = 0; j < T; ++j) {
      const td = ((j + 0.5) / T) * (Math.PI / 2);
      for (let k = 0; k < P; ++k) {
        const pd = ((k + 0.5) / P) * Math.PI, dx = Math.sin(td) * Math.cos(pd), dz = Math.cos(td);
        const wiz = -dx * Math.sin(th) + dz * Math.cos(th), woz = dx * Math.sin(th) + dz * Math.cos(th);
        const spec = (ks * Math.exp(-(Math.tan(th) ** 2) / (a * a))) / (4 * Math.PI * a * a * Math.sqrt(Math.max(wiz * woz, 1e-12)));
        for (let c = 0; c < 3; ++c) v[k + P * (j + T * i) + c * bins] = wiz > 0 && woz > 0 ? (kd[c] / Math.PI + spec) / scale[c] : -1;
      }
    }
  }
  const out = Buffer.alloc(12 + v.byteLength);
  [90, 90, 180].forEach((n, i) => out.writeInt32LE(n, 4 * i));
  Buffer.from(v.buffer).copy(out, 12);
  return out;
}
// The field table of a tensor file: where each field's name, dtype and data are (to corrupt them).
function fieldsOf(buf) {
  const fields = {};
  let pos = 18;
  for (let i = 0, n = buf.readUInt32LE(14); i < n; ++i) {
    const len = buf.readUInt16LE(pos), name = buf.toString("latin1", pos + 2, pos + 2 + len);
    const at = pos + 2 + len, ndim = buf.readUInt16LE(at);
    const shape = [];
    for (let d = 0; d < ndim; ++d) shape.push(Number(buf.readBigUInt64LE(at + 11 + 8 * d)));
    fields[name] = { namePos: pos + 2, dtypePos: at + 2, offset: Number(buf.readBigUInt64LE(at + 3)), shape };
    pos = at + 11 + 8 * ndim;
  }
  return fields;
}
function variant(src, name, edit) {
  const b = Buffer.from(fs.readFileSync(path.join(dir, src)));
  const r = edit(b, src.endsWith(".bsdf") ? fieldsOf(b) : null), out = Buffer.isBuffer(r) ? r : b;
  fs.writeFileSync(path.join(dir, name), out);
  return name;
}
const setF32 = (b, f, i, x) => b.writeFloatLE(x, f.offset + 4 * i);
// Truncated and corrupt tensor files, made from `src` (an aniso-written spectral anisotropic file).
function corruptTensors(src) {
  return [
    variant(src, "empty.bsdf", () => Buffer.alloc(0)),
    variant(src, "short.bsdf", (b) => b.subarray(0, 10)),
    variant(src, "magic.bsdf", (b) => void b.write("tensor_fil3", 0, "latin1")),
    variant(src, "version.bsdf", (b) => void (b[12] = 2)),
    variant(src, "count.bsdf", (b) => void b.writeUInt32LE(0x7fffffff, 14)),
    variant(src, "table.bsdf", (b) => b.subarray(0, 60)),
    variant(src, "truncated.bsdf", (b) => b.subarray(0, b.length - 1000)),
    variant(src, "dtype.bsdf", (b, f) => void (b[f.ndf.dtypePos] = 12)),
    variant(src, "float64.bsdf", (b, f) => void (b[f.theta_i.dtypePos] = 11)),
    variant(src, "twice.bsdf", (b, f) => void b.write("phi_i", f.sigma.namePos, "latin1")),
    variant(src, "missing.bsdf", (b, f) => void b.write("jacobiam", f.jacobian.namePos, "latin1")),
    variant(src, "jacobian.bsdf", (b, f) => void (b[f.jacobian.offset] = 0)),
    variant(src, "nan.bsdf", (b, f) => setF32(b, f.ndf, 37, NaN)),
    variant(src, "huge.bsdf", (b, f) => setF32(b, f.sigma, 3, 3e15)),
    variant(src, "negative.bsdf", (b, f) => setF32(b, f.luminance, 5, -0.25)),
    variant(src, "spectra.bsdf", (b, f) => setF32(b, f.spectra, 11, Infinity)),
    variant(src, "theta.bsdf", (b, f) => setF32(b, f.theta_i, 2, 0.1)),
    variant(src, "theta_range.bsdf", (b, f) => setF32(b, f.theta_i, 3, 2)),
    variant(src, "half_circle.bsdf", (b, f) => f.phi_i.shape[0] > 2 && setF32(b, f.phi_i, f.phi_i.shape[0] - 1, 0.5)),
    variant(src, "wavelengths.bsdf", (b, f) => setF32(b, f.wavelengths, 4, 300)),
    variant(src, "zero_slice.bsdf", (b, f) => {
      const n = f.vndf.shape[2] * f.vndf.shape[3];
      for (let i = 0; i < n; ++i) setF32(b, f.vndf, 2 * n + i, 0);
    }),
    variant(src, "garbage.bsdf", (b) => {
      for (let i = 18; i < 90; ++i) b[i] = (i * 37) & 0xff;
    }),
  ];
}
// Files that read, with a note: rounding noise of a density read as 0, sigma raised to its floor.
function notedTensors(src) {
  return [
    variant(src, "noise.bsdf", (b, f) => {
      setF32(b, f.luminance, 7, -1e-9);
      setF32(b, f.vndf, 9, -2e-10);
      setF32(b, f.vndf, 10, -3e-10);
    }),
    variant(src, "sigma_zero.bsdf", (b, f) => setF32(b, f.sigma, f.sigma.shape[1] - 1, 0)),
  ];
}
function corruptMerls(src) {
  const m = (name, edit) => variant(src, name, edit);
  const setRaw = (b, n, x) => b.writeDoubleLE(x, 12 + 8 * n);
  return [
    m("empty.binary", () => Buffer.alloc(0)),
    m("short.binary", (b) => b.subarray(0, 7)),
    m("header.binary", (b) => void b.writeInt32LE(91, 4)),
    m("truncated.binary", (b) => b.subarray(0, 12 + 8 * 2000003 + 5)),
    m("trailing.binary", (b) => Buffer.concat([b, Buffer.from([0])])),
    m("nan.binary", (b) => setRaw(b, 1458000 + 4321, NaN)),
    m("inf.binary", (b) => setRaw(b, 17, -Infinity)),
    m("large.binary", (b) => setRaw(b, 2 * 1458000 + 99, 2.5e20)),
  ];
}

// ---- the reader in Node: the page's scripts with the generated data, as the page loads them -------
// (in this context: a vm sandbox's typed arrays run the MERL tables 15 times slower)
function pageReader() {
  globalThis.window = globalThis;
  for (const f of ["aniso-data.js", "validate.js", "measured.js"]) vm.runInThisContext(fs.readFileSync(path.join(webDir, f), "utf8"), { filename: f });
  return globalThis.AnisoMeasured;
}
function readWithPage(M, name) {
  const b = fs.readFileSync(path.join(dir, name));
  try {
    const r = M.readMeasured(name, new Uint8Array(b.buffer, b.byteOffset, M.bytesNeeded(name, b.length)), b.length);
    return { r };
  } catch (e) {
    return { err: `aniso: error: ${e.message}` };
  }
}
const cliNotes = (err) => err.split("\n").filter((l) => l.startsWith("aniso: note: ")).map((l) => l.slice("aniso: note: ".length));

const realFiles = fs.existsSync(realDir) ? fs.readdirSync(realDir).filter((f) => f.endsWith(".bsdf")).sort() : [];
for (const f of realFiles) fs.symlinkSync(path.join(realDir, f), path.join(dir, f));  // read in place, named as the page names them
const iso = exportRgl("ggx_iso.bsdf", { model: "ggx", kd: [0.2, 0.1, 0.05], f0: 0.04, alpha: 0.2 });
const isoRgb = exportRgl("ggx_iso_rgb.bsdf", { model: "ggx", kd: [0.2, 0.1, 0.05], f0: 0.04, alpha: 0.2 }, ["--rgb"]);
const aniso_ = exportRgl("ggx_aniso.bsdf", { model: "ggx", kd: 0.1, f0: [0.9, 0.6, 0.3], alpha_x: 0.05, alpha_y: 0.3, rotation_deg: 30 }, ["--phi-i", "9"]);
fs.writeFileSync(path.join(dir, "ward.binary"), merlBytes());

if (want("reader")) {
  const M = pageReader();
  const good = [iso, isoRgb, aniso_, "ward.binary", ...realFiles, ...notedTensors(aniso_)];
  for (const name of good) {
    const tables = `${name}.tables`;
    const e = run(["export-glsl", "-m", name, "-o", `${name}.glsl`, "--tables", tables]);
    check(e.code === 0, `reader: aniso export-glsl -m ${name}: ${e.err}`);
    const { r, err } = readWithPage(M, name);
    check(!err, `reader: ${name}: the page refuses it: ${err}`);
    if (!r || e.code !== 0) continue;
    const c = fs.readFileSync(path.join(dir, tables)), cpp = new Float32Array(c.buffer, c.byteOffset, c.length / 4);
    let differ = 0, first = -1;
    for (let i = 0; i < cpp.length; ++i) {
      const v = i < r.tables.length ? r.tables[i] : 0;
      if (!Object.is(v, cpp[i])) {
        if (first < 0) first = i;
        ++differ;
      }
    }
    const padded = Math.ceil(r.tables.length / 4096) * 4096;
    console.log(`reader ${name}: ${r.model}, ${r.tables.length} floats, ${differ} differ from aniso export-glsl's tables`);
    check(cpp.length === padded && differ === 0, `reader: ${name}: ${differ} of ${cpp.length} floats differ from the C++ tables (the first at ${first}: page ${r.tables[first]}, C++ ${cpp[first]})`);
    const notes = cliNotes(run(["eval", "-m", name], "0 0 1 0 0 1\n").err);
    check(JSON.stringify(r.notes) === JSON.stringify(notes), `reader: ${name}: notes ${JSON.stringify(r.notes)}, the CLI's ${JSON.stringify(notes)}`);
  }
  check(readWithPage(M, "noise.bsdf").r.notes.length === 2 && readWithPage(M, "sigma_zero.bsdf").r.notes.length === 1, "reader: the noted files give their notes");
  let n = 0;
  for (const name of [...corruptTensors(aniso_), ...corruptMerls("ward.binary")]) {
    const cli = run(["eval", "-m", name], "0 0 1 0 0 1\n");
    const page = readWithPage(M, name).err;
    check(cli.code === 2 && page === cli.err.trim(), `reader: ${name}: page "${page}", CLI "${cli.err.trim()}"`);
    ++n;
  }
  console.log(`reader: ${n} bad files, each with the CLI's message`);
}

// ---- the browser ---------------------------------------------------------------------------------
const browserChecks = ["rgl", "rgl_real", "merl"].filter(want);
if (browserChecks.length) {
  const CHROMIUM = process.env.ANISO_CHROMIUM || "/usr/bin/chromium";
  if (!fs.existsSync(CHROMIUM)) skip(`${CHROMIUM} not found (install Debian's chromium: scripts/install-deps.sh)`);
  let harness;
  try {
    harness = await import("./harness.mjs");  // imports playwright-core
  } catch {
    skip(`playwright-core not installed (cd ${here} && npm ci)`);
  }
  if (browserChecks.length === 1 && browserChecks[0] === "rgl_real" && !realFiles.length)
    skip(`${realDir} is absent (CI has it): no real RGL file to open in the page`);
  const url = await harness.serve(aniso, webDir);
  const browser = await harness.launch();

  // A page with the light at 50 degrees, computing the polar plots only until views() adds the
  // others (each view's shader compiles for each material shape: seconds on SwiftShader, so the
  // analytic start-up material compiles only the plots'); console errors recorded.
  async function openPage() {
    const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
    const page = await context.newPage();
    page.errors = [];
    page.on("console", (m) => m.type() === "error" && page.errors.push(m.text()));
    page.on("pageerror", (e) => page.errors.push(String(e)));
    await page.goto(`${url}#theta=50&views=polar`);
    await page.waitForFunction(() => window.anisoExplorer && window.anisoExplorer.idle() && window.anisoExplorer.state.redraws > 0, null, { timeout: 120000 });
    return page;
  }
  const E = (page, f, arg) => page.evaluate(f, arg);
  const idle = (page) => page.waitForFunction(() => window.anisoExplorer.idle(), null, { timeout: 120000 });
  async function views(page, list) {
    await E(page, (v) => window.anisoExplorer.applyHash(`#views=${v}`), list);
    await idle(page);
  }
  // Opens a file through the file input (as the Open button) or by a drop on the page; waits until
  // it is read and every view redrawn.
  async function open(page, name, how = "input") {
    const n = await E(page, () => window.anisoExplorer.state.fileLoads);
    if (how === "input") await page.setInputFiles("#load", path.join(dir, name));
    else {
      const b64 = fs.readFileSync(path.join(dir, name)).toString("base64");
      await E(page, ([nm, data]) => {
        const bytes = Uint8Array.from(atob(data), (c) => c.charCodeAt(0));
        const dt = new DataTransfer();
        dt.items.add(new File([bytes], nm));
        document.dispatchEvent(new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
      }, [name, b64]);
    }
    await page.waitForFunction((k) => window.anisoExplorer.state.fileLoads > k, n, { timeout: 120000 });
    await idle(page);
    return E(page, () => window.anisoExplorer.error());
  }
  // What must not change when a file is refused: the material, its tables, the polar values.
  const snapshot = (page) =>
    E(page, () => {
      const X = window.anisoExplorer, A = X.state.A;
      let h = 0;
      if (A.tables) for (let i = 0; i < A.tables.length; i += 97) h = (h * 31 + A.tables[i]) % 1e9;
      return JSON.stringify([X.material(), A.where, A.summary, h, Array.from(X.results.polar.A.values)]);
    });

  // The bound of a value. The GPU's atan, sqrt and normalize are not correctly rounded, so its
  // angles are a few ulp off the CPU's, and the tables' interpolation (or MERL's nearest bin) turns
  // that into a change of f in proportion to its slope (or a step at a bin edge): as
  // tests/test_glsl_measured.cpp (jitter_bound; docs/glsl.md "Parity of the measured twins"), the
  // change of the CLI's f and pdf when wi and wo are each turned by 4e-6 rad in 8 directions. The CLI
  // is no exact reference either: its RGL kernel takes theta = acos(float(z)) as pbrt-v4 does
  // (include/aniso/brdf/rgl.h theta_of), where rgl.glsl takes atan(|w.xy|, z), so near the normal its
  // theta moves in steps of min(2^-24 / sin theta, 2^-11.5) rad (one float step of z; at theta
  // ~ 0.5 degrees 7e-6 rad, 0.08 %, which at a real file's sharp mirror peak is 0.05 % of f): the
  // pair turned rigidly by that step about the axes that tilt the half vector and wo gives that
  // term. The bound is 4 x the largest of those changes (several angles err at once), and at least
  // 2e-4 relative (float arithmetic through the interpolation) or 1e-6 absolute.
  const kJitter = 4e-6;
  const cross = (u, v) => [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  const norm = (v) => v.map((x) => x / Math.hypot(...v));
  function turned(w, k, which) {
    const a = Math.abs(w[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
    const t = norm(cross(a, w)), b = cross(w, t), ang = (2 * Math.PI * (k + 0.5 * which)) / 8;
    return norm(w.map((x, i) => x + kJitter * (Math.cos(ang) * t[i] + Math.sin(ang) * b[i])));
  }
  // v turned by `ang` about the unit axis k (Rodrigues).
  const rotate = (v, k, ang) => {
    const c = Math.cos(ang), s = Math.sin(ang), kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2], kx = cross(k, v);
    return v.map((x, i) => x * c + kx[i] * s + k[i] * kv * (1 - c));
  };
  // The pair turned rigidly by one float step of acos about the axis that tilts w (w = the half
  // vector, or wo).
  function tilted(wi, wo, w, sign) {
    const sin = Math.hypot(w[0], w[1]), axis = sin > 1e-12 ? [-w[1] / sin, w[0] / sin, 0] : [0, 1, 0];
    const step = sign * Math.min(2 ** -24 / Math.max(sin, 1e-30), 2 ** -11.5);
    return [rotate(wi, axis, step), rotate(wo, axis, step)];
  }
  // `aniso eval` at the pairs and at their perturbations: per pair the CLI's 4 values and bounds.
  const kPerturbed = 28;
  function evalWithBounds(name, pairs) {
    const lines = [];
    for (const [wi, wo] of pairs) {
      lines.push([wi, wo]);
      for (let k = 0; k < 8; ++k) for (let which = 0; which < 3; ++which) lines.push([which !== 1 ? turned(wi, k, which) : wi, which !== 0 ? turned(wo, k, which) : wo]);
      const wm = norm(wi.map((x, i) => x + wo[i]));
      for (const w of [wm, wo]) for (const sign of [1, -1]) lines.push(tilted(wi, wo, w, sign));
    }
    const e = run(["eval", "-m", name], lines.map(([a, b]) => `${a.map(g9).join(" ")} ${b.map(g9).join(" ")}`).join("\n") + "\n");
    if (e.code !== 0) throw new Error(`aniso eval -m ${name}: ${e.err}`);
    const rows = e.out.trim().split("\n").map((l) => l.trim().split(/\s+/).map(Number));
    return pairs.map((_, i) => {
      const at = (kPerturbed + 1) * i, base = rows[at], bound = [0, 0, 0, 0];
      for (let j = 1; j <= kPerturbed; ++j) for (let c = 0; c < 4; ++c) bound[c] = Math.max(bound[c], 4 * Math.abs(rows[at + j][c] - base[c]));
      return { cpu: base, bound: bound.map((b, c) => Math.max(b, 2e-4 * Math.abs(base[c]), 1e-6)) };
    });
  }
  // The polar values of A (f r g b, pdf at 362 directions) against the CLI.
  async function checkPolar(page, name) {
    const r = await E(page, () => {
      const p = window.anisoExplorer.results.polar.A;
      return { wi: p.wi, wo: p.wo, values: Array.from(p.values) };
    });
    const ref = evalWithBounds(name, r.wo.map((wo) => [r.wi, wo]));
    let worst = 0, where = "", widened = 0, rel = 0;
    ref.forEach(({ cpu, bound }, i) => {
      for (let k = 0; k < 4; ++k) {
        const g = r.values[i * 4 + k], d = Math.abs(g - cpu[k]);
        if (bound[k] > Math.max(2e-4 * Math.abs(cpu[k]), 1e-6)) ++widened;
        if (Math.abs(cpu[k]) > 1e-3) rel = Math.max(rel, d / Math.abs(cpu[k]));
        if (!(d / bound[k] <= worst)) {
          worst = d / bound[k];
          where = `direction ${i} channel ${k}: page ${g}, aniso eval ${cpu[k]}, bound ${bound[k]}`;
        }
      }
    });
    const lit = ref.filter(({ cpu }) => cpu[0] + cpu[1] + cpu[2] > 0).length;
    console.log(`polar ${name}: ${ref.length} directions (${lit} with f > 0), worst difference ${worst.toFixed(3)} of its bound, ` +
      `largest relative difference ${rel.toExponential(2)}, ${widened} of ${4 * ref.length} bounds widened by the slope`);
    check(ref.length === 362 && lit > 100 && worst <= 1, `polar: ${name}: ${where}`);
  }
  // Pixels of the lit sphere (A) against the CLI: the sphere's normal, natural tangent and the light
  // give wi, wo (as explorer.test.mjs "sphere"); radiance f cos E within the pair's bound, or 1e-3
  // relative (the GPU's float frame against the CLI's double one); the sphere is not black.
  async function checkSphere(page, name) {
    const r = await E(page, () => {
      const X = window.anisoExplorer, s = X.readSphere();
      return { w: s.w, h: s.h, data: s.data, light: X.state.light };
    });
    const picks = harness.spherePixels(r.w, r.h, r.light);
    const ref = evalWithBounds(name, picks.map((q) => [q.wi, q.wo]));
    let worst = 0, where = "", lit = 0, brightest = 0;
    picks.forEach((q, i) => {
      const E_ = q.wi[2] * r.light.irradiance;
      for (let c = 0; c < 3; ++c) {
        const cpu = ref[i].cpu[c] * E_, gpu = r.data[(q.y * r.w + q.x) * 4 + c];
        const d = Math.abs(gpu - cpu) / Math.max(ref[i].bound[c] * E_, 1e-3 * Math.abs(cpu), 1e-6);
        brightest = Math.max(brightest, gpu);
        if (c === 0 && Math.max(...[0, 1, 2].map((k) => r.data[(q.y * r.w + q.x) * 4 + k])) > 1e-3) ++lit;
        if (!(d <= worst)) {
          worst = d;
          where = `pixel (${q.x}, ${q.y}) channel ${c}: page ${gpu}, CPU ${cpu}`;
        }
      }
    });
    console.log(`sphere ${name}: ${picks.length} pixels, ${lit} lit (brightest ${brightest.toPrecision(4)}), worst difference ${worst.toFixed(3)} of its bound`);
    check(picks.length > 50 && lit > picks.length / 2 && worst <= 1, `sphere: ${name}: ${lit} of ${picks.length} pixels lit; ${where} (${worst} of its bound)`);
  }
  // The GLSL sampler's albedo (1024 samples per angle) against `aniso albedo` (200k samples): within
  // 5 standard errors of the two (the page's per-angle error from its samples; the CLI's the same
  // per-sample spread over its count).
  async function checkAlbedo(page, name) {
    const r = await E(page, () => ({ rows: window.anisoExplorer.results.albedo.A, phi: window.anisoExplorer.state.light.phi }));
    let worst = 0, where = "";
    for (const k of [0, 15, 30, 40]) {
      const row = r.rows[k];
      const cli = run(["albedo", "-m", name, "--theta-deg", String(row.theta), "--phi-deg", String(r.phi), "--samples", "200000"]);
      const ref = cli.out.trim().split(/\s+/).map(Number);
      for (let c = 0; c < 3; ++c) {
        const se = row.stderr[c] * Math.sqrt(1 + 1024 / 200000), z = Math.abs(row.rho[c] - ref[c]) / Math.max(se, 1e-6);
        if (!(z <= worst)) {
          worst = z;
          where = `theta ${row.theta.toFixed(1)} channel ${c}: page ${row.rho[c]} (standard error ${row.stderr[c]}), aniso albedo ${ref[c]}`;
        }
      }
    }
    console.log(`albedo ${name}: 4 angles, worst ${worst.toFixed(2)} standard errors from aniso albedo`);
    check(worst <= 5, `albedo: ${name}: ${where}`);
  }
  // A | B: the measured material (A) against the analytic B, split and difference.
  async function checkCompare(page, name) {
    for (const mode of ["split", "difference"]) {
      await page.selectOption("#compare", mode);
      await idle(page);
      const s = await E(page, () => {
        const X = window.anisoExplorer, c = document.getElementById("gl"), g = document.createElement("canvas");
        g.width = c.width;
        g.height = c.height;
        const x = g.getContext("2d");
        x.drawImage(c, 0, 0);
        const w = c.width / 2, px = (u) => Array.from(x.getImageData(Math.floor(u * w), Math.floor(c.height / 2), 1, 1).data.slice(0, 3));
        return { left: px(0.4), right: px(0.6), err: X.error(), b: X.material("B").model };
      });
      await page.locator("#gl").screenshot({ path: path.join(outDir, `${name}-compare-${mode}.png`) });
      check(s.err === "" && s.b !== "rgl" && s.b !== "measured", `${name}: compare ${mode}: ${s.err}`);
      if (mode === "split") check(JSON.stringify(s.left) !== JSON.stringify(s.right), `${name}: split: A ${s.left} and B ${s.right} look the same`);
    }
    await page.selectOption("#compare", "off");
    await idle(page);
  }
  // A refused file: the CLI's message, and nothing changed.
  async function checkRefused(page, name) {
    const before = await snapshot(page);
    const msg = await open(page, name);
    const cli = run(["eval", "-m", name], "0 0 1 0 0 1\n").err.trim();
    check(msg === cli, `refused: ${name}: page "${msg}", CLI "${cli}"`);
    check((await snapshot(page)) === before, `refused: ${name}: the material or its views changed`);
  }

  if (want("rgl")) {
    const page = await openPage();
    const err = await open(page, aniso_, "drop");
    check(err === "", `rgl: dropping ${aniso_}: ${err}`);
    check((await E(page, () => window.anisoExplorer.material())).model === "rgl", "rgl: the dropped file is not material A");
    await checkPolar(page, aniso_);
    await views(page, "lit,polar,albedo,lobe");
    await checkSphere(page, aniso_);
    await checkAlbedo(page, aniso_);
    const lobe = await E(page, () => Array.from(window.anisoExplorer.results.lobe.values).filter((v, i) => i % 4 === 1 && v > 0).length);
    check(lobe > 500, `rgl: the 3D lobe has ${lobe} directions with f > 0`);
    for (const id of ["gl", "polar-in", "polar-perp", "albedo", "lobe"]) await page.locator(`#${id}`).screenshot({ path: path.join(outDir, `rgl-${id}.png`) });
    // The exports: export-glsl's shader and side file; export-brdf's refusal.
    const [glsl, tables, brdf] = await E(page, () => {
      const X = window.anisoExplorer, m = X.state.A;
      let b = "";
      try {
        X.exportBrdf(m);
      } catch (e) {
        b = `aniso: error: ${e.message}`;
      }
      const t = X.exportTables(m);
      let s = "";
      for (let i = 0; i < t.length; i += 8192) s += String.fromCharCode(...t.subarray(i, i + 8192));
      return [X.exportGlsl(m), btoa(s), b];
    });
    const cli = run(["export-glsl", "--full", "-m", aniso_, "-o", "material.glsl"]);
    check(cli.code === 0 && glsl === fs.readFileSync(path.join(dir, "material.glsl"), "utf8"), "rgl: the page's GLSL differs from aniso export-glsl --full");
    check(Buffer.from(tables, "base64").equals(fs.readFileSync(path.join(dir, "material.glsl.tables"))), "rgl: the page's tables file differs from aniso export-glsl's");
    check(brdf === run(["export-brdf", "-m", aniso_]).err.trim(), `rgl: .brdf: page "${brdf}"`);
    await checkRefused(page, variant(aniso_, "cut.bsdf", (b) => b.subarray(0, b.length - 4096)));
    await checkRefused(page, variant(aniso_, "bad.bsdf", (b, f) => setF32(b, f.vndf, 100, -3)));
    check(page.errors.length === 0, `rgl: console errors: ${page.errors.join(" | ")}`);
    await page.context().close();
  }

  if (want("rgl_real")) {
    if (!realFiles.length) console.log(`rgl_real: skipped: ${realDir} is absent (CI has it)`);
    else {
      // The sharpest of them (a mirror peak of f ~ 300 / sr, where the CLI's acos steps matter).
      const name = realFiles.includes("chm_mint_rgb.bsdf") ? "chm_mint_rgb.bsdf" : realFiles[0];
      const page = await openPage();
      const err = await open(page, name);
      check(err === "", `rgl_real: opening ${name}: ${err}`);
      await checkPolar(page, name);
      await views(page, "lit,polar");
      await checkSphere(page, name);
      await page.screenshot({ path: path.join(outDir, "rgl-real-page.png") });
      await checkRefused(page, variant(name, "real_cut.bsdf", (b) => b.subarray(0, 300000)));
      check(page.errors.length === 0, `rgl_real: console errors: ${page.errors.join(" | ")}`);
      await page.context().close();
    }
  }

  if (want("merl")) {
    const page = await openPage();
    const err = await open(page, "ward.binary");
    check(err === "", `merl: opening ward.binary: ${err}`);
    check((await E(page, () => window.anisoExplorer.material())).model === "measured", "merl: the table is not material A");
    await checkPolar(page, "ward.binary");
    await views(page, "lit,polar,albedo");
    await checkSphere(page, "ward.binary");
    await checkAlbedo(page, "ward.binary");
    await page.locator("#views").screenshot({ path: path.join(outDir, "merl-views.png") });
    await checkCompare(page, "ward.binary");
    await checkRefused(page, variant("ward.binary", "cut.binary", (b) => b.subarray(0, 1000012)));
    await checkRefused(page, variant("ward.binary", "bad.binary", (b) => void b.writeDoubleLE(NaN, 12 + 8 * 777)));
    // A texture larger than the browser allows: the message, nothing changed.
    const before = await snapshot(page);
    await E(page, () => (window.anisoExplorer.limits.maxTextureSize = 1024));
    const msg = await open(page, "ward.binary");
    await E(page, () => (window.anisoExplorer.limits.maxTextureSize = 1 << 30));
    check(msg === "aniso: error: ward.binary: the measured tables (5491611 floats) need a 4096 x 1341 float texture; this browser's WebGL2 allows 1024 x 1024 (MAX_TEXTURE_SIZE)",
      `merl: too large: "${msg}"`);
    check((await snapshot(page)) === before, "merl: too large: the material changed");
    check(page.errors.length === 0, `merl: console errors: ${page.errors.join(" | ")}`);
    await page.context().close();
  }
  await browser.close();
}

finish(t0, outDir);

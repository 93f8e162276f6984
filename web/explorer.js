// web/explorer.js: the browser explorer (docs/web.md). Every number on the page comes from the
// project's GLSL library (window.ANISO_DATA.glsl, the files `aniso export-glsl` assembles) run by
// WebGL2: the lit views shade with it, the plots evaluate it into float targets
// (EXT_color_buffer_float) and read the values back. The controls are generated from the
// parameter tables (ANISO_DATA.models) and validated by web/validate.js, the mirror of the CLI's
// reader; a measured file (.bsdf, .binary) is read by web/measured.js into the tables texture its
// GLSL twin reads. No request leaves the page's own folder.
"use strict";

(function () {
  const D = window.ANISO_DATA;
  const V = window.AnisoValidate;
  const MF = window.AnisoMeasured;
  const $ = (id) => document.getElementById(id);
  const deg = Math.PI / 180;
  const lum = (r, g, b) => 0.2126 * r + 0.7152 * g + 0.0722 * b;  // Rec. 709, as src/view/plots.h

  // ---- state ---------------------------------------------------------------------------------
  const defaults = {
    light: { theta: 35, phi: 20, irradiance: 3, exposure: 0 },
    tangent: { angle: 0, field: "natural", swirl: 45, noise_scale: 4, noise_strength: 45 },
    view: { log: false, xcos: false, compare: "off", object: "torus", views: "lit,polar,albedo,lobe" },
  };
  const state = {
    A: null, B: null,  // {desc, where, preset}
    edit: "A",
    light: Object.assign({}, defaults.light),
    tangent: Object.assign({}, defaults.tangent),
    view: Object.assign({}, defaults.view),
    lastError: "",
    redraws: 0,
    fileLoads: 0,  // files opened or dropped and read (or refused) so far
  };
  // fileMs: the last measured file's reading (and tables) and texture upload times.
  const results = { polar: {}, albedo: {}, lobe: {}, frameMs: [], stageMs: [], fileMs: null };

  function showError(msg) {
    state.lastError = msg;
    const e = $("error");
    e.textContent = msg;
    e.hidden = !msg;
  }
  // Every failure is shown with the CLI's prefix ("aniso: error: <message>", apps/aniso/commands.h).
  function reportError(err) {
    if (err instanceof V.InputError) showError(`aniso: error: ${err.message}`);
    else showError(`aniso: error: ${err && err.message ? err.message : err}`);
  }

  function presetJson(name) {
    const p = D.presets.find((q) => q.name === name);
    return p ? p.material : null;
  }
  // A material from JSON (an object or text) named `where` as the CLI names it: "preset NAME", the
  // file's name, "inline material" (src/io/materials.cpp load_material).
  function makeMaterial(input, where, preset) {
    const obj = typeof input === "string" ? V.parseJsonText(input, where) : input;
    const desc = V.parseMaterial(obj, where, D);
    const shape = D.shapes[shapeKey(desc)];
    if (!shape) throw new V.InputError(`${where}: model "${desc.model}" has no GLSL form in the page`);
    return { desc, where, preset: preset || "" };
  }
  // Puts a material in slot A or B; the tables texture of the one it replaces goes when no slot
  // holds that material any more.
  function replaceMaterial(which, mat) {
    const old = state[which];
    state[which] = mat;
    if (old && old.texture && state.A !== old && state.B !== old) gl.deleteTexture(old.texture);
  }
  // Replaces material A or B by what make() returns; on error the message is shown and the state
  // stays as it was.
  function trySet(which, make) {
    try {
      replaceMaterial(which, make());
      showError("");
      onMaterialChange();
      return true;
    } catch (err) {
      reportError(err);
      return false;
    }
  }
  const setMaterial = (which, input, where, preset) => trySet(which, () => makeMaterial(input, where, preset));

  // ---- the material's shape and uniforms (mirrors apps/aniso/cmd_web.cpp shape_key) ----------
  function shapeParts(spec, pv, path, parts) {
    for (const p of spec.params) {
      const key = path + p.name;
      const has = Object.prototype.hasOwnProperty.call(pv, p.name);
      if (p.kind === "object") {
        parts.push(`${key}=${has ? 1 : 0}`);
        if (has) shapeParts(p.sub, pv[p.name], key + ".", parts);
      } else if (p.kind === "tagged-object" && has) {
        parts.push(`${key}=${pv[p.name].model}`);
        shapeParts(p.subs[pv[p.name].model], pv[p.name], key + ".", parts);
      } else if (p.kind === "list" && has) {
        parts.push(`${key}=${pv[p.name].length}`);
      }
    }
  }
  function modelSpec(name) {
    return D.models.find((m) => m.name === name);
  }
  function shapeKey(desc) {
    const parts = [];
    shapeParts(modelSpec(desc.model), desc.params, "", parts);
    return [desc.model].concat(parts).join("|");
  }
  // The table entry and value of a slot ("metal.lobe.alpha_x", "lafortune.lobes[0].cx") in the
  // material; a named metal's eta and k come from the metal table, as gl::glsl_material() does.
  function slotEntry(desc, slot) {
    let pv = desc.params;
    let spec = modelSpec(desc.model);
    if (desc.model === "metal" && pv.metal) {
      const md = D.metals.find((m) => m.name === pv.metal);
      pv = Object.assign({}, pv, { eta: md.eta, k: md.k });
    }
    let p = null;
    for (const seg of slot.key.slice(desc.model.length + 1).split(".")) {
      const m = /^(.*)\[(\d+)\]$/.exec(seg);
      const name = m ? m[1] : seg;
      p = spec.params.find((q) => q.name === name);
      let v = pv[name];
      if (m) v = v[Number(m[2])];
      if (p.kind === "object" || p.kind === "list") spec = p.sub;
      else if (p.kind === "tagged-object") spec = p.subs[v.model];
      pv = v;
    }
    return { p, v: pv };
  }
  // The value a uniform gets: a choice's index, a bool as 0 / 1.
  function slotValue(desc, slot) {
    const { p, v } = slotEntry(desc, slot);
    if (slot.type === "int") return p.choices.indexOf(v);
    if (slot.type === "bool") return v ? 1 : 0;
    return v;
  }

  // ---- WebGL2 ----------------------------------------------------------------------------------
  const canvas = $("gl");
  const gl = canvas.getContext("webgl2", { antialias: false, preserveDrawingBuffer: true });
  if (!gl) throw new Error("this browser has no WebGL2");
  if (!gl.getExtension("EXT_color_buffer_float")) throw new Error("WebGL2 without EXT_color_buffer_float: the plots need float targets");

  const PREAMBLE = "#version 300 es\nprecision highp float;\nprecision highp int;\n";  // gl::glsl_preamble(Es300)

  function compile(type, src, what) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(`${what}: ${gl.getShaderInfoLog(s)}`);
    return s;
  }
  function link(vs, fs, what) {
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, vs, what + " (vertex)"));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fs, what + " (fragment)"));
    gl.bindAttribLocation(p, 0, "a_pos");
    gl.bindAttribLocation(p, 1, "a_normal");
    gl.bindAttribLocation(p, 2, "a_dpdu");
    gl.bindAttribLocation(p, 3, "a_uv");
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(`${what}: ${gl.getProgramInfoLog(p)}`);
    p.loc = {};
    return p;
  }
  function loc(p, name) {
    if (!(name in p.loc)) p.loc[name] = gl.getUniformLocation(p, name);
    return p.loc[name];
  }

  const QUAD_VS = `${PREAMBLE}in vec2 a_pos; out vec2 v_xy; void main() { v_xy = a_pos; gl_Position = vec4(a_pos, 0.0, 1.0); }`;
  // The lit views: the sphere seen orthographically along -z (a full-screen quad, the sphere
  // found per pixel), or a mesh. At the point facing the camera the frame is world (x, y, z), so
  // the light's local (theta, phi) is the world direction u_to_light (docs/explorer.md).
  const MESH_VS = `${PREAMBLE}
in vec3 a_pos; in vec3 a_normal; in vec3 a_dpdu; in vec2 a_uv;
uniform mat3 u_rot; uniform vec2 u_scale;
out vec3 v_p; out vec3 v_n; out vec3 v_dpdu; out vec2 v_uv;
void main() {
  v_p = u_rot * a_pos; v_n = u_rot * a_normal; v_dpdu = u_rot * a_dpdu; v_uv = a_uv;
  gl_Position = vec4(v_p.xy * u_scale, -v_p.z * u_scale.x * 0.5, 1.0);
}`;
  const SHADE_COMMON = `
uniform vec3 u_to_light;
uniform float u_irradiance;
uniform int u_field;
uniform float u_tangent_angle, u_swirl, u_noise_scale, u_noise_strength;
out vec4 o_color;
// f cos theta_i E for the view direction +z, or -1 where nothing is hit.
vec3 shade(vec3 p, vec3 n, vec3 dpdu, vec2 uv) {
  TangentField tf;
  tf.kind = u_field; tf.direction = vec3(1.0, 0.0, 0.0); tf.center = vec3(0.0); tf.axis = vec3(0.0, 0.0, 1.0);
  tf.swirl = u_swirl; tf.scale = u_noise_scale; tf.strength = u_noise_strength; tf.angle = u_tangent_angle;
  SurfacePoint sp; sp.p = p; sp.n = n; sp.dpdu = dpdu; sp.uv = uv;
  Frame fr = tangent_frame(tf, sp);
  vec3 wi = Frame_to_local(fr, u_to_light);
  vec3 wo = Frame_to_local(fr, vec3(0.0, 0.0, 1.0));
  return aniso_f(wi, wo) * max(wi.z, 0.0) * u_irradiance;
}`;
  const SPHERE_FS = `
in vec2 v_xy;
uniform vec2 u_extent;
void main() {
  vec2 q = v_xy * u_extent;
  float r2 = dot(q, q);
  if (r2 >= 1.0) { o_color = vec4(0.0, 0.0, 0.0, 0.0); return; }
  vec3 n = vec3(q, sqrt(1.0 - r2));
  // Natural tangent: dp/du of the sphere turning about the y axis (world x at the front point).
  o_color = vec4(shade(n, n, vec3(n.z, 0.0, -n.x), vec2(0.0)), 1.0);
}`;
  const MESH_FS = `
in vec3 v_p; in vec3 v_n; in vec3 v_dpdu; in vec2 v_uv;
void main() { o_color = vec4(shade(v_p, normalize(v_n), v_dpdu, v_uv), 1.0); }`;
  // f and pdf at the directions of a texture (one wo per texel), for the light's wi.
  const EVAL_FS = `
uniform highp sampler2D u_dirs;
uniform vec3 u_wi;
out vec4 o_value;
void main() {
  vec3 wo = texelFetch(u_dirs, ivec2(gl_FragCoord.xy), 0).xyz;
  o_value = vec4(aniso_f(u_wi, wo), aniso_pdf(u_wi, wo));
}`;
  // Directional albedo by Monte Carlo with the GLSL sampler: one sample per texel, row = angle;
  // the two direction uniforms on a 32 x 32 stratified grid, the lobe choice from a hash.
  const ALBEDO_FS = `
uniform float u_phi;
uniform float u_rows;
out vec4 o_value;
uint hash(uint x) { x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16; return x; }
float unit(uint x) { return float(hash(x) >> 8) * (1.0 / 16777216.0); }
void main() {
  ivec2 c = ivec2(gl_FragCoord.xy);
  float theta = float(c.y) / (u_rows - 1.0) * 89.0 * kPi / 180.0;
  vec3 wo = vec3(sin(theta) * cos(u_phi), sin(theta) * sin(u_phi), cos(theta));
  uint i = uint(c.x), seed = uint(c.y) * 4096u + i;
  vec3 u = vec3(unit(seed * 3u), (float(i % 32u) + unit(seed * 3u + 1u)) / 32.0, (float(i / 32u) + unit(seed * 3u + 2u)) / 32.0);
  vec3 weight; float pdf;
  aniso_sample(wo, u, weight, pdf);
  o_value = vec4(pdf > 0.0 ? weight : vec3(0.0), 1.0);
}`;
  // Display: the one tone map, ToneMap_apply of aniso/image/tonemap.glsl (the twin of
  // render::tonemap, delivered by `aniso web-data` as D.glsl.tonemap): exposure, Narkowicz 2015's
  // ACES fit with its cap, NaN and negative radiance black, the sRGB encoding; A | B split or
  // |A - B| x gain.
  const DISPLAY_FS = `${PREAMBLE}${D.glsl.tonemap}
in vec2 v_xy;
uniform sampler2D u_a, u_b;
uniform int u_mode;  // 0 A, 1 split, 2 difference
uniform float u_gain, u_diff_gain;
out vec4 o_color;
vec3 tonemap(vec3 c) { return ToneMap_apply(c, u_gain, true); }
void main() {
  vec2 t = v_xy * 0.5 + 0.5;
  vec4 a = texture(u_a, t), b = texture(u_b, t);
  vec4 s = u_mode == 1 && t.x > 0.5 ? b : a;
  vec3 bg = vec3(0.16);
  if (u_mode == 2) { float cov = max(a.a, b.a); o_color = vec4(mix(bg, tonemap(abs(a.rgb - b.rgb) * u_diff_gain), cov), 1.0); return; }
  o_color = vec4(mix(bg, tonemap(s.rgb), s.a), 1.0);
  if (u_mode == 1 && abs(t.x - 0.5) < 0.002) o_color = vec4(1.0);
}`;

  const programs = new Map();
  function programFor(mat, kind) {
    const key = shapeKey(mat.desc) + "#" + kind;
    if (programs.has(key)) return programs.get(key);
    const shape = D.shapes[shapeKey(mat.desc)];
    const lib = PREAMBLE + D.glsl.library + shape.declarations + shape.code;
    let p;
    if (kind === "sphere") p = link(QUAD_VS, lib + SHADE_COMMON + SPHERE_FS, "sphere");
    else if (kind === "mesh") p = link(MESH_VS, lib + SHADE_COMMON + MESH_FS, "mesh");
    else if (kind === "eval") p = link(QUAD_VS, lib + EVAL_FS, "eval");
    else p = link(QUAD_VS, lib + ALBEDO_FS, "albedo");
    p.shape = shape;
    programs.set(key, p);
    return p;
  }
  // A measured material's tables texture, on its own unit (evalDirections uses 0, display 0 and 1).
  const TABLES_UNIT = 3;
  function setMaterialUniforms(p, mat) {
    if (p.shape.needs_tables) {
      gl.activeTexture(gl.TEXTURE0 + TABLES_UNIT);
      gl.bindTexture(gl.TEXTURE_2D, mat.texture);
      gl.activeTexture(gl.TEXTURE0);
      gl.uniform1i(loc(p, D.measured.tables.sampler), TABLES_UNIT);
    }
    for (const s of p.shape.slots) {
      const v = slotValue(mat.desc, s);
      const l = loc(p, "u_" + s.name);
      if (s.type === "float") gl.uniform1f(l, v);
      else if (s.type === "vec3") gl.uniform3f(l, v[0], v[1], v[2]);
      else gl.uniform1i(l, v);
    }
  }
  const displayProgram = link(QUAD_VS, DISPLAY_FS, "display");

  const quad = gl.createVertexArray();
  gl.bindVertexArray(quad);
  const quadBuf = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, quadBuf);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
  gl.bindVertexArray(null);

  function floatTarget(w, h) {
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, null);
    for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST], [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]])
      gl.texParameteri(gl.TEXTURE_2D, k, v);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
    let depth = null;
    depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, w, h);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) throw new Error("float framebuffer incomplete");
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return { tex, fb, depth, w, h };
  }
  function dirTexture(dirs, w, h) {
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, dirs);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    return tex;
  }

  // The measured tables texture (docs/glsl.md, "Measured materials"; gl::TablesTexture): R32F,
  // ANISO_DATA.measured.tables.width texels wide, float i at (i % width, i / width), NEAREST.
  const limits = { maxTextureSize: gl.getParameter(gl.MAX_TEXTURE_SIZE) };  // the tests lower it
  function uploadTables(tables, name) {
    const width = D.measured.tables.width, rows = Math.max(1, Math.ceil(tables.length / width)), max = limits.maxTextureSize;
    if (rows > max || width > max)
      throw new V.InputError(`${name}: the measured tables (${tables.length} floats) need a ${width} x ${rows} float texture; ` +
        `this browser's WebGL2 allows ${max} x ${max} (MAX_TEXTURE_SIZE)`);
    const padded = new Float32Array(width * rows);
    padded.set(tables);
    while (gl.getError() !== gl.NO_ERROR);
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 4);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R32F, width, rows, 0, gl.RED, gl.FLOAT, padded);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    const err = gl.getError();
    if (err !== gl.NO_ERROR) {
      gl.deleteTexture(tex);
      throw new V.InputError(`${name}: the measured tables (${tables.length} floats, a ${width} x ${rows} float texture) could not be uploaded: WebGL error 0x${err.toString(16)}`);
    }
    return tex;
  }
  // A measured file (its first bytes, its size) as material A or B: read by web/measured.js with the
  // C++ readers' rules, its tables uploaded; on error the message is shown and nothing changes.
  function setMeasured(which, name, bytes, size) {
    return trySet(which, () => {
      const t0 = performance.now();
      const r = MF.readMeasured(name, bytes, size);
      const t1 = performance.now();
      const texture = uploadTables(r.tables, name);
      results.fileMs = { read: t1 - t0, upload: performance.now() - t1 };
      const desc = { model: r.model, params: { file: name }, json: { model: r.model, file: name } };
      return { desc, where: name, preset: "", tables: r.tables, texture, notes: r.notes, summary: r.summary };
    });
  }

  let targets = null;
  function ensureTargets() {
    const w = Math.floor(canvas.width / 2), h = canvas.height;
    if (targets && targets.w === w && targets.h === h) return;
    targets = { w, h, A: floatTarget(w, h), B: floatTarget(w, h), obj: floatTarget(w, h), objB: floatTarget(w, h) };
  }

  // ---- the torus (or a dropped OBJ) ------------------------------------------------------------
  function torusMesh(R, r, nu, nv) {
    const pos = [], nrm = [], dpdu = [], uv = [], idx = [];
    for (let i = 0; i <= nu; ++i)
      for (let j = 0; j <= nv; ++j) {
        const u = (i / nu) * 2 * Math.PI, v = (j / nv) * 2 * Math.PI;
        const cu = Math.cos(u), su = Math.sin(u), cv = Math.cos(v), sv = Math.sin(v);
        pos.push((R + r * cv) * cu, (R + r * cv) * su, r * sv);
        nrm.push(cv * cu, cv * su, sv);
        dpdu.push(-su, cu, 0);
        uv.push(i / nu, j / nv);
      }
    for (let i = 0; i < nu; ++i)
      for (let j = 0; j < nv; ++j) {
        const a = i * (nv + 1) + j, b = a + nv + 1;
        idx.push(a, b, a + 1, a + 1, b, b + 1);
      }
    return { pos, nrm, dpdu, uv, idx, radius: R + r };
  }
  // A Wavefront OBJ: v, vt, vn, f (polygons as fans); tangents dp/du from the UVs per triangle,
  // summed at the vertices; normals from the faces where the file has none.
  function parseObj(text, name) {
    const v = [], vt = [], vn = [];
    const out = { pos: [], nrm: [], dpdu: [], uv: [], idx: [] };
    const lines = text.split("\n");
    lines.forEach((line, ln) => {
      const t = line.trim().split(/\s+/);
      const nums = () => t.slice(1).map(Number);
      if (t[0] === "v") v.push(nums().slice(0, 3));
      else if (t[0] === "vt") vt.push(nums().slice(0, 2));
      else if (t[0] === "vn") vn.push(nums().slice(0, 3));
      else if (t[0] === "f") {
        const corners = t.slice(1).map((c) => {
          const [a, b, n] = c.split("/").map((x) => (x ? Number(x) : 0));
          const fix = (k, len) => (k < 0 ? len + k : k - 1);
          const pi = fix(a, v.length);
          if (!(pi >= 0 && pi < v.length)) throw new V.InputError(`${name}: line ${ln + 1}: vertex index ${a} out of range (${v.length} vertices)`);
          return { p: v[pi], t: b ? vt[fix(b, vt.length)] : [0, 0], n: n ? vn[fix(n, vn.length)] : null };
        });
        for (let k = 1; k + 1 < corners.length; ++k) {
          const tri = [corners[0], corners[k], corners[k + 1]];
          const e1 = tri[1].p.map((x, i) => x - tri[0].p[i]), e2 = tri[2].p.map((x, i) => x - tri[0].p[i]);
          const fn = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
          const du1 = tri[1].t[0] - tri[0].t[0], du2 = tri[2].t[0] - tri[0].t[0];
          const dv1 = tri[1].t[1] - tri[0].t[1], dv2 = tri[2].t[1] - tri[0].t[1];
          const det = du1 * dv2 - du2 * dv1;
          const dp = Math.abs(det) > 1e-12 ? e1.map((x, i) => (dv2 * x - dv1 * e2[i]) / det) : [0, 0, 0];
          for (const c of tri) {
            out.idx.push(out.pos.length / 3);
            out.pos.push(...c.p);
            out.nrm.push(...(c.n || fn));
            out.dpdu.push(...dp);
            out.uv.push(...c.t);
          }
        }
      }
    });
    if (!out.idx.length) throw new V.InputError(`${name}: no faces (expected an OBJ file with "f" lines)`);
    let c = [0, 0, 0];
    for (let i = 0; i < out.pos.length; i += 3) for (let k = 0; k < 3; ++k) c[k] += out.pos[i + k] / (out.pos.length / 3);
    let rad = 0;
    for (let i = 0; i < out.pos.length; i += 3) {
      for (let k = 0; k < 3; ++k) out.pos[i + k] -= c[k];
      rad = Math.max(rad, Math.hypot(out.pos[i], out.pos[i + 1], out.pos[i + 2]));
    }
    out.radius = rad || 1;
    return out;
  }
  let mesh = null;
  function uploadMesh(m) {
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    [[m.pos, 3], [m.nrm, 3], [m.dpdu, 3], [m.uv, 2]].forEach(([data, n], i) => {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(data), gl.STATIC_DRAW);
      gl.enableVertexAttribArray(i);
      gl.vertexAttribPointer(i, n, gl.FLOAT, false, 0, 0);
    });
    const ib = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(m.idx), gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    mesh = { vao, count: m.idx.length, radius: m.radius };
  }
  uploadMesh(torusMesh(1, 0.4, 96, 48));

  // ---- drawing ----------------------------------------------------------------------------------
  const fieldKinds = { natural: 0, projected: 1, radial: 2, concentric: 3, swirl: 4, noise: 5 };
  function toLight() {
    const t = state.light.theta * deg, p = state.light.phi * deg;
    return [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  }
  function setShadeUniforms(p) {
    const L = toLight();
    gl.uniform3f(loc(p, "u_to_light"), L[0], L[1], L[2]);
    gl.uniform1f(loc(p, "u_irradiance"), state.light.irradiance);
    gl.uniform1i(loc(p, "u_field"), fieldKinds[state.tangent.field]);
    gl.uniform1f(loc(p, "u_tangent_angle"), state.tangent.angle * deg);
    gl.uniform1f(loc(p, "u_swirl"), state.tangent.swirl * deg);
    gl.uniform1f(loc(p, "u_noise_scale"), state.tangent.noise_scale);
    gl.uniform1f(loc(p, "u_noise_strength"), state.tangent.noise_strength * deg);
  }
  function renderSphere(mat, target) {
    const p = programFor(mat, "sphere");
    gl.useProgram(p);
    gl.bindFramebuffer(gl.FRAMEBUFFER, target.fb);
    gl.viewport(0, 0, target.w, target.h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    setMaterialUniforms(p, mat);
    setShadeUniforms(p);
    // The sphere fills 90 % of the shorter side.
    const s = 1 / 0.9;
    gl.uniform2f(loc(p, "u_extent"), (s * target.w) / Math.min(target.w, target.h), (s * target.h) / Math.min(target.w, target.h));
    gl.bindVertexArray(quad);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }
  function renderMesh(mat, target) {
    const p = programFor(mat, "mesh");
    gl.useProgram(p);
    gl.bindFramebuffer(gl.FRAMEBUFFER, target.fb);
    gl.viewport(0, 0, target.w, target.h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    setMaterialUniforms(p, mat);
    setShadeUniforms(p);
    // Tilted by 60 degrees about x so the ring is seen from above its plane.
    const a = -60 * deg, c = Math.cos(a), s = Math.sin(a);
    gl.uniformMatrix3fv(loc(p, "u_rot"), false, [1, 0, 0, 0, c, s, 0, -s, c]);
    const m = Math.min(target.w, target.h);
    gl.uniform2f(loc(p, "u_scale"), (0.9 / mesh.radius) * (m / target.w), (0.9 / mesh.radius) * (m / target.h));
    gl.bindVertexArray(mesh.vao);
    gl.drawElements(gl.TRIANGLES, mesh.count, gl.UNSIGNED_INT, 0);
    gl.disable(gl.DEPTH_TEST);
  }
  function display(a, b, mode, x) {
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(x, 0, targets.w, targets.h);
    gl.useProgram(displayProgram);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, a.tex);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, b.tex);
    gl.activeTexture(gl.TEXTURE0);
    gl.uniform1i(loc(displayProgram, "u_a"), 0);
    gl.uniform1i(loc(displayProgram, "u_b"), 1);
    gl.uniform1i(loc(displayProgram, "u_mode"), mode);
    gl.uniform1f(loc(displayProgram, "u_gain"), Math.pow(2, state.light.exposure));
    gl.uniform1f(loc(displayProgram, "u_diff_gain"), 4);
    gl.bindVertexArray(quad);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }
  // The lit views: rendered into float targets when their inputs change, then shown through the
  // display pass (an exposure change redoes only that).
  function drawLit(render) {
    const fresh = !targets || targets.w !== Math.floor(canvas.width / 2) || targets.h !== canvas.height;
    ensureTargets();
    const cmp = state.view.compare;
    const mode = cmp === "split" ? 1 : cmp === "difference" ? 2 : 0;
    if (render || fresh) {
      renderSphere(state.A, targets.A);
      if (mode) renderSphere(state.B, targets.B);
      renderMesh(state.A, targets.obj);
      if (mode) renderMesh(state.B, targets.objB);
    }
    display(targets.A, targets.B, mode, 0);
    display(targets.obj, targets.objB, mode, targets.w);
  }
  // The linear radiance of the lit sphere (A), row 0 at the bottom: what the tests compare.
  function readSphere() {
    ensureTargets();
    renderSphere(state.A, targets.A);
    gl.bindFramebuffer(gl.FRAMEBUFFER, targets.A.fb);
    const px = new Float32Array(targets.w * targets.h * 4);
    gl.readPixels(0, 0, targets.w, targets.h, gl.RGBA, gl.FLOAT, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return { w: targets.w, h: targets.h, data: Array.from(px) };
  }

  // The display pass (mode A) on a row of w RGBA float texels (radiance, alpha 1) at `exposure`
  // stops: the encoded values it writes, 4 w floats, read from a float target. What the tone-map
  // parity check compares with the CPU (tests/web/explorer.test.mjs, "tonemap").
  function toneMapProbe(texels, w, exposure) {
    const texture = (data) => {
      const t = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, t);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, 1, 0, gl.RGBA, gl.FLOAT, data);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
      return t;
    };
    const src = texture(new Float32Array(texels)), dst = texture(null);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, dst, 0);
    gl.viewport(0, 0, w, 1);
    gl.useProgram(displayProgram);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, src);
    gl.uniform1i(loc(displayProgram, "u_a"), 0);
    gl.uniform1i(loc(displayProgram, "u_b"), 0);
    gl.uniform1i(loc(displayProgram, "u_mode"), 0);
    gl.uniform1f(loc(displayProgram, "u_gain"), Math.pow(2, exposure));
    gl.bindVertexArray(quad);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const out = new Float32Array(w * 4);
    gl.readPixels(0, 0, w, 1, gl.RGBA, gl.FLOAT, out);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteFramebuffer(fb);
    gl.deleteTexture(src);
    gl.deleteTexture(dst);
    return Array.from(out);
  }

  // Evaluates f and pdf of `mat` for the light at the directions `dirs` (w x h unit vectors).
  function evalDirections(mat, dirs, w, h) {
    const data = new Float32Array(w * h * 4);
    dirs.forEach((d, i) => data.set([d[0], d[1], d[2], 0], i * 4));
    const tex = dirTexture(data, w, h);
    const t = floatTarget(w, h);
    const p = programFor(mat, "eval");
    gl.useProgram(p);
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
    gl.viewport(0, 0, w, h);
    setMaterialUniforms(p, mat);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.uniform1i(loc(p, "u_dirs"), 0);
    const L = toLight();
    gl.uniform3f(loc(p, "u_wi"), L[0], L[1], L[2]);
    gl.bindVertexArray(quad);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const out = new Float32Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, out);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteTexture(tex);
    gl.deleteTexture(t.tex);
    gl.deleteFramebuffer(t.fb);
    gl.deleteRenderbuffer(t.depth);
    // The directions as the GPU saw them (float32), for comparisons.
    return { wi: L.map(Math.fround), wo: dirs.map((d) => d.map(Math.fround)), values: out };
  }

  // ---- polar plots --------------------------------------------------------------------------
  const POLAR_N = 181;  // theta_o from -90 to 90 degrees, 1-degree steps
  function polarDirections() {
    const dirs = [];
    for (const off of [0, 90]) {
      const phi = (state.light.phi + off) * deg;
      for (let i = 0; i < POLAR_N; ++i) {
        const t = (i - 90) * deg;
        dirs.push([Math.sin(t) * Math.cos(phi), Math.sin(t) * Math.sin(phi), Math.cos(t)]);
      }
    }
    return dirs;
  }
  function computePolar(which) {
    const r = evalDirections(state[which], polarDirections(), POLAR_N, 2);
    results.polar[which] = r;
  }
  function drawPolar(canvasId, row, title) {
    const c = $(canvasId), g = c.getContext("2d");
    const W = c.width, H = c.height, cx = W / 2, cy = H - 14, R = Math.min(W / 2 - 10, H - 24);
    g.fillStyle = "#26272b";
    g.fillRect(0, 0, W, H);
    g.strokeStyle = "#444";
    for (const f of [0.25, 0.5, 0.75, 1]) {
      g.beginPath();
      g.arc(cx, cy, R * f, Math.PI, 2 * Math.PI);
      g.stroke();
    }
    g.beginPath();
    g.moveTo(cx - R, cy);
    g.lineTo(cx + R, cy);
    g.moveTo(cx, cy);
    g.lineTo(cx, cy - R);
    g.stroke();
    const series = [["A", "#f0a040"]];
    if (state.view.compare !== "off") series.push(["B", "#60a0f0"]);
    const vals = {};
    let max = 0;
    for (const [w] of series) {
      const r = results.polar[w];
      vals[w] = [];
      for (let i = 0; i < POLAR_N; ++i) {
        const k = (row * POLAR_N + i) * 4;
        const cosT = Math.cos((i - 90) * deg);
        const v = lum(r.values[k], r.values[k + 1], r.values[k + 2]) * (state.view.xcos ? cosT : 1);
        vals[w].push(v);
        max = Math.max(max, v);
      }
    }
    const radius = (v) => {
      if (!(max > 0)) return 0;
      if (!state.view.log) return v / max;
      return v > 0 ? Math.max(0, 1 + Math.log10(v / max) / 4) : 0;  // 4 decades below the maximum
    };
    for (const [w, color] of series) {
      g.strokeStyle = color;
      g.lineWidth = 1.5;
      g.beginPath();
      vals[w].forEach((v, i) => {
        const t = (i - 90) * deg, rr = R * radius(v);
        const x = cx + rr * Math.sin(t), y = cy - rr * Math.cos(t);
        if (i) g.lineTo(x, y);
        else g.moveTo(x, y);
      });
      g.stroke();
    }
    // The light (yellow: theta_o = +theta_light is the light's side) and, in the plane of
    // incidence, its mirror direction (grey); in the perpendicular plane only the light's theta.
    const th = state.light.theta * deg;
    g.strokeStyle = "#ffe060";
    g.setLineDash(row === 0 ? [] : [3, 3]);
    g.beginPath();
    g.moveTo(cx, cy);
    g.lineTo(cx + R * Math.sin(th), cy - R * Math.cos(th));
    g.stroke();
    if (row === 0) {
      g.strokeStyle = "#888";
      g.setLineDash([3, 3]);
      g.beginPath();
      g.moveTo(cx, cy);
      g.lineTo(cx - R * Math.sin(th), cy - R * Math.cos(th));
      g.stroke();
    }
    g.setLineDash([]);
    g.fillStyle = "#aaa";
    g.fillText(`${title}${state.view.log ? ", log (4 decades)" : ", linear"}${state.view.xcos ? ", x cos" : ""}; max ${max.toPrecision(4)}`, 4, 12);
  }

  // ---- directional albedo ---------------------------------------------------------------------
  const ALBEDO_ROWS = 46, ALBEDO_SAMPLES = 1024;
  function computeAlbedo(which) {
    const mat = state[which];
    const t = floatTarget(ALBEDO_SAMPLES, ALBEDO_ROWS);
    const p = programFor(mat, "albedo");
    gl.useProgram(p);
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
    gl.viewport(0, 0, ALBEDO_SAMPLES, ALBEDO_ROWS);
    setMaterialUniforms(p, mat);
    gl.uniform1f(loc(p, "u_phi"), state.light.phi * deg);
    gl.uniform1f(loc(p, "u_rows"), ALBEDO_ROWS);
    gl.bindVertexArray(quad);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const out = new Float32Array(ALBEDO_SAMPLES * ALBEDO_ROWS * 4);
    gl.readPixels(0, 0, ALBEDO_SAMPLES, ALBEDO_ROWS, gl.RGBA, gl.FLOAT, out);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteTexture(t.tex);
    gl.deleteFramebuffer(t.fb);
    gl.deleteRenderbuffer(t.depth);
    // Per angle the mean weight and its standard error (of independent samples: the stratified
    // ones vary less), which the tests hold against `aniso albedo`.
    const rows = [];
    for (let y = 0; y < ALBEDO_ROWS; ++y) {
      const s = [0, 0, 0], s2 = [0, 0, 0];
      for (let x = 0; x < ALBEDO_SAMPLES; ++x)
        for (let c = 0; c < 3; ++c) {
          const v = out[(y * ALBEDO_SAMPLES + x) * 4 + c];
          s[c] += v;
          s2[c] += v * v;
        }
      const rho = s.map((v) => v / ALBEDO_SAMPLES);
      const stderr = s2.map((v, c) => Math.sqrt(Math.max(0, v / ALBEDO_SAMPLES - rho[c] * rho[c]) / (ALBEDO_SAMPLES - 1)));
      rows.push({ theta: (y / (ALBEDO_ROWS - 1)) * 89, rho, stderr });
    }
    results.albedo[which] = rows;
  }
  function drawAlbedo() {
    const c = $("albedo"), g = c.getContext("2d");
    const W = c.width, H = c.height, x0 = 30, y0 = H - 18, w = W - 40, h = H - 34;
    g.fillStyle = "#26272b";
    g.fillRect(0, 0, W, H);
    const all = [results.albedo.A].concat(state.view.compare !== "off" ? [results.albedo.B] : []);
    let ymax = 1;
    for (const rows of all) for (const r of rows) ymax = Math.max(ymax, ...r.rho);
    g.strokeStyle = "#444";
    g.fillStyle = "#999";
    for (let k = 0; k <= 4; ++k) {
      const y = y0 - (h * k) / 4;
      g.beginPath();
      g.moveTo(x0, y);
      g.lineTo(x0 + w, y);
      g.stroke();
      g.fillText(((ymax * k) / 4).toFixed(2), 2, y + 3);
    }
    for (let d = 0; d <= 90; d += 30) g.fillText(`${d}`, x0 + (w * d) / 90 - 4, H - 4);
    const curve = (rows, f, color) => {
      g.strokeStyle = color;
      g.beginPath();
      rows.forEach((r, i) => {
        const x = x0 + (w * r.theta) / 90, y = y0 - (h * f(r.rho)) / ymax;
        if (i) g.lineTo(x, y);
        else g.moveTo(x, y);
      });
      g.stroke();
    };
    ["#f06060", "#60d060", "#6080f0"].forEach((col, ch) => curve(results.albedo.A, (r) => r[ch], col));
    if (state.view.compare !== "off") curve(results.albedo.B, (r) => lum(...r), "#bbb");
    const lx = x0 + (w * state.light.theta) / 90;
    g.strokeStyle = "#ffe060";
    g.beginPath();
    g.moveTo(lx, y0);
    g.lineTo(lx, y0 - h);
    g.stroke();
    g.fillStyle = "#aaa";
    g.fillText(`A r g b${state.view.compare !== "off" ? ", B luminance (grey)" : ""}; ${ALBEDO_SAMPLES} samples per angle`, x0, 12);
  }

  // ---- 3D lobe ----------------------------------------------------------------------------------
  const LOBE_T = 31, LOBE_P = 73;  // theta 0..90 in 3 degrees, phi 0..360 in 5 degrees
  const lobeView = { yaw: -30, pitch: 25 };
  function computeLobe() {
    const dirs = [];
    for (let j = 0; j < LOBE_T; ++j)
      for (let i = 0; i < LOBE_P; ++i) {
        const t = (j * 90) / (LOBE_T - 1) * deg, p = (i * 360) / (LOBE_P - 1) * deg;
        dirs.push([Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)]);
      }
    results.lobe = evalDirections(state.A, dirs, LOBE_P, LOBE_T);
  }
  function drawLobe() {
    const c = $("lobe"), g = c.getContext("2d");
    const W = c.width, H = c.height;
    g.fillStyle = "#26272b";
    g.fillRect(0, 0, W, H);
    const r = results.lobe;
    let max = 0;
    const val = (k) => lum(r.values[k * 4], r.values[k * 4 + 1], r.values[k * 4 + 2]) * (state.view.xcos ? r.wo[k][2] : 1);
    for (let k = 0; k < r.wo.length; ++k) max = Math.max(max, val(k));
    const cy = Math.cos(lobeView.yaw * deg), sy = Math.sin(lobeView.yaw * deg);
    const cp = Math.cos(lobeView.pitch * deg), sp = Math.sin(lobeView.pitch * deg);
    const S = Math.min(W, H) * 0.42;
    // The surface's z is up on the screen; yaw about z, then pitch about the screen's x.
    const proj = (v) => {
      const x = cy * v[0] - sy * v[1], y = sy * v[0] + cy * v[1], z = v[2];
      const y2 = cp * y - sp * z, z2 = sp * y + cp * z;
      return [W / 2 + S * x, H * 0.75 - S * z2, y2];
    };
    const pt = (k) => {
      const s = max > 0 ? val(k) / max : 0;
      return proj(r.wo[k].map((x) => x * s));
    };
    g.strokeStyle = "rgba(240,160,64,0.6)";
    g.lineWidth = 0.7;
    g.beginPath();
    for (let j = 0; j < LOBE_T; ++j)
      for (let i = 0; i < LOBE_P; ++i) {
        const a = pt(j * LOBE_P + i);
        if (i + 1 < LOBE_P) {
          const b = pt(j * LOBE_P + i + 1);
          g.moveTo(a[0], a[1]);
          g.lineTo(b[0], b[1]);
        }
        if (j + 1 < LOBE_T) {
          const b = pt((j + 1) * LOBE_P + i);
          g.moveTo(a[0], a[1]);
          g.lineTo(b[0], b[1]);
        }
      }
    g.stroke();
    const axis = (v, col) => {
      const o = proj([0, 0, 0]), e = proj(v);
      g.strokeStyle = col;
      g.lineWidth = 2;
      g.beginPath();
      g.moveTo(o[0], o[1]);
      g.lineTo(e[0], e[1]);
      g.stroke();
    };
    axis([0, 0, 1], "#4060ff");
    axis([0.6, 0, 0], "#ff4040");
    axis(toLight(), "#ffe060");
    g.lineWidth = 1;
    g.fillStyle = "#aaa";
    g.fillText(`A: luminance f${state.view.xcos ? " cos" : ""} / max; normal blue, tangent red, light yellow`, 4, 12);
  }

  // ---- light widget ---------------------------------------------------------------------------
  function drawLightWidget() {
    const c = $("light"), g = c.getContext("2d");
    const W = c.width, R = W / 2 - 6, cx = W / 2, cy = W / 2;
    g.fillStyle = "#26272b";
    g.fillRect(0, 0, W, W);
    g.strokeStyle = "#666";
    for (const t of [30, 60, 90]) {
      g.beginPath();
      g.arc(cx, cy, R * Math.sin(t * deg), 0, 2 * Math.PI);
      g.stroke();
    }
    g.beginPath();
    g.moveTo(cx - R, cy);
    g.lineTo(cx + R, cy);
    g.moveTo(cx, cy - R);
    g.lineTo(cx, cy + R);
    g.stroke();
    g.fillStyle = "#aaa";
    g.fillText("t", cx + R - 8, cy - 4);
    g.fillText("b", cx + 4, cy - R + 10);
    const r = R * Math.sin(state.light.theta * deg);
    const x = cx + r * Math.cos(state.light.phi * deg), y = cy - r * Math.sin(state.light.phi * deg);
    g.fillStyle = "#ffe060";
    g.beginPath();
    g.arc(x, y, 6, 0, 2 * Math.PI);
    g.fill();
  }
  function lightFromWidget(ev) {
    const c = $("light"), b = c.getBoundingClientRect();
    const R = c.width / 2 - 6;
    const x = ((ev.clientX - b.left) * c.width) / b.width - c.width / 2;
    const y = c.height / 2 - ((ev.clientY - b.top) * c.height) / b.height;
    const r = Math.min(1, Math.hypot(x, y) / R);
    state.light.theta = Math.min(89, Math.asin(r) / deg);  // stops at 89 degrees, as aniso view
    state.light.phi = Math.atan2(y, x) / deg;
    onViewChange(true);
  }

  // ---- controls generated from the tables ---------------------------------------------------
  const editing = () => state[state.edit];
  function logScale(p) {
    return p.min >= 0 && p.max / Math.max(p.min, 1e-3) > 1e3;  // aniso view's rule
  }
  function sliderRange(p) {
    if (logScale(p)) return [Math.max(p.min, 1e-3), Math.min(p.max, 1e4)];
    return [p.min, p.max];
  }
  function toSlider(p, v) {
    const [lo, hi] = sliderRange(p);
    if (logScale(p)) return (1000 * Math.log(Math.max(v, lo) / lo)) / Math.log(hi / lo);
    return (1000 * (v - lo)) / (hi - lo);
  }
  function fromSlider(p, s) {
    const [lo, hi] = sliderRange(p);
    let v = logScale(p) ? lo * Math.pow(hi / lo, s / 1000) : lo + ((hi - lo) * s) / 1000;
    if (p.min_exclusive && v <= p.min) v = p.min + (hi - lo) * 1e-4;
    return Number(v.toPrecision(6));
  }
  // A change of one key (path into the resolved material): the whole material is read again by
  // the reader; a refused value shows the CLI's message and the material stays.
  function editValue(path, value) {
    const m = editing();
    const obj = V.resolvedJson(m.desc);
    let o = obj;
    for (let i = 0; i < path.length - 1; ++i) o = o[path[i]];
    if (value === undefined) delete o[path[path.length - 1]];
    else o[path[path.length - 1]] = value;
    const ok = setMaterial(state.edit, obj, m.where, m.preset);
    if (!ok) buildControls();
    return ok;
  }
  // The defaults of a table as a JSON object (an optional object turned on, a new lobe).
  function defaultsOf(spec) {
    const o = {};
    for (const p of spec.params) {
      if (p.sets) continue;
      // A required number (its table default is unused) starts at 1 where its range allows.
      if ((p.kind === "scalar" || p.kind === "color") && p.required) o[p.name] = Math.min(Math.max(1, p.min), p.max);
      else if ((p.kind === "scalar" || p.kind === "color") && p.default !== null) o[p.name] = p.default;
      else if (p.kind === "list" && p.required) o[p.name] = [defaultsOf(p.sub)];
    }
    return o;
  }
  function paramRow(p, label, value, path, channel) {
    const row = document.createElement("div");
    row.className = "param";
    row.title = `${label}: ${p.doc} (${p.range}; default ${p.default_text})`;
    const name = document.createElement("span");
    name.className = "name";
    name.textContent = label.slice(label.lastIndexOf(".", channel !== undefined ? label.length - 3 : label.length) + 1);
    row.appendChild(name);
    const key = path.join(".").replace(/\.(\d+)(?=\.|$)/g, "[$1]") + (channel !== undefined ? `[${channel}]` : "");
    const set = (v) => {
      if (channel === undefined) return editValue(path, v);
      const c = V.resolvedJson(editing().desc);
      let o = c;
      for (const s of path) o = o[s];
      const arr = o.slice();
      arr[channel] = v;
      return editValue(path, arr);
    };
    if (p.kind === "scalar" || p.kind === "color") {
      const r = document.createElement("input");
      r.type = "range";
      r.min = 0;
      r.max = 1000;
      r.step = 1;
      r.value = toSlider(p, value);
      r.dataset.key = key;
      const n = document.createElement("input");
      n.type = "number";
      n.value = value;
      n.step = "any";
      n.dataset.key = key;
      r.addEventListener("input", () => {
        const v = fromSlider(p, Number(r.value));
        n.value = v;
        set(v);
      });
      // A typed value goes to the reader as it is: out of range gives the CLI's message.
      n.addEventListener("change", () => set(n.value.trim() === "" ? null : Number(n.value)));
      row.append(r, n);
    } else if (p.kind === "bool") {
      const b = document.createElement("input");
      b.type = "checkbox";
      b.checked = value;
      b.dataset.key = key;
      b.addEventListener("change", () => set(b.checked));
      row.append(b);
    } else if (p.kind === "choice" || (p.kind === "string" && p.name === "metal")) {
      const s = document.createElement("select");
      const opts = p.kind === "choice" ? p.choices : D.metals.map((m) => m.name);
      for (const c of opts) s.add(new Option(c, c));
      s.value = value;
      s.dataset.key = key;
      s.addEventListener("change", () => set(s.value));
      row.append(s);
    }
    return row;
  }
  function buildTable(container, spec, values, path, prefix) {
    for (const p of spec.params) {
      if (p.sets) continue;  // shorthands have no control: their halves do
      const v = values[p.name];
      const label = prefix + p.name;
      const here = path.concat([p.name]);
      if (p.kind === "scalar" || p.kind === "bool" || p.kind === "choice") {
        if (v !== undefined) container.appendChild(paramRow(p, label, v, here));
      } else if (p.kind === "string") {
        if (v !== undefined && p.name === "metal") container.appendChild(paramRow(p, label, v, here));
      } else if (p.kind === "color") {
        if (v !== undefined) ["r", "g", "b"].forEach((ch, i) => container.appendChild(paramRow(p, `${label}.${ch}`, v[i], here, i)));
      } else if (p.kind === "object") {
        const row = document.createElement("label");
        const cb = document.createElement("input");
        cb.type = "checkbox";
        cb.checked = v !== undefined;
        cb.dataset.key = here.join(".");
        cb.addEventListener("change", () => editValue(here, cb.checked ? defaultsOf(p.sub) : undefined));
        row.append(cb, ` ${label} (${p.sub.title})`);
        row.title = p.doc;
        container.appendChild(row);
        if (v !== undefined) {
          const box = document.createElement("div");
          box.className = "nested";
          buildTable(box, p.sub, v, here, label + ".");
          container.appendChild(box);
        }
      } else if (p.kind === "tagged-object") {
        const row = document.createElement("div");
        row.className = "param";
        row.title = p.doc;
        const s = document.createElement("select");
        for (const c of p.choices) s.add(new Option(c, c));
        s.value = v.model;
        s.dataset.key = here.join(".") + ".model";
        s.addEventListener("change", () => editValue(here, Object.assign(defaultsOf(p.subs[s.value]), { model: s.value })));
        row.append(`${label}.model `, s);
        container.appendChild(row);
        const box = document.createElement("div");
        box.className = "nested";
        buildTable(box, p.subs[v.model], v, here, label + ".");
        container.appendChild(box);
      } else if (p.kind === "list") {
        if (v === undefined) continue;
        v.forEach((item, i) => {
          const head = document.createElement("div");
          head.textContent = `${label}[${i}]`;
          container.appendChild(head);
          const box = document.createElement("div");
          box.className = "nested";
          buildTable(box, p.sub, item, here.concat([i]), `${label}[${i}].`);
          container.appendChild(box);
        });
        const row = document.createElement("div");
        row.className = "row";
        const plus = document.createElement("button");
        plus.textContent = `+ ${p.name.replace(/s$/, "")}`;
        plus.id = `add-${p.name}`;
        plus.disabled = v.length >= p.max_items;
        plus.addEventListener("click", () => editValue(here, v.concat([JSON.parse(JSON.stringify(v[v.length - 1]))])));
        const minus = document.createElement("button");
        minus.textContent = `- ${p.name.replace(/s$/, "")}`;
        minus.id = `remove-${p.name}`;
        minus.disabled = v.length <= 1;
        minus.addEventListener("click", () => editValue(here, v.slice(0, -1)));
        row.append(plus, minus);
        container.appendChild(row);
      }
    }
  }
  function buildControls() {
    const m = editing();
    $("model").value = m.desc.model;
    $("preset").value = m.preset || "";
    const box = $("params");
    box.textContent = "";
    buildTable(box, modelSpec(m.desc.model), V.resolvedJson(m.desc), [], "");
    // A measured file: what it is, and the reader's notes as the CLI prints them.
    const src = $("source");
    src.textContent = `${state.edit}: ${m.where}${m.summary ? ` (${m.summary})` : ""}`;
    for (const n of m.notes || []) {
      const line = document.createElement("div");
      line.textContent = `aniso: note: ${n}`;
      src.appendChild(line);
    }
  }
  function initPickers() {
    const pr = $("preset");
    pr.add(new Option("(edited)", ""));
    for (const p of D.presets) pr.add(new Option(p.name, p.name));
    pr.addEventListener("change", () => {
      if (pr.value) setMaterial(state.edit, presetJson(pr.value), `preset ${pr.value}`, pr.value);
    });
    const mo = $("model");
    // The measured models are files: listed, not chosen (open or drop the file).
    for (const m of D.models) {
      if (D.no_glsl.includes(m.name)) continue;
      const file = D.measured.models.includes(m.name);
      const o = new Option(file ? `${m.name} (open a file)` : m.name, m.name);
      o.disabled = file;
      mo.add(o);
    }
    mo.addEventListener("change", () => {
      // A model's defaults; a table with required keys gets the first preset of that model.
      const pre = D.presets.find((p) => p.material.model === mo.value);
      let obj = Object.assign(defaultsOf(modelSpec(mo.value)), { model: mo.value });
      try {
        V.parseMaterial(obj, "model", D);
      } catch (e) {
        if (pre) obj = pre.material;
      }
      setMaterial(state.edit, obj, `model ${mo.value}`);
    });
    $("ab").addEventListener("change", () => {
      state.edit = $("ab").value;
      buildControls();
    });
  }

  // ---- files, exports, links --------------------------------------------------------------------
  function download(name, data) {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([data], { type: typeof data === "string" ? "text/plain" : "application/octet-stream" }));
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
  }
  // The JSON a material file holds: every key, defaults filled in (as `aniso presets --show`).
  function materialText(m) {
    return JSON.stringify(V.resolvedJson(m.desc), null, 2) + "\n";
  }
  // C++ "{:.9g}", and glsl_float_literal (src/gl/glsl_material.cpp).
  const g9 = (x) => V.fmtG(x, 9);
  function floatLiteral(x) {
    let s = g9(Math.fround(x));
    if (!/[.eEn]/.test(s)) s += ".0";
    return s;
  }
  function oneLine(s) {
    return s.replace(/[\r\n]/g, " ");
  }
  // The names the GLSL button downloads; a measured material's tables go beside the shader.
  const GLSL_NAME = "material.glsl", GLSL_TABLES_NAME = GLSL_NAME + ".tables";
  // The side file of export-glsl (gl::export_glsl_tables): the floats, zero-padded to whole rows.
  function exportTables(m) {
    const w = D.measured.tables.width, out = new Float32Array(Math.ceil(m.tables.length / w) * w);
    out.set(m.tables);
    return new Uint8Array(out.buffer);
  }
  // export-glsl --full (src/gl/glsl_export.cpp export_glsl): header, the whole prefixed library,
  // the slots as constants, the prefixed builder; every piece but the constants' values is
  // generated text. (The CLI's default keeps only the library functions the material uses.)
  function exportGlsl(m) {
    const shape = D.shapes[shapeKey(m.desc)];
    let out =
      `// Generated by aniso ${D.version} \`aniso export-glsl\` from ${oneLine(m.where.replace(/^preset /, ""))} (model ${m.desc.model}); do not edit.\n` +
      "// Self-contained GLSL (3.30 core and later; ES 3.00 with `precision highp float;`), no #version\n" +
      "// and no main. Defines aniso_f(wi, wo), aniso_pdf(wi, wo), aniso_sample(wo, u, weight, pdf) and\n" +
      "// aniso_f_world(L, V, N, X, Y); every name it defines starts with aniso_ (docs/glsl.md).\n\n";
    if (shape.needs_tables) {
      // src/gl/glsl_export.cpp export_glsl: the side file the page downloads beside the shader.
      const w = D.measured.tables.width, rows = Math.ceil(m.tables.length / w);
      out +=
        `// A measured material: its tables are data, in the side file ${GLSL_TABLES_NAME} (${m.tables.length} floats, raw little-endian\n` +
        `// float32, zero-padded to ${w} x ${rows}). Upload them as one texture and set the sampler to its unit:\n` +
        `//   glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, ${w}, ${rows}, 0, GL_RED, GL_FLOAT, data);  (NEAREST filters)\n` +
        '//   glUniform1i(glGetUniformLocation(program, "aniso_MeasuredTables_texture"), unit);\n' +
        '// Layout: docs/glsl.md, "Measured materials".\n\n';
    }
    out += D.glsl.library_prefixed;
    out += "\n// ---- the material's parameters (from its parameter table) and entry points\n";
    for (const s of shape.slots) {
      const v = slotValue(m.desc, s);
      let lit;
      if (s.type === "float") lit = floatLiteral(v);
      else if (s.type === "vec3") lit = `vec3(${v.map(floatLiteral).join(", ")})`;
      else if (s.type === "bool") lit = v ? "true" : "false";
      else lit = String(v);
      out += `const ${s.type} aniso_p_${s.name} = ${lit};  // ${s.key}\n`;
    }
    out += shape.code_prefixed;
    return out;
  }

  // The link: material (compact JSON) and view in the fragment, so nothing is sent to a server.
  function linkHash() {
    const q = new URLSearchParams();
    q.set("material", JSON.stringify(V.resolvedJson(state.A.desc)));
    if (state.view.compare !== "off") q.set("material_b", JSON.stringify(V.resolvedJson(state.B.desc)));
    for (const [k, v] of Object.entries(state.light)) q.set(k, String(v));
    q.set("tangent_angle", String(state.tangent.angle));
    q.set("field", state.tangent.field);
    q.set("log", state.view.log ? "1" : "0");
    q.set("xcos", state.view.xcos ? "1" : "0");
    q.set("compare", state.view.compare);
    if (state.view.views !== defaults.view.views) q.set("views", state.view.views);
    return "#" + q.toString();
  }
  // Reads a link: every value is checked first; any bad one shows its message and nothing changes.
  function applyHash(hash) {
    const q = new URLSearchParams(hash.replace(/^#/, ""));
    try {
      const next = { light: Object.assign({}, state.light), tangent: Object.assign({}, state.tangent), view: Object.assign({}, state.view) };
      const num = (k, lo, hi, set) => {
        if (!q.has(k)) return;
        const s = q.get(k), x = Number(s);
        if (s.trim() === "" || !Number.isFinite(x) || x < lo || x > hi)
          throw new V.InputError(`link: key "${k}": expected a number in [${lo}, ${hi}], got "${V.textEscape(s)}"`);
        set(x);
      };
      num("theta", 0, 89, (x) => (next.light.theta = x));
      num("phi", -180, 180, (x) => (next.light.phi = x));
      num("irradiance", 0, 1000, (x) => (next.light.irradiance = x));
      num("exposure", -20, 20, (x) => (next.light.exposure = x));
      num("tangent_angle", -180, 180, (x) => (next.tangent.angle = x));
      const choice = (k, list, set) => {
        if (!q.has(k)) return;
        if (!list.includes(q.get(k)))
          throw new V.InputError(`link: key "${k}": expected one of ${list.map((s) => `"${s}"`).join(", ")}, got "${V.textEscape(q.get(k))}"`);
        set(q.get(k));
      };
      choice("field", Object.keys(fieldKinds), (s) => (next.tangent.field = s));
      choice("compare", ["off", "split", "difference"], (s) => (next.view.compare = s));
      choice("log", ["0", "1"], (s) => (next.view.log = s === "1"));
      choice("xcos", ["0", "1"], (s) => (next.view.xcos = s === "1"));
      if (q.has("size")) {
        const m = /^(\d{2,4})x(\d{2,4})$/.exec(q.get("size"));
        if (!m || Number(m[1]) < 64 || Number(m[2]) < 64 || Number(m[1]) > 4096 || Number(m[2]) > 4096)
          throw new V.InputError(`link: key "size": expected WxH, each from 64 to 4096 (the lit views' canvas), got "${V.textEscape(q.get("size"))}"`);
        next.size = [Number(m[1]), Number(m[2])];
      }
      if (q.has("views")) {
        const all = defaults.view.views.split(","), v = q.get("views").split(",");
        const bad = v.find((x) => !all.includes(x));
        if (bad !== undefined || !v.length)
          throw new V.InputError(`link: key "views": unknown view "${V.textEscape(bad || "")}"; expected a comma-separated list of ${all.map((x) => `"${x}"`).join(", ")}`);
        next.view.views = v.join(",");
      }
      const A = q.has("material") ? makeMaterial(q.get("material"), "inline material") : state.A;
      const B = q.has("material_b") ? makeMaterial(q.get("material_b"), "inline material") : state.B;
      if (next.size) {
        canvas.width = next.size[0];
        canvas.height = next.size[1];
        delete next.size;
      }
      Object.assign(state, next);
      replaceMaterial("A", A);
      replaceMaterial("B", B);
      showError("");
      syncInputs();
      onMaterialChange();
      return true;
    } catch (err) {
      reportError(err);
      return false;
    }
  }

  // A file opened or dropped: a measured file (.bsdf, .binary) as material A or B, an OBJ as the
  // object, anything else as a JSON material. state.fileLoads counts the files done.
  function loadFile(file) {
    const done = () => state.fileLoads++;
    if (MF.isMeasuredFile(file.name)) {
      file
        .slice(0, MF.bytesNeeded(file.name, file.size))
        .arrayBuffer()
        .then((buf) => setMeasured(state.edit, file.name, new Uint8Array(buf), file.size))
        .catch((err) => reportError(new V.InputError(`${file.name}: cannot read: ${err.message}`)))
        .finally(done);
      return;
    }
    file.text().then((text) => {
      if (/\.obj$/i.test(file.name)) {
        try {
          uploadMesh(parseObj(text, file.name));
          const o = $("object");
          if (![...o.options].some((x) => x.value === "file")) o.add(new Option(file.name, "file"));
          o.value = "file";
          showError("");
          schedule({ lit: true });
        } catch (err) {
          reportError(err);
        }
        return;
      }
      setMaterial(state.edit, text, file.name);
    }).finally(done);
  }

  // ---- redraw only on change ------------------------------------------------------------------
  const dirty = { lit: false, display: false, polar: false, albedo: false, lobe: false };
  let pending = false;
  function schedule(what) {
    Object.assign(dirty, what);
    if (pending) return;
    pending = true;
    requestAnimationFrame(redraw);
  }
  function redraw() {
    pending = false;
    const t0 = performance.now();
    try {
      const cmp = state.view.compare !== "off";
      // Views left out of the link's "views" list are not computed (the tests' CPU time).
      const on = new Set(state.view.views.split(","));
      for (const [k, id] of [["lit", "gl"], ["polar", "polar-in"], ["polar", "polar-perp"], ["albedo", "albedo"], ["lobe", "lobe"]])
        $(id).parentElement.hidden = !on.has(k);
      if (!on.has("lit")) dirty.lit = dirty.display = false;
      if (!on.has("albedo")) dirty.albedo = false;
      if (!on.has("lobe")) dirty.lobe = false;
      // Each stage's time. Chromium's gl.finish() does not wait for the GPU process; reading one
      // pixel back does, so the GPU's work is counted in the stage that issued it.
      const stage = {};
      let mark = performance.now();
      const px = new Uint8Array(4);
      const lap = (name) => {
        gl.bindFramebuffer(gl.FRAMEBUFFER, null);
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
        const now = performance.now();
        stage[name] = now - mark;
        mark = now;
      };
      if (dirty.lit || dirty.display) drawLit(dirty.lit);
      lap("lit");
      if (dirty.polar) {
        computePolar("A");
        if (cmp) computePolar("B");
      }
      lap("polar");
      if (dirty.polar || dirty.view) {
        drawPolar("polar-in", 0, "plane of incidence");
        drawPolar("polar-perp", 1, "perpendicular plane");
      }
      if (dirty.albedo) {
        computeAlbedo("A");
        if (cmp) computeAlbedo("B");
      }
      if (on.has("albedo") && (dirty.albedo || dirty.view)) drawAlbedo();
      lap("albedo");
      if (dirty.lobe) computeLobe();
      if (on.has("lobe") && (dirty.lobe || dirty.view)) drawLobe();
      lap("lobe");
      drawLightWidget();
      results.stageMs.push(stage);
    } catch (err) {
      reportError(err);
      console.error(err);
    }
    for (const k of Object.keys(dirty)) dirty[k] = false;
    results.frameMs.push(performance.now() - t0);
    state.redraws++;
  }
  function onMaterialChange() {
    buildControls();
    schedule({ lit: true, polar: true, albedo: true, lobe: true, view: true });
  }
  function onViewChange(light) {
    syncInputs();
    schedule(light ? { lit: true, polar: true, albedo: true, lobe: true, view: true } : { lit: true, view: true });
  }
  function syncInputs() {
    const pairs = [["theta", state.light, "theta"], ["phi", state.light, "phi"], ["irradiance", state.light, "irradiance"],
      ["exposure", state.light, "exposure"], ["tangent-angle", state.tangent, "angle"], ["swirl", state.tangent, "swirl"],
      ["noise-scale", state.tangent, "noise_scale"], ["noise-strength", state.tangent, "noise_strength"]];
    for (const [id, obj, k] of pairs) {
      $(id).value = obj[k];
      $(id + "-out").textContent = Number(obj[k]).toFixed(1);
    }
    $("tangent-field").value = state.tangent.field;
    $("log").checked = state.view.log;
    $("xcos").checked = state.view.xcos;
    $("compare").value = state.view.compare;
  }
  function initInputs() {
    const bind = (id, obj, k, light) =>
      $(id).addEventListener("input", () => {
        obj[k] = Number($(id).value);
        onViewChange(light);
      });
    bind("theta", state.light, "theta", true);
    bind("phi", state.light, "phi", true);
    bind("irradiance", state.light, "irradiance", false);
    $("exposure").addEventListener("input", () => {
      state.light.exposure = Number($("exposure").value);
      syncInputs();
      schedule({ display: true });
    });
    bind("tangent-angle", state.tangent, "angle", false);
    bind("swirl", state.tangent, "swirl", false);
    bind("noise-scale", state.tangent, "noise_scale", false);
    bind("noise-strength", state.tangent, "noise_strength", false);
    $("tangent-field").addEventListener("change", () => {
      state.tangent.field = $("tangent-field").value;
      onViewChange(false);
    });
    $("log").addEventListener("change", () => {
      state.view.log = $("log").checked;
      schedule({ view: true });
    });
    $("xcos").addEventListener("change", () => {
      state.view.xcos = $("xcos").checked;
      schedule({ view: true });
    });
    $("compare").addEventListener("change", () => {
      state.view.compare = $("compare").value;
      onMaterialChange();
    });
    $("object").addEventListener("change", () => {
      if ($("object").value === "torus") uploadMesh(torusMesh(1, 0.4, 96, 48));
      schedule({ lit: true });
    });
    const lc = $("light");
    let drag = false;
    lc.addEventListener("pointerdown", (e) => {
      drag = true;
      lc.setPointerCapture(e.pointerId);
      lightFromWidget(e);
    });
    lc.addEventListener("pointermove", (e) => drag && lightFromWidget(e));
    lc.addEventListener("pointerup", () => (drag = false));
    const lo = $("lobe");
    let lastDrag = null;
    lo.addEventListener("pointerdown", (e) => {
      lastDrag = [e.clientX, e.clientY];
      lo.setPointerCapture(e.pointerId);
    });
    lo.addEventListener("pointermove", (e) => {
      if (!lastDrag) return;
      lobeView.yaw += e.clientX - lastDrag[0];
      lobeView.pitch = Math.max(-89, Math.min(89, lobeView.pitch + e.clientY - lastDrag[1]));
      lastDrag = [e.clientX, e.clientY];
      schedule({ view: true });
    });
    lo.addEventListener("pointerup", () => (lastDrag = null));
    $("load").addEventListener("change", () => $("load").files[0] && loadFile($("load").files[0]));
    $("save").addEventListener("click", () => download("material.json", materialText(editing())));
    $("export-glsl").addEventListener("click", () => {
      const m = editing();
      download(GLSL_NAME, exportGlsl(m));
      if (m.tables) download(GLSL_TABLES_NAME, exportTables(m));
    });
    $("export-brdf").addEventListener("click", () => {
      try {
        download("material.brdf", exportBrdf(editing()));
      } catch (err) {
        reportError(err);
      }
    });
    $("share").addEventListener("click", () => {
      history.replaceState(null, "", linkHash());
      if (navigator.clipboard) navigator.clipboard.writeText(location.href).catch(() => {});
    });
    document.addEventListener("dragover", (e) => {
      e.preventDefault();
      document.body.classList.add("dragging");
    });
    document.addEventListener("dragleave", () => document.body.classList.remove("dragging"));
    document.addEventListener("drop", (e) => {
      e.preventDefault();
      document.body.classList.remove("dragging");
      if (e.dataTransfer.files[0]) loadFile(e.dataTransfer.files[0]);
    });
    window.addEventListener("hashchange", () => applyHash(location.hash));
  }
  // The upper end of a BRDF Explorer `float` slider: src/gl/glsl_export.cpp slider_max (an
  // open-ended range ends at the power of ten at or above 10 times the value, at least 10).
  function sliderMax(p, value) {
    if (!(p.max / Math.max(Math.abs(p.min), 1e-3) > 1e3 && p.min >= 0)) return p.max;
    return Math.min(p.max, Math.pow(10, Math.ceil(Math.log10(Math.max(10 * value, 10)))));
  }
  // export-brdf (src/gl/glsl_export.cpp export_brdf): BRDF Explorer's parameter lines from the
  // table's ranges and the material's values, the shader from the generated text.
  function exportBrdf(m) {
    const shape = D.shapes[shapeKey(m.desc)];
    const key = shapeKey(m.desc);
    if (shape.needs_tables)
      throw new V.InputError(`${oneLine(m.where)}: a measured material's GLSL reads its tables from a texture, which a BRDF Explorer .brdf file cannot ` +
        "carry; use `aniso export-glsl` (the shader and its tables file) or fit an analytic model first (`aniso fit`)");
    let out =
      `analytic\n\n# Generated by aniso ${D.version} \`aniso export-brdf\` from ${oneLine(m.where.replace(/^preset /, ""))} (model ${m.desc.model}); parameters from aniso's table\n` +
      "# (ranges) and from the material (defaults). Choices are sliders over their index.\n\n::begin parameters\n";
    for (const s of shape.slots) {
      const v = slotValue(m.desc, s);
      const p = slotEntry(m.desc, s).p;
      if (s.type === "float") out += `float ${s.name} ${g9(p.min)} ${g9(sliderMax(p, v))} ${g9(v)}\n`;
      else if (s.type === "bool") out += `bool ${s.name} ${v ? 1 : 0}\n`;
      else if (s.type === "int") out += `float ${s.name} 0 ${p.choices.length - 1} ${v}\n`;
      else if (p.min >= 0 && p.max <= 1) out += `color ${s.name} ${v.map(g9).join(" ")}\n`;
      else ["r", "g", "b"].forEach((ch, c) => (out += `float ${s.name}_${ch} ${g9(p.min)} ${g9(sliderMax(p, Math.max(...v)))} ${g9(v[c])}\n`));
    }
    out += "::end parameters\n\n::begin shader\n";
    out += D.glsl.library_prefixed + D.shapes[key].brdf_code + "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return aniso_f_world(L, V, N, X, Y); }\n::end shader\n";
    return out;
  }
  // ---- start ----------------------------------------------------------------------------------
  function start() {
    const first = (names) => names.find((n) => presetJson(n)) || D.presets[0].name;
    const a = first(["brushed-gold"]), b = first(["gold", "polished-gold"]);
    state.A = makeMaterial(presetJson(a), `preset ${a}`, a);
    state.B = makeMaterial(presetJson(b), `preset ${b}`, b);
    initPickers();
    initInputs();
    syncInputs();
    if (location.hash.length > 1) applyHash(location.hash);
    onMaterialChange();
  }

  // What the tests (tests/web) and the curious read: state, the plots' numbers, exports, links.
  window.anisoExplorer = {
    state, results, readSphere, toneMapProbe, linkHash, applyHash, exportGlsl, exportBrdf, exportTables, materialText, limits,
    setMaterial: (text, where) => setMaterial(state.edit, text, where),
    material: (which) => V.resolvedJson(state[which || "A"].desc),
    error: () => state.lastError,
    notes: (which) => state[which || "A"].notes || [],
    idle: () => !pending,
    shapeKey: (which) => shapeKey(state[which || "A"].desc),
  };
  start();
})();

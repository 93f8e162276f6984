// web/validate.js: the material reader of the CLI, mirrored for the page, driven by the parameter
// tables that `aniso web-data` exports (window.ANISO_DATA.models). Every message is the one the C++
// reader gives, line for line:
//   parseJsonText          src/io/json_read.cpp  parse_json_text (duplicate keys, depth 64)
//   jsonTypeName           src/io/materials.cpp  json_type_name
//   readParams, readValue  src/io/materials.cpp  read_params, read_value, resolve_pairs, apply_rule (the
//                                                tables' cross-key rules, exported with them)
//   parseMaterial          src/models/models.cpp parse_material
// The range texts ("number in (0, 1]") come from the C++ describe_range() through the tables, so
// they are not rewritten here. Known differences (docs/web.md): the syntax-error text of invalid
// JSON is the page's own ("invalid JSON: parse error at line L, column C: <what>"), not nlohmann's.
"use strict";

(function (global) {
  class InputError extends Error {}

  // src/io/json_read.cpp text_escape
  function textEscape(s) {
    let out = "";
    for (const ch of s) {
      const c = ch.codePointAt(0);
      if (ch === "\n") out += "\\n";
      else if (ch === "\t") out += "\\t";
      else if (ch === "\r") out += "\\r";
      else if (c < 0x20 || c === 0x7f) out += "\\u" + c.toString(16).padStart(4, "0");
      else out += ch;
    }
    return out;
  }

  // C++ fmt "{:g}" (printf %g, precision 6), or "{:.Pg}" with another precision P.
  function fmtG(x, precision = 6) {
    if (!Number.isFinite(x)) return Number.isNaN(x) ? "nan" : x > 0 ? "inf" : "-inf";
    if (x === 0) return Object.is(x, -0) ? "-0" : "0";
    const e = Number(x.toExponential(precision - 1).split("e")[1]);
    const strip = (s) => (s.includes(".") ? s.replace(/0+$/, "").replace(/\.$/, "") : s);
    if (e < -4 || e >= precision) {
      const [m, ex] = x.toExponential(precision - 1).split("e");
      const n = Number(ex);
      return strip(m) + "e" + (n < 0 ? "-" : "+") + String(Math.abs(n)).padStart(2, "0");
    }
    return strip(x.toFixed(precision - 1 - e));
  }

  // Which numbers were written as floating-point literals ("5.0", "1e10"): nlohmann keeps them
  // as doubles and dumps them differently from integers. container -> keys / indices.
  const floatLiterals = new WeakMap();
  const isFloatAt = (container, key) => !!(container && floatLiterals.has(container) && floatLiterals.get(container).has(key));

  // nlohmann::json's dump of a number (nlohmann/detail/conversions/to_chars.hpp, format_buffer):
  // an integer as written; a double from its shortest round-trip digits d1..dk and decimal
  // exponent n (value = 0.d1..dk x 10^n): "ddd000.0" for k <= n <= 15, "dd.ddd" for 0 < n <= 15,
  // "0.000ddd" for -4 < n <= 0, otherwise "d.ddde+XX" (at least two exponent digits).
  function dumpNumber(x, isFloat) {
    if (!isFloat) return String(x);
    if (x === 0) return Object.is(x, -0) ? "-0.0" : "0.0";
    const sign = x < 0 ? "-" : "";
    const [m, e] = Math.abs(x).toExponential().split("e");
    const digits = m.replace(".", "");
    const k = digits.length, n = Number(e) + 1;
    let out;
    if (k <= n && n <= 15) out = digits + "0".repeat(n - k) + ".0";
    else if (0 < n && n <= 15) out = digits.slice(0, n) + "." + digits.slice(n);
    else if (-4 < n && n <= 0) out = "0." + "0".repeat(-n) + digits;
    else {
      const ex = n - 1;
      out = digits[0] + (k > 1 ? "." + digits.slice(1) : "") + "e" + (ex < 0 ? "-" : "+") + String(Math.abs(ex)).padStart(2, "0");
    }
    return sign + out;
  }

  function jsonTypeName(v, isFloat) {
    if (typeof v === "number") return `the number ${dumpNumber(v, isFloat)}`;
    if (typeof v === "string") return `the string ${JSON.stringify(v)}`;
    if (typeof v === "boolean") return v ? "true" : "false";
    if (Array.isArray(v)) return `an array of ${v.length} elements`;
    if (v !== null && typeof v === "object") return "an object";
    return "null";
  }

  const kMaxJsonDepth = 64;  // src/io/json_read.h

  // A JSON parser that reports what parse_json_text reports: a duplicate key with its path, nesting
  // deeper than 64 levels, numbers that overflow a double. JSON.parse would keep the last of two
  // duplicate keys silently.
  function parseJsonText(text, where) {
    let i = 0;
    const stack = [];  // frames {obj, key, index}
    const pathOf = () => {
      let p = "";
      for (const f of stack) {
        if (f.obj) {
          if (f.key !== undefined && f.key !== "") p += (p ? "." : "") + textEscape(f.key);
        } else if (f.index >= 0) p += `[${f.index}]`;
      }
      return p;
    };
    const lineCol = (pos) => {
      const before = text.slice(0, pos).split("\n");
      return `line ${before.length}, column ${before[before.length - 1].length + 1}`;
    };
    const syntax = (what) => {
      throw new InputError(`${where}: invalid JSON: parse error at ${lineCol(i)}: ${what}`);
    };
    const ws = () => {
      while (i < text.length && " \t\n\r".includes(text[i])) ++i;
    };
    const element = () => {
      if (stack.length && !stack[stack.length - 1].obj) ++stack[stack.length - 1].index;
    };
    let lastFloat = false;  // the value just read was a floating-point literal
    const mark = (container, key) => {
      if (!floatLiterals.has(container)) floatLiterals.set(container, new Set());
      floatLiterals.get(container).add(key);
    };
    function value() {
      lastFloat = false;
      ws();
      const c = text[i];
      if (c === "{" || c === "[") {
        element();
        if (stack.length >= kMaxJsonDepth)
          throw new InputError(`${where}: ${pathOf() || "top level"}: nested deeper than ${kMaxJsonDepth} levels (no material or scene needs more)`);
        if (c === "{") {
          const f = { obj: true, keys: new Set(), key: undefined };
          stack.push(f);
          ++i;
          const out = {};
          ws();
          if (text[i] === "}") {
            ++i;
            stack.pop();
            return out;
          }
          for (;;) {
            ws();
            if (text[i] !== '"') syntax("expected a string (an object key)");
            const k = string();
            f.key = k;
            if (f.keys.has(k))
              throw new InputError(`${where}: ${pathOf()}: duplicate key "${textEscape(k)}" (each key may appear once in an object)`);
            f.keys.add(k);
            ws();
            if (text[i] !== ":") syntax("expected ':'");
            ++i;
            out[k] = value();
            if (lastFloat) mark(out, k);
            ws();
            if (text[i] === ",") {
              ++i;
              continue;
            }
            if (text[i] === "}") {
              ++i;
              break;
            }
            syntax("expected ',' or '}'");
          }
          stack.pop();
          lastFloat = false;
          return out;
        }
        const f = { obj: false, index: -1 };
        stack.push(f);
        ++i;
        const out = [];
        ws();
        if (text[i] === "]") {
          ++i;
          stack.pop();
          return out;
        }
        for (;;) {
          out.push(value());
          if (lastFloat) mark(out, out.length - 1);
          ws();
          if (text[i] === ",") {
            ++i;
            continue;
          }
          if (text[i] === "]") {
            ++i;
            break;
          }
          syntax("expected ',' or ']'");
        }
        stack.pop();
        lastFloat = false;
        return out;
      }
      element();
      if (c === '"') return string();
      const m = /^-?(0|[1-9]\d*)(\.\d+)?([eE][+-]?\d+)?/.exec(text.slice(i));
      if (m && m[0].length) {
        i += m[0].length;
        const x = Number(m[0]);
        if (!Number.isFinite(x)) syntax(`number overflow parsing '${m[0]}'`);
        lastFloat = m[2] !== undefined || m[3] !== undefined;
        return x;
      }
      for (const [lit, v] of [["true", true], ["false", false], ["null", null]])
        if (text.startsWith(lit, i)) {
          i += lit.length;
          return v;
        }
      if (i >= text.length) syntax("unexpected end of input");
      // The position nlohmann's lexer reports: the first character that leaves the literal.
      for (const lit of ["true", "false", "null"])
        if (text[i] === lit[0]) {
          let j = i;
          while (j - i < lit.length && text[j] === lit[j - i]) ++j;
          i = j;
          break;
        }
      syntax("invalid literal");
    }
    function string() {
      const m = /^"(?:[^"\\\u0000-\u001f]|\\["\\/bfnrt]|\\u[0-9a-fA-F]{4})*"/.exec(text.slice(i));
      if (!m) syntax("invalid string");
      i += m[0].length;
      return JSON.parse(m[0]);
    }
    const v = value();
    ws();
    if (i < text.length) syntax("unexpected text after the value");
    return v;
  }

  const isObject = (v) => v !== null && typeof v === "object" && !Array.isArray(v);
  const has = (o, k) => Object.prototype.hasOwnProperty.call(o, k);

  function inRange(p, x) {
    if (!Number.isFinite(x)) return false;
    if (p.min_exclusive ? !(x > p.min) : !(x >= p.min)) return false;
    return x <= p.max;
  }
  function fail(where, key, what) {
    throw new InputError(`${where}: key "${key}": ${what}`);
  }

  function readValue(v, p, where, data, isFloat) {
    const expected = () => `expected ${p.range}, got ${jsonTypeName(v, isFloat)}`;
    switch (p.kind) {
      case "scalar":
        if (typeof v !== "number" || !inRange(p, v)) fail(where, p.name, expected());
        return v + 0;
      case "color": {
        if (typeof v === "number") {
          if (!inRange(p, v)) fail(where, p.name, expected());
          return [v + 0, v + 0, v + 0];
        }
        if (!Array.isArray(v) || v.length !== 3) fail(where, p.name, expected());
        return v.map((x, i) => {
          if (typeof x !== "number" || !inRange(p, x))
            fail(where, p.name, `element ${i}: expected ${p.range}, got ${jsonTypeName(x, isFloatAt(v, i))}`);
          return x + 0;
        });
      }
      case "bool":
        if (typeof v !== "boolean") fail(where, p.name, expected());
        return v;
      case "choice":
      case "string":
        if (typeof v !== "string") fail(where, p.name, expected());
        if (p.kind === "choice" && !p.choices.includes(v)) fail(where, p.name, expected());
        return v;
      case "object":
        if (!isObject(v)) fail(where, p.name, expected());
        return readParams(v, p.sub, `${where}: ${p.name}`, undefined, data);
      case "tagged-object": {
        if (!isObject(v)) fail(where, p.name, expected());
        if (!has(v, "model") || typeof v.model !== "string") fail(where, `${p.name}.model`, expected());
        if (!p.choices.includes(v.model)) fail(where, `${p.name}.model`, expected());
        const out = readParams(v, p.subs[v.model], `${where}: ${p.name}`, "model", data);
        out.model = v.model;
        return out;
      }
      case "list": {
        if (!Array.isArray(v) || v.length === 0 || v.length > p.max_items) fail(where, p.name, expected());
        return v.map((item, i) => {
          if (!isObject(item)) fail(where, `${p.name}[${i}]`, `expected an object, got ${jsonTypeName(item, isFloatAt(v, i))}`);
          return readParams(item, p.sub, `${where}: ${p.name}[${i}]`, undefined, data);
        });
      }
    }
    fail(where, p.name, "unsupported parameter kind");
  }

  // read_params: unknown keys first, then every key of the table in order, then the pairs.
  function readParams(obj, spec, where, tagKey, data) {
    if (!isObject(obj)) throw new InputError(`${where}: expected a JSON object, got ${jsonTypeName(obj)}`);
    const names = spec.params.map((p) => p.name);
    for (const key of Object.keys(obj)) {
      if (key === tagKey) continue;
      if (!names.includes(key))
        throw new InputError(`${where}: unknown key "${textEscape(key)}" for ${spec.name}; allowed keys: ${names.map((n) => `"${n}"`).join(", ")}`);
    }
    const pv = {};
    const pfail = (key, what) => fail(where, key, what);
    for (const p of spec.params) {
      if (has(obj, p.name)) {
        pv[p.name] = readValue(obj[p.name], p, where, data, isFloatAt(obj, p.name));
        continue;
      }
      if (p.required) fail(where, p.name, `missing (required; ${p.range})`);
      if (p.kind === "scalar" && p.default !== null) pv[p.name] = p.default;
      else if (p.kind === "color" && p.default !== null) pv[p.name] = [p.default, p.default, p.default];
      else if (p.kind === "bool") pv[p.name] = p.default !== 0;
      else if (p.kind === "choice") pv[p.name] = p.choices[0];
    }
    // resolve_pairs
    for (const p of spec.params) {
      if (!p.sets || !has(obj, p.name)) continue;
      for (const half of p.sets)
        if (has(obj, half)) pfail(p.name, `sets "${p.sets[0]}" and "${p.sets[1]}": cannot be given together with "${half}"`);
      pv[p.sets[0]] = pv[p.name];
      pv[p.sets[1]] = pv[p.name];
      delete pv[p.name];
    }
    for (const p of spec.params) {
      if (!p.partner || !has(obj, p.name) || has(obj, p.partner)) continue;
      let shorthand = "";
      for (const q of spec.params)
        if (q.sets && (q.sets[0] === p.name || q.sets[1] === p.name)) shorthand = `, or "${q.name}" alone for an isotropic value`;
      pfail(p.name, `given without its partner "${p.partner}": give both${shorthand}`);
    }
    for (const r of spec.rules || []) applyRule(r, pv, where);
    Object.defineProperty(pv, "$where", { value: where, enumerable: false });
    return pv;
  }

  // A table's cross-key rules as `aniso web-data` exports them (ParamRule, include/aniso/io/params.h;
  // src/io/materials.cpp apply_rule): the C++ reader's own, not a copy.
  function applyRule(r, pv, where) {
    const given = (k) => has(pv, k);
    const at = (k, c) => (Array.isArray(pv[k]) ? pv[k][c] : pv[k]);
    if (r.kind === "exclusive") {
      if (given(r.key) && r.keys.some(given)) fail(where, r.key, r.message);
    } else if (r.kind === "key-or-all") {
      const missing = r.keys.find((k) => !given(k));
      if (!given(r.key) && missing !== undefined) fail(where, r.keys.some(given) ? missing : r.key, r.message);
    } else if (r.kind === "non-zero") {
      let largest = 0;
      for (const k of r.keys) for (let c = 0; c < 3; ++c) largest = Math.max(largest, Math.abs(at(k, c)));
      if (!(largest > 0)) fail(where, r.key, r.message);
    } else if (r.kind === "peak-below") {
      for (let c = 0; c < 3; ++c) {
        const cmax = Math.max(0, ...r.keys.map((k) => Math.abs(at(k, c))));
        const n = at(r.exponent, c), scale = at(r.scale, c);
        if (n * Math.log10(Math.max(cmax, 1e-300)) + Math.log10(Math.max(scale, 1e-300)) > r.limit) {
          const vals = { cmax, scale, n, channel: c };
          fail(where, r.key, r.message.replace(/\{(\w+)(:g)?\}/g, (m, name, g) => (g ? fmtG(vals[name]) : String(vals[name]))));
        }
      }
    }
  }

  // parse_material: the model key, "fit", the table (with its cross-key rules), the metal's name.
  function parseMaterial(obj, where, data) {
    if (!isObject(obj)) throw new InputError(`${where}: expected a JSON object, got ${jsonTypeName(obj)}`);
    const models = data.models.map((m) => `"${m.name}"`).join(", ");
    if (!has(obj, "model")) throw new InputError(`${where}: key "model": missing; expected one of ${models}`);
    const spec = typeof obj.model === "string" ? data.models.find((m) => m.name === obj.model) : undefined;
    if (!spec) throw new InputError(`${where}: key "model": expected one of ${models}, got ${jsonTypeName(obj.model, isFloatAt(obj, "model"))}`);
    if (has(obj, "fit") && !isObject(obj.fit))
      throw new InputError(`${where}: key "fit": expected an object (the provenance \`aniso fit\` writes), got ${jsonTypeName(obj.fit, isFloatAt(obj, "fit"))}`);
    const body = Object.assign({}, obj);
    delete body.fit;
    if (floatLiterals.has(obj)) floatLiterals.set(body, floatLiterals.get(obj));
    const pv = readParams(body, spec, where, "model", data);
    const model = obj.model;
    // A measured material's "file" is a path, which a page cannot open: the file itself is opened
    // or dropped (web/measured.js reads it).
    if (model === "measured" || model === "rgl")
      fail(where, "file", `the page opens no paths: open or drop the ${model === "rgl" ? "RGL tensor file (.bsdf)" : "MERL table (.binary)"} itself`);
    // The metal's name (src/models/metal.h, Metal::check): one of the exported metals.
    if (model === "metal" && has(pv, "metal") && !data.metals.find((m) => m.name === pv.metal))
      fail(where, "metal", `unknown metal "${textEscape(pv.metal)}"; the metals are ${data.metal_names}`);
    return { model, params: pv, json: obj };
  }

  // resolved_json: every key, defaults filled in, shorthands as their halves (materials.cpp).
  function resolvedJson(desc) {
    const out = JSON.parse(JSON.stringify(desc.params));
    out.model = desc.model;
    const sortKeys = (v) => {
      if (Array.isArray(v)) return v.map(sortKeys);
      if (isObject(v)) {
        const o = {};
        for (const k of Object.keys(v).sort()) o[k] = sortKeys(v[k]);
        return o;
      }
      return v;
    };
    return sortKeys(out);
  }

  global.AnisoValidate = { InputError, parseJsonText, parseMaterial, readParams, resolvedJson, jsonTypeName, fmtG, textEscape };
})(typeof window !== "undefined" ? window : globalThis);

// web/measured.js: the page's reader of measured materials (docs/web.md, "Measured files"): an RGL
// tensor file (.bsdf) or a MERL table (.binary), opened or dropped, read with the C++ readers' rules
// and messages and turned into the floats gl::glsl_tables() makes, the texture the GLSL twins
// (include/aniso/brdf/rgl.glsl, measured.glsl) read. Function for function:
//   parseTensor         src/rgl/tensor.cpp          parse_tensor (the container)
//   rglFromTensor       src/rgl/rgl_material.cpp    rgl_from_tensor (the fields' rules and notes)
//   buildPL2D           src/rgl/rgl_material.cpp    PL2DTables::build (pbrt-v4's PiecewiseLinear2D)
//   spectralToRgb       src/measured/spectral.cpp   SpectralToRgb, cie1931_cmf
//   readMerl            src/measured/merl.cpp       read_merl
//   makeMeasured        src/measured/measured.cpp   make_measured (the sampling tables)
//   rglTables, merlTables  src/gl/glsl_material.cpp glsl_tables (the texture's layout)
// Where the C++ computes in float, so does this file (Math.fround after every float operation);
// where it computes in double, JavaScript's numbers are the same doubles. The tables then equal the
// C++'s float for float: tests/web/measured.test.mjs compares them with the side file of
// `aniso export-glsl`. The texture's width, MERL's layout and scales, the sampling tables'
// resolution and the readers' limits come from the C++ through `aniso web-data`
// (ANISO_DATA.measured, apps/aniso/cmd_web.cpp measured_json).
"use strict";

(function (global) {
  const V = global.AnisoValidate;
  const L = global.ANISO_DATA.measured;
  const { InputError } = V;
  const f32 = Math.fround;
  // The C++ readers copy bytes into floats (tensor.cpp and merl.cpp static_assert a little-endian
  // host); so does this file, through typed arrays.
  const littleEndian = new Uint8Array(new Uint32Array([1]).buffer)[0] === 1;

  // ---- the C++ messages' number formats ------------------------------------------------------
  // fmt's "{}" of a double (isFloat false) or a float (isFloat true), fmt 9 do_write_float: the
  // shortest digits that read back as the same value, in exponent form below 1e-4 and from 1e16 on.
  function fmtShortest(x, isFloat) {
    if (Number.isNaN(x)) return "nan";
    if (!Number.isFinite(x)) return x > 0 ? "inf" : "-inf";
    if (x === 0) return Object.is(x, -0) ? "-0" : "0";
    let m = "";
    if (isFloat) {
      for (let p = 1; p <= 9 && !m; ++p) {
        const s = Math.abs(x).toExponential(p - 1);
        if (f32(Number(s)) === Math.abs(x)) m = s;
      }
    } else m = Math.abs(x).toExponential();
    const [mant, ex] = m.split("e");
    const digits = mant.replace(".", "");
    const e = Number(ex), sign = x < 0 ? "-" : "";
    if (e < -4 || e >= 16) return sign + digits[0] + (digits.length > 1 ? "." + digits.slice(1) : "") + "e" + (e < 0 ? "-" : "+") + String(Math.abs(e)).padStart(2, "0");
    if (e >= digits.length - 1) return sign + digits + "0".repeat(e - digits.length + 1);
    if (e >= 0) return sign + digits.slice(0, e + 1) + "." + digits.slice(e + 1);
    return sign + "0." + "0".repeat(-e - 1) + digits;
  }
  const fmtF = (x) => fmtShortest(x, true);
  const fmtG = V.fmtG;  // "{:g}", "{:.Pg}"

  // src/io/text_escape.cpp text_escape, on bytes (a field name may hold any byte).
  function escapeBytes(b) {
    const at = (k) => (k < b.length ? b[k] : 0);
    const seq = (i) => {
      const c = at(i), cont = (k, lo = 0x80, hi = 0xbf) => at(i + k) >= lo && at(i + k) <= hi;
      if (c < 0x80) return 1;
      if (c >= 0xc2 && c <= 0xdf) return cont(1) ? 2 : 0;
      if (c === 0xe0) return cont(1, 0xa0) && cont(2) ? 3 : 0;
      if ((c >= 0xe1 && c <= 0xec) || c === 0xee || c === 0xef) return cont(1) && cont(2) ? 3 : 0;
      if (c === 0xed) return cont(1, 0x80, 0x9f) && cont(2) ? 3 : 0;
      if (c === 0xf0) return cont(1, 0x90) && cont(2) && cont(3) ? 4 : 0;
      if (c >= 0xf1 && c <= 0xf3) return cont(1) && cont(2) && cont(3) ? 4 : 0;
      if (c === 0xf4) return cont(1, 0x80, 0x8f) && cont(2) && cont(3) ? 4 : 0;
      return 0;
    };
    const hex = (c, n) => c.toString(16).padStart(n, "0");
    let out = "";
    for (let i = 0; i < b.length;) {
      const n = seq(i), c = b[i];
      if (n === 0) out += "\\x" + hex(c, 2);
      else if (n === 1) {
        if (c === 10) out += "\\n";
        else if (c === 9) out += "\\t";
        else if (c === 13) out += "\\r";
        else if (c < 0x20 || c === 0x7f) out += "\\u" + hex(c, 4);
        else out += String.fromCharCode(c);
      } else {
        const c1 = b[i + 1];
        if (c === 0xc2 && c1 < 0xa0) out += "\\u" + hex(c1, 4);
        else if (c === 0xe2 && c1 === 0x80 && (b[i + 2] === 0xa8 || b[i + 2] === 0xa9)) out += b[i + 2] === 0xa8 ? "\\u2028" : "\\u2029";
        else if (c === 0xef && c1 === 0xbf && (b[i + 2] === 0xbe || b[i + 2] === 0xbf)) out += b[i + 2] === 0xbe ? "\\ufffe" : "\\uffff";
        else out += new TextDecoder().decode(b.subarray(i, i + n));
      }
      i += n || 1;  // a byte outside a well-formed sequence: that byte alone
    }
    return out;
  }

  // ---- the tensor file container (src/rgl/tensor.cpp) --------------------------------------------
  const DTYPES = ["invalid", "uint8", "int8", "uint16", "int16", "uint32", "int32", "uint64", "int64", "float16", "float32", "float64"];
  const DTYPE_SIZE = [0, 1, 1, 2, 2, 4, 4, 8, 8, 2, 4, 8];
  const UINT8 = 1, FLOAT32 = 10;
  const kHeaderSize = 12 + 2 + 4;
  const kMinFieldEntry = 13;  // name length, an empty name, ndim, dtype, offset

  function parseTensor(bytes, where) {
    const size = bytes.length;
    if (size < kHeaderSize) throw new InputError(`${where}: not a tensor file: ${size} bytes, the header alone is ${kHeaderSize} (truncated?)`);
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    let pos = 0;
    const take = (n, what) => {
      if (size - pos < n) throw new InputError(`${where}: truncated file: ${what} at byte ${pos} runs past the end (${size} bytes)`);
      const at = pos;
      pos += n;
      return at;
    };
    const u8 = (what) => dv.getUint8(take(1, what));
    const u16 = (what) => dv.getUint16(take(2, what), true);
    const u32 = (what) => dv.getUint32(take(4, what), true);
    const u64 = (what) => dv.getBigUint64(take(8, what), true);
    const str = (n, what) => {
      if (size - pos < n) throw new InputError(`${where}: truncated file: ${what} (${n} bytes at byte ${pos}) runs past the end (${size} bytes)`);
      pos += n;
      return bytes.subarray(pos - n, pos);
    };
    const magic = str(12, "the magic");
    if (String.fromCharCode(...magic) !== "tensor_file\0")
      throw new InputError(`${where}: not a tensor file: the first 12 bytes are not "tensor_file\\0" (pbrt-v4 and Mitsuba 3's magic)`);
    const major = u8("the version"), minor = u8("the version");
    if (major !== 1 || minor !== 0) throw new InputError(`${where}: tensor file version ${major}.${minor}, only 1.0 exists (pbrt-v4 bxdfs.cpp:769)`);
    const nFields = u32("the field count");
    if (nFields > Math.floor((size - kHeaderSize) / kMinFieldEntry))
      throw new InputError(`${where}: the header announces ${nFields} fields, more than the ${size} bytes of the file can hold`);
    const names = new Set(), fields = [];
    for (let i = 0; i < nFields; ++i) {
      const entry = `field table entry ${i}`;
      const nameLength = u16(`${entry}: name length`);
      const raw = str(nameLength, `${entry}: name`);
      const name = String.fromCharCode(...raw);  // one character per byte: the key of the name
      const label = `field "${escapeBytes(raw)}"`;
      const ndim = u16(`${label}: ndim`);
      const dtype = u8(`${label}: dtype`);
      const offset = u64(`${label}: offset`);
      if (dtype === 0 || dtype > 11) throw new InputError(`${where}: ${label}: unknown dtype code ${dtype} (1 to 11: uint8 ... float64)`);
      if (ndim * 8 > size - pos) throw new InputError(`${where}: truncated file: ${label} has ${ndim} dimensions, their sizes run past the end`);
      // The data must fit in the file: the shape's product checked at every step (BigInt: a shape
      // is a uint64).
      const shape = [];
      let total = BigInt(DTYPE_SIZE[dtype]), zero = false;
      for (let d = 0; d < ndim; ++d) {
        const s = u64(`${label}: shape`);
        shape.push(s);
        if (s === 0n) zero = true;
        if (!zero && s > BigInt(size) / total) throw new InputError(`${where}: ${label}: shape ${d} (${s}) needs more bytes than the file has (${size})`);
        total = zero ? 0n : total * s;
      }
      if (offset > BigInt(size) || total > BigInt(size) - offset)
        throw new InputError(`${where}: ${label}: data (${total} bytes at offset ${offset}) runs past the end of the file (${size} bytes)`);
      if (names.has(name)) throw new InputError(`${where}: ${label} appears twice in the field table`);
      names.add(name);
      const o = Number(offset);
      fields.push({ name, dtype, shape, offset: o, bytes: bytes.subarray(o, o + Number(total)) });
    }
    return { source: where, size, fields, find: (n) => fields.find((f) => f.name === n) };
  }
  const shapeString = (f) => `[${f.shape.join(", ")}]`;
  const count = (f) => f.shape.reduce((a, b) => a * b, 1n);
  const floats = (f) => new Float32Array(f.bytes.slice(0, f.bytes.length - (f.bytes.length % 4)).buffer);

  // ---- pbrt-v4's PiecewiseLinear2D tables (src/rgl/rgl_material.cpp PL2DTables::build) -----------
  function buildPL2D(input, sizeX, sizeY, params, normalize, buildCdf) {
    const t = { sizeX, sizeY, dim: params.length, paramSize: [1, 1, 1], paramStride: [0, 0, 0], paramValues: [[], [], []] };
    let slices = 1;
    for (let i = t.dim - 1; i >= 0; --i) {
      t.paramValues[i] = params[i];
      t.paramSize[i] = params[i].length;
      t.paramStride[i] = t.paramSize[i] > 1 ? slices : 0;
      slices *= t.paramSize[i];
    }
    const n = sizeX * sizeY;
    const data = new Float32Array(slices * n);
    let mcdfAll = new Float32Array(0), ccdfAll = new Float32Array(0);
    if (buildCdf) {
      mcdfAll = new Float32Array(slices * sizeY);
      ccdfAll = new Float32Array(slices * n);
      for (let slice = 0; slice < slices; ++slice) {
        const inp = input.subarray(slice * n, (slice + 1) * n);
        const mcdf = mcdfAll.subarray(slice * sizeY, (slice + 1) * sizeY);
        const ccdf = ccdfAll.subarray(slice * n, (slice + 1) * n);
        const out = data.subarray(slice * n, (slice + 1) * n);
        // sampling.h:1386-1420: sums in double, stored in float.
        for (let y = 0; y < sizeY; ++y) {
          let sum = 0, i = y * sizeX;
          ccdf[i] = 0;
          for (let x = 0; x < sizeX - 1; ++x, ++i) {
            sum += 0.5 * (inp[i] + inp[i + 1]);
            ccdf[i + 1] = sum;
          }
        }
        mcdf[0] = 0;
        let sum = 0;
        for (let y = 0; y < sizeY - 1; ++y) {
          sum += 0.5 * (ccdf[(y + 1) * sizeX - 1] + ccdf[(y + 2) * sizeX - 1]);
          mcdf[y + 1] = sum;
        }
        const normalization = f32(1 / mcdf[sizeY - 1]);
        for (let i = 0; i < n; ++i) ccdf[i] = ccdf[i] * normalization;
        for (let i = 0; i < sizeY; ++i) mcdf[i] = mcdf[i] * normalization;
        for (let i = 0; i < n; ++i) out[i] = inp[i] * normalization;
      }
    } else {
      for (let slice = 0; slice < slices; ++slice) {
        const inp = input.subarray(slice * n, (slice + 1) * n);
        const out = data.subarray(slice * n, (slice + 1) * n);
        // sampling.h:1426-1452: unnormalised, stored divided by the patch count, which evaluate()
        // multiplies back.
        let normalization = f32(1 / f32((sizeX - 1) * (sizeY - 1)));
        if (normalize) {
          let sum = 0;
          for (let y = 0; y < sizeY - 1; ++y)
            for (let x = 0, i = y * sizeX; x < sizeX - 1; ++x, ++i)
              sum += f32(0.25 * f32(f32(f32(inp[i] + inp[i + 1]) + inp[i + sizeX]) + inp[i + 1 + sizeX]));
          normalization = f32(1 / sum);
        }
        for (let k = 0; k < n; ++k) out[k] = inp[k] * normalization;
      }
    }
    // Float32Array stores round to float: each store above is the C++'s float(...) or float product.
    t.data = data;
    t.marginalCdf = mcdfAll;
    t.conditionalCdf = ccdfAll;
    return t;
  }

  // ---- spectra to linear sRGB (src/measured/spectral.cpp) ------------------------------------------
  function cie1931(l) {
    const g = (mu, lo, hi) => {
      const t = (l - mu) / (l < mu ? lo : hi);
      return Math.exp(-0.5 * t * t);
    };
    return [
      1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2),
      0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
      1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8),
    ];
  }
  // XYZ -> linear sRGB (IEC 61966-2-1), spectral.cpp kXyzToLinearSrgb.
  const XYZ_TO_SRGB = [[3.2404542, -1.5371385, -0.4985314], [-0.969266, 1.8760108, 0.041556], [0.0556434, -0.2040259, 1.0572252]];
  function spectralToRgb(lambda) {
    const n = lambda.length, w = [], white = [0, 0, 0];
    for (let j = 0; j < n; ++j) {
      const dx = 0.5 * ((j + 1 < n ? lambda[j + 1] - lambda[j] : 0) + (j > 0 ? lambda[j] - lambda[j - 1] : 0));
      const xyz = cie1931(lambda[j]).map((v) => v * dx);
      w.push(XYZ_TO_SRGB.map((r) => r[0] * xyz[0] + r[1] * xyz[1] + r[2] * xyz[2]));
      for (let c = 0; c < 3; ++c) white[c] += w[j][c];
    }
    return w.map((v) => v.map((x, c) => x / white[c]));
  }

  // ---- an RGL tensor file as a material (src/rgl/rgl_material.cpp rgl_from_tensor) ---------------
  function rglFromTensor(t) {
    const src = t.source;
    const fail = (field, problem) => {
      throw new InputError(`${src}: field "${field}": ${problem}`);
    };
    const need = (name, why) => {
      const f = t.find(name);
      if (!f) throw new InputError(`${src}: field "${name}" is missing (${why})`);
      return f;
    };
    const why = "every RGL reader requires it: pbrt-v4 bxdfs.cpp:886-895, Mitsuba 3 measured.cpp:98-106";
    const thetaI = need("theta_i", why), phiI = need("phi_i", why), ndf = need("ndf", why), sigma = need("sigma", why);
    const vndf = need("vndf", why), luminance = need("luminance", why), description = need("description", why), jacobian = need("jacobian", why);
    const spectral = !!t.find("wavelengths");
    const spectra = spectral
      ? need("spectra", 'a file with "wavelengths" is spectral (Mitsuba 3 measured.cpp:113-118)')
      : need("rgb", 'a file without "wavelengths" is an RGB file (Mitsuba 3 measured.cpp:119-124)');
    const expect = (f, dtype, ndim) => {
      if (f.dtype !== dtype) fail(f.name, `dtype ${DTYPES[f.dtype]}, expected ${DTYPES[dtype]}`);
      if (f.shape.length !== ndim) fail(f.name, `shape ${shapeString(f)} has ${f.shape.length} dimensions, expected ${ndim}`);
    };
    expect(description, UINT8, 1);
    expect(thetaI, FLOAT32, 1);
    expect(phiI, FLOAT32, 1);
    expect(ndf, FLOAT32, 2);
    expect(sigma, FLOAT32, 2);
    expect(vndf, FLOAT32, 4);
    expect(luminance, FLOAT32, 4);
    expect(spectra, FLOAT32, 5);
    expect(jacobian, UINT8, 1);
    const wavelengths = t.find("wavelengths");
    if (spectral) expect(wavelengths, FLOAT32, 1);
    const nPhi = phiI.shape[0], nTheta = thetaI.shape[0], nLambda = spectral ? wavelengths.shape[0] : 3n;
    const shapeIs = (f, dims, expected) =>
      dims.forEach((s, d) => {
        if (s !== 0n && f.shape[d] !== s) fail(f.name, `shape ${shapeString(f)}, expected ${expected} (phi_i has ${nPhi}, theta_i ${nTheta})`);
      });
    shapeIs(vndf, [nPhi, nTheta, 0n, 0n], "[phi_i, theta_i, *, *]");
    shapeIs(luminance, [nPhi, nTheta, 0n, 0n], "[phi_i, theta_i, n, n]");
    shapeIs(spectra, [nPhi, nTheta, nLambda, 0n, 0n], spectral ? "[phi_i, theta_i, wavelengths, n, n]" : "[phi_i, theta_i, 3, n, n]");
    if (luminance.shape[2] !== luminance.shape[3]) fail("luminance", `shape ${shapeString(luminance)}: the last two sizes must be equal (pbrt-v4 bxdfs.cpp:915)`);
    if (spectra.shape[3] !== spectra.shape[4]) fail(spectra.name, `shape ${shapeString(spectra)}: the last two sizes must be equal (pbrt-v4 bxdfs.cpp:921)`);
    if (luminance.shape[2] !== spectra.shape[3])
      fail("luminance", `shape ${shapeString(luminance)}: its grid must be the ${spectra.name} grid (${shapeString(spectra)})`);
    if (jacobian.shape[0] !== 1n) fail("jacobian", `shape ${shapeString(jacobian)}, expected [1]`);
    if (jacobian.bytes[0] !== 1)
      fail("jacobian",
        "value 0: pbrt-v4 always applies ndf / (4 sigma) (bxdfs.cpp:1048-1049), Mitsuba 3 only when jacobian is 1 " +
          "(measured.cpp:364-366); the two renderers disagree on such a file, aniso reads only jacobian = 1");
    if (nPhi < 1n || nTheta < 1n) fail(nPhi < 1n ? "phi_i" : "theta_i", "empty (at least 1 value expected)");
    if (spectral && nLambda < 2n) fail("wavelengths", "fewer than 2 wavelengths");
    const atLeast2 = (f, a, b) => {
      if (f.shape[a] < 2n || f.shape[b] < 2n) fail(f.name, `shape ${shapeString(f)}: the 2D grid needs at least 2 x 2 points`);
    };
    atLeast2(ndf, 0, 1);
    atLeast2(sigma, 0, 1);
    atLeast2(vndf, 2, 3);
    atLeast2(luminance, 2, 3);
    for (const f of [ndf, sigma, vndf, luminance, spectra]) if (count(f) >= 2n ** 31n) fail(f.name, `shape ${shapeString(f)}: more than 2^31 values`);

    const d = { source: src, spectral, notes: [] };
    d.thetaI = floats(thetaI);
    d.phiI = floats(phiI);
    const kPiF = f32(Math.PI);
    const increasing = (name, v, lo, hi, range) => {
      for (let i = 0; i < v.length; ++i) {
        if (!Number.isFinite(v[i]) || v[i] < lo || v[i] > hi) fail(name, `value ${fmtF(v[i])} at index ${i} outside ${range}`);
        if (i && !(v[i] > v[i - 1])) fail(name, `values not strictly increasing at index ${i} (${fmtF(v[i])} after ${fmtF(v[i - 1])})`);
      }
    };
    increasing("theta_i", d.thetaI, 0, f32(f32(kPiF / 2) + f32(1e-5)), "[0, pi/2]");
    increasing("phi_i", d.phiI, f32(-kPiF - f32(1e-5)), f32(kPiF + f32(1e-5)), "[-pi, pi]");
    d.isotropic = nPhi <= 2n;
    if (!d.isotropic) {
      const span = f32(d.phiI[d.phiI.length - 1] - d.phiI[0]);
      const q = f32(f32(2 * kPiF) / span);
      // std::rint: to the nearest integer, halves to even.
      let reduction = Math.round(q);
      if (Math.abs(q % 1) === 0.5 && reduction % 2 !== 0) reduction -= 1;
      if (reduction !== 1)
        fail("phi_i", `covers ${fmtG(f32(span / f32(2 * kPiF)), 4)} of 2 pi (reduction ${reduction}): pbrt-v4 reads only a full circle, [-pi, pi] (bxdfs.cpp:943-947)`);
    }
    if (spectral) {
      d.wavelengths = floats(wavelengths);
      increasing("wavelengths", d.wavelengths, 1, 1e5, "[1, 1e5] nm");
    }
    const changed = new Set();
    const ndfV = floats(ndf), sigmaV = floats(sigma), vndfV = floats(vndf), lumV = floats(luminance);
    const specV = floats(spectra);
    // Rounding noise of the densities read as 0, one note per field (rgl_material.h kRoundingNoiseUlps).
    const noiseBound = (v) => {
      let largest = 0;
      for (const x of v) if (Number.isFinite(x)) largest = Math.max(largest, Math.abs(x));
      return L.rgl.rounding_noise_ulps * 2 ** -23 * largest;
    };
    for (const [name, v] of [["ndf", ndfV], ["sigma", sigmaV], ["vndf", vndfV], ["luminance", lumV]]) {
      const bound = noiseBound(v);
      let n = 0, mostAt = 0, most = 0;
      for (let i = 0; i < v.length; ++i)
        if (v[i] < 0 && v[i] >= -bound) {
          if (v[i] < most) (most = v[i]), (mostAt = i);
          v[i] = 0;
          ++n;
        }
      if (n) {
        d.notes.push(
          `${src}: field "${name}": ${n} negative value${n === 1 ? "" : "s"} read as 0 (float rounding of 0: at most ${fmtG(L.rgl.rounding_noise_ulps)} x FLT_EPSILON x the table's ` +
            `largest value, ${fmtG(bound, 3)}; the most negative ${fmtG(most, 6)} at flat index ${mostAt})`);
        changed.add(name);
      }
    }
    const maxValue = L.rgl.max_table_value;
    const finiteNonNegative = (name, v) => {
      for (let i = 0; i < v.length; ++i)
        if (!Number.isFinite(v[i]) || v[i] < 0 || v[i] > maxValue)
          fail(name, `value ${fmtF(v[i])} at flat index ${i} (finite, in [0, ${fmtG(maxValue)}] expected${
            v[i] < 0 ? `; negatives down to ${fmtG(-noiseBound(v), 3)}, float rounding of 0 against the table's largest value, are read as 0` : ""})`);
    };
    finiteNonNegative("ndf", ndfV);
    finiteNonNegative("sigma", sigmaV);
    finiteNonNegative("vndf", vndfV);
    finiteNonNegative("luminance", lumV);
    for (let i = 0; i < specV.length; ++i)
      if (!Number.isFinite(specV[i]) || Math.abs(specV[i]) > maxValue)
        fail(spectra.name, `value ${fmtF(specV[i])} at flat index ${i} (finite, magnitude <= ${fmtG(maxValue)} expected)`);
    // sigma raised to its floor (f divides by it), with a note.
    {
      const minSigma = L.rgl.min_sigma;
      let raised = 0, first = 0, lowest = minSigma;
      for (let i = 0; i < sigmaV.length; ++i)
        if (sigmaV[i] < minSigma) {
          if (raised++ === 0) first = i;
          lowest = Math.min(lowest, sigmaV[i]);
          sigmaV[i] = minSigma;
        }
      if (raised) {
        changed.add("sigma");
        d.notes.push(
          `${src}: field "sigma": ${raised} value${raised === 1 ? "" : "s"} below ${fmtG(minSigma)} (the lowest ${fmtG(lowest)}, the first at flat index ` +
            `${first}) read as ${fmtG(minSigma)}: f divides by sigma, the renderers would give an infinite f there`);
      }
    }
    // Every vndf and luminance slice is normalised by its sum (sampling.h:1404-1405).
    const nThetaN = Number(nTheta);
    const positiveSlices = (name, v, perSlice) => {
      for (let s = 0; s * perSlice < v.length; ++s) {
        let sum = 0;
        for (let k = 0; k < perSlice; ++k) sum += v[s * perSlice + k];
        if (!(sum > 1e-20))
          fail(name, `slice (phi_i ${Math.floor(s / nThetaN)}, theta_i ${s % nThetaN}) is all zero (sum ${fmtG(sum)}): its density cannot be normalised`);
      }
    };
    positiveSlices("vndf", vndfV, Number(vndf.shape[2] * vndf.shape[3]));
    positiveSlices("luminance", lumV, Number(luminance.shape[2] * luminance.shape[3]));
    d.changed = [...changed];

    // bxdfs.cpp:950-985: the same constructors and arguments.
    const angles = [Array.from(d.phiI), Array.from(d.thetaI)];
    const N = (x) => Number(x);
    d.ndf = buildPL2D(ndfV, N(ndf.shape[1]), N(ndf.shape[0]), [], false, false);
    d.sigma = buildPL2D(sigmaV, N(sigma.shape[1]), N(sigma.shape[0]), [], false, false);
    d.vndf = buildPL2D(vndfV, N(vndf.shape[3]), N(vndf.shape[2]), angles, true, true);
    d.luminance = buildPL2D(lumV, N(luminance.shape[3]), N(luminance.shape[2]), angles, true, true);
    const n = N(spectra.shape[3]), plane = n * n;
    let rgbV = specV;
    if (spectral) {
      // Reduced to linear sRGB per grid point (rgl_material.cpp: the interpolant is linear in the table).
      const w = spectralToRgb(Array.from(d.wavelengths));
      const slices = N(nPhi * nTheta), nl = N(nLambda);
      rgbV = new Float32Array(slices * 3 * plane);
      for (let s = 0; s < slices; ++s)
        for (let j = 0; j < nl; ++j) {
          const inp = specV.subarray((s * nl + j) * plane);
          for (let c = 0; c < 3; ++c) {
            const wc = f32(w[j][c]), base = (s * 3 + c) * plane;
            for (let k = 0; k < plane; ++k) rgbV[base + k] = rgbV[base + k] + f32(wc * inp[k]);
          }
        }
    }
    d.rgb = buildPL2D(rgbV, n, n, [angles[0], angles[1], [0, 1, 2]], false, false);
    d.grids = { theta_i: N(nTheta), phi_i: N(nPhi), ndf: [N(ndf.shape[0]), N(ndf.shape[1])], vndf: [N(vndf.shape[2]), N(vndf.shape[3])], colour: n };
    d.description = escapeBytes(description.bytes);
    return d;
  }

  // ---- the tables texture (src/gl/glsl_material.cpp glsl_tables; rgl.glsl, measured.glsl) -------
  // A growing list of float arrays with their offsets, flattened once at the end.
  function parts(head) {
    const list = [head];
    let size = head.length;
    return {
      append(v) {
        const at = size;
        list.push(v);
        size += v.length;
        return at;
      },
      size: () => size,
      flat() {
        const out = new Float32Array(size);
        let at = 0;
        for (const v of list) {
          out.set(v, at);
          at += v.length;
        }
        return out;
      },
    };
  }
  // The RGL part (rgl.glsl): a 96-float header, [0] 1, [1] isotropic, at 16 + 16 k the PL2D
  // headers of ndf, sigma, vndf, luminance, rgb (sizes, strides, then the offsets of the parameter
  // grids, data, marginal and conditional cdfs; 0 for an empty table).
  function rglTables(d) {
    const head = new Float32Array(96);
    head[0] = 1;
    head[1] = d.isotropic ? 1 : 0;
    const p = parts(head);
    [d.ndf, d.sigma, d.vndf, d.luminance, d.rgb].forEach((t, k) => {
      const h = 16 + 16 * k;
      head.set([t.sizeX, t.sizeY, t.dim, ...t.paramSize, ...t.paramStride], h);
      for (let i = 0; i < 3; ++i) {
        const at = p.append(t.paramValues[i]);
        head[h + 9 + i] = t.paramValues[i].length ? at : 0;
      }
      [t.data, t.marginalCdf, t.conditionalCdf].forEach((v, i) => {
        const at = p.append(v);
        head[h + 12 + i] = v.length ? at : 0;
      });
    });
    return p;
  }

  // ---- MERL tables (src/measured/merl.cpp read_merl) ------------------------------------------------
  const ML = L.merl, kBins = ML.theta_h * ML.theta_d * ML.phi_d;
  const CHANNEL = ["R", "G", "B"];
  function describeValue(n) {
    const channel = Math.floor(n / kBins), k = n % kBins;
    return `channel ${CHANNEL[channel]}, bin (theta_h ${Math.floor(k / (ML.phi_d * ML.theta_d))}, theta_d ${Math.floor(k / ML.phi_d) % ML.theta_d}, phi_d ${k % ML.phi_d})`;
  }
  // bytes: the file's first bytes (at least file_bytes of them when it has that many); size: its size.
  function readMerl(bytes, size, where) {
    const fail = (offset, what) => {
      throw new InputError(`${where}: byte offset ${offset}: ${what}`);
    };
    const headerRead = Math.min(size, 12);
    if (headerRead === 0)
      fail(0, `empty file; a MERL .binary file is ${ML.file_bytes} bytes (a 12-byte header, then 3 x 90 x 90 x 180 doubles)`);
    if (headerRead < 12) fail(headerRead, `truncated header: the file ends after ${headerRead} bytes, the header has 12 (three int32: 90 90 180)`);
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    const dims = [0, 4, 8].map((o) => dv.getInt32(o, true));
    const expected = [ML.theta_h, ML.theta_d, ML.phi_d], dimName = ["theta_h", "theta_d", "phi_d"];
    for (let i = 0; i < 3; ++i)
      if (dims[i] !== expected[i])
        fail(4 * i, `header: ${dimName[i]} resolution ${dims[i]}, expected ${expected[i]} (a MERL .binary header is the int32s 90 90 180; got ${dims.join(" ")})`);
    const want = 3 * kBins * 8, got = Math.min(size - 12, want);
    if (got < want)
      fail(12 + got, `truncated: the file ends inside value ${Math.floor(got / 8)} of ${3 * kBins} (${describeValue(Math.floor(got / 8))}); a MERL .binary file is ${ML.file_bytes} bytes`);
    if (size > ML.file_bytes) fail(ML.file_bytes, `trailing data: the file is ${size} bytes, a MERL .binary file ${ML.file_bytes} (wrong file, or not the 90 x 90 x 180 layout)`);
    const table = new Float64Array(bytes.slice(12, 12 + want).buffer);
    for (let n = 0; n < table.length; ++n) {
      const raw = table[n];
      if (!Number.isFinite(raw))
        fail(12 + 8 * n, `${Number.isNaN(raw) ? "NaN" : "infinite value"} (${describeValue(n)}): expected a finite number (negative marks a missing sample)`);
      if (raw > ML.max_stored) fail(12 + 8 * n, `${fmtG(raw)} (${describeValue(n)}): above ${fmtG(ML.max_stored)}, no measured reflectance (a corrupt file?)`);
      table[n] = raw * ML.scale[Math.floor(n / kBins)];
    }
    return table;
  }

  // MERL's bin of (wi, wo) in double (include/aniso/brdf/measured.h merl_bin, merl_lookup).
  const kPiOver2 = Math.PI / 2;
  function merlIndex(wi, wo) {
    const sx = wi[0] + wo[0], sy = wi[1] + wo[1], sz = wi[2] + wo[2];
    const inv = 1 / Math.sqrt(sx * sx + sy * sy + sz * sz);  // glm::normalize: v * inversesqrt(dot(v, v))
    const hx = sx * inv, hy = sy * inv, hz = sz * inv;
    const sinH = Math.sqrt(hx * hx + hy * hy);
    const thetaH = Math.atan2(sinH, hz);
    const cp = sinH > 0 ? hx / sinH : 1, sp = sinH > 0 ? hy / sinH : 0;
    const x1 = wi[0] * cp + wi[1] * sp, y1 = -wi[0] * sp + wi[1] * cp, z1 = wi[2];
    const ct = hz, st = sinH;
    const dx = x1 * ct - z1 * st, dy = y1, dz = x1 * st + z1 * ct;
    const thetaD = Math.atan2(Math.sqrt(dx * dx + dy * dy), dz);
    let phiD = Math.atan2(dy, dx);
    const clamp = (i, n) => (i < 0 ? 0 : i >= n ? n - 1 : i);
    const ih = thetaH > 0 ? clamp(Math.trunc(Math.sqrt(thetaH / kPiOver2) * ML.theta_h), ML.theta_h) : 0;
    const id = clamp(Math.trunc((thetaD / kPiOver2) * ML.theta_d), ML.theta_d);
    if (phiD < 0) phiD += Math.PI;
    const ip = clamp(Math.trunc((phiD / Math.PI) * ML.phi_d), ML.phi_d);
    return ip + ML.phi_d * (id + ML.theta_d * ih);
  }
  const kHorizon = 1e-12;  // HorizonCos<double> (include/aniso/core/math.h)

  // The sampling tables (src/measured/measured.cpp make_measured).
  function makeMeasured(table) {
    const H = ML.theta_h, O = ML.theta_o_bins, P = ML.phi_h_bins, S = 2;
    const vEdges = new Float64Array(H + 1);
    for (let i = 0; i <= H; ++i) {
      const u = i / H, theta = (u * u * Math.PI) / 2, s = Math.sin(theta / 2);
      vEdges[i] = 2 * s * s;
    }
    const cellSolidAngle = new Float64Array(H);
    for (let i = 0; i < H; ++i) cellSolidAngle[i] = ((vEdges[i + 1] - vEdges[i]) * 2 * Math.PI) / P;
    const marginal = new Float64Array(O * (H + 1)), conditional = new Float64Array(O * H * (P + 1));
    const normalise = (cdf, n) => {
      const total = cdf[n];
      for (let k = 0; k <= n; ++k) cdf[k] = total > 0 ? cdf[k] / total : k / n;
      cdf[n] = 1;
    };
    const wi = [0, 0, 0];
    for (let o = 0; o < O; ++o) {
      const thetaO = ((o + 0.5) / O) * (Math.PI / 2);
      const wo = [Math.sin(thetaO), 0, Math.cos(thetaO)];
      const mcdf = marginal.subarray(o * (H + 1), (o + 1) * (H + 1));
      for (let i = 0; i < H; ++i) {
        const ccdf = conditional.subarray((o * H + i) * (P + 1), (o * H + i + 1) * (P + 1));
        for (let j = 0; j < P; ++j) {
          let sum = 0;
          for (let a = 0; a < S; ++a)
            for (let b = 0; b < S; ++b) {
              const v = vEdges[i] + ((vEdges[i + 1] - vEdges[i]) * (a + 0.5)) / S;
              const sinH = Math.sqrt(Math.max(0, v * (2 - v))), phi = ((j + (b + 0.5) / S) * 2 * Math.PI) / P;
              const hx = sinH * Math.cos(phi), hy = sinH * Math.sin(phi), hz = 1 - v;
              const woh = wo[0] * hx + wo[1] * hy + wo[2] * hz;
              if (!(woh > 0)) continue;
              const k2 = 2 * woh;
              wi[0] = k2 * hx - wo[0];
              wi[1] = k2 * hy - wo[1];
              wi[2] = k2 * hz - wo[2];
              if (!(wi[2] > kHorizon) || !(wo[2] > kHorizon)) continue;
              const k = merlIndex(wi, wo);
              const r = table[k], g = table[k + kBins], bl = table[k + 2 * kBins];
              const avg = r < 0 || g < 0 || bl < 0 ? 0 : (r + g + bl) / 3;
              sum += avg * wi[2] * 4 * woh;
            }
          ccdf[j + 1] = ccdf[j] + (sum / (S * S)) * cellSolidAngle[i];
        }
        mcdf[i + 1] = mcdf[i] + ccdf[P];
        normalise(ccdf, P);
      }
      normalise(mcdf, H);
    }
    return { vEdges, cellSolidAngle, marginal, conditional };
  }

  // The MERL part (measured.glsl): a 16-float header, [0] 2, [1] theta_o_bins, [2] phi_h_bins,
  // [3] uniform_fraction, [4..8] the offsets of the bins, the marginal and conditional cdfs,
  // v_edges and the cell densities (P(cell) / solid angle, in double as MeasuredT::table_pdf).
  function merlTables(table, s) {
    const H = ML.theta_h, O = ML.theta_o_bins, P = ML.phi_h_bins;
    const head = new Float32Array(16);
    head[0] = 2;
    head[1] = O;
    head[2] = P;
    head[3] = ML.uniform_fraction;
    const p = parts(head);
    head[4] = p.append(table);  // Float32Array.set rounds each double to float, as float(x)
    head[5] = p.append(s.marginal);
    head[6] = p.append(s.conditional);
    head[7] = p.append(s.vEdges);
    const density = new Float32Array(O * H * P);
    for (let o = 0, q = 0; o < O; ++o)
      for (let i = 0; i < H; ++i) {
        const m = o * (H + 1), c = (o * H + i) * (P + 1);
        for (let j = 0; j < P; ++j)
          density[q++] = ((s.marginal[m + i + 1] - s.marginal[m + i]) * (s.conditional[c + j + 1] - s.conditional[c + j])) / s.cellSolidAngle[i];
      }
    head[8] = p.append(density);
    return p;
  }

  // ---- a file as a material ---------------------------------------------------------------------
  const isRgl = (name) => /\.bsdf$/i.test(name);  // rgl::is_rgl_file_name
  const isMerl = (name) => /\.binary$/i.test(name);  // is_measured_file_name
  // How many of a file's bytes the reader needs: a MERL reader stops after its size (trailing
  // data is an error without reading it).
  const bytesNeeded = (name, size) => (isMerl(name) ? Math.min(size, ML.file_bytes) : size);

  // name: the file's name (the messages' prefix, as the CLI's path); bytes: its first
  // bytesNeeded(name, size) bytes; size: its size. Returns {model, tables (Float32Array), notes,
  // summary}; an InputError with the C++ reader's message for a bad file.
  function readMeasured(name, bytes, size) {
    if (!littleEndian) throw new InputError(`${name}: this browser is big-endian; tensor and MERL files are little-endian`);
    let model, p, notes = [], summary;
    if (isRgl(name)) {
      if (size > L.rgl.max_file_bytes)
        throw new InputError(`${name}: ${size} bytes: larger than ${L.rgl.max_file_text}, the limit for an RGL tensor file (.bsdf) (docs/cli.md, "Size limits")`);
      const d = rglFromTensor(parseTensor(bytes, name));
      model = "rgl";
      p = rglTables(d);
      notes = d.notes;
      const g = d.grids;
      summary = `RGL tensor file, ${d.spectral ? `spectral (${d.wavelengths.length} wavelengths)` : "RGB"}, ${d.isotropic ? "isotropic" : "anisotropic"}; ` +
        `theta_i ${g.theta_i}, phi_i ${g.phi_i}, ndf ${g.ndf.join("x")}, vndf ${g.vndf.join("x")}, colour ${g.colour}x${g.colour}; ${d.description}`;
    } else if (isMerl(name)) {
      const table = readMerl(bytes, size, name);
      let missing = 0;
      for (let k = 0; k < kBins; ++k) missing += table[k] < 0 || table[k + kBins] < 0 || table[k + 2 * kBins] < 0 ? 1 : 0;
      model = "measured";
      p = merlTables(table, makeMeasured(table));
      summary = `MERL table, ${missing} missing bins`;
    } else throw new InputError(`${name}: not a measured file (expected .bsdf, an RGL tensor file, or .binary, a MERL table)`);
    if (p.size() > L.tables.max_floats)
      throw new InputError(`${name}: the tables need ${p.size()} floats, more than the ${L.tables.max_floats} a tables texture addresses (docs/glsl.md)`);
    return { model, tables: p.flat(), notes, summary };
  }

  global.AnisoMeasured = { readMeasured, bytesNeeded, isMeasuredFile: (n) => isRgl(n) || isMerl(n), fmtShortest, escapeBytes };
})(typeof window !== "undefined" ? window : globalThis);

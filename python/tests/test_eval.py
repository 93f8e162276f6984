"""eval / pdf / sample / albedo: equal to the CLI's numbers and to the C++ batch path's, for any
layout and dtype of the input; errors name the argument and the expected shape."""
import json
import subprocess
import threading
import time

import numpy as np
import pytest

import aniso
from conftest import BATCH_EVAL_CPP, native_env, random_pairs, run_cli

MATERIALS = ["matte-steel", "brushed-gold", "ngan/ward/nickel", "clay",
             '{"model": "ward", "kd": 0.1, "ks": [0.5, 0.4, 0.3], "alpha_x": 0.05, "alpha_y": 0.3, "form": "angle"}',
             '{"model": "ashikhmin-shirley", "n_u": 10, "n_v": 1000}',
             '{"model": "ggx", "alpha_x": 0.05, "alpha_y": 0.4}']


def cli_eval(material, wi, wo):
    lines = "".join(" ".join(repr(float(v)) for v in (*a, *b)) + "\n" for a, b in zip(wi, wo))
    rc, out, err = run_cli("eval", "--material", material, stdin=lines)
    assert rc == 0, err
    return np.loadtxt(out.splitlines(), ndmin=2)


@pytest.mark.parametrize("material", MATERIALS)
def test_eval_and_pdf_equal_the_cli(material):
    # 600 pairs: below the CLI's batch threshold (1024), so the CLI runs its scalar loop in double;
    # it prints 9 significant digits: rtol 1e-8 covers the rounding of the printed numbers and the
    # SIMD twins' 1e-14 (docs/performance.md).
    wi, wo = random_pairs(600, seed=11, grazing=True)
    m = aniso.Material(material)
    ref = cli_eval(material, wi, wo)
    np.testing.assert_allclose(m.eval(wi, wo), ref[:, :3], rtol=1e-8, atol=1e-300)
    np.testing.assert_allclose(m.pdf(wi, wo), ref[:, 3], rtol=1e-8, atol=1e-300)


@pytest.mark.parametrize("material", MATERIALS[:4])
def test_eval_and_pdf_equal_the_cpp_batch_path_bit_for_bit(material, tmp):
    # The same pairs through batch::evaluate / batch::pdf from C++ (python/bench/batch_eval_cpp.cpp):
    # the chunking and transposition of the bindings change nothing, in float and in double.
    n = 10_000  # more than two chunks, the last one partial
    wi, wo = random_pairs(n, seed=5, grazing=True)
    pairs = tmp / "pairs.bin"
    np.concatenate([wi, wo], axis=1).tofile(pairs)
    out = tmp / "out.bin"
    subprocess.run([BATCH_EVAL_CPP, "dump", str(pairs), material, str(out)], check=True, timeout=60, env=native_env())
    raw = out.read_bytes()
    f32 = np.frombuffer(raw, np.float32, count=4 * n)
    f64 = np.frombuffer(raw, np.float64, offset=16 * n)
    m = aniso.Material(material)
    wi32, wo32 = wi.astype(np.float32), wo.astype(np.float32)
    np.testing.assert_array_equal(m.eval(wi32, wo32), f32[:3 * n].reshape(n, 3))
    np.testing.assert_array_equal(m.pdf(wi32, wo32), f32[3 * n:])
    np.testing.assert_array_equal(m.eval(wi, wo), f64[:3 * n].reshape(n, 3))
    np.testing.assert_array_equal(m.pdf(wi, wo), f64[3 * n:])


def test_dtypes_layouts_and_broadcasting():
    m = aniso.Material("brushed-gold")
    wi, wo = random_pairs(5000, seed=3)
    ref = m.eval(wi, wo)
    assert ref.dtype == np.float64 and ref.shape == (5000, 3) and ref.flags.c_contiguous
    f32 = m.eval(wi.astype(np.float32), wo.astype(np.float32))
    assert f32.dtype == np.float32
    np.testing.assert_allclose(f32, ref, rtol=2e-4, atol=1e-6)
    # Mixed precision computes in double.
    assert m.eval(wi.astype(np.float32), wo).dtype == np.float64
    # Non-contiguous inputs: Fortran order, a strided slice, a reversed view, a transposed (3, N).
    np.testing.assert_array_equal(m.eval(np.asfortranarray(wi), wo), ref)
    big = np.zeros((5000, 7))
    big[:, 2:5] = wi
    np.testing.assert_array_equal(m.eval(big[:, 2:5], wo), ref)
    np.testing.assert_array_equal(m.eval(wi[::-1], wo[::-1]), ref[::-1])
    np.testing.assert_array_equal(m.eval(np.ascontiguousarray(wi.T).T, wo), ref)
    np.testing.assert_array_equal(m.eval(np.repeat(wi, 2, axis=0)[::2], wo), ref)
    np.testing.assert_array_equal(m.pdf(np.asfortranarray(wi), wo[::1]), m.pdf(wi, wo))
    # (3,) against (N, 3): the one direction is used for every row; (3,) with (3,) gives (3,).
    one = wi[17]
    np.testing.assert_array_equal(m.eval(one, wo), m.eval(np.tile(one, (5000, 1)), wo))
    np.testing.assert_array_equal(m.eval(wo, one), m.eval(wo, np.tile(one, (5000, 1))))
    assert m.eval(one, wo[0]).shape == (3,)
    np.testing.assert_array_equal(m.eval(one, wo[0]), ref[17] if False else m.eval(one[None], wo[:1])[0])
    assert np.ndim(m.pdf(one, wo[0])) == 0
    # Lists and integer arrays are read as float64.
    assert m.eval([0, 0, 1], [0.6, 0, 0.8]).dtype == np.float64
    np.testing.assert_array_equal(m.eval(np.array([0, 0, 1]), [0.6, 0, 0.8]), m.eval([0.0, 0.0, 1.0], [0.6, 0, 0.8]))
    # Empty input gives empty output.
    assert m.eval(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0, 3)
    assert m.pdf(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)


def test_nan_and_inf_rows():
    m = aniso.Material("matte-steel")
    wi, wo = random_pairs(100, seed=4)
    wi[3, 1] = np.nan
    wo[7, 2] = np.inf
    wi[9] = [-np.inf, np.nan, 0.0]
    f, p = m.eval(wi, wo), m.pdf(wi, wo)
    bad = [3, 7, 9]
    assert np.isnan(f[bad]).all() and np.isnan(p[bad]).all()
    good = np.setdiff1d(np.arange(100), bad)
    assert np.isfinite(f[good]).all() and np.isfinite(p[good]).all()
    wi32 = wi.astype(np.float32)
    assert np.isnan(m.eval(wi32, wo.astype(np.float32))[bad]).all()
    # Below the horizon is not an error: f = pdf = 0 (docs/conventions.md).
    assert (m.eval([0, 0, -1], [0, 0, 1]) == 0).all()


@pytest.mark.parametrize("bad, message", [
    (np.zeros((4, 2)), r"wi: expected an array of shape \(N, 3\) or \(3,\), got shape \(4, 2\)"),
    (np.zeros(4), r"wi: expected an array of shape \(N, 3\) or \(3,\), got shape \(4,\)"),
    (np.zeros((2, 3, 3)), r"wi: expected an array of shape \(N, 3\) or \(3,\), got shape \(2, 3, 3\)"),
    (np.float64(1.0), r"wi: expected an array of shape \(N, 3\) or \(3,\), got shape \(\)"),
    (np.zeros((4, 3), np.complex128), r"wi: expected .* of float32 or float64 \(or integers\), got dtype complex128"),
    (np.array([["a", "b", "c"]]), r"wi: expected .* got dtype <U1"),
    (np.zeros((4, 3), bool), r"wi: expected .* got dtype bool"),
    ([[0, 0, 1], [0, 1]], r"wi: expected an array of shape \(N, 3\) or \(3,\), got list"),
])
def test_bad_arrays_raise_value_errors_naming_the_argument(bad, message):
    m = aniso.Material("clay")
    with pytest.raises(ValueError, match=message):
        m.eval(bad, [0, 0, 1])
    with pytest.raises(ValueError, match=message.replace("wi:", "wi:")):
        m.pdf(bad, [0, 0, 1])
    with pytest.raises(ValueError, match=message.replace("wi:", "wo:")):
        m.eval([0, 0, 1], bad)


def test_row_counts_must_agree():
    m = aniso.Material("clay")
    with pytest.raises(ValueError, match=r"wi and wo: expected the same number of rows N .* got 5 and 7"):
        m.eval(np.zeros((5, 3)), np.zeros((7, 3)))
    with pytest.raises(ValueError, match=r"wo and u: .* got 5 and 4"):
        m.sample(np.zeros((5, 3)), np.zeros((4, 3)))


@pytest.mark.parametrize("material", ["matte-steel", "brushed-gold", "ngan/ward/nickel"])
def test_sample_is_consistent_with_eval_and_pdf(material):
    m = aniso.Material(material)
    rng = np.random.default_rng(8)
    n = 20_000
    wo = aniso.direction(np.radians(35.0), 0.3)
    u = rng.random((n, 3))
    wi, weight, pdf = m.sample(wo, u)
    assert wi.shape == (n, 3) and weight.shape == (n, 3) and pdf.shape == (n,)
    valid = pdf > 0
    assert valid.mean() > 0.5
    assert (wi[~valid] == 0).all() and (weight[~valid] == 0).all()
    np.testing.assert_allclose(np.linalg.norm(wi[valid], axis=1), 1.0, rtol=1e-9)
    np.testing.assert_allclose(pdf[valid], m.pdf(wi[valid], wo), rtol=1e-9)
    f = m.eval(wi[valid], wo)
    np.testing.assert_allclose(weight[valid], f * wi[valid, 2:3] / pdf[valid, None], rtol=1e-9)
    # The mean weight estimates the albedo: agree with albedo() within 5 standard errors.
    mean = weight.mean(axis=0)
    sem = weight.std(axis=0) / np.sqrt(n)
    ref = m.albedo(np.radians(35.0), 0.3, samples=1 << 18)
    assert (np.abs(mean - ref) < 5 * sem + 1e-3).all(), (mean, ref, sem)
    # float32 gives the same samples to float precision.
    wi32, w32, p32 = m.sample(wo.astype(np.float32), u.astype(np.float32))
    assert wi32.dtype == np.float32
    same = (p32 > 0) == valid
    assert same.mean() > 0.999
    np.testing.assert_allclose(wi32[same & valid], wi[same & valid], atol=1e-4)


def test_sample_uniforms_checked_and_nan_rows():
    m = aniso.Material("clay")
    wo = np.tile([0.0, 0.0, 1.0], (10, 1))
    u = np.full((10, 3), 0.5)
    u[4, 1] = 1.5
    with pytest.raises(ValueError, match=r"u: expected uniforms in \[0, 1\), got 1.5 in row 4"):
        m.sample(wo, u)
    u[4, 1] = -0.25
    with pytest.raises(ValueError, match=r"got -0.25 in row 4"):
        m.sample(wo, u)
    u[4, 1] = 1.0  # 1 is taken as the largest number below 1
    assert np.isfinite(m.sample(wo, u)[0]).all()
    u[4, 1] = np.nan
    wi, weight, pdf = m.sample(wo, u)
    assert np.isnan(wi[4]).all() and np.isnan(pdf[4]) and np.isfinite(pdf[np.arange(10) != 4]).all()
    wi1, w1, p1 = m.sample([0, 0, 1], [0.1, 0.2, 0.3])
    assert wi1.shape == (3,) and np.ndim(p1) == 0


def test_albedo_equals_the_cli():
    for material in ["matte-steel", "brushed-gold"]:
        m = aniso.Material(material)
        rc, out, _ = run_cli("albedo", "--material", material, "--theta-deg", "30", "--phi-deg", "20", "--samples", "65536")
        assert rc == 0
        ref = np.array(out.split(), float)
        np.testing.assert_allclose(m.albedo(np.radians(30.0), np.radians(20.0), samples=65536), ref, rtol=1e-8)
    m = aniso.Material("clay")
    a = m.albedo(np.radians([0.0, 45.0, np.nan]), samples=4096)
    assert a.shape == (3, 3) and np.isnan(a[2]).all()
    mean, err = m.albedo(0.3, samples=4096, return_error=True)
    assert mean.shape == (3,) and (err > 0).all()
    with pytest.raises(ValueError, match=r"theta: expected viewing angles in \[0, pi/2\]"):
        m.albedo(2.0)
    with pytest.raises(ValueError, match=r"samples: expected a whole number in \[1, 1000000000\], got 0"):
        m.albedo(0.1, samples=0)


def test_the_gil_is_released_while_computing():
    m = aniso.Material("brushed-gold")
    wi, wo = random_pairs(1 << 20, seed=1)
    start = time.perf_counter()
    m.eval(wi, wo)
    one_call = time.perf_counter() - start
    calls = max(2, int(0.5 / max(one_call, 1e-3)))  # about half a second of work in the thread
    worker = threading.Thread(target=lambda: [m.eval(wi, wo) for _ in range(calls)])
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.002)
    worker.join()
    # With the GIL held, the main thread would get to run only between the calls.
    assert ticks > 2 * calls, (ticks, calls)


def test_out_arrays_and_column_major_layouts():
    m = aniso.Material("brushed-gold")
    wi, wo = random_pairs(9000, seed=12)
    wi[5, 0] = np.nan
    ref, pref = m.eval(wi, wo), m.pdf(wi, wo)
    for dtype in (np.float32, np.float64):
        a, b = wi.astype(dtype), wo.astype(dtype)
        want, pwant = m.eval(a, b), m.pdf(a, b)
        # Column-major inputs are read in place; a Fortran-ordered out is written in place.
        fa, fb = np.asfortranarray(a), np.asfortranarray(b)
        for order in "CF":
            out = np.empty((9000, 3), dtype, order=order)
            assert m.eval(fa, fb, out=out) is out
            np.testing.assert_array_equal(out, want)
            np.testing.assert_array_equal(m.eval(a, fb, out=out), want)
        pout = np.empty(9000, dtype)
        assert m.pdf(fa, fb, out=pout) is pout
        np.testing.assert_array_equal(pout, pwant)
        assert np.isnan(out[5]).all() and np.isnan(pout[5])
        # The transpose of a (3, N) array is column-major too.
        np.testing.assert_array_equal(m.eval(np.ascontiguousarray(a.T).T, np.ascontiguousarray(b.T).T), want)
    np.testing.assert_allclose(m.eval(wi.astype(np.float32), wo.astype(np.float32)), ref, rtol=2e-4, atol=1e-6)
    one = np.empty(3)
    assert m.eval(wi[0], wo[0], out=one) is one
    p0 = np.empty(())
    assert m.pdf(wi[1], wo[1], out=p0) is p0 and p0 == pref[1]
    with pytest.raises(ValueError, match=r"out: expected a writeable C- or Fortran-contiguous float64 array of shape \(9000, 3\)"):
        m.eval(wi, wo, out=np.empty((9000, 3), np.float32))
    with pytest.raises(ValueError, match=r"got float64 of shape \(9000, 6\)"):
        m.eval(wi, wo, out=np.empty((9000, 6)))
    with pytest.raises(ValueError, match="not contiguous"):
        m.eval(wi, wo, out=np.empty((9000, 6))[:, :3])
    ro = np.empty((9000, 3))
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        m.eval(wi, wo, out=ro)
    with pytest.raises(ValueError, match=r"shape \(9000,\)"):
        m.pdf(wi, wo, out=np.empty(10))


def test_sample_out_arrays_and_layouts():
    # Every layout eval takes, and out=, give the default call's samples bit for bit.
    n = 9000
    wi_ref, wo = random_pairs(n, seed=21)
    u = np.random.default_rng(22).random((n, 3))
    wo[5, 1] = np.nan
    u[11, 2] = np.nan
    u[12, 0] = 1.0  # taken as the largest number below 1, in every layout
    for m in [aniso.Material("brushed-gold"), aniso.Material("clay"), aniso.ggx(alpha_x=0.1, alpha_y=0.3)]:
        for dtype in (np.float64, np.float32):
            a, b = wo.astype(dtype), u.astype(dtype)
            ref = m.sample(a, b)
            assert all(r.dtype == dtype for r in ref) and ref[0].flags.c_contiguous
            assert np.isnan(ref[0][[5, 11]]).all() and np.isnan(ref[2][[5, 11]]).all()
            big = np.zeros((n, 7), dtype)
            big[:, 3:6] = b
            layouts = [(np.asfortranarray(a), np.asfortranarray(b)), (a, np.asfortranarray(b)),
                       (np.ascontiguousarray(a.T).T, big[:, 3:6]), (a[::-1].copy()[::-1], b[::-1].copy()[::-1])]
            for x, y in layouts:
                got = m.sample(x, y)
                for g, r in zip(got, ref):
                    np.testing.assert_array_equal(g, r)
            # u needing no change is read in place: the same samples without row 12's 1.0.
            b2 = b.copy()
            b2[12, 0] = 0.5
            want = m.sample(a, b2)
            for g, r in zip(m.sample(np.asfortranarray(a), np.asfortranarray(b2)), want):
                np.testing.assert_array_equal(g, r)
            for order in "CF":
                out = (np.empty((n, 3), dtype, order=order), np.empty((n, 3), dtype, order=order), np.empty(n, dtype))
                got = m.sample(np.asfortranarray(a), b, out=out)
                assert all(g is o for g, o in zip(got, out))
                for g, r in zip(got, ref):
                    np.testing.assert_array_equal(g, r)
    m = aniso.Material("gold")
    one = (np.empty(3), np.empty(3), np.empty(()))
    got = m.sample([0, 0.6, 0.8], [0.1, 0.2, 0.3], out=one)
    assert all(g is o for g, o in zip(got, one))
    ref = m.sample([0, 0.6, 0.8], [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(one[0], ref[0])
    assert one[2] == ref[2]
    with pytest.raises(ValueError, match=r"out: expected a tuple of three arrays \(wi, weight, pdf\), got ndarray"):
        m.sample(wo, u, out=np.empty((n, 3)))
    with pytest.raises(ValueError, match=r"out\[1\] \(weight\): expected a writeable C- or Fortran-contiguous float64 array of shape \(9000, 3\)"):
        m.sample(wo, u, out=(np.empty((n, 3)), np.empty((n, 3), np.float32), np.empty(n)))
    with pytest.raises(ValueError, match=r"out\[2\] \(pdf\): .* shape \(9000,\)"):
        m.sample(wo, u, out=(np.empty((n, 3)), np.empty((n, 3)), np.empty(n + 1)))


def test_unaligned_and_odd_arrays_take_the_general_path():
    # A float64 array whose data is not 8-byte aligned, and a size-1 row: the same values.
    m = aniso.Material("brushed-gold")
    wi, wo = random_pairs(1001, seed=31)
    buf = np.zeros(wi.nbytes + 4, np.uint8)
    odd = np.frombuffer(buf[4:4 + wi.nbytes], dtype=np.float64).reshape(wi.shape)
    odd[...] = wi
    assert odd.ctypes.data % 8 != 0
    np.testing.assert_array_equal(m.eval(odd, wo), m.eval(wi, wo))
    np.testing.assert_array_equal(m.pdf(odd, wo), m.pdf(wi, wo))
    np.testing.assert_array_equal(m.eval(wi[:1], wo[:1]), m.eval(wi, wo)[:1])


def test_concurrent_calls_from_threads_give_the_same_results():
    # Each oneTBB task copies its chunk into scratch arrays of its own thread: calls from several
    # Python threads at once (the GIL released) must not share them.
    m = aniso.Material("brushed-gold")
    wi, wo = random_pairs(50_000, seed=21)
    u = np.random.default_rng(2).random((50_000, 3))
    ref = m.eval(wi, wo), m.pdf(wi, wo), m.sample(wo, u)[1]
    results = [None] * 6

    def work(k):
        results[k] = m.eval(wi, wo), m.pdf(wi, wo), m.sample(wo, u)[1]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        for a, b in zip(r, ref):
            np.testing.assert_array_equal(a, b)


def test_directions_are_normalised_and_checked_as_the_cli():
    brushed = {"model": "ward", "kd": 0.05, "ks": [0.6, 0.5, 0.4], "alpha_x": 0.05, "alpha_y": 0.3,
               "normalization": "balanced"}
    m = aniso.Material(brushed)
    rc, out, err = run_cli("eval", "--material", json.dumps(brushed), stdin="6 0 8 -6 0 8\n0.6 0 0.8 -0.6 0 0.8\n")
    assert rc == 0, err
    cli = np.array([[float(x) for x in line.split()] for line in out.splitlines()])
    np.testing.assert_allclose(m.eval([6, 0, 8], [-6, 0, 8]), cli[0, :3], rtol=5e-9)
    np.testing.assert_allclose(m.pdf([6, 0, 8], [-6, 0, 8]), cli[0, 3], rtol=5e-9)
    assert abs(m.eval([6, 0, 8], [-6, 0, 8])[0] - 4.98950747) < 1e-7
    # Scaled rows among unit ones, float32 too; unit rows are read as they are.
    wi, wo = random_pairs(1000, seed=11)
    scale = np.random.default_rng(2).uniform(0.01, 100.0, (1000, 1))
    np.testing.assert_allclose(m.eval(wi * scale, wo), m.eval(wi, wo), rtol=1e-12)
    np.testing.assert_allclose(m.pdf(wi, wo / scale), m.pdf(wi, wo), rtol=1e-12)
    np.testing.assert_allclose(m.eval((wi * scale).astype(np.float32), wo.astype(np.float32)),
                               m.eval(wi.astype(np.float32), wo.astype(np.float32)), rtol=1e-4, atol=1e-6)
    ws, weight, pdf = m.sample([0, 0, 5], [0.3, 0.4, 0.5])
    np.testing.assert_array_equal(ws, m.sample([0, 0, 1], [0.3, 0.4, 0.5])[0])
    # A zero direction is an error naming its row, as the CLI's names its line.
    wi[5] = 0.0
    with pytest.raises(ValueError, match=r"wi\[5\]: expected a non-zero direction, got \(0, 0, 0\)"):
        m.eval(wi, wo)
    with pytest.raises(ValueError, match=r"^wo: expected a non-zero direction"):
        m.pdf(wo, [0, 0, 0])
    with pytest.raises(ValueError, match=r"wo: expected a non-zero direction"):
        m.sample([0.0, 0.0, 0.0], [0.3, 0.4, 0.5])
    # NaN rows stay NaN rows (not an error) even when other rows are normalised.
    wi[5] = [np.nan, 0, 1]
    wi[6] *= 3.0
    f = m.eval(wi, wo)
    assert np.isnan(f[5]).all() and np.isfinite(f[6]).all()


def test_float16_is_converted_and_long_double_refused():
    m = aniso.Material("brushed-gold")
    wi, wo = random_pairs(50, seed=5)
    h = wi.astype(np.float16)
    np.testing.assert_array_equal(m.eval(h, wo), m.eval(h.astype(np.float64), wo))
    if np.dtype(np.longdouble).itemsize > 8:
        with pytest.raises(ValueError, match=r"wi: .* got dtype float(96|128): convert it with .astype\(numpy.float64\)"):
            m.eval(wi.astype(np.longdouble), wo)
        with pytest.raises(ValueError, match=r"theta: .* dtype float(96|128)"):
            m.albedo(np.array([0.3], np.longdouble))


def test_albedo_takes_numbers_not_text():
    m = aniso.Material("clay")
    with pytest.raises(ValueError, match=r"theta: expected a number .* got str of dtype <U3"):
        m.albedo("0.3")
    with pytest.raises(ValueError, match=r"theta: expected a number"):
        m.albedo(["0.3"])
    np.testing.assert_array_equal(m.albedo(np.float16(0.25), samples=1000), m.albedo(float(np.float16(0.25)), samples=1000))

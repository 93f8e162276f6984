"""Tangent frames, direction helpers and conductor Fresnel (equal to `aniso fresnel`)."""
import numpy as np
import pytest

import aniso
from conftest import cli_error, run_cli


def test_frame_is_orthonormal_and_right_handed():
    rng = np.random.default_rng(2)
    for _ in range(50):
        n, t = rng.normal(size=3), rng.normal(size=3)
        for f in (aniso.Frame(n), aniso.Frame(n, t)):
            M = f.matrix
            np.testing.assert_allclose(M @ M.T, np.eye(3), atol=1e-12)
            np.testing.assert_allclose(np.cross(f.n, f.t), f.b, atol=1e-12)
            np.testing.assert_allclose(f.n, n / np.linalg.norm(n), atol=1e-12)
        # Gram-Schmidt: t lies in the plane of n and the given tangent, on its side.
        f = aniso.Frame(n, t)
        assert abs(np.dot(np.cross(n, t), f.t)) < 1e-12 and np.dot(f.t, t) > 0


def test_to_local_to_world_and_rotation():
    f = aniso.Frame([0, 0, 1], [1, 0, 0])
    np.testing.assert_allclose(f.t, [1, 0, 0]) and np.testing.assert_allclose(f.b, [0, 1, 0])
    w = np.random.default_rng(3).normal(size=(100, 3))
    g = aniso.Frame([0.3, -0.2, 0.9], [1, 1, 0])
    np.testing.assert_allclose(g.to_world(g.to_local(w)), w, atol=1e-12)
    np.testing.assert_allclose(g.to_local(w), w @ g.matrix.T, atol=1e-12)
    assert g.to_local(w[0]).shape == (3,)
    assert g.to_local(w.astype(np.float32)).dtype == np.float32
    # Rotating by psi turns t towards b: t' = cos psi t + sin psi b; a quarter turn gives t' = b.
    r = g.rotated(np.pi / 2)
    np.testing.assert_allclose(r.t, g.b, atol=1e-12)
    np.testing.assert_allclose(r.n, g.n)
    psi = 0.7
    np.testing.assert_allclose(g.rotated(psi).t, np.cos(psi) * g.t + np.sin(psi) * g.b, atol=1e-12)
    # A material evaluated in a rotated frame: rotating the frame by psi is rotating the
    # directions by -psi about n.
    m = aniso.Material("brushed-gold")
    wi, wo = aniso.direction(0.5, [0.1, 1.0]), aniso.direction(0.6, [2.0, 3.0])
    f0 = aniso.Frame()
    fr = f0.rotated(psi)
    np.testing.assert_allclose(m.eval(fr.to_local(wi), fr.to_local(wo)), m.eval(aniso.direction(0.5, np.array([0.1, 1.0]) - psi),
                                                                               aniso.direction(0.6, np.array([2.0, 3.0]) - psi)), rtol=1e-9)
    with pytest.raises(ValueError, match=r"n: expected a non-zero direction"):
        aniso.Frame([0, 0, 0])
    with pytest.raises(ValueError, match=r"n: expected one direction of shape \(3,\)"):
        aniso.Frame(np.zeros((2, 3)))


def test_direction_and_angles():
    w = aniso.direction(np.radians(30), np.radians(45))
    np.testing.assert_allclose(w, [0.5 * np.sqrt(0.5), 0.5 * np.sqrt(0.5), np.sqrt(3) / 2])
    theta = np.linspace(0, 1.5, 7)
    assert aniso.direction(theta, 0.0).shape == (7, 3)
    t, p = aniso.angles(aniso.direction(theta, 0.4))
    np.testing.assert_allclose(t, theta, atol=1e-12)


def test_fresnel_equals_the_cli():
    for metal in ["gold", "copper", "aluminium"]:
        for deg in [0.0, 45.0, 80.0, 89.0]:
            rc, out, _ = run_cli("fresnel", "--metal", metal, "--theta-deg", repr(deg))
            assert rc == 0
            np.testing.assert_allclose(aniso.fresnel(np.cos(np.radians(deg)), metal), np.array(out.split(), float), rtol=1e-8)
            rc, out, _ = run_cli("fresnel", "--metal", metal, "--theta-deg", repr(deg), "--schlick")
            np.testing.assert_allclose(aniso.fresnel(np.cos(np.radians(deg)), metal, schlick=True), np.array(out.split(), float), rtol=1e-8)
    rc, out, _ = run_cli("fresnel", "--eta", "0.2", "0.4", "1.4", "--k", "3.6", "2.6", "1.9", "--theta-deg", "60")
    np.testing.assert_allclose(aniso.fresnel(np.cos(np.radians(60.0)), eta=[0.2, 0.4, 1.4], k=[3.6, 2.6, 1.9]),
                               np.array(out.split(), float), rtol=1e-8)
    m = aniso.metals()
    np.testing.assert_allclose(aniso.fresnel(1.0, eta=m["gold"]["eta"], k=m["gold"]["k"]), m["gold"]["f0"])
    c = np.linspace(0, 1, 12).reshape(3, 4)
    assert aniso.fresnel(c, "gold").shape == (3, 4, 3)
    assert np.isnan(aniso.fresnel([np.nan, 1.0], "gold")[0]).all()


def test_fresnel_errors():
    expected = cli_error("fresnel", "--metal", "gld")
    with pytest.raises(ValueError) as e:
        aniso.fresnel(1.0, "gld")
    assert str(e.value) == expected.replace("--metal: ", "metal: ")
    with pytest.raises(ValueError, match=r"eta: channel 1: expected a number in \(0, 100\], got -1"):
        aniso.fresnel(1.0, eta=[1, -1, 1], k=1)
    with pytest.raises(ValueError, match="give either metal or eta and k"):
        aniso.fresnel(1.0, "gold", eta=1, k=1)
    with pytest.raises(ValueError, match="give metal=NAME"):
        aniso.fresnel(1.0)


def test_a_tangent_parallel_to_the_normal_is_an_error():
    for n, t in [([0, 0, 1], [0, 0, 3]), ([0, 0, 1], [0, 0, -1]), ([1, 1, 0], [2, 2, 1e-9]), ([0, 1, 0], [0, 0, 0])]:
        with pytest.raises(ValueError, match=r"^t: "):
            aniso.Frame(n, t)
    # Not parallel: Gram-Schmidt, t need not be unit nor perpendicular.
    f = aniso.Frame([0, 0, 2], [3, 0, 1])
    np.testing.assert_allclose(f.t, [1, 0, 0], atol=1e-15)

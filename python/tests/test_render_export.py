"""render() equals `aniso render`; export_glsl / export_brdf equal the CLI's exports."""
import json
import numpy as np
import pytest

import aniso
from conftest import SOURCE_DIR, cli_error, run_cli


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), "<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3)[::-1]  # PFM rows go bottom to top


def test_render_of_a_material_equals_the_cli(tmp):
    out = tmp / "preview.pfm"
    rc, _, err = run_cli("render", "--material", "brushed-gold", "-o", str(out), "--spp", "2", "--width", "48", "--height", "24")
    assert rc == 0, err
    img = aniso.render(material="brushed-gold", spp=2, width=48, height=24, progress=False)
    assert img.shape == (24, 48, 3) and img.dtype == np.float32
    assert np.isfinite(img).all() and img.max() > 0
    np.testing.assert_array_equal(img, read_pfm(out))
    # A Material object renders the same (its resolved keys are the same material).
    np.testing.assert_array_equal(aniso.render(material=aniso.Material("brushed-gold"), spp=2, width=48, height=24), img)


def test_render_of_a_scene_file_and_dict(tmp):
    scene = SOURCE_DIR / "examples" / "satin-ribbon.json"
    out = tmp / "scene.pfm"
    rc, _, err = run_cli("render", str(scene), "-o", str(out), "--spp", "1", "--width", "32", "--height", "32")
    assert rc == 0, err
    img = aniso.render(scene, spp=1, width=32, height=32)
    np.testing.assert_array_equal(img, read_pfm(out))
    rc, doc, _ = run_cli("render", "--material", "clay", "--print-scene")
    import json
    img2 = aniso.render(json.loads(doc), spp=1, width=32, height=16, seed=3)
    assert img2.shape == (16, 32, 3) and np.isfinite(img2).all()
    # One side alone keeps the scene's aspect ratio, as `aniso render --width` (the film is 640 x 360).
    scene_doc = json.loads(doc)
    scene_doc["film"].update(width=64, height=36)
    assert aniso.render(scene_doc, spp=1, width=32).shape == (18, 32, 3)
    assert aniso.render(scene_doc, spp=1, height=18).shape == (18, 32, 3)


def test_render_errors():
    with pytest.raises(ValueError, match=r"spp: expected a whole number in \[1, 1048576\], got 0"):
        aniso.render(material="clay", spp=0)
    with pytest.raises(ValueError, match="strategy: expected one of"):
        aniso.render(material="clay", strategy="path")
    with pytest.raises(ValueError, match="give either a scene or material="):
        aniso.render({}, material="clay")
    with pytest.raises(ValueError, match=r"scene dict: "):
        aniso.render({"camera": 3})
    expected = cli_error("render", "/nonexistent/scene.json")
    with pytest.raises(ValueError) as e:
        aniso.render("/nonexistent/scene.json")
    assert str(e.value) == expected


def test_export_glsl_and_brdf_equal_the_cli():
    for name in ["brushed-gold", "matte-steel"]:
        rc, out, _ = run_cli("export-glsl", "--material", name)
        assert rc == 0
        assert aniso.export_glsl(name) == out
        rc, out, _ = run_cli("export-glsl", "--material", name, "--full")
        assert rc == 0
        assert aniso.export_glsl(name, full=True) == out
        rc, out, _ = run_cli("export-brdf", "--material", name)
        assert aniso.export_brdf(name) == out
    src = aniso.export_glsl(aniso.Material("gold"))
    assert "aniso_f" in src and "aniso_pdf" in src
    with pytest.raises(ValueError):
        aniso.export_glsl({"model": "ward", "kd": 5})


def test_ctrl_c_stops_a_render_with_keyboard_interrupt():
    import os
    import signal
    import subprocess
    import sys
    import time
    # 64 tiles of 16 x 16 pixels, 1024 samples per pixel per pass: the render takes minutes, and the
    # cancel flag is read before every tile (a fraction of a second each).
    code = ("import aniso, sys\n"
            "print('ready', flush=True)\n"
            "try:\n"
            "    aniso.render(material='clay', spp=1 << 14, width=128, height=128, progress=False)\n"
            "    print('finished')\n"
            "except KeyboardInterrupt:\n"
            "    print('interrupted')\n")
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=dict(os.environ))
    assert p.stdout.readline().strip() == "ready"
    time.sleep(1.0)  # into the render
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    assert out.strip() == "interrupted"


def test_save_image_writes_what_the_cli_writes(tmp):
    args = ["--material", "brushed-gold", "--spp", "2", "--width", "48", "--height", "24"]
    for ext, extra in [(".png", []), (".png", ["--exposure", "1.5", "--tonemap", "clamp"]), (".exr", []), (".pfm", [])]:
        out = tmp / f"cli{ext}"
        rc, _, err = run_cli("render", *args, *extra, "-o", str(out))
        assert rc == 0, err
        img = aniso.render(material="brushed-gold", spp=2, width=48, height=24, progress=False)
        mine = tmp / f"py{ext}"
        keys = {"exposure": 1.5, "tonemap": "clamp"} if extra else {}
        assert aniso.save_image(img, mine, **keys) is None
        assert mine.read_bytes() == out.read_bytes(), (ext, extra)
    # float64 and lists of rows are read as float32 radiance.
    aniso.save_image(img.astype(np.float64), str(tmp / "d.pfm"))
    np.testing.assert_array_equal(read_pfm(tmp / "d.pfm"), img)


def test_save_image_errors(tmp):
    img = np.zeros((4, 5, 3), np.float32)
    with pytest.raises(ValueError, match=r"exposure and tonemap apply to PNG output only"):
        aniso.save_image(img, tmp / "x.exr", exposure=1.0)
    with pytest.raises(ValueError, match=r"expected a \.png, \.exr or \.pfm file name"):
        aniso.save_image(img, tmp / "x.bmp")
    with pytest.raises(ValueError, match=r"expected a \(height, width, 3\) array .* got shape \(4, 5\)"):
        aniso.save_image(img[..., 0], tmp / "x.png")
    bad = img.copy()
    bad[1, 2, 0] = np.nan
    with pytest.raises(ValueError, match=r"img\[1, 2, 0\]: expected finite radiance, got nan"):
        aniso.save_image(bad, tmp / "x.png")
    with pytest.raises(ValueError, match=r"exposure: expected a finite number of stops"):
        aniso.save_image(img, tmp / "x.png", exposure=float("inf"))
    with pytest.raises(OSError, match=r"cannot write .*x.png"):
        aniso.save_image(img, tmp / "no" / "such" / "x.png")
    assert not (tmp / "x.png").exists() and not (tmp / "x.exr").exists()


def test_export_to_a_renderer_equals_the_cli(tmp):
    """aniso.export writes what `aniso export --to` writes (docs/export.md), and returns the report."""
    for to, ext in (("pbrt-v4", "pbrt"), ("mitsuba3", "xml"), ("openpbr", "mtlx"), ("gltf", "gltf")):
        out = tmp / f"cli.{ext}"
        rc, _, err = run_cli("export", "--to", to, "--material", "gold", "-o", str(out))
        assert rc == 0, err
        r = aniso.export("gold", to=to, path=tmp / f"py.{ext}")
        assert r["report"]["path"] == "exact"
        assert r["report"]["target"] == to
        cli = out.read_text()
        py = (tmp / f"py.{ext}").read_text()
        if to == "gltf":  # the .bin's name differs with the file's
            assert py.replace("py.bin", "cli.bin") == cli
            assert (tmp / "py.bin").read_bytes() == (tmp / "cli.bin").read_bytes() == r["files"]["py.bin"]
        else:
            assert py == cli == r["files"][""]


def test_export_of_a_measured_source_equals_the_cli(tmp):
    """A tensor file to mitsuba3 / pbrt-v4 is the renderer's own measured BSDF, its tensor file beside path
    and named from path's stem as the CLI names it from -o; analytic=True is --analytic (docs/export.md)."""
    film = tmp / "film.bsdf"  # aniso's own tensor file, on small grids
    rc, _, err = run_cli("export-rgl", "-m", '{"model": "ggx", "alpha_x": 0.15, "alpha_y": 0.15, "f0": 0.05, '
                         '"kd": [0.3, 0.2, 0.1]}', "-o", str(film), "--rgb", "--isotropic", "--resolution", "16",
                         "--theta-i", "6", "--ndf", "32", "--vndf", "16")
    assert rc == 0, err
    (tmp / "cli").mkdir()
    (tmp / "py").mkdir()
    for to, ext, side in (("mitsuba3", "xml", "my_film_rgb.bsdf"), ("pbrt-v4", "pbrt", "my_film_spec.bsdf")):
        rc, _, err = run_cli("export", "--to", to, "-m", str(film), "-o", str(tmp / "cli" / f"my film.{ext}"), "--grid", "2")
        assert rc == 0, err
        r = aniso.export(str(film), to=to, path=tmp / "py" / f"my film.{ext}", grid=2)
        assert r["report"]["measured_file"] == side
        assert (tmp / "py" / side).read_bytes() == (tmp / "cli" / side).read_bytes() == r["files"][side]
        text = (tmp / "py" / f"my film.{ext}").read_text()
        assert text == (tmp / "cli" / f"my film.{ext}").read_text() == r["files"][""]
        assert ('id="film"' if to == "mitsuba3" else 'MakeNamedMaterial "film"') in text  # the source's stem
    rc, _, err = run_cli("export", "--to", "pbrt-v4", "-m", str(film), "-o", str(tmp / "cli" / "fit.pbrt"), "--grid", "2",
                         "--starts", "1", "--analytic")
    assert rc == 0, err
    r = aniso.export(str(film), to="pbrt-v4", path=tmp / "py" / "fit.pbrt", grid=2, starts=1, analytic=True)
    assert list(r["files"]) == [""] and "measured_file" not in r["report"]
    assert (tmp / "py" / "fit.pbrt").read_text() == (tmp / "cli" / "fit.pbrt").read_text() == r["files"][""]
    assert "\"string type\" \"measured\"" not in r["files"][""]
    assert sorted(p.name for p in (tmp / "py").iterdir()) == ["fit.pbrt", "my film.pbrt", "my film.xml",
                                                              "my_film_rgb.bsdf", "my_film_spec.bsdf"]


def test_export_errors(tmp):
    with pytest.raises(ValueError, match="unknown target"):
        aniso.export("gold", to="renderman")
    with pytest.raises(ValueError, match="metric"):
        aniso.export("gold", to="pbrt-v4", metric="l1")
    with pytest.raises(OSError):
        aniso.export("gold", to="gltf", path=tmp / "missing" / "x.gltf")
    assert not (tmp / "missing").exists()


def test_export_options_equal_the_cli(tmp):
    """grid, blender_version and tangent_angle_deg are the CLI's --grid, --blender-version and a scene
    object's tangent angle (--scene --object), composed with the material's rotation_deg."""
    mat = {"model": "ggx", "kd": 0.1, "f0": 0.04, "alpha_x": 0.3, "alpha_y": 0.1, "rotation_deg": 10}
    scene = tmp / "scene.json"
    scene.write_text(json.dumps({"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},
                                 "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "name": "knob",
                                              "tangent": {"angle_deg": 25}, "material": mat}]}))
    out = tmp / "cli.gltf"
    rc, _, err = run_cli("export", "--to", "gltf", "--scene", str(scene), "--object", "knob", "--grid", "2",
                         "-o", str(out))
    assert rc == 0, err
    r = aniso.export(mat, to="gltf", path=tmp / "py.gltf", name="knob", grid=2, tangent_angle_deg=25)
    py_gltf, cli_gltf = json.loads((tmp / "py.gltf").read_text()), json.loads(out.read_text())
    assert py_gltf["materials"] == cli_gltf["materials"]  # the files differ in the source's label only
    assert r["report"]["parameters"]["anisotropyRotation"] == pytest.approx(np.radians(35), abs=1e-12)

    rc, cli_text, err = run_cli("export", "--to", "blender", "--material", "gold", "--blender-version", "3.4")
    assert rc == 0, err
    r = aniso.export("gold", to="blender", blender_version=3.4)
    assert r["files"][""] == cli_text
    assert "3.4" in r["report"]["blender_version"]
    assert r["report"]["blender_version"] != aniso.export("gold", to="blender")["report"]["blender_version"]


def test_export_option_errors(tmp):
    for kw, match in ((dict(grid=0), r"grid: expected 1 to 12, got 0"), (dict(starts=101), r"starts: expected 1 to 100"),
                      (dict(blender_version=2.8), r"blender_version: expected 3 to 10, got 2.8"),
                      (dict(tangent_angle_deg=float("nan")), r"tangent_angle_deg: expected a finite angle")):
        with pytest.raises(ValueError, match=match):
            aniso.export("gold", to="blender", path=tmp / "x.py", **kw)
    assert not (tmp / "x.py").exists()


def test_export_glsl_of_a_measured_material_equals_the_cli_and_writes_its_tables(tmp_path):
    # A tensor file (export-rgl of an isotropic GGX) as GLSL: the shader and its tables file as
    # `aniso export-glsl -o X --tables T` writes them; glsl_tables() is the same floats as an array.
    bsdf = tmp_path / "ggx.bsdf"
    rc, _, err = run_cli("export-rgl", "--material", '{"model": "ggx", "kd": 0.1, "f0": 0.5, "alpha": 0.2}', "-o", str(bsdf))
    assert rc == 0, err
    cli_glsl, cli_tables = tmp_path / "cli.glsl", tmp_path / "cli.tables"
    rc, _, err = run_cli("export-glsl", "--material", str(bsdf), "-o", str(cli_glsl), "--tables", str(cli_tables))
    assert rc == 0, err
    py_tables = tmp_path / "py.tables"
    src = aniso.export_glsl(str(bsdf), tables=py_tables)
    assert src == cli_glsl.read_text().replace(str(cli_tables), str(py_tables))
    assert py_tables.read_bytes() == cli_tables.read_bytes()
    t = aniso.glsl_tables(str(bsdf))
    assert t.dtype == np.float32 and t.shape[1] == 4096
    assert t.astype("<f4").tobytes() == cli_tables.read_bytes()
    # The CLI's refusals, in Python.
    with pytest.raises(ValueError, match="needs its tables file"):
        aniso.export_glsl(str(bsdf))
    with pytest.raises(ValueError, match="is an analytic material, it has no tables"):
        aniso.export_glsl("gold", tables=tmp_path / "gold.tables")
    assert not (tmp_path / "gold.tables").exists()
    assert aniso.glsl_tables("gold") is None
    with pytest.raises(OSError):
        aniso.export_glsl(str(bsdf), tables=tmp_path / "no" / "such" / "dir.tables")

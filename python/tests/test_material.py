"""Materials: every way of giving one, round trips, the tables, and errors with the CLI's messages."""
import json
import pickle

import numpy as np
import pytest

import aniso
from conftest import SOURCE_DIR, cli_error, run_cli


def test_presets_are_the_clis():
    rc, out, _ = run_cli("presets")
    assert rc == 0
    names = [line.split()[0] for line in out.splitlines() if line.strip()]
    assert aniso.presets() == names
    assert "matte-steel" in names and "brushed-gold" in names


def test_every_preset_round_trips_through_to_dict():
    for name in aniso.presets():
        m = aniso.Material(name)
        d = m.to_dict()
        assert aniso.Material(d) == m, name
        assert aniso.Material(d).to_dict() == d, name
        assert aniso.Material(json.loads(m.to_json())) == m


def test_to_dict_is_the_clis_resolved_material():
    for name in ["matte-steel", "brushed-gold", "ngan/ward/nickel", "clay"]:
        rc, out, _ = run_cli("presets", "--show", name)
        assert rc == 0
        assert aniso.Material(name).to_dict() == json.loads(out), name


def test_material_from_dict_path_inline_json_and_keywords(tmp):
    d = {"model": "ward", "kd": 0.1, "ks": [0.5, 0.4, 0.3], "alpha_x": 0.05, "alpha_y": 0.3,
         "form": "vector", "normalization": "balanced"}
    path = tmp / "ward.json"
    path.write_text(json.dumps(d))
    a = aniso.Material(d)
    assert aniso.Material(str(path)) == a
    assert aniso.Material(path) == a  # os.PathLike
    assert aniso.Material(json.dumps(d)) == a  # inline JSON text
    assert aniso.Material(**d) == a
    assert aniso.ward(kd=0.1, ks=[0.5, 0.4, 0.3], alpha_x=0.05, alpha_y=0.3, normalization="balanced") == a
    assert aniso.Material(a) == a
    # NumPy values inside the dict are read as numbers and lists.
    assert aniso.Material({**d, "ks": np.array([0.5, 0.4, 0.3]), "kd": np.float32(0.1)}).to_dict()["ks"] == [0.5, 0.4, 0.3]
    assert a.model == "ward"


def test_keywords_change_a_presets_keys():
    base = aniso.Material("matte-steel")
    m = aniso.Material("brushed-gold", lobe={"model": "ggx", "alpha_x": 0.1, "alpha_y": 0.4})
    assert m.to_dict()["lobe"]["model"] == "ggx"
    assert m.to_dict()["metal"] == "gold"
    # A shorthand replaces both halves of its pair; None removes a key (the default applies again).
    w = aniso.Material(aniso.ward(alpha_x=0.05, alpha_y=0.3), alpha=0.2)
    assert (w.to_dict()["alpha_x"], w.to_dict()["alpha_y"]) == (0.2, 0.2)
    assert aniso.Material(aniso.ward(kd=0.3), kd=None).to_dict()["kd"] == 0.0
    assert base == aniso.Material("matte-steel")
    with pytest.raises(ValueError, match="model: cannot be changed"):
        aniso.Material("gold", model="ward")


def test_pickle_and_repr():
    m = aniso.Material("brushed-gold")
    assert pickle.loads(pickle.dumps(m)) == m
    assert repr(m).startswith("aniso.Material({")
    assert type(m).__module__ == "aniso"


# Each bad material as the CLI is given it and as Python is given it: the messages are equal.
BAD_INLINE = [
    {"model": "ward", "kd": 2},                       # out of range
    {"model": "ward", "kd": 0.1, "shininess": 3},     # unknown key
    {"model": "ward", "alpha_x": 0.1},                # half of a pair
    {"model": "ward", "form": "exact"},               # not a choice
    {"model": "ward", "kd": "red"},                   # wrong type
    {"model": "wrad"},                                # unknown model
    {"kd": 0.5},                                      # no model
    {"model": "metal", "metal": "gld", "lobe": {"model": "ward", "alpha": 0.1}},  # unknown metal
    {"model": "lafortune", "lobes": []},              # empty list
    {"model": "ward", "ks": [0.1, 0.2]},              # colour of two channels
]


@pytest.mark.parametrize("bad", BAD_INLINE, ids=[json.dumps(b) for b in BAD_INLINE])
def test_bad_dict_raises_the_clis_message(bad):
    expected = cli_error("eval", "--material", json.dumps(bad), stdin="0 0 1 0 0 1\n")
    with pytest.raises(ValueError) as e:
        aniso.Material(bad)
    assert str(e.value) == expected
    with pytest.raises(ValueError) as e:
        aniso.Material(json.dumps(bad))
    assert str(e.value) == expected


def test_bad_preset_file_and_json_text_raise_the_clis_message(tmp):
    bad_file = tmp / "bad.json"
    bad_file.write_text('{"model": "ward", "kd": 0.1,\n "alpha": 7}')
    broken = tmp / "broken.json"
    broken.write_text('{"model": "ward", "kd": }')
    for spec in ["matte-stel", "", str(tmp / "missing.json"), str(bad_file), str(broken), str(tmp), '{"model": "ward",']:
        expected = cli_error("eval", "--material", spec, stdin="0 0 1 0 0 1\n")
        with pytest.raises(ValueError) as e:
            aniso.Material(spec)
        assert str(e.value) == expected, spec


def test_bad_python_values_are_value_errors():
    with pytest.raises(ValueError, match=r"inline material: ks\[1\]: expected a number, string, bool, list or dict, got object"):
        aniso.Material({"model": "ward", "ks": [0.1, object()]})
    with pytest.raises(ValueError, match="expected string keys"):
        aniso.Material({"model": "ward", 3: 0.1})
    with pytest.raises(ValueError, match="expected a preset name"):
        aniso.Material(3.5)
    with pytest.raises(ValueError, match="expected a preset name"):
        aniso.Material()
    with pytest.raises(ValueError, match="inline material: kd: expected a finite number, got nan"):
        aniso.Material({"model": "ward", "kd": float("nan")})
    with pytest.raises(ValueError, match=r"inline material: ks\[2\]: expected a finite number, got inf"):
        aniso.Material({"model": "ward", "ks": [0.1, 0.2, np.inf]})
    with pytest.raises(ValueError):
        aniso.ward(kd=10**30)  # beyond int64: a number out of range


def _nested(depth, leaf):
    """A dict nested `depth` levels under "x" keys, the innermost holding `leaf`."""
    d = leaf
    for _ in range(depth):
        d = {"x": d}
    return d


def test_deep_dicts_get_the_clis_depth_limit_and_message():
    # 64 levels are read (the model then rejects the unknown key); 65 are refused with the CLI's
    # message for the same document.
    with pytest.raises(ValueError, match="unknown key"):
        aniso.Material({"model": "lambert", **_nested(63, {})})
    for depth in [64, 65, 30000]:
        doc = {"model": "lambert", **_nested(depth, {})}
        with pytest.raises(ValueError, match="nested deeper than 64 levels") as e:
            aniso.Material(doc)
        if depth < 1000:  # nlohmann's parser itself recurses; the CLI's text for a short one
            assert str(e.value) == cli_error("eval", "--material", json.dumps(doc), stdin="0 0 1 0 0 1\n")
        with pytest.raises(ValueError, match="nested deeper than 64 levels"):
            aniso.render({"camera": _nested(depth, {})})
    deep_list = []
    for _ in range(30000):
        deep_list = [deep_list]
    with pytest.raises(ValueError, match="nested deeper than 64 levels"):
        aniso.Material({"model": "ward", "ks": deep_list})


def test_self_referencing_dicts_and_lists_are_value_errors():
    d = {"model": "lambert"}
    d["fit"] = d
    with pytest.raises(ValueError, match=r"inline material: fit: the dict contains itself \(a cycle\)"):
        aniso.Material(d)
    with pytest.raises(ValueError, match="contains itself"):
        aniso.render(d)
    lst = [0.1, 0.2]
    lst.append(lst)
    with pytest.raises(ValueError, match=r"inline material: ks\[2\]: the list contains itself"):
        aniso.Material({"model": "ward", "ks": lst})
    # The same dict twice side by side is no cycle.
    shared = {"cxy": -1.0, "cz": 1.0, "n": 10.0}
    assert aniso.Material({"model": "lafortune", "lobes": [shared, shared]}).to_dict()["lobes"][1]["n"] == 10.0


def test_huge_integers_and_bad_text_are_clear_value_errors():
    with pytest.raises(ValueError, match=r"inline material: kd: expected a number, got an integer of 401 decimal digits"):
        aniso.Material({"model": "lambert", "kd": 10**400})
    with pytest.raises(ValueError, match=r"inline material: kd: expected a number, got an integer of 401 decimal digits"):
        aniso.Material({"model": "lambert", "kd": -10**400})
    with pytest.raises(ValueError, match=r"inline material: \(top level\): a key '\\ud800' is not valid Unicode text"):
        aniso.Material({"model": "lambert", "\ud800": 1})
    with pytest.raises(ValueError, match=r"inline material: model: a string '\\udfff' is not valid Unicode text"):
        aniso.Material({"model": "\udfff"})


def test_models_are_the_parameter_tables():
    tables = aniso.models()
    rc, out, _ = run_cli("models")
    assert rc == 0
    listed = [line.split()[0] for line in out.splitlines() if line and not line.startswith(" ")]
    assert list(tables) == listed
    ward = {p["name"]: p for p in tables["ward"]["params"]}
    assert ward["alpha_x"]["kind"] == "scalar"
    assert (ward["alpha_x"]["min"], ward["alpha_x"]["max"], ward["alpha_x"]["default_value"]) == (0.001, 1.0, 0.15)
    assert ward["alpha_x"]["partner"] == "alpha_y"
    assert ward["alpha"]["sets"] == ["alpha_x", "alpha_y"]
    assert ward["form"]["choices"] == ["vector", "angle", "approx"]
    assert ward["form"]["default_value"] == "vector"
    # Every key line of `aniso models` (name, range, default, doc) is in the Python tables.
    for model, spec in tables.items():
        for p in spec["params"]:
            assert p["name"] in out and p["range"] in out and p["doc"] in out, (model, p["name"])
    metal = {p["name"]: p for p in tables["metal"]["params"]}
    assert set(metal["lobe"]["params"]) == {"ward", "ashikhmin-shirley", "ggx"}
    lafortune = {p["name"]: p for p in tables["lafortune"]["params"]}
    assert {q["name"] for q in lafortune["lobes"]["params"]} >= {"cx", "cy", "cz", "n"}


def test_docstrings_come_from_the_tables():
    doc = aniso.Material.__doc__
    for spec in aniso.models().values():
        assert f'model="{spec["name"]}"' in doc
        for p in spec["params"]:
            assert p["doc"] in doc
    import inspect
    sig = inspect.signature(aniso.ward)
    assert list(sig.parameters) == [p["name"] for p in aniso.models()["ward"]["params"]]
    assert sig.parameters["alpha_x"].default == 0.15
    assert "RMS slope along the tangent t" in aniso.ward.__doc__
    assert aniso.ashikhmin_shirley(n_u=10, n_v=100).model == "ashikhmin-shirley"


def test_preset_source():
    assert "Ngan" in aniso.preset_source("ngan/ward/nickel") or aniso.preset_source("ngan/ward/nickel")
    with pytest.raises(ValueError):
        aniso.preset_source("nope")


def test_measured_merl_file_goes_through_load_material(tmp):
    # A synthetic MERL table (header 90 90 180, then three channels of float64): Material(path)
    # reads it as the CLI does, and evaluates to the CLI's numbers.
    rng = np.random.default_rng(3)
    path = tmp / "synthetic.binary"
    with open(path, "wb") as f:
        np.array([90, 90, 180], "<i4").tofile(f)
        rng.uniform(100.0, 3000.0, size=3 * 90 * 90 * 180).astype("<f8").tofile(f)
    m = aniso.Material(path)
    assert m.model == "measured"
    assert aniso.Material({"model": "measured", "file": str(path)}) == m
    assert aniso.Material(m.to_dict()) == m
    wi = aniso.direction(np.radians([10.0, 30.0, 60.0, 80.0]), [0.0, 1.0, 2.0, 3.0])
    wo = aniso.direction(np.radians([20.0, 45.0, 5.0, 70.0]), [3.0, 0.5, 1.5, 4.0])
    lines = "".join(" ".join(repr(float(v)) for v in (*a, *b)) + "\n" for a, b in zip(wi, wo))
    rc, out, err = run_cli("eval", "--material", str(path), stdin=lines)
    assert rc == 0, err
    ref = np.loadtxt(out.splitlines(), ndmin=2)
    np.testing.assert_allclose(m.eval(wi, wo), ref[:, :3], rtol=1e-8)
    np.testing.assert_allclose(m.pdf(wi, wo), ref[:, 3], rtol=1e-8)
    assert np.isfinite(m.eval(wi.astype(np.float32), wo.astype(np.float32))).all()
    expected = cli_error("eval", "--material", str(tmp / "missing.binary"), stdin="0 0 1 0 0 1\n")
    with pytest.raises(ValueError) as e:
        aniso.Material(str(tmp / "missing.binary"))
    assert str(e.value) == expected

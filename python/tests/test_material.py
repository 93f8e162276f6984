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

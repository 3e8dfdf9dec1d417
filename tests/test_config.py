"""Configuration: the defaults validate; bad values fail with the key, the value and the range."""

import copy

import pytest

from rail.setup import build
from rail.setup import config as rconfig


def test_default_config_is_valid_and_builds_parameters(defaults, schema):
    cfg = rconfig.validate_config(copy.deepcopy(defaults), schema)
    m = build.scenario(cfg).elastic
    assert (m.youngs_modulus, m.poisson_ratio, m.density) == (2.1e11, 0.3, 7850.0)


def test_unknown_key_names_key_value_and_allowed_keys(defaults, schema):
    cfg = rconfig.deep_merge(defaults, {"track": {"pad": {"stifness": 3.5e8}}})
    with pytest.raises(rconfig.ConfigError, match=r"scen.yaml: unknown key track\.pad\.stifness = 350000000\.0; "
                       r"the keys allowed under track\.pad are: longitudinal_loss_factor, longitudinal_stiffness, "
                       r"longitudinal_viscous_damping, loss_factor, rotational_stiffness, stiffness, viscous_damping"):
        rconfig.validate_config(cfg, schema, source="scen.yaml")


def test_negative_modulus_names_value_and_range(defaults, schema):
    cfg = rconfig.deep_merge(defaults, {"material": {"youngs_modulus": -2.1e11}})
    with pytest.raises(rconfig.ConfigError, match=r"material\.youngs_modulus = -210000000000\.0 Pa is not allowed: it must be > 0 Pa "
                       r"\(valid range \(0, inf\) Pa\)"):
        rconfig.validate_config(cfg, schema)


@pytest.mark.parametrize("nu", [0.5, 0.7])
def test_poisson_ratio_of_half_or_more_is_rejected(defaults, schema, nu):
    cfg = rconfig.deep_merge(defaults, {"material": {"poisson_ratio": nu}})
    with pytest.raises(rconfig.ConfigError, match=rf"material\.poisson_ratio = {nu} is not allowed: it must be < 0\.5 \(valid range \(-1, 0\.5\)\)"):
        rconfig.validate_config(cfg, schema)


def test_every_problem_is_listed_at_once(defaults, schema):
    cfg = rconfig.deep_merge(defaults, {"material": {"poisson_ratio": 0.5, "density": -1.0}, "wear": {"coefficent": 1.0}})
    with pytest.raises(rconfig.ConfigError) as info:
        rconfig.validate_config(cfg, schema)
    text = str(info.value)
    assert "poisson_ratio" in text and "density" in text and "wear.coefficent" in text


def test_yaml_exponent_without_dot_gets_a_hint(defaults, schema):
    cfg = rconfig.deep_merge(defaults, {"track": {"pad": {"stiffness": "3.5e8"}}})
    with pytest.raises(rconfig.ConfigError, match=r"track\.pad\.stiffness = '3\.5e8' has the wrong type: it must be of type number "
                       r"\(YAML reads 3\.5e8 as text"):
        rconfig.validate_config(cfg, schema)


def test_static_friction_below_dynamic_is_rejected(defaults, schema):
    cfg = rconfig.deep_merge(defaults, {"contact": {"friction_static": 0.2}})
    with pytest.raises(rconfig.ConfigError, match=r"contact\.friction_static = 0\.2 is not allowed: it must be >= contact\.friction_dynamic = 0\.3"):
        rconfig.validate_config(cfg, schema)


def test_scenario_merge_keeps_unchanged_defaults(defaults, schema):
    cfg = rconfig.resolve(defaults, schema, {"track": {"pad": {"stiffness": 7.0e7}}}, source="soft_pad.yaml")
    assert cfg["track"]["pad"] == {"stiffness": 7.0e7, "loss_factor": 0.25, "viscous_damping": 2.8e4}
    assert defaults["track"]["pad"]["stiffness"] == 3.5e8  # defaults untouched


def test_schema_states_a_unit_and_description_for_every_leaf(schema):
    # Every configurable number must say its unit; a schema leaf without one is a defect.
    def leaves(node, path):
        if node.get("type") == "object":
            for key, sub in node.get("properties", {}).items():
                yield from leaves(sub, f"{path}.{key}")
        else:
            yield path, node

    defs = schema["$defs"]
    for path, node in leaves(schema, "config"):
        if "$ref" in node:
            node = {**defs[node["$ref"].split("/")[-1]], **node}
        assert "description" in node, path
        if node.get("type") in ("number", "integer"):
            assert "unit" in node, path


def test_a_yaml_alias_bomb_gives_a_short_message(tmp_path, schema):
    # nine levels of nine aliases: a value whose repr is about 10^9 characters; the message names the
    # key and stays short (it was 28 MB)
    from rail.setup.config import ConfigError, load_yaml, validate_config

    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    for i in range(1, 7):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 9) + "]")
    lines.append("speeds: *a6")
    f = tmp_path / "bomb.yaml"
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ConfigError, match=r"bomb\.yaml: holds more than 100000 values once its aliases"):
        load_yaml(f)  # issue 45: refused while reading (tests/test_doors.py)
    data = ["x"] * 9  # the same value built in Python, as a caller of validate_config might
    for _ in range(6):
        data = [data] * 9
    with pytest.raises(ConfigError) as e:
        validate_config({"speeds": data}, schema, source="bomb.yaml")
    assert "speeds" in str(e.value) and len(str(e.value)) < 5000, len(str(e.value))


def test_a_nested_value_given_as_text_gets_the_configfile_hint(defaults, schema):
    # snakemake --config 'material={poisson_ratio: 0.25}' arrives as the text '{poisson_ratio: 0.25}'
    from rail.setup.config import ConfigError, validate_config

    cfg = copy.deepcopy(defaults)
    cfg["material"] = "{poisson_ratio: 0.25}"
    with pytest.raises(ConfigError, match=r"material = '\{poisson_ratio: 0\.25\}' has the wrong type: it must be of type "
                                          r"object \(snakemake --config passes a nested value as text: .*--configfile\)"):
        validate_config(cfg, schema, source="--config")


def test_an_absent_optional_key_takes_the_schema_default(defaults, schema):
    # config.yaml sets no contact.friction_decay and no wheelset: the schema's defaults apply, read
    # where they are used (rail.setup.config.setting); a torsional wheelset given only its model gets
    # the schema's inertias, stiffnesses and damping (its description states them: 40, 10, 5e6, 0, 1e6, 0.02)
    from rail.creepage.wheelset import Wheelset, wheelset_modes

    cfg = rconfig.resolve(defaults, schema, {"wheelset": {"model": "torsional"}})
    assert "friction_decay" not in cfg["contact"] and rconfig.setting(cfg, "contact.friction_decay", schema) == 0
    assert rconfig.setting(cfg, "wheelset.other_wheel", schema) == "in_phase"
    expected = wheelset_modes(Wheelset(model="torsional", radius=float(cfg["wheels"]["radius"]), wheel_inertia=40.0, centre_inertia=10.0,
                                       axle_stiffness=5e6, motor_inertia=0.0, coupling_stiffness=1e6, damping=0.02, other_wheel="in_phase"))
    assert repr(build.scenario(cfg).material.longitudinal) == repr(expected)
    # a value the file gives wins over the default
    cfg = rconfig.resolve(defaults, schema, {"contact": {"friction_decay": 0.5}})
    assert rconfig.setting(cfg, "contact.friction_decay", schema) == 0.5 and build.scenario(cfg).material.friction_decay == 0.5


def test_a_key_config_yaml_sets_has_no_schema_default(schema):
    # its default is its value in config/config.yaml: one home, not two
    with pytest.raises(KeyError, match=r"contact\.creepage: config/schema/config\.schema\.yaml states no default"):
        rconfig.schema_default(schema, "contact.creepage")
    with pytest.raises(KeyError, match=r"contact\.nokey: not a key"):
        rconfig.schema_default(schema, "contact.nokey")


def test_the_wheelset_dataclass_defaults_are_the_schemas(schema):
    # rail.creepage.wheelset.Wheelset keeps defaults for direct use from Python (tests/test_creep.py); the
    # workflow passes every key from the schema, and the two must not drift apart
    import dataclasses

    from rail.creepage.wheelset import Wheelset

    for f in dataclasses.fields(Wheelset):
        if f.default is not dataclasses.MISSING:
            assert f.default == rconfig.schema_default(schema, f"wheelset.{f.name}"), f.name

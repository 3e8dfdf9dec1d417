"""The model choices as objects (issue 54, "one home"): each named as the configuration names it, held by
the Scenario, written to results as a value beside its description and read back by that value, its
default the schema's alone (tests/test_architecture.py checks that no module outside a model's
package compares a name)."""

import numpy as np
import pytest
import xarray as xr

from rail import contact as C
from rail.creepage import choices as S
from rail.setup import build
from rail.setup import config as rconfig
from rail.setup.targets import read_part
from rail.studies import speed_study
from rail.studies.rate_spectrum import model_mechanisms
from rail.studies.validity import model_attributes, stated_wear_path, validity_text
from rail.creepage.wheelset import WHEELSET_MODELS


def _enum(schema, key):
    section, leaf = key.split(".")
    return schema["properties"][section]["properties"][leaf]["enum"]


def test_each_choice_is_named_as_the_schema_names_it(schema):
    assert list(C.NORMAL_MODELS) == _enum(schema, "contact.normal")
    assert list(C.WEAR_PATHS) == _enum(schema, "contact.wear_path")
    assert list(S.WHEELSET_CHOICES) == _enum(schema, "wheelset.model") == list(WHEELSET_MODELS)
    assert list(S.RAIL_FLEXIBILITIES) == _enum(schema, "rail_flexibility.model")
    # every description opens with its value, so a reader of the file sees which one it describes
    for choice in ([C.normal_contact(n) for n in C.NORMAL_MODELS] + [C.wear_path(n) for n in C.WEAR_PATHS]
                   + [S.wheelset_model(n) for n in S.WHEELSET_CHOICES] + [S.rail_flexibility(n) for n in S.RAIL_FLEXIBILITIES]):
        assert choice.description.startswith(f"{choice.name}: ") and str(choice) == choice.name


@pytest.mark.parametrize("look_up, key", [(S.wheelset_model, "wheelset.model"), (S.rail_flexibility, "rail_flexibility.model"),
                                          (C.wear_path, "contact.wear_path")])
def test_an_unknown_name_is_refused_naming_the_key(look_up, key):
    with pytest.raises(ValueError, match=rf"{key.replace('.', '[.]')} = 'none_at_all' is not allowed: it must be one of \["):
        look_up("none_at_all")


def test_the_defaults_of_the_creepage_sources_are_the_schemas_alone(schema):
    # an absent wheelset section is the schema's wheelset.model (the report's fixed creepage), an absent
    # rail_flexibility its rail_flexibility.model; the speed study read 'none', which the schema does not allow
    assert rconfig.schema_default(schema, "wheelset.model") == "fixed_creepage"
    assert rconfig.schema_default(schema, "rail_flexibility.model") == "none"
    assert speed_study.mechanism_label({"track": {"pad": {"stiffness": 1e9}}}) == "fixed creepage"
    assert speed_study.mechanism_label({"wheelset": {"model": "rigid"}}) == "rigid wheelset"
    assert speed_study.mechanism_label({"wheelset": {"model": "torsional", "motor_inertia": 40.0},
                                        "rail_flexibility": {"model": "rod"}}) == "motored wheelset + rail flexibility"
    # the numbers the contact numerics hold are given, not defaulted: the configuration's
    with pytest.raises(TypeError, match="path"):
        C.ContactNumerics(41, "default", 1.0, "report")


def test_the_scenario_names_its_model_choices_as_objects(defaults, schema):
    # the rod alone (no bending) is named 'rod', not lost in RailHead's bool
    cfg = rconfig.resolve_scenario_file(defaults, schema, {"wheelset": {"model": "torsional", "motor_inertia": 40.0},
                                                           "rail_flexibility": {"model": "rod"},
                                                           "contact": {"friction_decay": 0.5, "friction_static": 0.4}}, "mine.yaml")
    m = build.passage_scenario(cfg, "mine", "mine.yaml").models
    assert (m.normal_contact, m.wear_path) == (C.NonHertzianNormal(), C.PatchPath())  # a scenario file's defaults
    assert (m.wheelset.name, m.rail_flexibility.name, m.friction_law.name) == ("torsional", "rod", "falling")
    assert m.wheelset.modelled and m.rail_flexibility.modelled and not m.rail_flexibility.bending and m.friction_law.falling
    report = build.passage_scenario(rconfig.validate_config(defaults, schema)).models
    assert [str(c) for c in (report.normal_contact, report.wear_path, report.wheelset, report.rail_flexibility, report.friction_law)] == [
        "report", "wheel", "fixed_creepage", "none", "step"]


def test_a_spectrum_file_stores_each_choice_as_a_value_beside_its_description_and_reads_it_back_by_value(defaults, schema, tmp_path):
    cfg = rconfig.resolve_scenario_file(defaults, schema, {"wheelset": {"model": "rigid"}, "rail_flexibility": {"model": "rod_and_bending"}},
                                        "mine.yaml")
    scn = build.passage_scenario(cfg, "mine", "mine.yaml")
    xr.Dataset({"x": ("x", np.zeros(1))}, attrs=model_mechanisms(scn)).to_netcdf(tmp_path / "s.nc")
    with xr.open_dataset(tmp_path / "s.nc") as ds:
        attrs = dict(ds.attrs)
    assert {k: attrs[k] for k in ("normal_contact", "wear_path", "wheelset_model", "rail_flexibility", "friction_law")} == {
        "normal_contact": "nonhertzian", "wear_path": "patch", "wheelset_model": "rigid", "rail_flexibility": "rod_and_bending",
        "friction_law": "step"}
    assert S.wheelset_model(attrs["wheelset_model"]) is S.wheelset_model("rigid")
    assert S.rail_flexibility(attrs["rail_flexibility"]).bending
    assert attrs["rail_flexibility_description"] == S.rail_flexibility("rod_and_bending").description
    assert stated_wear_path(attrs) == C.PatchPath()


def test_a_results_wear_path_is_read_by_its_value_and_a_sentence_is_not_parsed_back():
    from rail.plotting.text import validity_notes

    patch = model_attributes("patch", "nonhertzian")
    assert patch == {"wear_path": "patch", "wear_path_description": C.PatchPath.description, "contact_shift_modelled": 1,
                     "normal_contact": "nonhertzian", "normal_contact_description": C.NonHertzianNormal.description}
    assert validity_notes(model_attributes("wheel", "report")) == []  # the report's model within its range: no note
    assert validity_notes(patch) == [("wear on the contact patch's true path (docs/contact.md)", "0.4")]
    assert validity_text(model_attributes("wheel", "report")).startswith("wear under the wheel centre (the report's model)")
    # a file of the earlier form (the sentence as the value) states no wear path that can be read: nothing is guessed
    sentence = {"wear_path": C.PatchPath.description}
    assert stated_wear_path(sentence) is None and validity_notes(sentence) == [] and validity_text(sentence) == ""
    assert model_attributes("none", "none")["wear_path_description"] == "none: no wear is computed for this result"


def test_a_wheelset_at_the_schemas_default_model_reruns_nothing(defaults, schema):
    # read_part leaves out a wheelset the chain does not read: the fixed creepage, written or absent
    for ws in ({"model": "fixed_creepage"}, {"model": "fixed_creepage", "wheel_inertia": 55.0}):
        cfg = rconfig.resolve_scenario_file(defaults, schema, {"wheelset": ws}, "x.yaml")
        assert "wheelset" not in read_part(cfg, schema)
    rigid = rconfig.resolve_scenario_file(defaults, schema, {"wheelset": {"model": "rigid", "axle_stiffness": 2e6}}, "x.yaml")
    assert read_part(rigid, schema)["wheelset"] == {"model": "rigid"}  # the rigid wheelset reads no stiffness

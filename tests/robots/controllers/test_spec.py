"""Architecture specs (robots.controllers.spec): parsed, spelled back, refused in one line."""

import pytest

from ekm.config import EKMConfig
from ekm.errors import InputError
from robots.controllers.spec import parse_architecture, parse_architectures


def test_architecture_specs_parse_parameters_and_spell_them_all():
    specs = parse_architectures("fusion:sensors=long,beta=0.6,fields,fields:form=thesis,commit=false")
    assert [s.name for s in specs] == ["fusion", "fields", "fields"]
    assert specs[0].params.sensors == "long" and specs[0].params.beta == 0.6
    assert specs[2].params.form == "thesis" and specs[2].params.commit is False
    assert specs[0].label == "fusion:sensors=long,beta=0.6" and specs[1].label == "fields"
    assert str(parse_architecture(str(specs[0]))) == str(specs[0])  # the full spelling parses back
    assert specs[2].label == "fields:form=thesis,commit=false"  # a switch as the command line spells it
    assert "commit=false" in str(specs[2]) and "commit=true" in str(specs[1])


@pytest.mark.parametrize("text, message", [
    ("fuson", "architecture 'fuson': unknown; did you mean 'fusion'? (choose from fusion, fields"),
    ("xyz", "architecture 'xyz': unknown (choose from fusion, fields"),
    ("fusion:foo=1", "architecture fusion: unknown parameter 'foo' (known: sensors, beta,"),
    ("fusion:beta=x", "architecture fusion: beta: must be a number, got 'x'"),
    ("fusion:beta=2", "architecture fusion: beta must be in (0, 1], got 2.0"),
    ("fusion:sensors=mid", "architecture fusion: sensors: must be one of short, long, got 'mid'"),
    ("fields:commit=maybe", "architecture fields: commit: must be true or false, got 'maybe'"),
    ("fusion:beta", "architecture fusion: 'beta' is not k=v"),
    ("fusion:beta=0.5,beta=0.6", "architecture fusion: parameter 'beta' given twice"),
    ("beta=1", "parameter 'beta=1' before any architecture name"),
    ("fusion,,fields", "empty item between commas"),
    ("", "architecture: empty"),
])
def test_bad_architecture_specs_are_one_line_errors(text, message):
    with pytest.raises(InputError) as err:
        parse_architectures(text)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_an_architecture_refuses_a_direct_map():
    from ekm.direct import init as direct_init

    cfg = EKMConfig(mapping="direct", neurons=3)
    with pytest.raises(InputError, match="needs an indirect map"):
        parse_architecture("fields").build(direct_init(cfg), cfg)

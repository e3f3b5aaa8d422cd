"""Loading gearboxes from files, YAML text and dicts; edits by schema path; input errors."""
import copy

import pytest

import gearnvh
from conftest import IDLE_RATTLE

MINIMAL = """\
schema: gearnvh/1
name: minimal pair
materials:
  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}
gears:
  pinion: {teeth: 27, module: 2 mm, pressure_angle: 20 deg, face_width: 15 mm, bore_diameter: 25 mm, material: steel}
  wheel: {teeth: 43, module: 2 mm, pressure_angle: 20 deg, face_width: 15 mm, bore_diameter: 30 mm, material: steel}
mesh: {backlash: 100 um}
operating: {speed: 800 rpm, torque: 0.2 N*m}
"""


def test_load_from_file_string_and_dict_agree():
    from_file = gearnvh.load(str(IDLE_RATTLE))
    assert from_file.name == "Passenger-car 5th gear, idle rattle"
    assert from_file.source == str(IDLE_RATTLE)
    from_path = gearnvh.load(IDLE_RATTLE)  # os.PathLike
    assert from_path.source == str(IDLE_RATTLE)
    from_text = gearnvh.load(MINIMAL)
    assert from_text.source == "<string>"
    yaml = pytest.importorskip("yaml")
    from_dict = gearnvh.load(yaml.safe_load(MINIMAL))
    assert from_dict.source == "<dict>"
    # The same gearbox through text and dict: the same check document (exact: same SI input).
    a, b = gearnvh.check(from_text), gearnvh.check(from_dict)
    a.pop("file"), b.pop("file")
    assert a == b


def test_set_takes_units_and_si_floats_alike():
    gb = gearnvh.load(str(IDLE_RATTLE))
    gb.set("operating.torque", "0.3 N*m")
    assert gb.get("operating.torque") == "0.3 N*m"
    with_units = gearnvh.check(gb)
    gb.set("operating.torque", 0.3)  # plain floats are SI
    assert gb.get("operating.torque") == "0.3"
    si = gearnvh.check(gb)
    # The mesh load is T / r_b2 from the same double: equal exactly.
    assert with_units["mesh"]["load"] == si["mesh"]["load"]
    gb.set("mesh.backlash", "80 um")
    gb.set("operating.excitation[0].amplitude", "1000 rad/s^2")
    assert gb.get("operating.excitation.0.amplitude") == "1000 rad/s^2"
    gb.set("operating.excitation", [{"order": 2, "amplitude": "500 rad/s^2"}])
    assert gb.get("operating.excitation[0].amplitude") == "500 rad/s^2"


def test_set_rejects_bad_values_naming_path_and_rule_and_keeps_the_gearbox():
    gb = gearnvh.load(str(IDLE_RATTLE))
    before = gb.yaml
    with pytest.raises(gearnvh.InputError) as bad_value:
        gb.set("mesh.backlash", "-5 um")
    assert bad_value.value.path == "mesh.backlash"
    assert "> 0" in bad_value.value.rule
    assert "mesh.backlash" in str(bad_value.value)
    with pytest.raises(gearnvh.InputError) as wrong_unit:
        gb.set("operating.torque", "0.3 m")
    assert wrong_unit.value.path == "operating.torque"
    assert "N" in wrong_unit.value.rule  # lists the accepted torque units
    with pytest.raises(gearnvh.InputError) as typo:
        gb.set("operating.torqe", "1 N*m")
    assert typo.value.path == "operating.torqe"
    assert "did you mean 'torque'" in typo.value.rule
    with pytest.raises(gearnvh.InputError) as index:
        gb.set("operating.excitation[3].amplitude", 1.0)
    assert "out of range" in index.value.rule
    with pytest.raises(TypeError):
        gb.set("operating.torque", object())
    assert gb.yaml == before  # nothing half-changed


def test_set_names_the_path_of_a_huge_index_or_a_lone_surrogate():
    gb = gearnvh.load(str(IDLE_RATTLE))
    before = gb.yaml
    with pytest.raises(gearnvh.InputError) as huge:
        gb.set("operating.excitation[99999999999999999999].amplitude", 1.0)
    assert huge.value.path == "operating.excitation[99999999999999999999].amplitude"
    assert "is not a list index" in huge.value.rule
    with pytest.raises(gearnvh.InputError) as value:
        gb.set("name", "idle \ud800")
    assert value.value.path == "name"
    assert "lone surrogate" in value.value.rule
    with pytest.raises(gearnvh.InputError) as path:
        gb.set("mesh.\ud800", "1 um")
    assert path.value.path == "'mesh.\\ud800'"
    assert "lone surrogate" in path.value.rule
    with pytest.raises(TypeError):
        gb.set(3, "1 um")
    assert gb.yaml == before


def test_load_errors_carry_path_line_and_source():
    with pytest.raises(gearnvh.InputError) as missing:
        gearnvh.load("/nonexistent/gearbox.yaml")
    assert missing.value.source == "/nonexistent/gearbox.yaml"
    with pytest.raises(gearnvh.InputError) as bad:
        gearnvh.load(MINIMAL.replace("teeth: 27", "teeth: 2"))
    assert bad.value.path == "gears.pinion.teeth"
    assert bad.value.line == 6
    assert bad.value.source == "<string>"
    assert isinstance(bad.value, ValueError)


def test_load_names_an_empty_path_and_a_directory():
    with pytest.raises(gearnvh.InputError) as empty:
        gearnvh.load("")
    assert "the file name is empty" in str(empty.value)
    assert "cannot open" not in str(empty.value)
    with pytest.raises(gearnvh.InputError) as folder:
        gearnvh.load(str(IDLE_RATTLE.parent))
    assert folder.value.source == str(IDLE_RATTLE.parent)
    assert "is a directory, not a gearbox file" in str(folder.value)


def test_every_class_of_the_module_has_its_own_repr():
    classes = [c for c in vars(gearnvh).values()
               if isinstance(c, type) and not issubclass(c, BaseException)]
    assert len(classes) > 20
    # pybind11's default is object.__repr__ ("<gearnvh.Validation object at 0x...>").
    assert [c.__name__ for c in classes if "__repr__" not in vars(c)] == []


def test_copies_are_independent():
    gb = gearnvh.load(str(IDLE_RATTLE))
    other = copy.deepcopy(gb)
    other.set("operating.torque", "1 N*m")
    assert gb.get("operating.torque") == "0.2 N*m"
    assert other.get("operating.torque") == "1 N*m"
    assert "edited" in repr(other) and "edited" not in repr(gb)


def test_check_matches_the_command_line(gearnvh_exe):
    import json
    import subprocess
    cli = json.loads(subprocess.run([gearnvh_exe, "check", str(IDLE_RATTLE), "--json"],
                                    check=True, capture_output=True, text=True).stdout)
    # The same library calls on the same input: the same document, every number bit for bit.
    assert gearnvh.check(gearnvh.load(str(IDLE_RATTLE))) == cli


def test_check_gives_tier_1_no_compliance_error():
    # Tier 1 keeps only the held gear rotations: no mesh compliance, so None rather than -1.
    tiers = gearnvh.check(gearnvh.load(str(IDLE_RATTLE)))["tiers"]
    assert tiers[0]["name"] == "tier 1"
    assert tiers[0]["compliance_error_vs_full"] is None
    assert isinstance(tiers[1]["compliance_error_vs_full"], float)


def test_misalignment_sweep_through_set_and_check():
    # A sweep over f_ma and crowning, as docs/python.md shows: the face load factor grows with
    # the misalignment on the loaded pair (a uniform face gives exactly 1), and a crowning
    # relieves the loaded edge of a large one.
    gb = gearnvh.load(MINIMAL)
    gb.set("operating.torque", "100 N*m")
    factors = []
    for f in ["0 um", "2 um", "8 um", "30 um"]:
        gb.set("mesh.misalignment", f)
        face = gearnvh.check(gb)["mesh"]["face_load"]
        factors.append(face["factor"])
    assert factors[0] == 1.0
    assert factors == sorted(factors) and factors[3] > 2.0
    assert face["misalignment"]["manufacturing"] == pytest.approx(30e-6, rel=1e-12)
    gb.set("gears.pinion.lead", {"crowning": "10 um"})
    crowned = gearnvh.check(gb)["mesh"]["face_load"]
    assert crowned["model"] == "modelled"
    assert crowned["factor"] < factors[3]

"""Gear trains (schema gearnvh/2) from Python: load, set, check, simulate and sweep."""
import json
import subprocess

import numpy as np
import pytest

import gearnvh
from conftest import EXAMPLES

REDUCER = EXAMPLES / "two_stage_helical_reducer.yaml"
TRANSMISSION = EXAMPLES / "manual_transmission_idle.yaml"
RUN = {"cycles": 60, "transient": 20}


def without_timings(doc):
    for key in ("wall_s", "real_time_ratio"):
        doc["summary"].pop(key)
    return doc


@pytest.fixture(scope="module")
def transmission():
    return gearnvh.load(TRANSMISSION)


def test_a_schema_2_file_loads_as_a_train(transmission):
    assert isinstance(transmission, gearnvh.Train)
    assert transmission.meshes == ["in-l0", "l1-o1", "l2-o2", "l3-o3", "l4-o4", "l5-o5"]
    assert isinstance(gearnvh.load(EXAMPLES / "idle_rattle.yaml"), gearnvh.Gearbox)
    doc = gearnvh.check(transmission)
    assert doc["schema"] == "gearnvh/2"
    assert [m["name"] for m in doc["meshes"]] == transmission.meshes


def test_train_edits_by_path_keep_the_schema_and_a_failed_edit_changes_nothing():
    train = gearnvh.load(REDUCER)
    train.set("operating.speed.value", "1500 rpm")
    assert train.get("operating.speed.value") == "1500 rpm"
    before = train.yaml
    with pytest.raises(gearnvh.InputError) as changed:
        train.set("schema", "gearnvh/1")
    assert changed.value.path == "schema"
    with pytest.raises(gearnvh.InputError) as bad:
        train.set("meshes[0].backlash", "-1 um")
    assert bad.value.path.startswith("meshes[0].backlash")
    assert train.yaml == before


def test_simulate_gives_the_command_line_document(gearnvh_exe, transmission):
    result = gearnvh.simulate(transmission, **RUN)
    cli = json.loads(subprocess.run(
        [gearnvh_exe, "simulate", str(TRANSMISSION), "--cycles", "60", "--transient", "20",
         "--json"], check=True, capture_output=True, text=True).stdout)
    # Both call app::RunTrainOperatingPoint on the same spec through the same static library:
    # every number is equal bit for bit (tolerance 0), except the wall-clock timings.
    assert without_timings(result.to_dict()) == without_timings(cli)
    assert [m.name for m in result.meshes] == transmission.meshes
    assert result.meshes[3].te_rms == cli["meshes"][3]["te"]["rms"]
    ranked = [g.name for g in result.loose_gears]
    assert ranked == [g["name"] for g in cli["loose_gears"]]
    assert [g.rank for g in result.loose_gears] == list(range(1, len(ranked) + 1))
    assert result.ok and result.events == cli["summary"]["events"] > 0


def test_sweep_arrays_are_the_runs_at_each_speed(transmission):
    train = transmission.copy()
    train.set("analysis.speed_sweep", {"from": "700 rpm", "to": "900 rpm", "points": 2})
    sweep = gearnvh.sweep(train, jobs=1, **RUN)
    assert np.allclose(sweep.speeds_rpm, [700.0, 900.0], rtol=1e-12)
    assert sweep.te_rms.shape == (2, len(train.meshes))
    assert sweep.rattle_index.shape == (2, len(sweep.loose_gear_names))
    assert all(sweep.ok)
    # The point at 900 rpm is the same run as simulate at 900 rpm (the sweep keeps no TE series
    # for spectra, which changes no statistic): equal exactly.
    train.set("operating.speed.value", "900 rpm")
    single = gearnvh.simulate(train, **RUN)
    assert list(sweep.te_rms[1]) == [m.te_rms for m in single.meshes]
    by_name = {g.name: g.rattle_index for g in single.loose_gears}
    assert list(sweep.rattle_index[1]) == [by_name[n] for n in sweep.loose_gear_names]
    doc = sweep.to_dict()
    assert doc["schema"] == "gearnvh/2" and doc["name"] == train.name
    assert doc["tier"] == "tier 1" and doc["cycles_per_speed"] == RUN["cycles"]
    assert doc["transient_cycles"] == RUN["transient"]


def test_train_option_errors_name_the_option_and_the_progress_callback_can_stop_a_run(
        transmission):
    with pytest.raises(gearnvh.InputError):
        gearnvh.simulate(transmission, cycles=0)
    with pytest.raises(gearnvh.InputError) as method:
        gearnvh.simulate(transmission, method="v7")
    assert method.value.path == "method"
    with pytest.raises(gearnvh.InputError) as tier:
        gearnvh.simulate(transmission, tier=7)
    assert tier.value.path == "tier"
    with pytest.raises(gearnvh.InputError) as flexible:  # tier 4 needs an elastic shaft
        gearnvh.sweep(transmission, tier=4)
    assert flexible.value.path == "tier"

    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop()

    with pytest.raises(Stop):  # a million cycles would take minutes
        gearnvh.simulate(transmission, cycles=10, transient=1_000_000, progress=stop)

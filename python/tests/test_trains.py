"""Gear trains (schema gearnvh/2) from Python: load, set, check, simulate and sweep."""
import csv
import json
import subprocess

import numpy as np
import pytest

import gearnvh
from conftest import EXAMPLES, SOURCE_DIR, STRONG_RATTLE_TRAIN, interrupted_after

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
    # Both call RunTrainOperatingPoint (analysis/) on the same spec through the same static library:
    # every number is equal bit for bit (tolerance 0), except the wall-clock timings.
    assert without_timings(result.to_dict()) == without_timings(cli)
    assert [m.name for m in result.meshes] == transmission.meshes
    assert result.meshes[3].te_rms == cli["meshes"][3]["te"]["rms"]
    ranked = [g.name for g in result.loose_gears]
    assert ranked == [g["name"] for g in cli["loose_gears"]]
    assert [g.rank for g in result.loose_gears] == list(range(1, len(ranked) + 1))
    assert result.ok and result.events == cli["summary"]["events"] > 0


def test_histories_are_the_command_lines_trajectory_and_events(gearnvh_exe, tmp_path):
    # The rattling 3-mesh train: simulate(histories=True) holds what `simulate --out` writes
    # (trajectory.csv, events.csv), and without it there are none.
    loose = SOURCE_DIR / "tests" / "data" / "loose_gear_train.yaml"
    train = gearnvh.load(loose)
    assert gearnvh.simulate(train, cycles=40, transient=10).histories is None
    result = gearnvh.simulate(train, cycles=40, transient=10, histories=True)
    h = result.histories
    subprocess.run([gearnvh_exe, "simulate", str(loose), "--cycles", "40", "--transient", "10",
                    "--out", str(tmp_path / "out")], check=True, capture_output=True)
    state = {"back": 0, "free": 1, "drive": 2}
    with open(tmp_path / "out" / "trajectory.csv") as f:
        rows = list(csv.DictReader(f))
    assert h.te.shape == h.force.shape == h.contact.shape == (3, 40 * 32)
    assert len(h.time) == len(rows) == 40 * 32
    # The CSV writes 17 significant digits: the same doubles (tolerance 0; the writer forms each
    # time as start + k dt, as the binding does).
    assert np.array_equal(h.time, [float(r["time_s"]) for r in rows])
    for i, name in enumerate(train.meshes):
        assert np.array_equal(h.te[i], [float(r[name + ".te_m"]) for r in rows])
        assert np.array_equal(h.force[i], [float(r[name + ".mesh_force_n"]) for r in rows])
        assert np.array_equal(h.contact[i], [state[r[name + ".contact"]] for r in rows])
        # Apart, no force acts (state 1 is free flight).
        assert np.all(h.force[i][h.contact[i] == 1] == 0.0)
    with open(tmp_path / "out" / "events.csv") as f:
        events = list(csv.DictReader(f))
    assert len(h.event_time) == len(events) == result.to_dict()["time_histories"]["events"] > 0
    assert np.array_equal(h.event_time, [float(e["time_s"]) for e in events])
    assert [train.meshes[i] for i in h.event_mesh] == [e["mesh"] for e in events]
    assert np.array_equal(h.event_from, [state[e["from"]] for e in events])
    assert np.array_equal(h.event_to, [state[e["to"]] for e in events])
    assert np.array_equal(h.event_gap_rate, [float(e["gap_rate_m_s"]) for e in events])
    assert not h.truncated and not h.events_truncated
    assert h.coupling_twist.size == h.coupling_torque.size == 0  # the train has no coupling


def test_coupling_histories_are_the_command_lines_columns(gearnvh_exe, tmp_path):
    # The driveline example: each coupling's twist and torque at every sample, equal to
    # trajectory.csv's columns (17 digits: tolerance 0), with the exact record's mean between the
    # samples' extrema.
    driveline = EXAMPLES / "manual_transmission_driveline.yaml"
    train = gearnvh.load(driveline)
    result = gearnvh.simulate(train, cycles=20, transient=5, histories=True)
    h = result.histories
    subprocess.run([gearnvh_exe, "simulate", str(driveline), "--cycles", "20", "--transient", "5",
                    "--out", str(tmp_path / "out")], check=True, capture_output=True)
    with open(tmp_path / "out" / "trajectory.csv") as f:
        rows = list(csv.DictReader(f))
    couplings = result.to_dict()["couplings"]
    assert [c["name"] for c in couplings] == ["clutch_damper", "halfshaft"]
    assert h.coupling_twist.shape == h.coupling_torque.shape == (2, len(rows))
    for i, c in enumerate(couplings):
        name = c["name"]
        assert np.array_equal(h.coupling_twist[i], [float(r[name + ".twist_rad"]) for r in rows])
        assert np.array_equal(h.coupling_torque[i], [float(r[name + ".torque_n_m"]) for r in rows])
        assert h.coupling_twist[i].min() < c["twist_rad"]["mean"] < h.coupling_twist[i].max()


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
    # Columns follow loose_gear_names, though each run lists its gears by rank.
    energy = {g.name: g.impact_energy_per_second for g in single.loose_gears}
    assert list(sweep.impact_energy_per_second[1]) == [energy[n] for n in sweep.loose_gear_names]
    ranked = sorted((g for g in single.loose_gears if g.rank > 0), key=lambda g: g.rank)
    assert [g.impact_energy_per_second for g in ranked] == sorted(
        (g.impact_energy_per_second for g in ranked), reverse=True)
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

    # 20000 cycles take about 30 s; the first progress call, after 1 % of them, stops the run.
    # (A transient of a million cycles took 35 s to the first progress call, its first 64 cycles:
    # most likely building the cycle map of certified jumps, which is not interrupted.)
    with pytest.raises(Stop):
        gearnvh.simulate(transmission, cycles=10, transient=20_000, progress=stop)


# Atlas, orbits, tiers, validate and Lyapunov on a train. LINEAR is a two-shaft train whose one
# mesh has a constant stiffness (a Fourier model with its mean only) and a load that keeps it in
# drive contact: a linear time-invariant system with one elastic mode, so its numbers have closed
# forms. With the effective mass m_e = 1 / (r_a^2 / J_a + r_b^2 / J_b) (base radii, body
# inertias), the mode decays at the rate zeta * omega, omega = sqrt(k / m_e) (the mesh damping is
# c = 2 zeta sqrt(k m_e)), and the engine order drives the TE, delta = r_a th_a + r_b th_b, as
# m_e delta'' + c delta' + k delta = m_e r_a s(t), s the input's angular acceleration.
LINEAR_FILE = SOURCE_DIR / "tests" / "data" / "linear_train.yaml"  # shared with the C++ tests
LINEAR = LINEAR_FILE.read_text()
STIFFNESS = 2e8  # N/m
ZETA = 0.02
ORDER, ACCELERATION = 2.0, 200.0  # the engine order and its amplitude, rad/s^2


@pytest.fixture(scope="module")
def linear_file():
    return LINEAR_FILE


def linear_mode(train):
    """(m_e, omega, base radius of the input gear) of the linear train from its check document
    (body inertias and the base pitch: inputs of the model, not results)."""
    doc = gearnvh.check(train)
    inertia = {b["name"]: b["polar_inertia"] for b in doc["bodies"]}
    base_pitch = doc["meshes"][0]["geometry"]["base_pitch"]
    r_a, r_b = 20 * base_pitch / (2 * np.pi), 40 * base_pitch / (2 * np.pi)
    m_e = 1.0 / (r_a**2 / inertia["input"] + r_b**2 / inertia["output"])
    return m_e, np.sqrt(STIFFNESS / m_e), r_a


def decay_rate(train, zeta=ZETA):
    _, omega, _ = linear_mode(train)
    return zeta * omega


def steady_te_rms(train, speed_rad_s):
    """RMS of the linear steady-state TE under the engine order (a sinusoid)."""
    m_e, _, r_a = linear_mode(train)
    forcing = ORDER * speed_rad_s
    damping = 2 * ZETA * np.sqrt(STIFFNESS * m_e)
    amplitude = m_e * r_a * ACCELERATION / np.hypot(STIFFNESS - m_e * forcing**2,
                                                    damping * forcing)
    return amplitude / np.sqrt(2)


def cli_json(gearnvh_exe, *args):
    out = subprocess.run([gearnvh_exe, *map(str, args), "--json"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_lyapunov_of_a_linear_train_is_its_decay_rate(gearnvh_exe, linear_file):
    train = gearnvh.load(linear_file)
    r = gearnvh.simulate(train, lyapunov=2)
    assert r.ok and r.events == 0  # never leaves drive contact
    rate = decay_rate(train)
    # One complex pair of eigenvalues -zeta omega +- i omega_d: both exponents are -zeta omega.
    # Tolerance: 3 block standard errors, or 1e-3 of the rate (Benettin's finite-time error for a
    # rotating pair, ~1 / (omega T) per block, is below that over 400 mesh cycles).
    for lam, se in zip(r.lyapunov.exponents, r.lyapunov.standard_errors):
        assert abs(lam + rate) <= max(3 * se, 1e-3 * rate)
    assert r.lyapunov.predictability_horizon_s == np.inf
    # The TE: the linear steady state. The solver carries the engine order exactly (an exosystem):
    # measured 4.2e-12 apart (3.3e-5 while the order was held per segment); tolerance 1e-9 for
    # the transient's remainder and rounding.
    speed = 3000 * 2 * np.pi / 60
    assert r.meshes[0].te_rms == pytest.approx(steady_te_rms(train, speed), rel=1e-9)
    assert r.meshes[0].separation_fraction == 0.0
    # The same document as `simulate --lyapunov 2 --json`: both call PlanTrainSimulate,
    # RunTrainOperatingPoint and RunTrainLyapunov; equal bit for bit but for the timings.
    cli = cli_json(gearnvh_exe, "simulate", linear_file, "--lyapunov", "2")
    doc = r.to_dict()
    doc["file"] = cli["file"]
    assert without_timings(doc) == without_timings(cli)
    assert doc["lyapunov"]["exponents_per_s"] == list(r.lyapunov.exponents)


def test_a_train_atlas_axis_of_one_point_is_refused(linear_file):
    # The rule of analysis.atlas axes, as on the command line: at least 2 points.
    with pytest.raises(gearnvh.InputError) as bad:
        gearnvh.atlas(gearnvh.load(linear_file), x="operating.speed=2500rpm:3500rpm:1",
                      y="meshes[0].damping_ratio=0.02:0.04:2", cycles=20, transient=20, jobs=1)
    assert "POINTS" in str(bad.value) and "analysis.atlas axes" in str(bad.value)


def test_atlas_of_a_linear_train_has_no_rattle_and_the_decay_rate(gearnvh_exe, linear_file):
    train = gearnvh.load(linear_file)
    args = dict(x="operating.speed=2500rpm:3500rpm:2", y="meshes[0].damping_ratio=0.02:0.04:2",
                cycles=200, transient=300, jobs=1)
    seen = []
    a = gearnvh.atlas(train, progress=lambda done, total: seen.append((done, total)), **args)
    assert seen[-1] == (4, 4) and a.failed == 0
    assert a.x_parameter == "operating.speed" and a.y_parameter == "meshes[0].damping_ratio"
    assert np.allclose(a.y, [0.02, 0.04], rtol=1e-12)
    assert a.mesh_names == ["g1-g2"] and a.loose_gear_names == []
    # Permanent contact: no impact and no separation in any cell, on the train and its mesh.
    assert a.regime == [["no impact"] * 2] * 2 and a.mesh_regime == [a.regime]
    assert not a.drive_impacts_per_cycle.any() and not a.back_impacts_per_cycle.any()
    assert not a.separation_fraction.any()
    # The largest exponent is -zeta omega: omega does not depend on the speed, zeta is the row's
    # (tolerance as the Lyapunov test's).
    for iy, zeta in enumerate(a.y):
        rate = decay_rate(train, zeta)
        for ix in range(2):
            cell = a.cell(ix, iy)
            assert cell.lyapunov_per_s == a.lyapunov_per_s[iy, ix]
            assert abs(cell.lyapunov_per_s + rate) <= max(3 * cell.lyapunov_standard_error,
                                                          1e-3 * rate)
            assert cell.meshes[0].name == "g1-g2" and cell.meshes[0].regime == "no impact"
    cli = cli_json(gearnvh_exe, "atlas", linear_file, "--x", args["x"], "--y", args["y"],
                   "--cycles", 200, "--transient", 300, "--jobs", 1)
    doc = a.to_dict()
    # RunTrainAtlas on the same plan: every cell equal bit for bit but its wall time.
    for d in (doc, cli):
        d.pop("wall_s"), d.pop("file")
        for c in d["cells"]:
            c.pop("wall_s")
    assert doc == cli


def test_orbit_multipliers_of_a_linear_train_are_its_decay_over_the_period(gearnvh_exe,
                                                                            linear_file):
    train = gearnvh.load(linear_file)
    o = gearnvh.orbits(train, transient=50)
    assert o.parameter == "operating point" and len(o.points) == 1
    p = o.points[0]
    assert p.found and p.stable and p.events_per_period == 0
    # Linear and time-invariant: the multipliers are exp(lambda T) of the complex pair, so both
    # have modulus exp(-zeta omega T). Tolerance 1e-9: Newton's monodromy is exact to rounding.
    expected = np.exp(-decay_rate(train) * p.period_s)
    assert len(p.multipliers) == 2
    assert np.allclose(np.abs(p.multipliers), expected, rtol=1e-9, atol=0)
    assert p.spectral_radius == pytest.approx(expected, rel=1e-9)
    cli = cli_json(gearnvh_exe, "orbits", linear_file, "--transient", 50)
    doc = o.to_dict()
    doc["file"] = cli["file"]
    assert doc == cli  # the same RunTrainOrbits: no timing in the document


def test_tier_1_of_a_linear_train_is_its_steady_state(linear_file):
    train = gearnvh.load(linear_file)
    t = gearnvh.tiers(train, cycles=100, transient=300)
    assert t.names[0] == "tier 1" and t.mesh_names == ["g1-g2"]
    assert t.te_rms.shape == (len(t.names), 1) and t.rattle_index.shape == (len(t.names), 0)
    # Tier 1 (one body per shaft) is the linear train of the closed form (tolerance as the
    # Lyapunov test's); the differences are |TE RMS - finest| / finest.
    speed = 3000 * 2 * np.pi / 60
    assert t.te_rms[0, 0] == pytest.approx(steady_te_rms(train, speed), rel=1e-4)
    finest = t.te_rms[t.names.index(t.finest), 0]
    assert np.allclose(t.te_rms_difference[:, 0], np.abs(t.te_rms[:, 0] - finest) / finest,
                       rtol=1e-12, atol=0)


# LINEAR with a loose gear g4 on the output, driven by g3 on the input against its drag.
LOOSE = LINEAR.replace("name: Linear two-shaft train", "name: Two shafts and a loose gear").replace(
    "meshes:\n", """  g3: {shaft: input, teeth: 30, module: 2 mm, face_width: 12 mm, bore_diameter: 20 mm, material: steel}
  g4: {shaft: output, mounting: loose, teeth: 30, module: 2 mm, face_width: 12 mm,
       bore_diameter: 20 mm, material: steel}
meshes:
  - {gears: [g3, g4], backlash: 80 um, damping_ratio: 0.02,
     stiffness: {model: fourier, fourier: {mean: 1.5e8 N/m}}}
""").replace("    - {on: output, torque: 20 N*m}\n",
             "    - {on: output, torque: 20 N*m}\n    - {on: g4, torque: 0.05 N*m}\n")


def test_tiers_of_a_train_with_a_loose_gear_are_the_command_lines(gearnvh_exe, tmp_path):
    path = tmp_path / "loose.yaml"
    path.write_text(LOOSE)
    t = gearnvh.tiers(gearnvh.load(path), cycles=60, transient=20)
    assert t.mesh_names == ["g3-g4", "g1-g2"] and t.loose_gear_names == ["g4"]
    cli = cli_json(gearnvh_exe, "tiers", path, "--cycles", 60, "--transient", 20)
    # CompareTrainTiers on the same plan: equal bit for bit but for the timings.
    assert t.names == [row["name"] for row in cli["tiers"]] and t.finest == cli["finest_tier"]
    for i, row in enumerate(cli["tiers"]):
        assert list(t.te_rms[i]) == [m["te_rms_m"] for m in row["meshes"]]
        assert list(t.rattle_index[i]) == [g["rattle_index"] for g in row["loose_gears"]]
        assert t.dof[i] == row["dof"] and t.state_dim[i] == row["state_dim"]
    doc = t.to_dict()
    for d in (doc, cli):
        d.pop("file")
        for row in d["tiers"]:
            row.pop("us_per_cycle"), row.pop("real_time_ratio")
    assert doc == cli


def test_validate_a_train_as_the_command_line(gearnvh_exe, transmission):
    v = gearnvh.validate(transmission)
    cli = subprocess.run([gearnvh_exe, "validate", str(TRANSMISSION), "--json"],
                         capture_output=True, text=True)
    doc = json.loads(cli.stdout)
    assert v.passed == doc["pass"] == (cli.returncode == 0)
    assert [c.name for c in v.checks] == [c["name"] for c in doc["checks"]]
    # The ladder's own rows compare V3 with CVODE and with V2 and V1 (docs/cli.md): each value
    # is a measured difference against its stated threshold.
    for c in v.checks:
        assert c.skipped or c.passed == (c.value <= c.threshold)
    d = v.to_dict()
    d["file"] = doc["file"]
    assert d == doc


def test_validate_compares_fusion_with_stepping(gearnvh_exe, linear_file):
    # The linear train stays in drive contact: segment-run fusion certifies its runs, each equal to
    # the same grid segments stepped to within the row's 3e-11 of the TE (docs/cli.md).
    v = gearnvh.validate(gearnvh.load(linear_file))
    fusion = [c for c in v.checks if "segment-run fusion vs step by step" in c.name]
    assert len(fusion) == 1
    row = fusion[0]
    assert not row.skipped and row.passed and row.threshold == 3e-11 and row.value <= 3e-11
    cli = subprocess.run([gearnvh_exe, "validate", str(linear_file), "--json"],
                         capture_output=True, text=True)
    doc = json.loads(cli.stdout)
    assert [c for c in doc["checks"] if c["name"] == row.name][0]["value"] == row.value


def test_train_analyses_name_the_keyword_value_and_rule(transmission, linear_file):
    train = gearnvh.load(linear_file)
    with pytest.raises(gearnvh.InputError) as few:
        gearnvh.atlas(train, x="operating.speed=2500rpm:3500rpm:2",
                      y="meshes[0].damping_ratio=0.02:0.04:2", cycles=4)
    assert (few.value.path, few.value.value, few.value.rule) == ("cycles", "4", "must be >= 8")
    with pytest.raises(gearnvh.InputError) as schema1:  # a schema-1 name on a train
        gearnvh.atlas(train, x="mesh.backlash=50um:100um:2", y="operating.speed=1rpm:2rpm:2")
    assert schema1.value.path == "x" and "mesh.backlash" in str(schema1.value)
    with pytest.raises(gearnvh.InputError) as axes:
        gearnvh.atlas(train)
    assert axes.value.path == "analysis.atlas" and "x and y" in axes.value.rule
    with pytest.raises(gearnvh.InputError) as period:
        gearnvh.orbits(train, period=0)
    assert (period.value.path, period.value.value) == ("period", "0")
    with pytest.raises(gearnvh.InputError) as long_period:  # the CLI's --period limit
        gearnvh.orbits(train, period=65)
    assert (long_period.value.path, long_period.value.rule) == ("period", "must be in [1, 64]")
    with pytest.raises(gearnvh.InputError) as index:
        gearnvh.orbits(train, sweep="meshes[3].backlash=50um:100um:3")
    assert index.value.path == "sweep"
    with pytest.raises(gearnvh.InputError) as many:  # 2 bodies: 2n - 2 = 2 exponents
        gearnvh.simulate(train, lyapunov=3)
    assert many.value.path == "lyapunov" and "2n - 2 = 2" in many.value.rule
    with pytest.raises(gearnvh.InputError) as long_run:  # beyond the 3600 s run-length limit
        gearnvh.tiers(transmission, transient=10**9)
    assert long_run.value.path == "transient"


@pytest.mark.parametrize("analysis", ["atlas", "orbits"])
def test_ctrl_c_interrupts_train_analyses(transmission, analysis):
    # A transient of 900000 cycles (about an hour of simulated time) would take hours: SIGINT
    # sets the cancel flag the train stepper polls at every grid segment. (Without cancellation
    # this test would run into ctest's timeout.)
    with interrupted_after(0.5):
        if analysis == "atlas":
            gearnvh.atlas(transmission, x="operating.loads[2].torque=0.1Nm:0.2Nm:2",
                          y="meshes[2].backlash=80um:120um:2", cycles=10, transient=900_000,
                          jobs=1)
        else:
            gearnvh.orbits(transmission, transient=900_000)


def test_a_progress_exception_stops_the_lyapunov_run(linear_file):
    class Stop(Exception):
        pass

    calls = []

    def stop_in_the_second_run(done, total):
        calls.append((done, total))
        if done > 1000:  # thousandths: the operating point is 0..1000, the Lyapunov run beyond
            raise Stop()

    with pytest.raises(Stop):
        gearnvh.simulate(gearnvh.load(linear_file), cycles=20_000, transient=10, lyapunov=1,
                         progress=stop_in_the_second_run)
    assert all(total == 2000 for _, total in calls)


# The C++ tests' rattling 3-mesh train (tests/app/loose_gear_train_yaml.h) with its loose gear f
# at 1e-15 kg m^2.
TINY_LOOSE_GEAR = (SOURCE_DIR / "tests" / "data" / "loose_gear_train.yaml").read_text().replace(
    "bore_diameter: 30 mm, material: steel}",
    "bore_diameter: 30 mm, material: steel, inertia: 1e-15 kg*m^2}")
assert "inertia: 1e-15" in TINY_LOOSE_GEAR


def test_a_run_estimated_above_an_hour_is_refused_at_allow_slow(tmp_path):
    # The loose gear f at 1e-15 kg m^2 has a ~1e10 rad/s mode: hours of sub-steps (docs/cli.md,
    # "Run cost"). Every train analysis refuses before it runs, naming the keyword that allows it.
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY_LOOSE_GEAR)
    train = gearnvh.load(path)
    calls = {
        "simulate": lambda **k: gearnvh.simulate(train, **k),
        "sweep": lambda **k: gearnvh.sweep(train, **k),
        "tiers": lambda **k: gearnvh.tiers(train, **k),
        "atlas": lambda **k: gearnvh.atlas(train, x="operating.speed=900rpm:1000rpm:2",
                                           y="meshes[2].backlash=80um:100um:2", **k),
        "validate": lambda **k: gearnvh.validate(train, **k),
    }
    for name, call in calls.items():
        with pytest.raises(gearnvh.InputError) as refused:
            call()
        assert refused.value.path == "allow_slow", name
        assert "without allow_slow" in refused.value.rule, name
        # The body and its own inertia, at every tier (tiers' costliest run is tier 3).
        assert "body f, inertia 1e-15 kg m²" in refused.value.rule, name


def test_whine_gives_the_command_line_document_on_a_train_and_a_pair(gearnvh_exe):
    # Both call RunWhine (analysis/) on the same spec through the same static library: every
    # number is equal bit for bit (tolerance 0).
    for path, tier in ((REDUCER, 3), (EXAMPLES / "industrial_whine.yaml", 1)):
        w = gearnvh.whine(gearnvh.load(path), tier=tier, speeds=30)
        cli = json.loads(subprocess.run(
            [gearnvh_exe, "whine", str(path), "--tier", str(tier), "--speeds", "30", "--json"],
            check=True, capture_output=True, text=True).stdout)
        assert w.to_dict() == cli
        assert w.speeds_rpm.shape == (30,)
        assert list(w.orders) == [line["order"] for line in cli["lines"]]
        for i, mesh in enumerate(cli["meshes"]):
            te = w.te_amplitude_m(mesh["name"])
            assert te.shape == (len(cli["lines"]), 30)
            assert np.array_equal(te, [o["te_amplitude_m"] for o in mesh["orders"]])
            assert np.array_equal(w.force_amplitude_n(i),
                                  [o["force_amplitude_n"] for o in mesh["orders"]])
            assert list(w.contact_loss(i)) == mesh["contact_loss"]
    with pytest.raises(gearnvh.InputError) as bad:
        gearnvh.whine(gearnvh.load(REDUCER), speeds=1)
    assert bad.value.path == "speeds"
    with pytest.raises(KeyError):
        gearnvh.whine(gearnvh.load(REDUCER), speeds=2).te_amplitude_m("no such mesh")


def test_whine_reads_a_housing_table_as_the_command_line(gearnvh_exe, tmp_path):
    table = tmp_path / "housing.csv"
    table.write_text("frequency_hz,bearing,direction,real,imag\n"
                     "0,input.bearings[0],x,1e-3,0\n10000,input.bearings[0],x,1e-3,0\n")
    w = gearnvh.whine(gearnvh.load(REDUCER), tier=3, speeds=5, housing=str(table))
    cli = json.loads(subprocess.run(
        [gearnvh_exe, "whine", str(REDUCER), "--tier", "3", "--speeds", "5", "--housing",
         str(table), "--json"], check=True, capture_output=True, text=True).stdout)
    assert w.to_dict() == cli
    assert cli["housing"]["orders"][0]["acceleration_m_s2"][0] > 0
    table.write_text("frequency_hz,bearing,direction,real,imag\n0,input.bearings[0],q,1,0\n")
    with pytest.raises(gearnvh.InputError) as bad:
        gearnvh.whine(gearnvh.load(REDUCER), tier=3, speeds=2, housing=str(table))
    assert bad.value.path == "direction"


def test_tiers_of_a_train_keep_the_others_when_one_stops():
    t = gearnvh.tiers(gearnvh.load(str(STRONG_RATTLE_TRAIN)), cycles=300, transient=100)
    assert [name for name, ok in zip(t.names, t.ok) if not ok] == ["tier 2", "tier 3"]
    assert t.failed == 2
    assert t.statuses[1] == "out of range"
    assert "on mesh pinion-wheel" in t.messages[1]
    assert np.isnan(t.te_rms[1, 0]) and t.te_rms[0, 0] > 0
    assert t.finest == "N40 full"
    assert t.to_dict()["tiers"][1]["meshes"][0]["te_rms_m"] is None

"""gearnvh.simulate: the same numbers as `gearnvh simulate --json`, NumPy views, Ctrl-C."""
import json
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import gearnvh
from conftest import EXAMPLES, IDLE_RATTLE, strong_rattle_file

RUN = dict(tier=1, cycles=200, transient=50)


def without_timings(doc):
    doc = json.loads(json.dumps(doc))
    for key in ("wall_s", "real_time_ratio"):  # wall-clock, differs from run to run
        doc["summary"].pop(key)
    return doc


@pytest.fixture(scope="module")
def result():
    return gearnvh.simulate(gearnvh.load(str(IDLE_RATTLE)), **RUN)


def test_same_document_as_the_command_line(gearnvh_exe, result):
    cli = json.loads(subprocess.run(
        [gearnvh_exe, "simulate", str(IDLE_RATTLE), "--tier", "1", "--cycles", "200",
         "--transient", "50", "--json"], check=True, capture_output=True, text=True).stdout)
    # Both call app::AnalyseOperatingPoint on the same spec through the same static library:
    # every number is equal bit for bit (tolerance 0), except the wall-clock timings.
    assert without_timings(result.to_dict()) == without_timings(cli)
    assert result.te.rms == cli["te"]["rms"]
    assert result.te.peak_to_peak == cli["te"]["peak_to_peak"]
    assert result.summary.events == cli["summary"]["events"]


def test_attributes_are_si_floats_and_views(result):
    assert isinstance(result.te.rms, float) and result.te.rms > 0.0
    assert result.te.peak_to_peak >= 2 * result.te.rms * 0.99  # p-p >= 2 RMS for any signal
    assert result.summary.real_time_ratio > 0.0
    assert result.summary.status == "success" and result.ok
    t = result.trajectory
    n = result.cycles * 32
    assert len(t) == n and t.time.shape == (n,) and t.te.shape == (n,) and t.force.shape == (n,)
    # Views into the C++ samples: no copy, read-only, kept alive by the result.
    assert not t.te.flags.owndata and not t.te.flags.writeable
    assert t.time.strides[0] > 8  # strided over the sample structs
    # The exact statistics and the samples agree: RMS of the samples about their mean matches the
    # exact time-integral RMS to the sampling error of 32 samples per mesh cycle (1 %).
    sampled = float(np.sqrt(np.mean((t.te - t.te.mean()) ** 2)))
    assert sampled == pytest.approx(result.te.rms, rel=1e-2)
    # Uniform sampling: 32 per mesh period.
    dt = np.diff(t.time)
    assert np.allclose(dt, dt[0], rtol=1e-9)
    assert set(np.unique(t.contact)) <= {0, 1, 2}
    assert len(result.trajectory.event_time) == result.summary.events
    assert result.spectrum.amplitude.shape == result.spectrum.frequency_hz.shape
    assert result.rattle.regime in ("no impact", "single-sided", "double-sided")
    assert result.rattle_index >= 0.0


def test_views_outlive_the_result():
    r = gearnvh.simulate(gearnvh.load(str(IDLE_RATTLE)), tier=1, cycles=20, transient=0)
    te, expected = r.trajectory.te, r.trajectory.te.copy()
    del r
    assert np.array_equal(te, expected)


def test_solver_option_errors_name_the_option():
    gb = gearnvh.load(str(IDLE_RATTLE))
    with pytest.raises(gearnvh.InputError) as tier:
        gearnvh.simulate(gb, tier=9)
    assert tier.value.path == "tier"
    assert tier.value.source == str(IDLE_RATTLE)  # as every other keyword's error
    with pytest.raises(gearnvh.InputError) as method:
        gearnvh.simulate(gb, method="v9")
    assert method.value.path == "method"
    with pytest.raises(gearnvh.InputError) as cycles:
        gearnvh.simulate(gb, cycles=0)
    assert cycles.value.source == str(IDLE_RATTLE)
    # The library checks the run length (SolverOptions); the module names its keyword.
    assert (cycles.value.path, cycles.value.value, cycles.value.rule) == ("cycles", "0",
                                                                          "must be >= 1")
    with pytest.raises(gearnvh.InputError) as transient:
        gearnvh.simulate(gb, transient=-1)
    assert (transient.value.path, transient.value.value) == ("transient", "-1")
    # A tier the model cannot have (idle_rattle has rigid shafts): the keyword, its tier, the rule.
    with pytest.raises(gearnvh.InputError) as flexible:
        gearnvh.simulate(gb, tier=5)
    assert flexible.value.path == "tier" and flexible.value.value == "N40 full"
    assert flexible.value.rule.startswith("needs flexible shafts")


def test_counts_beyond_the_command_lines_limits_are_refused_before_any_work():
    # The command line refuses these (--cycles at most 1e6, cycles + transient at most 3600 s of
    # simulated time); the module ran them: cycles=10**12 hung allocating 32 samples per cycle.
    gb = gearnvh.load(str(IDLE_RATTLE))  # 27 teeth at 800 rpm: 360 mesh cycles per second
    with pytest.raises(gearnvh.InputError) as recorded:
        gearnvh.simulate(gb, cycles=10**12)
    assert (recorded.value.path, recorded.value.value) == ("cycles", "1000000000000")
    assert recorded.value.rule.startswith("must be <= 1000000")
    assert recorded.value.source == str(IDLE_RATTLE)
    calls = [
        ("simulate", {"transient": 10**9}, "transient"),
        ("sweep", {"cycles": 10**12}, "cycles"),
        ("atlas", {"transient": 10**10, "x": "operating.speed=600rpm:3000rpm:2",
                   "y": "operating.torque=0.1Nm:1Nm:2"}, "transient"),
        ("orbits", {"transient": 10**10}, "transient"),
        ("tiers", {"cycles": 10**9}, "cycles"),
    ]
    for name, kwargs, keyword in calls:
        with pytest.raises(gearnvh.InputError) as length:
            getattr(gearnvh, name)(gb, **kwargs)
        assert length.value.path == keyword, name
        assert "the limit is 3600 s" in length.value.rule, name
    # 1300 s at 360 Hz is within the limit: only the recorded cycles' bound applies.
    with pytest.raises(gearnvh.InputError) as within:
        gearnvh.simulate(gb, cycles=1000001, transient=0)
    assert within.value.rule.startswith("must be <= 1000000")


def test_progress_callback_sees_the_run_and_can_stop_it():
    gb = gearnvh.load(str(IDLE_RATTLE))
    seen = []
    r = gearnvh.simulate(gb, tier=1, cycles=600, transient=0, method="v3",
                         progress=lambda done, total: seen.append((done, total)))
    # Totals are the cycles as run (rounded up to whole periods of the engine order).
    assert seen and all(total == r.cycles for _, total in seen)
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    assert seen[-1][0] == r.cycles  # the last call reports the end

    class Stop(Exception):
        pass

    def stop(done, total):
        raise Stop()

    # 1.2 million cycles (3333 s simulated, under the 3600 s limit) would take minutes.
    with pytest.raises(Stop):
        gearnvh.simulate(gb, tier=1, cycles=10, transient=1_200_000, method="v3", progress=stop)


def test_ctrl_c_interrupts_a_long_run():
    gb = gearnvh.load(str(IDLE_RATTLE))
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signals reach the main thread only")
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        # 1.2 million mesh cycles would take minutes; SIGINT stops the run at the next cycle.
        with pytest.raises(KeyboardInterrupt):
            gearnvh.simulate(gb, tier=1, cycles=10, transient=1_200_000, method="v3")
    finally:
        timer.cancel()


def test_simulate_checks_memory_as_the_command_line(monkeypatch):
    # A pair's and a train's run estimated above the memory limit are refused before they run, at
    # the keyword that set the recorded cycles (or the file's analysis.cycles), naming the limit
    # (docs/cli.md, "Memory"). 1 MB holds neither run's recorded samples.
    monkeypatch.setenv("GEARNVH_MEMORY_LIMIT", "1000000")
    pair = gearnvh.load(str(IDLE_RATTLE))
    train = gearnvh.load(str(EXAMPLES / "manual_transmission_idle.yaml"))
    for model in (pair, train):
        with pytest.raises(gearnvh.InputError) as refused:
            gearnvh.simulate(model, tier=1, cycles=2000, transient=10)
        assert refused.value.path == "cycles"
        assert refused.value.value == "2000"
        assert "GEARNVH_MEMORY_LIMIT" in refused.value.rule
        with pytest.raises(gearnvh.InputError) as from_file:
            gearnvh.simulate(model, tier=1, transient=10)
        assert from_file.value.path == "analysis.cycles"
    # Within the limit the same call runs.
    monkeypatch.setenv("GEARNVH_MEMORY_LIMIT", str(8 << 30))
    assert gearnvh.simulate(pair, tier=1, cycles=50, transient=10).summary.events >= 0


def test_cycles_of_a_stopped_run_are_those_recorded(tmp_path):
    gb = gearnvh.load(str(strong_rattle_file(tmp_path)))
    r = gearnvh.simulate(gb, tier=2, cycles=500, transient=50)
    assert not r.ok
    assert r.summary.status == "out_of_range"
    # Stopped after ~92 of the 550 cycles: ~42 recorded, not the 500 asked for.
    assert r.cycles == r.summary.mesh_cycles - 50
    assert 0 < r.cycles < 500

"""Fleet processing on Dask (fusion_altitude.fleet, ``fusion-altitude fleet``).

A fleet of 42 logs is built in a temporary directory from the shared real
logs (FUSION_ALTITUDE_SHARED_DATA, else ../shared/data; missing data fails)
and from the simulator: PX4 ULog, ArduPilot DataFlash, CSV windows of the
Hedy rocket flight, simulated CSV flights, and two corrupt logs. It runs on
a 2-worker LocalCluster (threads, one process) except where a worker process
has to be killed.
"""

import io
import json
import os
import shutil
import signal
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest

import distributed  # noqa: E402
import pyarrow.parquet as pq  # noqa: E402

from fusion_altitude import runner  # noqa: E402
from fusion_altitude import cli, fleet, tuning  # noqa: E402
from fusion_altitude.scenarios import run_scenario  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CSV_OPTIONS = dict(time_column="t", accel_column="accel", baro_column="baro", reference_column="ref")
CSV_FLAGS = ["--time", "t", "--accel", "accel", "--baro", "baro"]
GRAVITY = 9.80665


@pytest.fixture(scope="module")
def data_dir():
    path = Path(os.environ.get("FUSION_ALTITUDE_SHARED_DATA", ROOT / ".." / "shared" / "data"))
    assert path.is_dir(), f"shared data not found at {path}: set FUSION_ALTITUDE_SHARED_DATA"
    return path


def _write_csv(path, time, accel, baro, reference):
    table = np.column_stack([time, accel, baro, reference])
    np.savetxt(path, table, delimiter=",", header="t,accel,baro,ref", comments="", fmt="%.9g")


@pytest.fixture(scope="module")
def fleet_dir(tmp_path_factory, data_dir):
    """42 logs in nested directories: 6 ULog, 6 DataFlash, 12 Hedy CSV (the first 10 to 120 s of the flight),
    16 simulated CSV, 2 corrupt."""
    root = tmp_path_factory.mktemp("fleet")
    for k in range(6):
        (root / "px4" / f"day{k % 2}").mkdir(parents=True, exist_ok=True)
        shutil.copyfile(data_dir / "px4_sample_log_small.ulg", root / "px4" / f"day{k % 2}" / f"flight{k}.ulg")
        (root / "ardupilot").mkdir(exist_ok=True)
        shutil.copyfile(data_dir / "ardupilot_test.BIN", root / "ardupilot" / f"plane{k}.BIN")
    baro = np.genfromtxt(data_dir / "hedy_baro.csv", delimiter=",", names=True)
    imu = np.genfromtxt(data_dir / "hedy_imu.csv", delimiter=",", names=True)
    info = np.genfromtxt(data_dir / "hedy_flight_info.csv", delimiter=",", names=True)
    time = imu["ts"]
    accel = -imu["Ay"] - GRAVITY  # long axis = sensor Y, pointing down the rail: a crude vertical acceleration
    altitude = 44330.0 * (1.0 - (np.interp(time, baro["ts"], baro["P"]) / 101325.0) ** 0.190263)
    reference = np.interp(time, info["ts"], info["height"]) + altitude[0]
    (root / "hedy").mkdir()
    for k, seconds in enumerate(np.linspace(10.0, 120.0, 12)):  # the first 10 ... 120 s, all from the pad
        keep = time <= time[0] + seconds
        _write_csv(root / "hedy" / f"hedy_part{k:02d}.csv", time[keep], accel[keep], altitude[keep], reference[keep])
    (root / "sim").mkdir()
    for seed in range(16):
        result = run_scenario("realistic" if seed % 2 else "climb-cruise-descend", seed=seed)
        _write_csv(root / "sim" / f"sim{seed:02d}.csv", result.time, result.vertical_acceleration,
                   result.baro_altitude, result.trajectory.altitude)
    (root / "bad").mkdir()
    (root / "bad" / "truncated.ulg").write_bytes((data_dir / "px4_sample_log_small.ulg").read_bytes()[:3000])
    lines = (root / "sim" / "sim00.csv").read_text().splitlines()
    lines[50] = "0.49,0.1,garbage,1.0"
    (root / "bad" / "garbled.csv").write_text("\n".join(lines) + "\n")
    return root


@pytest.fixture(scope="module")
def cluster():
    """A 2-worker LocalCluster in this process, on TCP so the CLI can connect with --scheduler."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp",
                                  dashboard_address=":0", silence_logs=40) as local:
        yield local


@pytest.fixture(scope="module")
def client(cluster):
    with distributed.Client(cluster) as connected:
        yield connected


@pytest.fixture(scope="module")
def first_run(fleet_dir, client, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    return fleet.run_many(str(fleet_dir), client=client, output_dir=str(out), csv_options=CSV_OPTIONS,
                          write_csv=True)


def _single_log_columns(path):
    """The columns of a single-log run, computed here without Dask."""
    options = CSV_OPTIONS if path.endswith(".csv") else {}
    return fleet.run_columns(runner.run_log(fleet.read_log(path, options), estimator="observer",
                                               settings=fleet.resolve_settings("observer", None)))


def _bits(values):
    values = np.ascontiguousarray(values)
    if values.dtype.kind in "iub":  # integer columns (the flags) compare as they are
        return values.astype(np.int64)
    return values.view(np.uint32 if values.dtype == np.float32 else np.uint64)


def _good_paths(first_run):
    return [row["path"] for row in first_run.summary.to_pylist() if row["status"] == "ok"]


def _file_states(directory):
    """{path: (mtime ns, bytes)} of the finished files (a write in flight on another worker, a temporary file
    (``fleet._is_temporary``: ``.NAME.XXXX.part.EXT``), is not a result yet: it is renamed into place or removed)."""
    states = {}
    for path in Path(directory).rglob("*"):
        try:
            if path.is_file() and not fleet._is_temporary(path.name):
                states[path] = (path.stat().st_mtime_ns, path.read_bytes())
        except FileNotFoundError:  # renamed away between the listing and the read
            pass
    return states


# ----------------------------------------------------------------------------
# run_many


def test_fleet_has_at_least_40_logs_of_four_formats(first_run):
    sources = [row["source"] for row in first_run.summary.to_pylist() if row["status"] == "ok"]
    assert first_run.summary.num_rows == 42
    assert {source.rsplit("(", 1)[-1] for source in sources} == {"PX4 ULog)", "ArduPilot DataFlash)", "CSV)"}
    assert sum("hedy_part" in source for source in sources) == 12


def test_every_good_log_equals_its_single_log_run_bit_for_bit(first_run):
    good = _good_paths(first_run)
    assert len(good) == 40
    for path in good:
        table = pq.read_table(Path(first_run.output_dir) / "logs" / f"{fleet.log_id(path)}.parquet")
        expected = _single_log_columns(path)
        assert table.column_names == ["log_id"] + [name for name, _ in expected], path
        for name, values in expected:
            stored = table.column(name).to_numpy()
            assert stored.dtype == values.dtype, (path, name)
            np.testing.assert_array_equal(_bits(stored), _bits(values), err_msg=f"{path}: {name}")
        assert set(table.column("log_id").to_pylist()) == {fleet.log_id(path)}


@pytest.mark.parametrize("estimator", [  # the INS needs raw gyro + accel; the rocket estimator is for rocket logs
    entry.name for entry in runner.ESTIMATORS.values() if not entry.needs and not entry.vehicle])
def test_every_estimator_of_this_build_equals_its_single_log_run(estimator, fleet_dir, client, tmp_path):
    logs = [fleet_dir / "px4" / "day1" / "flight3.ulg", fleet_dir / "ardupilot" / "plane2.BIN",
            fleet_dir / "sim" / "sim10.csv"]
    result = fleet.run_many([str(path) for path in logs], estimator=estimator, client=client,
                            output_dir=str(tmp_path), csv_options=CSV_OPTIONS)
    assert result.failed == [] and set(result.summary.column("estimator").to_pylist()) == {estimator}
    for path in map(str, logs):
        table = pq.read_table(tmp_path / "logs" / f"{fleet.log_id(path)}.parquet")
        run = runner.run_log(fleet.read_log(path, CSV_OPTIONS), estimator=estimator, settings=fleet.resolve_settings(estimator, None))
        for name, values in fleet.run_columns(run):
            np.testing.assert_array_equal(_bits(table.column(name).to_numpy()), _bits(values), err_msg=name)


def test_per_log_csv_is_byte_identical_to_the_run_command_output(first_run, fleet_dir, client, tmp_path):
    # `run` takes no reference column: its CSV logs are compared with a fleet run given the same options; the fleet
    # runs the observer on every log, `run` picks per log (the INS on the .ulg and .bin): --estimator observer
    csv_logs = [str(fleet_dir / "hedy" / "hedy_part04.csv"), str(fleet_dir / "sim" / "sim07.csv")]
    run_options = {key: value for key, value in CSV_OPTIONS.items() if key != "reference_column"}
    csv_run = fleet.run_many(csv_logs, client=client, output_dir=str(tmp_path / "out"), csv_options=run_options,
                             write_csv=True)
    cases = [(fleet_dir / "px4" / "day0" / "flight0.ulg", first_run), (fleet_dir / "ardupilot" / "plane3.BIN", first_run)]
    cases += [(Path(path), csv_run) for path in csv_logs]
    for path, fleet_run in cases:
        single = tmp_path / f"{path.name}.csv"
        flags = CSV_FLAGS if path.suffix == ".csv" else []
        with redirect_stdout(io.StringIO()):
            assert cli.main(["run", str(path), *flags, "--estimator", "observer", "-o", str(single)]) == 0
        fleet_csv = Path(fleet_run.output_dir) / "csv" / f"{fleet.log_id(str(path))}.csv"
        assert fleet_csv.read_bytes() == single.read_bytes(), path


def test_corrupt_logs_are_rows_with_a_one_line_error(first_run):
    failed = [row for row in first_run.summary.to_pylist() if row["status"] == "failed"]
    assert sorted(Path(row["path"]).name for row in failed) == ["garbled.csv", "truncated.ulg"]
    for row in failed:
        assert row["error"] and "\n" not in row["error"]
        assert not (Path(first_run.output_dir) / "logs" / f"{row['log_id']}.parquet").exists()
        record = json.loads((Path(first_run.output_dir) / "failed" / f"{row['log_id']}.json").read_text())
        assert {key: row[key] for key in record["row"]} == record["row"]
        assert all(row[key] is None for key in row.keys() - record["row"].keys())
    garbled = next(row for row in failed if row["path"].endswith("garbled.csv"))
    assert "'garbage' is not a number" in garbled["error"] and "line 51" in garbled["error"]
    assert sorted(first_run.failed) == sorted(row["log_id"] for row in failed)


def test_summary_row_describes_the_log_and_its_run(first_run, fleet_dir):
    path = str(fleet_dir / "sim" / "sim03.csv")
    row = next(row for row in first_run.summary.to_pylist() if row["path"] == path)
    data = fleet.read_log(path, CSV_OPTIONS)
    run = runner.run_log(data, estimator="observer", settings=fleet.resolve_settings("observer", None))
    fused, raw = run.comparison(), run.baro_comparison()
    finite = np.isfinite(data.baro_altitude)
    assert row["samples"] == data.time.size and row["baro_samples"] == int(finite.sum())
    assert row["duration_s"] == data.time[-1] - data.time[0]
    assert row["imu_rate_hz"] == pytest.approx(100.0)
    assert (row["rms_error_m"], row["max_abs_error_m"], row["baro_rms_error_m"]) == (fused.rms, fused.max, raw.rms)
    assert row["final_accel_bias_m_s2"] == float(run.estimate.accel_bias[-1])
    assert row["estimator"] == "observer" and row["settings_hash"] == first_run.settings_hash
    assert row["bytes"] == os.path.getsize(path)


def test_summary_is_written_as_parquet_and_csv_with_the_same_rows(first_run):
    out = Path(first_run.output_dir)
    assert pq.read_table(out / "summary.parquet").equals(first_run.summary)
    import pyarrow.csv as pcsv
    from_csv = pcsv.read_csv(out / "summary.csv")
    assert from_csv.column("log_id").to_pylist() == first_run.summary.column("log_id").to_pylist()
    assert from_csv.column("samples").to_pylist() == first_run.summary.column("samples").to_pylist()


def test_summary_function_reads_the_table_back(first_run):
    assert fleet.summary(first_run.output_dir).equals(first_run.summary)


def test_rerun_with_the_same_settings_does_nothing(first_run, fleet_dir, client):
    before = _file_states(first_run.output_dir)
    again = fleet.run_many(str(fleet_dir), client=client, output_dir=first_run.output_dir, csv_options=CSV_OPTIONS,
                           write_csv=True)
    assert again.computed == []
    assert sorted(again.reused) == sorted(fleet.log_id(path) for path in _good_paths(first_run))
    assert again.summary.equals(first_run.summary)
    assert _file_states(first_run.output_dir) == before


def test_changed_settings_recompute(fleet_dir, client, tmp_path):
    logs = [str(fleet_dir / "sim" / "sim01.csv"), str(fleet_dir / "px4" / "day1" / "flight1.ulg")]
    vtol = fleet.run_many(logs, client=client, output_dir=str(tmp_path), csv_options=CSV_OPTIONS)
    racing = fleet.run_many(logs, settings="racing", client=client, output_dir=str(tmp_path), csv_options=CSV_OPTIONS)
    assert sorted(racing.computed) == sorted(vtol.computed) == sorted(fleet.log_id(path) for path in logs)
    assert racing.settings_hash != vtol.settings_hash
    table = pq.read_table(tmp_path / "logs" / f"{fleet.log_id(logs[0])}.parquet")
    expected = runner.run_log(fleet.read_log(logs[0], CSV_OPTIONS), estimator="observer",
                               settings=fleet.resolve_settings("observer", "racing"))
    np.testing.assert_array_equal(table.column("altitude").to_numpy(), expected.estimate.altitude)


def test_a_changed_log_file_is_recomputed(fleet_dir, client, tmp_path):
    log = tmp_path / "flight.csv"
    shutil.copyfile(fleet_dir / "sim" / "sim05.csv", log)
    first = fleet.run_many(str(log), client=client, output_dir=str(tmp_path / "out"), csv_options=CSV_OPTIONS)
    shutil.copyfile(fleet_dir / "sim" / "sim06.csv", log)
    second = fleet.run_many(str(log), client=client, output_dir=str(tmp_path / "out"), csv_options=CSV_OPTIONS)
    assert first.computed == second.computed == [fleet.log_id(str(log))]
    assert first.summary.column("rms_error_m").to_pylist() != second.summary.column("rms_error_m").to_pylist()


def test_failed_logs_are_retried_only_when_asked(fleet_dir, client, tmp_path):
    bad = str(fleet_dir / "bad" / "garbled.csv")
    fleet.run_many(bad, client=client, output_dir=str(tmp_path), csv_options=CSV_OPTIONS)
    kept = fleet.run_many(bad, client=client, output_dir=str(tmp_path), csv_options=CSV_OPTIONS)
    retried = fleet.run_many(bad, client=client, output_dir=str(tmp_path), csv_options=CSV_OPTIONS,
                             retry_failed=True)
    assert kept.costs.column("action").to_pylist() == ["reused"]
    assert retried.costs.column("action").to_pylist() == ["failed"]
    assert kept.failed == retried.failed == [fleet.log_id(bad)]


def test_fsspec_urls_are_read_and_written(fleet_dir, client):
    import fsspec

    memory = fsspec.filesystem("memory")
    source = fleet_dir / "sim" / "sim02.csv"
    memory.pipe_file("/fleet-in/a/sim02.csv", source.read_bytes())
    result = fleet.run_many("memory://fleet-in/a/*.csv", client=client, output_dir="memory://fleet-out",
                            csv_options=CSV_OPTIONS)
    (path,) = result.summary.column("path").to_pylist()
    assert path.startswith("memory://") and path.endswith("/fleet-in/a/sim02.csv")
    assert result.computed == [fleet.log_id(path)]
    with memory.open(f"/fleet-out/logs/{result.computed[0]}.parquet", "rb") as handle:
        table = pq.read_table(handle)
    expected = dict(_single_log_columns(str(source)))
    np.testing.assert_array_equal(_bits(table.column("altitude").to_numpy()), _bits(expected["altitude"]))


def test_a_killed_worker_loses_nothing(fleet_dir, tmp_path):
    """Kill one of two worker processes while logs are in flight; Dask reruns its tasks."""
    out = tmp_path / "out"
    killed = {}
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  silence_logs=50) as local, distributed.Client(local) as process_client:
        pids = process_client.run(os.getpid)
        victim = sorted(pids)[0]

        def kill_after_three(row):
            killed.setdefault("seen", 0)
            killed["seen"] += 1
            if killed["seen"] == 3:
                killed["existing"] = _file_states(out / "logs")
                os.kill(pids[victim], signal.SIGKILL)

        result = fleet.run_many(str(fleet_dir), client=process_client, output_dir=str(out), csv_options=CSV_OPTIONS,
                                on_result=kill_after_three)
        survivors = set(process_client.scheduler_info()["workers"])
        lost = [entry for entry in local.scheduler.transition_log  # (key, start, finish, recommendations, stimulus)
                if str(entry[0]).startswith("fleet-run") and entry[1:3] == ("processing", "released")
                and str(entry[4]).startswith("handle-worker-cleanup")]
    assert victim not in survivors  # the worker really died (its nanny started a new one)
    assert lost  # ... with logs in flight, which Dask gave to the other worker
    assert len(result.computed) + len(result.reused) == 40 and len(result.failed) == 2
    for path, state in killed["existing"].items():  # nothing written before the kill was lost or rewritten
        assert path.exists() and path.read_bytes() == state[1]
    assert not [p for p in out.rglob("*") if fleet._is_temporary(p.name)]
    for path in _good_paths(result)[::5]:
        table = pq.read_table(out / "logs" / f"{fleet.log_id(path)}.parquet")
        expected = dict(_single_log_columns(path))
        np.testing.assert_array_equal(_bits(table.column("altitude").to_numpy()), _bits(expected["altitude"]))


def test_an_interrupted_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    import fsspec

    target = tmp_path / "logs" / "x.parquet"
    target.parent.mkdir()
    target.write_bytes(b"old")

    def crash(_):
        raise OSError("disk pulled")

    monkeypatch.setattr(os, "fsync", crash)
    with pytest.raises(OSError, match="disk pulled"):
        fleet._atomic_write(fsspec.filesystem("file"), str(target), b"new content")
    assert target.read_bytes() == b"old"
    assert [p.name for p in target.parent.iterdir()] == ["x.parquet"]


def test_settings_hash_follows_what_is_computed():
    base = fleet.settings_hash("observer", fleet.resolve_settings("observer", None), CSV_OPTIONS)
    assert base == fleet.settings_hash("observer", fleet.resolve_settings("observer", "vtol"), dict(CSV_OPTIONS))
    assert base != fleet.settings_hash("observer", fleet.resolve_settings("observer", "racing"), CSV_OPTIONS)
    assert base != fleet.settings_hash("observer", fleet.resolve_settings("observer", None),
                                       {**CSV_OPTIONS, "accel_units": "g"})


def test_expand_paths_searches_directories_and_globs(fleet_dir):
    found = fleet.expand_paths([str(fleet_dir / "px4"), str(fleet_dir / "px4" / "day0" / "*.ulg")])
    assert len(found) == 6 and found == sorted(found)
    assert all(os.path.isabs(path) for path in found)


def test_expand_paths_names_a_glob_that_matches_nothing(fleet_dir):
    with pytest.raises(ValueError, match="paths_or_globs: .*matches no file"):
        fleet.expand_paths(str(fleet_dir / "*.nothing"))


def test_run_many_rejects_an_unknown_estimator_before_any_work(fleet_dir, client, tmp_path):
    with pytest.raises(ValueError, match="estimator must be one of"):
        fleet.run_many(str(fleet_dir / "sim"), estimator="magic", client=client, output_dir=str(tmp_path / "o"))
    assert not (tmp_path / "o").exists()


def test_run_many_rejects_bad_workers_and_no_paths_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="workers must be a positive integer, got 0"):
        fleet.run_many(str(tmp_path), workers=0, output_dir=str(tmp_path / "o"))
    with pytest.raises(ValueError, match="paths_or_globs is empty"):
        fleet.run_many([], output_dir=str(tmp_path / "o"))
    assert not (tmp_path / "o").exists()


def test_worst_logs_puts_failed_first_then_largest_rms(first_run):
    worst = fleet.worst_logs(first_run.summary, 4)
    assert [row["status"] for row in worst] == ["failed", "failed", "ok", "ok"]
    assert worst[2]["rms_error_m"] >= worst[3]["rms_error_m"]
    ok = [row["rms_error_m"] for row in first_run.summary.to_pylist() if row["status"] == "ok"]
    assert worst[2]["rms_error_m"] == max(ok)


# ----------------------------------------------------------------------------
# fit_many


def _fit_arrays(path, skip=5.0):
    """(accel, baro, dt, reference, mask) of a log as ``fusion-altitude fit --skip`` scores it."""
    data = fleet.read_log(path, CSV_OPTIONS)
    mask = tuning.training_mask(data.time, skip)
    return data.vertical_acceleration, data.baro_altitude, tuning.sample_periods(data.time), data.reference_altitude, mask


def _same_fit(fleet_fit, single):
    assert fleet_fit.settings.as_tuple() == single.settings.as_tuple()
    assert (fleet_fit.omega, fleet_fit.zeta, fleet_fit.omega_b) == (single.omega, single.zeta, single.omega_b)
    assert (fleet_fit.rms_error, fleet_fit.default_rms_error) == (single.rms_error, single.default_rms_error)
    np.testing.assert_array_equal(fleet_fit.landscape, single.landscape)


def test_fleet_fit_of_one_log_equals_the_single_machine_fit(fleet_dir, client):
    path = str(fleet_dir / "sim" / "sim04.csv")
    fleet_fit = fleet.fit_many(path, client=client, csv_options=CSV_OPTIONS)
    arrays = _fit_arrays(path)
    _same_fit(fleet_fit, tuning.fit(*arrays, steps_per_baro=tuning.steps_per_baro(arrays[1])))


def test_fleet_fit_of_the_px4_log_equals_the_cli_fit_with_the_same_skip(data_dir, client, monkeypatch):
    """The shared PX4 ULog has a 20 Hz baro on a 205 Hz grid and a 0.16 s logging gap: fit checks stability at the
    median dt times the steps per baro sample and runs the gains multiplied by it; the fleet fit must do the same."""
    path = str(data_dir / "px4_sample_log_small.ulg")
    results = []
    real_fit = tuning.fit
    monkeypatch.setattr(tuning, "fit", lambda *a, **k: results.append(real_fit(*a, **k)) or results[-1])
    status, out, _ = _cli(["fit", path, "--skip", "1"])
    assert status == 0, out
    (single,) = results
    monkeypatch.undo()
    data = fleet.read_log(path)
    dt = tuning.sample_periods(data.time)
    assert tuning.steps_per_baro(data.baro_altitude) > 5 and dt.max() > 10 * np.median(dt)  # what the test is about
    _same_fit(fleet.fit_many(path, client=client, skip=1.0), single)


def test_fleet_fit_minimises_the_pooled_rms_over_all_logs(fleet_dir, client):
    paths = [str(fleet_dir / "sim" / f"sim{k:02d}.csv") for k in range(8, 14)]
    result = fleet.fit_many(paths, client=client, csv_options=CSV_OPTIONS)
    sums, count = 0.0, 0
    for path in paths:  # the pooled RMS of the winner, recomputed log by log with the sweep kernel
        accel, baro, dt, reference, mask = _fit_arrays(path)
        one = tuning.score(accel, baro, dt, reference, mask, [result.settings.as_tuple()], tuning.steps_per_baro(baro))
        sums += float(one.sum_squared_error[0])
        count += one.metric_samples
    assert result.rms_error == np.sqrt(sums / count)
    assert result.metric_samples == count
    assert result.rms_error == result.landscape["rms_error"].min()
    assert result.rms_error < result.default_rms_error


def test_fleet_fit_does_not_depend_on_the_cluster(fleet_dir, client):
    paths = [str(fleet_dir / "sim" / f"sim{k:02d}.csv") for k in (1, 2, 3)] + [str(fleet_dir / "hedy" / "hedy_part05.csv")]
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=":0") as one:
        alone = fleet.fit_many(paths, client=one, csv_options=CSV_OPTIONS, refinements=1)
    spread = fleet.fit_many(paths, client=client, csv_options=CSV_OPTIONS, refinements=1)
    np.testing.assert_array_equal(alone.landscape, spread.landscape)
    assert alone.settings.as_tuple() == spread.settings.as_tuple()


def test_fleet_fit_scores_held_out_logs(fleet_dir, client):
    train = [str(fleet_dir / "sim" / f"sim{k:02d}.csv") for k in (1, 3, 5)]
    held = [str(fleet_dir / "sim" / "sim07.csv"), str(fleet_dir / "sim" / "sim09.csv")]
    result = fleet.fit_many(train, holdout=held, client=client, csv_options=CSV_OPTIONS, refinements=1)
    assert [row["log_id"] for row in result.holdout] == [fleet.log_id(path) for path in held]
    for row, path in zip(result.holdout, held):
        accel, baro, dt, reference, mask = _fit_arrays(path)
        one = tuning.score(accel, baro, dt, reference, mask,
                           [result.settings.as_tuple(), fleet.AltitudeSettings().as_tuple()],
                           tuning.steps_per_baro(baro))
        assert (row["rms_error_m"], row["default_rms_error_m"]) == tuple(one.rms_error)
    assert min(r["rms_error_m"] for r in result.holdout) <= result.holdout_rms_error <= max(
        r["rms_error_m"] for r in result.holdout)


def test_fleet_fit_leaves_out_unusable_logs_with_their_reason(fleet_dir, client):
    paths = [str(fleet_dir / "sim" / "sim01.csv"), str(fleet_dir / "bad" / "garbled.csv")]
    result = fleet.fit_many(paths, client=client, csv_options=CSV_OPTIONS, refinements=0)
    assert result.logs == [fleet.log_id(paths[0])]
    assert [path for path, _ in result.excluded] == [paths[1]]
    assert "is not a number" in result.excluded[0][1]


def test_fleet_fit_rejects_a_holdout_that_is_also_training(fleet_dir, client):
    path = str(fleet_dir / "sim" / "sim01.csv")
    with pytest.raises(ValueError, match="holdout: .* is also a training log"):
        fleet.fit_many(path, holdout=path, client=client, csv_options=CSV_OPTIONS)


# ----------------------------------------------------------------------------
# CLI


def _cli(argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = cli.main(argv)
    return status, out.getvalue(), err.getvalue()


def test_cli_fleet_run_writes_outputs_and_reports_failures(fleet_dir, cluster, tmp_path):
    status, out, _ = _cli(["fleet", "run", str(fleet_dir / "sim"), str(fleet_dir / "bad"), "-o", str(tmp_path),
                           "--scheduler", cluster.scheduler_address, *CSV_FLAGS, "--worst", "3"])
    assert status == 1  # some logs failed
    assert "16 computed, 0 reused" in out and "2 failed" in out
    assert "worst 3" in out and "garbled.csv" in out and "is not a number" in out
    assert len(list((tmp_path / "logs").glob("*.parquet"))) == 16


def test_cli_fleet_run_takes_every_preset_of_run_including_rocket(fleet_dir, cluster, tmp_path):
    import argparse

    def command(parser, name):
        subparsers = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        return subparsers.choices[name]

    def presets(parser):
        return tuple(next(a.choices for a in parser._actions if a.dest == "preset"))

    parser = cli.build_parser()
    assert "rocket" in presets(command(parser, "run"))
    assert presets(command(command(parser, "fleet"), "run")) == presets(command(parser, "run"))
    path = fleet_dir / "sim" / "sim01.csv"
    status, out, _ = _cli(["fleet", "run", str(path), "-o", str(tmp_path), "--preset", "rocket",
                           "--scheduler", cluster.scheduler_address, *CSV_FLAGS])
    assert status == 0, out
    (parquet,) = (tmp_path / "logs").glob("*.parquet")
    from fusion_altitude import AltitudeSettings

    alone = runner.run_log(fleet.read_log(str(path), CSV_OPTIONS), estimator="observer", settings=AltitudeSettings.preset("rocket"))
    np.testing.assert_array_equal(pq.read_table(parquet).column("altitude").to_numpy(), alone.estimate.altitude)


def test_cli_fleet_summary_prints_the_table_and_the_worst_logs(first_run):
    status, out, _ = _cli(["fleet", "summary", first_run.output_dir, "--worst", "2"])
    assert status == 0
    assert "42 logs: 40 ok, 2 failed" in out
    worst_block = out.split("worst 2")[1]
    assert "truncated.ulg" in worst_block and "garbled.csv" in worst_block


def test_cli_fleet_fit_writes_the_gains(fleet_dir, cluster, tmp_path):
    status, out, _ = _cli(["fleet", "fit", str(fleet_dir / "sim" / "sim1*.csv"), "--holdout-every", "3",
                           "--scheduler", cluster.scheduler_address, *CSV_FLAGS, "--reference", "ref",
                           "-o", str(tmp_path / "fit.json")])
    assert status == 0, out
    record = json.loads((tmp_path / "fit.json").read_text())
    assert len(record["logs"]) == 4 and len(record["holdout"]) == 2
    assert "held-out logs, fitted gains" in out


def test_cli_fleet_summary_of_an_empty_directory_is_a_one_line_error(tmp_path):
    status, _, err = _cli(["fleet", "summary", str(tmp_path)])
    assert status == 2 and len(err.strip().splitlines()) == 1 and "no summary.parquet" in err


def test_cli_fleet_rejects_zero_workers(fleet_dir, tmp_path):
    status, _, err = _cli(["fleet", "run", str(fleet_dir / "sim"), "-o", str(tmp_path), "--workers", "0"])
    assert status == 2 and "--workers must be >= 1" in err


def test_the_fleet_extra_brings_the_dashboard_and_fleet_run_prints_its_link(fleet_dir, tmp_path):
    """bokeh comes with the [fleet] extra (through [report]), so the LocalCluster that `fleet run` starts (no
    --scheduler) has a dashboard, and its link is printed."""
    import re

    text = (ROOT / "pyproject.toml").read_text()
    extra = re.search(r"^fleet = \[(.*)\]$", text, re.MULTILINE).group(1)
    assert '"fusion-altitude[report]"' in extra
    assert '"bokeh>=' in re.search(r"^report = \[(.*)\]$", text, re.MULTILINE).group(1)
    status, _, err = _cli(["fleet", "run", str(fleet_dir / "sim" / "sim01.csv"), "-o", str(tmp_path),
                           "--workers", "1", *CSV_FLAGS])
    assert status == 0, err
    line = next(line for line in err.splitlines() if line.startswith("Dask cluster: 1 worker"))
    assert ", dashboard http://" in line and line.rstrip().endswith("/status")


def test_without_a_client_a_local_cluster_of_one_single_thread_worker_per_cpu_is_started():
    with fleet.open_client() as local:
        workers = local.scheduler_info()["workers"].values()
        assert len(workers) == os.cpu_count()
        assert all(worker["nthreads"] == 1 for worker in workers)
        pids = set(local.run(os.getpid).values())
        assert len(pids) == os.cpu_count() and os.getpid() not in pids  # one process each


def test_cli_fleet_run_with_workers_starts_and_stops_its_own_cluster(fleet_dir, tmp_path):
    status, out, err = _cli(["fleet", "run", str(fleet_dir / "ardupilot" / "plane1.BIN"),
                             str(fleet_dir / "sim" / "sim12.csv"), "-o", str(tmp_path), "--workers", "1", *CSV_FLAGS])
    assert status == 0, err
    assert "Dask cluster: 1 worker" in err and "2 computed, 0 reused" in out


def test_a_log_whose_estimate_is_not_finite_is_a_failed_row_never_ok(fleet_dir, client, tmp_path):
    from typing import NamedTuple

    from fusion_altitude import runner

    class Batch(NamedTuple):
        altitude: np.ndarray
        vertical_velocity: np.ndarray

    def diverging(data, dt, options):
        altitude = np.zeros(data.time.size, np.float32)
        altitude[data.time.size // 2:] = np.inf
        return Batch(altitude, np.zeros(data.time.size, np.float32))

    runner.register_estimator(runner.EstimatorEntry("diverging_test", "returns inf from mid-log", diverging))
    try:
        result = fleet.run_many([str(fleet_dir / "sim" / "sim10.csv")], estimator="diverging_test", client=client,
                                output_dir=str(tmp_path), csv_options=CSV_OPTIONS)
    finally:
        del runner.ESTIMATORS["diverging_test"]
    row = result.summary.to_pylist()[0]
    assert row["status"] == "failed" and "non-finite altitude" in row["error"] and "cannot be trusted" in row["error"]


def test_the_summary_has_the_health_columns_of_run(first_run):
    row = next(r for r in first_run.summary.to_pylist() if r["status"] == "ok" and r["path"].endswith(".ulg"))
    assert row["baro_first_s"] < row["baro_last_s"] and row["stopped_streams"] == ""
    assert row["gps_samples"] > 0 and row["estimator_gaps"] >= 0 and row["not_baro_aided_s"] == 0.0

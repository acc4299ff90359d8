"""How the fleet hands logs to Dask and writes them (fusion_altitude.fleet): batches of consecutive logs per
task, the Parquet writer options of the per-log estimates, the publishing of each task's files, the clean-up of
interrupted writes, the Dask configuration of the local cluster, a finished task leaving its worker's slot
while it waits for the disk, and the rounds of ``benchmarks/fleet_bench.py``.

Most run without a cluster: ``fleet._batches`` is what ``run_many`` submits, and
``fleet._process_batch`` is the task body a worker runs.
"""

import os

import numpy as np
import pyarrow.parquet as pq
import pytest

from fusion_altitude import fleet, runner
from fusion_altitude.scenarios import run_scenario

CSV_OPTIONS = dict(time_column="t", accel_column="accel", baro_column="baro", reference_column="ref")


@pytest.mark.parametrize("logs", [1, 7, 42, 240, 1000])
@pytest.mark.parametrize("workers", [1, 2, 8])
def test_batches_give_out_every_log_once_in_path_order(logs, workers):
    batches = fleet._batches(list(range(logs)), workers)
    assert [job for batch in batches for job in batch] == list(range(logs))


@pytest.mark.parametrize("logs, workers", [(240, 1), (240, 2), (1000, 2), (42, 2)])
def test_batches_are_long_first_and_short_last_so_workers_finish_together(logs, workers):
    sizes = [len(batch) for batch in fleet._batches(list(range(logs)), workers)]
    assert sizes == sorted(sizes, reverse=True)
    assert sizes[-1] == 1 and max(sizes) <= fleet.BATCH_LOGS
    assert sizes[0] == min(fleet.BATCH_LOGS, max(fleet.MIN_BATCH_LOGS, logs // (4 * workers)))


@pytest.mark.parametrize("logs, workers", [(240, 2), (1000, 2), (42, 2), (120, 1)])
def test_no_batch_is_shorter_than_the_minimum_while_each_worker_has_that_many_logs_left(logs, workers):
    start = 0
    for batch in fleet._batches(list(range(logs)), workers):
        if logs - start >= fleet.MIN_BATCH_LOGS * workers:
            assert len(batch) >= fleet.MIN_BATCH_LOGS
        start += len(batch)


@pytest.mark.parametrize("logs, workers", [(2, 2), (10, 2), (7, 8)])
def test_a_small_fleet_is_still_shared_out_over_the_workers(logs, workers):
    assert len(fleet._batches(list(range(logs)), workers)) >= min(logs, workers)


def test_a_fleet_of_240_logs_on_2_workers_is_far_fewer_tasks_than_logs():
    assert len(fleet._batches(list(range(240)), 2)) <= 240 // 10


@pytest.fixture
def one_log(tmp_path):
    sim = run_scenario("realistic", seed=3)
    path = tmp_path / "sim3.csv"
    np.savetxt(path, np.column_stack([sim.time, sim.vertical_acceleration, sim.baro_altitude, sim.trajectory.altitude]),
               delimiter=",", header="t,accel,baro,ref", comments="", fmt="%.9g")
    return str(path)


def _jobs(paths, output_dir):
    settings = fleet.resolve_settings("observer", None)
    digest = fleet.settings_hash("observer", settings, CSV_OPTIONS)
    fleet._output_folders(output_dir)
    return [fleet._Job(path, fleet.log_id(path), output_dir, "observer", settings, CSV_OPTIONS, digest, False, False)
            for path in paths]


def test_a_batch_records_a_failed_log_in_its_own_row_and_runs_the_others(one_log, tmp_path):
    missing = str(tmp_path / "missing.csv")
    results = fleet._process_batch(_jobs([one_log, missing, one_log], str(tmp_path / "out")))
    assert [r["row"]["status"] for r in results] == ["ok", "failed", "ok"]
    assert [r["action"] for r in results] == ["computed", "failed", "reused"]
    assert "missing.csv" in results[1]["row"]["error"]


def test_estimate_files_store_float_columns_byte_stream_split_without_a_dictionary(one_log, tmp_path):
    (job,) = _jobs([one_log], str(tmp_path / "out"))
    assert fleet._process_log(job)["action"] == "computed"
    handle = pq.ParquetFile(tmp_path / "out" / "logs" / f"{job.log_id}.parquet")
    group = handle.metadata.row_group(0)
    floats = [group.column(i) for i in range(group.num_columns) if group.column(i).physical_type in ("FLOAT", "DOUBLE")]
    assert floats and all("BYTE_STREAM_SPLIT" in column.encodings for column in floats)
    assert not [column.path_in_schema for column in floats if any("DICTIONARY" in e for e in column.encodings)]


def test_estimate_files_hold_the_single_log_run_bit_for_bit(one_log, tmp_path):
    (job,) = _jobs([one_log], str(tmp_path / "out"))
    fleet._process_log(job)
    table = pq.read_table(tmp_path / "out" / "logs" / f"{job.log_id}.parquet")
    expected = fleet.run_columns(runner.run_log(fleet.read_log(one_log, CSV_OPTIONS), estimator="observer"))
    assert table.column_names == ["log_id"] + [name for name, _ in expected]
    for name, values in expected:
        column = table.column(name).to_numpy()
        assert column.dtype == values.dtype
        np.testing.assert_array_equal(column.view(np.uint8), values.view(np.uint8))


def test_leftovers_of_interrupted_writes_are_removed_and_outputs_kept(tmp_path):
    import fsspec

    logs = tmp_path / "logs"
    logs.mkdir()
    kept = logs / "a.csv-12345678.parquet"
    kept.write_bytes(b"output")
    (logs / ".a.csv-12345678.parquet.k2j3h4.part.parquet").write_bytes(b"half")  # outputs.atomic_output's
    (logs / ".b.csv-12345678.parquet.tmp-0123abcd").write_bytes(b"half")  # earlier versions'
    assert fleet._remove_leftovers(fsspec.filesystem("file"), str(tmp_path)) == 2
    assert [p.name for p in logs.iterdir()] == [kept.name]


def test_a_failed_fsync_on_the_publish_thread_fails_the_task_and_leaves_the_old_file(one_log, tmp_path, monkeypatch):
    (job,) = _jobs([one_log], str(tmp_path / "out"))
    target = tmp_path / "out" / "logs" / f"{job.log_id}.parquet"
    target.write_bytes(b"old")

    def crash(_):
        raise OSError("disk pulled")

    monkeypatch.setattr(os, "fsync", crash)
    with pytest.raises(OSError, match="disk pulled"):
        fleet._process_batch([job])
    assert target.read_bytes() == b"old"
    assert [p.name for p in target.parent.iterdir()] == [target.name]


def test_every_file_of_a_task_is_in_place_when_the_task_returns(one_log, tmp_path):
    jobs = _jobs([one_log], str(tmp_path / "out"))
    fleet._process_batch(jobs)
    files = sorted(p.name for p in (tmp_path / "out").rglob("*") if p.is_file())
    assert files == [f"{jobs[0].log_id}.parquet"]


def test_the_local_cluster_workers_run_without_dask_malloc_trimming_and_profiler(monkeypatch):
    import dask

    monkeypatch.delenv("MALLOC_TRIM_THRESHOLD_", raising=False)  # an earlier cluster of this process may set it
    with fleet.open_client(None, 1) as client:
        (environ,) = client.run(lambda: os.environ.get("MALLOC_TRIM_THRESHOLD_")).values()
        (profiling,) = client.run(lambda: dask.config.get("distributed.worker.profile.enabled")).values()
    assert environ is None and profiling is False


def test_a_worker_starts_its_next_task_while_a_finished_task_waits_for_the_disk(one_log, tmp_path, monkeypatch):
    """The wait for the last files' fsync happens off the worker's one slot (``distributed.secede``): with one
    thread, a second task runs while the first one is still in ``_Publisher.close``."""
    import threading

    import distributed

    next_task_ran = threading.Event()
    close = fleet._Publisher.close

    def slow_disk(publisher):
        waited = next_task_ran.wait(timeout=20)
        close(publisher)
        return waited

    monkeypatch.setattr(fleet._Publisher, "close", lambda publisher: seen.append(slow_disk(publisher)))
    monkeypatch.setattr(fleet, "_test_next_task_ran", next_task_ran, raising=False)  # a task's arguments are pickled
    seen = []
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=None) as client:
        first = client.submit(fleet._process_batch, _jobs([one_log], str(tmp_path / "out")), pure=False)
        second = client.submit(lambda: fleet._test_next_task_ran.set(), pure=False)
        second.result(timeout=20)
        assert first.result(timeout=30)[0]["action"] == "computed"
    assert seen == [True]


def test_a_batch_run_outside_a_worker_waits_for_its_files_on_its_own_thread(one_log, tmp_path, monkeypatch):
    import threading

    threads = []
    close = fleet._Publisher.close

    def record(publisher):
        threads.append(threading.current_thread())
        close(publisher)

    monkeypatch.setattr(fleet._Publisher, "close", record)
    fleet._process_batch(_jobs([one_log], str(tmp_path / "out")))
    assert threads == [threading.current_thread()]


def _fleet_bench():
    import importlib.util

    path = os.path.join(os.path.dirname(__file__), "..", "benchmarks", "fleet_bench.py")
    spec = importlib.util.spec_from_file_location("fleet_bench", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_fleet_bench_prints_each_rounds_ratio_and_the_median_and_shows_the_median_round(capsys):
    bench = _fleet_bench()

    def run(workers, seconds):
        return bench.ClusterRun(f"{workers} workers", workers, "out", ("name", seconds, 0.0, 0.0), {}, {}, 0.0,
                                (0, 0), (0, 0), {}, 1)

    rounds = [{1: run(1, 2.0), 2: run(2, seconds)} for seconds in (1.0, 1.25, 1.1)]  # ratios 2.0, 1.6, 1.82
    chosen = bench.print_rounds(rounds, [1, 2], logs=240)
    printed = capsys.readouterr().out
    assert "| 1 | 120.0 | 240.0 | 2.00 | nan, nan |" in printed and "| 2 | 120.0 | 192.0 | 1.60 |" in printed
    assert "median ratio 2 / 1 workers over 3 rounds: 1.82x (min 1.60, max 2.00)" in printed
    assert chosen is rounds[2]


def test_the_fleet_bench_refuses_fewer_than_one_round():
    with pytest.raises(SystemExit) as refused:
        _fleet_bench().main(["--rounds", "0"])
    assert refused.value.code == 2


def test_the_fleet_bench_cold_pass_empties_the_decoders_firmware_caches(shared_logs):
    from fusion_altitude.logs import _dataflash_fast, _ulog_fast, load_log

    load_log(str(shared_logs / "px4_sample_log_small.ulg"))
    load_log(str(shared_logs / "ardupilot_test.BIN"))
    assert _ulog_fast.firmware_definitions.cache_info().currsize > 0
    assert _dataflash_fast.format_table.cache_info().currsize > 0
    _fleet_bench().clear_firmware_caches()
    assert _ulog_fast.firmware_definitions.cache_info().currsize == 0
    assert _dataflash_fast.format_table.cache_info().currsize == 0

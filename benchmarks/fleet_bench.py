"""Fleet throughput: logs/s and MB/s of ``fleet.run_many`` with 1 and 2 workers
against a plain sequential loop over the same logs, in one run, and the per-log cost
split into read, estimate and write; where each cluster run's CPU and time went.

    python benchmarks/fleet_bench.py [--copies N] [--workers 1 2] [--rounds R] [--data DIR]

The 2-to-1 worker ratio of issue 25, on an idle machine, in one command:

    python benchmarks/fleet_bench.py --copies 200 --rounds 5

(5 rounds of a 1-worker then a 2-worker run, each on a fresh cluster; every round's ratio and the median
are printed, then the tables of the round whose ratio is the median.)

The fleet is ``--copies`` copies of each of four kinds of log, built in a temporary
directory from the shared real logs (FUSION_ALTITUDE_SHARED_DATA, else ../shared/data)
and the simulator: the PX4 ULog (0.9 MB, 6.5 s), the ArduPilot DataFlash log (64 KB,
1 s), the Hedy rocket flight as one CSV (245 s at 100 Hz) and a simulated 60 s
multirotor CSV (100 Hz). The sequential loop reads, runs and writes each log's Parquet
file in this process (what a user writes without the fleet, with the fleet's Parquet writer options), then once more
with the ULog and DataFlash decoders' firmware caches cleared before each read (every log as if from a firmware not
seen before: the benchmark's copies share their firmware's definitions); the fleet runs on a
``LocalCluster`` of worker processes started as ``fleet run`` starts it (``fleet.open_client``) and warmed
up (one log of each kind run) before the clock starts, into a fresh output directory each time. Over each
cluster run it records:

- the CPU time of every process: the workers, this process (the client, the local scheduler, the nannies
  and the dashboard) and any other child process; and of each kind of thread in them (from /proc);
- where the worker slots' wall time went: the tasks' work, their wait for the disk while holding the slot
  and after leaving it (``fleet._leave_worker_slot``), and the time a slot had no task;
- the messages and bytes each side wrote to Dask's TCP connections.

The machine is shared, so a single run's figures move by ±20 %; ``--rounds`` repeats the clusters.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, NamedTuple, Tuple

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CSV_OPTIONS = dict(time_column="t", accel_column="accel", baro_column="baro", reference_column="ref")
GRAVITY = 9.80665


def _write_csv(path, time_s, accel, baro, reference):
    np.savetxt(path, np.column_stack([time_s, accel, baro, reference]), delimiter=",", header="t,accel,baro,ref",
               comments="", fmt="%.9g")


def build_fleet(directory: Path, data: Path, copies: int) -> dict:
    """Write the benchmark fleet; returns {kind: [paths]}."""
    from fusion_altitude.scenarios import run_scenario

    kinds = {"PX4 ULog": [], "ArduPilot .bin": [], "Hedy CSV (245 s)": [], "simulated CSV (60 s)": []}
    baro = np.genfromtxt(data / "hedy_baro.csv", delimiter=",", names=True)
    imu = np.genfromtxt(data / "hedy_imu.csv", delimiter=",", names=True)
    info = np.genfromtxt(data / "hedy_flight_info.csv", delimiter=",", names=True)
    altitude = 44330.0 * (1.0 - (np.interp(imu["ts"], baro["ts"], baro["P"]) / 101325.0) ** 0.190263)
    hedy = (imu["ts"], -imu["Ay"] - GRAVITY, altitude, np.interp(imu["ts"], info["ts"], info["height"]) + altitude[0])
    for k in range(copies):
        for kind, name in (("PX4 ULog", f"px4_{k}.ulg"), ("ArduPilot .bin", f"ardupilot_{k}.bin")):
            shutil.copyfile(data / ("px4_sample_log_small.ulg" if name.endswith("ulg") else "ardupilot_test.BIN"),
                            directory / name)
            kinds[kind].append(str(directory / name))
        _write_csv(directory / f"hedy_{k}.csv", *hedy)
        kinds["Hedy CSV (245 s)"].append(str(directory / f"hedy_{k}.csv"))
        sim = run_scenario("realistic", seed=k)
        _write_csv(directory / f"sim_{k}.csv", sim.time, sim.vertical_acceleration, sim.baro_altitude,
                   sim.trajectory.altitude)
        kinds["simulated CSV (60 s)"].append(str(directory / f"sim_{k}.csv"))
    return kinds


def clear_firmware_caches() -> None:
    """Forget what the ULog and DataFlash decoders keep per firmware (the definitions and FMT caches), so that
    the next read of each log costs what a log of a firmware not seen before costs."""
    from fusion_altitude.logs import _dataflash_fast, _ulog_fast

    _ulog_fast.firmware_definitions.cache_clear()
    _dataflash_fast.format_table.cache_clear()


def sequential(paths, output: Path, cold: bool = False) -> dict:
    """A plain loop: read, run, write Parquet; per-log seconds of each phase (``cold``: the decoders' firmware
    caches cleared before each read, outside the clock)."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from fusion_altitude import fleet, runner

    output.mkdir()
    settings = fleet.resolve_settings("observer", None)
    costs = {}
    for path in paths:
        if cold:
            clear_firmware_caches()
        cpu = [time.thread_time()]
        wall = [time.perf_counter()]
        data = fleet.read_log(path, CSV_OPTIONS if path.endswith(".csv") else {})
        cpu.append(time.thread_time())
        wall.append(time.perf_counter())
        columns = fleet.run_columns(runner.run_log(data, estimator="observer", settings=settings))
        cpu.append(time.thread_time())
        wall.append(time.perf_counter())
        table = pa.table({name: values for name, values in columns})
        pq.write_table(table, output / (Path(path).name + ".parquet"), **fleet._estimates_parquet_options(table))
        cpu.append(time.thread_time())
        wall.append(time.perf_counter())
        costs[path] = tuple(np.diff(wall)) + tuple(np.diff(cpu))
    return costs


def warm_up(paths):
    """Run ``paths`` (one log of each kind) through the fleet in a throwaway directory, so that imports and
    first-call costs are not timed."""
    from fusion_altitude import fleet

    with tempfile.TemporaryDirectory(prefix="fleet-bench-warm-") as out:
        settings = fleet.resolve_settings("observer", None)
        digest = fleet.settings_hash("observer", settings, CSV_OPTIONS)
        fleet._output_folders(out)
        fleet._process_batch([fleet._Job(path, fleet.log_id(path), out, "observer", settings, CSV_OPTIONS, digest,
                                         False, False) for path in paths])
    return os.getpid()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--copies", type=int, default=10, help="copies of each kind of log (default 10)")
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2], help="cluster sizes (default 1 2)")
    parser.add_argument("--rounds", type=int, default=1,
                        help="runs of each cluster size, alternating (1 2 1 2 ...); the tables show the median "
                             "round, and every round's ratio is printed (default 1)")
    parser.add_argument("--data", default=os.environ.get("FUSION_ALTITUDE_SHARED_DATA",
                                                         str(ROOT / ".." / "shared" / "data")))
    args = parser.parse_args(argv)
    if args.rounds < 1:
        parser.error(f"--rounds must be >= 1, got {args.rounds}")
    data = Path(args.data)
    if not data.is_dir():
        print(f"shared data not found at {data}: set FUSION_ALTITUDE_SHARED_DATA or --data", file=sys.stderr)
        return 2

    from fusion_altitude import fleet

    with tempfile.TemporaryDirectory(prefix="fleet-bench-") as tmp:
        tmp = Path(tmp)
        (tmp / "logs").mkdir()
        kinds = build_fleet(tmp / "logs", data, args.copies)
        paths = sorted(p for group in kinds.values() for p in group)
        megabytes = sum(os.path.getsize(p) for p in paths) / 1e6
        print(f"{len(paths)} logs, {megabytes:.1f} MB; {os.cpu_count()} CPUs")
        print()
        firsts = [group[0] for group in kinds.values()]
        warm_up(firsts)
        sequential(firsts, tmp / "warm")
        load = os.getloadavg()[0]
        start = time.perf_counter()
        costs = sequential(paths, tmp / "sequential")
        elapsed = time.perf_counter() - start
        loop_row = ("sequential loop (this process)", elapsed, sum(sum(c[:3]) for c in costs.values()),
                    sum(sum(c[3:]) for c in costs.values()))
        rounds = []
        for number in range(args.rounds):
            rounds.append({workers: cluster_run(tmp, paths, firsts, workers, f"fleet{number}-{workers}")
                           for workers in args.workers})
        chosen = print_rounds(rounds, args.workers, len(paths)) if args.rounds > 1 else rounds[0]
        runs = [chosen[workers] for workers in args.workers]
        print(f"load average (1 min) at the start: {load:.1f} on {os.cpu_count()} CPUs")
        print()
        print_runs([loop_row] + [run.row for run in runs], len(paths), megabytes)
        print()
        print_processes(runs, len(paths))
        print()
        print_slots(runs, len(paths))
        print()
        print_threads(runs, len(paths))
        print()
        print_messages(runs, len(paths))
        print()
        print("Per log, sequential loop (mean; wall ms, CPU ms in brackets; read MB/s from CPU time):")
        print()
        print("| log | size (MB) | samples | read (ms) | estimate (ms) | write (ms) | read MB/s |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for kind, group in kinds.items():
            split = np.mean([costs[p] for p in group], axis=0)
            size = os.path.getsize(group[0]) / 1e6
            samples = fleet.read_log(group[0], CSV_OPTIONS if group[0].endswith(".csv") else {}).time.size
            print(f"| {kind} | {size:.2f} | {samples} | {split[0] * 1e3:.1f} ({split[3] * 1e3:.1f}) | "
                  f"{split[1] * 1e3:.2f} ({split[4] * 1e3:.2f}) | {split[2] * 1e3:.1f} ({split[5] * 1e3:.1f}) | "
                  f"{size / split[3]:.1f} |")
        written = sum(p.stat().st_size for p in (tmp / runs[-1].directory / "logs").iterdir()) / 1e6
        samples_total = sum(fleet.read_log(p, CSV_OPTIONS if p.endswith(".csv") else {}).time.size for p in paths)
        print()
        print(f"outputs: {written:.1f} MB of Parquet for {samples_total} samples "
              f"({written * 1e6 / samples_total:.1f} bytes per sample)")
        total = np.sum([costs[p] for p in paths], axis=0)
        print()
        for label, part in (("wall", total[:3]), ("CPU", total[3:])):
            print(f"all {len(paths)} logs, {label}: read {part[0]:.2f} s, estimate {part[1]:.3f} s, write {part[2]:.2f} s "
                  f"({100 * part[0] / part.sum():.0f} / {100 * part[1] / part.sum():.1f} / "
                  f"{100 * part[2] / part.sum():.0f} %)")
        cold = sequential(paths, tmp / "sequential-cold", cold=True)
        part = np.sum([cold[p] for p in paths], axis=0)[3:]
        print(f"all {len(paths)} logs, CPU, the decoders' firmware caches cleared before each read: read "
              f"{part[0]:.2f} s, estimate {part[1]:.3f} s, write {part[2]:.2f} s ({100 * part[0] / part.sum():.0f} / "
              f"{100 * part[1] / part.sum():.1f} / {100 * part[2] / part.sum():.0f} %)")
        ulog, csv = (np.mean([costs[p] for p in kinds[kind]], axis=0) for kind in ("PX4 ULog", "Hedy CSV (245 s)"))
        csv_samples = fleet.read_log(kinds["Hedy CSV (245 s)"][0], CSV_OPTIONS).time.size
        print()
        print(fleet_cost_table(os.path.getsize(kinds["PX4 ULog"][0]) / 1e6 / ulog[3], csv[4] / csv_samples,
                               csv[5] / csv_samples, written * 1e6 / samples_total))
    return 0


class ClusterRun(NamedTuple):
    """One ``fleet.run_many`` over the bench's logs on a fresh local cluster, and where its CPU went."""

    name: str
    workers: int
    directory: str  # its output directory, under the bench's temporary directory
    row: Tuple[str, float, float, float]  # (name, wall s, per-log wall s summed, per-log CPU s summed)
    worker_threads: Dict[str, float]  # CPU s of the worker processes, by thread role (every worker summed)
    client_threads: Dict[str, float]  # CPU s of this process (client, scheduler, nannies), by thread role
    other_cpu: float  # CPU s of this process's other children (neither worker nor this process), s
    worker_comm: Tuple[int, int]  # (messages, bytes) the workers wrote to their TCP connections
    client_comm: Tuple[int, int]  # (messages, bytes) this process wrote (client, scheduler, nannies)
    slots: Dict[str, float]  # where the worker slots' time went, s (slot_use)
    tasks: int  # Dask tasks the run submitted (fleet._batches)
    load: float = math.nan  # the machine's 1-minute load average when the run started

    @property
    def elapsed(self) -> float:
        return self.row[1]

    @property
    def worker_cpu(self) -> float:
        return sum(self.worker_threads.values())

    @property
    def client_cpu(self) -> float:
        return sum(self.client_threads.values())


def cluster_run(tmp: Path, paths, firsts, workers: int, directory: str) -> ClusterRun:
    """Run the fleet on a fresh cluster of ``workers`` processes (the one ``fleet run`` starts), warmed up;
    CPU by process and thread, and the TCP messages written, over the run only."""
    import psutil

    from fusion_altitude import fleet

    with fleet.open_client(None, workers) as client:  # the cluster `fleet run` starts
        client.run(warm_up, firsts)
        client.run(count_comm_writes)
        client.run(record_slots)
        worker_pids = set(client.run(os.getpid).values())
        before = (sum_threads(client.run(thread_cpu).values()), thread_cpu(), comm_written(client),
                  other_children_cpu(psutil.Process(), worker_pids))
        load, start, since = os.getloadavg()[0], time.perf_counter(), time.time()
        result = fleet.run_many(str(tmp / "logs"), client=client, output_dir=str(tmp / directory),
                                csv_options=CSV_OPTIONS)
        elapsed, until = time.perf_counter() - start, time.time()
        after = (sum_threads(client.run(thread_cpu).values()), thread_cpu(), comm_written(client),
                 other_children_cpu(psutil.Process(), worker_pids))
        slots = slot_use(client, since, until)
    assert len(result.computed) == len(paths), result.failed
    rows = result.costs.to_pylist()
    busy = sum(sum(row[name] for name in ("read_s", "estimate_s", "write_s")) for row in rows)
    cpu = sum(row["cpu_s"] for row in rows)
    name = f"fleet.run_many, {workers} worker process{'es' if workers > 1 else ''}"
    delta = [{role: value - old.get(role, 0.0) for role, value in new.items()} for new, old in
             zip(after[:2], before[:2])]
    comm = [tuple(a - b for a, b in zip(new, old)) for new, old in zip(after[2], before[2])]
    return ClusterRun(name, workers, directory, (name, elapsed, busy, cpu), delta[0], delta[1],
                      after[3] - before[3], comm[0], comm[1], slots,
                      len(fleet._batches(paths, workers)), load)


def print_rounds(rounds, sizes, logs) -> Dict[int, ClusterRun]:
    """Each round's throughput ratio of the larger clusters to the first, their medians, and the round whose
    ratio is the median one (its tables follow)."""
    first, *others = sizes
    names = [f"{w} worker{'s' if w > 1 else ''} (logs/s)" for w in sizes]
    print(f"| round | {' | '.join(names)} | {' | '.join(f'{w} / {first} workers' for w in others)} "
          "| load average at the runs' starts |")
    print("|---:|" + "---:|" * (len(sizes) + len(others)) + "---|")
    ratios = []
    for number, runs in enumerate(rounds, 1):
        ratio = [runs[first].elapsed / runs[w].elapsed for w in others]
        ratios.append(ratio[-1] if ratio else 1.0)
        print(f"| {number} | {' | '.join(f'{logs / runs[w].elapsed:.1f}' for w in sizes)} | "
              f"{' | '.join(f'{r:.2f}' for r in ratio)} | {', '.join(f'{runs[w].load:.1f}' for w in sizes)} |")
    for index, w in enumerate(others):
        values = [runs[first].elapsed / runs[w].elapsed for runs in rounds]
        print(f"median ratio {w} / {first} workers over {len(rounds)} rounds: {float(np.median(values)):.2f}x "
              f"(min {min(values):.2f}, max {max(values):.2f})")
    print()
    middle = int(np.argsort(ratios)[len(ratios) // 2])
    print(f"The tables below are round {middle + 1}'s (its ratio is the median"
          + ("; of an even number of rounds, the higher of the middle two)." if len(ratios) % 2 == 0 else ")."))
    print()
    return rounds[middle]


def print_runs(rows, logs, megabytes):
    """The table of runs, then the throughput of each cluster against the first (one-worker) cluster."""
    print("| run | wall time (s) | logs/s | MB/s | per-log wall time, summed (s) | per-log CPU time, summed (s) "
          "| CPU ms per log |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, seconds, busy, cpu in rows:
        print(f"| {name} | {seconds:.2f} | {logs / seconds:.1f} | {megabytes / seconds:.2f} | {busy:.2f} "
              f"| {cpu:.2f} | {1e3 * cpu / logs:.2f} |")
    print()
    sequential, *clusters = rows
    for name, seconds, _, cpu in clusters:
        print(f"{name}: {sequential[1] / seconds:.2f}x the sequential loop's throughput, "
              f"{cpu / sequential[3]:.2f}x its CPU time per log")
    for name, seconds, _, _ in clusters[1:]:
        print(f"ratio: {name} / {clusters[0][0]}: {clusters[0][1] / seconds:.2f}x the throughput")


def print_processes(runs, logs):
    """Where the CPU of each cluster run went: its worker processes (every thread: the tasks, Dask's own
    event loop, the publish thread), this process (the client, the ``LocalCluster``'s scheduler and nannies,
    the dashboard) and any other child process."""
    cores = os.cpu_count() or 1
    print("| run | workers' CPU (s) | workers' CPU ms per log | client and scheduler CPU (s) "
          "| client and scheduler CPU ms per log | other processes' CPU ms per log | CPU busy, % of all cores |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for run in runs:
        total = run.worker_cpu + run.client_cpu + run.other_cpu
        print(f"| {run.name} | {run.worker_cpu:.2f} | {1e3 * run.worker_cpu / logs:.2f} | {run.client_cpu:.2f} | "
              f"{1e3 * run.client_cpu / logs:.2f} | {1e3 * run.other_cpu / logs:.2f} | "
              f"{100 * total / (run.elapsed * cores):.0f} |")


def print_slots(runs, logs):
    """Where the worker slots' wall time went (ms per log, summed over the workers): a task's work (read,
    estimate, write, handed to the publish thread), its wait for the disk while it still held the slot,
    its wait after it left the slot (the next task running meanwhile), and the time a slot had no task: before
    its first task (the client finding the logs, the first round trip), between two tasks (Dask's round trips)
    and after its last task (the other worker's tail, the client writing the summary); and how far apart the
    workers' last tasks ended."""
    columns = ("work", "disk wait in the slot", "disk wait after the slot", "empty before the first task",
               "empty between tasks", "empty after the last task")
    print("| run | work (ms per log) | disk wait holding the slot | disk wait after leaving it "
          "| slot empty before the first task | between tasks | after the last task | slot busy, % of the run "
          "| workers' last tasks ended apart (ms) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for run in runs:
        held = run.slots["work"] + run.slots["disk wait in the slot"]
        print(f"| {run.name} | " + " | ".join(f"{1e3 * run.slots[k] / logs:.2f}" for k in columns)
              + f" | {100 * held / (run.workers * run.elapsed):.0f} | {1e3 * run.slots['ends apart']:.0f} |")


#: The thread roles of the thread table: (process, role, the thread names in it). Dask's task threads end when
#: their task secedes (``fleet._leave_worker_slot``), so a worker's ended threads count as task threads.
THREAD_ROLES = (("worker", "task threads (Dask-Default-Threads)", ("Dask-Default-Threads", "ended threads")),
                ("worker", "event loop (MainThread: Dask's messages, heartbeats)", ("MainThread",)),
                ("worker", "publish thread (fsync, rename)", ("fleet-publish",)),
                ("worker", "other threads", None),
                ("client", "client (MainThread: run_many)", ("MainThread",)),
                ("client", "IO loop (scheduler, nannies, dashboard, client's messages)", ("IO loop",)),
                ("client", "other threads", None))


def print_threads(runs, logs):
    """CPU ms per log of each kind of thread, in the worker processes (all workers summed) and in this
    process (:data:`THREAD_ROLES`)."""
    print("CPU ms per log by thread (workers summed; from /proc, in 10 ms ticks):")
    print()
    print("| process: threads | " + " | ".join(run.name for run in runs) + " |")
    print("|---|" + "---:|" * len(runs))
    for side, role, names in THREAD_ROLES:
        named = {name for s, _, group in THREAD_ROLES if s == side and group for name in group}
        values = []
        for run in runs:
            threads = run.worker_threads if side == "worker" else run.client_threads
            values.append(max(0.0, sum(seconds for name, seconds in threads.items()
                                       if (name in names if names else name not in named))))
        print(f"| {side}: {role} | " + " | ".join(f"{1e3 * value / logs:.2f}" for value in values) + " |")


def print_messages(runs, logs):
    """TCP messages (Dask's comm writes; a batched write counts once) and bytes per log, by writer."""
    print("| run | tasks | workers' messages per log | workers' bytes per log | client and scheduler messages "
          "per log | client and scheduler bytes per log |")
    print("|---|---:|---:|---:|---:|---:|")
    for run in runs:
        print(f"| {run.name} | {run.tasks} | {run.worker_comm[0] / logs:.2f} | {run.worker_comm[1] / logs:.0f} | "
              f"{run.client_comm[0] / logs:.2f} | {run.client_comm[1] / logs:.0f} |")


def thread_cpu() -> Dict[str, float]:
    """CPU time (user + system, s) of this process by thread role: each thread's name without its numbers,
    from /proc; the time of threads that have ended is "ended threads" (the process's total minus the
    living threads')."""
    import re
    import threading

    tick = os.sysconf("SC_CLK_TCK")
    names = {thread.native_id: thread.name for thread in threading.enumerate()}

    def cpu(stat_path):
        with open(stat_path) as handle:
            fields = handle.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / tick

    roles: Dict[str, float] = {}
    for tid in os.listdir("/proc/self/task"):
        try:
            seconds = cpu(f"/proc/self/task/{tid}/stat")
        except OSError:  # ended meanwhile
            continue
        name = names.get(int(tid), "C threads (no Python name)")
        role = re.sub(r"--+", "-", re.sub(r"\d+", "", name)).strip("-_ ")
        roles[role] = roles.get(role, 0.0) + seconds
    roles["ended threads"] = max(0.0, cpu("/proc/self/stat") - sum(roles.values()))
    return roles


def sum_threads(per_process) -> Dict[str, float]:
    """Thread-role CPU times of several processes, added up."""
    total: Dict[str, float] = {}
    for roles in per_process:
        for role, seconds in roles.items():
            total[role] = total.get(role, 0.0) + seconds
    return total


def other_children_cpu(process, worker_pids) -> float:
    """CPU s of this process's child processes other than the workers (alive now)."""
    total = 0.0
    for child in process.children(recursive=True):
        if child.pid not in worker_pids:
            try:
                times = child.cpu_times()
                total += times.user + times.system
            except Exception:  # ended meanwhile
                pass
    return total


def count_comm_writes() -> Tuple[int, int]:
    """(messages, bytes) this process has written to Dask's TCP connections since the first call, which starts
    counting (the counts live on the patched method: this function reaches a worker by value, through
    ``client.run``, so a global of this script would be a fresh copy at each call)."""
    from distributed.comm.tcp import TCP

    if not hasattr(TCP.write, "counts"):
        original = TCP.write

        async def write(self, *args, **kwargs):
            written = await original(self, *args, **kwargs)
            write.counts[0] += 1
            write.counts[1] += written
            return written

        write.counts = [0, 0]
        TCP.write = write
    return tuple(TCP.write.counts)


def comm_written(client) -> Tuple[Tuple[int, int], Tuple[int, int]]:
    """((messages, bytes) written by all the workers, (messages, bytes) written by this process) so far."""
    workers = list(client.run(count_comm_writes).values())
    return (sum(w[0] for w in workers), sum(w[1] for w in workers)), count_comm_writes()


def record_slots():
    """Per task run in this process since the first call (which starts recording): (start, logs done, slot
    free, end), wall-clock s (``time.time``): when ``fleet._process_batch`` began, when its last log was
    handed to the publish thread, when the worker's slot was free for the next task (after
    ``fleet._leave_worker_slot`` seceded, else at the end) and when it returned, its files durable."""
    import threading

    from distributed.threadpoolexecutor import thread_state

    from fusion_altitude import fleet

    if not hasattr(fleet._process_batch, "slots"):
        run_batch, leave = fleet._process_batch, fleet._leave_worker_slot
        local = threading.local()

        def timed_leave():
            local.times.append(time.time())
            leave()
            if getattr(thread_state, "proceed", True) is False:  # seceded: the slot is free
                local.times.append(time.time())

        def timed_batch(jobs):
            local.times = [time.time()]
            try:
                return run_batch(jobs)
            finally:
                end = time.time()
                times = local.times + [end] * (4 - len(local.times))
                timed_batch.slots.append(tuple(times[:2]) + (times[2], end))

        timed_batch.slots = []
        fleet._process_batch, fleet._leave_worker_slot = timed_batch, timed_leave
    return list(fleet._process_batch.slots)


def slot_use(client, since: float, until: float) -> Dict[str, float]:
    """Where the worker slots' time went between ``since`` and ``until`` (s, summed over the workers): the
    tasks' work and disk waits (:func:`record_slots`), and the time each slot had no task: before its first
    task, between two tasks, and after its last one left the slot; and how far apart the workers' last tasks
    ended."""
    use = dict.fromkeys(("work", "disk wait in the slot", "disk wait after the slot", "empty before the first task",
                         "empty between tasks", "empty after the last task"), 0.0)
    ends = []
    for slots in client.run(record_slots).values():
        tasks = sorted(task for task in slots if task[0] >= since)
        for k in range(len(tasks) - 1):  # the slot was free when the next task started, if before secede returned
            begin, done, free, end = tasks[k]
            tasks[k] = (begin, done, max(done, min(free, tasks[k + 1][0])), end)
        if not tasks:
            use["empty before the first task"] += until - since
            continue
        use["work"] += sum(done - begin for begin, done, _, _ in tasks)
        use["disk wait in the slot"] += sum(free - done for _, done, free, _ in tasks)
        use["disk wait after the slot"] += sum(end - free for _, _, free, end in tasks)
        use["empty before the first task"] += tasks[0][0] - since
        use["empty between tasks"] += sum(later[0] - earlier[2] for earlier, later in zip(tasks, tasks[1:]))
        use["empty after the last task"] += until - tasks[-1][2]
        ends.append(tasks[-1][3])
    use["ends apart"] = max(ends) - min(ends) if ends else 0.0
    return use


#: Assumed, not measured: a mean flight of 10 min logged at the sample ULog's rate (0.92 MB per 6.5 s),
#: i.e. 85 MB and 120,000 grid steps (200 Hz) per log; reading scales linearly with size.
FLEET_LOGS, LOG_MEGABYTES, LOG_SAMPLES = 100_000, 85.0, 120_000


def fleet_cost_table(read_megabytes_per_s, estimate_s_per_sample, write_s_per_sample, output_bytes_per_sample):
    """The CPU time and storage of a 100,000-log fleet from one core's measured rates, as a markdown table."""
    read, estimate, write = (LOG_MEGABYTES / read_megabytes_per_s, estimate_s_per_sample * LOG_SAMPLES,
                             write_s_per_sample * LOG_SAMPLES)
    output = output_bytes_per_sample * LOG_SAMPLES / 1e6
    rows = [("input (assumed)", f"{LOG_MEGABYTES:.0f} MB", f"{LOG_MEGABYTES * FLEET_LOGS / 1e6:.1f} TB", "10 min of a ULog"),
            ("read", f"{read:.1f} s", f"{read * FLEET_LOGS / 3600:.0f} CPU-hours", f"{read_megabytes_per_s:.1f} MB/s per CPU (ULog)"),
            ("estimate", f"{estimate * 1e3:.0f} ms", f"{estimate * FLEET_LOGS / 3600:.1f} CPU-hours",
             f"{estimate_s_per_sample * 1e6:.3f} µs/sample (Hedy CSV)"),
            ("write", f"{write:.2f} s", f"{write * FLEET_LOGS / 3600:.1f} CPU-hours",
             f"{write_s_per_sample * 1e6:.2f} µs/sample (Hedy CSV)"),
            ("output Parquet", f"{output:.1f} MB", f"{output * FLEET_LOGS / 1e6:.2f} TB", f"{output_bytes_per_sample:.1f} bytes/sample"),
            ("**total CPU**", f"**{read + estimate + write:.1f} s**", f"**{(read + estimate + write) * FLEET_LOGS / 3600:.0f} CPU-hours**", "")]
    lines = ["| | per log | 100,000 logs | rate |", "|---|---:|---:|---|"]
    return "\n".join(lines + [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows])


if __name__ == "__main__":
    sys.exit(main())

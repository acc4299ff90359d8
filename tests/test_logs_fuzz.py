"""Reader fuzz, bounded and seeded: truncated and bit-flipped logs of every format raise only LogError.

The long run is ``python tests/fuzz_readers.py --seconds 60``; this test runs a
fixed number of mutations (20 per seed file, seed 1) so it is deterministic.
One ULog seed is the shared PX4 sample (FUSION_ALTITUDE_SHARED_DATA); its
absence fails the test rather than skipping it.
"""

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # pytest runs with --import-mode=importlib
import fuzz_readers  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = os.environ.get("FUSION_ALTITUDE_SHARED_DATA", str(ROOT / ".." / "shared" / "data"))


def test_mutated_logs_of_every_format_raise_only_log_error():
    assert os.path.exists(os.path.join(DATA, "px4_sample_log_small.ulg")), f"shared data not found at {DATA}"
    runs, findings = fuzz_readers.fuzz(seconds=1e9, seed=1, data_dir=DATA, timeout=60.0, max_runs=240)
    assert set(runs) == {"altos", "altos-1.4", "altos-telemetry", "cats", "cats-imu", "csv", "dataflash-TimeMS",
                         "dataflash-TimeUS", "raven", "rrc3", "ulog-appended", "ulog-fixture", "ulog-px4-sample",
                         "ulog-sync"}
    assert [f"{fmt}: {finding}" for fmt, finding in findings] == []
